"""Every operator of the add-on, registered in one place.

- `ops_object.py`: solids, exact moves, copy and remove, op scripts, any op;
- `ops_history.py`: stepping back and forward, Ctrl-Z past the load point,
  joining a shared session;
- `ops_export.py`: export (the print path on a thread, Esc cancels) and
  the one-click render;
- `forms.py`: one typed operator per op of the op table (`op_table.py`)
  and a generic one for every other op of the core's schema.

Blender's conventions: class names `SHAPEWRIGHT_OT_<op>` with
`bl_idname = "shapewright.<op>"`; `bl_options` has 'UNDO' wherever data
changes, so that Blender's undo step and the log's cursor move together;
labels are "Shapewright: ..." so F3 finds every one and none repeats one
of Blender's own; `short_label` is what the sidebar and the menus show.
"""

from __future__ import annotations

import bpy

from . import forms, op_table, ops_export, ops_history, ops_object, schema

classes = ops_object.classes + ops_history.classes + ops_export.classes
HAND_WRITTEN = ops_object.HAND_WRITTEN

typed_classes: tuple[type, ...] = ()
_keymaps: list = []


def generic_ops() -> tuple[str, ...]:
    """The core's ops that have neither a typed operator (`op_table`) nor
    a hand-written one: each gets a generic operator. Ops of kind
    `session` (`reserve_ids`) are written by shared sessions, never by a
    person, and get none."""
    return tuple(
        n
        for n in schema.OPS
        if n not in op_table.BY_OP and n not in HAND_WRITTEN and schema.OPS[n]["kind"] != "session"
    )


def short_label(idname: str) -> str:
    """What a button or menu item shows for operator `shapewright.x`."""
    cls = getattr(bpy.types, f"SHAPEWRIGHT_OT_{idname.split('.', 1)[1]}", None)
    return getattr(cls, "short_label", None) or idname


def register() -> None:
    global typed_classes
    typed_classes = tuple(forms.typed_operator(spec) for spec in op_table.SPECS)
    typed_classes += tuple(forms.generic_operator(op) for op in generic_ops())
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
