#!/usr/bin/env bash
# Installs everything and runs the demo: replays the bundled teapot input
# trace (a scripted hand puppet sketching a generalized-cylinder teapot
# with paper 1's gestures) through the standalone host headless, with no
# OpenXR runtime, and writes the model with its whole op log (USD), the
# printable mesh (STL) and a picture from the host's own Vulkan renderer
# (lavapipe), then checks the files and renders a Blender Workbench view.
#   bash scripts/demo.sh [TRACE.trace.jsonl]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$root/scripts/setup.sh"
cd "$root"

trace="${1:-tests/data/teapot.trace.jsonl}"
name="$(basename "$trace" .trace.jsonl)"
mkdir -p out
cargo build --release -q -p shapewright-xr
bin=target/release/shapewright-xr
"$bin" replay "$trace" --out "out/$name.usda" --stl "out/$name.stl" --png "out/$name.png"
echo
"$bin" info "out/$name.usda"
.venv/bin/python scripts/render.py "out/$name.stl" "out/$name.workbench.png" > out/render.log 2>&1 \
  || { cat out/render.log >&2; exit 1; }
echo
echo "demo: out/$name.usda (model + op log), out/$name.stl (printable mesh),"
echo "      out/$name.png (host renderer) and out/$name.workbench.png (Blender Workbench)"
