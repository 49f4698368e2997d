"""Operators of the History panel: stepping back and forward through
Blender's undo and the op log (labels that do not repeat Blender's own
Undo and Redo), Ctrl-Z and Ctrl-Shift-Z past the point a file was opened,
and joining and leaving a shared session (joining on a thread: the UI
never waits for a network)."""

from __future__ import annotations

import bpy
import shapewright as sw

from . import history, shared

PREFIX = "Shapewright: "


class SHAPEWRIGHT_OT_undo(bpy.types.Operator):
    """Step back: Blender's undo; where the file was opened or the document imported, the op log's"""

    bl_idname = "shapewright.undo"
    bl_label = PREFIX + "Step Back"
    short_label = "Step Back"

    def execute(self, context):
        done = history.undo_step(context)
        if done == "nothing":
            self.report({"INFO"}, "Nothing to step back to")
            return {"CANCELLED"}
        return {"FINISHED"}


class SHAPEWRIGHT_OT_redo(bpy.types.Operator):
    """Step forward: Blender's redo, and at the point the file was opened, the op log's"""

    bl_idname = "shapewright.redo"
    bl_label = PREFIX + "Step Forward"
    short_label = "Step Forward"

    def execute(self, context):
        done = history.redo_step(context)
        if done == "nothing":
            self.report({"INFO"}, "Nothing to step forward to")
            return {"CANCELLED"}
        return {"FINISHED"}


class SHAPEWRIGHT_OT_join(bpy.types.Operator):
    """Join the shared session at the address: everyone's edits reach everyone, each undoes their own"""

    bl_idname = "shapewright.join"
    bl_label = PREFIX + "Join Shared Session"
    short_label = "Join Session"

    @classmethod
    def poll(cls, context):
        scene = context.scene
        return scene is not None and shared.joined(scene) is None and scene.name not in shared.joining

    def execute(self, context):
        wm = context.window_manager.shapewright_join
        if not wm.url.strip():
            self.report({"ERROR"}, "Type the session's address first: nats://HOST:PORT/DOC")
            return {"CANCELLED"}
        try:
            shared.start_join(context.scene, wm.url, wm.name)
        except sw.ShapewrightError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        self.report({"INFO"}, f"Joining {wm.url.strip()}…")
        return {"FINISHED"}


class SHAPEWRIGHT_OT_leave(bpy.types.Operator):
    """Leave the shared session: the document stays here as your own history"""

    bl_idname = "shapewright.leave"
    bl_label = PREFIX + "Leave Shared Session"
    short_label = "Leave Session"

    @classmethod
    def poll(cls, context):
        return context.scene is not None and shared.joined(context.scene) is not None

    def execute(self, context):
        shared.leave(context.scene)
        return {"FINISHED"}


class SHAPEWRIGHT_OT_undo_past_load(bpy.types.Operator):
    """Ctrl-Z where Blender's undo history ends (after opening a file): undo the op log"""

    bl_idname = "shapewright.undo_past_load"
    bl_label = PREFIX + "Step Back (saved history)"
    bl_options = {"INTERNAL"}

    @classmethod
    def poll(cls, context):
        scene = context.scene
        if scene is None or not history.has_document(scene) or history.blender_can("undo"):
            return False
        return history.session(scene).can_undo

    def execute(self, context):
        return {"FINISHED"} if history.undo_step(context) != "nothing" else {"CANCELLED"}


class SHAPEWRIGHT_OT_redo_past_load(bpy.types.Operator):
    """Ctrl-Shift-Z at the point a file was opened: redo the op log"""

    bl_idname = "shapewright.redo_past_load"
    bl_label = PREFIX + "Step Forward (saved history)"
    bl_options = {"INTERNAL"}

    @classmethod
    def poll(cls, context):
        scene = context.scene
        if scene is None or not history.has_document(scene):
            return False
        base = history._bases.get(scene.name)
        log_first = history.at_base(scene) and base is not None and base.override is not None
        if not log_first and history.blender_can("redo"):
            return False
        return history.session(scene).can_redo

    def execute(self, context):
        return {"FINISHED"} if history.redo_step(context) != "nothing" else {"CANCELLED"}


classes = (
    SHAPEWRIGHT_OT_undo,
    SHAPEWRIGHT_OT_redo,
    SHAPEWRIGHT_OT_join,
    SHAPEWRIGHT_OT_leave,
    SHAPEWRIGHT_OT_undo_past_load,
    SHAPEWRIGHT_OT_redo_past_load,
)
