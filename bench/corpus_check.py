#!/usr/bin/env python3
"""Runs `kezuri check --json` on every corpus program and groups the stops by reason.

Usage: python3 bench/corpus_check.py [--json] [--no-linuxcnc] [--timeout S]
(bench/corpus-check.sh builds kezuri first and calls this). Exit status 0 always.
"""

import argparse
import json
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from corpus_common import all_programs, kezuri_binary  # noqa: E402

# A G or M code (G83, G05.1, M97) in a message.
CODE = re.compile(r"\b([GM])\s*0*(\d+(?:\.\d+)?)\b", re.I)

# Construct classes: any message that names one of these codes, or says one of these
# words, is one reason, whatever its wording.
CLASSES = [
    ("canned cycles (G73/G74/G76/G81–G89)", {"G73", "G74", "G76", "G81", "G82", "G83", "G84", "G85", "G86",
                                             "G87", "G88", "G89", "G80", "G98", "G99"}, r"canned|drilling cycle"),
    ("cutter radius compensation (G41/G42)", {"G41", "G42", "G41.1", "G42.1", "G40"}, r"cutter (radius )?comp|radius comp"),
    ("coordinate rotation (G68/G69)", {"G68", "G69", "G68.2"}, r"rotation"),
    ("scaling / mirroring (G50/G51/G50.1/G51.1)", {"G50", "G51", "G50.1", "G51.1"}, r"scaling|mirror"),
    ("local coordinate system (G52)", {"G52"}, r"local coordinate"),
    ("polar coordinates (G15/G16)", {"G15", "G16"}, r"polar"),
    ("subprograms (M98/M99/M97/G65/G66)", {"M98", "M99", "M97", "G65", "G66", "G67"}, r"subprogram|macro call"),
    ("high-speed / smoothing modes (G05.1/G187/G64/G61)", {"G5.1", "G187", "G64", "G61", "G61.1"}, r"smoothing|look-?ahead"),
    ("LinuxCNC O-word flow control (sub/if/while/call)", set(), r"\bo-?word|o<|\bendsub\b|\bendwhile\b|named parameter"),
    ("lathe cycles and threading (G33/G70–G76/G96)", {"G33", "G70", "G71", "G72", "G75", "G76", "G96", "G97", "G7", "G8"},
     r"thread|lathe"),
    ("spindle-synchronised tapping (M29)", {"M29"}, r"rigid tap"),
    ("probing (G38.x/G31)", {"G38.2", "G38.3", "G38.4", "G38.5", "G31"}, r"prob"),
    ("tool table / tool change (T, M6, G43)", {"M6", "G43", "G43.1", "G49"}, r"tool (length|table|change)"),
]


def _num(text):
    n = float(text)
    return str(int(n)) if n.is_integer() else str(n)


def normalise(message):
    """A reason: the construct class for a message, or the message with numbers blanked."""
    m = message.strip()
    codes = {c.upper() + _num(n) for c, n in CODE.findall(m)}
    low = m.lower()
    for name, class_codes, words in CLASSES:
        if codes & class_codes or (words and re.search(words, low)):
            return name
    # Unclassified codes stay (G92.1, G30); other numbers and long quoted text go.
    keep = {}

    def hold(mm):
        keep["\0%d\0" % len(keep)] = mm.group(1).upper() + _num(mm.group(2))
        return "\0%d\0" % (len(keep) - 1)

    generic = CODE.sub(hold, m)
    generic = re.sub(r"'[^']{4,}'|\"[^\"]{4,}\"|`[^`]{4,}`", "'…'", generic)
    generic = re.sub(r"#\d+", "#<var>", generic)
    generic = re.sub(r"(?<![\d\0])[-+]?\d+(\.\d+)?(?![\d\0])", "<n>", generic)
    for k, v in keep.items():
        generic = generic.replace(k, v)
    return generic


def headline_parts(headline, program):
    """(file:line, message) from `file:line:col: error: message`."""
    m = re.match(r"^(.*?):(\d+):(\d+): (error|warning): (.*)$", headline, re.S)
    if not m:
        return program.label, headline
    where = "%s:%s" % (program.label, m.group(2))
    if os.path.basename(m.group(1)) != os.path.basename(program.path):
        where += " (in %s)" % os.path.basename(m.group(1))
    return where, m.group(5)


def check(program, binary, timeout):
    cmd = [binary, "check", os.path.basename(program.path), "--json"] + program.kezuri_flags()
    try:
        p = subprocess.run(cmd, cwd=os.path.dirname(program.path), capture_output=True, text=True,
                           timeout=timeout, stdin=subprocess.DEVNULL)
    except subprocess.TimeoutExpired:
        return {"program": program.label, "ok": False, "reason": "timeout (%g s)" % timeout,
                "where": program.label, "message": "no answer in %g s" % timeout}
    out = p.stdout.strip().splitlines()
    data = None
    for line in reversed(out):
        try:
            data = json.loads(line)
            break
        except ValueError:
            continue
    if data is None:
        msg = (p.stderr.strip().splitlines() or ["exit %d, no JSON" % p.returncode])[0]
        if p.returncode not in (0, 1):
            reason = "crashed (exit %d)" % p.returncode
        else:
            reason = normalise(re.sub(r"^error:\s*", "", msg))
        return {"program": program.label, "ok": False, "reason": reason, "where": program.label, "message": msg}
    errors = data.get("errors") or []
    if data.get("completed", not errors) and not errors:
        return {"program": program.label, "ok": True, "motions": data.get("motions"),
                "warnings": len(data.get("warnings") or [])}
    if errors:
        where, msg = headline_parts(errors[0], program)
    else:
        where, msg = program.label, "stopped without an error message"
    return {"program": program.label, "ok": False, "reason": normalise(msg), "where": where, "message": msg}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--json", action="store_true", help="one JSON object on stdout")
    ap.add_argument("--no-linuxcnc", action="store_true", help="leave out LinuxCNC's installed examples")
    ap.add_argument("--timeout", type=float, default=20.0, help="seconds per program (default 20)")
    a = ap.parse_args()
    binary = kezuri_binary()
    if not os.path.exists(binary):
        print("kezuri binary not found at %s (bench/corpus-check.sh builds it)" % binary, file=sys.stderr)
        return 0
    programs = all_programs(include_linuxcnc=not a.no_linuxcnc)
    results = [check(p, binary, a.timeout) for p in programs]
    groups = {}
    for r in results:
        if not r["ok"]:
            groups.setdefault(r["reason"], []).append(r)
    order = sorted(groups.items(), key=lambda kv: (-len(kv[1]), kv[0]))
    by_origin = {}
    for p, r in zip(programs, results):
        o = by_origin.setdefault(p.origin, [0, 0])
        o[0 if r["ok"] else 1] += 1
    if a.json:
        print(json.dumps({
            "programs": len(results),
            "ran_to_end": sum(r["ok"] for r in results),
            "stopped": sum(not r["ok"] for r in results),
            "by_origin": {k: {"ran_to_end": v[0], "stopped": v[1]} for k, v in by_origin.items()},
            "reasons": [{"reason": k, "count": len(v),
                         "programs": [{"where": r["where"], "message": r["message"]} for r in v]} for k, v in order],
        }, ensure_ascii=False))
        return 0
    ok = sum(r["ok"] for r in results)
    print("kezuri check over the corpus: %d programs, %d run to the end, %d stop" % (len(results), ok, len(results) - ok))
    for k, v in sorted(by_origin.items()):
        print("  %-9s %4d run to the end, %4d stop" % (k, v[0], v[1]))
    if order:
        print("\n%5s  %s" % ("stops", "reason (first error, construct normalised)"))
        for k, v in order:
            print("%5d  %s" % (len(v), k))
        for k, v in order:
            print("\n== %s (%d)" % (k, len(v)))
            for r in v:
                print("  %s: %s" % (r["where"], r["message"]))
    return 0


if __name__ == "__main__":
    try:
        main()
    except Exception as e:  # the script reports; it never fails the caller
        print("corpus_check: %s" % e, file=sys.stderr)
    sys.exit(0)
