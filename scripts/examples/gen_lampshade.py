"""Writes tests/data/lampshade.jsonl: an open curve network shaped like a
lampshade (a flared band: two rings of four arcs joined by four bowed
verticals), with only its four side loops filled, so the surface stays
open at the top and the bottom. The printable path thickens it into a
2 mm shell (issue 17).

    python scripts/examples/gen_lampshade.py

The loop pieces name node indices; they were read from the network the
draws build (nodes are numbered as intersections are found, in draw order)
and are checked by core/tests/suite/print_cases.rs.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
R_BOTTOM, R_TOP, HEIGHT, BOW = 0.12, 0.07, 0.16, 0.012
CORNERS = [math.radians(45 + 90 * k) for k in range(4)]


def ring_arc(r: float, z: float, a0: float, a1: float, n: int = 9) -> list:
    return [[round(r * math.cos(a), 6), round(r * math.sin(a), 6), z] for a in (a0 + (a1 - a0) * i / (n - 1) for i in range(n))]


def vertical(a: float, n: int = 9) -> list:
    pts = []
    for i in range(n):
        t = i / (n - 1)
        r = R_BOTTOM + (R_TOP - R_BOTTOM) * t + BOW * math.sin(math.pi * t)
        pts.append([round(r * math.cos(a), 6), round(r * math.sin(a), 6), round(HEIGHT * t, 6)])
    return pts


def draw(samples: list) -> dict:
    return {"op": "curve_draw", "id": 1, "samples": samples, "fit": {"mode": "interpolate"}, "resample": None, "snap_tol": 0.002}


def main() -> None:
    ops: list = [{"op": "curve_network_create", "resolution": 16, "surface_n": 8}]
    for k in range(4):
        a0, a1 = CORNERS[k], CORNERS[k] + math.pi / 2
        ops.append(draw(ring_arc(R_BOTTOM, 0.0, a0, a1)))
    for k in range(4):
        a0, a1 = CORNERS[k], CORNERS[k] + math.pi / 2
        ops.append(draw(ring_arc(R_TOP, HEIGHT, a0, a1)))
    for a in CORNERS:
        ops.append(draw(vertical(a)))
    # The four side loops (bottom arc, vertical, top arc, vertical), as the
    # network numbers its nodes; the two rings are loops too, left open.
    sides = [
        [(0, 3, 0), (9, 0, 4), (4, 4, 7), (8, 7, 3)],
        [(1, 0, 1), (10, 1, 5), (5, 5, 4), (9, 4, 0)],
        [(2, 1, 2), (11, 2, 6), (6, 6, 5), (10, 5, 1)],
        [(3, 2, 3), (8, 3, 7), (7, 7, 6), (11, 6, 2)],
    ]
    for loop in sides:
        ops.append({"op": "curve_fill_loop", "id": 1, "pieces": [{"curve": c, "from": a, "to": b} for c, a, b in loop]})
    lines = [
        "# A lampshade: an open curve network (two rings of arcs, four bowed",
        "# verticals) with only its four side loops filled; top and bottom stay",
        "# open. Printing thickens it into a 2 mm shell. Written by",
        "# scripts/examples/gen_lampshade.py.",
    ]
    lines += [json.dumps(op) for op in ops]
    (ROOT / "tests" / "data" / "lampshade.jsonl").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
