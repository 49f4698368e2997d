"""Writes the GC assembly example scripts tests/data/{mug,teapot,...}.jsonl.

Picked points lie on key sections (where the skinned surface passes
exactly through the section circle/rectangle), so they are on the
parent's surface by construction. Run: python3 scripts/examples/gen_gc_models.py
"""

import json
from pathlib import Path

OUT = Path(__file__).resolve().parents[2] / "tests" / "data"


def circ(r, v, **kw):
    return {"profile": {"template": "circle", "radius": r}, "v": v, **kw}


def rect(w, h, v):
    return {"profile": {"template": "rectangle", "width": w, "height": h}, "v": v}


def container(t, end="start"):
    return {"type": "container", "thickness": t, "closed_end": end}


def create(spine, normal, sections, shape=None):
    op = {"op": "gc_create", "spine": spine, "plane_normal": normal, "sections": sections}
    if shape:
        op["shape"] = shape
    return op


def child(parent, at, spine, sections, end="free", shape=None, end_tol=1e-4):
    op = {
        "op": "gc_add_child",
        "id": 1,
        "parent": parent,
        "at": at,
        "spine": spine,
        "end": end,
        "end_tolerance": end_tol,
        "sections": sections,
    }
    if shape:
        op["shape"] = shape
    return op


def write(name, ops):
    (OUT / f"{name}.jsonl").write_text("".join(json.dumps(o) + "\n" for o in ops))


def natural_spline(vs, rs):
    """Natural cubic spline through (vs, rs): returns r(v) and r'(v)."""
    n = len(vs) - 1
    h = [vs[i + 1] - vs[i] for i in range(n)]
    # second derivatives m, m0 = mn = 0
    a = [0.0] * (n + 1)
    b = [1.0] * (n + 1)
    c = [0.0] * (n + 1)
    d = [0.0] * (n + 1)
    for i in range(1, n):
        a[i] = h[i - 1]
        b[i] = 2 * (h[i - 1] + h[i])
        c[i] = h[i]
        d[i] = 6 * ((rs[i + 1] - rs[i]) / h[i] - (rs[i] - rs[i - 1]) / h[i - 1])
    for i in range(1, n + 1):
        w = a[i] / b[i - 1]
        b[i] -= w * c[i - 1]
        d[i] -= w * d[i - 1]
    m = [0.0] * (n + 1)
    m[n] = d[n] / b[n]
    for i in range(n - 1, -1, -1):
        m[i] = (d[i] - c[i] * m[i + 1]) / b[i]

    def ev(v):
        i = max(0, min(n - 1, next((k for k in range(n) if v <= vs[k + 1]), n - 1)))
        t0, t1 = vs[i + 1] - v, v - vs[i]
        r = (
            (m[i] * t0**3 + m[i + 1] * t1**3) / (6 * h[i])
            + (rs[i] / h[i] - m[i] * h[i] / 6) * t0
            + (rs[i + 1] / h[i] - m[i + 1] * h[i] / 6) * t1
        )
        dr = (
            (-m[i] * t0**2 + m[i + 1] * t1**2) / (2 * h[i])
            - (rs[i] / h[i] - m[i] * h[i] / 6)
            + (rs[i + 1] / h[i] - m[i + 1] * h[i] / 6)
        )
        return r, dr

    return ev


def side_frame(vs, rs, height, v, side):
    """Picked point and (n, t) in the xz plane on a vertical body of
    revolution (spine (0,0,0)-(0,0,height)) at spine parameter v, on the
    +x (side = 1) or -x (side = -1) side."""
    r, dr = natural_spline(vs, rs)(v)
    dz = height
    # surface tangent along v in (x, z): (side * dr, dz); outward normal
    import math

    L = math.hypot(dr, dz)
    n = (side * dz / L, -dr / L)
    t = (side * dr / L, dz / L)
    return (side * r, v * height), n, t


def to_nt(at, n, t, pts):
    return [
        [(x - at[0]) * n[0] + (z - at[1]) * n[1], (x - at[0]) * t[0] + (z - at[1]) * t[1]] for x, z in pts
    ]


def arc_handle(p0, p1, bulge, side, k=9):
    """World (x, z) points of a smooth C-shaped handle from p0 to p1 bulging
    `bulge` outwards (side = +-1 in x)."""
    import math

    out = []
    for i in range(k):
        s = i / (k - 1)
        x = p0[0] + (p1[0] - p0[0]) * s + side * bulge * math.sin(math.pi * s) ** 0.8
        z = p0[1] + (p1[1] - p0[1]) * s
        out.append((x, z))
    return out


def dense(sections, k=12):
    """The GC surface is skinned through the key sections only, so a bent
    part needs sections all along it: `k + 1` sections, sizes interpolated
    linearly between the given ones (scale factor over the first)."""
    out = []
    for i in range(k + 1):
        v = i / k
        j = max(a for a in range(len(sections)) if sections[a]["v"] <= v + 1e-12)
        j = min(j, len(sections) - 2)
        a, b = sections[j], sections[j + 1]
        w = (v - a["v"]) / (b["v"] - a["v"])
        prof = dict(a["profile"])
        for key in prof:
            if key != "template":
                prof[key] = a["profile"][key] * (1 - w) + b["profile"][key] * w
        out.append({"profile": prof, "v": v})
    return out


def handle_child(vs, rs, h, v0, v1, bulge, sections, inset=0.005):
    sections = dense(sections)
    at0, n0, t0 = side_frame(vs, rs, h, v0, -1)
    at1, _, _ = side_frame(vs, rs, h, v1, -1)
    pts = arc_handle((at0[0] + inset, at0[1]), (at1[0] + inset, at1[1]), bulge, -1)
    return child(
        0, [at0[0], 0, at0[1]], to_nt(at0, n0, t0, pts), sections, end="parent", end_tol=inset + 0.002
    )


def mug():
    h = 0.10
    vs, rs = [0.0, 0.2, 0.8, 1.0], [0.040, 0.041, 0.042, 0.043]
    return [
        create([[0, 0, 0], [0, 0, h]], [0, 1, 0], [circ(r, v) for v, r in zip(vs, rs)], container(0.004)),
        handle_child(
            vs,
            rs,
            h,
            0.8,
            0.2,
            0.035,
            [
                {"profile": {"template": "ellipse", "rx": 0.008, "ry": 0.005}, "v": 0.0},
                {"profile": {"template": "ellipse", "rx": 0.008, "ry": 0.005}, "v": 1.0},
            ],
        ),
    ]


def teapot():
    h = 0.16
    vs, rs = [0.0, 0.15, 0.45, 0.75, 1.0], [0.065, 0.088, 0.100, 0.088, 0.056]
    body = create([[0, 0, 0], [0, 0, h]], [0, 1, 0], [circ(r, v) for v, r in zip(vs, rs)], container(0.004))
    spout = child(
        0,
        [0.1, 0, 0.45 * h],
        [[-0.006, 0.0], [0.035, 0.012], [0.07, 0.045], [0.095, 0.095], [0.118, 0.125]],
        dense([circ(0.024, 0.0), circ(0.016, 0.35), circ(0.011, 0.8), circ(0.0105, 1.0)]),
        shape={"type": "shell", "thickness": 0.0025},
    )
    handle = handle_child(
        vs,
        rs,
        h,
        0.75,
        0.2,
        0.06,
        [
            {"profile": {"template": "ellipse", "rx": 0.011, "ry": 0.007}, "v": 0.0},
            {"profile": {"template": "ellipse", "rx": 0.009, "ry": 0.006}, "v": 0.5},
            {"profile": {"template": "ellipse", "rx": 0.011, "ry": 0.007}, "v": 1.0},
        ],
    )
    lid = create(
        [[0, 0, 0.154], [0, 0, 0.2]],
        [0, 1, 0],
        [
            circ(0.061, 0.0),
            circ(0.06, 0.15),
            circ(0.035, 0.55),
            circ(0.008, 0.72),
            circ(0.014, 0.86),
            circ(0.012, 1.0),
        ],
    )
    return [body, spout, handle, lid]


def vase():
    star = [
        [(0.05 if i % 2 == 0 else 0.044) * c, (0.05 if i % 2 == 0 else 0.044) * s]
        for i, (c, s) in enumerate(
            [
                (
                    __import__("math").cos(k * 3.14159265358979 / 6),
                    __import__("math").sin(k * 3.14159265358979 / 6),
                )
                for k in range(12)
            ]
        )
    ]
    prof = {"template": "ellipse", "rx": 0.05, "ry": 0.036}
    del star
    return [
        create(
            [[0, 0, 0], [0, 0, 0.25]],
            [0, 1, 0],
            [
                {"profile": prof, "v": 0.0, "scale": 1.0},
                {"profile": prof, "v": 0.3, "scale": 1.5},
                {"profile": prof, "v": 0.65, "scale": 0.8},
                {"profile": prof, "v": 1.0, "scale": 1.2},
            ],
            container(0.003),
        ),
        {"op": "gc_bend", "id": 1, "part": 0, "section": 2, "to": [0.03, 0, 0.1625]},
        {"op": "gc_bend", "id": 1, "part": 0, "section": 3, "to": [0.02, 0, 0.25]},
        {"op": "gc_twist", "id": 1, "part": 0, "section": 2, "angle": 0.8},
    ]


def funnel():
    return [
        create(
            [[0, 0, 0], [0, 0, 0.2]],
            [0, 1, 0],
            [circ(0.012, 0.0), circ(0.012, 0.4), circ(0.02, 0.5), circ(0.09, 1.0)],
            {"type": "shell", "thickness": 0.003},
        )
    ]


def hammer():
    head = create(
        [[-0.07, 0, 0.3], [0.07, 0, 0.3]],
        [0, 1, 0],
        [circ(0.02, 0.0), circ(0.018, 0.1), rect(0.03, 0.03, 0.5), circ(0.015, 0.9), circ(0.012, 1.0)],
    )
    # handle on the underside of the head's middle section (rectangle, local y = z)
    grip = child(
        0,
        [0.0, 0.0, 0.3 - 0.015],
        [[-0.005, 0], [0.12, 0], [0.27, 0]],
        [
            {"profile": {"template": "ellipse", "rx": 0.011, "ry": 0.008}, "v": 0.0},
            {"profile": {"template": "ellipse", "rx": 0.009, "ry": 0.007}, "v": 0.4},
            {"profile": {"template": "ellipse", "rx": 0.013, "ry": 0.01}, "v": 1.0},
        ],
    )
    return [head, grip]


def slab(x0, x1, z, depth, thick):
    return create([[x0, 0, z], [x1, 0, z]], [0, 1, 0], [rect(depth, thick, 0.0), rect(depth, thick, 1.0)])


def leg_ops(z_under, x, y, length, r0, r1):
    return [
        child(0, [x, y, z_under], [[-0.004, 0], [length, 0]], [circ(r0, 0.0), circ(r1, 1.0)]),
        {"op": "gc_copy", "id": 1, "part": 1, "mirror": True},
        {"op": "gc_copy", "id": 1, "part": 1, "translate": [-2 * x, 0, 0]},
        {"op": "gc_copy", "id": 1, "part": 2, "translate": [-2 * x, 0, 0]},
    ]


def table():
    z = 0.72
    return [slab(-0.45, 0.45, z, 0.6, 0.03)] + leg_ops(z - 0.015, 0.4, 0.25, z - 0.015, 0.022, 0.016)


def chair():
    z = 0.45
    ops = [slab(-0.22, 0.22, z, 0.44, 0.03)] + leg_ops(z - 0.015, 0.19, 0.19, z - 0.015, 0.018, 0.014)
    # back posts from the seat's top surface at the back (x = -0.19), twins
    ops.append(
        child(
            0,
            [-0.19, 0.19, z + 0.015],
            [[-0.004, 0], [0.45, 0]],
            [circ(0.015, 0.0), circ(0.015, 1.0)],
            end="free",
        )
    )
    ops.append({"op": "gc_copy", "id": 1, "part": 5, "mirror": True})
    # back rails: children of the first post (its side facing -y), reaching
    # into the second post
    for height in (0.22, 0.40):
        ops.append(
            child(
                5,
                [-0.19, 0.19 - 0.015, z + 0.011 + height],
                [[-0.004, 0], [0.358, 0]],
                [
                    {"profile": {"template": "ellipse", "rx": 0.03, "ry": 0.009}, "v": 0.0},
                    {"profile": {"template": "ellipse", "rx": 0.03, "ry": 0.009}, "v": 1.0},
                ],
            )
        )
    return ops


def rack():
    z = 0.03
    base = slab(-0.5, 0.5, z, 0.06, 0.03)
    ops = [base]
    ops.append(child(0, [0.42, 0, z + 0.015], [[-0.004, 0], [1.5, 0]], [circ(0.015, 0.0), circ(0.015, 1.0)]))
    ops.append({"op": "gc_copy", "id": 1, "part": 1, "translate": [-0.84, 0, 0]})
    # feet: from the base's front face (y = 0.03) out along +y, mirrored to the back
    for x in (0.42, -0.42):
        ops.append(child(0, [x, 0.03, z], [[-0.004, 0], [0.22, 0]], [circ(0.014, 0.0), circ(0.01, 1.0)]))
        ops.append(
            {
                "op": "gc_copy",
                "id": 1,
                "part": len([o for o in ops if o["op"] in ("gc_add_child", "gc_copy")]),
                "mirror": True,
            }
        )
    # top bar: child of the first pole near its top, reaching through the second
    ops.append(
        child(1, [0.42 - 0.015, 0, 1.45], [[-0.004, 0], [0.825, 0]], [circ(0.012, 0.0), circ(0.012, 1.0)])
    )
    return ops


if __name__ == "__main__":
    for name, f in [
        ("mug", mug),
        ("teapot", teapot),
        ("vase", vase),
        ("funnel", funnel),
        ("hammer", hammer),
        ("table", table),
        ("chair", chair),
        ("rack", rack),
    ]:
        write(name, f())
