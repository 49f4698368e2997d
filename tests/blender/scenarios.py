"""Blender-side checks of the Shapewright extension, one scenario per run:

    BLENDER_USER_RESOURCES=DIR python scenarios.py ZIP SCENARIO WORKDIR

Runs inside `bpy` (Blender 5.0.1 as a module, headless). Installs the
extension zip through Blender's extension API, enables it, then runs the
scenario; any failed assertion exits non-zero. Headless Blender does not
push undo steps for operators called from Python (the window manager does
that in the UI for 'UNDO' operators), so `step()` pushes one after each
operator, as the UI would.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import bpy
import numpy as np


def install(zip_path: str) -> None:
    bpy.ops.extensions.package_install_files(filepath=zip_path, repo="user_default", enable_on_install=True)
    assert "bl_ext.user_default.shapewright" in bpy.context.preferences.addons, "extension not enabled"
    bpy.ops.ed.undo_push(message="start")


def addon():
    import importlib

    return importlib.import_module("bl_ext.user_default.shapewright")


def step(result: set[str], label: str) -> None:
    assert result == {"FINISHED"}, f"{label}: {result}"
    bpy.ops.ed.undo_push(message=label)


def core_session():
    return addon().history.session(bpy.context.scene)


def sw_objects() -> dict[int, bpy.types.Object]:
    sync = addon().sync
    return {o[sync.ID_PROP]: o for o in sync.collection(bpy.context.scene).objects if sync.ID_PROP in o}


def assert_synced() -> None:
    """Every core object has a Blender mesh with identical topology and
    float32-rounded positions, and nothing else is in the collection."""
    import shapewright as sw

    s = core_session()
    objs = sw_objects()
    assert sorted(objs) == s.object_ids(), (sorted(objs), s.object_ids())
    sync = addon().sync
    for oid, obj in objs.items():
        pos, tri = sync.read_mesh(obj.data)
        cpos, ctri, _ = sw.mesh_arrays(s, oid)
        assert np.array_equal(tri, ctri.astype(np.int32)), f"object {oid}: triangles differ"
        assert np.array_equal(pos, cpos.astype(np.float32).astype(np.float64)), (
            f"object {oid}: positions differ"
        )
    assert bpy.context.scene.shapewright.cursor == s.cursor


def add(shape: str, x: float, **kw) -> None:
    step(
        bpy.ops.shapewright.add_solid(shape=shape, use_cursor=False, location=(x, 0.0, 0.2), **kw),
        f"add {shape}",
    )


def scenario_build(work: Path) -> None:
    add("sphere", 0.0, radius=0.2)
    add("box", 0.6, size=(0.3, 0.2, 0.4))
    add("torus", 1.2, radius=0.2, minor_radius=0.05)
    bpy.context.view_layer.objects.active = sw_objects()[2]
    step(bpy.ops.shapewright.move(offset=(0.0, 0.5, 0.0), angle_z=0.3, scale=1.5), "move")
    step(bpy.ops.shapewright.edit_solid(shape="cylinder", radius=0.1, height=0.5), "edit")
    step(bpy.ops.shapewright.duplicate(), "duplicate")
    assert_synced()
    report = core_session().validate()
    assert report["closed_manifold"], report
    # A refused op reports an error and changes nothing.
    before = core_session().content_hash()
    bpy.context.view_layer.objects.active = sw_objects()[1]
    try:
        bpy.ops.shapewright.edit_solid(shape="torus", radius=0.05, minor_radius=0.1)
    except RuntimeError as e:
        assert "smaller than major_radius" in str(e), e
    else:
        raise AssertionError("a self-intersecting torus must be refused")
    assert core_session().content_hash() == before
    assert_synced()


def scenario_undo(work: Path) -> None:
    add("sphere", 0.0, radius=0.2)
    add("box", 0.6)
    add("cone", 1.2)
    hashes = []
    s = core_session()
    for _ in range(3):
        hashes.append(s.content_hash())
        bpy.ops.ed.undo()
        s = core_session()
        assert_synced()
    assert s.cursor == 0 and not sw_objects()
    for k in range(3):
        bpy.ops.ed.redo()
        s = core_session()
        assert_synced()
        assert s.content_hash() == hashes[2 - k]
    # Undo twice, then a new op: the redo tail is dropped in both histories.
    bpy.ops.ed.undo()
    bpy.ops.ed.undo()
    add("capsule", 2.0)
    s = core_session()
    assert s.cursor == 2 and len(s) == 2, (s.cursor, len(s))
    assert_synced()
    ops = [json.loads(line)["op"] for line in s.ops_jsonl().splitlines()]
    assert ops == ["add_solid", "add_solid"], ops


def scenario_save_reload(work: Path) -> None:
    add("sphere", 0.0, radius=0.2)
    add("torus", 0.8, radius=0.2, minor_radius=0.05)
    add("box", 1.6)
    bpy.ops.ed.undo()
    s = core_session()
    want = (s.ops_jsonl(), s.cursor, s.content_hash())
    path = work / "model.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path))
    bpy.ops.wm.read_homefile(use_empty=True)
    bpy.ops.wm.open_mainfile(filepath=str(path))
    s = core_session()
    # The redo tail is not in the saved scene (Blender keeps no redo past a
    # save either); the applied history and the model are.
    assert s.cursor == want[1] and s.content_hash() == want[2], (s.cursor, want[1])
    assert want[0].startswith(s.ops_jsonl())
    assert_synced()
    bpy.ops.ed.undo_push(message="reopened")
    step(
        bpy.ops.shapewright.add_solid(shape="cone", use_cursor=False, location=(0, 1, 0)), "add after reopen"
    )
    bpy.ops.ed.undo()
    assert core_session().cursor == want[1]
    assert_synced()


def mesh_volume(pos: np.ndarray, tri: np.ndarray) -> float:
    a, b, c = pos[tri[:, 0]], pos[tri[:, 1]], pos[tri[:, 2]]
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


def scenario_usd_roundtrip(work: Path) -> None:
    add("sphere", 0.0, radius=0.2)
    add("torus", 0.8, radius=0.2, minor_radius=0.05)
    sync = addon().sync
    before = {}
    for obj in sw_objects().values():
        pos, tri = sync.read_mesh(obj.data)
        before[obj.name] = (len(tri), mesh_volume(pos, tri))
    path = work / "model.usda"
    bpy.ops.wm.usd_export(filepath=str(path), selected_objects_only=False)
    bpy.ops.wm.read_homefile(use_empty=True)
    bpy.ops.wm.usd_import(filepath=str(path))
    after = {}
    for obj in bpy.data.objects:
        if obj.type == "MESH" and obj.name in before:
            me = obj.data
            me.calc_loop_triangles()
            pos = np.empty(len(me.vertices) * 3, dtype=np.float32)
            me.vertices.foreach_get("co", pos)
            tri = np.empty(len(me.loop_triangles) * 3, dtype=np.int32)
            me.loop_triangles.foreach_get("vertices", tri)
            m = np.array(obj.matrix_world)
            p = pos.astype(np.float64).reshape(-1, 3) @ m[:3, :3].T + m[:3, 3]
            after[obj.name] = (len(tri) // 3, mesh_volume(p, tri.reshape(-1, 3)))
    assert set(after) == set(before), (after.keys(), before.keys())
    for name, (n, v) in before.items():
        assert after[name][0] == n, (name, after[name], n)
        assert abs(after[name][1] - v) <= 1e-6 * abs(v), (name, after[name][1], v)


def scenario_render(work: Path) -> None:
    add("sphere", 0.0, radius=0.2)
    add("box", 0.6)
    out = work / "render.png"
    step(bpy.ops.shapewright.render_png(filepath=str(out), resolution=320), "render")
    assert out.is_file() and out.stat().st_size > 1000
    img = bpy.data.images.load(str(out))
    px = np.array(img.pixels[:]).reshape(img.size[1], img.size[0], 4)[..., :3]
    frac = float((np.abs(px - px[0, 0]).max(axis=-1) > 0.05).mean())
    assert 0.03 < frac < 0.9, frac


def scenario_export(work: Path) -> None:
    add("sphere", 0.0, radius=0.2)
    out = work / "model.stl"
    bpy.ops.shapewright.export_mesh(filepath=str(out))
    assert out.is_file() and out.stat().st_size == 84 + 50 * core_session().validate()["triangles"]


def main() -> int:
    zip_path, name, work = sys.argv[1], sys.argv[2], Path(sys.argv[3])
    install(zip_path)
    globals()[f"scenario_{name}"](work)
    print(f"scenario {name}: ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
