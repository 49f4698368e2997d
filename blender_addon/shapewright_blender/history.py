"""One history for Blender and the core.

The core `Session` of each scene is kept in memory; the scene stores the
op log, the cursor and a generation counter `gen` (a new value for every
recorded change). After any Blender undo, redo or file load, the session
is reconciled with what the scene now says:
- if the scene's ops are a prefix of the session's (an undo), the session
  only moves its cursor, keeping its redo tail;
- otherwise (a reopened file, another history) it is rebuilt by replay.
Then the Blender meshes are synced.

Undo past the load point. Blender's undo history starts at the state a
file was opened in (or an import brought a document in): the *base*.
Blender cannot step before it, but the log can. At the base, undo and redo
move the log's cursor *in place*: the scene's log changes while Blender's
base step still holds the state it was loaded with, so the new state is
remembered as the base's *override*, and whenever Blender's undo or redo
returns to a state of the base (same `gen`), the override is put back.
Blender's own undo steps stay untouched, so Ctrl-Z, the panel's Undo and
`{"op": "undo"}` never disagree about where the log is:
- `undo_step` / `redo_step` (the panel's buttons and Ctrl-Z / Ctrl-Shift-Z
  through the add-on's key map) use Blender's undo, except at the base,
  where they move the log in place;
- `{"op": "undo"}` / `{"op": "redo"}` lines (`shapewright.apply_op`,
  scripts, VR undo) are log steps recorded like any op, as in `.jsonl`.
A redo at the base first walks the log back up to the loaded state, then
continues into Blender's redo steps, unless an op was recorded at the
overridden base (then Blender's redo steps follow from the override).

Besides the .blend, the log is saved as USD (`NAME.shapewright.usda`, the
core's usda with ops, cursor and snapshot) after every save, and restored
from it on load when the USD is newer than the .blend (e.g. edited since
by the OpenXR host) or the scene has no log. A timer autosaves the log to
`NAME.shapewright.autosave.usda` (or the temp dir for an unsaved file)
whenever it changed; Blender timers keep running while our modal
operators run, which is when Blender skips its own autosave.

Renames made in Blender (the outliner, F2, `obj.name = ...` in a script)
become `rename_object` ops (`adopt_renames`, run by a
`depsgraph_update_post` handler, which Blender calls after any rename,
and after every undo, redo and load). Blender pushes the rename's undo
step before the handler records the op, so that step holds the new name
with the old log; when Blender's undo or redo comes back to it, the op is
found as the next op of the session's redo tail and redone (keeping the
tail), so the name and the log agree again and one Ctrl-Z undoes the
rename. A name the core refuses is put back, with the reason printed.

Moves made in Blender (G/R/S and the transform gizmo, the N panel's
fields, snapping, scripts setting `location`, `rotation_*`, `scale` or
`matrix_world`) become `transform_by` ops (`adopt_moves`). Synced meshes
are in world space under an identity matrix, so a Shapewright object
whose placement is not the identity has been moved in Blender. A modal
transform works from the matrices it started with and Blender pushes its
undo step only when it ends, so nothing may be recorded while it runs:
the `depsgraph_update_post` handler only notices the move and starts a
timer (`moves_tick`), which records once no transform modal runs in any
window (`Window.modal_operators`, Blender 4.2+) and the matrices did not
change since its last look (dragging an N-panel field is not a modal
operator; it keeps changing them while it lasts). All objects moved
together become one `record`, so one undo step. Blender's undo step of
the move holds the moved matrix with the old log, like a rename's: coming
back to it by undo or redo finds the op as the next op of the redo tail
and redoes it (keeping the tail) instead of recording it again, and a
step before the move has identity matrices, so nothing is recorded. An op
that runs (`apply`, `undo_step`, `redo_step`) first records a move still
waiting, so ops stay in the order they were made. A move the core
refuses (a non-uniform scale of a rotated object, a zero scale) is put
back, with the reason printed.

The History panel's validation is computed on a worker thread (the core
releases the GIL) on a snapshot of the session, cached by the scene's log
state, and only recomputed when that changes.
"""

from __future__ import annotations

import json
import os
import threading
from dataclasses import dataclass
from pathlib import Path

import bpy
import shapewright as sw
from bpy.app.handlers import persistent

from . import sync

_sessions: dict[str, sw.Session] = {}


@dataclass
class Base:
    """The state Blender's undo history starts at, for one scene."""

    gen: int
    ops: str
    cursor: int
    override: tuple[str, int] | None = None
    # True once an op was recorded on the overridden base: Blender's redo
    # steps then follow from the override, not from the loaded state.
    redo_follows_override: bool = False


_bases: dict[str, Base] = {}
_gen_seen = 0
# Scenes in a shared session (`shared.py`): their session is the shared
# one, whatever the scene's properties say (Blender's undo cannot take a
# shared edit back; `reconcile_all` writes the session back to the scene).
shared_sessions: dict[str, sw.Session] = {}


def session(scene: bpy.types.Scene) -> sw.Session:
    """The core session of `scene`, reconciled with the scene's log."""
    shared = shared_sessions.get(scene.name)
    if shared is not None:
        return shared
    s = _sessions.get(scene.name)
    props = scene.shapewright
    if s is None or not s.ops_jsonl().startswith(props.ops):
        s = sw.Session.from_ops(props.ops, min(props.cursor, props.ops.count("\n")))
        _sessions[scene.name] = s
    elif s.cursor != props.cursor:
        s.seek(props.cursor)
    return s


def _next_gen(scene: bpy.types.Scene) -> int:
    global _gen_seen
    _gen_seen = max(_gen_seen, scene.shapewright.gen) + 1
    return _gen_seen


def record(scene: bpy.types.Scene, s: sw.Session, in_place: bool = False) -> None:
    """Stores the session's log and cursor in the scene and syncs meshes.
    `in_place` (only at the base) keeps the base's generation and makes
    the new state the base's override."""
    props = scene.shapewright
    base = _bases.get(scene.name)
    if in_place and base is not None:
        base.override = (s.ops_jsonl(), s.cursor)
        if base.override == (base.ops, base.cursor):
            base.override = None
        base.redo_follows_override = False
    else:
        if base is not None and props.gen == base.gen and base.override is not None:
            base.redo_follows_override = True
        props.gen = _next_gen(scene)
    props.ops = s.ops_jsonl()
    props.cursor = s.cursor
    scene.update_tag()
    sync.sync_scene(scene, s)


def apply(scene: bpy.types.Scene, op: dict) -> int | None:
    """Applies one op (or an undo/redo line) to the scene's session;
    raises sw.ShapewrightError (with nothing changed) if the core refuses
    it. Returns the id the op created, if any."""
    finish_pending(scene)
    s = session(scene)
    created = sw.apply(s, op)
    record(scene, s)
    return created


def finish_pending(scene: bpy.types.Scene) -> None:
    """Finishes an import whose object work is still pending (Blender runs
    the timer that does it only after the import, in its event loop), and
    records a move made in Blender that is still waiting for its timer
    (unless a transform modal is still running)."""
    if scene.shapewright.import_fixup:
        from . import usd_hook

        usd_hook.finish_import(scene)
    if scene.shapewright.ops and not transform_running(_windows()) and moved_objects(scene):
        adopt_moves(scene)


def mark_base(scene: bpy.types.Scene) -> None:
    """The scene's current state is where Blender's undo history starts
    (after a file load or a Shapewright import)."""
    props = scene.shapewright
    _bases[scene.name] = Base(gen=props.gen, ops=props.ops, cursor=props.cursor)


def at_base(scene: bpy.types.Scene) -> bool:
    base = _bases.get(scene.name)
    return base is not None and scene.shapewright.gen == base.gen


def _blender_can(kind: str) -> bool:
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
    """One undo, as the panel's Undo and Ctrl-Z do it. Returns what moved:
    `blender` (Blender's undo), `log` (the log, at the base) or `nothing`."""
    scene = context.scene
    finish_pending(scene)
    shared = _shared_step(scene, "undo")
    if shared is not None:
        return shared
    bottom = not _blender_can("undo")
    if not bottom and not at_base(scene):
        bpy.ops.ed.undo()
        return "blender"
    s = session(scene) if scene.shapewright.ops else None
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
    """One redo, as the panel's Redo and Ctrl-Shift-Z do it (see the
    module doc). Returns `blender`, `log` or `nothing`."""
    scene = context.scene
    finish_pending(scene)
    shared = _shared_step(scene, "redo")
    if shared is not None:
        return shared
    props = scene.shapewright
    base = _bases.get(scene.name)
    s = session(scene) if props.ops else None
    if at_base(scene) and base is not None and base.override is not None and s is not None:
        below_loaded = not base.redo_follows_override
        if (below_loaded or not _blender_can("redo")) and s.can_redo:
            s.redo()
            record(scene, s, in_place=True)
            return "log"
    if _blender_can("redo"):
        bpy.ops.ed.redo()
        return "blender"
    if s is not None and s.can_redo:
        s.redo()
        if at_base(scene) or not _blender_can("undo"):
            if not at_base(scene):
                mark_base(scene)
            record(scene, s, in_place=True)
        else:
            record(scene, s)
            bpy.ops.ed.undo_push(message="Shapewright: redo")
        return "log"
    return "nothing"


def forget_session(scene: bpy.types.Scene) -> None:
    """Drops the scene's in-memory session (it is rebuilt from the scene)."""
    _sessions.pop(scene.name, None)
    _bases.pop(scene.name, None)


def forget() -> None:
    """Drops every in-memory session (e.g. before loading a file); a
    shared session is left (its document stays in the scene)."""
    shared_sessions.clear()
    _sessions.clear()
    _bases.clear()
    _validation.clear()
    _move_seen.clear()


def reconcile_all() -> None:
    from . import usd_hook

    for scene in bpy.data.scenes:
        shared = shared_sessions.get(scene.name)
        if shared is not None:
            # Blender's undo moved the scene's log; the shared session's
            # document stands (each person undoes their own edits).
            if (scene.shapewright.ops, scene.shapewright.cursor) != (shared.ops_jsonl(), shared.cursor):
                record(scene, shared)
            continue
        base = _bases.get(scene.name)
        props = scene.shapewright
        if base is not None and base.override is not None and props.gen == base.gen:
            ops, cursor = base.override
            if (props.ops, props.cursor) != (ops, cursor):
                props.ops, props.cursor = ops, cursor
        if props.import_fixup:
            usd_hook.finish_import(scene)  # an import's undo step came back
        elif props.ops or scene.name in _sessions:
            sync.sync_scene(scene, session(scene))
            adopt_renames(scene)
            adopt_moves(scene)  # no modal runs during an undo, redo or load


def renamed_objects(scene: bpy.types.Scene) -> list[tuple[int, str, bpy.types.Object]]:
    """Shapewright objects of `scene` whose Blender name is no longer the
    one the add-on gave them: (id, new name, object), by id."""
    coll = bpy.data.collections.get(sync.COLLECTION)
    if coll is None or coll.name not in scene.collection.children:
        return []
    out = []
    for obj in coll.objects:
        oid = obj.get(sync.ID_PROP)
        shown = sync.shown_name(obj)
        if oid is not None and shown is not None and obj.name != shown:
            out.append((int(oid), obj.name, obj))
    return sorted(out, key=lambda r: r[0])


def _next_op(s: sw.Session) -> dict | None:
    """The op a redo would apply (None at the end of the log)."""
    if not s.can_redo:
        return None
    lines = s.ops_jsonl().splitlines()
    return json.loads(lines[s.cursor]) if s.cursor < len(lines) else None


_adopting = False


def adopt_renames(scene: bpy.types.Scene) -> int:
    """Records Blender renames of Shapewright objects as `rename_object`
    ops (see the module doc); returns how many were recorded or redone."""
    global _adopting
    props = scene.shapewright
    if _adopting or not props.ops or props.import_fixup:
        return 0
    renamed = renamed_objects(scene)
    if not renamed:
        return 0
    _adopting = True
    try:
        s = session(scene)
        ids = set(s.object_ids())
        done = 0
        for oid, name, obj in renamed:
            if oid not in ids:
                continue
            op = {"op": "rename_object", "id": oid, "name": name}
            if _next_op(s) == op:
                s.redo()
            else:
                try:
                    sw.apply(s, op)
                except sw.ShapewrightError as e:
                    print(f"Shapewright: {name!r} not taken as the name of object {oid}: {e}")
                    obj.name = sync.shown_name(obj)
                    continue
            done += 1
        if done:
            record(scene, s)
        return done
    finally:
        _adopting = False


# Moves made in Blender (see the module doc).

# Modal operators during which objects are being moved: every transform
# (G/R/S, the gizmo, snapping, "Transform" tools), the gizmo drag that
# starts them and the interactive "Align to Transform Target".
MOVING_MODALS = ("TRANSFORM_OT_", "GIZMOGROUP_OT_gizmo_tweak", "OBJECT_OT_transform_axis_target")
MOVES_TICK = 0.15  # seconds between looks while a move is in progress
_identity = None


def _is_identity(m) -> bool:
    global _identity
    if _identity is None:
        from mathutils import Matrix

        _identity = Matrix.Identity(4)
    return m == _identity


def placement(obj: bpy.types.Object):
    """The object's world matrix as Blender's data says it now: from its
    location, rotation and scale (deltas included) without a parent or
    constraints, so a script's `obj.location = ...` counts before the
    depsgraph runs; else the evaluated `matrix_world`."""
    if obj.parent is None and not obj.constraints:
        return obj.matrix_basis
    return obj.matrix_world


def moved_objects(scene: bpy.types.Scene) -> list[tuple[int, bpy.types.Object]]:
    """Shapewright objects of `scene` whose placement is not the identity
    (moved in Blender, not recorded yet): (id, object), by id."""
    coll = bpy.data.collections.get(sync.COLLECTION)
    if coll is None or coll.name not in scene.collection.children:
        return []
    out = [
        (int(o[sync.ID_PROP]), o)
        for o in coll.objects
        if sync.ID_PROP in o and not _is_identity(placement(o))
    ]
    return sorted(out, key=lambda r: r[0])


def moves_signature(scene: bpy.types.Scene) -> tuple:
    """The moved objects and their matrices, to see whether a move is
    still changing them."""
    return tuple((oid, tuple(tuple(row) for row in placement(obj))) for oid, obj in moved_objects(scene))


def modal_idname(op) -> str:
    """A running modal operator's id as `window.modal_operators` gives it
    (`TRANSFORM_OT_translate`; Python operators may say `transform.x`)."""
    name = getattr(op, "bl_idname", "") or ""
    if "." in name and "_OT_" not in name:
        mod, _, rest = name.partition(".")
        name = f"{mod.upper()}_OT_{rest}"
    return name


def transform_running(windows) -> bool:
    """Whether a modal operator that moves objects runs in any of
    `windows` (objects with `modal_operators`, Blender 4.2+)."""
    for window in windows:
        for op in getattr(window, "modal_operators", ()) or ():
            if modal_idname(op).startswith(MOVING_MODALS):
                return True
    return False


def move_decision(windows, signature: tuple, last_signature: tuple | None) -> str:
    """What the move timer does now: `idle` (nothing moved), `wait` (a
    transform modal runs, or the matrices changed since the last look) or
    `record`."""
    if not signature:
        return "idle"
    if transform_running(windows) or signature != last_signature:
        return "wait"
    return "record"


def _windows() -> list:
    wm = bpy.context.window_manager
    return list(wm.windows) if wm is not None else []


def _transform_op(oid: int, matrix) -> dict:
    loc, rot, scale = matrix.decompose()
    return {
        "op": "transform_by",
        "id": oid,
        "transform": {
            "translate": [loc.x, loc.y, loc.z],
            "rotate": [rot.x, rot.y, rot.z, rot.w],
            "scale": [scale.x, scale.y, scale.z],
        },
    }


def _reset_placement(obj: bpy.types.Object) -> None:
    # Through `matrix_world`: it sets location, rotation and scale (under
    # a parent too) and the world matrix itself, which the depsgraph would
    # otherwise only update at its next evaluation.
    obj.matrix_world.identity()


def adopt_moves(scene: bpy.types.Scene) -> int:
    """Records the moves made in Blender of Shapewright objects as
    `transform_by` ops, all in one `record` (see the module doc); returns
    how many were recorded or redone."""
    global _adopting
    props = scene.shapewright
    if _adopting or not props.ops or props.import_fixup:
        return 0
    moved = moved_objects(scene)
    if not moved:
        return 0
    _adopting = True
    try:
        s = session(scene)
        ids = set(s.object_ids())
        done = []
        for oid, obj in moved:
            if oid not in ids:
                continue
            op = _transform_op(oid, placement(obj))
            if _next_op(s) == json.loads(json.dumps(op)):
                s.redo()
            else:
                try:
                    sw.apply(s, op)
                except sw.ShapewrightError as e:
                    print(f"Shapewright: the move of {obj.name!r} is not taken: {e}")
                    _reset_placement(obj)
                    continue
            done.append(obj)
        if done:
            record(scene, s)
            for obj in done:  # sync resets it when the mesh changed; always
                if not _is_identity(placement(obj)):
                    _reset_placement(obj)
        _move_seen.pop(scene.name, None)
        return len(done)
    finally:
        _adopting = False


_move_seen: dict[str, tuple] = {}


def moves_tick() -> float | None:
    """The move timer (a bpy.app.timers callback): records the moves of
    each scene once `move_decision` says so; runs again while a move is
    in progress."""
    again = False
    windows = _windows()
    for scene in bpy.data.scenes:
        if not scene.shapewright.ops:
            continue
        sig = moves_signature(scene)
        decision = move_decision(windows, sig, _move_seen.get(scene.name))
        if decision == "idle":
            _move_seen.pop(scene.name, None)
        elif decision == "wait":
            _move_seen[scene.name] = sig
            again = True
        else:
            adopt_moves(scene)
    return MOVES_TICK if again else None


def watch_moves() -> None:
    """Starts the move timer unless it runs."""
    if not bpy.app.timers.is_registered(moves_tick):
        bpy.app.timers.register(moves_tick, first_interval=MOVES_TICK)


@persistent
def _on_undo_redo(*_args) -> None:
    reconcile_all()


@persistent
def _on_depsgraph_update(scene, depsgraph) -> None:
    if scene is not None and scene.shapewright.ops and depsgraph.id_type_updated("OBJECT"):
        adopt_renames(scene)
        if not _adopting and moved_objects(scene):
            watch_moves()


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


# The History panel's validation: computed off the UI thread, cached by
# the log state it was computed for.
_validation: dict[str, tuple[tuple, dict | None]] = {}
_validating: dict[str, threading.Thread] = {}
validations_run = 0  # how many validations ran (tests check the cache)


def _log_key(scene: bpy.types.Scene) -> tuple:
    # `gen` changes with every recorded log; in place (at the base) only
    # the cursor moves. No hashing of the (possibly long) log per redraw.
    props = scene.shapewright
    return (props.gen, props.cursor, len(props.ops))


def _tag_redraw() -> None:
    wm = bpy.context.window_manager
    for window in wm.windows if wm else ():
        for area in window.screen.areas:
            if area.type == "VIEW_3D":
                area.tag_redraw()


def _poll_validation() -> float | None:
    if any(t.is_alive() for t in _validating.values()):
        return 0.2
    _validating.clear()
    _tag_redraw()
    return None


def validation(scene: bpy.types.Scene, wait: bool = False) -> dict | None:
    """The validation report of the scene's model, or None while it is
    being computed (a redraw follows). Recomputed only when the log or
    its cursor changed. `wait` blocks until it is known (scripts, tests)."""
    key = _log_key(scene)
    cached = _validation.get(scene.name)
    if cached is not None and cached[0] == key and cached[1] is not None:
        return cached[1]
    name = scene.name
    thread = _validating.get(name)
    if thread is None or not thread.is_alive() or (cached and cached[0] != key):
        snap = session(scene).snapshot()

        def work() -> None:
            global validations_run
            report = snap.validate()
            validations_run += 1
            if _validation.get(name, (None,))[0] == key:
                _validation[name] = (key, report)

        _validation[name] = (key, None)
        thread = threading.Thread(target=work, name="shapewright-validate", daemon=True)
        _validating[name] = thread
        thread.start()
        if not bpy.app.timers.is_registered(_poll_validation):
            bpy.app.timers.register(_poll_validation, first_interval=0.2)
    if wait:
        thread.join()
        return _validation[name][1]
    return None


@persistent
def _on_load_post(*_args) -> None:
    reconcile_all()
    if bpy.data.filepath and bpy.context.scene is not None:
        try:
            restore_from_usd(bpy.context.scene, bpy.data.filepath)
        except (sw.ShapewrightError, OSError) as e:
            print(f"Shapewright: not restored from USD: {e}")
    for scene in bpy.data.scenes:
        if scene.shapewright.ops:
            mark_base(scene)


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
    (bpy.app.handlers.depsgraph_update_post, _on_depsgraph_update),
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
    for timer in (_poll_validation, moves_tick):
        if bpy.app.timers.is_registered(timer):
            bpy.app.timers.unregister(timer)
    forget()
