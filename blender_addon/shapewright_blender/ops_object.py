"""Operators on whole objects: add and edit a solid, move by exact
amounts, copy and remove (for scripts and the sidebar; Blender's own
Shift-D and X do the same, `adopt.py`), run an op script, apply any op.

Each has the core build its ops from form values (`shapewright.build_form`:
no op wire shapes here) and hands them to `history` through
`run.run_op`; refusals are reported with the core's message. Lengths are
in the scene's units (`units.py`), rotations Euler in its angle unit.
"""

from __future__ import annotations

import json
from pathlib import Path

import bpy
import shapewright as sw
from bpy.props import BoolProperty, EnumProperty, FloatVectorProperty, IntProperty, StringProperty
from mathutils import Euler

from . import history, op_table, run, schema, units

SKIP = {"SKIP_SAVE"}
PREFIX = "Shapewright: "
SHAPES = tuple((k, k.capitalize(), f"A parametric {k}") for k in sw.solid_kinds())
# The core's form of a solid: its defaults (a 10 cm sphere, 64 segments)
# and help.
SOLID_FORM = op_table.form_of("add_solid")
DEFAULT_DIMENSIONS = tuple(SOLID_FORM["dimensions"]["default"])  # metres


def _quat(euler) -> list[float]:
    q = Euler(tuple(euler)).to_quaternion()
    return [q.x, q.y, q.z, q.w]


class _ShapeProps:
    # The schema fields these properties stand for (tooltips; tests check
    # them); the core refuses what is out of range, by name.
    sw_schema = {"segments": ("add_solid", "segments")}
    shape: EnumProperty(
        name="Shape",
        items=SHAPES,
        default=SOLID_FORM["shape"]["default"],
        description=schema.info(("@SolidShape", "kind")).doc or "The solid's shape",
        options=SKIP,
    )
    dimensions: FloatVectorProperty(
        name="Dimensions",
        description=SOLID_FORM["dimensions"]["doc"],
        default=DEFAULT_DIMENSIONS,
        subtype="XYZ_LENGTH",
        unit="LENGTH",
        options=SKIP,
    )
    segments: IntProperty(
        name="Segments",
        description=schema.info(("add_solid", "segments")).tooltip("Segments around curved solids"),
        default=SOLID_FORM["segments"]["default"],
        soft_min=8,
        soft_max=1024,
        options=SKIP,
    )

    def solid_values(self, scene) -> dict:
        """The solid's form values (the core's `add_solid` / `edit_solid`
        forms), lengths in metres."""
        return {
            "shape": self.shape,
            "dimensions": units.to_metres(scene, units.snap32(list(self.dimensions))),
            "segments": self.segments,
        }


class SHAPEWRIGHT_OT_add_solid(_ShapeProps, bpy.types.Operator):
    """Add a parametric solid at the 3D cursor"""

    bl_idname = "shapewright.add_solid"
    bl_label = PREFIX + "Add Solid"
    bl_options = {"REGISTER", "UNDO"}
    short_label = "Solid"

    location: FloatVectorProperty(
        name="Location",
        description="Where the solid's centre goes, when not at the 3D cursor",
        default=(0.0, 0.0, 0.0),
        subtype="TRANSLATION",
        unit="LENGTH",
        options=SKIP,
    )
    rotation: FloatVectorProperty(
        name="Rotation",
        description="The solid's rotation",
        size=3,
        subtype="EULER",
        unit="ROTATION",
        options=SKIP,
    )
    use_cursor: BoolProperty(
        name="At 3D cursor", description="Place the solid at the 3D cursor", default=True, options=SKIP
    )

    def execute(self, context):
        scene = context.scene
        units.fill_defaults(self, scene, {"dimensions": DEFAULT_DIMENSIONS})
        loc = scene.cursor.location if self.use_cursor else self.location
        try:
            values = {
                **self.solid_values(scene),
                "location": units.to_metres(scene, units.snap32(list(loc))),
                "rotation": _quat(self.rotation),
            }
            op = sw.build_form("add_solid", values)
        except sw.ShapewrightError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        return run.run_op(self, context, op)


class SHAPEWRIGHT_OT_edit_solid(_ShapeProps, bpy.types.Operator):
    """Change the active solid's shape and sizes, keeping its placement (starts from its current ones)"""

    bl_idname = "shapewright.edit_solid"
    bl_label = PREFIX + "Edit Solid"
    bl_options = {"REGISTER", "UNDO"}
    short_label = "Edit Solid"

    @classmethod
    def poll(cls, context):
        return run.active_kind(context) == "solid"

    def execute(self, context):
        scene = context.scene
        oid = run.active_id(context)
        now = history.session(scene).form_current("edit_solid", oid)
        props = self.properties
        if not props.is_property_set("shape"):
            self.shape = now["shape"]
        if not props.is_property_set("dimensions"):
            self.dimensions = units.to_units(scene, now["dimensions"])
        if not props.is_property_set("segments"):
            self.segments = now["segments"]
        try:
            op = sw.build_form("edit_solid", {"id": oid, **self.solid_values(scene)})
        except sw.ShapewrightError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        return run.run_op(self, context, op)


class SHAPEWRIGHT_OT_move(bpy.types.Operator):
    """Move, rotate or scale the selected Shapewright objects by exact amounts (about the world origin)"""

    bl_idname = "shapewright.move"
    bl_label = PREFIX + "Move by Amounts"
    bl_options = {"REGISTER", "UNDO"}
    short_label = "Move by Amounts"

    offset: FloatVectorProperty(
        name="Offset",
        description="Translation",
        default=(0.0, 0.0, 0.0),
        subtype="TRANSLATION",
        unit="LENGTH",
        options=SKIP,
    )
    rotation: FloatVectorProperty(
        name="Rotation", description="Rotation", size=3, subtype="EULER", unit="ROTATION", options=SKIP
    )
    scale: FloatVectorProperty(
        name="Scale", description="Scale factor per axis (non-zero)", default=(1.0, 1.0, 1.0), options=SKIP
    )

    @classmethod
    def poll(cls, context):
        return bool(run.selected_ids(context))

    def execute(self, context):
        by = {
            "offset": units.to_metres(context.scene, units.snap32(list(self.offset))),
            "rotation": _quat(self.rotation),
            "scale": list(self.scale),
        }
        try:
            ops = [sw.build_form("transform_by", {"id": i, **by}) for i in run.selected_ids(context)]
        except sw.ShapewrightError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        return run.run_op(self, context, ops)


class SHAPEWRIGHT_OT_duplicate(bpy.types.Operator):
    """Copy the selected Shapewright objects in the document (Shift-D does the same)"""

    bl_idname = "shapewright.duplicate"
    bl_label = PREFIX + "Copy Objects"
    bl_options = {"REGISTER", "UNDO"}
    short_label = "Copy"

    @classmethod
    def poll(cls, context):
        return bool(run.selected_ids(context))

    def execute(self, context):
        ops = [sw.build_form("duplicate", {"id": i}) for i in run.selected_ids(context)]
        return run.run_op(self, context, ops)


class SHAPEWRIGHT_OT_delete(bpy.types.Operator):
    """Remove the selected Shapewright objects from the document (X does the same; undoable)"""

    bl_idname = "shapewright.delete"
    bl_label = PREFIX + "Remove Objects"
    bl_options = {"REGISTER", "UNDO"}
    short_label = "Remove"

    @classmethod
    def poll(cls, context):
        return bool(run.selected_ids(context))

    def execute(self, context):
        ops = [sw.build_form("delete", {"id": i}) for i in run.selected_ids(context)]
        return run.run_op(self, context, ops)


class SHAPEWRIGHT_OT_run_script(bpy.types.Operator):
    """Run an op script (.jsonl, metres) on the scene's document, as one undo step"""

    bl_idname = "shapewright.run_script"
    bl_label = PREFIX + "Run Op Script"
    bl_options = {"REGISTER", "UNDO"}
    short_label = "Run Op Script"

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
        scene = context.scene
        history.finish_pending(scene)
        s = history.session(scene)
        try:
            s.run_script(text)  # all or none
        except sw.ShapewrightError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        history.record(scene, s)
        return {"FINISHED"}


class SHAPEWRIGHT_OT_apply_op(bpy.types.Operator):
    """Apply any op given as JSON (one line of an op script, metres; undo and redo included)"""

    bl_idname = "shapewright.apply_op"
    bl_label = PREFIX + "Apply Op"
    bl_options = {"REGISTER", "UNDO"}
    short_label = "Apply Op"

    op_json: StringProperty(
        name="Op (JSON)",
        description='One op script line, e.g. {"op":"add_solid",...} or {"op":"undo"}',
        default="",
        options=SKIP,
    )

    def execute(self, context):
        # A script line is JSON text by definition (the one place the
        # add-on reads ops as text: what a person pastes).
        try:
            op = json.loads(self.op_json)
        except json.JSONDecodeError as e:
            self.report({"ERROR"}, f"op is not JSON: {e}")
            return {"CANCELLED"}
        if not isinstance(op, dict):
            self.report({"ERROR"}, "op must be a JSON object")
            return {"CANCELLED"}
        return run.run_op(self, context, op)


classes = (
    SHAPEWRIGHT_OT_add_solid,
    SHAPEWRIGHT_OT_edit_solid,
    SHAPEWRIGHT_OT_move,
    SHAPEWRIGHT_OT_duplicate,
    SHAPEWRIGHT_OT_delete,
    SHAPEWRIGHT_OT_run_script,
    SHAPEWRIGHT_OT_apply_op,
)

# The core's ops emitted by the hand-written operators above, by operator.
HAND_WRITTEN = {
    "add_solid": "add_solid",
    "edit_solid": "edit_solid",
    "transform_by": "move",
    "duplicate": "duplicate",
    "delete": "delete",
}
