#!/usr/bin/env bash
# Installs everything and runs the demo: the standalone host replays a
# recorded hand-tracking session headless (no OpenXR runtime needed), in
# which a teapot is modelled by hand gestures alone (paper 1: OPEN aims,
# POINT sketches sections and spines, FIST drags rings, PINCH opens
# ends, a 3 s hold inserts a section). The same interaction core a headset
# drives turns the recorded joints into ops; the host writes
#   out/teapot.usda  the model with its whole op log (reopen it to undo),
#   out/teapot.stl   the printable union: one closed 2-manifold,
#   out/teapot.png   a picture from the host's own Vulkan renderer (lavapipe),
# and prints a one-screen summary. Then the lamp session (issue 19): the
# same outputs as out/lamp.*, plus out/lamp_headset.png, the headset view
# with the palette open.
#   bash scripts/demo.sh [TRACE.trace.jsonl]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$root/scripts/setup.sh"
cd "$root"

trace="${1:-tests/data/teapot.trace.jsonl}"
name="$(basename "$trace" .trace.jsonl)"
mkdir -p out
# A user gets the release build. Under scripts/test.sh
# (SHAPEWRIGHT_TEST_PROFILE=dev) the demo test runs the host that
# `cargo test --workspace` has just built in cargo's dev profile, as every
# other test does (tests/conftest.py: dependencies optimized, the same
# bits), instead of a second, optimized build of the whole core: that
# cold release build, from this test, was 7.7 minutes of a 61.7-minute
# cold run of scripts/test.sh (2026-11-29).
# scripts/release.sh builds the release host it ships.
profile="${SHAPEWRIGHT_TEST_PROFILE:-release}"
[ "$profile" = dev ] && dir=debug || dir="$profile"
bin="${CARGO_TARGET_DIR:-target}/$dir/shapewright-xr"
# dev: build only when it is missing; built alone, the host's features
# differ from the workspace's, and the core would compile again. So with
# SHAPEWRIGHT_TEST_PROFILE=dev set by hand, run `cargo test --workspace`
# first, or the demo runs an older dev host (as tests/conftest.py does).
if [ "$profile" != dev ] || [ ! -x "$bin" ]; then
    cargo build --profile "$profile" -q -p shapewright-xr
fi
"$bin" replay "$trace" --out "out/$name.usda" --stl "out/$name.stl" --png "out/$name.png"
echo
"$bin" info "out/$name.usda"
echo
echo "demo: out/$name.usda (model + op log), out/$name.stl (printable), out/$name.png (host render)"
if [ $# -eq 0 ]; then
    # The second picture: a desk lamp made in one modeler session (every
    # tool switched through the off hand's palette), and the headset view
    # with the palette open while the shade is dragged.
    echo
    "$bin" replay tests/data/lamp_session.trace.jsonl --out out/lamp.usda --stl out/lamp.stl \
        --png out/lamp.png --view-png out/lamp_headset.png --view-at 43.5
    echo "demo: out/lamp.usda, out/lamp.stl, out/lamp.png, out/lamp_headset.png (the headset view)"
fi
