"""Blender's own renames and moves of Shapewright objects become ops (one undo step each)."""

from __future__ import annotations

import math
import os
from pathlib import Path

import bpy
import numpy as np
from helpers import (
    add,
    addon,
    assert_synced,
    blender_world,
    core_session,
    core_world,
    last_op,
    settle,
    step,
    sw_objects,
)
from sc_typed import op_scene


def scenario_rename(work: Path) -> None:
    """Renaming a Shapewright object in Blender (`obj.name = ...`, which is
    what the outliner and F2 set) records a `rename_object` op; one undo
    takes the rename back, redo brings it again (the log keeps its redo
    tail); a name the core refuses is put back; the name survives a .blend
    reload, the usda beside it, and Blender's own USD export and import."""
    import shapewright as sw

    add("sphere", 0.0, dimensions=(0.2, 0.2, 0.2))
    add("box", 0.6)
    s = core_session()
    n0 = len(s)
    assert sw_objects()[1].name == "SW1" and s.object_name(1) == ""
    # A script's rename, the depsgraph update Blender runs after it, then
    # the undo push the UI makes.
    sw_objects()[1].name = "Mug body"
    bpy.context.view_layer.update()
    bpy.ops.ed.undo_push(message="rename body")
    s = core_session()
    assert last_op() == {"op": "rename_object", "id": 1, "name": "Mug body"}, last_op()
    assert len(s) == n0 + 1 and s.cursor == n0 + 1 and s.object_name(1) == "Mug body"
    assert sw_objects()[1].name == "Mug body"
    assert_synced()
    bpy.ops.ed.undo()
    s = core_session()
    assert s.cursor == n0 and s.object_name(1) == "" and sw_objects()[1].name == "SW1"
    assert_synced()
    bpy.ops.ed.redo()
    s = core_session()
    assert s.cursor == n0 + 1 and s.object_name(1) == "Mug body" and sw_objects()[1].name == "Mug body"
    # The UI's order (outliner, F2): the rename's undo step is pushed
    # before the depsgraph update records the op (headless, the push
    # itself evaluates the depsgraph: the handler is held back for it).
    handlers = bpy.app.handlers.depsgraph_update_post
    handler = addon().adopt.on_depsgraph_update
    handlers.remove(handler)
    sw_objects()[2].name = "Lid"
    bpy.ops.ed.undo_push(message="rename lid")
    handlers.append(handler)
    assert core_session().cursor == n0 + 1, "the rename is not recorded before the handler runs"
    sw_objects()[2].update_tag()
    bpy.context.view_layer.update()
    s = core_session()
    assert last_op() == {"op": "rename_object", "id": 2, "name": "Lid"}, last_op()
    assert s.cursor == n0 + 2 == len(s)
    step(bpy.ops.shapewright.add_solid(shape="cone", use_cursor=False, location=(1.2, 0, 0)), "cone")
    want_ops = core_session().ops_jsonl()
    # One undo takes the rename back (the panel's Undo, then Blender's).
    assert bpy.ops.shapewright.undo() == {"FINISHED"}
    assert bpy.ops.shapewright.undo() == {"FINISHED"}
    s = core_session()
    assert s.cursor == n0 + 1 and s.object_name(2) == "" and sw_objects()[2].name == "SW2", s.cursor
    assert_synced()
    # Redo returns to the step Blender pushed with the old log: the op is
    # redone from the log's tail, not recorded again, and the tail stays.
    bpy.ops.ed.redo()
    s = core_session()
    assert s.cursor == n0 + 2 and sw_objects()[2].name == "Lid" and s.ops_jsonl() == want_ops
    bpy.ops.ed.redo()
    s = core_session()
    assert s.cursor == n0 + 3 and s.ops_jsonl() == want_ops, s.ops_jsonl()
    assert_synced()
    # A name the core refuses (a control character) is put back.
    sw_objects()[2].name = "bad\x07name"
    bpy.context.view_layer.update()
    assert sw_objects()[2].name == "Lid" and core_session().ops_jsonl() == want_ops
    names = {1: "Mug body", 2: "Lid", 3: "SW3"}

    def check_names(where: str) -> None:
        s = core_session()
        got = {oid: o.name for oid, o in sw_objects().items()}
        assert got == names, (where, got)
        assert [s.object_name(i) for i in (1, 2, 3)] == ["Mug body", "Lid", ""], where
        assert s.ops_jsonl() == want_ops, (where, s.ops_jsonl())
        assert_synced()

    # Save and reopen: the .blend and the usda beside it.
    path = work / "renamed.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path))
    bpy.ops.wm.read_homefile(use_empty=True)
    bpy.ops.wm.open_mainfile(filepath=str(path))
    check_names("reopened .blend")
    beside = sw.load_usd(str(work / "renamed.shapewright.usda"), verify_history=True)
    assert beside.object_name(1) == "Mug body" and beside.ops_jsonl() == want_ops
    # Blender's own USD export and import (the prim is "Mug_body").
    bpy.ops.wm.usd_export(filepath=str(work / "renamed_blender.usda"), selected_objects_only=False)
    assert "Mug_body" in (work / "renamed_blender.usda").read_text()
    bpy.ops.wm.read_homefile(use_empty=True)
    bpy.ops.ed.undo_push(message="empty")
    bpy.ops.wm.usd_import(filepath=str(work / "renamed_blender.usda"))
    bpy.ops.ed.undo_push(message="import")
    addon().usd_hook.finish_imports()
    bpy.context.view_layer.update()
    check_names("Blender's USD import")
    # After reopening, the rename is undone past the load point too.
    for _ in range(2):
        assert bpy.ops.shapewright.undo() == {"FINISHED"}
    assert core_session().object_name(2) == "" and sw_objects()[2].name == "SW2"
    assert sw_objects()[1].name == "Mug body"


def world_of(oid: int) -> np.ndarray:
    """Blender's world positions of object `oid` (metres)."""
    return blender_world(sw_objects()[oid])[0]


def scenario_transform_kinds(work: Path) -> None:
    """G/R/S in Blender on an object of every kind, several at once: one
    `set_transform` op per moved object (its origin where Blender put it),
    recorded by the edit timer in one undo step, with no button; each core
    mesh lands where Blender's matrix had put it (vertices within 1e-5 m)
    and the object keeps the matrix (its origin) and its mesh; one undo
    puts the document and the placements back, redo redoes the ops from
    the log's tail. SW_PNG=path renders the moved scene there."""
    from mathutils import Matrix

    kinds = op_scene()
    bpy.ops.ed.undo_push(message="scene")
    s = core_session()
    n0, h0 = len(s), s.content_hash()
    m = Matrix.Translation((0.1, -0.05, 0.02)) @ Matrix.Rotation(math.pi / 2, 4, "Z") @ Matrix.Scale(1.25, 4)
    mm = np.array(m, dtype=np.float64)
    want, before = {}, {}
    for oid, obj in sw_objects().items():
        before[oid] = (world_of(oid), obj.matrix_world.copy())
        if not len(obj.data.polygons):
            continue  # the CSG volume with a pending operand has no mesh yet
        obj.matrix_world = m @ obj.matrix_world
        pos = before[oid][0]
        want[oid] = pos @ mm[:3, :3].T + mm[:3, 3]
    assert len(want) >= 3, sorted(want)
    bpy.context.view_layer.objects.active = sw_objects()[kinds["gc_assembly"]]
    # The UI's order: the transform's undo step, then the timer records.
    bpy.context.view_layer.update()
    bpy.ops.ed.undo_push(message="move")
    assert len(core_session()) == n0, "nothing is recorded before the timer runs"
    settle()
    s = core_session()
    ops = [s.op(i) for i in range(n0, len(s))]
    assert s.cursor == n0 + len(want) and [o["op"] for o in ops] == ["set_transform"] * len(want), ops
    assert sorted(o["id"] for o in ops) == sorted(want)
    moved_ops = s.ops_jsonl()
    h1 = s.content_hash()
    for oid, pos_want in want.items():
        cpos = core_world(s, oid)[0]
        err = float(np.abs(cpos - pos_want).max())
        assert err < 1e-5, f"object {oid} ({s.object_kind(oid)}): {err} m from Blender's move"
    assert_synced()
    # Nothing moved since: nothing more recorded.
    bpy.context.view_layer.update()
    settle()
    assert core_session().ops_jsonl() == moved_ops

    if os.environ.get("SW_PNG"):
        assert bpy.ops.shapewright.render_png(filepath=os.environ["SW_PNG"], resolution=640) == {"FINISHED"}
    # One undo takes all the moves back.
    bpy.ops.ed.undo()
    settle()
    s = core_session()
    assert s.cursor == n0 and s.content_hash() == h0
    for oid, (pos, _matrix) in before.items():
        assert np.abs(world_of(oid) - pos).max(initial=0.0) < 1e-6, oid
    assert_synced()
    # Redo returns to the step that holds the moved matrices with the old
    # log: the ops are redone from the tail, not recorded again.
    bpy.ops.ed.redo()
    settle()
    s = core_session()
    assert s.cursor == n0 + len(want) and s.ops_jsonl() == moved_ops and s.content_hash() == h1
    assert_synced()


class FakeOp:
    def __init__(self, idname: str) -> None:
        self.bl_idname = idname


class FakeWindow:
    def __init__(self, *idnames: str) -> None:
        self.modal_operators = [FakeOp(i) for i in idnames]


def scenario_transform_auto(work: Path) -> None:
    """Moves made in Blender without any button: `location`, rotation and
    `scale` set on a solid, a GC and a curve network give exactly one
    `set_transform` op each, not while a transform modal runs (a simulated
    one: headless Blender has no window to run one) nor while the
    matrices still change; undo restores the content hash and the
    placements, redo reapplies without recording again, and save and
    reopen keep it. A move the core refuses (a zero scale) is put back; an
    op run right after a move comes after it in the log."""
    adopt = addon().adopt
    assert "modal_operators" in bpy.types.Window.bl_rna.properties, "Blender without Window.modal_operators"
    # The decision, on fake window lists.
    sig = ((1, ((1.0,),)),)
    assert adopt.move_decision([], (), None) == "idle"
    assert adopt.move_decision([FakeWindow("TRANSFORM_OT_translate")], sig, sig) == "wait"
    two = [FakeWindow(), FakeWindow("VIEW3D_OT_rotate", "TRANSFORM_OT_resize")]
    assert adopt.move_decision(two, sig, sig) == "wait"
    assert adopt.move_decision([FakeWindow("transform.rotate")], sig, sig) == "wait"
    assert adopt.move_decision([FakeWindow("GIZMOGROUP_OT_gizmo_tweak")], sig, sig) == "wait"
    assert (
        adopt.move_decision([FakeWindow("VIEW3D_OT_rotate", "SHAPEWRIGHT_OT_sketch")], sig, sig) == "record"
    )
    assert adopt.move_decision([], sig, None) == "wait", "the first look waits for the matrices to settle"
    assert adopt.move_decision([], sig, ((1, ((2.0,),)),)) == "wait"
    assert adopt.move_decision([], sig, sig) == "record"

    kinds = op_scene()
    bpy.ops.ed.undo_push(message="scene")
    moves = [
        ("solid", "location", (0.1, -0.2, 0.05)),
        ("gc_assembly", "rotation_euler", (0.0, 0.0, 0.6)),
        ("curve_network", "scale", (1.5, 1.5, 1.5)),
    ]
    windows = adopt.windows
    hashes = [core_session().content_hash()]
    worlds = [{oid: world_of(oid) for oid in sw_objects()}]
    try:
        for k, (kind, attr, value) in enumerate(moves):
            oid = kinds[kind]
            obj = sw_objects()[oid]
            n = len(core_session())
            fake = [FakeWindow("TRANSFORM_OT_transform")]
            adopt.windows = lambda fake=fake: fake
            setattr(obj, attr, value)
            bpy.context.view_layer.update()
            assert bpy.app.timers.is_registered(adopt.moves_tick), "the depsgraph handler starts the timer"
            for _ in range(4):
                assert adopt.moves_tick() == adopt.MOVES_TICK, "waits while the modal runs"
            assert len(core_session()) == n
            # An op run meanwhile does not take a move that is still going.
            addon().history.finish_pending(bpy.context.scene)
            assert len(core_session()) == n
            fake.clear()  # the modal ends
            if k == 1:
                bpy.ops.ed.undo_push(message=f"move {kind}")  # the UI's order
            assert settle() == 1, "the matrices were already settled"
            if k != 1:
                bpy.ops.ed.undo_push(message=f"move {kind}")  # a script's order
            s = core_session()
            assert len(s) == n + 1 and s.cursor == n + 1, (kind, len(s), n)
            assert last_op()["op"] == "set_transform" and last_op()["id"] == oid, last_op()
            assert tuple(getattr(obj, attr)) == tuple(value) or np.allclose(
                tuple(getattr(obj, attr)), value, atol=1e-6
            )
            assert_synced()
            hashes.append(s.content_hash())
            worlds.append({i: world_of(i) for i in sw_objects()})
    finally:
        adopt.windows = windows
    want_ops = core_session().ops_jsonl()
    n3 = len(core_session())

    def check(k: int, where: str) -> None:
        s = core_session()
        assert s.content_hash() == hashes[k], (where, k)
        assert s.ops_jsonl() == want_ops, (where, "the log changed")
        for oid in sw_objects():
            assert np.abs(world_of(oid) - worlds[k][oid]).max(initial=0.0) < 1e-6, (where, k, oid)
        assert_synced()

    for k in (2, 1, 0):
        bpy.ops.ed.undo()
        settle()
        check(k, "undo")
    for k in (1, 2, 3):
        bpy.ops.ed.redo()
        settle()
        check(k, "redo")
    # Save and reopen.
    path = work / "moved.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path))
    bpy.ops.wm.read_homefile(use_empty=True)
    bpy.ops.wm.open_mainfile(filepath=str(path))
    settle()
    check(3, "reopened")
    # A move the core refuses (a zero scale flattens the GC) is put back,
    # with a message, and nothing is recorded.
    gc = sw_objects()[kinds["gc_assembly"]]
    gc.scale = (1.0, 0.0, 1.0)
    bpy.context.view_layer.update()
    settle()
    assert len(core_session()) == n3, last_op()
    assert tuple(gc.scale) != (1.0, 0.0, 1.0)
    assert any("not taken" in m for m in addon().notify.messages), addon().notify.messages
    check(3, "refused")
    # An op right after a move (before the timer ran): the move first.
    sw_objects()[kinds["solid"]].location = (0.0, 0.0, 0.3)
    step(bpy.ops.shapewright.add_solid(shape="box", use_cursor=False, location=(2.0, 0.0, 0.0)), "box")
    s = core_session()
    ops = [s.op(i) for i in range(n3, len(s))]
    assert [o["op"] for o in ops] == ["set_transform", "add_solid"], ops
    assert ops[0]["id"] == kinds["solid"]
    assert np.allclose(ops[0]["transform"]["translate"], [0.0, 0.0, 0.3], atol=1e-7), ops[0]
    assert tuple(sw_objects()[kinds["solid"]].location) == (0.0, 0.0, 0.3) or np.allclose(
        tuple(sw_objects()[kinds["solid"]].location), (0.0, 0.0, 0.3), atol=1e-7
    )
    assert_synced()
