#!/usr/bin/env python3
"""Generate tests/data/bust.jsonl: a bust-like head sculpted from a sphere
by a scripted sequence of warp-brush strokes (z up, face towards -y).

Every stroke is one `sculpt_stroke` op with its sampled path; the edge
length limits are given in absolute units and converted to the op's
brush-relative settings, so small and large brushes refine alike.

Usage: python3 scripts/sculpt/bust_gen.py > tests/data/bust.jsonl
"""

import json
import math

MAX_LEN = 0.07
MIN_LEN = 0.02


def bound_radius(brush):
    k = brush["kind"]
    if k == "sphere":
        return brush["radius"]
    if k == "ellipsoid":
        return max(brush["radii"])
    if k == "capsule":
        return brush["radius"] + brush["half_length"]
    if k == "box":
        return math.sqrt(sum(x * x for x in brush["half_extents"]))
    raise ValueError(k)


def quat_axis_angle(axis, angle):
    n = math.sqrt(sum(a * a for a in axis))
    s = math.sin(angle / 2) / n
    return [axis[0] * s, axis[1] * s, axis[2] * s, math.cos(angle / 2)]


def stroke(
    brush, warp, a, b, frames, h, rot_axis=(1, 0, 0), rot=0.0, rot0=None, falloff="smooth", pressure=1.0
):
    size = bound_radius(brush)
    samples = []
    for i in range(frames):
        t = i / max(frames - 1, 1)
        p = [a[k] + (b[k] - a[k]) * t for k in range(3)]
        q = quat_axis_angle(rot_axis, rot * t)
        if rot0 is not None:
            q = quat_mul(q, rot0)
        samples.append({"position": p, "rotation": q, "pressure": pressure})
    return {
        "op": "sculpt_stroke",
        "id": 1,
        "settings": {
            "brush": brush,
            "brush_scale": 1.0,
            "influence": h,
            "falloff": falloff,
            "warp": warp,
            "max_edge_rel": MAX_LEN / size,
            "min_edge_rel": MIN_LEN / size,
        },
        "samples": samples,
    }


def quat_mul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return [
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    ]


def sphere(r):
    return {"kind": "sphere", "radius": r}


DRAG = {"kind": "drag"}
WHITTLE = {"kind": "whittle"}


def explode(d):
    return {"kind": "explode", "delta": d}


def main():
    ops = [{"op": "sculpt_create", "base": {"kind": "sphere", "radius": 1.0, "edge_length": 0.06}}]
    add = ops.append
    # Cranium: pull the top up and back into an egg.
    add(stroke(sphere(0.7), DRAG, [0, 0.1, 0.6], [0, 0.25, 0.95], 16, 0.7))
    # Jaw: narrow the lower half and pull the chin down and forward.
    add(stroke(sphere(0.45), DRAG, [0, -0.35, -0.75], [0, -0.45, -1.05], 12, 0.45))
    # Neck: grab the underside and pull a column down.
    add(stroke(sphere(0.3), DRAG, [0, 0.15, -0.85], [0, 0.2, -1.75], 36, 0.3))
    # Shoulders: pull the neck base out to both sides, nearly level.
    for side in (-1, 1):
        add(
            stroke(
                {"kind": "capsule", "radius": 0.24, "half_length": 0.12},
                DRAG,
                [0.1 * side, 0.2, -1.72],
                [1.2 * side, 0.2, -1.95],
                44,
                0.32,
            )
        )
    # Torso: pull the whole underside down with a wide flat brush so the
    # shoulder lobes merge into one chest.
    add(
        stroke(
            {"kind": "ellipsoid", "radii": [0.95, 0.4, 0.2]}, DRAG, [0, 0.2, -2.0], [0, 0.2, -2.55], 30, 0.35
        )
    )
    # Chest: pull the front of the neck base forward and down.
    add(stroke(sphere(0.3), DRAG, [0, 0.05, -1.75], [0, -0.25, -2.3], 30, 0.35))
    # Back: pull the back down too so the torso is deep.
    add(stroke(sphere(0.3), DRAG, [0, 0.35, -1.75], [0, 0.55, -2.3], 30, 0.35))
    # Smooth the torso.
    for z in (-1.9, -2.15, -2.4):
        add(stroke(sphere(0.6), WHITTLE, [-0.8, 0.2, z], [0.8, 0.2, z], 16, 0.3))
    # Eye sockets: push in.
    for side in (-1, 1):
        add(stroke(sphere(0.1), DRAG, [0.33 * side, -0.92, 0.2], [0.33 * side, -0.8, 0.2], 8, 0.14))
    # Brow: pull a ridge forward a little.
    add(
        stroke(
            {"kind": "capsule", "radius": 0.08, "half_length": 0.3},
            DRAG,
            [0, -0.98, 0.38],
            [0, -1.05, 0.38],
            6,
            0.12,
            rot0=quat_axis_angle((0, 1, 0), math.pi / 2),
        )
    )
    # Nose: pull out forward and down.
    add(stroke(sphere(0.1), DRAG, [0, -0.97, 0.05], [0, -1.22, -0.05], 14, 0.16))
    # Lips: a small bump.
    add(
        stroke(
            {"kind": "ellipsoid", "radii": [0.16, 0.06, 0.05]},
            DRAG,
            [0, -0.9, -0.35],
            [0, -0.96, -0.35],
            6,
            0.08,
        )
    )
    # Ears: small flaps on both sides.
    for side in (-1, 1):
        add(
            stroke(
                {"kind": "ellipsoid", "radii": [0.06, 0.1, 0.18]},
                DRAG,
                [0.97 * side, 0.1, 0.1],
                [1.12 * side, 0.15, 0.1],
                8,
                0.1,
            )
        )
    # Final smoothing of the face.
    add(stroke(sphere(0.5), WHITTLE, [0, -0.9, 0.0], [0, -0.9, 0.0], 2, 0.2, pressure=0.5))
    for op in ops:
        print(json.dumps(op, separators=(",", ":")))


if __name__ == "__main__":
    main()
