#!/usr/bin/env python3
"""Writes tests/data/curve_network.jsonl: a box-like curve network drawn from
tracked samples (some noisy, resampled and approximated), then styled with
the curve puller, smoother and sharpener, filled with patches found
automatically, and shaped with the surface puller and smoother. The result
exports as a closed, printable mesh. Deterministic (fixed pseudo-noise)."""

import json
import math
import os

H = 0.1  # half size of the box, metres
Z0 = H  # the box stands on z = 0
BOW = 0.012  # edges bow outwards


def noise(i, k):
    return ((i * 7919 + k * 104729) % 17) / 17.0 - 0.5


def edge(a, b, bow, count, jitter):
    pts = []
    for i in range(count + 1):
        s = i / count
        p = [a[k] + (b[k] - a[k]) * s + bow[k] * 4 * s * (1 - s) for k in range(3)]
        if 0 < i < count:
            p = [p[k] + jitter * noise(i, k) for k in range(3)]
        pts.append([round(v, 6) for v in p])
    return pts


def edges():
    out = []
    for axis in range(3):
        o1, o2 = (axis + 1) % 3, (axis + 2) % 3
        for s1 in (-H, H):
            for s2 in (-H, H):
                a = [0.0] * 3
                a[axis], a[o1], a[o2] = -H, s1, s2
                b = list(a)
                b[axis] = H
                w = [0.0] * 3
                w[o1], w[o2] = math.copysign(BOW, s1), math.copysign(BOW, s2)
                a[2] += Z0
                b[2] += Z0
                out.append((a, b, w))
    return out


def main():
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    lines = [
        "# A styled curve-network box: 12 curves drawn from tracked samples (noisy ones",
        "# resampled and approximated), joined at 8 corners, pulled, smoothed and",
        "# sharpened, filled with 6 patches found automatically, the top patch pulled",
        "# into a dome and a side patch smoothed. Exports as a closed printable mesh.",
        json.dumps({"op": "curve_network_create", "resolution": 24, "surface_n": 8}),
    ]
    for i, (a, b, w) in enumerate(edges()):
        noisy = i % 3 == 1
        samples = edge(a, b, w, 60 if noisy else 14, 0.0015 if noisy else 0.0)
        fit = {"mode": "approximate", "tol": 0.002} if noisy else {"mode": "interpolate"}
        lines.append(
            json.dumps(
                {
                    "op": "curve_draw",
                    "id": 1,
                    "samples": samples,
                    "fit": fit,
                    "resample": 0.008 if noisy else None,
                    "snap_tol": 0.002,
                }
            )
        )
    # Curve 0 runs along x at y = -H, z = 0 (bottom front). Curve 3: x at y = H, z = 2H (top back).
    # Pull the middle of the top-back edge up and back.
    mid = [0.0, H + BOW, 2 * H + BOW]
    pull = [[mid[0], mid[1] + 0.003 * k, mid[2] + 0.003 * k] for k in range(7)]
    lines.append(
        json.dumps(
            {
                "op": "curve_pull",
                "id": 1,
                "curve": 3,
                "params": {"wpp": 200.0, "wp0": 1.0, "wp1": 0.001},
                "path": pull,
            }
        )
    )
    # Smooth a noisy edge (curve 1) along its length, flat-iron style.
    a, b, w = edges()[1]
    sweep = [[a[k] + (b[k] - a[k]) * s + w[k] for k in range(3)] for s in [0.2 + 0.06 * j for j in range(11)]]
    lines.append(
        json.dumps(
            {
                "op": "curve_smooth",
                "id": 1,
                "curve": 1,
                "params": {"wb": 1e-6, "ws": 0.0, "wp0": 1.0, "wp1": 0.0, "wp2": 0.0, "alpha": 20.0},
                "path": sweep,
            }
        )
    )
    # Sharpen the middle of a vertical edge (curve 8: z axis at x = -H... see edges()).
    a, b, w = edges()[8]
    m = [0.5 * (a[k] + b[k]) + w[k] for k in range(3)]
    lines.append(
        json.dumps(
            {
                "op": "curve_sharpen",
                "id": 1,
                "curve": 8,
                "params": {"wb": 2e-6, "ws": 0.0, "wp0": 1.0, "wp1": 0.0, "wp2": 3e-6, "alpha": 30.0},
                "limits": {"max_step": 0.004, "max_growth": 4.0},
                "path": [m] * 12,
            }
        )
    )
    lines.append(json.dumps({"op": "curve_fill_auto", "id": 1}))
    lines.append("# Patch 2 is the top (z = 2H): pull its centre up into a dome.")
    lines.append(
        json.dumps(
            {
                "op": "surface_pull",
                "id": 1,
                "patch": 2,
                "weights": {"wb": 1.0, "ws": 0.0},
                "wpp": 2000.0,
                "u0": 0.5,
                "v0": 0.5,
                "path": [[0.0, 0.0, 2 * H + 0.03 + 0.005 * k] for k in range(5)],
            }
        )
    )
    lines.append(
        json.dumps(
            {
                "op": "surface_smooth",
                "id": 1,
                "patch": 0,
                "weights": {"wb": 1.0, "ws": 0.0},
                "f": 0.8,
                "wq_max": 1.0,
                "path": [[0.0, -H - 0.03, H]] * 6,
            }
        )
    )
    with open(os.path.join(root, "tests", "data", "curve_network.jsonl"), "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
