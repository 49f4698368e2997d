#!/usr/bin/env bash
# Installs everything and runs the demo:
# 1. builds the bundled teapot (a generalized-cylinder assembly: container
#    body, shell spout, solid handle, lid) from its op script and writes
#    the printable STL and the USD file with the whole op log;
# 2. replays a recorded controller session (the paper-2 CSG cup, made by a
#    scripted puppet) through the standalone host headless, with no OpenXR
#    runtime: the same interaction core a headset drives, writing USD, STL
#    and a picture from the host's own Vulkan renderer (lavapipe);
# then checks the files and renders the teapot with Blender Workbench.
#   bash scripts/demo.sh [SCRIPT.jsonl [TRACE.trace.jsonl]]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$root/scripts/setup.sh"
cd "$root"

script="${1:-tests/data/teapot.jsonl}"
trace="${2:-tests/data/csg_cup.trace.jsonl}"
name="$(basename "$script" .jsonl)"
tname="$(basename "$trace" .trace.jsonl)"
mkdir -p out
cargo build --release -q -p shapewright-xr
bin=target/release/shapewright-xr
"$bin" apply "$script" --out "out/$name.stl"
"$bin" apply "$script" --out "out/$name.usda"
"$bin" info "out/$name.usda"
.venv/bin/python scripts/render.py "out/$name.stl" "out/$name.png" > out/render.log 2>&1 \
  || { cat out/render.log >&2; exit 1; }
echo
"$bin" replay "$trace" --out "out/$tname.usda" --stl "out/$tname.stl" --png "out/$tname.png"
echo
echo "demo: out/$name.{stl,usda,png} (teapot: printable mesh, model + op log, Workbench render)"
echo "      out/$tname.{stl,usda,png} (replayed VR session: mesh, model + op log, host render)"
