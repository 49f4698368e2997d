#!/usr/bin/env bash
# Issue 18's renders into docs/images/: the teapot before and after a body
# spine replace and a spout slide, a 6-sided patch (the hexagon prism of
# scripts/styling/make_ngon_patch.py, top cap domed and sharpened), and a
# sheet of every library component. Meshes come from the ignored test
# core/tests/suite/render_assets.rs; scripts/render.py (Blender Workbench) draws
# them. Usage: scripts/render_issue18.sh  (CARGO_TARGET_DIR is honoured)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
py="${PYTHON:-$root/.venv/bin/python}"
[ -x "$py" ] || py=/work/main/.venv/bin/python
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
"$py" "$root/scripts/styling/make_ngon_patch.py" "$tmp"
(cd "$root/core" && SHAPEWRIGHT_RENDER_DIR="$tmp" SHAPEWRIGHT_NGON_DIR="$tmp" \
    cargo test --test suite render_assets:: -- --ignored --nocapture)
img="$root/docs/images"
mkdir -p "$img"
r() { "$py" "$root/scripts/render.py" "$@"; }
r "$tmp/teapot_before.stl" "$img/issue18_teapot_before.png" --size 900x700 --azimuth 0 --elevation 12
r "$tmp/teapot_edited.stl" "$img/issue18_teapot_spine_replaced_spout_slid.png" --size 900x700 --azimuth 0 --elevation 12
r "$tmp/hexagon.stl" "$img/issue18_hexagon_patch.png" --size 900x700 --azimuth 20 --elevation 75
r "$tmp/hexagon_shaped.stl" "$img/issue18_hexagon_patch_shaped.png" --size 900x700 --azimuth 20 --elevation 30
r "$tmp/library_sheet.stl" "$img/issue18_library_sheet.png" --size 1600x1300 --azimuth 0 --elevation 60
# 256-colour palettes keep the PNGs under 1 MB each.
"$py" - "$img"/issue18_*.png <<'PY'
import sys
from PIL import Image
for p in sys.argv[1:]:
    Image.open(p).convert("RGB").quantize(colors=256, method=Image.Quantize.MEDIANCUT).save(p, optimize=True)
PY
