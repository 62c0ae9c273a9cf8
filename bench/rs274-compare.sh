#!/usr/bin/env bash
# Compares kezuri's end points with LinuxCNC's standalone interpreter rs274 on every
# corpus program (and LinuxCNC's installed examples, read in place): agree / differ
# (first differing move, both values) / kezuri stops / rs274 stops.
#
#   bench/rs274-compare.sh [--install] [--json] [--no-linuxcnc] [--timeout S] [--only SUBSTR] [--file P.ngc]...
#
# --file     compare these LinuxCNC programs (paths from the repository root) instead of the
#            corpus, e.g. bench/programs/comp-linuxcnc.ngc (G41, G42, G41.1).
#
# --install  apt-get update && apt-get install -y linuxcnc-uspace when rs274 is missing
#            (needs root). Without it a missing rs274 skips the comparison with a message.
# Builds target/release/kezuri when it is missing (KEZURI=/path/to/kezuri overrides).
# Always exits 0.
set -u
cd "$(dirname "$0")/.."
install=0
args=()
for a in "$@"; do
    case "$a" in
        --install) install=1 ;;
        -h|--help) sed -n '2,15p' "$0"; exit 0 ;;
        *) args+=("$a") ;;
    esac
done
if ! command -v rs274 >/dev/null 2>&1; then
    if [ "$install" = 1 ]; then
        (apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y linuxcnc-uspace) >&2 \
            || echo "rs274-compare: installing linuxcnc-uspace failed" >&2
    fi
    if ! command -v rs274 >/dev/null 2>&1; then
        echo "rs274 not found: LinuxCNC comparison skipped (run bench/rs274-compare.sh --install, or apt-get install -y linuxcnc-uspace)"
        exit 0
    fi
fi
if [ -z "${KEZURI:-}" ] && [ ! -x target/release/kezuri ]; then
    echo "rs274-compare: building kezuri (release)…" >&2
    cargo build --release -q -p kezuri >&2 || { echo "rs274-compare: build failed" >&2; exit 0; }
fi
if ! command -v python3 >/dev/null 2>&1; then
    echo "rs274-compare: python3 is needed (apt-get install -y python3)" >&2
    exit 0
fi
python3 bench/rs274_compare.py "${args[@]+"${args[@]}"}"
exit 0
