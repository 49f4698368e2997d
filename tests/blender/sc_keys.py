"""Blender's own keys on Shapewright objects (issue 34): Shift-D, X, a
click-select then G then Ctrl-Z, Edit Mode, modifiers, and a randomized
run of undo, redo, select, move, duplicate and delete that checks after
every step that Blender shows exactly the core's document."""

from __future__ import annotations

import os
import random
import tempfile
from pathlib import Path

import bpy
from helpers import (
    add_solid,
    assert_world_synced,
    core_session,
    last_ops,
    metres_per_unit,
    module,
    select_only,
    settle,
    sw_objects,
    world_mismatches,
)


def _two_solids() -> tuple[int, int]:
    add_solid("sphere", (0.0, 0.0, 0.1))
    add_solid("box", (0.4, 0.0, 0.1))
    ids = core_session().object_ids()
    assert len(ids) == 2, ids
    return ids[0], ids[1]


def _click_select(obj) -> None:
    select_only(obj)
    bpy.ops.ed.undo_push(message="Select")  # a click-select pushes a step


def _printed_volume(s) -> float:
    with tempfile.TemporaryDirectory() as d:
        return float(s.export_mesh(str(Path(d) / "x.stl"))["volume"])


def scenario_keys_duplicate(work: Path) -> None:
    """Shift-D records `duplicate` of the object duplicated (and the copy's
    move), as one undo step; the original stays where it was and both
    print."""
    a, b = _two_solids()
    s = core_session()
    n = len(s)
    one = _printed_volume(s)
    original = sw_objects()[a]
    before = tuple(original.matrix_world.translation)
    _click_select(original)
    mpu = metres_per_unit()
    assert bpy.ops.object.duplicate_move(TRANSFORM_OT_translate={"value": (0.0, 0.3 / mpu, 0.0)}) == {
        "FINISHED"
    }
    bpy.ops.ed.undo_push(message="Duplicate Objects")
    settle()
    s = core_session()
    ids = s.object_ids()
    assert len(ids) == 3, f"Shift-D: the document has {ids}, not the two objects and the copy"
    ops = last_ops(s, len(s) - n)
    assert ops[0]["op"] == "duplicate" and ops[0]["id"] == a, f"Shift-D recorded {ops}"
    assert all(o.get("id") != a for o in ops[1:]), f"the original was changed: {ops}"
    assert tuple(sw_objects()[a].matrix_world.translation) == before, "the original moved"
    assert_world_synced("after Shift-D")
    assert _printed_volume(s) > one * 1.2, "the copy is not in the print"
    # One Ctrl-Z takes the copy back; Ctrl-Shift-Z brings it again.
    bpy.ops.ed.undo()
    settle()
    assert core_session().object_ids() == [a, b], core_session().object_ids()
    assert_world_synced("after Ctrl-Z of Shift-D")
    bpy.ops.ed.redo()
    settle()
    assert len(core_session().object_ids()) == 3
    assert_world_synced("after Ctrl-Shift-Z of Shift-D")


def scenario_keys_delete(work: Path) -> None:
    """X records `delete`, as one undo step: the object stays gone after
    the next op and is not printed; Ctrl-Z brings it back."""
    a, b = _two_solids()
    s = core_session()
    n = len(s)
    both = _printed_volume(s)
    _click_select(sw_objects()[a])
    assert bpy.ops.object.delete() == {"FINISHED"}
    bpy.ops.ed.undo_push(message="Delete")
    settle()
    s = core_session()
    assert s.object_ids() == [b], f"X: the document still has {s.object_ids()}"
    ops = last_ops(s, len(s) - n)
    assert [o["op"] for o in ops] == ["delete"] and ops[0]["id"] == a, ops
    add_solid("cone", (0.8, 0.0, 0.1))
    s = core_session()
    assert a not in s.object_ids() and a not in sw_objects(), "the deleted object came back"
    assert_world_synced("after X and another op")
    bpy.ops.ed.undo()
    settle()
    bpy.ops.ed.undo()
    settle()
    s = core_session()
    assert s.object_ids() == [a, b], s.object_ids()
    assert abs(_printed_volume(s) - both) < 1e-9 * max(both, 1.0)
    assert_world_synced("after Ctrl-Z of X")


def scenario_select_move_undo(work: Path) -> None:
    """A click-select (Blender pushes a "Select" step), a G move, then
    Ctrl-Z: Blender shows the document the core has, before and after."""
    a, _ = _two_solids()
    obj = sw_objects()[a]
    _click_select(obj)
    mpu = metres_per_unit()
    assert bpy.ops.transform.translate(value=(0.2 / mpu, 0.1 / mpu, 0.0)) == {"FINISHED"}
    bpy.ops.ed.undo_push(message="Move")
    settle()
    moved = core_session().content_hash()
    assert_world_synced("after G")
    bpy.ops.ed.undo()
    settle()
    assert core_session().content_hash() != moved, "Ctrl-Z did not take the move back"
    assert_world_synced("after Ctrl-Z")
    bpy.ops.ed.redo()
    settle()
    assert core_session().content_hash() == moved
    assert_world_synced("after Ctrl-Shift-Z")


def _notices() -> list[str]:
    n = module("notify")
    return list(n.messages) if n is not None else []


def scenario_edit_mode(work: Path) -> None:
    """Edit Mode on a Shapewright object is refused at once (its mesh is
    the core's to make), with a message; the mesh stays the core's."""
    a, _ = _two_solids()
    obj = sw_objects()[a]
    select_only(obj)
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.transform.translate(value=(0.0, 0.0, 0.5 / metres_per_unit()))
    if obj.mode == "EDIT":
        bpy.ops.object.mode_set(mode="OBJECT")
    bpy.ops.ed.undo_push(message="Edit")
    settle()
    assert obj.mode == "OBJECT"
    assert_world_synced("after Edit Mode")
    assert any("Edit Mode" in m for m in _notices()), _notices()


def scenario_modifiers(work: Path) -> None:
    """A modifier on a Shapewright object (it would change what Blender
    shows, not what prints) is removed at once, with a message."""
    a, _ = _two_solids()
    obj = sw_objects()[a]
    select_only(obj)
    assert bpy.ops.object.modifier_add(type="SUBSURF") == {"FINISHED"}
    bpy.ops.ed.undo_push(message="Add Modifier")
    settle()
    assert not obj.modifiers, [m.name for m in obj.modifiers]
    assert_world_synced("after adding a modifier")
    assert any("modifier" in m.lower() for m in _notices()), _notices()


ACTIONS = ("select", "move", "rotate", "scale", "duplicate", "delete", "undo", "redo")
WEIGHTS = (3, 3, 2, 1, 2, 1, 3, 2)


def scenario_keys_random(work: Path) -> None:
    """Hundreds of random steps of Blender's undo, redo, select, move,
    rotate, scale, duplicate and delete (undo pushed as the UI pushes it),
    checking after every step that every Blender mesh is the core's.
    SW_STEPS sets the number of steps (300), SW_SEED the seed."""
    steps = int(os.environ.get("SW_STEPS", "300"))
    rng = random.Random(int(os.environ.get("SW_SEED", "34")))
    add_solid("sphere", (0.0, 0.0, 0.1))
    add_solid("box", (0.4, 0.0, 0.1))
    add_solid("torus", (0.0, 0.4, 0.1))
    mpu = metres_per_unit()
    log: list[str] = []
    mismatches: list[str] = []
    for k in range(steps):
        action = rng.choices(ACTIONS, WEIGHTS)[0]
        objs = list(sw_objects().values())
        done = action
        if not objs and action != "undo":
            add_solid(rng.choice(("sphere", "box", "cone")), (rng.uniform(-0.3, 0.3) / mpu, 0.0, 0.1 / mpu))
            done = "add"
        elif action == "select":
            _click_select(rng.choice(objs))
        elif action in ("move", "rotate", "scale", "duplicate", "delete"):
            if not any(o.select_get() for o in objs):
                _click_select(rng.choice(objs))
            if action == "move":
                v = [rng.uniform(-0.2, 0.2) / mpu for _ in range(3)]
                r = bpy.ops.transform.translate(value=v)
            elif action == "rotate":
                r = bpy.ops.transform.rotate(value=rng.uniform(-1.5, 1.5), orient_axis=rng.choice("XYZ"))
            elif action == "scale":
                f = rng.uniform(0.7, 1.4)
                r = bpy.ops.transform.resize(value=(f, f, f))
            elif action == "duplicate":
                v = (rng.uniform(-0.3, 0.3) / mpu, rng.uniform(-0.3, 0.3) / mpu, 0.0)
                r = bpy.ops.object.duplicate_move(TRANSFORM_OT_translate={"value": v})
            else:
                r = bpy.ops.object.delete()
            bpy.ops.ed.undo_push(message=action)
            done = f"{action} {r}"
        elif action == "undo":
            done = "undo" if bpy.ops.ed.undo.poll() and bpy.ops.ed.undo() else "undo (none)"
        elif action == "redo":
            done = "redo" if bpy.ops.ed.redo.poll() and bpy.ops.ed.redo() else "redo (none)"
        settle()
        log.append(done)
        problems = world_mismatches()
        if problems:
            mismatches.append(f"step {k} ({done}; before: {log[-6:-1]}): {problems}")
    print(f"keys_random: {steps} steps, {len(mismatches)} with a mismatch; actions {_count(log)}")
    assert not mismatches, (
        f"{len(mismatches)} of {steps} steps left Blender and the core different: {mismatches[:3]}"
    )


def _count(log: list[str]) -> dict[str, int]:
    out: dict[str, int] = {}
    for x in log:
        key = x.split()[0]
        out[key] = out.get(key, 0) + 1
    return out
