#!/bin/sh
# `kezuri view` on 100,000- and 1,000,000-move programs: the time and peak
# memory to write the page (median of 5), its size, and in headless Chromium
# (SwiftShader WebGL2) the time to the first frame, a slider step of 1,000
# moves and a full redraw (crates/cli/tests/browser/bench.mjs).
#
#   bench/view.sh            (needs chromium and npm: .ci/run installs them)
set -eu
cd "$(dirname "$0")/.."
cargo build --release -q -p kezuri
dir=${TMPDIR:-/tmp}/kezuri-view-bench
mkdir -p "$dir"
for n in 100000 1000000; do
    python3 bench/view_program.py $n > "$dir/$n.nc"
    for i in 1 2 3 4 5; do
        /usr/bin/time -f "%e s %M KB" target/release/kezuri view "$dir/$n.nc" -o "$dir/$n.html" 2>&1 >/dev/null | tail -1
    done | sort -n | sed -n 3p | sed "s/^/$n moves: page written in (median) /"
    ls -l "$dir/$n.html" | awk '{printf "  page %.1f MB\n", $5 / 1e6}'
done
cd crates/cli/tests/browser
[ -d node_modules ] || npm ci --silent
node bench.mjs "$dir/100000.html" "$dir/1000000.html"
