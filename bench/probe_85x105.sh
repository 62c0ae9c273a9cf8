#!/usr/bin/env bash
# Seed 000's pipeline on the paper's 85 x 105 grid (1 mm pitch): the demo's simulated
# capture of the plum-blossom rice mould (10 mm ball stylus, tilt, ±0.003 mm noise)
# through `probe level`, `probe export` (DXF, STL, PNG, CSV at once) and `probe mill`
# (10 mm stylus, the paper's 10 mm ball end mill, stepover and step 1 mm, flat top at rapid).
# Each command is run RUNS times (default 5) as a whole process, release build; prints the
# median wall time of each and of the three together.
#
#   bench/probe_85x105.sh            # from the repository root
#   RUNS=9 bench/probe_85x105.sh
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet
K="$PWD/target/release/kezuri"
RUNS="${RUNS:-5}"
W="$(mktemp -d)"
trap 'rm -rf "$W"' EXIT
"$K" demo --out "$W/demo" >/dev/null 2>&1
cp "$W/demo/plum.txt" "$W/plum.txt"
cd "$W"

median() { sort -n | awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }'; }
timed() { # NAME COMMAND...: prints NAME and the median seconds of RUNS runs
    local name="$1"; shift
    local t=()
    for _ in $(seq "$RUNS"); do
        local s e
        s=$(date +%s.%N); "$@" >/dev/null 2>&1; e=$(date +%s.%N)
        t+=("$(awk "BEGIN { print $e - $s }")")
    done
    printf '%s\n' "${t[@]}" | median | xargs printf '%-58s %6.3f s\n' "$name"
}

echo "85 x 105 points, $RUNS runs each, median wall time ($(nproc) cores)"
timed "probe level --reference border" \
    "$K" probe level plum.txt --reference border -o plum-level.txt
timed "probe export --dxf --stl --png --csv" \
    "$K" probe export plum-level.txt --dxf p.dxf --stl p.stl --png p.png --csv p.csv
timed "probe mill --tool ball:10 (resolution pitch/8)" \
    "$K" probe mill plum-level.txt --stylus ball:10 --tool ball:10 -o p.nc
timed "probe mill --tool ball:10 --res 0.25" \
    "$K" probe mill plum-level.txt --stylus ball:10 --tool ball:10 --res 0.25 -o p.nc
timed "probe mill --tool ball:6 (resolution pitch/8)" \
    "$K" probe mill plum-level.txt --stylus ball:10 --tool ball:6 -o p.nc
timed "probe mill --tool flat:6 (resolution pitch/8)" \
    "$K" probe mill plum-level.txt --stylus ball:10 --tool flat:6 -o p.nc
timed "level + export + mill ball:10 (one shell)" sh -c \
    "'$K' probe level plum.txt --reference border -o l.txt && \
     '$K' probe export l.txt --dxf p.dxf --stl p.stl --png p.png --csv p.csv && \
     '$K' probe mill l.txt --stylus ball:10 --tool ball:10 -o p.nc"
