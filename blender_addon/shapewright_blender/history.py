"""One history for Blender and the core.

The core `Session` of each scene is kept in memory; the scene stores the
op log and the cursor. After any Blender undo, redo or file load, the
session is reconciled with what the scene now says:
- if the scene's ops are a prefix of the session's (an undo), the session
  only moves its cursor, keeping its redo tail;
- otherwise (a reopened file, another history) it is rebuilt by replay.
Then the Blender meshes are synced.
"""

from __future__ import annotations

import bpy
import shapewright as sw
from bpy.app.handlers import persistent

from . import sync

_sessions: dict[str, sw.Session] = {}


def session(scene: bpy.types.Scene) -> sw.Session:
    """The core session of `scene`, reconciled with the scene's log."""
    s = _sessions.get(scene.name)
    props = scene.shapewright
    if s is None or not s.ops_jsonl().startswith(props.ops):
        s = sw.Session.from_ops(props.ops, min(props.cursor, props.ops.count("\n")))
        _sessions[scene.name] = s
    elif s.cursor != props.cursor:
        s.seek(props.cursor)
    return s


def record(scene: bpy.types.Scene, s: sw.Session) -> None:
    """Stores the session's log and cursor in the scene and syncs meshes."""
    scene.shapewright.ops = s.ops_jsonl()
    scene.shapewright.cursor = s.cursor
    sync.sync_scene(scene, s)


def apply(scene: bpy.types.Scene, op: dict) -> int | None:
    """Applies one op to the scene's session; raises sw.ShapewrightError
    (with nothing changed) if the core refuses it."""
    s = session(scene)
    created = sw.apply(s, op)
    record(scene, s)
    return created


def forget() -> None:
    """Drops every in-memory session (e.g. before loading a file)."""
    _sessions.clear()


def reconcile_all() -> None:
    for scene in bpy.data.scenes:
        if scene.shapewright.ops or scene.name in _sessions:
            sync.sync_scene(scene, session(scene))


@persistent
def _on_undo_redo(*_args) -> None:
    reconcile_all()


@persistent
def _on_load_pre(*_args) -> None:
    forget()


@persistent
def _on_load_post(*_args) -> None:
    reconcile_all()


_handlers = (
    (bpy.app.handlers.undo_post, _on_undo_redo),
    (bpy.app.handlers.redo_post, _on_undo_redo),
    (bpy.app.handlers.load_pre, _on_load_pre),
    (bpy.app.handlers.load_post, _on_load_post),
)


def register() -> None:
    for lst, fn in _handlers:
        if fn not in lst:
            lst.append(fn)


def unregister() -> None:
    for lst, fn in _handlers:
        if fn in lst:
            lst.remove(fn)
    forget()
