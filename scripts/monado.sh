#!/usr/bin/env bash
# Builds Monado, the open-source OpenXR runtime, for the host's integration
# tests (xr_host/tests/monado.rs) and prints its runtime manifest (for
# XR_RUNTIME_JSON) on the last line. The build lives in target/monado (or
# $SHAPEWRIGHT_MONADO_DIR), cached like the cargo target: a second run only
# checks (about a second); a cold build takes 3-4 minutes on 2 cores.
# The source and build recipe are the shared tools (../shared/tools/monado:
# Monado from ../shared/vendor, null compositor, `remote` and `simulated`
# drivers); set SHAPEWRIGHT_MONADO_TOOLS to use another copy.
#   manifest=$(bash scripts/monado.sh)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${SHAPEWRIGHT_MONADO_DIR:-$root/target/monado}"
tools="${SHAPEWRIGHT_MONADO_TOOLS:-}"
if [ -z "$tools" ]; then
  for d in "$root/../shared/tools/monado" "$root/../../shared/tools/monado"; do
    if [ -f "$d/build.sh" ]; then tools="$d"; break; fi
  done
fi
if [ -z "$tools" ] || [ ! -f "$tools/build.sh" ]; then
  echo "monado.sh: no Monado build recipe found (looked in ../shared/tools/monado); set SHAPEWRIGHT_MONADO_TOOLS" >&2
  exit 1
fi
mkdir -p "$out"
start=$(date +%s)
manifest="$(bash "$tools/build.sh" "$out" | tail -n 1)"
echo "monado.sh: $manifest ready in $(( $(date +%s) - start )) s" >&2
echo "$manifest"
