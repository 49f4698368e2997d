"""The document on disk: in the .blend, beside it as USD, and autosaved.

- Saving the .blend writes the log's text into the scene (`props.ops`,
  the one time the whole log is serialized) just before Blender writes
  the file (`save_pre`), and the core's usda (`NAME.shapewright.usda`:
  ops, cursor, snapshot) beside it afterwards (`save_post`).
- Opening a .blend rebuilds each scene's session from that text, or from
  the USD beside it when that is newer (e.g. edited since by the headset
  host) or the scene has none (`load_post`); the loaded state is where
  Blender's undo history starts (`history.mark_base`).
- Autosave is the core's policy (`shapewright.Autosaver`, the
  `shapewright_usd::Autosaver` the headset host uses: after every change,
  or once unsaved changes are 30 s old) to
  `NAME.shapewright.autosave.usda` (the temp dir for an unsaved file). The
  save runs on a thread of its own on a copy of the log, so a big
  document's edit never waits for it; a timer collects finished saves
  (Blender timers keep running while our modal operators run, which is
  when Blender skips its own autosave).
"""

from __future__ import annotations

import os
from pathlib import Path

import bpy
import shapewright as sw
from bpy.app.handlers import persistent

from . import history, notify

AUTOSAVE_TICK = 5.0  # seconds between looks at the time trigger
_autosavers: dict[str, sw.Autosaver] = {}


def usd_path(blend: str, suffix: str = ".shapewright.usda") -> Path | None:
    """The USD file beside a .blend (None for an unsaved file)."""
    if not blend:
        return None
    p = Path(blend)
    return p.with_name(p.stem + suffix)


def autosave_path() -> Path:
    beside = usd_path(bpy.data.filepath, ".shapewright.autosave.usda")
    return beside or Path(bpy.app.tempdir or "/tmp") / "shapewright.autosave.usda"


def autosaver(scene: bpy.types.Scene) -> sw.Autosaver:
    """The scene's autosaver (a new one when the file's path changed)."""
    path = autosave_path()
    saver = _autosavers.get(scene.name)
    if saver is None or Path(saver.path) != path:
        if saver is not None:
            saver.wait()
        saver = _autosavers[scene.name] = sw.Autosaver(str(path))
    return saver


def changed(scene: bpy.types.Scene, s: sw.Session) -> None:
    """A recorded change of the scene's document (`history.record`)."""
    try:
        autosaver(scene).changed(s)
    except sw.ShapewrightError as e:
        notify.warn(f"autosave not started: {e}")


def autosave_tick() -> float:
    """Collects finished autosaves and starts those the time trigger asks
    for (a bpy.app.timers callback); never waits for a save."""
    for name, saver in list(_autosavers.items()):
        scene = bpy.data.scenes.get(name)
        if scene is None or not history.has_document(scene):
            continue
        try:
            saver.tick(history.session(scene))
        except sw.ShapewrightError as e:
            notify.warn(f"autosave not started: {e}")
        if saver.last_error:
            notify.warn(f"autosave failed: {saver.last_error}")
    return AUTOSAVE_TICK


def save_usd_beside(scene: bpy.types.Scene, blend: str) -> Path | None:
    path = usd_path(blend)
    if path is None or not history.has_document(scene):
        return None
    sw.save_usd(history.session(scene), str(path))
    return path


def restore_from_usd(scene: bpy.types.Scene, blend: str) -> bool:
    """Replaces the scene's log by the USD beside the .blend when that is
    newer or the scene has none. Returns whether it did."""
    path = usd_path(blend)
    if path is None or not path.is_file():
        return False
    newer = os.path.getmtime(path) > os.path.getmtime(blend) + 1e-3
    if history.has_document(scene) and not newer:
        return False
    s = sw.load_usd(str(path))
    if history.has_document(scene) and history.session_key(s) == history.key_of(scene):
        return False
    history.adopt_session(scene, s)
    history.record(scene, s)
    return True


@persistent
def _on_save_pre(*_args) -> None:
    # The whole log's text, once per save: the .blend keeps the history.
    for scene in bpy.data.scenes:
        if history.has_document(scene):
            text = history.session(scene).ops_jsonl()
            if scene.shapewright.ops != text:
                scene.shapewright.ops = text


@persistent
def _on_save_post(*_args) -> None:
    if bpy.context.scene is not None:
        try:
            save_usd_beside(bpy.context.scene, bpy.data.filepath)
        except (sw.ShapewrightError, OSError) as e:
            notify.warn(f"USD beside the .blend not written: {e}")


@persistent
def _on_load_pre(*_args) -> None:
    for saver in _autosavers.values():
        saver.wait()
    _autosavers.clear()
    history.forget()


@persistent
def _on_load_post(*_args) -> None:
    history.reconcile_all()
    if bpy.data.filepath and bpy.context.scene is not None:
        try:
            restore_from_usd(bpy.context.scene, bpy.data.filepath)
        except (sw.ShapewrightError, OSError) as e:
            notify.warn(f"not restored from USD: {e}")
    for scene in bpy.data.scenes:
        if history.has_document(scene):
            history.mark_base(scene)


_handlers = (
    (bpy.app.handlers.load_pre, _on_load_pre),
    (bpy.app.handlers.load_post, _on_load_post),
    (bpy.app.handlers.save_pre, _on_save_pre),
    (bpy.app.handlers.save_post, _on_save_post),
)


def register() -> None:
    for lst, fn in _handlers:
        if fn not in lst:
            lst.append(fn)
    if not bpy.app.timers.is_registered(autosave_tick):
        bpy.app.timers.register(autosave_tick, first_interval=AUTOSAVE_TICK, persistent=True)


def unregister() -> None:
    for lst, fn in _handlers:
        if fn in lst:
            lst.remove(fn)
    if bpy.app.timers.is_registered(autosave_tick):
        bpy.app.timers.unregister(autosave_tick)
    for saver in _autosavers.values():
        saver.wait()
    _autosavers.clear()
