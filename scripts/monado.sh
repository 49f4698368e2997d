#!/usr/bin/env bash
# Builds Monado, the open-source OpenXR runtime, for the host's integration
# tests (xr_host/tests/monado.rs) and prints its runtime manifest (for
# XR_RUNTIME_JSON) on the last line. The build lives in target/monado (or
# $SHAPEWRIGHT_MONADO_DIR), cached like the cargo target: a second run only
# checks (about a second); a cold build took 56 s on 2 cores (2026-11-29, packages installed).
# The source and build recipe are vendored in third_party/monado (Monado's
# source tarball, BSL-1.0; null compositor, `remote` and `simulated`
# drivers); nothing outside the repository is read.
#   manifest=$(bash scripts/monado.sh)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${SHAPEWRIGHT_MONADO_DIR:-$root/target/monado}"
tools="$root/third_party/monado"
if [ ! -f "$tools/build.sh" ] || ! ls "$tools"/monado-src-*.tar.xz >/dev/null 2>&1; then
  echo "monado.sh: the vendored Monado source or recipe is missing from $tools (a partial checkout?)" >&2
  exit 1
fi
mkdir -p "$out"
start=$(date +%s)
manifest="$(bash "$tools/build.sh" "$out" | tail -n 1)"
echo "monado.sh: $manifest ready in $(( $(date +%s) - start )) s" >&2
echo "$manifest"
