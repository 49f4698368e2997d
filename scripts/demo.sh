#!/usr/bin/env bash
# Installs everything and runs the demo: builds the bundled teapot (a
# generalized-cylinder assembly: container body, shell spout, solid handle)
# from its op script, writes the printable STL and the USD file with the
# whole op log, checks both and renders a PNG.
#   bash scripts/demo.sh [SCRIPT.jsonl]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$root/scripts/setup.sh"
cd "$root"

script="${1:-tests/data/teapot.jsonl}"
name="$(basename "$script" .jsonl)"
mkdir -p out
cargo build --release -q -p shapewright-xr
bin=target/release/shapewright-xr
"$bin" apply "$script" --out "out/$name.stl"
"$bin" apply "$script" --out "out/$name.usda"
"$bin" info "out/$name.stl"
"$bin" info "out/$name.usda"
.venv/bin/python scripts/render.py "out/$name.stl" "out/$name.png" > out/render.log 2>&1 \
  || { cat out/render.log >&2; exit 1; }
echo
echo "demo: wrote out/$name.stl (printable mesh), out/$name.usda (model + op log) and out/$name.png (Workbench render)"
