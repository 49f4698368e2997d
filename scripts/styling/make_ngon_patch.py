#!/usr/bin/env python3
"""Writes two op scripts of a hexagonal curve-network prism whose caps are
6-sided patches (issue 18): OUT_DIR/hexagon.jsonl (drawn and filled) and
OUT_DIR/hexagon_shaped.jsonl (the same, then the top hexagon pulled up into
a dome and sharpened, the bottom one smoothed).

The caps' corners rise and fall around the hexagon and their edges bow up
and out, so the caps are curved (a planar loop would give a flat patch).
Each curve is drawn from tracked samples; the loops are found and filled
automatically (6 quads, then the 2 hexagons: patch 6 is the bottom cap,
patch 7 the top). An n-sided patch's (u0, v0) is a point of the regular
n-gon inscribed in the unit square, (0.5, 0.5) its centre.

Usage: python scripts/styling/make_ngon_patch.py OUT_DIR
Then:  shapewright-xr apply OUT_DIR/hexagon.jsonl --out hexagon.stl
"""

import json
import math
import os
import sys

N = 6
R = 0.1  # circumradius, metres
H = 0.12  # height
WAVE = 0.02  # cap corners rise and fall by this
BOW = 0.008  # edges bow outwards


def corner(k, z):
    a = 2 * math.pi * k / N
    return [R * math.cos(a), R * math.sin(a), z + WAVE * math.sin(2 * a + 0.3)]


def edge(a, b, bow, count=12):
    out = []
    for i in range(count + 1):
        s = i / count
        out.append([round(a[j] + (b[j] - a[j]) * s + bow[j] * 4 * s * (1 - s), 9) for j in range(3)])
    return out


def outward(a, b, up):
    mx, my = (a[0] + b[0]) / 2, (a[1] + b[1]) / 2
    length = math.hypot(mx, my)
    return [BOW * mx / length, BOW * my / length, up]


def draw(samples):
    return json.dumps(
        {
            "op": "curve_draw",
            "id": 1,
            "samples": samples,
            "fit": {"mode": "interpolate"},
            "resample": None,
            "snap_tol": 0.001,
        }
    )


def base_lines():
    lines = [json.dumps({"op": "curve_network_create", "resolution": 24, "surface_n": 10})]
    for z, up in ((0.0, -0.5 * WAVE), (H, 0.5 * WAVE)):
        for k in range(N):
            a, b = corner(k, z), corner(k + 1, z)
            lines.append(draw(edge(a, b, outward(a, b, up))))
    for k in range(N):
        a = corner(k, 0.0)
        lines.append(draw(edge(a, corner(k, H), outward(a, a, 0.0))))
    lines.append(json.dumps({"op": "curve_fill_auto", "id": 1}))
    return lines


def path(p0, p1, frames):
    return [[p0[j] + (p1[j] - p0[j]) * (i + 1) / frames for j in range(3)] for i in range(frames)]


def shaped_lines():
    top = [0.0, 0.0, H + 0.01]
    lines = base_lines()
    lines.append(
        json.dumps(
            {
                "op": "surface_pull",
                "id": 1,
                "patch": 7,
                "weights": {"wb": 1.0, "ws": 0.0},
                "wpp": 5000.0,
                "u0": 0.5,
                "v0": 0.5,
                "path": path(top, [0.0, 0.0, H + 0.06], 8),
            }
        )
    )
    lines.append(
        json.dumps(
            {
                "op": "surface_sharpen",
                "id": 1,
                "patch": 7,
                "weights": {"wb": 1.0, "ws": 0.0},
                "f": 1.15,
                "wq_max": 1.5,
                "path": [top] * 4,
            }
        )
    )
    lines.append(
        json.dumps(
            {
                "op": "surface_smooth",
                "id": 1,
                "patch": 6,
                "weights": {"wb": 1.0, "ws": 0.0},
                "f": 0.7,
                "wq_max": 1.0,
                "path": [[0.0, 0.0, 0.0]] * 6,
            }
        )
    )
    return lines


def main():
    if len(sys.argv) != 2:
        raise SystemExit(__doc__)
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    for name, lines in (("hexagon", base_lines()), ("hexagon_shaped", shaped_lines())):
        with open(os.path.join(out, f"{name}.jsonl"), "w") as f:
            f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
