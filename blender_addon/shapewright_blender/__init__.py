"""Shapewright for Blender: the Shapewright modeling core inside Blender.

Every edit is an op in the core's log. The log lives in the core's
session; the scene keeps a key of it (so Blender's own undo restores it
and the .blend saves it), and Blender's Ctrl-Z / Ctrl-Shift-Z move the
log's cursor (`history.py`), continuing into the saved history past the
point a file was opened. Blender's own keys on Shapewright objects
(G/R/S, F2, Shift-D, X) become ops, and edits of their meshes are refused
(`adopt.py`); lengths are in the scene's units (`units.py`); origins are
the core's (`sync.py`). Blender's own USD export and import carry the
document with its history (`usd_hook.py`).

Modules: props (scene settings), history (one undo), adopt (Blender's
edits), sync (core to Blender), persist (files, autosave), checks (the
printable verdict), notify (status-bar messages), units, run / forms /
current / op_table (Blender's text for the core's op forms) / ops_*
(operators), operators (their registration), menus, panels, sketch, xr
and draw (VR), shared (shared sessions), usd_hook, render.
"""

from __future__ import annotations

# Reloaded in dependency order (F3 > Reload Scripts).
_ORDER = (
    "units", "props", "notify", "sync", "history", "adopt", "persist", "checks", "schema",
    "op_table", "current", "run", "forms", "ops_object", "ops_history", "ops_export", "operators", "draw",
    "shared", "sketch", "xr", "menus", "panels", "usd_hook",
)  # fmt: skip

if "bpy" in locals():
    import importlib

    for _name in _ORDER:
        importlib.reload(globals()[_name])
else:
    from . import (
        adopt,
        checks,
        current,
        draw,
        forms,
        history,
        menus,
        notify,
        op_table,
        operators,
        ops_export,
        ops_history,
        ops_object,
        panels,
        persist,
        props,
        run,
        schema,
        shared,
        sketch,
        sync,
        units,
        usd_hook,
        xr,
    )

import bpy  # noqa: E402

_modules = (props, notify, operators, sketch, xr, draw, panels, menus, usd_hook, history, adopt, persist)


def register() -> None:
    for m in _modules:
        m.register()


def unregister() -> None:
    shared.unregister()
    checks.unregister()
    for m in reversed(_modules):
        m.unregister()


__all__ = [
    "adopt",
    "bpy",
    "checks",
    "current",
    "forms",
    "history",
    "notify",
    "op_table",
    "ops_export",
    "ops_history",
    "ops_object",
    "persist",
    "register",
    "run",
    "schema",
    "sync",
    "units",
    "unregister",
    "usd_hook",
]
