#!/usr/bin/env bash
# Runs `kezuri check` on every program of corpus/shop (and LinuxCNC's installed example
# programs, read in place, when linuxcnc-uspace is installed), 20 s each, from each
# program's own folder, and prints how many run to the end and why the others stop.
#
#   bench/corpus-check.sh [--json] [--install] [--no-linuxcnc] [--timeout S]
#
# --install  apt-get update && apt-get install -y linuxcnc-uspace first (root), so that
#            LinuxCNC's examples are included.
# Builds target/release/kezuri when it is missing (KEZURI=/path/to/kezuri overrides).
# Always exits 0: it measures, it does not gate.
set -u
cd "$(dirname "$0")/.."
args=()
for a in "$@"; do
    case "$a" in
        --install)
            if ! command -v rs274 >/dev/null 2>&1 || [ ! -d /usr/share/linuxcnc/ncfiles ]; then
                (apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y linuxcnc-uspace) >&2 \
                    || echo "corpus-check: installing linuxcnc-uspace failed; going on without it" >&2
            fi ;;
        -h|--help) sed -n '2,13p' "$0"; exit 0 ;;
        *) args+=("$a") ;;
    esac
done
if [ -z "${KEZURI:-}" ] && [ ! -x target/release/kezuri ]; then
    echo "corpus-check: building kezuri (release)…" >&2
    cargo build --release -q -p kezuri >&2 || { echo "corpus-check: build failed" >&2; exit 0; }
fi
if ! command -v python3 >/dev/null 2>&1; then
    echo "corpus-check: python3 is needed (apt-get install -y python3)" >&2
    exit 0
fi
python3 bench/corpus_check.py "${args[@]+"${args[@]}"}"
exit 0
