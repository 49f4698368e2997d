"""Scene properties: the op log (JSON lines) and its cursor. Both are part
of Blender's undo state and of the saved .blend."""

from __future__ import annotations

import bpy
from bpy.props import IntProperty, PointerProperty, StringProperty


class ShapewrightSceneProps(bpy.types.PropertyGroup):
    ops: StringProperty(
        name="Op log",
        description="Every recorded op, one JSON object per line",
        default="",
    )
    cursor: IntProperty(name="Cursor", description="How many ops are applied", default=0, min=0)
    sketch: StringProperty(
        name="Sketch",
        description="The last desktop or VR sketch, JSON [[x, y, z], ...] (world space)",
        default="",
    )
    xr_tool: StringProperty(
        name="VR tool",
        description="The core tool VR controller actions drive",
        default="object",
    )


classes = (ShapewrightSceneProps,)


def register() -> None:
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.shapewright = PointerProperty(type=ShapewrightSceneProps)


def unregister() -> None:
    del bpy.types.Scene.shapewright
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
