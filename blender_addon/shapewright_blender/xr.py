"""VR: our XR action map, and the modal operator its actions drive.

When a VR Scene Inspection session starts (`xr_session_start_pre`), the
action map is built from the core's bindings data (`sw.action_map()`,
every profile: Oculus Touch, Index, Vive, WMR, simple, hand interaction),
the way the bundled `viewport_vr_preview` add-on builds its own: one action
set, pose actions for grip and aim, float actions that run
`shapewright.xr_tool` modally, a haptic action. Our set is made active.

Input path: every XR action event and every timer tick goes to one
`XrDriver`, which keeps the controllers' latest poses and button values,
turns them into a core `InputFrame` (a typed value: stage space, metres;
Blender's Z-up world in the scene's units turned to OpenXR's Y-up, so the
model space is Blender's world space) and steps the core `InputSession`
(sanitizer, gestures, active tool); the command it returns (an op dict)
is already applied to the scene's log, which is then recorded and synced
like any other op. Headless tests drive the same `XrDriver` with a
recorded trace converted into this event stream.
"""

from __future__ import annotations

import time

import bpy
import shapewright as sw
from bpy.app.handlers import persistent
from bpy.props import StringProperty

from . import draw, history, units

ACTION_SET = "shapewright"
HANDS = ("/user/hand/left", "/user/hand/right")
FLOAT_ACTIONS = ("select", "grab")
STICK = {"stick_x": 0, "stick_y": 1}
BUTTON_ACTIONS = ("primary", "secondary", "menu")
# Blender's world is the model's (Z up), at the stage's origin; the core
# turns it into the OpenXR stage (Y up), as the headset host does.
PLACEMENT = sw.Placement.z_up_in_stage()


def _mpu() -> float:
    return units.metres_per_unit(bpy.context.scene)


def to_stage(location, rotation_wxyz) -> sw.Pose:
    """A Blender world pose (scene units) as a stage-space pose (metres)."""
    k = _mpu()
    w, qx, qy, qz = (float(c) for c in rotation_wxyz)
    return sw.Pose.from_z_up(tuple(float(c) * k for c in location), (qx, qy, qz, w))


def from_stage(pose: sw.Pose) -> tuple[tuple, tuple]:
    """The inverse of `to_stage`: (location, rotation wxyz) in Blender."""
    k = 1.0 / _mpu()
    p, (qx, qy, qz, w) = pose.to_z_up()
    return tuple(c * k for c in p), (w, qx, qy, qz)


def hand_index(user_path: str) -> int:
    return HANDS.index(user_path) if user_path in HANDS else 1


class XrDriver:
    """Latest controller state, turned into core input frames."""

    def __init__(self, tool: str = "object", modeler: bool = True) -> None:
        # A modeler session (every tool, the left hand's palette), as the
        # headset host runs; `modeler=False` runs one tool alone (traces
        # recorded before the palette).
        if modeler:
            self.input = sw.InputSession.modeler(tool, PLACEMENT)
        else:
            self.input = sw.InputSession(tool, PLACEMENT)
        self.saves = 0
        self.poses: list[dict] = [{}, {}]
        self.buttons: list[dict] = [{}, {}]
        self.head: sw.Pose | None = None
        self.commands: list[tuple[dict, str | None]] = []

    def set_pose(self, hand: int, kind: str, location, rotation_wxyz) -> None:
        """`kind` is "grip" or "aim"; Blender world space."""
        self.poses[hand][kind] = to_stage(location, rotation_wxyz)

    def set_head(self, location, rotation_wxyz) -> None:
        self.head = to_stage(location, rotation_wxyz)

    def on_action(self, action: str, user_path: str, state: float, released: bool) -> None:
        """One XR action event as Blender delivers it (`event.xr.action`,
        `user_path`, `state`; released on the RELEASE event)."""
        b = self.buttons[hand_index(user_path)]
        value = 0.0 if released else float(state)
        if action in FLOAT_ACTIONS:
            b[action] = value
        elif action in STICK:
            stick = list(b.get("stick", [0.0, 0.0]))
            stick[STICK[action]] = value
            b["stick"] = stick
        elif action in BUTTON_ACTIONS:
            b[action] = not released

    def frame(self, t: float) -> sw.InputFrame:
        controllers = []
        for hand in range(2):
            p = self.poses[hand]
            if not p:
                controllers.append(None)
                continue
            grip = p.get("grip", p.get("aim"))
            b = self.buttons[hand]
            controllers.append(
                sw.Controller(
                    grip,
                    p.get("aim", grip),
                    select=b.get("select", 0.0),
                    grab=b.get("grab", 0.0),
                    primary=b.get("primary", False),
                    secondary=b.get("secondary", False),
                    menu=b.get("menu", False),
                    stick=tuple(b.get("stick", (0.0, 0.0))),
                )
            )
        return sw.InputFrame(t, self.head, (controllers[0], controllers[1]))

    def step(self, scene: bpy.types.Scene, t: float) -> str | None:
        """Feeds the current state as one frame; applies and records the
        command it produces. Returns the command's JSON, if any."""
        s = history.session(scene)
        out = self.input.step(s, self.frame(t))
        self.show(s)
        for _ in range(self.input.take_save_requests()):
            # The palette's Save: the .blend (and the log's USD beside it,
            # written by the save handler) when the file has a path.
            self.saves += 1
            if bpy.data.filepath:
                bpy.ops.wm.save_mainfile()
        if out is None:
            return None
        self.commands.append(out)
        if out[1] is None:
            history.record(scene, s)
        return out[0]["op"]

    def show(self, s: sw.Session) -> None:
        """Hands the preview to the draw handlers (Blender world space)."""
        p = self.input.preview()
        rays = []
        k = 1.0 / _mpu()
        for r in p["rays"]:
            if r is not None:
                o = _stage_point(r[0])
                d = tuple(c / k for c in _stage_point(r[1]))  # a direction: no unit
                rays.append((o, d, r[2] * k, r[3]))
        draw.set_rays(rays)
        draw.set_sketch(units.to_units(bpy.context.scene, p["sketch"]))
        draw.set_palette(palette_geometry(self.input.palette()))


def _stage_point(p) -> tuple:
    return from_stage(sw.Pose(tuple(p)))[0]


def palette_geometry(view: sw.PaletteView | None) -> dict | None:
    """The core's palette draw list (stage space: layout, depth layers,
    theme) as Blender-world geometry for the draw handler: quads
    `(corners, role, rgb)` and labels `(text, origin, right_end, top, rgb)`,
    the baseline's start and the ends of its one-em right and up vectors,
    placed by the core from blf's measure of each text."""
    if view is None:
        return None
    import blf

    d = view.draw_list()
    quads = [([_stage_point(p) for p in corners], role, rgb) for corners, role, rgb in d.quads]
    size = draw.BLF_SIZE
    blf.size(0, size)
    cap = blf.dimensions(0, "H")[1] / size
    labels = []
    for label in d.labels:
        o, em = label.place(blf.dimensions(0, label.text)[0] / size, cap)
        right = [c + r * em for c, r in zip(o, label.right, strict=True)]
        up = [c + u * em for c, u in zip(o, label.up, strict=True)]
        labels.append((label.text, _stage_point(o), _stage_point(right), _stage_point(up), label.color))
    return {"quads": quads, "labels": labels}


_driver: XrDriver | None = None
_running = False


def driver(scene: bpy.types.Scene) -> XrDriver:
    global _driver
    if _driver is None:
        _driver = XrDriver(scene.shapewright.xr_tool)
    return _driver


def current_driver() -> XrDriver | None:
    """The VR driver while it runs (the modal feeding it ends with the VR
    session or Esc): after that its last frame is stale, and presence
    must not keep showing it."""
    return _driver if _running else None


def reset() -> None:
    global _driver, _running
    _driver, _running = None, False
    draw.set_rays([])


def poll_session(context, d: XrDriver) -> None:
    """Reads the controller and viewer poses from the running XR session."""
    ss = context.window_manager.xr_session_state
    if ss is None:
        return
    for hand in range(2):
        d.set_pose(
            hand,
            "grip",
            ss.controller_grip_location_get(context, hand),
            ss.controller_grip_rotation_get(context, hand),
        )
        d.set_pose(
            hand,
            "aim",
            ss.controller_aim_location_get(context, hand),
            ss.controller_aim_rotation_get(context, hand),
        )
    d.set_head(ss.viewer_pose_location, ss.viewer_pose_rotation)


class SHAPEWRIGHT_OT_xr_tool(bpy.types.Operator):
    """Run the active Shapewright tool from VR controller actions"""

    bl_idname = "shapewright.xr_tool"
    bl_label = "Shapewright: VR Tool"
    short_label = "VR Tool"

    tool: StringProperty(
        name="Tool", description="The tool to run (empty: the scene's VR tool setting)", default=""
    )

    @classmethod
    def poll(cls, context):
        return context.window_manager.xr_session_state is not None

    def _feed(self, context, event) -> None:
        d = driver(context.scene)
        if event.type == "XR_ACTION":
            xr = event.xr
            d.on_action(xr.action, xr.user_path, xr.state, event.value == "RELEASE")
        poll_session(context, d)
        d.step(context.scene, time.perf_counter() - self._t0)

    def invoke(self, context, event):
        global _running
        self._t0 = time.perf_counter()
        if _running:  # one modal instance drives everything; others forward
            self._feed(context, event)
            return {"FINISHED"}
        _running = True
        self._timer = context.window_manager.event_timer_add(1 / 90, window=context.window)
        context.window_manager.modal_handler_add(self)
        self._feed(context, event)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        global _running
        if context.window_manager.xr_session_state is None or event.type == "ESC":
            context.window_manager.event_timer_remove(self._timer)
            _running = False
            return {"FINISHED"}
        if event.type in {"XR_ACTION", "TIMER"}:
            self._feed(context, event)
            return {"RUNNING_MODAL"}
        return {"PASS_THROUGH"}


def action_map() -> dict:
    """The core's bindings data."""
    return sw.action_map()


def build_actionmap(session_state) -> object:
    """Adds our action map to a session state, from the core's data."""
    am = session_state.actionmaps.new(session_state, ACTION_SET, True)
    for item in action_map()["items"]:
        ami = am.actionmap_items.new(item["name"], True)
        for path in item["user_paths"]:
            ami.user_paths.new(path)
        kind = item["type"]
        if kind == "pose":
            ami.type = "POSE"
            ami.pose_is_controller_grip = item["name"] == "grip_pose"
            ami.pose_is_controller_aim = item["name"] == "aim_pose"
        elif kind == "vibration":
            ami.type = "VIBRATION"
        else:
            ami.type = "FLOAT"
            ami.op = "shapewright.xr_tool"
            ami.op_mode = "MODAL"
            ami.bimanual = False
        for b in item["bindings"]:
            paths = b["component_paths"]
            if None in paths:  # Blender binds one path per user path
                continue
            amb = ami.bindings.new(
                b["profile"].rsplit("/", 2)[-2] + "_" + b["profile"].rsplit("/", 1)[-1], True
            )
            amb.profile = b["profile"]
            for p in paths:
                amb.component_paths.new(p)
            if kind in ("float", "button"):
                amb.threshold = b["threshold"]
                amb.axis0_region = b["axis0_region"].upper()
    return am


@persistent
def create_actions(*_args) -> None:
    """`xr_session_start_pre`: register our action set with the session."""
    context = bpy.context
    ss = context.window_manager.xr_session_state
    if ss is None:
        return
    reset()
    am = build_actionmap(ss)
    if not ss.action_set_create(context, am):
        return
    for ami in am.actionmap_items:
        if len(ami.bindings) and ss.action_create(context, am, ami):
            for amb in ami.bindings:
                ss.action_binding_create(context, am, ami, amb)
    ss.controller_pose_actions_set(context, am.name, "grip_pose", "aim_pose")
    ss.active_action_set_set(context, am.name)


classes = (SHAPEWRIGHT_OT_xr_tool,)


def register() -> None:
    for cls in classes:
        bpy.utils.register_class(cls)
    if create_actions not in bpy.app.handlers.xr_session_start_pre:
        bpy.app.handlers.xr_session_start_pre.append(create_actions)


def unregister() -> None:
    if create_actions in bpy.app.handlers.xr_session_start_pre:
        bpy.app.handlers.xr_session_start_pre.remove(create_actions)
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
    reset()
