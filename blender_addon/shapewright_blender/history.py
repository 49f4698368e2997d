"""One history for Blender and the core.

The core `Session` of each scene is kept in memory; the scene stores the
op log and the cursor. After any Blender undo, redo or file load, the
session is reconciled with what the scene now says:
- if the scene's ops are a prefix of the session's (an undo), the session
  only moves its cursor, keeping its redo tail;
- otherwise (a reopened file, another history) it is rebuilt by replay.
Then the Blender meshes are synced.

Besides the .blend, the log is saved as USD (`NAME.shapewright.usda`, the
core's usda with ops, cursor and snapshot) after every save, and restored
from it on load when the USD is newer than the .blend (e.g. edited since
by the OpenXR host) or the scene has no log. A timer autosaves the log to
`NAME.shapewright.autosave.usda` (or the temp dir for an unsaved file)
whenever it changed; Blender timers keep running while our modal
operators run, which is when Blender skips its own autosave.
"""

from __future__ import annotations

import os
from pathlib import Path

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


def usd_path(blend: str, suffix: str = ".shapewright.usda") -> Path | None:
    """The USD file beside a .blend (None for an unsaved file)."""
    if not blend:
        return None
    p = Path(blend)
    return p.with_name(p.stem + suffix)


def save_usd_beside(scene: bpy.types.Scene, blend: str) -> Path | None:
    path = usd_path(blend)
    if path is None or not scene.shapewright.ops:
        return None
    sw.save_usd(session(scene), str(path))
    return path


def restore_from_usd(scene: bpy.types.Scene, blend: str) -> bool:
    """Replaces the scene's log by the USD beside the .blend when that is
    newer or the scene has none. Returns whether it did."""
    path = usd_path(blend)
    if path is None or not path.is_file():
        return False
    newer = os.path.getmtime(path) > os.path.getmtime(blend) + 1e-3
    if scene.shapewright.ops and not newer:
        return False
    s = sw.load_usd(str(path))
    if s.ops_jsonl() == scene.shapewright.ops and s.cursor == scene.shapewright.cursor:
        return False
    _sessions[scene.name] = s
    record(scene, s)
    return True


_autosaved: dict[str, tuple[int, int]] = {}
AUTOSAVE_SECONDS = 10.0


def autosave_path() -> Path:
    beside = usd_path(bpy.data.filepath, ".shapewright.autosave.usda")
    return beside or Path(bpy.app.tempdir or "/tmp") / "shapewright.autosave.usda"


def autosave_tick() -> float:
    """Saves the active scene's log if it changed since the last autosave;
    returns the interval until the next call (a bpy.app.timers callback)."""
    scene = bpy.context.scene
    if scene is not None and scene.shapewright.ops:
        key = (hash(scene.shapewright.ops), scene.shapewright.cursor)
        if _autosaved.get(scene.name) != key:
            try:
                sw.save_usd(session(scene), str(autosave_path()))
                _autosaved[scene.name] = key
            except (sw.ShapewrightError, OSError) as e:
                print(f"Shapewright autosave failed: {e}")
    return AUTOSAVE_SECONDS


@persistent
def _on_load_post(*_args) -> None:
    reconcile_all()
    if bpy.data.filepath and bpy.context.scene is not None:
        try:
            restore_from_usd(bpy.context.scene, bpy.data.filepath)
        except (sw.ShapewrightError, OSError) as e:
            print(f"Shapewright: not restored from USD: {e}")


@persistent
def _on_save_post(*_args) -> None:
    if bpy.context.scene is not None:
        try:
            save_usd_beside(bpy.context.scene, bpy.data.filepath)
        except (sw.ShapewrightError, OSError) as e:
            print(f"Shapewright: USD beside the .blend not written: {e}")


_handlers = (
    (bpy.app.handlers.undo_post, _on_undo_redo),
    (bpy.app.handlers.redo_post, _on_undo_redo),
    (bpy.app.handlers.load_pre, _on_load_pre),
    (bpy.app.handlers.load_post, _on_load_post),
    (bpy.app.handlers.save_post, _on_save_post),
)


def register() -> None:
    for lst, fn in _handlers:
        if fn not in lst:
            lst.append(fn)
    if not bpy.app.timers.is_registered(autosave_tick):
        bpy.app.timers.register(autosave_tick, first_interval=AUTOSAVE_SECONDS, persistent=True)


def unregister() -> None:
    for lst, fn in _handlers:
        if fn in lst:
            lst.remove(fn)
    if bpy.app.timers.is_registered(autosave_tick):
        bpy.app.timers.unregister(autosave_tick)
    forget()
