"""Shared pieces of bench/corpus_check.py and bench/rs274_compare.py (stdlib only).

The program set: every file under corpus/shop/<owner>__<repo>/ (SOURCES.tsv says how
each is read), plus LinuxCNC's own example programs when linuxcnc-uspace is installed.
The LinuxCNC examples are GPL: they are read where Debian's package put them and are
never copied into this repository.
"""

import csv
import os

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHOP = os.path.join(ROOT, "corpus", "shop")
LINUXCNC_DIRS = ["/usr/share/linuxcnc/ncfiles", "/usr/share/doc/linuxcnc/examples/nc_files"]
SKIP_NAMES = {"SOURCES.tsv", "LICENSE.upstream"}
NC_EXTENSIONS = (".ngc", ".nc", ".tap", ".cnc", ".gcode", ".txt", ".eia")


class Program:
    """One program of the set: its path, where it came from, how kezuri reads it."""

    def __init__(self, path, label, origin, no_decimal):
        self.path = path  # absolute
        self.label = label  # shown in reports
        self.origin = origin  # "shop" or "linuxcnc"
        self.no_decimal = no_decimal  # "increments" (Fanuc) or "units" (LinuxCNC, GRBL)

    def kezuri_flags(self):
        return ["--no-decimal", "units"] if self.no_decimal == "units" else []


def shop_programs():
    sources = {}
    tsv = os.path.join(SHOP, "SOURCES.tsv")
    if os.path.exists(tsv):
        with open(tsv, newline="") as f:
            for row in csv.DictReader(f, delimiter="\t"):
                sources[row["path"]] = row
    out = []
    if not os.path.isdir(SHOP):
        return out
    for folder in sorted(os.listdir(SHOP)):
        d = os.path.join(SHOP, folder)
        if not os.path.isdir(d):
            continue
        for name in sorted(os.listdir(d)):
            if name in SKIP_NAMES or not os.path.isfile(os.path.join(d, name)):
                continue
            rel = folder + "/" + name
            row = sources.get(rel, {})
            nd = row.get("no_decimal") or ("units" if name.lower().endswith((".ngc", ".gcode")) else "increments")
            out.append(Program(os.path.join(d, name), "shop/" + rel, "shop", nd))
    return out


def linuxcnc_programs():
    """LinuxCNC's example programs, read in place (GPL: never copied)."""
    seen = set()
    out = []
    for base in LINUXCNC_DIRS:
        if not os.path.isdir(base):
            continue
        for dirpath, dirnames, filenames in os.walk(base, followlinks=True):
            dirnames.sort()
            for name in sorted(filenames):
                if not name.lower().endswith(".ngc"):
                    continue
                p = os.path.join(dirpath, name)
                real = os.path.realpath(p)
                if real in seen:
                    continue
                seen.add(real)
                rel = os.path.relpath(p, base)
                out.append(Program(p, "linuxcnc/" + rel, "linuxcnc", "units"))
    return out


def all_programs(include_linuxcnc=True):
    progs = shop_programs()
    if include_linuxcnc:
        progs += linuxcnc_programs()
    return progs


def kezuri_binary():
    return os.environ.get("KEZURI") or os.path.join(ROOT, "target", "release", "kezuri")
