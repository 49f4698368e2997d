#!/usr/bin/env bash
# Issue 33's renders into docs/images/, one per structure/topology fix:
# - issue33_teapot_resized_spout_root.png: the lidless teapot (the first
#   three ops of tests/data/teapot.jsonl) with the body's widest section
#   (2) resized by 1.2, the headset's FIST resize, cut through the spout's
#   plane (y = 0); left the whole cut, right the spout root enlarged: the
#   spout's wall runs into the body's wall on both sides of the bore
#   (before the fix the resize opened a gap there, genus 2 -> 4);
# - issue33_mug_handle_turned.png: tests/data/mug.jsonl before and after
#   gc_transform_part turns the handle 180 degrees about the mug's axis
#   (the rotation used to be applied twice and put the handle inside the
#   body, genus 1 -> 0); top row before | after, bottom row after seen from
#   above | after cut through the handle's plane;
# - csg_cup_4mm.png: tests/data/csg_cup.jsonl at the finest step, 4 mm
#   (a spurious tunnel at the grazing handle junction made it genus 2):
#   the cup, its handle junction enlarged, and the cup cut through the
#   handle's plane: the handle's hole is the one tunnel;
# - csg_cup_copies.png: tests/data/csg_cup.jsonl at 1 cm with three
#   copies of the fused result (sdf_copy_fused) fused by one update: off
#   the lattice (front right), turned a sixth of a turn (back left) and
#   grown by 1.3 (back right). A copy is the fold of the cup's operands:
#   each has the cup's rim and handle (made from the result's mesh, the
#   copy alone had kept 98.3% of the cup's volume at 1 cm). The toothed
#   rims of the copies whose rim is off the grid's planes are the cup's
#   own there (the cup moved off them shows the same): a wall of 1.5
#   cells has two creases in one cell, which one feature vertex cannot
#   hold (issue 33, open).
# Each model is built by the host CLI from an op script written here, its
# genus checked with `shapewright-xr info` (the script fails otherwise),
# cut with scripts/examples/cut_stl.py (manifold3d) and drawn by
# scripts/render.py (Blender Workbench); the panels are put together with
# bpy and numpy (the venv has no Pillow).
# Usage: scripts/render_issue33.sh
#   SHAPEWRIGHT_XR=path/to/shapewright-xr picks the binary (default: the
#   release build in CARGO_TARGET_DIR or target/).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
py="${PYTHON:-$root/.venv/bin/python}"
xr="${SHAPEWRIGHT_XR:-${CARGO_TARGET_DIR:-$root/target}/release/shapewright-xr}"
if [ ! -x "$xr" ]; then
  echo "render_issue33.sh: no $xr; build it (cargo build --release -p shapewright-xr) or set SHAPEWRIGHT_XR" >&2
  exit 1
fi
data="$root/tests/data"
img="$root/docs/images"
mkdir -p "$img"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# The op scripts: the fixtures plus the edit of the issue (kept out of
# tests/data, whose every script has a recorded hash).
head -n 3 "$data/teapot.jsonl" >"$tmp/teapot_resized.jsonl"
echo '{"op": "gc_edit_part", "id": 1, "part": 0, "edit": {"edit": "resize", "section": 2, "factor": 1.2}}' \
  >>"$tmp/teapot_resized.jsonl"
cp "$data/mug.jsonl" "$tmp/mug.jsonl"
cp "$data/mug.jsonl" "$tmp/mug_turned.jsonl"
echo '{"op": "gc_transform_part", "id": 1, "part": 1, "rotate": [0, 0, 1, 0]}' >>"$tmp/mug_turned.jsonl"
cp "$data/csg_cup.jsonl" "$tmp/csg_cup_copies.jsonl"
cat >>"$tmp/csg_cup_copies.jsonl" <<'OPS'
{"op": "sdf_copy_fused", "volume": 1, "name": "off", "csg": "union", "transform": {"translate": [0.41, 0.013, 0.0071], "rotate": [0, 0, 0, 1], "scale": [1, 1, 1]}}
{"op": "sdf_copy_fused", "volume": 1, "name": "turned", "csg": "union", "transform": {"translate": [0.0, 0.45, 0.0033], "rotate": [0, 0, 0.5, 0.8660254037844386], "scale": [1, 1, 1]}}
{"op": "sdf_copy_fused", "volume": 1, "name": "grown", "csg": "union", "transform": {"translate": [0.45, 0.5, 0.0157], "rotate": [0, 0, 0, 1], "scale": [1.3, 1.3, 1.3]}}
{"op": "sdf_update", "volume": 1}
OPS
sed 's/{"op": "sdf_create", "step": 0.01}/{"op": "sdf_create", "step": 0.004}/' \
  "$data/csg_cup.jsonl" >"$tmp/csg_cup_4mm.jsonl"
grep -q '"step": 0.004' "$tmp/csg_cup_4mm.jsonl" || {
  echo "render_issue33.sh: csg_cup.jsonl no longer starts with a 1 cm sdf_create" >&2
  exit 1
}

# Build each one and check what the issue is about: its pieces (one unless
# given), its genus.
build() { # NAME GENUS [PIECES]
  "$xr" apply "$tmp/$1.jsonl" --out "$tmp/$1.stl" >"$tmp/$1.log" 2>&1 || {
    echo "$1: apply failed" >&2
    cat "$tmp/$1.log" >&2
    exit 1
  }
  "$xr" info "$tmp/$1.stl" >"$tmp/$1.info"
  local genus comps vol
  genus="$(sed -n 's/^genus: *//p' "$tmp/$1.info")"
  comps="$(sed -n 's/^components: *//p' "$tmp/$1.info")"
  vol="$(sed -n 's/^signed volume: *.*(\(.*\))$/\1/p' "$tmp/$1.info")"
  echo "$1: genus $genus, $comps component(s), $vol"
  grep -q '^printable: *yes' "$tmp/$1.info" || { echo "$1: not printable" >&2; exit 1; }
  [ "$genus" = "$2" ] && [ "$comps" = "${3:-1}" ] || { echo "$1: want genus $2 in ${3:-1} piece(s)" >&2; exit 1; }
}
build teapot_resized 2
build mug 1
build mug_turned 1
build csg_cup_4mm 1
build csg_cup_copies 4 4

cut() { "$py" "$root/scripts/examples/cut_stl.py" "$tmp/$1.stl" "$tmp/$1_cut.stl" --normal 0,1,0; }
cut teapot_resized
cut mug_turned
cut csg_cup_4mm
# Blender's log (EGL chatter on headless machines) is shown only on failure.
r() {
  "$py" "$root/scripts/render.py" "$@" >"$tmp/render.log" 2>&1 || { cat "$tmp/render.log" >&2; return 1; }
}
# Cuts keep y >= 0 and are seen from -y (azimuth 0), square on the section.
r "$tmp/teapot_resized_cut.stl" "$tmp/teapot.png" --size 3600x2400 --azimuth 0 --elevation 0
r "$tmp/mug.stl" "$tmp/mug.png" --size 960x720 --azimuth 0 --elevation 30
r "$tmp/mug_turned.stl" "$tmp/mug_turned.png" --size 960x720 --azimuth 0 --elevation 30
r "$tmp/mug_turned.stl" "$tmp/mug_turned_top.png" --size 960x720 --azimuth 0 --elevation 80
r "$tmp/mug_turned_cut.stl" "$tmp/mug_turned_cut.png" --size 960x720 --azimuth 0 --elevation 0
r "$tmp/csg_cup_4mm.stl" "$tmp/cup.png" --size 3200x2400 --azimuth 45 --elevation 20
r "$tmp/csg_cup_4mm_cut.stl" "$tmp/cup_cut.png" --size 960x720 --azimuth 0 --elevation 0
r "$tmp/csg_cup_copies.stl" "$tmp/cup_copies.png" --size 1600x1200 --azimuth 20 --elevation 35

# compose OUT HEIGHT PANEL... [-- PANEL...]: rows of panels, each scaled to
# HEIGHT; a panel is FILE[@X0:Y0:X1:Y1 crop][#X0:Y0:X1:Y1 red frame], in
# the file's pixels from its top left.
compose() {
  "$py" - "$@" <<'PY'
import struct
import sys
import zlib
from pathlib import Path

import bpy
import numpy as np


def load(path):
    im = bpy.data.images.load(str(Path(path).resolve()))
    w, h = im.size
    px = np.empty(w * h * 4, dtype=np.float32)
    im.pixels.foreach_get(px)
    return np.round(px.reshape(h, w, 4)[::-1, :, :3] * 255).astype(np.uint8)


def box(text):
    return [int(v) for v in text.split(":")]


def scaled(a, height):
    h, w = a.shape[:2]
    width = round(w * height / h)
    if (w, h) == (width, height):
        return a
    im = bpy.data.images.new("panel", w, h)
    rgba = np.dstack([a, np.full((h, w), 255, np.uint8)])[::-1]
    im.pixels.foreach_set((rgba.astype(np.float32) / 255).ravel())
    im.scale(width, height)
    px = np.empty(width * height * 4, dtype=np.float32)
    im.pixels.foreach_get(px)
    return np.round(px.reshape(height, width, 4)[::-1, :, :3] * 255).astype(np.uint8)


def panel(spec, height):
    spec, _, frame = spec.partition("#")
    path, _, crop = spec.partition("@")
    a = load(path)
    if frame:
        x0, y0, x1, y1 = box(frame)
        t = max(3, round(3 * a.shape[0] / height))
        red = np.array([200, 30, 30], np.uint8)
        a[y0 : y0 + t, x0:x1] = red
        a[y1 - t : y1, x0:x1] = red
        a[y0:y1, x0 : x0 + t] = red
        a[y0:y1, x1 - t : x1] = red
    if crop:
        x0, y0, x1, y1 = box(crop)
        a = a[y0:y1, x0:x1]
    return scaled(a, height)


def palette(a, n=256):
    """256 colours for RGB8 `a` (weighted k-means over its distinct colours
    from a farthest-point start, so it is deterministic) and each pixel's
    index: like Pillow's quantize it keeps these PNGs at 0.2-0.4 MB (the
    renders' dither noise is most of their size)."""
    colours, inverse, counts = np.unique(a.reshape(-1, 3), axis=0, return_inverse=True, return_counts=True)
    c = colours.astype(np.float64)
    if len(c) <= n:
        return colours.astype(np.uint8), inverse.reshape(a.shape[:2])
    picked = [int(counts.argmax())]
    d = ((c - c[picked[0]]) ** 2).sum(1)
    for _ in range(n - 1):
        picked.append(int(d.argmax()))
        d = np.minimum(d, ((c - c[picked[-1]]) ** 2).sum(1))
    centres = c[picked]
    for _ in range(12):
        nearest = ((c[:, None, :] - centres[None]) ** 2).sum(2).argmin(1)
        for k in range(n):
            m = nearest == k
            if m.any():
                centres[k] = (c[m] * counts[m, None]).sum(0) / counts[m].sum()
    nearest = ((c[:, None, :] - centres[None]) ** 2).sum(2).argmin(1)
    return np.round(centres).astype(np.uint8), nearest[inverse].reshape(a.shape[:2])


def png(a, path):
    """Writes RGB8 `a` as an 8-bit palette PNG."""
    h, w = a.shape[:2]
    colours, index = palette(a)
    raw = np.hstack([np.zeros((h, 1), np.uint8), index.astype(np.uint8)]).tobytes()

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

    head = struct.pack(">IIBBBBB", w, h, 8, 3, 0, 0, 0)
    data = (
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", head)
        + chunk(b"PLTE", colours.tobytes())
        + chunk(b"IDAT", zlib.compress(raw, 9))
        + chunk(b"IEND", b"")
    )
    Path(path).write_bytes(data)


out, height, specs = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
gap, white = 10, 255
rows, row = [], []
for s in specs + ["--"]:
    if s == "--":
        parts = [panel(p, height) for p in row]
        strip = [parts[0]]
        for p in parts[1:]:
            strip += [np.full((height, gap, 3), white, np.uint8), p]
        rows.append(np.hstack(strip))
        row = []
    else:
        row.append(s)
width = max(r.shape[1] for r in rows)
rows = [np.pad(r, ((0, 0), (0, width - r.shape[1]), (0, 0)), constant_values=white) for r in rows]
sheet = rows[0]
for r in rows[1:]:
    sheet = np.vstack([sheet, np.full((gap, width, 3), white, np.uint8), r])
png(sheet, out)
print(f"{out}: {sheet.shape[1]}x{sheet.shape[0]}")
PY
}
compose "$img/issue33_teapot_resized_spout_root.png" 800 \
  "$tmp/teapot.png#1950:1040:2950:1840" "$tmp/teapot.png@1950:1040:2950:1840"
compose "$img/issue33_mug_handle_turned.png" 720 \
  "$tmp/mug.png" "$tmp/mug_turned.png" -- "$tmp/mug_turned_top.png" "$tmp/mug_turned_cut.png"
compose "$img/csg_cup_4mm.png" 720 \
  "$tmp/cup.png#1660:840:2540:1860" "$tmp/cup.png@1660:840:2540:1860" "$tmp/cup_cut.png"
compose "$img/csg_cup_copies.png" 900 "$tmp/cup_copies.png"
