"""Render a G-code file's extrusion moves to a PNG, as a slicer's preview
shows the sliced layers: every extruding move of the model's features,
coloured by its feature type (PrusaSlicer's colours), seen from above at
an angle, nearest move in front (a z-buffer). Pure numpy; the PNG is
written with zlib.

Usage: python scripts/gcode_preview.py IN.gcode OUT.png [--size 960x720]
       [--azimuth 35] [--elevation 35] [--title TEXT]
"""

from __future__ import annotations

import argparse
import math
import re
import struct
import zlib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

# PrusaSlicer 2.5's preview colours per ;TYPE: (RGB 0-255).
COLORS = {
    "External perimeter": (255, 125, 56),
    "Perimeter": (255, 230, 77),
    "Overhang perimeter": (0, 0, 255),
    "Internal infill": (176, 48, 41),
    "Solid infill": (150, 84, 204),
    "Top solid infill": (240, 64, 64),
    "Bridge infill": (77, 128, 186),
    "Gap fill": (255, 255, 255),
    "Support material": (0, 255, 0),
    "Support material interface": (0, 128, 0),
}
OTHER = (200, 200, 200)
SKIP = {"", "Custom", "Skirt", "Skirt/Brim", "Brim", "Wipe tower"}


@dataclass
class Extrusions:
    """What a G-code file extrudes for the model's own features (skirt,
    brim, wipe tower and custom start/end code left out)."""

    # One row per extruding move: x0, y0, x1, y1, z.
    moves: np.ndarray
    # Each move's feature type (`;TYPE:` of PrusaSlicer's G-code).
    kinds: list[str]
    # `;LAYER_CHANGE` markers.
    layers: int
    # The external perimeter extrusion width in mm, from the G-code's
    # settings block (None when absent).
    width: float | None


def extrusions(text: str) -> Extrusions:
    """The extruding moves of `text` (absolute or relative E, `G92 E`
    resets): the one G-code reader of this preview and of
    tests/python/test_slicer.py."""
    x = y = z = None
    e_abs = 0.0
    relative = False
    kind = ""
    rows: list[tuple[float, float, float, float, float]] = []
    kinds: list[str] = []
    layers = 0
    width = None
    for line in text.splitlines():
        if line.startswith(";TYPE:"):
            kind = line[6:].strip()
            continue
        if line.startswith(";LAYER_CHANGE"):
            layers += 1
            continue
        m = re.match(r"; external perimeters extrusion width = ([\d.]+)mm", line)
        if m:
            width = float(m[1])
        code = line.split(";", 1)[0].split()
        if not code:
            continue
        if code[0] == "M83":
            relative = True
        elif code[0] == "M82":
            relative = False
        elif code[0] == "G92":
            for w in code[1:]:
                if w[0] == "E":
                    e_abs = float(w[1:])
        elif code[0] in ("G0", "G1"):
            d = {w[0]: float(w[1:]) for w in code[1:] if w[0] in "XYZEF"}
            nx, ny, nz = d.get("X", x), d.get("Y", y), d.get("Z", z)
            e = d.get("E")
            extrudes = e is not None and (e > 0 if relative else e > e_abs)
            if e is not None and not relative:
                e_abs = e
            if extrudes and kind not in SKIP and None not in (x, y, nx, ny, nz):
                rows.append((x, y, nx, ny, nz))
                kinds.append(kind)
            x, y, z = nx, ny, nz
    return Extrusions(np.array(rows, dtype=np.float64).reshape(-1, 5), kinds, layers, width)


def segments(text: str) -> tuple[np.ndarray, list[tuple[int, int, int]]]:
    """Extruding moves as rows (x0, y0, x1, y1, z, color index)."""
    ex = extrusions(text)
    palette: list[tuple[int, int, int]] = []
    index: dict[tuple[int, int, int], int] = {}
    colors = []
    for kind in ex.kinds:
        color = COLORS.get(kind, OTHER)
        if color not in index:
            index[color] = len(palette)
            palette.append(color)
        colors.append(index[color])
    rows = np.column_stack([ex.moves, np.array(colors, dtype=np.float64)]) if ex.kinds else np.zeros((0, 6))
    return rows, palette


def write_png(path: Path, rgb: np.ndarray) -> None:
    h, w, _ = rgb.shape
    raw = b"".join(b"\x00" + rgb[r].astype(np.uint8).tobytes() for r in range(h))

    def chunk(tag: bytes, data: bytes) -> bytes:
        return (
            struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)
        )

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    path.write_bytes(png)


def render(segs: np.ndarray, palette: list, size: tuple[int, int], az: float, el: float) -> np.ndarray:
    w, h = size
    a, e = math.radians(az), math.radians(el)
    # Camera axes: right, up, and the direction towards the viewer.
    fwd = np.array([math.cos(e) * math.sin(a), -math.cos(e) * math.cos(a), math.sin(e)])
    right = np.array([math.cos(a), math.sin(a), 0.0])
    up = np.cross(fwd, right)
    p0 = np.column_stack([segs[:, 0], segs[:, 1], segs[:, 4]])
    p1 = np.column_stack([segs[:, 2], segs[:, 3], segs[:, 4]])
    # Sample each move every ~0.25 mm.
    lengths = np.linalg.norm(p1 - p0, axis=1)
    n = np.maximum(1, np.ceil(lengths / 0.25).astype(int))
    seg_of = np.repeat(np.arange(len(segs)), n)
    t = (np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n)) / np.repeat(n, n)
    pts = p0[seg_of] + (p1 - p0)[seg_of] * t[:, None]
    u, v, depth = pts @ right, pts @ up, pts @ fwd
    margin = 0.06
    span = max(u.max() - u.min(), (v.max() - v.min()) * w / h)
    scale = (1 - 2 * margin) * w / span
    cu, cv = (u.max() + u.min()) / 2, (v.max() + v.min()) / 2
    px = np.round(w / 2 + (u - cu) * scale).astype(int)
    py = np.round(h / 2 - (v - cv) * scale).astype(int)
    zmin, zmax = segs[:, 4].min(), segs[:, 4].max()
    shade = 0.55 + 0.45 * (pts[:, 2] - zmin) / max(zmax - zmin, 1e-9)
    # Every other layer a little darker, so the layers show.
    layer = np.searchsorted(np.unique(segs[:, 4]), segs[seg_of, 4])
    shade *= 1.0 - 0.1 * (layer % 2)
    colors = np.array(palette, dtype=np.float64)[segs[seg_of, 5].astype(int)] * shade[:, None]
    image = np.full((h, w, 3), 250.0)
    zbuf = np.full((h, w), -np.inf)
    # Nearest last: sort by depth, then draw a 2x2 dot per sample.
    order = np.argsort(depth)
    for dx, dy in ((0, 0), (1, 0), (0, 1), (1, 1)):
        x, y = px[order] + dx, py[order] + dy
        ok = (x >= 0) & (x < w) & (y >= 0) & (y < h)
        x, y, d, c = x[ok], y[ok], depth[order][ok], colors[order][ok]
        flat = y * w + x
        # Later (nearer) samples overwrite earlier ones.
        zb = zbuf.reshape(-1)
        img = image.reshape(-1, 3)
        nearer = d >= zb[flat]
        img[flat[nearer]] = c[nearer]
        zb[flat[nearer]] = d[nearer]
    return np.clip(image, 0, 255)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("gcode", type=Path)
    p.add_argument("png", type=Path)
    p.add_argument("--size", default="960x720")
    p.add_argument("--azimuth", type=float, default=35.0)
    p.add_argument("--elevation", type=float, default=35.0)
    a = p.parse_args()
    size = tuple(int(s) for s in a.size.lower().split("x"))
    segs, palette = segments(a.gcode.read_text())
    if len(segs) == 0:
        raise SystemExit(f"gcode_preview.py: {a.gcode} has no extruding moves")
    write_png(a.png, render(segs, palette, size, a.azimuth, a.elevation))
    layers = len(np.unique(segs[:, 4]))
    print(f"{a.gcode} -> {a.png}: {len(segs)} extruding moves, {layers} layers")


if __name__ == "__main__":
    main()
