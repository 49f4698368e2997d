"""Operators: every modeling action is one op in the core's log.

Each operator builds an op (a plain dict), hands it to `history.apply`,
and reports the core's error text if the op is refused (nothing changes
then). `bl_options` has 'UNDO' wherever data changes, so that Blender's
undo step and the log's cursor move together.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import bpy
import shapewright as sw
from bpy.props import (
    BoolProperty,
    EnumProperty,
    FloatProperty,
    FloatVectorProperty,
    IntProperty,
    StringProperty,
)

from . import history, op_table, sync

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


class _ShapeProps:
    shape: EnumProperty(name="Shape", items=SHAPES, default="sphere")
    size: FloatVectorProperty(name="Size", default=(0.2, 0.2, 0.2), min=1e-4, subtype="XYZ_LENGTH")
    radius: FloatProperty(name="Radius", default=0.1, min=1e-4, subtype="DISTANCE")
    minor_radius: FloatProperty(name="Minor radius", default=0.03, min=1e-4, subtype="DISTANCE")
    height: FloatProperty(name="Height / length", default=0.2, min=0.0, subtype="DISTANCE")
    segments: IntProperty(name="Segments", default=64, min=8, max=1024)


def run_op(operator, context, op: dict) -> set[str]:
    try:
        history.apply(context.scene, op)
    except sw.ShapewrightError as e:
        operator.report({"ERROR"}, str(e))
        return {"CANCELLED"}
    return {"FINISHED"}


class SHAPEWRIGHT_OT_add_solid(_ShapeProps, bpy.types.Operator):
    """Add a parametric solid at the 3D cursor"""

    bl_idname = "shapewright.add_solid"
    bl_label = "Add Solid"
    bl_options = {"REGISTER", "UNDO"}

    location: FloatVectorProperty(name="Location", default=(0.0, 0.0, 0.0), subtype="TRANSLATION")
    use_cursor: bpy.props.BoolProperty(name="At 3D cursor", default=True)

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
        return active_id(context) is not None

    def execute(self, context):
        op = {
            "op": "edit_solid",
            "id": active_id(context),
            "shape": shape_dict(self),
            "segments": self.segments,
        }
        return run_op(self, context, op)


class SHAPEWRIGHT_OT_commit_transform(bpy.types.Operator):
    """Record the active object's Blender transform (moved with G/R/S) as an op"""

    bl_idname = "shapewright.commit_transform"
    bl_label = "Commit Transform"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return active_id(context) is not None

    def execute(self, context):
        obj = context.active_object
        loc, rot, scale = obj.matrix_world.decompose()
        op = {
            "op": "transform_by",
            "id": obj[sync.ID_PROP],
            "transform": {
                "translate": list(loc),
                "rotate": [rot.x, rot.y, rot.z, rot.w],
                "scale": list(scale),
            },
        }
        return run_op(self, context, op)


class SHAPEWRIGHT_OT_move(bpy.types.Operator):
    """Move, rotate (about Z) or scale the active object by exact amounts"""

    bl_idname = "shapewright.move"
    bl_label = "Move Object"
    bl_options = {"REGISTER", "UNDO"}

    offset: FloatVectorProperty(name="Offset", default=(0.0, 0.0, 0.0), subtype="TRANSLATION")
    angle_z: FloatProperty(name="Angle Z", default=0.0, subtype="ANGLE")
    scale: FloatProperty(name="Uniform scale", default=1.0, min=1e-3)

    @classmethod
    def poll(cls, context):
        return active_id(context) is not None

    def execute(self, context):
        h = self.angle_z / 2
        op = {
            "op": "transform_by",
            "id": active_id(context),
            "transform": {
                "translate": list(self.offset),
                "rotate": [0.0, 0.0, math.sin(h), math.cos(h)],
                "scale": [self.scale] * 3,
            },
        }
        return run_op(self, context, op)


class SHAPEWRIGHT_OT_duplicate(bpy.types.Operator):
    """Copy the active object (a new op; the copy gets the next id)"""

    bl_idname = "shapewright.duplicate"
    bl_label = "Duplicate"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return active_id(context) is not None

    def execute(self, context):
        return run_op(self, context, {"op": "duplicate", "id": active_id(context)})


class SHAPEWRIGHT_OT_delete(bpy.types.Operator):
    """Delete the active object (undoable)"""

    bl_idname = "shapewright.delete"
    bl_label = "Delete"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return active_id(context) is not None

    def execute(self, context):
        return run_op(self, context, {"op": "delete", "id": active_id(context)})


class SHAPEWRIGHT_OT_run_script(bpy.types.Operator):
    """Run an op script (.jsonl) on the scene's document"""

    bl_idname = "shapewright.run_script"
    bl_label = "Run Op Script"
    bl_options = {"REGISTER", "UNDO"}

    filepath: StringProperty(subtype="FILE_PATH")
    filter_glob: StringProperty(default="*.jsonl", options={"HIDDEN"})

    def invoke(self, context, event):
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def execute(self, context):
        try:
            text = Path(self.filepath).read_text()
        except OSError as e:
            self.report({"ERROR"}, f"cannot read {self.filepath}: {e}")
            return {"CANCELLED"}
        s = history.session(context.scene)
        before = s.cursor
        try:
            s.run_script(text)
        except sw.ShapewrightError as e:
            # A script is one undo step: roll back what it applied.
            s.seek(before)
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        history.record(context.scene, s)
        return {"FINISHED"}


class SHAPEWRIGHT_OT_apply_op(bpy.types.Operator):
    """Apply any op given as JSON (one line of an op script)"""

    bl_idname = "shapewright.apply_op"
    bl_label = "Apply Op"
    bl_options = {"REGISTER", "UNDO"}

    op_json: StringProperty(name="Op (JSON)", default="")

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


def _property(f: op_table.Field):
    """The bpy property of one op-table field."""
    label = f.label or f.name.replace("_", " ").capitalize()
    if f.kind == "target":
        return IntProperty(name=label, default=-1, min=-1, description="Object id (-1: the active object)")
    if f.kind == "int":
        return IntProperty(name=label, default=f.default)
    if f.kind == "float":
        return FloatProperty(name=label, default=f.default, precision=4)
    if f.kind == "bool":
        return BoolProperty(name=label, default=f.default)
    if f.kind == "vec3":
        return FloatVectorProperty(name=label, default=f.default, size=3)
    if f.kind == "enum":
        return EnumProperty(
            name=label, items=[(i, i.replace("_", " ").capitalize(), "") for i in f.items], default=f.default
        )
    if f.kind == "library":
        return EnumProperty(name=label, items=[(n, n, "") for n in sw.library_names()], default=f.default)
    if f.kind == "json":
        return StringProperty(name=label, default=json.dumps(f.default))
    return StringProperty(name=label, default="", description="JSON [[x, y, z], ...]; empty: the last sketch")


def op_values(operator, spec: op_table.OpSpec, context) -> dict:
    """The flat values of a typed operator, with targets and sketches
    resolved. Raises ValueError with a message for the user."""
    values = {}
    for f in spec.fields:
        raw = getattr(operator, f.name)
        if f.kind == "target" and raw < 0:
            raw = active_id(context)
            if raw is None:
                raise ValueError(f"{spec.label}: select a Shapewright object (or set {f.name})")
        try:
            v = op_table.decode(f, raw)
        except json.JSONDecodeError as e:
            raise ValueError(f"{spec.label}: {f.name} is not JSON: {e}") from e
        if f.kind == "points" and not v:
            v = json.loads(context.scene.shapewright.sketch or "[]")
            if not v and spec.op != "gc_create":
                raise ValueError(f"{spec.label}: sketch a path first (Sketch on Plane) or give {f.name}")
        values[f.name] = v
    return values


def _typed_execute(self, context):
    spec = op_table.BY_OP[self.op_name]
    try:
        op = op_table.build_op(spec, op_values(self, spec, context))
    except ValueError as e:
        self.report({"ERROR"}, str(e))
        return {"CANCELLED"}
    return run_op(self, context, op)


def typed_operator(spec: op_table.OpSpec) -> type:
    """A thin operator class for one op spec: its fields as properties,
    execute = build the op dict and apply it."""
    return type(
        f"SHAPEWRIGHT_OT_{spec.op}",
        (bpy.types.Operator,),
        {
            "__doc__": spec.description,
            "bl_idname": f"shapewright.{spec.op}",
            "bl_label": spec.label,
            "bl_options": {"REGISTER", "UNDO"},
            "op_name": spec.op,
            "__annotations__": {f.name: _property(f) for f in spec.fields},
            "execute": _typed_execute,
        },
    )


class SHAPEWRIGHT_OT_undo(bpy.types.Operator):
    """Undo through Blender's undo, which moves the op log's cursor"""

    bl_idname = "shapewright.undo"
    bl_label = "Undo"

    def execute(self, context):
        bpy.ops.ed.undo()
        return {"FINISHED"}


class SHAPEWRIGHT_OT_redo(bpy.types.Operator):
    """Redo through Blender's redo, which moves the op log's cursor"""

    bl_idname = "shapewright.redo"
    bl_label = "Redo"

    def execute(self, context):
        bpy.ops.ed.redo()
        return {"FINISHED"}


class SHAPEWRIGHT_OT_export_mesh(bpy.types.Operator):
    """Export the document's mesh (STL, OBJ or PLY, by extension)"""

    bl_idname = "shapewright.export_mesh"
    bl_label = "Export Mesh"

    filepath: StringProperty(subtype="FILE_PATH")

    def invoke(self, context, event):
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def execute(self, context):
        s = history.session(context.scene)
        try:
            s.export_mesh(self.filepath)
        except (sw.ShapewrightError, OSError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        return {"FINISHED"}


class SHAPEWRIGHT_OT_render_png(bpy.types.Operator):
    """Render the Shapewright model to a PNG with Workbench (one click)"""

    bl_idname = "shapewright.render_png"
    bl_label = "Render PNG"

    filepath: StringProperty(subtype="FILE_PATH", default="//shapewright.png")
    resolution: IntProperty(name="Width", default=960, min=64, max=8192)

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
    SHAPEWRIGHT_OT_commit_transform,
    SHAPEWRIGHT_OT_move,
    SHAPEWRIGHT_OT_duplicate,
    SHAPEWRIGHT_OT_delete,
    SHAPEWRIGHT_OT_run_script,
    SHAPEWRIGHT_OT_apply_op,
    SHAPEWRIGHT_OT_undo,
    SHAPEWRIGHT_OT_redo,
    SHAPEWRIGHT_OT_export_mesh,
    SHAPEWRIGHT_OT_render_png,
)


typed_classes: tuple[type, ...] = ()


def register() -> None:
    global typed_classes
    typed_classes = tuple(typed_operator(spec) for spec in op_table.SPECS)
    for cls in classes + typed_classes:
        bpy.utils.register_class(cls)


def unregister() -> None:
    for cls in reversed(classes + typed_classes):
        bpy.utils.unregister_class(cls)
