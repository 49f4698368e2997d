"""Blender's own choices for the core's ops: the ops that get a typed
operator with a Blender-shaped form (`SHAPEWRIGHT_OT_gc_bend`,
`shapewright.gc_bend`) and a button in the sidebar, their labels and
panel category, and which build function of `op_build.py` turns their
flat fields into the op (templates, sketches, placements). Each spec
lists its fields (name, kind, default); a field's tooltip, unit and range
come from the core's op schema (`schema.py`): the op's field of the same
name, or the one named by `like`. Every other op of the schema gets a
generic operator built from the schema alone (`forms.generic_operator`;
`GENERIC_LABELS` only names some), so a new core op needs no edit here.

Field kinds:
- ``target``: an object id; -1 means the active Shapewright object.
- ``int``, ``float``, ``bool``, ``vec3``, ``enum``, ``rotation`` (an Euler
  rotation shown in the scene's angle unit, a quaternion in the op):
  plain properties; lengths in the scene's units.
- ``struct``: a nested value (a solver's weights, a stroke's settings)
  shown as one typed property per member, from the schema (defaults are
  the values the example scripts use; `units` names the members that are
  lengths where the schema does not say).
- ``points``: a polyline as JSON ``[[x, y, z], ...]`` (a sketch: the
  Sketch operator passes it, scripts may), in the scene's units. Never
  remembered: an operator without points does what its other fields say
  (e.g. a straight cylinder at ``location``), or asks for a sketch when it
  needs one.
- ``pieces``: a picked loop as "curve from to" triples.

Labels never repeat Blender's own ("Delete", "Duplicate", "Draw Curve",
...): every operator is "Shapewright: <label>" in menus and F3 search.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import shapewright as sw

from .op_build import (
    SURFACE_PIECES_DOC,
    _curve_draw,
    _gc_add_child,
    _gc_create,
    _gc_replace_section,
    _gc_replace_spine,
    _import_component,
    _part_move,
    _pieces,
    _sculpt_create,
    _sculpt_stroke,
    _sdf_add,
    _sdf_two_hand,
    _section_op,
    _vec_op,
    shape_type,
    transform,
)


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
    # For `struct` fields: members that are lengths ("m") where the
    # schema gives no unit, by their name under the field.
    units: dict = field(default_factory=dict)


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


HAND_DOC = "The %s hand's position when the gesture %s"
TEMPLATE_DOC = "Section template: circle, ellipse, regular polygon or rectangle"
SIZE_A_DOC = "Circle or polygon radius, ellipse semi-axis rx, rectangle width (positive)"
SIZE_B_DOC = "Ellipse semi-axis ry, rectangle height (positive); unused by circles and polygons"
DIMENSIONS_DOC = (
    "The solid's size along its x, y and z (its bounding box): a round shape's diameter is x; a "
    "cylinder's, cone's or capsule's height z; a torus's tube diameter z"
)
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
    Field("shape", "enum", "sphere", tuple(sw.solid_kinds()), like=("@SolidShape", "kind")),
    Field("dimensions", "vec3", (0.1, 0.1, 0.1), doc=DIMENSIONS_DOC, unit="m"),
)
PLACE_FIELDS = (
    Field("location", "vec3", (0.0, 0.0, 0.0), like=("@Transform", "translate")),
    Field("rotation", "rotation", (0.0, 0.0, 0.0, 1.0), doc="Rotation"),
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


SURFACE_EQ = (
    Field("weights", "struct", SURFACE_WEIGHTS),
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
        "Curve from Sketch",
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
    path_tool("curve_smooth", "Smooth Curve", "curve", (Field("params", "struct", SMOOTH_PARAMS),)),
    path_tool(
        "curve_sharpen",
        "Sharpen Curve",
        "curve",
        (
            Field("params", "struct", SHARPEN_PARAMS),
            Field("limits", "struct", {"max_step": 0.004, "max_growth": 4.0}, units={"max_step": "m"}),
        ),
    ),
    path_tool(
        "curve_pull",
        "Pull Curve",
        "curve",
        (Field("params", "struct", {"wpp": 200.0, "wp0": 1.0, "wp1": 0.001}),),
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
        (Field("id", "target", -1), Field("pieces", "pieces", "", doc=SURFACE_PIECES_DOC)),
        _pieces,
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
            Field("weights", "struct", SURFACE_WEIGHTS),
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
            Field(
                "settings",
                "struct",
                STROKE_SETTINGS,
                units={"brush_radius": "m", "brush_radii": "m", "brush_half_length": "m", "influence": "m"},
            ),
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
