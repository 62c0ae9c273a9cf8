#!/usr/bin/env bash
# CAM at scale: wall, CPU and peak RSS (/usr/bin/time -v) of `kezuri dropcut` and `kezuri mill`
# on a wavy surface of 320,000 triangles, and of `kezuri dropcut` on one of 20 million (1 GB).
#
#   bench/cam_scale.sh [KEZURI] [BEFORE]     # default target/release/kezuri; BEFORE: a second
#                                            # binary to run beside it and compare outputs with
#
# The STLs are made by bench/wavy_stl.py in a scratch folder (removed at the end); the 1 GB one
# needs 1 GB of disk and takes some minutes of Python. Skip it with SMALL_ONLY=1.
set -euo pipefail
cd "$(dirname "$0")/.."
KEZURI=${1:-target/release/kezuri}
BEFORE=${2:-}
dir=$(mktemp -d /tmp/kezuri-cam-scale.XXXXXX)
trap 'rm -rf "$dir"' EXIT

measure() { # label, command...: one line: label, user s, system s, wall, peak RSS MiB
  local label=$1; shift
  /usr/bin/time -v "$@" 2>"$dir/time" >/dev/null || { tail -3 "$dir/time"; return 1; }
  awk -v l="$label" -F': ' '/User time/{u=$2} /System time/{s=$2} /Elapsed/{w=$2}
    /Maximum resident/{m=$2} END{printf "%-44s user %6.2f s  sys %5.2f s  wall %8s  peak %7.1f MiB\n", l, u, s, w, m/1024}' "$dir/time"
}

bins=("$KEZURI")
[ -n "$BEFORE" ] && bins+=("$BEFORE")

python3 bench/wavy_stl.py 400 200 "$dir/w320k.stl"
for b in "${bins[@]}"; do
  tag=$(basename "$b")
  measure "$tag dropcut 320k tri, 160,801 pts" "$b" dropcut "$dir/w320k.stl" --tool ball:6 --grid 0,0,200,200,0.5 -o "$dir/$tag.cl"
  measure "$tag dropcut 320k tri, 1 pt (mesh+index)" "$b" dropcut "$dir/w320k.stl" --tool ball:6 --grid 100,100,100,100,1 -o "$dir/$tag.1.cl"
  measure "$tag mill ball:6 stepover 2" "$b" mill "$dir/w320k.stl" --tool ball:6 --stepover 2 -o "$dir/$tag.nc"
  measure "$tag mill flat:6 stepover 2" "$b" mill "$dir/w320k.stl" --tool flat:6 --stepover 2 -o "$dir/$tag.flat.nc"
  # Four times the lines on the same mesh: what memory a line costs.
  measure "$tag mill ball:6 stepover 0.5" "$b" mill "$dir/w320k.stl" --tool ball:6 --stepover 0.5 -o "$dir/$tag.fine.nc"
  # (One file at a time: `wc … | head` could stop wc early, which pipefail takes for a failure.)
  for f in "$dir/$tag.cl" "$dir/$tag.nc" "$dir/$tag.flat.nc" "$dir/$tag.fine.nc"; do wc -l "$f"; done
done
if [ -n "$BEFORE" ]; then
  b=$(basename "$BEFORE"); a=$(basename "$KEZURI")
  for f in cl 1.cl nc flat.nc fine.nc; do cmp "$dir/$a.$f" "$dir/$b.$f" && echo "identical: $f"; done
fi
rm -f "$dir/w320k.stl"

[ "${SMALL_ONLY:-}" = 1 ] && exit 0
free -g | head -2; df -h "$dir" | tail -1
python3 bench/wavy_stl.py 3163 1000 "$dir/w20m.stl"
ls -l "$dir/w20m.stl"
for b in "${bins[@]}"; do
  tag=$(basename "$b")
  measure "$tag dropcut 20M tri, 40,401 pts" "$b" dropcut "$dir/w20m.stl" --tool ball:6 --grid 0,0,1000,1000,5 -o "$dir/$tag.20m.cl"
done
[ -n "$BEFORE" ] && cmp "$dir/$(basename "$KEZURI").20m.cl" "$dir/$(basename "$BEFORE").20m.cl" && echo "identical: 20m"
