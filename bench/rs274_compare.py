#!/usr/bin/env python3
"""Compares kezuri's motion with LinuxCNC's standalone interpreter rs274, program by program.

For every corpus program (and LinuxCNC's installed examples, read in place):
  rs274 -t TOOLTABLE -g FILE            (run from the program's folder)
  kezuri run FILE --to csv --machine M.toml [--no-decimal units]
rs274's canonical calls (STRAIGHT_TRAVERSE / STRAIGHT_FEED / STRAIGHT_PROBE / ARC_FEED,
with USE_LENGTH_UNITS and SELECT_PLANE tracked) become a list of end points in mm, moved
from rs274's program frame into kezuri's (SET_XY_ROTATION, then SET_G5X_OFFSET +
SET_G92_OFFSET added, as LinuxCNC's canon layer does);
kezuri's CSV rows (line,kind,x,y,z,a,b,c,feed) are the other list. Both tool tables
hold the same tools: T1..T99, diameter 6 mm, length 0 (rs274's table is in inches,
so it says D0.2362…). With cutter radius compensation (G41/G42) rs274 prints the tool
centre path, which kezuri's CSV is too.

Agreement: the same number of moves (moves of zero length dropped on both sides), the
same kind (rapid / feed / cw / ccw / probe), and every end point within
1e-3 mm + half of rs274's printed step (4 decimals in program units: 0.00005 mm in mm
programs, 0.00127 mm in inch programs). Arc centres: rs274 prints them; kezuri's CSV
has no centre column, so for arcs the centre kezuri used is read from its
`--to linuxcnc --apply-comp` output (I/J/K; arcs matched in order, when both have as many arcs) and
compared too.

Usage: python3 bench/rs274_compare.py [--json] [--no-linuxcnc] [--timeout S] [--only SUBSTR]
                                      [--file PROGRAM.ngc]...
(--file: compare these programs instead, read as LinuxCNC programs; e.g.
bench/programs/comp-linuxcnc.ngc, cutter compensation with G41, G42 and G41.1.)
(bench/rs274-compare.sh checks for rs274, builds kezuri, and calls this). Exit 0 always.
"""

import argparse
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from corpus_common import Program, all_programs, kezuri_binary  # noqa: E402

CANON = re.compile(r"^\s*\d+\s+N\S*\s+([A-Z_0-9]+)\((.*)\)\s*$")
ABS_TOL_MM = 1e-3
ZERO_MM = 1e-9


def tool_files(tmp):
    tbl = os.path.join(tmp, "tools.tbl")
    with open(tbl, "w") as f:
        for t in range(1, 100):
            # rs274 (standalone) reads the tool table in inches: 6 mm.
            f.write("T%d P%d D%.17g Z0 ;\n" % (t, t, 6.0 / 25.4))
    machine = os.path.join(tmp, "machine.toml")
    with open(machine, "w") as f:
        f.write("[tools]\n")
        f.write("lengths = { %s }\n" % ", ".join("%d = 0.0" % t for t in range(1, 100)))
        f.write("radii = { %s }\n" % ", ".join("%d = 3.0" % t for t in range(1, 100)))
        # LinuxCNC's G73 retract and G83 clearance: a fixed 0.010 inch.
        f.write("[cycles]\npeck_retract_mm = 0.254\npeck_clearance_mm = 0.254\n")
    return tbl, machine


# ---------------------------------------------------------------- rs274 side

def numbers(args):
    out = []
    for a in args.split(","):
        a = a.strip()
        try:
            out.append(float(a))
        except ValueError:
            out.append(a)
    return out


def run_rs274(program, tbl, timeout):
    """(moves, step_mm, error or None). A move: dict kind, end [x,y,z,a,b,c] (mm, deg), centre."""
    try:
        p = subprocess.run(["rs274", "-t", tbl, "-g", os.path.basename(program.path)],
                           cwd=os.path.dirname(program.path), capture_output=True, text=True,
                           timeout=timeout, stdin=subprocess.DEVNULL, errors="replace")
    except subprocess.TimeoutExpired:
        return [], 0.0, "no answer in %g s" % timeout
    factor = 1.0
    step = 0.5e-4
    inch_seen = False
    plane = "XY"
    moves = []
    g5x = [0.0] * 6
    g92 = [0.0] * 6
    rot = 0.0

    def to_frame(v):
        """rs274's program-frame point (mm) into kezuri's frame: rotation, then G5x + G92."""
        v = list(v)
        if rot and v[0] is not None and v[1] is not None:
            c, s_ = math.cos(math.radians(rot)), math.sin(math.radians(rot))
            v[0], v[1] = v[0] * c - v[1] * s_, v[0] * s_ + v[1] * c
        return [None if x is None else x + g5x[i] + g92[i] for i, x in enumerate(v)]

    for line in p.stdout.splitlines():
        m = CANON.match(line)
        if not m:
            continue
        name, args = m.group(1), numbers(m.group(2))
        if name == "USE_LENGTH_UNITS":
            factor = 25.4 if "INCH" in m.group(2) else (10.0 if "CM" in m.group(2) else 1.0)
            inch_seen = inch_seen or factor == 25.4
        elif name == "SET_G5X_OFFSET":
            v = [a for a in args if isinstance(a, float)][1:7]
            g5x = [x * factor for x in v[:3]] + list(v[3:6]) + [0.0] * (6 - len(v))
        elif name == "SET_G92_OFFSET":
            v = [a for a in args if isinstance(a, float)][:6]
            g92 = [x * factor for x in v[:3]] + list(v[3:6]) + [0.0] * (6 - len(v))
        elif name == "SET_XY_ROTATION":
            rot = float(args[0]) if args and isinstance(args[0], float) else 0.0
        elif name == "SELECT_PLANE":
            plane = {"CANON_PLANE_XY": "XY", "CANON_PLANE_XZ": "XZ", "CANON_PLANE_YZ": "YZ"}.get(
                m.group(2).strip(), m.group(2).strip())
        elif name in ("STRAIGHT_TRAVERSE", "STRAIGHT_FEED", "STRAIGHT_PROBE"):
            v = [a for a in args if isinstance(a, float)]
            if len(v) < 3:
                continue
            end = [v[0] * factor, v[1] * factor, v[2] * factor] + (v[3:6] + [0.0, 0.0, 0.0])[:3]
            kind = {"STRAIGHT_TRAVERSE": "rapid", "STRAIGHT_FEED": "feed", "STRAIGHT_PROBE": "probe"}[name]
            moves.append({"kind": kind, "end": to_frame(end), "centre": None, "factor": factor})
        elif name == "ARC_FEED":
            v = [a for a in args if isinstance(a, float)]
            if len(v) < 6:
                continue
            fe, se, fc, sc, turn, ae = v[:6]
            abc = (v[6:9] + [0.0, 0.0, 0.0])[:3]
            if plane == "XY":
                end = [fe, se, ae]
                centre = [fc, sc, None]
            elif plane == "XZ":  # first axis Z, second X (LinuxCNC canon)
                end = [se, ae, fe]
                centre = [sc, None, fc]
            else:  # YZ: first Y, second Z
                end = [ae, fe, se]
                centre = [None, fc, sc]
            end = [c * factor for c in end] + abc
            centre = [None if c is None else c * factor for c in centre]
            moves.append({"kind": "ccw" if turn > 0 else "cw", "end": to_frame(end), "centre": to_frame(centre),
                          "factor": factor, "turns": abs(int(turn))})
    step = (0.5e-4 * 25.4) if inch_seen else 0.5e-4
    err = None
    lines = [l.strip() for l in p.stderr.splitlines() if l.strip() and l.strip() != "executing"]
    if lines:
        err = lines[0] + (("  [" + lines[1] + "]") if len(lines) > 1 else "")
    elif p.returncode != 0:
        err = "exit %d" % p.returncode
    return moves, step, err


# ---------------------------------------------------------------- kezuri side

def run_kezuri(program, binary, machine, timeout, emit="csv"):
    cmd = [binary, "run", os.path.basename(program.path), "--to", emit, "--machine", machine]
    cmd += program.kezuri_flags()
    if emit == "linuxcnc":
        # The tool centre, as rs274 prints it (G41/G42 applied, G40).
        cmd += ["--digits", "6", "--apply-comp"]
    try:
        p = subprocess.run(cmd, cwd=os.path.dirname(program.path), capture_output=True, text=True,
                           timeout=timeout, stdin=subprocess.DEVNULL, errors="replace")
    except subprocess.TimeoutExpired:
        return None, "no answer in %g s" % timeout
    if p.returncode != 0:
        msgs = [l for l in p.stderr.splitlines() if re.match(r"^\S.*: error: ", l)]
        first = msgs[0] if msgs else (p.stderr.strip().splitlines() or ["exit %d" % p.returncode])[0]
        return None, first
    return p.stdout, None


def csv_moves(text):
    moves = []
    for i, line in enumerate(text.splitlines()):
        if i == 0 or not line.strip():
            continue
        f = line.split(",")
        if len(f) < 8:
            continue
        moves.append({"kind": f[1], "end": [float(x) for x in f[2:8]], "line": f[0], "centre": None})
    return moves


WORD = re.compile(r"([A-Z])\s*([-+]?(?:\d+\.?\d*|\.\d+))")


def linuxcnc_centres(text):
    """Arc centres (mm) of kezuri's --to linuxcnc output, one entry per move (None for lines)."""
    pos = [0.0, 0.0, 0.0]
    inch = False
    absolute = True
    arc_abs = False
    plane = "XY"
    motion = None
    out = []
    for raw in text.splitlines():
        line = re.sub(r"\(.*?\)|;.*$", "", raw).upper()
        words = WORD.findall(line)
        if not words:
            continue
        g = [float(v) for k, v in words if k == "G"]
        for code in g:
            if code == 20: inch = True
            elif code == 21: inch = False
            elif code == 90: absolute = True
            elif code == 91: absolute = False
            elif code == 90.1: arc_abs = True
            elif code == 91.1: arc_abs = False
            elif code == 17: plane = "XY"
            elif code == 18: plane = "XZ"
            elif code == 19: plane = "YZ"
            elif code in (0, 1, 2, 3): motion = int(code)
        vals = {k: float(v) for k, v in words if k in "XYZIJKR"}
        if not any(k in vals for k in "XYZ") and not any(k in vals for k in "IJK"):
            continue
        if motion is None or any(c in (28, 30, 53, 92, 10, 4) for c in g):
            continue
        u = 25.4 if inch else 1.0
        new = list(pos)
        for i, k in enumerate("XYZ"):
            if k in vals:
                new[i] = vals[k] * u if absolute else pos[i] + vals[k] * u
        centre = None
        if motion in (2, 3):
            centre = [None, None, None]
            for i, k in enumerate("IJK"):
                if k in vals:
                    centre[i] = vals[k] * u if arc_abs else pos[i] + vals[k] * u
            axes = {"XY": (0, 1), "XZ": (0, 2), "YZ": (1, 2)}[plane]
            for i in axes:
                if centre[i] is None:
                    centre[i] = pos[i]
            if "R" in vals:
                centre = [None, None, None]  # an R arc: no centre written
        out.append(centre)
        pos = new
    return out


# ---------------------------------------------------------------- comparison

def drop_zero(moves, start=(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)):
    out = []
    prev = list(start)
    for m in moves:
        if m["kind"] in ("rapid", "feed", "probe") and all(abs(a - b) <= ZERO_MM for a, b in zip(m["end"], prev)):
            continue
        out.append(m)
        prev = m["end"]
    return out


def fmt(v):
    return "(" + ", ".join("-" if c is None else "%.5f" % c for c in v) + ")"


def compare(rs_moves, kz_moves, step):
    tol = ABS_TOL_MM + step
    a = drop_zero(rs_moves)
    b = drop_zero(kz_moves)
    for i in range(min(len(a), len(b))):
        ra, kb = a[i], b[i]
        if ra["kind"] != kb["kind"]:
            return ("move %d (kezuri line %s): rs274 %s to %s, kezuri %s to %s"
                    % (i + 1, kb.get("line", "?"), ra["kind"], fmt(ra["end"]), kb["kind"], fmt(kb["end"])))
        d = max(abs(x - y) for x, y in zip(ra["end"], kb["end"]))
        if d > tol:
            return ("move %d (kezuri line %s, %s): rs274 %s, kezuri %s, off by %.4g mm"
                    % (i + 1, kb.get("line", "?"), ra["kind"], fmt(ra["end"]), fmt(kb["end"]), d))
        if ra["centre"] is not None and kb.get("centre") is not None:
            dc = max((abs(x - y) for x, y in zip(ra["centre"], kb["centre"]) if x is not None and y is not None), default=0.0)
            if dc > tol:
                return ("move %d (kezuri line %s, arc centre): rs274 %s, kezuri %s, off by %.4g mm"
                        % (i + 1, kb.get("line", "?"), fmt(ra["centre"]), fmt(kb["centre"]), dc))
    if len(a) != len(b):
        i = min(len(a), len(b))
        extra = a[i] if len(a) > len(b) else b[i]
        who = "rs274" if len(a) > len(b) else "kezuri"
        return ("move count: rs274 %d, kezuri %d; first extra move (%s) %s to %s"
                % (len(a), len(b), who, extra["kind"], fmt(extra["end"])))
    return None


def one(program, binary, tbl, machine, timeout):
    res = {"program": program.label}
    rs, step, rs_err = run_rs274(program, tbl, timeout)
    csv_text, kz_err = run_kezuri(program, binary, machine, timeout)
    if rs_err is not None and rs_err.startswith("File ended with no percent sign or program end"):
        # A fragment without M2/M30: rs274 ran every block; compare what it printed.
        res["note"] = "no program end (rs274 complains at the end of the file)"
        rs_err = None
    if rs_err is not None:
        res.update(status="rs274 stops", message=rs_err)
        if kz_err is not None:
            res["kezuri"] = kz_err
        return res
    if kz_err is not None:
        res.update(status="kezuri stops", message=kz_err)
        return res
    kz = csv_moves(csv_text)
    centres_checked = False
    if any(m["kind"] in ("cw", "ccw") for m in kz):
        lc_text, lc_err = run_kezuri(program, binary, machine, timeout, emit="linuxcnc")
        if lc_text is not None:
            # kezuri's arcs in its CSV and in its LinuxCNC output, matched in order.
            cs = [c for c in linuxcnc_centres(lc_text) if c is not None]
            arcs = [m for m in kz if m["kind"] in ("cw", "ccw")]
            if len(cs) == len(arcs):
                for m, c in zip(arcs, cs):
                    m["centre"] = c
                centres_checked = True
    diff = compare(rs, kz, step)
    res["moves"] = len(kz)
    res["arcs"] = sum(m["kind"] in ("cw", "ccw") for m in kz)
    res["centres_checked"] = centres_checked
    if diff is None:
        res["status"] = "agree"
    else:
        res.update(status="differ", message=diff)
    return res


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--no-linuxcnc", action="store_true", help="leave out LinuxCNC's installed examples")
    ap.add_argument("--timeout", type=float, default=20.0)
    ap.add_argument("--only", default=None, help="programs whose label contains this")
    ap.add_argument("--file", action="append", default=[],
                    help="compare this LinuxCNC program instead of the corpus (repeatable)")
    a = ap.parse_args()
    if shutil.which("rs274") is None:
        print("rs274 not found: LinuxCNC comparison skipped "
              "(bench/rs274-compare.sh --install installs linuxcnc-uspace)")
        return
    binary = kezuri_binary()
    if not os.path.exists(binary):
        print("kezuri binary not found at %s" % binary)
        return
    if a.file:
        programs = [Program(os.path.abspath(f), "file/" + os.path.basename(f), "file", "units") for f in a.file]
    else:
        programs = [p for p in all_programs(not a.no_linuxcnc) if a.only is None or a.only in p.label]
    tmp = tempfile.mkdtemp(prefix="rs274cmp-")
    try:
        tbl, machine = tool_files(tmp)
        results = [one(p, binary, tbl, machine, a.timeout) for p in programs]
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    order = ["agree", "differ", "kezuri stops", "rs274 stops"]
    counts = {k: sum(r["status"] == k for r in results) for k in order}
    if a.json:
        print(json.dumps({"programs": len(results), "counts": counts, "results": results}, ensure_ascii=False))
        return
    print("rs274 vs kezuri: %d programs: %s" % (len(results), ", ".join("%s %d" % (k, counts[k]) for k in order)))
    for origin in ("shop/", "linuxcnc/", "file/"):
        sub = [r for r in results if r["program"].startswith(origin)]
        if sub:
            print("  %-9s %s" % (origin[:-1], ", ".join("%s %d" % (k, sum(r["status"] == k for r in sub)) for k in order)))
    for k in order:
        sub = [r for r in results if r["status"] == k]
        if not sub:
            continue
        print("\n== %s (%d)" % (k, len(sub)))
        for r in sub:
            if k == "agree":
                print("  %s: %d moves, %d arcs%s%s" % (
                    r["program"], r["moves"], r["arcs"],
                    " (arc centres not compared)" if r["arcs"] and not r.get("centres_checked") else "",
                    ("; " + r["note"]) if r.get("note") else ""))
            else:
                extra = ("  | kezuri: " + r["kezuri"]) if r.get("kezuri") else ""
                print("  %s: %s%s" % (r["program"], r["message"], extra))


if __name__ == "__main__":
    try:
        main()
    except Exception as e:
        print("rs274_compare: %s" % e, file=sys.stderr)
    sys.exit(0)
