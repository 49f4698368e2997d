"""Messages for the person, in Blender's status bar.

Operators report their refusals themselves (`self.report`). What the
add-on refuses outside an operator (a name or move the core refuses, Edit
Mode, a modifier, a mesh edited elsewhere, a failed autosave) goes
through `warn`: it is shown by a tiny operator (`shapewright.notify`)
run from a timer, so it reaches the status bar and the Info log as any
operator's report does, and is kept in `messages` (the last 50) for
scripts and tests.
"""

from __future__ import annotations

import bpy
from bpy.props import EnumProperty, StringProperty

messages: list[str] = []
# What the notify operator reported (the status bar got it), newest last.
shown: list[str] = []
_pending: list[tuple[str, str]] = []


def warn(text: str, level: str = "WARNING") -> None:
    """Shows `text` in the status bar (soon: from a timer) and keeps it."""
    messages.append(text)
    del messages[:-50]
    print(f"Shapewright: {text}")
    _pending.append((level, text))
    if not bpy.app.timers.is_registered(flush):
        bpy.app.timers.register(flush, first_interval=0.0)


def flush() -> None:
    """Reports what `warn` queued (a timer; tests call it)."""
    while _pending:
        level, text = _pending.pop(0)
        try:
            bpy.ops.shapewright.notify(level=level, message=text)
        except (RuntimeError, AttributeError):
            pass  # unregistered meanwhile
    return None


class SHAPEWRIGHT_OT_notify(bpy.types.Operator):
    """Show a Shapewright message in the status bar"""

    bl_idname = "shapewright.notify"
    bl_label = "Shapewright: Message"
    bl_options = {"INTERNAL"}

    message: StringProperty(name="Message", description="What to tell", default="", options={"SKIP_SAVE"})
    level: EnumProperty(
        name="Level",
        description="How the status bar shows it",
        items=(("INFO", "Info", ""), ("WARNING", "Warning", ""), ("ERROR", "Error", "")),
        default="WARNING",
        options={"SKIP_SAVE"},
    )

    def execute(self, context):
        # An error report from a script-called operator raises; the
        # message is a warning either way.
        self.report({"WARNING" if self.level == "ERROR" else self.level}, self.message)
        shown.append(self.message)
        del shown[:-50]
        return {"FINISHED"}


classes = (SHAPEWRIGHT_OT_notify,)


def register() -> None:
    for cls in classes:
        bpy.utils.register_class(cls)


def unregister() -> None:
    if bpy.app.timers.is_registered(flush):
        bpy.app.timers.unregister(flush)
    _pending.clear()
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
