"""One history for Blender and the core.

The core `Session` of each scene lives in memory and holds the op log;
the scene stores only a key of it: the op count, a hash of those ops
(`Session.prefix_hash`), the cursor and a generation counter `gen` (a new
value for every recorded change). Blender's undo steps restore that key,
never a copy of the log, so recording an op costs the same at op 10 as at
op 10,000. After any Blender undo, redo or file load, the session is
reconciled with the key the scene now holds:
- if the session's first `op_count` ops hash to the key (an undo came
  back to an earlier state of the same log), the session only moves its
  cursor, keeping its redo tail;
- otherwise (a reopened file, another history) it is rebuilt from the
  log text the .blend saved (`persist.py` writes it when the file is
  saved; `props.ops`).
Then the Blender meshes are synced (`sync.py`).

Undo past the load point. Blender's undo history starts at the state a
file was opened in (or an import brought a document in): the *base*.
Blender cannot step before it, but the log can. At the base, undo and redo
move the log's cursor *in place*: the scene's key changes while Blender's
base step still holds the state it was loaded with, so the new key is
remembered as the base's *override*, and whenever Blender's undo or redo
returns to a state of the base (same `gen`), the override is put back.
Blender's own undo steps stay untouched, so Ctrl-Z, the panel's Step Back
and `{"op": "undo"}` never disagree about where the log is:
- `undo_step` / `redo_step` (the panel's buttons and Ctrl-Z / Ctrl-Shift-Z
  through the add-on's key map) use Blender's undo, except at the base,
  where they move the log in place;
- `{"op": "undo"}` / `{"op": "redo"}` (scripts, VR undo) are log steps
  recorded like any op, as in `.jsonl`.
A redo at the base first walks the log back up to the loaded state, then
continues into Blender's redo steps, unless an op was recorded at the
overridden base (then Blender's redo steps follow from the override).

Blender's own edits of Shapewright objects (G/R/S, F2, Shift-D, X) become
ops in `adopt.py`; saving, loading and autosave are `persist.py`; the
History panel's printability verdict is `checks.py`.
"""

from __future__ import annotations

from dataclasses import dataclass

import bpy
import shapewright as sw
from bpy.app.handlers import persistent

from . import sync

_sessions: dict[str, sw.Session] = {}
# Scenes in a shared session (`shared.py`): their session is the shared
# one, whatever the scene's key says (Blender's undo cannot take a shared
# edit back; `reconcile_all` writes the session's key back to the scene).
shared_sessions: dict[str, sw.Session] = {}

Key = tuple[int, str, int]  # (op count, prefix hash, cursor)


@dataclass
class Base:
    """The state Blender's undo history starts at, for one scene."""

    gen: int
    key: Key
    override: Key | None = None
    # True once an op was recorded on the overridden base: Blender's redo
    # steps then follow from the override, not from the loaded state.
    redo_follows_override: bool = False


_bases: dict[str, Base] = {}
_gen_seen = 0


def key_of(scene: bpy.types.Scene) -> Key:
    props = scene.shapewright
    return (props.op_count, props.log_hash, props.cursor)


def session_key(s: sw.Session) -> Key:
    return (len(s), s.prefix_hash(len(s)) or "", s.cursor)


def has_document(scene: bpy.types.Scene) -> bool:
    """Whether the scene has a Shapewright document (ops, or a session)."""
    props = scene.shapewright
    return bool(props.op_count or props.ops or scene.name in _sessions or scene.name in shared_sessions)


def _holds(s: sw.Session, count: int, digest: str) -> bool:
    """Whether session `s` holds the history of `count` ops hashing to
    `digest` (an empty key: no history yet)."""
    if not digest:
        return count == 0
    return s.prefix_hash(count) == digest


def _rebuild(scene: bpy.types.Scene) -> sw.Session:
    """The scene's session from the log text its file saved."""
    props = scene.shapewright
    if not props.ops:
        return sw.Session()
    s = sw.Session.from_ops(props.ops, min(props.cursor, props.ops.count("\n")))
    if props.log_hash and not _holds(s, props.op_count, props.log_hash):
        print(
            f"Shapewright: {scene.name}: the saved log does not hold the history this state "
            "names (the file was saved before it); using the saved log"
        )
    return s


# Sessions a scene left behind (the newest first): undo past the load
# point can make Blender's base step hold the loaded log while a newer
# branch was recorded after it; going back and forth between the two finds
# each here instead of replaying the saved text.
_previous: dict[str, list[sw.Session]] = {}
KEEP_PREVIOUS = 4


def session(scene: bpy.types.Scene) -> sw.Session:
    """The core session of `scene`, reconciled with the scene's key."""
    shared = shared_sessions.get(scene.name)
    if shared is not None:
        return shared
    s = _sessions.get(scene.name)
    props = scene.shapewright
    if s is None or not _holds(s, props.op_count, props.log_hash):
        older = _previous.setdefault(scene.name, [])
        found = next((o for o in older if _holds(o, props.op_count, props.log_hash)), None)
        if s is not None:
            older.insert(0, s)
        if found is not None:
            older.remove(found)
        s = found or _rebuild(scene)
        del older[KEEP_PREVIOUS:]
        _sessions[scene.name] = s
    cursor = min(props.cursor, len(s))
    if s.cursor != cursor:
        s.seek(cursor)
    return s


def _next_gen(scene: bpy.types.Scene) -> int:
    global _gen_seen
    _gen_seen = max(_gen_seen, scene.shapewright.gen) + 1
    return _gen_seen


def write_key(scene: bpy.types.Scene, key: Key) -> None:
    props = scene.shapewright
    props.op_count, props.log_hash, props.cursor = key


def record(scene: bpy.types.Scene, s: sw.Session, in_place: bool = False) -> None:
    """Stores the session's key in the scene and syncs meshes. `in_place`
    (only at the base) keeps the base's generation and makes the new
    state the base's override."""
    props = scene.shapewright
    base = _bases.get(scene.name)
    key = session_key(s)
    if in_place and base is not None:
        base.override = None if key == base.key else key
        base.redo_follows_override = False
    else:
        if base is not None and props.gen == base.gen and base.override is not None:
            base.redo_follows_override = True
        props.gen = _next_gen(scene)
    write_key(scene, key)
    scene.update_tag()
    sync.sync_scene(scene, s)
    from . import persist

    persist.changed(scene, s)


def apply(scene: bpy.types.Scene, op: dict | sw.Built) -> int | None:
    """Applies one op (or an undo/redo line, or a form's built ops, all or
    none) to the scene's session;
    raises sw.ShapewrightError (with nothing changed) if the core refuses
    it. Returns the id the op created, if any."""
    finish_pending(scene)
    s = session(scene)
    created = s.apply(op)
    record(scene, s)
    return created


def apply_all(scene: bpy.types.Scene, ops: list[dict | sw.Built]) -> int | None:
    """Applies ops all or none (see `Session.apply_all`), as one record."""
    finish_pending(scene)
    s = session(scene)
    created = s.apply_all(ops)
    record(scene, s)
    return created


def finish_pending(scene: bpy.types.Scene) -> None:
    """Finishes an import whose object work is still pending (Blender runs
    the timer that does it only after the import, in its event loop), and
    records Blender edits still waiting for their timer (unless a
    transform modal is still running)."""
    if scene.shapewright.import_fixup:
        from . import usd_hook

        usd_hook.finish_import(scene)
    if has_document(scene):
        from . import adopt

        if not adopt.transform_running(adopt.windows()):
            adopt.adopt_all(scene)


def mark_base(scene: bpy.types.Scene) -> None:
    """The scene's current state is where Blender's undo history starts
    (after a file load or a Shapewright import)."""
    _bases[scene.name] = Base(gen=scene.shapewright.gen, key=key_of(scene))


def at_base(scene: bpy.types.Scene) -> bool:
    base = _bases.get(scene.name)
    return base is not None and scene.shapewright.gen == base.gen


def blender_can(kind: str) -> bool:
    op = bpy.ops.ed.undo if kind == "undo" else bpy.ops.ed.redo
    try:
        return bool(op.poll())
    except RuntimeError:
        return False


def _shared_step(scene: bpy.types.Scene, kind: str) -> str | None:
    """In a shared session, undo and redo take back this person's own
    edits (the session's rule), never Blender's undo steps. None outside
    one."""
    s = shared_sessions.get(scene.name)
    if s is None:
        return None
    can = s.can_undo if kind == "undo" else s.can_redo
    if not can:
        return "nothing"
    s.undo() if kind == "undo" else s.redo()
    record(scene, s)
    return "log"


def undo_step(context) -> str:
    """One undo, as the panel's Step Back and Ctrl-Z do it. Returns what
    moved: `blender` (Blender's undo), `log` (the log, at the base) or
    `nothing`."""
    scene = context.scene
    finish_pending(scene)
    shared = _shared_step(scene, "undo")
    if shared is not None:
        return shared
    bottom = not blender_can("undo")
    if not bottom and not at_base(scene):
        bpy.ops.ed.undo()
        return "blender"
    s = session(scene) if has_document(scene) else None
    if s is not None and s.can_undo:
        if bottom and not at_base(scene):
            mark_base(scene)  # e.g. a file opened before the add-on was enabled
        s.undo()
        record(scene, s, in_place=True)
        return "log"
    if not bottom:
        bpy.ops.ed.undo()  # the log is at its start: undo what brought it in
        return "blender"
    return "nothing"


def redo_step(context) -> str:
    """One redo, as the panel's Step Forward and Ctrl-Shift-Z do it (see
    the module doc). Returns `blender`, `log` or `nothing`."""
    scene = context.scene
    finish_pending(scene)
    shared = _shared_step(scene, "redo")
    if shared is not None:
        return shared
    base = _bases.get(scene.name)
    s = session(scene) if has_document(scene) else None
    if at_base(scene) and base is not None and base.override is not None and s is not None:
        below_loaded = not base.redo_follows_override
        if (below_loaded or not blender_can("redo")) and s.can_redo:
            s.redo()
            record(scene, s, in_place=True)
            return "log"
    if blender_can("redo"):
        bpy.ops.ed.redo()
        return "blender"
    if s is not None and s.can_redo:
        s.redo()
        if at_base(scene) or not blender_can("undo"):
            if not at_base(scene):
                mark_base(scene)
            record(scene, s, in_place=True)
        else:
            record(scene, s)
            bpy.ops.ed.undo_push(message="Shapewright: redo")
        return "log"
    return "nothing"


def adopt_session(scene: bpy.types.Scene, s: sw.Session) -> None:
    """Makes `s` the scene's session (a load or an import brought it)."""
    _sessions[scene.name] = s


def forget_session(scene: bpy.types.Scene) -> None:
    """Drops the scene's in-memory session (it is rebuilt from the scene)."""
    _sessions.pop(scene.name, None)
    _previous.pop(scene.name, None)
    _bases.pop(scene.name, None)


def forget() -> None:
    """Drops every in-memory session (e.g. before loading a file)."""
    shared_sessions.clear()
    _sessions.clear()
    _previous.clear()
    _bases.clear()
    from . import adopt, checks

    checks.forget()
    adopt.forget()


def reconcile_all() -> None:
    """After Blender's undo, redo or a load: every scene's session follows
    its key, the meshes follow the session, then Blender's own edits that
    the state holds are taken (`adopt.adopt_all`)."""
    from . import adopt, usd_hook

    for scene in bpy.data.scenes:
        shared = shared_sessions.get(scene.name)
        if shared is not None:
            # Blender's undo moved the scene's key; the shared session's
            # document stands (each person undoes their own edits).
            if key_of(scene) != session_key(shared):
                record(scene, shared)
            continue
        base = _bases.get(scene.name)
        props = scene.shapewright
        overridden = base is not None and base.override is not None and props.gen == base.gen
        if overridden and key_of(scene) != base.override:
            write_key(scene, base.override)
        if props.import_fixup:
            usd_hook.finish_import(scene)  # an import's undo step came back
        elif has_document(scene):
            # Blender's edit first (a step that holds it with the log
            # before it redoes the op), then the meshes follow the log. At
            # an overridden base, Blender's objects are the loaded state,
            # not an edit: they only follow the log.
            if not overridden:
                adopt.adopt_all(scene)
            sync.sync_scene(scene, session(scene))


def tag_redraw() -> None:
    wm = bpy.context.window_manager
    for window in wm.windows if wm else ():
        for area in window.screen.areas if window.screen else ():
            if area.type == "VIEW_3D":
                area.tag_redraw()


@persistent
def _on_undo_redo(*_args) -> None:
    reconcile_all()


_handlers = (
    (bpy.app.handlers.undo_post, _on_undo_redo),
    (bpy.app.handlers.redo_post, _on_undo_redo),
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
