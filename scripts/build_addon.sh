#!/usr/bin/env bash
# Builds the Blender extension zip: the abi3-py311 wheel of the native
# module (maturin + zig, tagged manylinux_2_28 as Blender's docs use), then
# the extension package with Blender's own `blender_ext.py build`.
#   bash scripts/build_addon.sh            -> out/shapewright-0.1.0.zip
# SHAPEWRIGHT_ADDON_DEV=1 builds the wheel in the dev profile for the host
# (no zig, no manylinux audit): minutes faster while iterating locally.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
export PATH="$root/.venv/bin:$PATH"
addon=blender_addon/shapewright_blender
rm -rf "$addon/wheels"
mkdir -p "$addon/wheels" out
if [[ "${SHAPEWRIGHT_ADDON_DEV:-}" == 1 ]]; then
  maturin build -q -m blender_addon/native/Cargo.toml --compatibility manylinux_2_28 --auditwheel skip \
    -o "$addon/wheels"
else
  maturin build --release -q -m blender_addon/native/Cargo.toml --zig --compatibility manylinux_2_28 \
    -o "$addon/wheels"
fi
ext_tool="$(python -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')/bpy/5.0/scripts/addons_core/bl_pkg/cli/blender_ext.py"
python "$ext_tool" build --source-dir "$addon" --output-dir out
ls -1 out/shapewright-*.zip
