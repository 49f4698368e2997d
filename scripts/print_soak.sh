#!/usr/bin/env bash
# The printable path's random mixed-document property test at soak size
# (CI runs 300 documents; issue 17 asks for more, reported): prints the
# count of printed documents and of typed refusals by reason. Builds with
# --workspace so the features match the warm CI build.
#   bash scripts/print_soak.sh [DOCS] [FIRST_SEED]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
uptime
SHAPEWRIGHT_PRINT_DOCS="${1:-3000}" SHAPEWRIGHT_PRINT_SEED="${2:-1000}" \
    cargo test -q --workspace --test suite print_props:: -- --nocapture
uptime
