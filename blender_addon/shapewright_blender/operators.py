"""Operators: every modeling action is one op in the core's log.

Each operator builds an op (a plain dict), hands it to `history.apply`,
and reports the core's error text if the op is refused (nothing changes
then). Blender's conventions:
- `bl_options` has 'UNDO' wherever data changes, so that Blender's undo
  step and the log's cursor move together;
- operators act on the active object and the selection; an object id is
  only used when a script passes one (`id >= 0`); no property is
  remembered between calls (`SKIP_SAVE`), so one call's values never
  steer the next;
- a created object becomes the active and only selected object;
- `poll` hides what does not apply (edits of a kind need an object of
  that kind);
- bad values are refused with the field's name and the reason: numbers
  are not clamped by the properties (no hard limits), NaN, infinity and
  Blender's float32 overflow of `inf` are refused before the op is
  built (`shapewright.check_finite`), and the core refuses zero or
  negative sizes by name.
Typed operators come from `op_table`; every other op of the core's schema
gets a generic one (`generic_operator`), its properties built from the
schema. Every property's tooltip, unit and soft range come from the
schema, and values outside the range are refused by field name before the
op is built (float32 property values snapped to their shortest decimal).
Long exports run on a thread of their own with Blender's progress bar and
Esc to cancel (`SHAPEWRIGHT_OT_export_mesh`).
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import bpy
import numpy as np
import shapewright as sw
from bpy.props import (
    BoolProperty,
    EnumProperty,
    FloatProperty,
    FloatVectorProperty,
    IntProperty,
    StringProperty,
)

from . import history, op_table, schema, shared, sync

SKIP = {"SKIP_SAVE"}

SHAPES = (
    ("box", "Box", "Axis-aligned box"),
    ("sphere", "Sphere", "Sphere"),
    ("ellipsoid", "Ellipsoid", "Ellipsoid"),
    ("cylinder", "Cylinder", "Closed cylinder along Z"),
    ("cone", "Cone", "Cone along Z"),
    ("torus", "Torus", "Torus around Z"),
    ("capsule", "Capsule", "Cylinder with hemispherical ends"),
)


def shape_dict(op) -> dict:
    k = op.shape
    if k == "box":
        return {"kind": k, "size": list(op.size)}
    if k == "sphere":
        return {"kind": k, "radius": op.radius}
    if k == "ellipsoid":
        return {"kind": k, "radii": [s / 2 for s in op.size]}
    if k in ("cylinder", "cone"):
        return {"kind": k, "radius": op.radius, "height": op.height}
    if k == "torus":
        return {"kind": k, "major_radius": op.radius, "minor_radius": op.minor_radius}
    return {"kind": k, "radius": op.radius, "length": op.height}


def active_id(context) -> int | None:
    obj = context.active_object
    return obj.get(sync.ID_PROP) if obj is not None else None


def active_kind(context) -> str | None:
    return sync.kind_of(context.active_object)


def selected_ids(context, kind: str | None = None) -> list[int]:
    """Ids of the selected Shapewright objects (of `kind`), the active one
    first; the active object counts even when not selected."""
    objs = [context.active_object] if context.active_object is not None else []
    objs += [o for o in context.selected_objects if o is not context.active_object]
    out = []
    for o in objs:
        oid = o.get(sync.ID_PROP)
        if oid is not None and oid not in out and (kind is None or sync.kind_of(o) == kind):
            out.append(oid)
    return out


def scene_has_kind(context, kind: str) -> bool:
    coll = bpy.data.collections.get(sync.COLLECTION)
    return coll is not None and any(sync.kind_of(o) == kind for o in coll.objects)


class _ShapeProps:
    # The schema fields these properties stand for (the tooltips' ranges,
    # and tests check the soft ranges against them); the core refuses what
    # is out of range, by name.
    sw_schema = {
        "size": ("@SolidShape", "size"),
        "radius": ("@SolidShape", "radius"),
        "minor_radius": ("@SolidShape", "minor_radius"),
        "height": ("@SolidShape", "height"),
        "segments": ("add_solid", "segments"),
    }
    shape: EnumProperty(
        name="Shape",
        items=SHAPES,
        default="sphere",
        description=schema.info(("@SolidShape", "kind")).doc or "The solid's shape",
        options=SKIP,
    )
    size: FloatVectorProperty(
        name="Size",
        description=schema.info(("@SolidShape", "size")).tooltip("Box edge lengths; ellipsoid diameters"),
        default=(0.2, 0.2, 0.2),
        soft_min=0.0,
        subtype="XYZ_LENGTH",
        unit="LENGTH",
        options=SKIP,
    )
    radius: FloatProperty(
        name="Radius",
        description="Radius; the torus's major radius. Range: > 0 m.",
        default=0.1,
        soft_min=0.0,
        subtype="DISTANCE",
        unit="LENGTH",
        options=SKIP,
    )
    minor_radius: FloatProperty(
        name="Minor radius",
        description="The torus tube's radius, smaller than the radius. Range: > 0 m.",
        default=0.03,
        soft_min=0.0,
        subtype="DISTANCE",
        unit="LENGTH",
        options=SKIP,
    )
    height: FloatProperty(
        name="Height / length",
        description="Cylinder and cone height; capsule length between its caps. Range: > 0 m.",
        default=0.2,
        soft_min=0.0,
        subtype="DISTANCE",
        unit="LENGTH",
        options=SKIP,
    )
    segments: IntProperty(
        name="Segments",
        description=schema.info(("add_solid", "segments")).tooltip("Segments around curved solids"),
        default=64,
        soft_min=8,
        soft_max=1024,
        options=SKIP,
    )


def run_op(operator, context, op: dict | list[dict]) -> set[str]:
    """Applies `op` (or a list of ops, all or none) to the scene; reports
    the core's message if it is refused. A created object becomes the
    active and only selected one."""
    ops = op if isinstance(op, list) else [op]
    scene = context.scene
    history.finish_pending(scene)  # a move made just before comes first
    try:
        if len(ops) > 1:
            # All or none: try them on a copy first.
            trial = history.session(scene).snapshot()
            for o in ops:
                sw.apply(trial, o)
        created = None
        for o in ops:
            created = history.apply(scene, o) or created
    except sw.ShapewrightError as e:
        operator.report({"ERROR"}, str(e))
        return {"CANCELLED"}
    if created is not None:
        obj = sync.object_for(scene, created)
        if obj is not None:
            sync.select_only(context, obj)
    return {"FINISHED"}


class SHAPEWRIGHT_OT_add_solid(_ShapeProps, bpy.types.Operator):
    """Add a parametric solid at the 3D cursor"""

    bl_idname = "shapewright.add_solid"
    bl_label = "Add Solid"
    bl_options = {"REGISTER", "UNDO"}

    location: FloatVectorProperty(
        name="Location",
        description="Where the solid's center goes (m), when not at the 3D cursor",
        default=(0.0, 0.0, 0.0),
        subtype="TRANSLATION",
        options=SKIP,
    )
    use_cursor: BoolProperty(
        name="At 3D cursor", description="Place the solid at the 3D cursor", default=True, options=SKIP
    )

    def execute(self, context):
        loc = context.scene.cursor.location if self.use_cursor else self.location
        op = {
            "op": "add_solid",
            "shape": shape_dict(self),
            "segments": self.segments,
            "transform": {"translate": list(loc), "rotate": [0.0, 0.0, 0.0, 1.0], "scale": [1.0, 1.0, 1.0]},
        }
        return run_op(self, context, op)


class SHAPEWRIGHT_OT_edit_solid(_ShapeProps, bpy.types.Operator):
    """Change the active solid's shape and sizes, keeping its placement"""

    bl_idname = "shapewright.edit_solid"
    bl_label = "Edit Solid"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return active_kind(context) == "solid"

    def execute(self, context):
        op = {
            "op": "edit_solid",
            "id": active_id(context),
            "shape": shape_dict(self),
            "segments": self.segments,
        }
        return run_op(self, context, op)


class SHAPEWRIGHT_OT_move(bpy.types.Operator):
    """Move, rotate (about Z) or scale the selected Shapewright objects by exact amounts"""

    bl_idname = "shapewright.move"
    bl_label = "Move Object"
    bl_options = {"REGISTER", "UNDO"}

    offset: FloatVectorProperty(
        name="Offset",
        description="Translation (m)",
        default=(0.0, 0.0, 0.0),
        subtype="TRANSLATION",
        options=SKIP,
    )
    angle_z: FloatProperty(
        name="Angle Z", description="Rotation about Z", default=0.0, subtype="ANGLE", options=SKIP
    )
    scale: FloatProperty(
        name="Uniform scale", description="Scale factor (positive)", default=1.0, soft_min=1e-3, options=SKIP
    )

    @classmethod
    def poll(cls, context):
        return bool(selected_ids(context))

    def execute(self, context):
        h = self.angle_z / 2
        ops = [
            {
                "op": "transform_by",
                "id": oid,
                "transform": {
                    "translate": list(self.offset),
                    "rotate": [0.0, 0.0, math.sin(h), math.cos(h)],
                    "scale": [self.scale] * 3,
                },
            }
            for oid in selected_ids(context)
        ]
        return run_op(self, context, ops)


class SHAPEWRIGHT_OT_duplicate(bpy.types.Operator):
    """Copy the selected Shapewright objects (each copy gets the next id)"""

    bl_idname = "shapewright.duplicate"
    bl_label = "Duplicate"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return bool(selected_ids(context))

    def execute(self, context):
        return run_op(self, context, [{"op": "duplicate", "id": i} for i in selected_ids(context)])


class SHAPEWRIGHT_OT_delete(bpy.types.Operator):
    """Delete the selected Shapewright objects (undoable)"""

    bl_idname = "shapewright.delete"
    bl_label = "Delete"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return bool(selected_ids(context))

    def execute(self, context):
        return run_op(self, context, [{"op": "delete", "id": i} for i in selected_ids(context)])


class SHAPEWRIGHT_OT_run_script(bpy.types.Operator):
    """Run an op script (.jsonl) on the scene's document, as one undo step"""

    bl_idname = "shapewright.run_script"
    bl_label = "Run Op Script"
    bl_options = {"REGISTER", "UNDO"}

    filepath: StringProperty(description="The op script (.jsonl) to run", subtype="FILE_PATH", options=SKIP)
    filter_glob: StringProperty(default="*.jsonl", description="Files the browser lists", options={"HIDDEN"})

    def invoke(self, context, event):
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def execute(self, context):
        try:
            text = Path(self.filepath).read_text()
        except OSError as e:
            self.report({"ERROR"}, f"cannot read {self.filepath}: {e}")
            return {"CANCELLED"}
        history.finish_pending(context.scene)
        s = history.session(context.scene)
        trial = s.snapshot()
        try:
            trial.run_script(text)
        except sw.ShapewrightError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        s.run_script(text)
        history.record(context.scene, s)
        return {"FINISHED"}


class SHAPEWRIGHT_OT_apply_op(bpy.types.Operator):
    """Apply any op given as JSON (one line of an op script, undo and redo included)"""

    bl_idname = "shapewright.apply_op"
    bl_label = "Apply Op"
    bl_options = {"REGISTER", "UNDO"}

    op_json: StringProperty(
        name="Op (JSON)",
        description='One op script line, e.g. {"op":"add_solid",...} or {"op":"undo"}',
        default="",
        options=SKIP,
    )

    def execute(self, context):
        try:
            op = json.loads(self.op_json)
        except json.JSONDecodeError as e:
            self.report({"ERROR"}, f"op is not JSON: {e}")
            return {"CANCELLED"}
        if not isinstance(op, dict):
            self.report({"ERROR"}, "op must be a JSON object")
            return {"CANCELLED"}
        return run_op(self, context, op)


TARGET_DOC = "Object id, for scripts; -1 (the default): the active object"


def field_info(spec: op_table.OpSpec, f: op_table.Field) -> schema.Info:
    """The schema's doc, unit and range for one op-table field (the field
    it stands for, `f.like`, or the op's field of the same name), with
    Blender's own text and unit where the field is the add-on's own."""
    path = f.like or (spec.op, f.name)
    inf = schema.info(path) if schema.field_schema(path) is not None else schema.Info()
    return dataclasses.replace(inf, doc=f.doc or inf.doc, unit=f.unit or inf.unit)


def schema_path(spec: op_table.OpSpec, f: op_table.Field) -> tuple[str, ...] | None:
    """The schema field a typed operator's property stands for (None: a
    field of the add-on's own)."""
    path = f.like or (spec.op, f.name)
    return path if schema.field_schema(path) is not None else None


def _description(kind: str, inf: schema.Info, label: str) -> str:
    if kind == "target":
        return f"{inf.doc} {TARGET_DOC}".strip() if inf.doc and inf.doc != "The object." else TARGET_DOC
    if kind == "points":
        return "A sketch as JSON [[x, y, z], ...] (the Sketch operator fills it); empty: none"
    tip = inf.tooltip(label)
    if kind == "json":
        return f"{tip} (JSON)"
    return tip


def make_property(kind: str, label: str, inf: schema.Info, default, items=(), size: int = 0):
    """One bpy property with its tooltip, unit and soft range from the
    schema. Not remembered between calls; no hard limits (they would clamp
    silently): `check_value` refuses what the core would refuse, by name."""
    desc = _description(kind, inf, label)
    lo, hi = inf.soft_range()
    rng = {}
    if kind in ("int", "float", "vec", "vec3"):
        if lo is not None:
            rng["soft_min"] = int(lo) if kind == "int" else float(lo)
        if hi is not None:
            rng["soft_max"] = int(hi) if kind == "int" else float(hi)
    unit, subtype, vec_subtype = schema.UNITS.get(inf.unit or "", ("NONE", "NONE", "NONE"))
    if kind == "target":
        return IntProperty(name=label, default=-1, description=desc, options=SKIP)
    if kind == "int":
        return IntProperty(name=label, default=default, description=desc, options=SKIP, **rng)
    if kind == "float":
        return FloatProperty(
            name=label,
            default=default,
            precision=4,
            description=desc,
            subtype=subtype,
            unit=unit,
            options=SKIP,
            **rng,
        )
    if kind == "bool":
        return BoolProperty(name=label, default=default, description=desc, options=SKIP)
    if kind in ("vec", "vec3"):
        n = size or 3
        return FloatVectorProperty(
            name=label,
            default=tuple(default),
            size=n,
            description=desc,
            subtype=vec_subtype if n == 3 else "NONE",
            unit=unit,
            options=SKIP,
            **rng,
        )
    if kind == "enum":
        return EnumProperty(
            name=label,
            items=[(i, i.replace("_", " ").capitalize(), "") for i in items],
            default=default,
            description=desc,
            options=SKIP,
        )
    if kind == "library":
        return EnumProperty(
            name=label,
            items=[(n, n, "") for n in sw.library_names()],
            default=default,
            description=desc,
            options=SKIP,
        )
    if kind == "json":
        text = "" if default in (None, "") else json.dumps(default)
        return StringProperty(name=label, default=text, description=desc, options=SKIP)
    return StringProperty(name=label, default=default or "", description=desc, options=SKIP)


def _property(spec: op_table.OpSpec, f: op_table.Field):
    """The bpy property of one op-table field."""
    label = f.label or f.name.replace("_", " ").capitalize()
    return make_property(f.kind, label, field_info(spec, f), f.default, f.items)


def snap32(v):
    """A float (or vector) property's value as the shortest decimal that
    rounds to the same float32: Blender keeps 0.012 as 0.0120000001, which
    the core would refuse at its bound 0.012, and the op log should read
    what the user typed."""
    if isinstance(v, (list, tuple)):
        return type(v)(snap32(x) for x in v)
    if isinstance(v, float) and math.isfinite(v):
        return float(str(np.float32(v)))
    return v


def check_value(label: str, inf: schema.Info, v, none_at=None) -> None:
    """Refuses (ValueError naming the field) a number or vector component
    outside the schema's range."""
    if none_at is not None and v == none_at:
        return
    xs = v if isinstance(v, (list, tuple)) else [v]
    for x in xs:
        if isinstance(x, (int, float)) and not isinstance(x, bool):
            problem = inf.problem(x)
            if problem is not None:
                raise ValueError(f"{label} {problem}")


def op_values(operator, spec: op_table.OpSpec, context) -> dict:
    """The flat values of a typed operator, with targets resolved (the
    active object unless a script passed an id). Raises ValueError with a
    message for the user."""
    values = {}
    kind = op_table.kind_of(spec)
    for f in spec.fields:
        raw = getattr(operator, f.name)
        if f.kind == "target" and raw < 0:
            raw = active_id(context)
            if raw is None or (kind is not None and active_kind(context) != kind):
                what = (kind or "Shapewright object").replace("_", " ")
                raise ValueError(f"{spec.label}: make a {what} the active object (or pass {f.name})")
        try:
            v = op_table.decode(f, raw)
        except json.JSONDecodeError as e:
            raise ValueError(f"{spec.label}: {f.name} is not JSON: {e}") from e
        if f.kind in ("float", "vec3"):
            v = snap32(v)
        if f.kind in ("int", "float", "vec3"):
            check_value(f"{spec.label}: {f.name}", field_info(spec, f), v, f.none_at)
        values[f.name] = v
    for f in spec.fields:
        if f.kind == "points" and not values[f.name] and spec.needs_points:
            raise ValueError(f"{spec.label}: sketch it (Sketch panel) or give {f.name}")
    sw.check_finite(values)
    return values


def _typed_execute(self, context):
    spec = op_table.BY_OP[self.op_name]
    try:
        values = op_values(self, spec, context)
        s = history.session(context.scene) if spec.build_with is not None else None
        op = op_table.build_op(spec, values, s)
    except ValueError as e:  # also sw.ShapewrightError (a ValueError)
        self.report({"ERROR"}, str(e))
        return {"CANCELLED"}
    return run_op(self, context, op)


def _typed_poll(spec: op_table.OpSpec):
    kind = op_table.kind_of(spec)
    if kind is None:
        return None

    def poll(cls, context):
        # The active object's kind for buttons and menus; a script may
        # pass an id while something else is active.
        return active_kind(context) == kind or scene_has_kind(context, kind)

    return classmethod(poll)


def typed_operator(spec: op_table.OpSpec) -> type:
    """A thin operator class for one op spec: its fields as properties,
    execute = build the op dict and apply it."""
    attrs = {
        "__doc__": spec.description,
        "bl_idname": f"shapewright.{spec.op}",
        "bl_label": spec.label,
        "bl_options": {"REGISTER", "UNDO"},
        "op_name": spec.op,
        "__annotations__": {f.name: _property(spec, f) for f in spec.fields},
        "execute": _typed_execute,
        # Which schema field each property stands for (tests check the
        # properties' tooltips and ranges against it).
        "sw_schema": {
            f.name: p
            for f in spec.fields
            if f.kind not in ("target", "points") and (p := schema_path(spec, f)) is not None
        },
    }
    poll = _typed_poll(spec)
    if poll is not None:
        attrs["poll"] = poll
    return type(f"SHAPEWRIGHT_OT_{spec.op}", (bpy.types.Operator,), attrs)


def generic_values(operator, op: str, fields: tuple[schema.GenField, ...], context) -> dict:
    """The op dict of a generic operator: its properties put back where
    the schema has them, targets resolved (the active object unless a
    script passed an id), numbers checked against the schema's ranges.
    Raises ValueError with a message for the user."""
    kind = schema.OPS[op]["kind"]
    want = None if kind == "document" else kind
    label = op_table.label_of(op)
    out: dict = {"op": op}
    missing: list[str] = []
    for g in fields:
        raw = getattr(operator, g.prop)
        if g.kind == "target":
            if raw < 0:
                raw = active_id(context)
                if raw is None or (want is not None and active_kind(context) != want):
                    what = (want or "Shapewright object").replace("_", " ")
                    raise ValueError(f"{label}: make a {what} the active object (or pass {g.prop})")
            v = raw
        elif g.kind == "json":
            if not raw.strip():
                if g.required:
                    missing.append(g.prop)
                continue
            try:
                v = json.loads(raw)
            except json.JSONDecodeError as e:
                raise ValueError(f"{label}: {g.prop} is not JSON: {e}") from e
        elif g.kind == "vec":
            v = [snap32(float(x)) for x in raw]
        elif g.kind == "float":
            v = snap32(raw)
        else:
            v = raw
        if g.kind in ("int", "float", "vec"):
            check_value(f"{label}: {g.prop}", g.info, v)
        d = out
        for k in g.path[:-1]:
            d = d.setdefault(k, {})
        d[g.path[-1]] = v
    if missing:
        raise ValueError(f"{label}: give {', '.join(missing)} (JSON)")
    sw.check_finite(out)
    return out


def generic_operator(op: str) -> type:
    """An operator for any op of the core's schema, its properties built
    from the schema (`schema.fields`): a new core op gets one with no
    add-on edit."""
    fields = schema.fields(op)
    kind = schema.OPS[op]["kind"]
    label = op_table.label_of(op)

    def execute(self, context):
        try:
            built = generic_values(self, op, fields, context)
        except ValueError as e:  # also sw.ShapewrightError
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        return run_op(self, context, built)

    attrs = {
        "__doc__": schema.clean_doc(schema.OPS[op]["doc"]) or label,
        "bl_idname": f"shapewright.{op}",
        "bl_label": label,
        "bl_options": {"REGISTER", "UNDO"},
        "op_name": op,
        "__annotations__": {
            g.prop: make_property(
                g.kind, g.prop.replace("_", " ").capitalize(), g.info, g.default, g.items, g.size
            )
            for g in fields
        },
        "execute": execute,
        "sw_schema": {g.prop: (op, *g.path) for g in fields if g.kind != "target"},
    }
    if any(g.kind == "target" for g in fields):
        want = None if kind == "document" else kind

        def poll(cls, context):
            if want is None:
                return active_kind(context) is not None
            return active_kind(context) == want or scene_has_kind(context, want)

        attrs["poll"] = classmethod(poll)
    return type(f"SHAPEWRIGHT_OT_{op}", (bpy.types.Operator,), attrs)


def generic_ops() -> tuple[str, ...]:
    """The core's ops that have neither a typed operator (`op_table`) nor
    a hand-written one here: each gets a generic operator. Ops of kind
    `session` (`reserve_ids`) are written by shared sessions, never by a
    person, and get none."""
    return tuple(
        n
        for n in schema.OPS
        if n not in op_table.BY_OP and n not in HAND_WRITTEN and schema.OPS[n]["kind"] != "session"
    )


class SHAPEWRIGHT_OT_undo(bpy.types.Operator):
    """Undo: Blender's undo; where the file was opened or the document imported, the op log's"""

    bl_idname = "shapewright.undo"
    bl_label = "Undo"

    def execute(self, context):
        done = history.undo_step(context)
        if done == "nothing":
            self.report({"INFO"}, "Nothing to undo")
            return {"CANCELLED"}
        return {"FINISHED"}


class SHAPEWRIGHT_OT_redo(bpy.types.Operator):
    """Redo: Blender's redo, and at the point the file was opened, the op log's"""

    bl_idname = "shapewright.redo"
    bl_label = "Redo"

    def execute(self, context):
        done = history.redo_step(context)
        if done == "nothing":
            self.report({"INFO"}, "Nothing to redo")
            return {"CANCELLED"}
        return {"FINISHED"}


class SHAPEWRIGHT_OT_join(bpy.types.Operator):
    """Join the shared session at the Join address: everyone's edits reach everyone, each undoes their own"""

    bl_idname = "shapewright.join"
    bl_label = "Join"

    @classmethod
    def poll(cls, context):
        return context.scene is not None and shared.joined(context.scene) is None

    def execute(self, context):
        wm = context.window_manager.shapewright_join
        if not wm.url.strip():
            self.report({"ERROR"}, "Type the session's address first: nats://HOST:PORT/DOC")
            return {"CANCELLED"}
        try:
            messages = shared.join(context.scene, wm.url, wm.name)
        except sw.ShapewrightError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        for m in messages:
            self.report({"INFO"}, m)
        return {"FINISHED"}


class SHAPEWRIGHT_OT_leave(bpy.types.Operator):
    """Leave the shared session: the document stays here as your own history"""

    bl_idname = "shapewright.leave"
    bl_label = "Leave"

    @classmethod
    def poll(cls, context):
        return context.scene is not None and shared.joined(context.scene) is not None

    def execute(self, context):
        shared.leave(context.scene)
        return {"FINISHED"}


class SHAPEWRIGHT_OT_undo_past_load(bpy.types.Operator):
    """Ctrl-Z where Blender's undo history ends (after opening a file): undo the op log"""

    bl_idname = "shapewright.undo_past_load"
    bl_label = "Undo (saved history)"
    bl_options = {"INTERNAL"}

    @classmethod
    def poll(cls, context):
        scene = context.scene
        if scene is None or not scene.shapewright.ops or history._blender_can("undo"):
            return False
        return history.session(scene).can_undo

    def execute(self, context):
        return {"FINISHED"} if history.undo_step(context) != "nothing" else {"CANCELLED"}


class SHAPEWRIGHT_OT_redo_past_load(bpy.types.Operator):
    """Ctrl-Shift-Z at the point a file was opened: redo the op log"""

    bl_idname = "shapewright.redo_past_load"
    bl_label = "Redo (saved history)"
    bl_options = {"INTERNAL"}

    @classmethod
    def poll(cls, context):
        scene = context.scene
        if scene is None or not scene.shapewright.ops:
            return False
        base = history._bases.get(scene.name)
        log_first = history.at_base(scene) and base is not None and base.override is not None
        if not log_first and history._blender_can("redo"):
            return False
        return history.session(scene).can_redo

    def execute(self, context):
        return {"FINISHED"} if history.redo_step(context) != "nothing" else {"CANCELLED"}


class ExportTask:
    """One export on a thread of its own (the core's `ExportJob`), polled
    by the modal operator (or a test): `tick()` returns `running`,
    `done` or `failed`; `message` says what happened."""

    def __init__(self, s: sw.Session, path: str) -> None:
        self.job = sw.ExportJob(s, path)
        self.message = ""
        self.summary: dict | None = None

    def progress(self) -> tuple[str, float]:
        return self.job.progress()

    def cancel(self) -> None:
        self.job.cancel()

    def tick(self) -> str:
        if not self.job.done():
            return "running"
        try:
            self.summary = self.job.result()
        except (sw.ShapewrightError, OSError) as e:
            self.message = str(e)
            return "failed"
        self.message = f"exported {self.summary['triangles']} triangles to {self.summary['path']}"
        return "done"


class SHAPEWRIGHT_OT_export_mesh(bpy.types.Operator):
    """Export the printable union (STL, OBJ or PLY, by extension); refused when empty or not closed"""

    bl_idname = "shapewright.export_mesh"
    bl_label = "Export Mesh"

    filepath: StringProperty(
        description="Where to write the mesh; .stl, .obj or .ply chooses the format",
        subtype="FILE_PATH",
        options=SKIP,
    )
    filter_glob: StringProperty(
        default="*.stl;*.obj;*.ply", description="Files the browser lists", options={"HIDDEN"}
    )

    _task: ExportTask | None = None
    _timer = None

    @classmethod
    def poll(cls, context):
        return context.scene is not None and bool(context.scene.shapewright.ops)

    def invoke(self, context, event):
        if not self.filepath:
            self.filepath = bpy.path.ensure_ext(bpy.data.filepath or "untitled", ".stl")
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def execute(self, context):
        s = history.session(context.scene)
        if context.window is None or bpy.app.background:
            # Scripts and headless runs: the same checks, on this thread.
            try:
                out = s.export_mesh(self.filepath)
            except (sw.ShapewrightError, OSError) as e:
                self.report({"ERROR"}, str(e))
                return {"CANCELLED"}
            self.report({"INFO"}, f"exported {out['triangles']} triangles to {out['path']}")
            return {"FINISHED"}
        try:
            self._task = ExportTask(s, self.filepath)
        except sw.ShapewrightError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        wm = context.window_manager
        wm.progress_begin(0.0, 1.0)
        self._timer = wm.event_timer_add(0.1, window=context.window)
        wm.modal_handler_add(self)
        context.workspace.status_text_set("Shapewright export: Esc cancels")
        return {"RUNNING_MODAL"}

    def _finish(self, context) -> None:
        wm = context.window_manager
        wm.progress_end()
        if self._timer is not None:
            wm.event_timer_remove(self._timer)
        context.workspace.status_text_set(None)

    def modal(self, context, event):
        task = self._task
        if task is None:
            return {"CANCELLED"}
        if event.type == "ESC":
            task.cancel()
        if event.type != "TIMER" and event.type != "ESC":
            return {"PASS_THROUGH"}
        phase, fraction = task.progress()
        context.window_manager.progress_update(fraction)
        context.workspace.status_text_set(f"Shapewright export: {phase} ({fraction:.0%}); Esc cancels")
        state = task.tick()
        if state == "running":
            return {"RUNNING_MODAL"}
        self._finish(context)
        if state == "failed":
            self.report({"ERROR"}, task.message)
            return {"CANCELLED"}
        self.report({"INFO"}, task.message)
        return {"FINISHED"}


class SHAPEWRIGHT_OT_render_png(bpy.types.Operator):
    """Render the Shapewright model to a PNG with Workbench (one click)"""

    bl_idname = "shapewright.render_png"
    bl_label = "Render PNG"

    filepath: StringProperty(
        description="Where to write the PNG (// is the .blend's folder)",
        subtype="FILE_PATH",
        default="//shapewright.png",
        options=SKIP,
    )
    resolution: IntProperty(name="Width", description="Image width in pixels", default=960, min=64, max=8192)

    def execute(self, context):
        from . import render

        try:
            out = render.render_png(context, bpy.path.abspath(self.filepath), self.resolution)
        except RuntimeError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        self.report({"INFO"}, f"rendered {out}")
        return {"FINISHED"}


classes = (
    SHAPEWRIGHT_OT_add_solid,
    SHAPEWRIGHT_OT_edit_solid,
    SHAPEWRIGHT_OT_move,
    SHAPEWRIGHT_OT_duplicate,
    SHAPEWRIGHT_OT_delete,
    SHAPEWRIGHT_OT_run_script,
    SHAPEWRIGHT_OT_apply_op,
    SHAPEWRIGHT_OT_undo,
    SHAPEWRIGHT_OT_redo,
    SHAPEWRIGHT_OT_join,
    SHAPEWRIGHT_OT_leave,
    SHAPEWRIGHT_OT_undo_past_load,
    SHAPEWRIGHT_OT_redo_past_load,
    SHAPEWRIGHT_OT_export_mesh,
    SHAPEWRIGHT_OT_render_png,
)


# The core's ops emitted by the hand-written operators above, by operator.
HAND_WRITTEN = {
    "add_solid": "add_solid",
    "edit_solid": "edit_solid",
    "transform_by": "move",
    "duplicate": "duplicate",
    "delete": "delete",
}

typed_classes: tuple[type, ...] = ()
_keymaps: list = []


def register() -> None:
    global typed_classes
    typed_classes = tuple(typed_operator(spec) for spec in op_table.SPECS)
    typed_classes += tuple(generic_operator(op) for op in generic_ops())
    for cls in classes + typed_classes:
        bpy.utils.register_class(cls)
    # Ctrl-Z / Ctrl-Shift-Z continue into the saved history where
    # Blender's own undo history ends (the operators' poll is false
    # everywhere else, so the keys fall through to Blender's undo).
    kc = bpy.context.window_manager.keyconfigs.addon if bpy.context.window_manager else None
    if kc is not None:
        km = kc.keymaps.new(name="Screen", space_type="EMPTY")
        _keymaps.append((km, km.keymap_items.new("shapewright.undo_past_load", "Z", "PRESS", ctrl=True)))
        _keymaps.append(
            (km, km.keymap_items.new("shapewright.redo_past_load", "Z", "PRESS", ctrl=True, shift=True))
        )


def unregister() -> None:
    for km, kmi in _keymaps:
        km.keymap_items.remove(kmi)
    _keymaps.clear()
    for cls in reversed(classes + typed_classes):
        bpy.utils.unregister_class(cls)
