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
Long exports run on a thread of their own with Blender's progress bar and
Esc to cancel (`SHAPEWRIGHT_OT_export_mesh`).
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
    shape: EnumProperty(name="Shape", items=SHAPES, default="sphere", options=SKIP)
    size: FloatVectorProperty(
        name="Size",
        description="Box edge lengths; ellipsoid diameters (m)",
        default=(0.2, 0.2, 0.2),
        soft_min=1e-3,
        subtype="XYZ_LENGTH",
        options=SKIP,
    )
    radius: FloatProperty(
        name="Radius",
        description="Radius (m); the torus's major radius. Must be positive",
        default=0.1,
        soft_min=1e-3,
        subtype="DISTANCE",
        options=SKIP,
    )
    minor_radius: FloatProperty(
        name="Minor radius",
        description="The torus tube's radius (m), smaller than the radius",
        default=0.03,
        soft_min=1e-3,
        subtype="DISTANCE",
        options=SKIP,
    )
    height: FloatProperty(
        name="Height / length",
        description="Cylinder and cone height; capsule length between its caps (m)",
        default=0.2,
        soft_min=0.0,
        subtype="DISTANCE",
        options=SKIP,
    )
    segments: IntProperty(
        name="Segments",
        description="Segments around curved solids (8 to 1024)",
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


def _transform_op(oid: int, loc, rot, scale) -> dict:
    return {
        "op": "transform_by",
        "id": oid,
        "transform": {"translate": list(loc), "rotate": [rot.x, rot.y, rot.z, rot.w], "scale": list(scale)},
    }


class SHAPEWRIGHT_OT_commit_transform(bpy.types.Operator):
    """Record the Blender transform (moved with G/R/S) of the selected solids as ops"""

    bl_idname = "shapewright.commit_transform"
    bl_label = "Commit Transform"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return bool(selected_ids(context, "solid"))

    def execute(self, context):
        ops = []
        for oid in selected_ids(context, "solid"):
            obj = sync.object_for(context.scene, oid)
            if obj is not None:
                loc, rot, scale = obj.matrix_world.decompose()
                ops.append(_transform_op(oid, loc, rot, scale))
        return run_op(self, context, ops)


class SHAPEWRIGHT_OT_move(bpy.types.Operator):
    """Move, rotate (about Z) or scale the selected solids by exact amounts"""

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
        return bool(selected_ids(context, "solid"))

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
            for oid in selected_ids(context, "solid")
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

    filepath: StringProperty(subtype="FILE_PATH", options=SKIP)
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


def _description(f: op_table.Field, label: str) -> str:
    if f.doc:
        return f.doc
    if f.kind == "target":
        return "Object id for scripts; -1 (default) acts on the active object"
    if f.kind == "points":
        return "A sketch as JSON [[x, y, z], ...] (the Sketch operator fills it); empty: none"
    if f.kind == "json":
        return f"{label} as JSON"
    return label


def _property(f: op_table.Field):
    """The bpy property of one op-table field (not remembered between
    calls; no hard limits, so bad values reach the checks instead of being
    clamped)."""
    label = f.label or f.name.replace("_", " ").capitalize()
    desc = _description(f, label)
    if f.kind == "target":
        return IntProperty(name=label, default=-1, description=desc, options=SKIP)
    if f.kind == "int":
        return IntProperty(name=label, default=f.default, description=desc, options=SKIP)
    if f.kind == "float":
        return FloatProperty(name=label, default=f.default, precision=4, description=desc, options=SKIP)
    if f.kind == "bool":
        return BoolProperty(name=label, default=f.default, description=desc, options=SKIP)
    if f.kind == "vec3":
        return FloatVectorProperty(name=label, default=f.default, size=3, description=desc, options=SKIP)
    if f.kind == "enum":
        return EnumProperty(
            name=label,
            items=[(i, i.replace("_", " ").capitalize(), "") for i in f.items],
            default=f.default,
            description=desc,
            options=SKIP,
        )
    if f.kind == "library":
        return EnumProperty(
            name=label,
            items=[(n, n, "") for n in sw.library_names()],
            default=f.default,
            description=desc,
            options=SKIP,
        )
    if f.kind == "json":
        return StringProperty(name=label, default=json.dumps(f.default), description=desc, options=SKIP)
    return StringProperty(name=label, default="", description=desc, options=SKIP)


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
        if f.kind == "points" and not v and spec.needs_points:
            raise ValueError(f"{spec.label}: sketch it (Sketch panel) or give {f.name}")
        values[f.name] = v
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
        "__annotations__": {f.name: _property(f) for f in spec.fields},
        "execute": _typed_execute,
    }
    poll = _typed_poll(spec)
    if poll is not None:
        attrs["poll"] = poll
    return type(f"SHAPEWRIGHT_OT_{spec.op}", (bpy.types.Operator,), attrs)


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

    filepath: StringProperty(subtype="FILE_PATH", options=SKIP)
    filter_glob: StringProperty(default="*.stl;*.obj;*.ply", options={"HIDDEN"})

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

    filepath: StringProperty(subtype="FILE_PATH", default="//shapewright.png", options=SKIP)
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
    SHAPEWRIGHT_OT_commit_transform,
    SHAPEWRIGHT_OT_move,
    SHAPEWRIGHT_OT_duplicate,
    SHAPEWRIGHT_OT_delete,
    SHAPEWRIGHT_OT_run_script,
    SHAPEWRIGHT_OT_apply_op,
    SHAPEWRIGHT_OT_undo,
    SHAPEWRIGHT_OT_redo,
    SHAPEWRIGHT_OT_undo_past_load,
    SHAPEWRIGHT_OT_redo_past_load,
    SHAPEWRIGHT_OT_export_mesh,
    SHAPEWRIGHT_OT_render_png,
)


typed_classes: tuple[type, ...] = ()
_keymaps: list = []


def register() -> None:
    global typed_classes
    typed_classes = tuple(typed_operator(spec) for spec in op_table.SPECS)
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
