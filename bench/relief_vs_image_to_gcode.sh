#!/usr/bin/env bash
# kezuri relief side by side with LinuxCNC's image-to-gcode (bench/relief_vs_image_to_gcode.py
# says what is timed). Fetches Debian's linuxcnc-uspace package (for its image-to-gcode script
# and the rs274 Python package beside it; nothing of it is installed or committed), makes a
# venv with numpy < 2 and Pillow, builds kezuri.
#   bench/relief_vs_image_to_gcode.sh            # the issue's 1024 x 1024 case
#   SIZE=256 RUNS=5 bench/relief_vs_image_to_gcode.sh
set -euo pipefail
cd "$(dirname "$0")/.."
CACHE="${XDG_CACHE_HOME:-$HOME/.cache}/kezuri-bench"
mkdir -p "$CACHE"
if [ ! -d "$CACHE/linuxcnc/usr/bin" ]; then
    (cd "$CACHE" && apt-get download linuxcnc-uspace >/dev/null 2>&1 && dpkg-deb -x linuxcnc-uspace_*.deb linuxcnc)
fi
if [ ! -x "$CACHE/venv/bin/python" ]; then
    python3 -m venv "$CACHE/venv"
    "$CACHE/venv/bin/pip" install --quiet "numpy<2" pillow
fi
cargo build --release --quiet
IMAGE_TO_GCODE="$CACHE/linuxcnc" KEZURI="$PWD/target/release/kezuri" "$CACHE/venv/bin/python" bench/relief_vs_image_to_gcode.py
