"""Shared sessions in Blender (issue 23): the History panel's Join field.

A scene joins a session with `tls://HOST:PORT/DOC` (the same address
headsets use with `shapewright-xr run --join`; `nats://` on a server of
this machine without TLS). The person's user, password and the team's CA
certificate come from their credentials file, named by the environment
variable SHAPEWRIGHT_SESSION_CREDENTIALS (or given to `join`), never
from the address: it shows in the panel and in logs (issue 35). While
joined:
- the scene's core session is the shared one (`history.session`): the
  panel's operators apply to it, and their edits reach everyone;
- Undo and Redo (the panel's buttons and the add-on's Ctrl-Z) take back
  this person's own latest edit, not the last edit in the session;
  Blender's own undo steps cannot change the shared document: after one,
  the scene is synced from the session again;
- a timer pumps the connection every 50 ms: others' edits arrive, ours go
  out, refused edits and lost connections are reported in the status bar;
- the others show as empties in their colour in the collection
  "Shapewright people": a sphere at the head, axes at each hand (from
  their presence, in model space, which is Blender's world space here);
- Blender sends its own presence: in Blender's VR session the viewer's
  head, and always the selected Shapewright object.
Leaving keeps the document as it is, as a single-user history.

Joining never blocks the UI: the connection is made on a thread of its
own (`start_join`; the core releases the GIL while it connects), and a
timer takes the joined session over when it is ready, or reports why it
could not be (an unreachable host, a refusal) in the status bar.
Presence crosses as typed values (`shapewright.Presence`, model space,
metres; Blender's side in the scene's units).
"""

from __future__ import annotations

import os
import threading
import time

import bpy
import shapewright as sw

from . import history, notify, sync, units

TICK = 0.05
# The environment variable naming a person's credentials file (the core
# reads it when Join is pressed).
CREDENTIALS_ENV = "SHAPEWRIGHT_SESSION_CREDENTIALS"
PEOPLE = "Shapewright people"
# Blender sends its presence at most this often (seconds): the core's
# rate, the headset host's too.
PRESENCE_EVERY = 1.0 / sw.PRESENCE_HZ

_last_presence = 0.0
# What the last pumps said, per scene (shown in the panel).
status: dict[str, str] = {}


def joined(scene: bpy.types.Scene) -> sw.Session | None:
    """The scene's shared session, if it is in one."""
    return history.shared_sessions.get(scene.name)


def join(scene: bpy.types.Scene, url: str, name: str, credentials: str | None = None) -> list[str]:
    """Joins `url` as `name` on this thread (scripts, tests); the scene's
    document (if any) starts an empty session. `credentials` names the
    person's credentials file (default: the one
    SHAPEWRIGHT_SESSION_CREDENTIALS names); with a user in it, that user is
    who they are in the session. Raises sw.ShapewrightError (SessionError)
    with the reason when the server cannot be reached or refuses, or the
    address holds a password. The UI uses `start_join`."""
    _use_credentials(credentials)
    if joined(scene) is not None:
        raise sw.SessionError(f"already in {joined(scene).shared_url}; leave it first")
    history.finish_pending(scene)
    opened = history.session(scene) if history.has_document(scene) else None
    s, messages = sw.Session.join(url.strip(), name.strip() or "Blender", opened=opened)
    _take(scene, s)
    return messages


def _take(scene: bpy.types.Scene, s: sw.Session) -> None:
    history.shared_sessions[scene.name] = s
    history.record(scene, s)
    status[scene.name] = "online"
    if not bpy.app.timers.is_registered(tick):
        bpy.app.timers.register(tick, first_interval=TICK, persistent=True)


# Joins under way: scene name -> (thread, result list).
joining: dict[str, tuple[threading.Thread, list]] = {}


def _use_credentials(credentials: str | None) -> None:
    if credentials:
        os.environ[CREDENTIALS_ENV] = os.path.abspath(bpy.path.abspath(credentials))


def start_join(
    scene: bpy.types.Scene, url: str, name: str, credentials: str | None = None
) -> None:
    """Starts joining on a thread of its own; `finish_joins` (a timer)
    takes the session over when it is ready. Returns at once.
    `credentials`: as for `join`."""
    if joined(scene) is not None:
        raise sw.SessionError(f"already in {joined(scene).shared_url}; leave it first")
    if scene.name in joining:
        raise sw.SessionError("already joining; wait for it or press Leave")
    history.finish_pending(scene)
    _use_credentials(credentials)
    opened = history.session(scene).snapshot() if history.has_document(scene) else None
    result: list = []

    def work() -> None:
        try:
            result.append(sw.Session.join(url.strip(), name.strip() or "Blender", opened=opened))
        except sw.ShapewrightError as e:
            result.append(e)

    thread = threading.Thread(target=work, name="shapewright-join", daemon=True)
    joining[scene.name] = (thread, result)
    status[scene.name] = "joining"
    thread.start()
    if not bpy.app.timers.is_registered(finish_joins):
        bpy.app.timers.register(finish_joins, first_interval=0.1)


def finish_joins() -> float | None:
    """The timer of `start_join`: takes over each join that finished."""
    for name, (thread, result) in list(joining.items()):
        if thread.is_alive():
            continue
        del joining[name]
        scene = bpy.data.scenes.get(name)
        out = result[0] if result else sw.SessionError("the join thread stopped")
        if isinstance(out, Exception):
            status.pop(name, None)
            notify.warn(f"could not join: {out}")
        elif scene is not None:
            s, messages = out
            _take(scene, s)
            for m in messages:
                notify.warn(m, "INFO")
        history.tag_redraw()
    return 0.1 if joining else None


def leave(scene: bpy.types.Scene) -> None:
    """Leaves the session: the document stays, as single-user history."""
    s = history.shared_sessions.pop(scene.name, None)
    status.pop(scene.name, None)
    if s is None:
        return
    local = sw.Session.from_ops(s.ops_jsonl(), s.cursor)
    history.forget_session(scene)
    history.adopt_session(scene, local)
    history.record(scene, local)
    _clear_people(scene)


def pump(scene: bpy.types.Scene) -> bool:
    """Takes in others' edits and sends ours once; returns whether the
    document changed (then the scene is synced)."""
    s = joined(scene)
    if s is None:
        return False
    r = s.pump()
    for m in r["messages"]:
        print(f"Shapewright: shared session: {m}")
    for e in r["errors"]:
        print(f"Shapewright: shared session: {e}")
    status[scene.name] = (
        "view only" if r["view_only"] else "online" if r["online"] else "offline: edits are kept"
    )
    if r["changed"]:
        history.record(scene, s)
    _send_presence(scene, s)
    _show_people(scene, s)
    return bool(r["changed"])


def tick() -> float | None:
    """The timer: pumps every joined scene."""
    scenes = [bpy.data.scenes.get(n) for n in list(history.shared_sessions)]
    if not scenes:
        return None
    changed = False
    for scene in scenes:
        if scene is not None:
            changed |= pump(scene)
    if changed:
        history.tag_redraw()
    return TICK


def _pose(scene, location, rotation) -> sw.Pose:
    q = rotation  # Blender's (w, x, y, z)
    p = units.to_metres(scene, [float(c) for c in location])
    return sw.Pose(p, (float(q[1]), float(q[2]), float(q[3]), float(q[0])))


def presence(scene: bpy.types.Scene) -> sw.Presence:
    """This person's presence: in Blender's VR session, the core's input
    session's last frame (head and both hands in model space, as the
    headset host sends); else the viewer's head alone, if there is one.
    The active Shapewright object is the selection."""
    from . import xr

    obj = bpy.context.view_layer.objects.active if bpy.context.view_layer else None
    selected = int(obj[sync.ID_PROP]) if obj is not None and sync.ID_PROP in obj else None
    d = xr.current_driver()
    p = d.input.presence(selected) if d is not None else None
    if p is not None:
        return p
    head = None
    state = getattr(bpy.context.window_manager, "xr_session_state", None)
    if state is not None:
        head = _pose(scene, state.viewer_pose_location, state.viewer_pose_rotation)
    return sw.Presence(head=head, selected=selected)


def _send_presence(scene: bpy.types.Scene, s: sw.Session) -> None:
    global _last_presence
    now = time.monotonic()
    if now - _last_presence < PRESENCE_EVERY:
        return
    _last_presence = now
    try:
        s.send_presence(presence(scene))
    except sw.ShapewrightError as e:
        print(f"Shapewright: presence not sent: {e}")


def _empty(coll, name: str, display: str, size: float, colour) -> bpy.types.Object:
    obj = bpy.data.objects.get(name)
    if obj is None:
        obj = bpy.data.objects.new(name, None)
        coll.objects.link(obj)
    obj.empty_display_type = display
    obj.empty_display_size = size
    obj.color = (*colour, 1.0)
    obj.hide_select = True
    return obj


def _show_people(scene: bpy.types.Scene, s: sw.Session) -> None:
    """One empty per other person's head and hands, in their colour;
    those not heard from lately are removed."""
    people = {pid: (name, colour) for pid, name, colour in s.participants()}
    others = s.others()
    if not others and bpy.data.collections.get(PEOPLE) is None:
        return
    coll = sync.collection(scene, PEOPLE)
    keep = set()
    k = units.units_per_metre(scene)
    for pid, p in others:
        name, colour = people.get(pid, (pid, (0.8, 0.8, 0.8)))
        poses = [("head", p.head, "SPHERE", 0.12 * k)]
        sides = ("left hand", "right hand")
        poses += [(side, h, "PLAIN_AXES", 0.05 * k) for side, h in zip(sides, p.hands, strict=True)]
        for part, pose, display, size in poses:
            if pose is None:
                continue
            obj = _empty(coll, f"{name} ({part})", display, size, colour)
            x, y, z, w = pose.q
            obj.location = units.to_units(scene, list(pose.p))
            obj.rotation_mode = "QUATERNION"
            obj.rotation_quaternion = (w, x, y, z)
            obj["shapewright_person"] = pid
            keep.add(obj.name)
    for obj in list(coll.objects):
        if obj.name not in keep:
            bpy.data.objects.remove(obj)


def _clear_people(scene: bpy.types.Scene) -> None:
    coll = bpy.data.collections.get(PEOPLE)
    if coll is None:
        return
    for obj in list(coll.objects):
        bpy.data.objects.remove(obj)
    bpy.data.collections.remove(coll)


def unregister() -> None:
    joining.clear()
    if bpy.app.timers.is_registered(finish_joins):
        bpy.app.timers.unregister(finish_joins)
    for name in list(history.shared_sessions):
        scene = bpy.data.scenes.get(name)
        if scene is not None:
            leave(scene)
    if bpy.app.timers.is_registered(tick):
        bpy.app.timers.unregister(tick)
