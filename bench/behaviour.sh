#!/usr/bin/env bash
# Checksums of what a kezuri binary makes, to prove a change leaves behaviour alone:
# every file of `kezuri demo` (the tool database as its rows, less the time they were added), and `kezuri run --emit csv` (its standard output, its
# messages and its exit status) of every program under crates/*/testdata.
#
#   bench/behaviour.sh BINARY > before.txt   (then again after the change, and diff)
set -euo pipefail
bin=$(realpath "$1")
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
"$bin" demo --out demo >/dev/null 2>&1
(cd demo && find . -type f ! -name '*.sqlite' | LC_ALL=C sort | xargs sha256sum) | sed 's/^/demo /'
# The tool database records when each row was added: its dump, that time column blanked.
python3 - demo/tools.sqlite <<'PY' | sha256sum | sed 's/^/demo tools.sqlite (dump, added-at blanked) /'
import re, sqlite3, sys
for line in sqlite3.connect(sys.argv[1]).iterdump():
    print(re.sub(r"'\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ','[^']*'", "'T','T'", line))
PY
cd "$root"
find crates/*/testdata -type f \( -name '*.nc' -o -name '*.ngc' -o -name '*.rml' \) | LC_ALL=C sort |
while read -r f; do
    set +e
    out=$("$bin" run --emit csv "$f" 2>"$work/err" | sha256sum | cut -c1-16)
    rc=${PIPESTATUS[0]}
    set -e
    err=$(sha256sum <"$work/err" | cut -c1-16)
    echo "run $f stdout=$out stderr=$err rc=$rc"
done
