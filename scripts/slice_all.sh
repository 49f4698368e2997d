#!/usr/bin/env bash
# Slices every example model, the lamp session and the thickened lampshade
# with Debian's PrusaSlicer, from STL and from 3MF, and checks each against
# the document's own size and volume (tests/python/test_slicer.py with
# SHAPEWRIGHT_SLICE_ALL=1; CI runs the same test on a few models). Prints
# each model's time and result, then the total.
#   bash scripts/slice_all.sh [-k PATTERN]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
command -v prusa-slicer >/dev/null || { echo "slice_all: prusa-slicer is missing (bash scripts/setup.sh installs it)" >&2; exit 1; }
cargo build --release -q -p shapewright-xr
start=$(date +%s)
SHAPEWRIGHT_SLICE_ALL=1 .venv/bin/python -m pytest tests/python/test_slicer.py -q -rA \
  --durations=0 -p no:cacheprovider "$@"
echo "slice_all: $(( $(date +%s) - start )) s in all"
