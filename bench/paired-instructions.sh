#!/usr/bin/env bash
# Instructions two kezuri binaries take for the same whole-process jobs, counted by
# callgrind (repeatable whatever else the machine is doing), and their ratio.
#
#   bench/paired-instructions.sh OLD_BINARY NEW_BINARY
#
# The jobs run on the bundled samples and on a 100,000-block G1 raster made here.
set -euo pipefail
old=$(realpath "$1"); new=$(realpath "$2")
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
cp -r "$root/samples" samples
python3 - <<'PY'
lines = ["%", "O1000", "G21 G90 G17", "G0 X0 Y0 Z5.", "G1 Z-1. F1200"]
for row in range(100):
    for i in range(1000):
        x = i * 0.1 if row % 2 == 0 else (999 - i) * 0.1
        lines.append(f"X{x:.3f} Z{-1 - 0.001 * (i % 7):.3f}")
    lines.append(f"Y{(row + 1) * 0.5:.3f}")
lines += ["G0 Z5.", "M30", "%"]
open("raster.nc", "w").write("\n".join(lines) + "\n")
PY
"$new" demo --only thermal --out demo >/dev/null 2>&1
"$new" thermal measure demo/thermal/index.csv -o meas.csv -q
"$new" thermal fit meas.csv --machine samples/mill-turn.toml -o model.json -q >/dev/null
jobs=(
  "check raster.nc"
  "run raster.nc --to linuxcnc -o OUT.ngc"
  "view raster.nc -o OUT.html"
  "relief samples/plum-sketch.png --width 20 --depth 1 --smooth 2 --tool ball:0.5 --stepover 0.5 --post grbl -o OUT.gcode"
  "sim samples/nameplate-cam.nc --tool ball:6 --res 0.2 -o OUT.png"
  "view samples/nameplate-cam.nc --sim --tool ball:6 --res 0.2 -o OUT-sim.html"
  "thermal apply samples/o2007-thermal.nc --model model.json --machine samples/mill-turn.toml --allow-extrapolation -o OUT.nc"
)
count() {
    valgrind --tool=callgrind --callgrind-out-file=/dev/null "$@" 2>&1 >/dev/null | grep -o 'Collected : [0-9]*' | grep -o '[0-9]*'
}
printf '%-12s %16s %16s %8s\n' job old new new/old
for j in "${jobs[@]}"; do
    read -r -a words <<<"$j"
    a=$(count "$old" -q "${words[@]/OUT/old}")
    b=$(count "$new" -q "${words[@]/OUT/new}")
    label=${words[0]}; [[ $j == *--sim* ]] && label="$label --sim"
    printf '%-12s %16s %16s %8.4f\n' "$label" "$a" "$b" "$(echo "$b / $a" | bc -l)"
done
