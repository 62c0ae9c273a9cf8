#!/bin/sh
# Drop-cutter against OpenCAMLib (see bench/ocl_dropcut.py and BENCHMARKS.md).
# Usage: bench/ocl_dropcut.sh [KINDS-ON-ONE-CORE]   (default: ball; e.g. flat,ball,bull)
set -eu
cd "$(dirname "$0")/.."
VENV=${OCL_VENV:-/tmp/ocl-venv}
if [ ! -x "$VENV/bin/python" ] || ! "$VENV/bin/python" -c 'import opencamlib, numpy' 2>/dev/null; then
    python3 -m venv "$VENV"
    "$VENV/bin/pip" install --quiet opencamlib numpy
fi
cargo build --release --quiet -p kezuri
exec "$VENV/bin/python" bench/ocl_dropcut.py "$@"
