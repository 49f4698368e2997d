"""Scene properties: the key of the scene's history (op count, a hash of
those ops, the cursor and a generation counter; Blender's undo steps
restore it, `history.py`), the log's text as the .blend saves it
(written only when the file is saved, `persist.py`), and the add-on's
display settings."""

from __future__ import annotations

import bpy
import shapewright as sw
from bpy.props import BoolProperty, EnumProperty, IntProperty, PointerProperty, StringProperty

_TOOL_LABELS = {
    "object": "Objects",
    "gc": "Generalized cylinders",
    "csg": "SDF CSG",
    "curve": "Curves",
    "sculpt": "Sculpt",
}
_TOOL_HELP = {
    "object": "Place, move, scale and delete objects",
    "gc": "Paper 1 by gestures: trigger sketches, grip drags, A/X pinches, a still ray holds",
    "csg": "Paper 2: components, CSG operands, two-hand scaling",
    "curve": "Paper 3: draw and style curves, fill patches",
    "sculpt": "Paper 4: warp brushes, trigger pressure",
}

# The core's tools as enum items (built here: Blender evaluates the
# property annotations below where a comprehension cannot see this module).
_TOOL_ITEMS = [(t, _TOOL_LABELS.get(t, t.title()), _TOOL_HELP.get(t, "")) for t in sw.tool_names()]


def _parametric_toggled(props, context) -> None:
    from . import history, sync

    scene = props.id_data
    if history.has_document(scene):
        sync.sync_scene(scene, history.session(scene))


class ShapewrightSceneProps(bpy.types.PropertyGroup):
    ops: StringProperty(
        name="Op log",
        description="Every recorded op, one JSON object per line, as the file was saved",
        default="",
        options={"HIDDEN"},
    )
    op_count: IntProperty(name="Ops", description="How many ops the history holds", default=0, min=0)
    log_hash: StringProperty(
        name="Log hash",
        description="A hash of those ops (the session is rebuilt when it does not hold them)",
        default="",
        options={"HIDDEN"},
    )
    cursor: IntProperty(name="Cursor", description="How many ops are applied", default=0, min=0)
    gen: IntProperty(
        name="Generation",
        description="Changes with every recorded change of the log (history.py tells undo steps apart by it)",
        default=0,
        options={"HIDDEN"},
    )
    import_fixup: StringProperty(
        name="Import fix-up",
        description="Objects a USD import made, to adopt and to drop once Blender's importer is done (JSON)",
        default="",
        options={"HIDDEN"},
    )
    show_parametric: BoolProperty(
        name="Show parametric parts",
        description=(
            "Show the spines, key sections and skins of generalized cylinders and the curves and "
            "patches of curve networks as Blender curves and meshes (exact NURBS, kept up to date)"
        ),
        default=False,
        update=_parametric_toggled,
    )
    sketch: StringProperty(
        name="Sketch",
        description="The last desktop or VR sketch, JSON [[x, y, z], ...] (world space, scene units)",
        default="",
        options={"HIDDEN"},
    )
    xr_tool: EnumProperty(
        name="VR tool",
        description="The core tool VR controller actions drive",
        items=_TOOL_ITEMS,
        default="object",
    )


class ShapewrightJoinProps(bpy.types.PropertyGroup):
    """Where to join a shared session (on the window manager: never saved
    in the .blend, as the address may hold a password)."""

    url: StringProperty(
        name="Join",
        description=(
            "A shared session's address, nats://[USER:PASSWORD@]HOST:PORT/DOC "
            "(scripts/nats.sh starts a server; headsets join with shapewright-xr run --join)"
        ),
        default="",
    )
    name: StringProperty(
        name="Name",
        description="Your name in the shared session, shown to the others",
        default="Blender",
    )


classes = (ShapewrightSceneProps, ShapewrightJoinProps)


def register() -> None:
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.shapewright = PointerProperty(type=ShapewrightSceneProps)
    bpy.types.WindowManager.shapewright_join = PointerProperty(type=ShapewrightJoinProps)


def unregister() -> None:
    del bpy.types.WindowManager.shapewright_join
    del bpy.types.Scene.shapewright
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
