#!/usr/bin/env bash
# blender (issue 20): the extension in the newest Blender that installs
# here as a Python module, besides the 5.0.1 of .venv: bpy 5.2.3 (Python
# 3.13, found on PATH or in pyenv) in its own venv, .venv/bpy-newest.
# Runs the smoke scenario (install and enable the extension, build a mug,
# Blender's USD export and import, undo and redo against the original's
# hashes, a rename) with the zip the main pytest run built.
#   bash scripts/blender_newest.sh [pytest -k expression]
# The full suite against it: bash scripts/blender_newest.sh ''
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
BPY_NEWEST="${SHAPEWRIGHT_BPY_NEWEST:-5.2.3}"
venv="$root/.venv/bpy-newest"
# A Python 3.13 that runs (pyenv's shim on PATH may only say it exists).
py313=""
cands=(python3.13)
if command -v pyenv >/dev/null 2>&1; then
  for v in $(pyenv versions --bare 2>/dev/null | grep '^3\.13' | sort -V -r); do
    cands+=("$(pyenv root)/versions/$v/bin/python3.13")
  done
fi
for c in "${cands[@]}"; do
  if "$c" -c 'import sys; assert sys.version_info[:2] == (3, 13)' >/dev/null 2>&1; then
    py313="$c"
    break
  fi
done
if [ -z "$py313" ]; then
  echo "blender_newest: no Python 3.13 (bpy $BPY_NEWEST needs it); install one (pyenv install 3.13)" >&2
  exit 1
fi
stamp="$venv/.bpy-version"
if [ ! -f "$stamp" ] || [ "$(cat "$stamp")" != "$BPY_NEWEST" ]; then
  rm -rf "$venv"
  "$py313" -m venv "$venv"
  "$venv/bin/pip" install -q "bpy==$BPY_NEWEST" pytest
  echo "$BPY_NEWEST" > "$stamp"
fi
zip="${SHAPEWRIGHT_ADDON_ZIP:-$(ls -1 out/shapewright-*.zip 2>/dev/null | tail -1)}"
[ -n "$zip" ] || { bash scripts/build_addon.sh >/dev/null; zip="$(ls -1 out/shapewright-*.zip | tail -1)"; }
"$venv/bin/python" -c 'import bpy; print("bpy", bpy.app.version_string)'
SHAPEWRIGHT_ADDON_ZIP="$(realpath "$zip")" "$venv/bin/python" -m pytest -q -p no:cacheprovider \
  tests/blender/test_addon.py -k "${1-smoke}"
