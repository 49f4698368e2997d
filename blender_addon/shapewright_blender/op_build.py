"""How the op table's forms become ops: each function takes a form's
values (metres, quaternions: `forms.op_values` converted them at the
border) and builds the op dict, with the core's help where a sketch needs
it (`shapewright`'s `sketch_spine`, `child_from_stroke`,
`replace_spine_from_stroke`, `match_section`: the same RDP and template
matching as the headset) and the core's one solid mapping
(`shapewright.solid_shape`). Nothing here computes geometry; the core
validates every value and refuses bad ones.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import shapewright as sw

IDENTITY_ROT = [0.0, 0.0, 0.0, 1.0]
SURFACE_PIECES_DOC = (
    'The loop\'s pieces head to tail, each "curve from to" (a curve and two of its nodes), '
    'separated by commas: e.g. "0 0 1, 1 0 1, 2 0 1"'
)


def profile(v: dict) -> dict:
    """A GC section profile from the template fields."""
    t = v["template"]
    if t == "circle":
        return {"template": t, "radius": v["size_a"]}
    if t == "ellipse":
        return {"template": t, "rx": v["size_a"], "ry": v["size_b"]}
    if t == "polygon":
        return {"template": t, "sides": v["sides"], "radius": v["size_a"]}
    return {"template": t, "width": v["size_a"], "height": v["size_b"]}


def shape_type(v: dict) -> dict:
    t = v["shape_type"]
    if t == "solid":
        return {"type": t}
    if t == "shell":
        return {"type": t, "thickness": v["thickness"]}
    return {"type": t, "thickness": v["thickness"], "closed_end": v["closed_end"]}


def solid_shape(v: dict) -> dict:
    """A parametric solid from the shape fields: the core's one mapping
    (`SolidShape::from_sizes`, kind and dimensions)."""
    return sw.solid_shape(v["shape"], tuple(v["dimensions"]))


def transform(v: dict, loc: str = "location") -> dict:
    return {
        "translate": list(v[loc]),
        "rotate": list(v.get("rotation", IDENTITY_ROT)),
        "scale": list(v.get("scale", (1.0, 1.0, 1.0))),
    }


def sections(v: dict) -> list[dict]:
    p = profile(v)
    return [
        {"profile": p, "v": 0.0, "scale": 1.0, "twist": 0.0},
        {"profile": p, "v": 1.0, "scale": 1.0, "twist": 0.0},
    ]


def sections_at(p: dict, params: list[float]) -> list[dict]:
    return [{"profile": p, "v": t, "scale": 1.0, "twist": 0.0} for t in params]


def x_hint(normal) -> list[float]:
    """Any direction not parallel to `normal` (a sketch plane's x axis)."""
    n = [float(x) for x in normal]
    return [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 * math.sqrt(sum(x * x for x in n) or 1.0) else [0.0, 1.0, 0.0]


def _gc_create(v: dict, _s=None) -> dict:
    p = profile(v)
    normal = list(v["plane_normal"])
    if v["points"]:
        radius = sw.profile_radius(p)
        sk = sw.sketch_spine(v["points"], v["points"][0], normal, x_hint(normal), radius)
        spine, normal, params = sk["points"], sk["plane_normal"], sk["params"]
    else:
        loc = list(v["location"])
        spine = [loc, [loc[0], loc[1], loc[2] + v["length"]]]
        params = [0.0, 1.0]
    return {
        "op": "gc_create",
        "spine": spine,
        "plane_normal": normal,
        "sections": sections_at(p, params),
        "shape": shape_type(v),
        "resolution": {"u": v["res_u"], "v": v["res_v"]},
    }


def _gc_add_child(v: dict, s) -> dict:
    p = profile(v)
    common = {
        "op": "gc_add_child",
        "id": v["id"],
        "tolerance": 1e-4,
        "shape": shape_type(v),
        "resolution": {"u": 96, "v": 64},
    }
    if v["points"]:
        radius = sw.profile_radius(p)
        c = sw.child_from_stroke(s, v["id"], v["points"], radius, v["end"])
        return {
            **common,
            "parent": c["parent"],
            "at": c["at"],
            "spine": c["spine"],
            "end": c["end"],
            "end_tolerance": c["end_tolerance"],
            "sections": sections_at(p, c["params"]),
        }
    return {
        **common,
        "parent": v["parent"],
        "at": list(v["at"]),
        "spine": [[-0.004, 0.0], [v["length"], 0.0]],
        "end": "parent" if v["end"] == "parent" else "free",
        "end_tolerance": 1e-4,
        "sections": sections(v),
    }


def _gc_replace_spine(v: dict, s) -> list[dict]:
    """Key sections first where the new spine needs them (they keep the
    current shape), then the spine, moved to start where it started."""
    r = sw.replace_spine_from_stroke(s, v["id"], v["part"], v["points"])
    part = {"id": v["id"], "part": v["part"]}
    ops = [{"op": "gc_insert_section", **part, "v": t} for t in r["insert_at"]]
    ops.append({"op": "gc_replace_spine", **part, "points": r["points"], "plane_normal": r["plane_normal"]})
    return ops


MIN_TEMPLATE_SCORE = 0.7  # as the headset's GC tool (GcToolSettings)


def _gc_replace_section(v: dict, _s=None) -> dict:
    out = {"op": "gc_replace_section", "id": v["id"], "part": v["part"], "section": v["section"]}
    if v["points"]:
        normal = list(v["plane_normal"])
        m = sw.match_section(v["points"], v["points"][0], normal, x_hint(normal))
        out["profile"] = m["profile"] if m["score"] >= MIN_TEMPLATE_SCORE else m["sketch"]
    else:
        out["profile"] = profile(v)
    return out


def _part_move(op: str) -> Callable[[dict], dict]:
    def build(v: dict) -> dict:
        out = {"op": op, "id": v["id"], "part": v["part"], "translate": list(v["location"])}
        out["rotate"] = list(v["rotation"])
        out["tolerance"] = 1e-4
        if op == "gc_copy":
            out["mirror"] = v["mirror"]
        return out

    return build


def _pieces(v: dict) -> dict:
    """`curve_fill_loop`'s pieces from "curve from to" triples separated
    by commas (e.g. "0 0 1, 1 0 1, 2 0 1")."""
    pieces = []
    for chunk in v["pieces"].split(","):
        if not chunk.strip():
            continue
        nums = chunk.split()
        if len(nums) != 3 or not all(n.isdigit() for n in nums):
            raise ValueError(
                f"Fill Loop: each piece is three whole numbers 'curve from to', got {chunk.strip()!r}"
            )
        c, a, b = (int(n) for n in nums)
        pieces.append({"curve": c, "from": a, "to": b})
    return {"op": "curve_fill_loop", "id": v["id"], "pieces": pieces}


def _sdf_add(v: dict) -> dict:
    comp = (
        {"kind": "library", "name": v["library"]}
        if v["component"] == "library"
        else {"kind": "solid", "shape": solid_shape(v)}
    )
    return {
        "op": "sdf_add_operand",
        "volume": v["volume"],
        "component": comp,
        "csg": v["csg"],
        "transform": transform(v),
    }


def _sdf_two_hand(v: dict) -> dict:
    return {
        "op": "sdf_scale_two_hand",
        "volume": v["volume"],
        "operand": v["operand"],
        "axis": v["axis"],
        "hands_start": [list(v["left_start"]), list(v["right_start"])],
        "hands_end": [list(v["left_end"]), list(v["right_end"])],
    }


def _import_component(v: dict) -> dict:
    from . import sync  # Blender's side: reads the mesh object

    name, positions, triangles = sync.world_triangles(v["mesh"])
    return {
        "op": "sdf_import_component",
        "volume": v["volume"],
        "name": v["name"] or name,
        "positions": positions,
        "triangles": triangles,
    }


def _curve_draw(v: dict) -> dict:
    fit = {"mode": "interpolate"} if v["fit"] == "interpolate" else {"mode": "approximate", "tol": v["tol"]}
    return {
        "op": "curve_draw",
        "id": v["id"],
        "samples": v["points"],
        "fit": fit,
        "resample": v["resample"] if v["resample"] > 0 else None,
        "snap_tol": v["snap_tol"],
    }


def _sculpt_create(v: dict) -> dict:
    if v["base"] == "sphere":
        base = {"kind": "sphere", "radius": v["size_a"], "edge_length": v["edge_length"]}
    else:
        base = {"kind": "box", "size": [v["size_a"] * 2] * 3, "edge_length": v["edge_length"]}
    return {"op": "sculpt_create", "base": base, "transform": transform(v)}


def _sculpt_stroke(v: dict) -> dict:
    samples = [{"position": p, "rotation": IDENTITY_ROT, "pressure": 1.0} for p in v["points"]]
    return {"op": "sculpt_stroke", "id": v["id"], "settings": v["settings"], "samples": samples}


def _vec_op(op: str, key: str) -> Callable[[dict], dict]:
    """Ops whose only nested part is a sketch `path`/`points` (styling tools)."""

    def build(v: dict) -> dict:
        out = {k: val for k, val in v.items() if k != "points"}
        out["op"] = op
        out[key] = v["points"]
        return out

    return build


def _section_op(op: str) -> Callable[[dict], dict]:
    def build(v: dict) -> dict:
        return {"op": op, "id": v["id"], "part": v["part"], "section": v["section"]}

    return build
