"""Blender's own choices for the core's op forms: which ops get a typed
operator with a form (`SHAPEWRIGHT_OT_gc_bend`, `shapewright.gc_bend`) and
a button in the sidebar, their labels, descriptions and panel category.
The forms themselves (fields, kinds, defaults, choices) and how their
values become ops are the core's (`shapewright.op_forms`,
`shapewright.build_form`: `core/src/interact/forms/`), so this file holds
no op wire shapes or tool defaults; a field's tooltip, unit and range come
from the core's op schema (`schema.py`): the op's field of the same name,
or the one named by `like`. Every other op of the schema gets a generic
operator built from the schema alone (`forms.generic_operator`;
`GENERIC_LABELS` only names some), so a new core op needs no edit here.

Field kinds (the core's `FieldKind`):
- ``target``: an object id; -1 means the active Shapewright object.
- ``int``, ``float``, ``bool``, ``vec3``, ``enum``, ``rotation`` (an Euler
  rotation shown in the scene's angle unit, a quaternion in the op):
  plain properties; lengths in the scene's units.
- ``struct``: a nested value (a solver's weights, a stroke's settings)
  shown as one typed property per member, from the schema (`units` names
  the members that are lengths where the schema does not say).
- ``points``: a polyline as JSON ``[[x, y, z], ...]`` (a sketch: the
  Sketch operator passes it, scripts may), in the scene's units. Never
  remembered: an operator without points does what its other fields say
  (e.g. a straight cylinder at ``location``), or asks for a sketch when it
  needs one.
- ``pieces``: a picked loop as "curve from to" triples.
- ``mesh``: a Blender mesh object by name, read here (`sync.world_triangles`)
  and passed to the core as positions and triangles.

Labels never repeat Blender's own ("Delete", "Duplicate", "Draw Curve",
...): every operator is "Shapewright: <label>" in menus and F3 search.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import shapewright as sw


@dataclass(frozen=True)
class Field:
    """One field of a core form (`shapewright.op_forms`)."""

    name: str
    kind: str
    default: Any = None
    items: tuple[str, ...] = ()
    label: str = ""
    # The core's text, for a field the op does not have as such (a
    # template's size, a location); else the schema's doc is the tooltip.
    doc: str = ""
    # The schema field this property stands for when its name differs
    # (`("@Profile", "radius")`, `("gc_create", "resolution", "u")`): its
    # doc, unit and range. Default: the op's field of the same name.
    like: tuple[str, ...] = ()
    unit: str | None = None  # where the schema gives none: "m" or "rad"
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
    # How the core builds the op (both call `shapewright.build_form`):
    # `build` from the values alone, `build_with` with the scene's session
    # too (sketches on an object, Blender meshes). Neither: the values are
    # the op's fields as they are.
    build: Callable[[dict], sw.Built] | None = None
    build_with: Callable[[dict, Any], sw.Built] | None = None
    sketch: str = ""  # the field a sketch fills ("points" fields), if any
    # The core kind of the object the op edits (None: it creates one).
    target_kind: str | None = None
    # Points are required (the op has nothing to do without a sketch).
    needs_points: bool = False
    # Built from Blender data (a mesh object), not from the fields alone.
    from_blender: bool = False


# Blender's text for each form: (label, sidebar category, description), in
# the core's order of forms.
UI: dict[str, tuple[str, str, str]] = {
    # Generalized cylinders (paper 1)
    "gc_create": (
        "Cylinder from Template",
        "gc",
        "Create a generalized cylinder: a template section swept along the sketch or a straight spine",
    ),
    "gc_bend": ("Bend", "gc", "Move a key point of the spine"),
    "gc_replace_spine": (
        "Replace Spine",
        "gc",
        "Replace the spine by a sketched curve (in the part's spine plane, starting where it started)",
    ),
    "gc_resize": ("Resize Section", "gc", "Scale a key section"),
    "gc_shift": ("Shift Section", "gc", "Move a key section along the spine"),
    "gc_twist": ("Twist Section", "gc", "Twist an interior key section"),
    "gc_replace_section": (
        "Replace Section",
        "gc",
        "Replace a key section by a template, or by the template a sketched loop matches",
    ),
    "gc_delete_section": ("Delete Section", "gc", "Delete a key section"),
    "gc_insert_section": ("Insert Section", "gc", "Insert a key section at spine parameter v"),
    "gc_set_shape": ("Shape Type", "gc", "Solid, shell or container, with a wall thickness"),
    "gc_add_child": (
        "Add Child",
        "gc",
        "Add a child cylinder starting on a part's surface: sketched from the part (a handle when the "
        "stroke ends on it, else a spout), or a straight stub at a point",
    ),
    "gc_copy": ("Instance Part", "gc", "Copy a part with its children (an instance; optionally mirrored)"),
    "gc_transform_part": ("Move Part", "gc", "Move a part rigidly"),
    # CSG with the component library (paper 2)
    "sdf_create": ("New CSG Volume", "csg", "Create an empty CSG volume"),
    "sdf_add_operand": (
        "Add Component",
        "csg",
        "Add a library component or a solid with a boolean operation",
    ),
    "sdf_set_operand_transform": ("Place Operand", "csg", "Place an operand"),
    "sdf_scale_two_hand": (
        "Two-Hand Scale",
        "csg",
        "Scale an operand by the change of distance between two hands",
    ),
    "sdf_update": ("Operate", "csg", "Fuse the pending operands into the volume"),
    "sdf_cancel_operand": ("Cancel Operand", "csg", "Drop a pending operand"),
    "sdf_copy_operand": ("Copy Operand", "csg", "Copy an operand to a new placement"),
    "sdf_import_component": (
        "Import Component",
        "csg",
        "Add a closed Blender mesh (triangulated, in world space) to the volume's components; "
        "then add it with Add Component as a user component (Apply Op) by its name",
    ),
    "sdf_set_step": ("Grid Step", "csg", "Set the volume's grid step"),
    # Curve drawing and styling (paper 3)
    "curve_network_create": ("New Curve Network", "curve", "Create an empty curve network"),
    "curve_draw": ("Curve from Sketch", "curve", "Draw a curve from sketch samples"),
    "curve_smooth": ("Smooth Curve", "curve", ""),
    "curve_sharpen": ("Sharpen Curve", "curve", ""),
    "curve_pull": ("Pull Curve", "curve", ""),
    "curve_delete": ("Delete Curve", "curve", "Delete a network curve"),
    "curve_fill_loop": ("Fill Loop", "curve", "Fill a picked loop of curve pieces with a patch"),
    "curve_fill_auto": ("Fill All Loops", "curve", "Fill every loop found automatically"),
    "surface_smooth": ("Smooth Surface", "curve", ""),
    "surface_sharpen": ("Sharpen Surface", "curve", ""),
    "surface_pull": ("Pull Surface", "curve", ""),
    # Warp brushes (paper 4)
    "sculpt_create": ("New Sculpt", "sculpt", "Create a sculpt object from a base shape"),
    "sculpt_stroke": ("Warp Stroke", "sculpt", "Apply a warp-brush stroke along the sketch"),
}


def _built(op: str, values: dict, s=None) -> sw.Built:
    """The core's op (or ops, applied as one step) of form `op`, kept in
    the core until `Session.apply`; a refusal names the operator ("Fill
    Loop: ...")."""
    try:
        return sw.build_form(op, values, s)
    except sw.ShapewrightError as e:
        label = UI[op][0] if op in UI else op
        raise type(e)(f"{label}: {e}") from e


def _with_mesh(op: str, values: dict, s=None) -> sw.Built:
    """Form values with their Blender mesh read (world space, triangles)."""
    from . import sync  # Blender's side: reads the mesh object

    name, positions, triangles = sync.world_triangles(values["mesh"])
    mesh = {"name": name, "positions": positions, "triangles": triangles}
    return _built(op, {**values, "mesh": mesh}, s)


def form_of(op: str) -> dict[str, dict]:
    """The core's form of `op`, its fields by name (the hand-written
    operators' defaults and help, `ops_object.py`)."""
    form = next(f for f in sw.op_forms() if f["op"] == op)
    return {f["name"]: f for f in form["fields"]}


def _field(f: dict) -> Field:
    return Field(
        f["name"],
        f["kind"],
        tuple(f["default"]) if f["kind"] in ("vec3", "rotation") else f["default"],
        tuple(f["items"]),
        f["label"],
        f["doc"],
        tuple(f["like"]),
        f["unit"],
        f["none_at"],
        dict(f["units"]),
    )


def _spec(form: dict) -> OpSpec:
    op = form["op"]
    label, category, description = UI[op]
    how = form["build"]
    build = build_with = None
    if how == "values":
        build = lambda v, _op=op: _built(_op, v)  # noqa: E731
    elif how == "sketch":
        build_with = lambda v, s=None, _op=op: _built(_op, v, s)  # noqa: E731
    elif how == "host_mesh":
        build_with = lambda v, s=None, _op=op: _with_mesh(_op, v, s)  # noqa: E731
    return OpSpec(
        op,
        label,
        category,
        description or f"{label}: the tool held along the sketch path",
        tuple(_field(f) for f in form["fields"]),
        build,
        build_with,
        form["sketch"],
        form["target_kind"],
        form["needs_points"],
        how == "host_mesh",
    )


# The core's forms of solids and the document's own ops (add_solid,
# transform_by, duplicate, delete, ...) have hand-written operators
# (`ops_object.py`: the Add menu, Shift-D and X) and no entry here.
SPECS: tuple[OpSpec, ...] = tuple(_spec(f) for f in sw.op_forms() if f["op"] in UI)
assert set(UI) == {s.op for s in SPECS}, "every op given Blender's text has a core form"

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


def build_op(spec: OpSpec, values: dict, s=None) -> sw.Built:
    """The op (or, for composite edits, the ops) of `spec` from
    flat property values (json/points fields already decoded); `s` is the
    scene's session, for ops built with the core's sketch functions."""
    if spec.build_with is not None:
        return spec.build_with(values, s)
    if spec.build is not None:
        return spec.build(values)
    return _built(spec.op, values)


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
