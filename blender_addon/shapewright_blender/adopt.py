"""Blender's own editing of Shapewright objects keeps the document whole.

What a Blender user does with Blender's keys becomes an op the core
understands, recorded the way the core decides (`Session.adopt_*`: the op
is *redone* when the log's next op is that very edit, see below), or is
refused at once with a message and put back:

- G / R / S, the gizmo, the N panel, snapping, `obj.location = ...`:
  `set_transform`, the object's origin where Blender put it;
- F2, the outliner, `obj.name = ...`: `rename_object` (a name the core
  refuses is put back);
- Shift-D (and Object > Duplicate, Alt-D): `duplicate` of that object,
  then the copy's move;
- X / Delete (and the outliner's Delete): `delete`;
- Edit Mode: refused, back to Object Mode at once;
- a modifier: refused, removed at once;
- any other change of the mesh (a script, Apply > Transform, Set Origin,
  Join): refused, the core's mesh put back (objects a Join took come
  back: their deletes are refused with it).

Edit Mode, modifiers and mesh edits are refused rather than taken: a
Shapewright object's mesh is made by the core from its parameters (a
solid's sizes, a GC's sections, a sculpt's strokes), so an edit of the
triangles has no parameter to go to; the tools that change those
parameters are the Shapewright menus (Shift-A, the object's context menu,
the sidebar). To shape a mesh freely, make it a sculpt (Shapewright: New
Sculpt from a copy) or a component.

Timing. A modal transform works from the matrices it started with, and
Blender pushes its undo step only when it ends, so nothing is recorded
while one runs: the `depsgraph_update_post` handler only notices moves
and copies and starts a timer (`moves_tick`), which adopts them once no
transform modal runs in any window (`Window.modal_operators`, Blender
4.2+) and the matrices did not change since its last look (dragging an N
panel field is not a modal operator; it keeps changing them while it
lasts). Everything adopted together is one `record`, so one undo step
with Blender's own. Renames and deletes are adopted by the handler at
once (no modal is involved).

Redo instead of record. Blender pushes the undo step of an edit before
the add-on records the op, so that step holds the edit with the log
before it. When Blender's undo or redo comes back to such a step, the
edit is found again and the core redoes the log's next op when it is that
very edit (keeping the rest of the redo tail): one Ctrl-Z undoes an edit,
one Ctrl-Shift-Z redoes it, and the two never disagree.
"""

from __future__ import annotations

import bpy
import shapewright as sw
from bpy.app.handlers import persistent

from . import history, notify, sync, units

# Modal operators during which objects are being moved: every transform
# (G/R/S, the gizmo, snapping, "Transform" tools), the gizmo drag that
# starts them and the interactive "Align to Transform Target".
MOVING_MODALS = ("TRANSFORM_OT_", "GIZMOGROUP_OT_gizmo_tweak", "OBJECT_OT_transform_axis_target")
MOVES_TICK = 0.15  # seconds between looks while an edit is in progress
# A placement within this (relative) of the core's origin is the origin:
# Blender keeps matrices in float32.
TOLERANCE = 2e-6

_adopting = False
_move_seen: dict[str, tuple] = {}


def forget() -> None:
    _move_seen.clear()


def windows() -> list:
    wm = bpy.context.window_manager
    return list(wm.windows) if wm is not None else []


def modal_idname(op) -> str:
    """A running modal operator's id as `window.modal_operators` gives it
    (`TRANSFORM_OT_translate`; Python operators may say `transform.x`)."""
    name = getattr(op, "bl_idname", "") or ""
    if "." in name and "_OT_" not in name:
        mod, _, rest = name.partition(".")
        name = f"{mod.upper()}_OT_{rest}"
    return name


def transform_running(wins) -> bool:
    """Whether a modal operator that moves objects runs in any of `wins`
    (objects with `modal_operators`, Blender 4.2+)."""
    for window in wins:
        for op in getattr(window, "modal_operators", ()) or ():
            if modal_idname(op).startswith(MOVING_MODALS):
                return True
    return False


def move_decision(wins, signature: tuple, last_signature: tuple | None) -> str:
    """What the edit timer does now: `idle` (nothing to adopt), `wait` (a
    transform modal runs, or the matrices changed since the last look) or
    `record`."""
    if not signature:
        return "idle"
    if transform_running(wins) or signature != last_signature:
        return "wait"
    return "record"


def placement_matrix(obj: bpy.types.Object):
    """The object's world matrix as Blender's data says it now: from its
    location, rotation and scale (deltas included) without a parent or
    constraints, so a script's `obj.location = ...` counts before the
    depsgraph runs; else the evaluated `matrix_world`."""
    if obj.parent is None and not obj.constraints:
        return obj.matrix_basis
    return obj.matrix_world


def blender_origin(scene, obj) -> sw.Placement:
    """Where Blender has put the object's origin, in metres."""
    rows = [list(r) for r in placement_matrix(obj)]
    return sw.Placement.from_matrix(rows, units.metres_per_unit(scene))


def by_id(scene: bpy.types.Scene) -> dict[int, list[bpy.types.Object]]:
    """The scene's Shapewright objects by core id (two or more: copies)."""
    out: dict[int, list] = {}
    for obj in scene.objects:
        oid = obj.get(sync.ID_PROP)
        if oid is not None:
            out.setdefault(int(oid), []).append(obj)
    return out


def _original(objs: list) -> bpy.types.Object:
    """Of objects sharing an id, the one the add-on made (its name is the
    one the add-on gave it; copies get Blender's `.001`)."""
    for o in objs:
        if o.name == sync.shown_name(o):
            return o
    return min(objs, key=lambda o: o.name)


def copies(scene) -> list[tuple[int, bpy.types.Object]]:
    """Copies Blender made of Shapewright objects (Shift-D): (id copied,
    copy), by id."""
    out = []
    for oid, objs in sorted(by_id(scene).items()):
        if len(objs) > 1:
            first = _original(objs)
            out += [(oid, o) for o in sorted(objs, key=lambda o: o.name) if o is not first]
    return out


def moved(scene, s: sw.Session) -> list[tuple[int, bpy.types.Object]]:
    """Shapewright objects whose origin Blender has moved away from the
    core's (not recorded yet): (id, object), by id."""
    ids = set(s.object_ids())
    out = []
    for oid, objs in sorted(by_id(scene).items()):
        if len(objs) != 1 or oid not in ids:
            continue
        try:
            where = blender_origin(scene, objs[0])
        except sw.ShapewrightError:
            out.append((oid, objs[0]))  # a shear: refused when adopted
            continue
        if not where.close_to(s.object_origin(oid), TOLERANCE):
            out.append((oid, objs[0]))
    return out


def signature(scene, s: sw.Session) -> tuple:
    """What is waiting to be adopted and where, to see whether an edit is
    still changing it."""
    waiting = moved(scene, s) + copies(scene)
    return tuple((oid, obj.name, tuple(tuple(r) for r in placement_matrix(obj))) for oid, obj in waiting)


def _renames(scene, s: sw.Session) -> int:
    done = 0
    ids = set(s.object_ids())
    for oid, objs in sorted(by_id(scene).items()):
        if len(objs) != 1 or oid not in ids:
            continue
        obj = objs[0]
        shown = sync.shown_name(obj)
        if shown is None or obj.name == shown:
            continue
        try:
            s.adopt_name(oid, obj.name)
            done += 1
        except sw.ShapewrightError as e:
            notify.warn(f"{obj.name!r} is not taken as the name of object {oid}: {e}")
            obj.name = shown
    return done


def _deletes(scene, s: sw.Session) -> int:
    present = by_id(scene)
    done = 0
    for oid in s.object_ids():
        if oid not in present:
            s.adopt_delete(oid)
            done += 1
    return done


def _copies(scene, s: sw.Session) -> int:
    done = 0
    for oid, copy in copies(scene):
        if oid not in s.object_ids():
            continue
        _how, new = s.adopt_duplicate(oid)
        sync.adopt_object(copy, new)
        done += 1
    return done


def _moves(scene, s: sw.Session) -> int:
    done = 0
    for oid, obj in moved(scene, s):
        try:
            s.adopt_placement(oid, blender_origin(scene, obj))
            done += 1
        except sw.ShapewrightError as e:
            notify.warn(f"the move of {obj.name!r} is not taken: {e}")
            sync.place(scene, obj, s.object_origin(oid))
    return done


def adopt_all(scene: bpy.types.Scene, moves: bool = True) -> int:
    """Takes every Blender edit of the scene's Shapewright objects (see
    the module doc), in one `record`; returns how many ops were recorded
    or redone. `moves=False` leaves moves and copies to the timer (a
    transform may still run)."""
    global _adopting
    if _adopting or not history.has_document(scene) or scene.shapewright.import_fixup:
        return 0
    _adopting = True
    try:
        s = history.session(scene)
        done = _deletes(scene, s)
        if moves:
            done += _copies(scene, s)
        done += _renames(scene, s)
        if moves:
            done += _moves(scene, s)
            _move_seen.pop(scene.name, None)
        if done:
            history.record(scene, s)
        return done
    finally:
        _adopting = False


def moves_tick() -> float | None:
    """The edit timer (a bpy.app.timers callback): adopts each scene's
    moves and copies once `move_decision` says so; runs again while an
    edit is in progress."""
    again = False
    wins = windows()
    for scene in bpy.data.scenes:
        if not history.has_document(scene):
            continue
        sig = signature(scene, history.session(scene))
        decision = move_decision(wins, sig, _move_seen.get(scene.name))
        if decision == "idle":
            _move_seen.pop(scene.name, None)
        elif decision == "wait":
            _move_seen[scene.name] = sig
            again = True
        else:
            adopt_all(scene)
    return MOVES_TICK if again else None


def watch_moves() -> None:
    """Starts the edit timer unless it runs."""
    if not bpy.app.timers.is_registered(moves_tick):
        bpy.app.timers.register(moves_tick, first_interval=MOVES_TICK)


# Refusals: Edit Mode, modifiers, mesh edits.


def _leave_edit_mode() -> None:
    """A timer: back to Object Mode (operators cannot run in a depsgraph
    handler)."""
    obj = bpy.context.view_layer.objects.active if bpy.context.view_layer else None
    if obj is not None and obj.mode != "OBJECT" and sync.ID_PROP in obj:
        try:
            with bpy.context.temp_override(active_object=obj, object=obj):
                bpy.ops.object.mode_set(mode="OBJECT")
        except RuntimeError as e:
            print(f"Shapewright: could not leave Edit Mode: {e}")
    return None


EDIT_MODE = (
    "Edit Mode would change only Blender's copy of a Shapewright object: its mesh is made from "
    "its parameters. Use the Shapewright tools (Shift-A, the context menu, the sidebar), or "
    "make a plain copy to edit freely"
)


def guard(scene: bpy.types.Scene, depsgraph) -> bool:
    """Refuses edits of Shapewright objects' meshes (see the module doc):
    returns whether something was put back."""
    put_back = False
    active = bpy.context.view_layer.objects.active if bpy.context.view_layer else None
    if active is not None and sync.ID_PROP in active and active.mode not in ("OBJECT", "POSE"):
        notify.warn(EDIT_MODE)
        if not bpy.app.timers.is_registered(_leave_edit_mode):
            bpy.app.timers.register(_leave_edit_mode, first_interval=0.0)
        return True
    s = None
    for obj in scene.objects:
        if sync.ID_PROP not in obj or obj.type != "MESH":
            continue
        if obj.modifiers:
            names = ", ".join(m.name for m in obj.modifiers)
            obj.modifiers.clear()
            notify.warn(
                f"a modifier ({names}) on {obj.name!r} would change what Blender shows, not what "
                "prints; removed (Shapewright objects are shaped by their own tools)"
            )
            put_back = True
        if obj.mode == "OBJECT" and not sync.mesh_is_current(obj):
            s = s or history.session(scene)
            oid = int(obj[sync.ID_PROP])
            if oid in s.object_ids():
                sync.rewrite(scene, s, obj, oid)
                notify.warn(
                    f"the mesh of {obj.name!r} was changed outside Shapewright's tools; put back "
                    "(its shape comes from its parameters)"
                )
                put_back = True
    return put_back


_guarding = False


@persistent
def on_depsgraph_update(scene, depsgraph) -> None:
    global _guarding
    if scene is None or _adopting or _guarding or not history.has_document(scene):
        return
    if scene.shapewright.import_fixup:
        return
    if not (depsgraph.id_type_updated("OBJECT") or depsgraph.id_type_updated("MESH")):
        sync.follow_units(scene)
        return
    _guarding = True
    try:
        guard(scene, depsgraph)
        adopt_all(scene, moves=False)
        s = history.session(scene)
        if moved(scene, s) or copies(scene):
            watch_moves()
    finally:
        _guarding = False


def register() -> None:
    if on_depsgraph_update not in bpy.app.handlers.depsgraph_update_post:
        bpy.app.handlers.depsgraph_update_post.append(on_depsgraph_update)


def unregister() -> None:
    if on_depsgraph_update in bpy.app.handlers.depsgraph_update_post:
        bpy.app.handlers.depsgraph_update_post.remove(on_depsgraph_update)
    for timer in (moves_tick, _leave_edit_mode):
        if bpy.app.timers.is_registered(timer):
            bpy.app.timers.unregister(timer)
    forget()
