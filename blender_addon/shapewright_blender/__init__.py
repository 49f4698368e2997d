"""Shapewright for Blender: the Shapewright modeling core inside Blender.

Every edit is an op in the core's log. The log and its cursor live in the
scene (so they are saved in the .blend and restored by Blender's own undo),
and Blender's Ctrl-Z / Ctrl-Shift-Z move the log's cursor through the
`undo_post` / `redo_post` handlers in `history.py`, continuing into the
saved history past the point a file was opened. Blender's own USD export
and import carry the document with its history (`usd_hook.py`).
"""

from __future__ import annotations

if "bpy" in locals():
    import importlib

    for _m in (props, history, sync, schema, op_table, draw, shared, operators, sketch, xr, panels, usd_hook):  # noqa: F821
        importlib.reload(_m)
else:
    from . import (
        draw,
        history,
        op_table,
        operators,
        panels,
        props,
        schema,
        shared,
        sketch,
        sync,
        usd_hook,
        xr,
    )

import bpy  # noqa: E402

_modules = (props, operators, sketch, xr, draw, panels, usd_hook)


def register() -> None:
    for m in _modules:
        m.register()
    history.register()


def unregister() -> None:
    shared.unregister()
    history.unregister()
    for m in reversed(_modules):
        m.unregister()


__all__ = ["register", "unregister", "sync", "op_table", "schema", "usd_hook", "bpy"]
