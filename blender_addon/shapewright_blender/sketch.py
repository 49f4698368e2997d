"""Desktop sketching with the mouse on a plane, so every sketch-driven op
(spines, curves, styling tool paths, warp strokes) works without a
headset.

`SHAPEWRIGHT_OT_sketch` is modal: while the left button is held, each mouse
position is cast from the view onto the sketch plane (through the 3D
cursor; XY, XZ, YZ or facing the view) and kept when it is at least
`spacing` from the last kept point. On release the target op's typed
operator runs on the points (and on the plane's normal, for ops that
take one), as one undo step; the core does the rest (RDP, template
matching, section placement: the headset's pipeline). The points are
also an operator property, so `execute` replays the same sketch (redo
panel, scripts, tests) without a mouse. The scene keeps the last sketch
for display only; no operator reads it back.
"""

from __future__ import annotations

import json

import bpy
from bpy.props import EnumProperty, FloatProperty, FloatVectorProperty, StringProperty
from mathutils import Vector, geometry

from . import draw, op_table, units

PLANES = (
    ("XY", "XY", "Horizontal plane through the 3D cursor"),
    ("XZ", "XZ", "Front plane through the 3D cursor"),
    ("YZ", "YZ", "Side plane through the 3D cursor"),
    ("VIEW", "View", "Plane through the 3D cursor facing the view"),
)
NORMALS = {"XY": (0.0, 0.0, 1.0), "XZ": (0.0, 1.0, 0.0), "YZ": (1.0, 0.0, 0.0)}
TARGETS = tuple((s.op, s.label, s.description) for s in op_table.SPECS if s.sketch)


def plane_normal(plane: str, view_dir: Vector | None) -> Vector:
    if plane == "VIEW" and view_dir is not None:
        return -view_dir.normalized()
    return Vector(NORMALS.get(plane, NORMALS["XY"]))


def project(origin: Vector, direction: Vector, point: Vector, normal: Vector) -> Vector | None:
    """Where the ray hits the plane, or None (parallel, or behind the eye)."""
    hit = geometry.intersect_line_plane(origin, origin + direction, point, normal)
    if hit is None or (hit - origin).dot(direction) < 0:
        return None
    return hit


class Stroke:
    """The kept samples of one sketch: a new point is kept when it is at
    least `spacing` from the last one."""

    def __init__(self, spacing: float) -> None:
        self.spacing = spacing
        self.points: list[Vector] = []

    def add(self, p: Vector) -> bool:
        if self.points and (p - self.points[-1]).length < self.spacing:
            return False
        self.points.append(p.copy())
        return True

    def as_lists(self) -> list[list[float]]:
        return [[p.x, p.y, p.z] for p in self.points]


class SHAPEWRIGHT_OT_sketch(bpy.types.Operator):
    """Sketch with the mouse on a plane (left drag), then apply the target op to the sketch"""

    bl_idname = "shapewright.sketch"
    bl_label = "Shapewright: Sketch on Plane"
    short_label = "Sketch"
    bl_options = {"REGISTER", "UNDO"}

    target: EnumProperty(
        name="Target", description="The op the sketch drives", items=TARGETS, default="curve_draw"
    )
    plane: EnumProperty(name="Plane", description="The plane the mouse draws on", items=PLANES, default="XY")
    spacing: FloatProperty(
        name="Spacing",
        description="Distance between kept samples (5 mm unless set)",
        default=0.005,
        min=1e-9,
        subtype="DISTANCE",
        unit="LENGTH",
    )
    points: StringProperty(
        name="Points",
        default="",
        description="The sketch, JSON [[x, y, z], ...] (a recorded stroke, scene units)",
        options={"SKIP_SAVE"},
    )
    options: StringProperty(
        name="Op options",
        description='For scripts: other fields of the target op, JSON {"name": value, ...} (scene units)',
        default="",
        options={"SKIP_SAVE", "HIDDEN"},
    )
    normal: FloatVectorProperty(
        name="Plane normal",
        description="Normal of the plane the sketch was drawn on (set by the mouse sketch)",
        default=(0.0, 0.0, 1.0),
        size=3,
        options={"SKIP_SAVE"},
    )

    def execute(self, context):
        try:
            pts = json.loads(self.points or "[]")
        except json.JSONDecodeError as e:
            self.report({"ERROR"}, f"points are not JSON: {e}")
            return {"CANCELLED"}
        if len(pts) < 2:
            self.report({"ERROR"}, "a sketch needs at least two points")
            return {"CANCELLED"}
        context.scene.shapewright.sketch = json.dumps(pts)
        run = getattr(bpy.ops.shapewright, self.target)
        spec = op_table.BY_OP[self.target]
        try:
            extra = json.loads(self.options or "{}")
        except json.JSONDecodeError as e:
            self.report({"ERROR"}, f"options are not JSON: {e}")
            return {"CANCELLED"}
        if not isinstance(extra, dict):
            self.report({"ERROR"}, "options must be a JSON object")
            return {"CANCELLED"}
        if any(f.name == "plane_normal" for f in spec.fields):
            extra.setdefault("plane_normal", tuple(self.normal))
        try:
            return run("EXEC_DEFAULT", points=json.dumps(pts), **extra)
        except RuntimeError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}

    def invoke(self, context, event):
        if context.area is None or context.area.type != "VIEW_3D":
            self.report({"ERROR"}, "sketch in a 3D Viewport")
            return {"CANCELLED"}
        units.fill_defaults(self, context.scene, {"spacing": 0.005})
        self._stroke = Stroke(self.spacing)
        self._drawing = False
        if self.plane != "VIEW":
            self.normal = NORMALS[self.plane]
        else:
            rv3d = context.region_data
            self.normal = tuple(plane_normal("VIEW", rv3d.view_rotation @ Vector((0.0, 0.0, -1.0))))
        draw.set_sketch([])
        context.window_manager.modal_handler_add(self)
        context.workspace.status_text_set(
            "Sketch: left-drag to draw, release to apply, Esc/right-click to cancel"
        )
        return {"RUNNING_MODAL"}

    def _sample(self, context, event) -> None:
        from bpy_extras import view3d_utils

        region, rv3d = context.region, context.region_data
        co = (event.mouse_region_x, event.mouse_region_y)
        origin = view3d_utils.region_2d_to_origin_3d(region, rv3d, co)
        direction = view3d_utils.region_2d_to_vector_3d(region, rv3d, co)
        normal = plane_normal(self.plane, rv3d.view_rotation @ Vector((0.0, 0.0, -1.0)))
        hit = project(origin, direction, context.scene.cursor.location, normal)
        if hit is not None and self._stroke.add(hit):
            draw.set_sketch(self._stroke.as_lists())
            context.area.tag_redraw()

    def _end(self, context) -> None:
        context.workspace.status_text_set(None)
        draw.set_sketch([])
        context.area.tag_redraw()

    def modal(self, context, event):
        if event.type in {"ESC", "RIGHTMOUSE"}:
            self._end(context)
            return {"CANCELLED"}
        if event.type == "LEFTMOUSE" and event.value == "PRESS":
            self._drawing = True
            self._sample(context, event)
        elif event.type == "MOUSEMOVE" and self._drawing:
            self._sample(context, event)
        elif event.type == "LEFTMOUSE" and event.value == "RELEASE" and self._drawing:
            self._end(context)
            self.points = json.dumps(self._stroke.as_lists())
            return self.execute(context)
        return {"RUNNING_MODAL"}


classes = (SHAPEWRIGHT_OT_sketch,)


register, unregister = bpy.utils.register_classes_factory(classes)
