"""Desktop sketching: strokes projected on planes, sketched spines and edits that keep their shape."""

from __future__ import annotations

import json
import math
from pathlib import Path

import bpy
import numpy as np
from helpers import addon, blender_world, core_session, last_op, step, sw_objects
from sc_typed import activate
from sc_usd import handle_stroke


def scenario_sketch_projection(work: Path) -> None:
    """The modal sketch's geometry: view rays onto the plane, spacing."""
    from mathutils import Vector

    sk = addon().sketch
    hit = sk.project(
        Vector((0.3, -2.0, 1.0)), Vector((0.0, 1.0, -0.5)), Vector((0.0, 0.0, 0.0)), Vector((0, 0, 1))
    )
    assert (hit - Vector((0.3, 0.0, 0.0))).length < 1e-12, hit
    assert sk.project(Vector((0, 0, 1)), Vector((1, 0, 0)), Vector((0, 0, 0)), Vector((0, 0, 1))) is None
    assert sk.project(Vector((0, 0, 1)), Vector((0, 0, 1)), Vector((0, 0, 0)), Vector((0, 0, 1))) is None
    st = sk.Stroke(0.01)
    kept = [st.add(Vector((0.004 * i, 0.0, 0.0))) for i in range(10)]
    assert kept == [True, False, False, True, False, False, True, False, False, True], kept
    assert sk.plane_normal("XZ", None) == Vector((0, 1, 0))
    assert (sk.plane_normal("VIEW", Vector((0, 0, -2))) - Vector((0, 0, 1))).length < 1e-12


def arc_stroke(radius: float = 0.12, n: int = 38) -> list[list[float]]:
    return [
        [radius * (1 - math.cos(0.5 * math.pi * i / n)), 0.0, radius * math.sin(0.5 * math.pi * i / n)]
        for i in range(n + 1)
    ]


def section_centre(
    pos: np.ndarray, tri: np.ndarray, p: np.ndarray, t: np.ndarray, reach: float
) -> np.ndarray:
    """Centre of the mesh's cross-section by the plane through `p` normal
    to `t` (the length-weighted centre of the triangles' cut segments
    within `reach` of `p`): for a tube, its axis point there."""
    d = (pos - p) @ t
    cuts = []
    for u, v in ((0, 1), (1, 2), (2, 0)):
        du, dv = d[tri[:, u]], d[tri[:, v]]
        crosses = du * dv < 0
        s = np.where(crosses, du / np.where(crosses, du - dv, 1.0), 0.0)
        q = pos[tri[:, u]] + (pos[tri[:, v]] - pos[tri[:, u]]) * s[:, None]
        cuts.append((crosses, q))
    mids, lens = [], []
    for a, b in ((0, 1), (1, 2), (2, 0)):
        m = cuts[a][0] & cuts[b][0]
        q0, q1 = cuts[a][1][m], cuts[b][1][m]
        mids.append(0.5 * (q0 + q1))
        lens.append(np.linalg.norm(q1 - q0, axis=1))
    mid, ln = np.concatenate(mids), np.concatenate(lens)
    near = np.linalg.norm(mid - p, axis=1) < reach
    assert near.sum() >= 8, near.sum()
    return (mid[near] * ln[near, None]).sum(0) / ln[near].sum()


def axis_deviation(obj, stroke: list[list[float]], radius: float, samples: int = 20) -> float:
    """Largest distance from the stroke to the tube's axis, measured on the
    Blender mesh the user sees: at `samples` points along the stroke, the
    centre of the mesh's cross-section there."""
    pos, tri = blender_world(obj)
    st = np.array(stroke)
    seg = np.linalg.norm(np.diff(st, axis=0), axis=1)
    acc = np.concatenate([[0.0], np.cumsum(seg)])
    ab = st[1:] - st[:-1]
    worst = 0.0
    for f in np.linspace(0.05, 0.95, samples):
        arc = f * acc[-1]
        i = min(int(np.searchsorted(acc, arc)) - 1, len(seg) - 1)
        t = ab[i] / seg[i]
        p = st[i] + t * (arc - acc[i])
        c = section_centre(pos, tri.astype(np.int64), p, t, 1.6 * radius)
        tt = np.clip(((c - st[:-1]) * ab).sum(1) / (ab * ab).sum(1), 0, 1)
        worst = max(worst, float(np.linalg.norm(st[:-1] + ab * tt[:, None] - c, axis=1).min()))
    return worst


def scenario_sketch_arc(work: Path) -> None:
    """A sketched arc gives a curved tube that follows the stroke (under
    2 mm at 20 points), through the mouse sketch operator; a U-shaped
    sketch works or says why not; Cylinder from Template without a sketch
    ignores the last one."""
    ops = bpy.ops.shapewright
    stroke = arc_stroke()
    step(ops.sketch(target="gc_create", points=json.dumps(stroke), normal=(0.0, 1.0, 0.0)), "sketched arc")
    op = last_op()
    assert len(op["sections"]) > 3, len(op["sections"])
    obj = sw_objects()[1]
    assert bpy.context.view_layer.objects.active == obj and obj.select_get(), "new objects are active"
    dev = axis_deviation(obj, stroke, 0.05)
    assert dev < 2e-3, f"the tube strays {dev * 1e3:.2f} mm from the sketch"
    print(f"sketched arc: {len(op['sections'])} sections, axis within {dev * 1e3:.3f} mm of the stroke")
    # No sketch given: a straight cylinder at the location, whatever was
    # sketched before (nothing is remembered).
    step(ops.gc_create(location=(0.5, 0.0, 0.0), length=0.2), "straight")
    op = last_op()
    assert np.allclose(op["spine"], [[0.5, 0.0, 0.0], [0.5, 0.0, 0.2]]) and len(op["sections"]) == 2, op
    # A U: works with a section that fits its bend ...
    u = [[0.0, 0.0, 0.1 - 0.005 * i] for i in range(20)]
    u += [
        [0.04 * (1 - math.cos(math.pi * i / 24)), 0.0, -0.04 * math.sin(math.pi * i / 24)] for i in range(25)
    ]
    u += [[0.08, 0.0, 0.005 * i] for i in range(1, 21)]
    step(
        ops.sketch(
            target="gc_create", points=json.dumps(u), normal=(0.0, 1.0, 0.0), options='{"size_a": 0.015}'
        ),
        "U",
    )
    uid = core_session().object_ids()[-1]
    assert core_session().validate(uid)["closed_manifold"]
    assert axis_deviation(sw_objects()[uid], u, 0.015) < 2e-3
    # ... and says why not when the section is wider than the bend.
    h = core_session().content_hash()
    try:
        ops.gc_create(points=json.dumps(u), plane_normal=(0.0, 1.0, 0.0), size_a=0.06)
    except RuntimeError as e:
        assert "fold into itself" in str(e) and "mm" in str(e), e
    else:
        raise AssertionError("a section wider than the bend must be refused")
    assert core_session().content_hash() == h


def scenario_sketch_edits(work: Path) -> None:
    """Replace Spine on a two-section handle keeps the part (and follows
    the stroke); a sketched section loop is matched by the core's template
    matcher; a stroke starting in the air gets a clear message."""
    ops = bpy.ops.shapewright
    step(ops.gc_create(template="circle", size_a=0.04, length=0.1), "body")
    activate(1)
    step(ops.gc_add_child(parent=0, at=(0.04, 0.0, 0.05), length=0.05, size_a=0.006), "stub")
    one = core_session().validate(1)
    arc = [
        [
            0.5 + 0.05 * math.sin(0.6 * math.pi * i / 30),
            0.0,
            0.3 + 0.05 * (1 - math.cos(0.6 * math.pi * i / 30)),
        ]
        for i in range(31)
    ]
    step(
        ops.sketch(
            target="gc_replace_spine", points=json.dumps(arc), normal=(0.0, 1.0, 0.0), options='{"part": 1}'
        ),
        "replace",
    )
    after = core_session().validate(1)
    assert after["closed_manifold"] and after["components"] == 1, after
    assert after["volume"] > one["volume"], (after["volume"], one["volume"])
    asm = core_session().object_params(1)
    assert len(asm["parts"]) == 2 and len(asm["parts"][1]["gc"]["sections"]) > 2
    # Replace a section by a sketched square loop: the matcher's template.
    sq = [[0.1 * math.cos(a), 0.1 * math.sin(a), 0.0] for a in np.linspace(0, 2 * math.pi, 80)[:-1]]
    sq = [[max(-0.07, min(0.07, x)), max(-0.07, min(0.07, y)), 0.0] for x, y, _ in sq]
    step(ops.sketch(target="gc_replace_section", points=json.dumps(sq), normal=(0.0, 0.0, 1.0)), "section")
    prof = last_op()["profile"]
    assert prof["template"] in ("polygon", "rectangle"), prof
    # A handle stroke starting off the body: refused with the distance.
    h = core_session().content_hash()
    off = [[x + 0.1, y, z + 0.1] for x, y, z in handle_stroke()]
    try:
        ops.gc_add_child(points=json.dumps(off))
    except RuntimeError as e:
        assert "starts" in str(e) and "mm from the nearest part" in str(e), e
    else:
        raise AssertionError("a stroke off the part must be refused")
    assert core_session().content_hash() == h
