"""Blender's own choices for the core's ops: the ops that get a typed
operator with a Blender-shaped form (`SHAPEWRIGHT_OT_gc_bend`,
`shapewright.gc_bend`) and a button in `panels.py`, their labels and panel
category, and how their flat fields build the op (templates, sketches,
placements). Each spec lists its fields (name, kind, default); a field's
tooltip, unit and range come from the core's op schema (`schema.py`): the
op's field of the same name, or the one named by `like`. Every other op
of the schema gets a generic operator built from the schema alone
(`operators.generic_operator`; `GENERIC_LABELS` only names some), so a new
core op needs no edit here. Nothing here computes geometry; the core
validates every value and refuses bad ones.

Field kinds:
- ``target``: an object id; -1 means the active Shapewright object.
- ``int``, ``float``, ``bool``, ``vec3``, ``enum``: plain properties.
- ``json``: a nested value given as JSON text (defaults are the values the
  example scripts use).
- ``points``: a polyline as JSON ``[[x, y, z], ...]`` (a sketch: the
  Sketch operator passes it, scripts may). Never remembered: an operator
  without points does what its other fields say (e.g. a straight
  cylinder at ``location``), or asks for a sketch when it needs one.

Sketched GC ops go through the core's sketch pipeline (`shapewright`'s
`sketch_spine`, `child_from_stroke`, `replace_spine_from_stroke`,
`match_section`: the same RDP and template matching as the headset), so a
sketched spine gets as many key sections as its curve needs.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import shapewright as sw

IDENTITY_ROT = [0.0, 0.0, 0.0, 1.0]


@dataclass(frozen=True)
class Field:
    name: str
    kind: str
    default: Any = None
    items: tuple[str, ...] = ()
    label: str = ""
    # Blender's own text, for a field the op does not have as such (a
    # template's size, a location); else the schema's doc is the tooltip.
    doc: str = ""
    # The schema field this property stands for when its name differs
    # (`("@Profile", "radius")`, `("gc_create", "resolution", "u")`): its
    # doc, unit and range. Default: the op's field of the same name.
    like: tuple[str, ...] = ()
    unit: str | None = None  # for Blender's own fields: "m" or "rad"
    # A value meaning "none" (not range-checked), e.g. resample 0.
    none_at: Any = None


@dataclass(frozen=True)
class OpSpec:
    op: str
    label: str
    category: str
    description: str
    fields: tuple[Field, ...] = ()
    build: Callable[[dict], dict] | None = None
    sketch: str = ""  # the field a sketch fills ("points" fields), if any
    extra: dict = field(default_factory=dict)
    # For ops built from a sketch with the core's help: (values, session)
    # -> one op dict or a list of op dicts applied as one step.
    build_with: Callable[[dict, Any], dict | list[dict]] | None = None
    # The core kind of the object the op edits (None: it creates one).
    target_kind: str | None = None
    # Points are required (the op has nothing to do without a sketch).
    needs_points: bool = False
    # Built from Blender data (a mesh object), not from the fields alone.
    from_blender: bool = False


PROFILE_TEMPLATES = ("circle", "ellipse", "polygon", "rectangle")
SOLID_SHAPES = ("box", "sphere", "ellipsoid", "cylinder", "cone", "torus", "capsule")


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
    """A parametric solid (`SolidShape`) from the shape fields."""
    k, a, b = v["shape"], v["size_a"], v["size_b"]
    if k == "box":
        return {"kind": k, "size": [a, a, b]}
    if k == "sphere":
        return {"kind": k, "radius": a}
    if k == "ellipsoid":
        return {"kind": k, "radii": [a, a, b]}
    if k in ("cylinder", "cone"):
        return {"kind": k, "radius": a, "height": b}
    if k == "torus":
        return {"kind": k, "major_radius": a, "minor_radius": b}
    return {"kind": k, "radius": a, "length": b}


def transform(v: dict, loc: str = "location") -> dict:
    rz = v.get("angle_z", 0.0) / 2
    return {
        "translate": list(v[loc]),
        "rotate": [0.0, 0.0, math.sin(rz), math.cos(rz)],
        "scale": list(v.get("scale", (1.0, 1.0, 1.0))),
    }


def sections(v: dict) -> list[dict]:
    p = profile(v)
    return [
        {"profile": p, "v": 0.0, "scale": 1.0, "twist": 0.0},
        {"profile": p, "v": 1.0, "scale": 1.0, "twist": 0.0},
    ]


HAND_DOC = "The %s hand's position when the gesture %s"
TEMPLATE_DOC = "Section template: circle, ellipse, regular polygon or rectangle"
SIZE_A_DOC = "Circle or polygon radius, ellipse semi-axis rx, rectangle width (positive)"
SIZE_B_DOC = "Ellipse semi-axis ry, rectangle height (positive); unused by circles and polygons"
SOLID_A_DOC = "Sphere, cylinder, cone or capsule radius; torus major radius; box and ellipsoid x and y size"
SOLID_B_DOC = "Cylinder or cone height, capsule length, torus minor radius; box and ellipsoid z size"
TEMPLATE_FIELDS = (
    Field("template", "enum", "circle", PROFILE_TEMPLATES, doc=TEMPLATE_DOC),
    Field("size_a", "float", 0.05, label="Radius / width", doc=SIZE_A_DOC, like=("@Profile", "radius")),
    Field("size_b", "float", 0.03, label="Height / ry", doc=SIZE_B_DOC, like=("@Profile", "ry")),
    Field("sides", "int", 6, like=("@Profile", "sides")),
)
# A child's section: handle- and spout-sized by default.
CHILD_TEMPLATE_FIELDS = (
    Field("template", "enum", "circle", PROFILE_TEMPLATES, doc=TEMPLATE_DOC),
    Field("size_a", "float", 0.008, label="Radius / width", doc=SIZE_A_DOC, like=("@Profile", "radius")),
    Field("size_b", "float", 0.005, label="Height / ry", doc=SIZE_B_DOC, like=("@Profile", "ry")),
    Field("sides", "int", 6, like=("@Profile", "sides")),
)
SHAPE_TYPE_FIELDS = (
    Field("shape_type", "enum", "solid", ("solid", "shell", "container"), like=("@ShapeType", "type")),
    Field("thickness", "float", 0.004, like=("@ShapeType", "thickness")),
    Field("closed_end", "enum", "start", ("start", "end"), like=("@ShapeType", "closed_end")),
)
SOLID_FIELDS = (
    Field("shape", "enum", "sphere", SOLID_SHAPES, like=("@SolidShape", "kind")),
    Field("size_a", "float", 0.1, label="Radius / size", doc=SOLID_A_DOC, like=("@SolidShape", "radius")),
    Field("size_b", "float", 0.2, label="Height / minor", doc=SOLID_B_DOC, like=("@SolidShape", "height")),
)
PLACE_FIELDS = (
    Field("location", "vec3", (0.0, 0.0, 0.0), like=("@Transform", "translate")),
    Field("angle_z", "float", 0.0, doc="Rotation about Z", unit="rad"),
    Field("scale", "vec3", (1.0, 1.0, 1.0), like=("@Transform", "scale")),
)
GC_PART = (Field("id", "target", -1), Field("part", "int", 0))
SMOOTH_PARAMS = {"wb": 1e-06, "ws": 0.0, "wp0": 1.0, "wp1": 0.0, "wp2": 0.0, "alpha": 20.0}
SHARPEN_PARAMS = {"wb": 2e-06, "ws": 0.0, "wp0": 1.0, "wp1": 0.0, "wp2": 3e-06, "alpha": 30.0}
SURFACE_WEIGHTS = {"wb": 1.0, "ws": 0.0}
# A local default: a 2 cm brush whose weights fall to 0 at 5 cm from it
# (a 0.3 m brush with 0.7 m influence used to drag a whole sphere).
STROKE_SETTINGS = {
    "brush": {"kind": "sphere", "radius": 0.02},
    "brush_scale": 1.0,
    "influence": 0.05,
    "falloff": "smooth",
    "warp": {"kind": "drag"},
    "max_edge_rel": 0.1,
    "min_edge_rel": 0.03,
}


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
        radius = sw.profile_radius(json.dumps(p))
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
        radius = sw.profile_radius(json.dumps(p))
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
        out["profile"] = json.loads(m["profile"] if m["score"] >= MIN_TEMPLATE_SCORE else m["sketch"])
    else:
        out["profile"] = profile(v)
    return out


def _part_move(op: str) -> Callable[[dict], dict]:
    def build(v: dict) -> dict:
        out = {"op": op, "id": v["id"], "part": v["part"], "translate": list(v["location"])}
        t = transform(v)
        out["rotate"] = t["rotate"]
        out["tolerance"] = 1e-4
        if op == "gc_copy":
            out["mirror"] = v["mirror"]
        return out

    return build


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


SURFACE_EQ = (
    Field("weights", "json", SURFACE_WEIGHTS),
    Field("f", "float", 0.8),
    Field("wq_max", "float", 1.0),
)


def path_tool(op: str, label: str, element: str, params: tuple[Field, ...]) -> OpSpec:
    """A styling tool held along a sketched path on one curve or patch."""
    return OpSpec(
        op,
        label,
        "curve",
        f"{label}: the tool held along the sketch path",
        (Field("id", "target", -1), Field(element, "int", 0), *params, Field("points", "points", "")),
        _vec_op(op, "path"),
        sketch="points",
        target_kind="curve_network",
        needs_points=True,
    )


SPECS: tuple[OpSpec, ...] = (
    # Generalized cylinders (paper 1)
    OpSpec(
        "gc_create",
        "Cylinder from Template",
        "gc",
        "Create a generalized cylinder: a template section swept along the sketch or a straight spine",
        (
            Field(
                "location",
                "vec3",
                (0.0, 0.0, 0.0),
                doc="Where the straight spine starts (no sketch)",
                unit="m",
            ),
            Field("length", "float", 0.2, doc="Length of the straight spine along +Z (no sketch)", unit="m"),
            Field("plane_normal", "vec3", (0.0, 1.0, 0.0)),
            Field("points", "points", ""),
            *TEMPLATE_FIELDS,
            *SHAPE_TYPE_FIELDS,
            Field("res_u", "int", 96, like=("gc_create", "resolution", "u")),
            Field("res_v", "int", 64, like=("gc_create", "resolution", "v")),
        ),
        sketch="points",
        build_with=_gc_create,
    ),
    OpSpec(
        "gc_bend",
        "Bend",
        "gc",
        "Move a key point of the spine",
        (*GC_PART, Field("section", "int", 1), Field("to", "vec3", (0.0, 0.0, 0.1))),
    ),
    OpSpec(
        "gc_replace_spine",
        "Replace Spine",
        "gc",
        "Replace the spine by a sketched curve (in the part's spine plane, starting where it started)",
        (*GC_PART, Field("points", "points", "")),
        sketch="points",
        build_with=_gc_replace_spine,
        target_kind="gc_assembly",
        needs_points=True,
    ),
    OpSpec(
        "gc_resize",
        "Resize Section",
        "gc",
        "Scale a key section",
        (*GC_PART, Field("section", "int", 0), Field("factor", "float", 1.2)),
    ),
    OpSpec(
        "gc_shift",
        "Shift Section",
        "gc",
        "Move a key section along the spine",
        (*GC_PART, Field("section", "int", 1), Field("v", "float", 0.5)),
    ),
    OpSpec(
        "gc_twist",
        "Twist Section",
        "gc",
        "Twist an interior key section",
        (*GC_PART, Field("section", "int", 1), Field("angle", "float", 0.5)),
    ),
    OpSpec(
        "gc_replace_section",
        "Replace Section",
        "gc",
        "Replace a key section by a template, or by the template a sketched loop matches",
        (
            *GC_PART,
            Field("section", "int", 0),
            *TEMPLATE_FIELDS,
            Field("points", "points", ""),
            Field("plane_normal", "vec3", (0.0, 0.0, 1.0), doc="Normal of the sketched loop's plane"),
        ),
        sketch="points",
        build_with=_gc_replace_section,
        target_kind="gc_assembly",
    ),
    OpSpec(
        "gc_delete_section",
        "Delete Section",
        "gc",
        "Delete a key section",
        (*GC_PART, Field("section", "int", 1)),
        _section_op("gc_delete_section"),
    ),
    OpSpec(
        "gc_insert_section",
        "Insert Section",
        "gc",
        "Insert a key section at spine parameter v",
        (*GC_PART, Field("v", "float", 0.5)),
    ),
    OpSpec(
        "gc_set_shape",
        "Shape Type",
        "gc",
        "Solid, shell or container, with a wall thickness",
        (*GC_PART, *SHAPE_TYPE_FIELDS),
        lambda v: {"op": "gc_set_shape", "id": v["id"], "part": v["part"], "shape": shape_type(v)},
    ),
    OpSpec(
        "gc_add_child",
        "Add Child",
        "gc",
        "Add a child cylinder starting on a part's surface: sketched from the part (a handle when the "
        "stroke ends on it, else a spout), or a straight stub at a point",
        (
            Field("id", "target", -1),
            Field("points", "points", ""),
            Field("parent", "int", 0),
            Field("at", "vec3", (0.0, 0.0, 0.0)),
            Field("length", "float", 0.1, doc="Length of a straight stub (no sketch)", unit="m"),
            Field(
                "end",
                "enum",
                "auto",
                ("auto", "free", "parent"),
                doc="Where the spine ends: free (a spout), on the parent (a handle), or auto: on the parent "
                "when a sketch ends on it",
            ),
            *CHILD_TEMPLATE_FIELDS,
            *SHAPE_TYPE_FIELDS,
        ),
        sketch="points",
        build_with=_gc_add_child,
        target_kind="gc_assembly",
    ),
    OpSpec(
        "gc_copy",
        "Instance Part",
        "gc",
        "Copy a part with its children (an instance; optionally mirrored)",
        (*GC_PART, Field("mirror", "bool", False), *PLACE_FIELDS[:2]),
        _part_move("gc_copy"),
    ),
    OpSpec(
        "gc_transform_part",
        "Move Part",
        "gc",
        "Move a part rigidly",
        (*GC_PART, *PLACE_FIELDS[:2]),
        _part_move("gc_transform_part"),
    ),
    # CSG with the component library (paper 2)
    OpSpec(
        "sdf_create", "New CSG Volume", "csg", "Create an empty CSG volume", (Field("step", "float", 0.01),)
    ),
    OpSpec(
        "sdf_add_operand",
        "Add Component",
        "csg",
        "Add a library component or a solid with a boolean operation",
        (
            Field("volume", "target", -1),
            Field("component", "enum", "library", ("library", "solid"), doc="A library component or a solid"),
            Field("library", "library", "chair_seat", doc="The starter-library component"),
            *SOLID_FIELDS,
            Field("csg", "enum", "union", ("union", "subtract", "intersect")),
            *PLACE_FIELDS,
        ),
        _sdf_add,
    ),
    OpSpec(
        "sdf_set_operand_transform",
        "Place Operand",
        "csg",
        "Place an operand",
        (Field("volume", "target", -1), Field("operand", "int", 0), *PLACE_FIELDS),
        lambda v: {
            "op": "sdf_set_operand_transform",
            "volume": v["volume"],
            "operand": v["operand"],
            "transform": transform(v),
        },
    ),
    OpSpec(
        "sdf_scale_two_hand",
        "Two-Hand Scale",
        "csg",
        "Scale an operand by the change of distance between two hands",
        (
            Field("volume", "target", -1),
            Field("operand", "int", 0),
            Field("axis", "enum", "uniform", ("x", "y", "z", "uniform")),
            Field("left_start", "vec3", (0.0, 0.0, 0.0), doc=HAND_DOC % ("left", "began"), unit="m"),
            Field("right_start", "vec3", (0.2, 0.0, 0.0), doc=HAND_DOC % ("right", "began"), unit="m"),
            Field("left_end", "vec3", (0.0, 0.0, 0.0), doc=HAND_DOC % ("left", "ended"), unit="m"),
            Field("right_end", "vec3", (0.3, 0.0, 0.0), doc=HAND_DOC % ("right", "ended"), unit="m"),
        ),
        _sdf_two_hand,
    ),
    OpSpec(
        "sdf_update",
        "Operate",
        "csg",
        "Fuse the pending operands into the volume",
        (Field("volume", "target", -1),),
    ),
    OpSpec(
        "sdf_cancel_operand",
        "Cancel Operand",
        "csg",
        "Drop a pending operand",
        (Field("volume", "target", -1), Field("operand", "int", 0)),
    ),
    OpSpec(
        "sdf_copy_operand",
        "Copy Operand",
        "csg",
        "Copy an operand to a new placement",
        (Field("volume", "target", -1), Field("operand", "int", 0), *PLACE_FIELDS),
        lambda v: {
            "op": "sdf_copy_operand",
            "volume": v["volume"],
            "operand": v["operand"],
            "transform": transform(v),
        },
    ),
    OpSpec(
        "sdf_import_component",
        "Import Component",
        "csg",
        "Add a closed Blender mesh (triangulated, in world space) to the volume's components; "
        "then add it with Add Component as a user component (Apply Op) by its name",
        (
            Field("volume", "target", -1),
            Field("name", "string", "", doc="The component's name; empty: the mesh object's name"),
            Field(
                "mesh",
                "string",
                "",
                doc="The Blender mesh object to import (closed, outward normals); empty: the selected "
                "mesh that is not a Shapewright object",
            ),
        ),
        build_with=lambda v, _s=None: _import_component(v),
        from_blender=True,
    ),
    OpSpec(
        "sdf_set_step",
        "Grid Step",
        "csg",
        "Set the volume's grid step",
        (Field("volume", "target", -1), Field("step", "float", 0.01)),
    ),
    # Curve drawing and styling (paper 3)
    OpSpec(
        "curve_network_create",
        "New Curve Network",
        "curve",
        "Create an empty curve network",
        (Field("resolution", "int", 24), Field("surface_n", "int", 8)),
    ),
    OpSpec(
        "curve_draw",
        "Draw Curve",
        "curve",
        "Draw a curve from sketch samples",
        (
            Field("id", "target", -1),
            Field("points", "points", ""),
            Field("fit", "enum", "interpolate", ("interpolate", "approximate")),
            Field(
                "tol",
                "float",
                0.002,
                doc="Approximation tolerance (approximate fit)",
                like=("@FitMode", "tol"),
            ),
            Field(
                "resample",
                "float",
                0.0,
                doc="Arc-length resampling spacing applied first; 0: none",
                like=("curve_draw", "resample"),
                none_at=0.0,
            ),
            Field("snap_tol", "float", 0.002),
        ),
        _curve_draw,
        sketch="points",
        target_kind="curve_network",
        needs_points=True,
    ),
    path_tool("curve_smooth", "Smooth Curve", "curve", (Field("params", "json", SMOOTH_PARAMS),)),
    path_tool(
        "curve_sharpen",
        "Sharpen Curve",
        "curve",
        (
            Field("params", "json", SHARPEN_PARAMS),
            Field("limits", "json", {"max_step": 0.004, "max_growth": 4.0}),
        ),
    ),
    path_tool(
        "curve_pull",
        "Pull Curve",
        "curve",
        (Field("params", "json", {"wpp": 200.0, "wp0": 1.0, "wp1": 0.001}),),
    ),
    OpSpec(
        "curve_delete",
        "Delete Curve",
        "curve",
        "Delete a network curve",
        (Field("id", "target", -1), Field("curve", "int", 0)),
    ),
    OpSpec(
        "curve_fill_loop",
        "Fill Loop",
        "curve",
        "Fill a picked loop of curve pieces with a patch",
        (Field("id", "target", -1), Field("pieces", "json", [])),
    ),
    OpSpec(
        "curve_fill_auto",
        "Fill All Loops",
        "curve",
        "Fill every loop found automatically",
        (Field("id", "target", -1),),
    ),
    path_tool("surface_smooth", "Smooth Surface", "patch", SURFACE_EQ),
    path_tool("surface_sharpen", "Sharpen Surface", "patch", SURFACE_EQ),
    path_tool(
        "surface_pull",
        "Pull Surface",
        "patch",
        (
            Field("weights", "json", SURFACE_WEIGHTS),
            Field("wpp", "float", 2000.0),
            Field("u0", "float", 0.5),
            Field("v0", "float", 0.5),
        ),
    ),
    # Warp brushes (paper 4)
    OpSpec(
        "sculpt_create",
        "New Sculpt",
        "sculpt",
        "Create a sculpt object from a base shape",
        (
            Field("base", "enum", "sphere", ("sphere", "box"), like=("@SculptBase", "kind")),
            Field(
                "size_a",
                "float",
                0.3,
                label="Radius / half size",
                doc="Sphere radius; half the box's edge",
                like=("@SculptBase", "radius"),
            ),
            Field("edge_length", "float", 0.03, like=("@SculptBase", "edge_length")),
            *PLACE_FIELDS,
        ),
        _sculpt_create,
    ),
    OpSpec(
        "sculpt_stroke",
        "Warp Stroke",
        "sculpt",
        "Apply a warp-brush stroke along the sketch",
        (
            Field("id", "target", -1),
            Field("settings", "json", STROKE_SETTINGS),
            Field("points", "points", ""),
        ),
        _sculpt_stroke,
        sketch="points",
        target_kind="sculpt_mesh",
        needs_points=True,
    ),
)

BY_OP = {s.op: s for s in SPECS}
# The core kind each category's edits act on.
CATEGORY_KIND = {"gc": "gc_assembly", "csg": "sdf_volume", "curve": "curve_network", "sculpt": "sculpt_mesh"}


def kind_of(spec: OpSpec) -> str | None:
    """The core kind of the object `spec` edits (None: it creates one)."""
    if spec.target_kind is not None:
        return spec.target_kind
    if any(f.kind == "target" for f in spec.fields):
        return CATEGORY_KIND.get(spec.category)
    return None


CATEGORIES = (
    ("gc", "Generalized Cylinders"),
    ("csg", "CSG"),
    ("curve", "Curves and Surfaces"),
    ("sculpt", "Warp Brushes"),
)


def build_op(spec: OpSpec, values: dict, s=None) -> dict | list[dict]:
    """The op dict (or, for composite edits, the op dicts) of `spec` from
    flat property values (json/points fields already decoded); `s` is the
    scene's session, for ops built with the core's sketch functions."""
    if spec.build_with is not None:
        return spec.build_with(values, s)
    if spec.build is not None:
        return spec.build(values)
    out = {"op": spec.op}
    for f in spec.fields:
        v = values[f.name]
        out[f.name] = list(v) if f.kind == "vec3" else v
    return out


def decode(f: Field, raw: Any) -> Any:
    """A property value as the op wants it (JSON text decoded)."""
    if f.kind in ("json", "points"):
        return json.loads(raw) if raw.strip() else []
    if f.kind == "vec3":
        return tuple(float(x) for x in raw)
    return raw


# Labels of the ops that have a generic operator (built from the schema by
# `operators.generic_operator`); any other op is labelled from its name.
GENERIC_LABELS = {
    "set_transform": "Set Placement",
    "rename_object": "Rename",
    "gc_set_resolution": "Mesh Resolution",
    "gc_edit_part": "Edit Part (propagated)",
    "sdf_import_component": "Import Component",
}


def label_of(op: str) -> str:
    spec = BY_OP.get(op)
    if spec is not None:
        return spec.label
    return GENERIC_LABELS.get(op) or op.replace("_", " ").capitalize()
