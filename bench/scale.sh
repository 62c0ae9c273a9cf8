#!/usr/bin/env bash
# Wall time, CPU time and peak memory of kezuri's program commands on generated G1 rasters
# of growing size, beside LinuxCNC's rs274 on the same file (where it is installed).
#
#   bench/scale.sh [SIZES...]        (default: 100000 1000000; e.g. 100000 1000000 9000000)
#
# Each program is a zig-zag raster, 29 bytes a block: `X… Y… Z…` lines under G1, rows of
# 1,000 blocks. Prints a Markdown table: blocks, command, wall s, user s, sys s, peak RSS
# MiB, and blocks a second (wall). Builds target/release/kezuri when it is missing
# (KEZURI=/path/to/kezuri overrides; KEEP_PAGE=DIR keeps each view page). A command that fails is
# shown with its exit status.
# Measures; never gates.
set -u
cd "$(dirname "$0")/.."
sizes=("$@")
[ ${#sizes[@]} -eq 0 ] && sizes=(100000 1000000)
bin=${KEZURI:-target/release/kezuri}
[ -x "$bin" ] || cargo build --release -p kezuri >/dev/null 2>&1 || { echo "cannot build kezuri" >&2; exit 1; }
bin=$(realpath "$bin")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

generate() { # blocks file
    awk -v n="$1" 'BEGIN {
        print "%"; print "O1000"; print "G21 G90 G17"; print "G0 X0 Y0 Z5."; print "G1 Z-1. F1200."
        for (k = 0; k < n; k++) {
            row = int(k / 1000); i = k % 1000; if (row % 2) i = 999 - i
            printf "X%.3f Y%.3f Z%.3f\n", i * 0.1, row * 0.5, -1 - 0.001 * (k % 7)
        }
        print "G0 Z5."; print "M30"; print "%"
    }' > "$2"
}

measure() { # label blocks command...
    local label=$1 blocks=$2; shift 2
    /usr/bin/time -f "%e %U %S %M" -o "$work/time" "$@" > /dev/null 2> "$work/err"
    local rc=$?
    read -r wall user sys kb < <(tail -1 "$work/time")
    local rate
    rate=$(awk -v b="$blocks" -v w="$wall" 'BEGIN { printf "%.2f M", (w > 0 ? b / w / 1e6 : 0) }')
    local status=""
    [ $rc -ne 0 ] && status=" (exit $rc: $(head -c 80 "$work/err" | tr '\n' ' '))"
    printf "| %s | %s | %s | %s | %s | %.0f | %s%s |\n" "$blocks" "$label" "$wall" "$user" "$sys" \
        "$(awk -v k="$kb" 'BEGIN { print k / 1024 }')" "$rate" "$status"
}

# What the program transforms need: a thermal model fitted to a made-up drift, a worn 1 mm
# ball's profile and a plane under the raster for wear apply.
awk 'BEGIN { print "axis,command_mm,ex_mm,ey_mm,ez_mm"
    for (a = 0; a < 3; a++) for (c = -4000; c <= 4000; c += 2000)
        printf "%s,%d,%g,%g,%g\n", substr("XYZ", a + 1, 1), c, 2.5e-6 * c, 5e-3 + 1e-10 * c * c, -1e-7 * c }' > "$work/meas.csv"
"$bin" thermal fit "$work/meas.csv" --degree 2 -o "$work/model.json" >/dev/null 2>&1
awk 'BEGIN { print "z_mm,radius_mm"; for (i = 0; i <= 20; i++) { z = i * 0.05; d = z < 0.49 ? z : 0.49; printf "%.3f,%.6f\n", z, sqrt(0.49 * 0.49 - (0.49 - d) * (0.49 - d)) } }' > "$work/worn.csv"
{
    echo "solid plane"
    for t in "-1e5 -1e5 1e5 -1e5 1e5 1e5" "-1e5 -1e5 1e5 1e5 -1e5 1e5"; do
        read -r x1 y1 x2 y2 x3 y3 <<< "$t"
        echo " facet normal 0 0 1"; echo "  outer loop"
        echo "   vertex $x1 $y1 -1"; echo "   vertex $x2 $y2 -1"; echo "   vertex $x3 $y3 -1"
        echo "  endloop"; echo " endfacet"
    done
    echo "endsolid plane"
} > "$work/plane.stl"

echo "| blocks | command | wall s | user s | sys s | peak MiB | blocks/s |"
echo "|---|---|---|---|---|---|---|"
for n in "${sizes[@]}"; do
    f="$work/raster-$n.nc"
    generate "$n" "$f"
    measure "check" "$n" "$bin" check "$f"
    measure "run -o" "$n" "$bin" run "$f" -o "$work/out.nc"
    measure "run --emit csv -o" "$n" "$bin" run "$f" --emit csv -o "$work/out.csv"
    # view draws the path as the run hands it on: past some 3e6 moves it is simplified to fit
    # the default 32 MB page (the page kept with KEEP_PAGE=DIR, e.g. to open it in Chromium).
    measure "view" "$n" "$bin" view "$f" -o "$work/page.html"
    [ -n "${KEEP_PAGE:-}" ] && cp "$work/page.html" "$KEEP_PAGE/view-$n.html"
    measure "convert -o .ngc" "$n" "$bin" convert "$f" -o "$work/out.ngc"
    measure "thermal apply -o" "$n" "$bin" thermal apply "$f" --model "$work/model.json" --allow-extrapolation -o "$work/out.nc"
    measure "wear apply -o" "$n" "$bin" wear apply "$f" --profile "$work/worn.csv" --nominal ball:1 --surface "$work/plane.stl" -o "$work/out.nc"
    # sim over a 100 × 100 mm stock at 0.1 mm (a million cells): the moves past it skipped by their box.
    measure "sim" "$n" "$bin" sim "$f" --tool ball:2 --res 0.1 --stock 0,0,100,100,0
    if command -v rs274 >/dev/null; then
        # rs274 reads .ngc; the same text as a LinuxCNC program (no O word, no %).
        grep -v '^[%O]' "$f" > "$work/raster.ngc"
        measure "rs274" "$n" rs274 -g "$work/raster.ngc"
    fi
    rm -f "$f" "$work/out.nc" "$work/out.ngc" "$work/out.csv" "$work/page.html" "$work/raster.ngc"
done
