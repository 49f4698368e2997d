"""What every Blender scenario uses: installing the extension, pushing
undo steps as Blender's UI pushes them, the add-on's modules, and the
check that Blender shows exactly the core's document.

Headless Blender does not push undo steps for operators called from
Python (the window manager does that in the UI for 'UNDO' operators), so
`step()` pushes one after each operator, as the UI would, and the add-on's
timers (which Blender's event loop runs) are run by `settle()`.
"""

from __future__ import annotations

import importlib
import json
from pathlib import Path

import bpy
import numpy as np


def install(zip_path: str) -> None:
    bpy.ops.extensions.package_install_files(filepath=zip_path, repo="user_default", enable_on_install=True)
    assert "bl_ext.user_default.shapewright" in bpy.context.preferences.addons, "extension not enabled"
    bpy.ops.ed.undo_push(message="start")


def addon():
    return importlib.import_module("bl_ext.user_default.shapewright")


def module(name: str):
    """A module of the add-on (`adopt`, `history`, ...), or None."""
    try:
        return importlib.import_module(f"bl_ext.user_default.shapewright.{name}")
    except ImportError:
        return None


def step(result: set[str], label: str) -> None:
    assert result == {"FINISHED"}, f"{label}: {result}"
    bpy.ops.ed.undo_push(message=label)


def core_session():
    return addon().history.session(bpy.context.scene)


ID_PROP = "shapewright_id"
DATA = Path(__file__).resolve().parents[1] / "data"


def sw_objects() -> dict[int, bpy.types.Object]:
    """The scene's Shapewright objects by core id (the last one wins when
    two claim one id; `blender_objects_by_id` shows all)."""
    return {o[ID_PROP]: o for o in bpy.context.scene.objects if ID_PROP in o}


def blender_objects_by_id() -> dict[int, list[bpy.types.Object]]:
    out: dict[int, list] = {}
    for o in bpy.context.scene.objects:
        if ID_PROP in o:
            out.setdefault(int(o[ID_PROP]), []).append(o)
    return out


def settle(limit: int = 40) -> int:
    """Runs the add-on's edit timer as Blender's event loop would, until
    it stops; returns how many times it ran."""
    owner = module("adopt") or addon().history
    for n in range(1, limit):
        if owner.moves_tick() is None:
            return n
    raise AssertionError("the edit timer never settles")


def metres_per_unit() -> float:
    """The scene's metres per Blender unit, as the add-on reads it (the
    float32 `scale_length` as the decimal it was typed as)."""
    return float(str(np.float32(bpy.context.scene.unit_settings.scale_length))) or 1.0


def core_world(s, oid: int) -> tuple[np.ndarray, np.ndarray]:
    """The core's mesh of `oid` in world space, metres."""
    import shapewright as sw

    pos, tri, _ = sw.mesh_arrays(s, oid)
    return pos, tri


def blender_world(obj) -> tuple[np.ndarray, np.ndarray]:
    """What Blender shows of `obj`: its mesh placed by its world matrix
    (the modifiers' result if it has any), in metres."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    ev = obj.evaluated_get(depsgraph)
    me = ev.to_mesh()
    try:
        pos = np.empty(len(me.vertices) * 3, dtype=np.float32)
        me.vertices.foreach_get("co", pos)
        idx = np.empty(len(me.loops), dtype=np.int32)
        me.loops.foreach_get("vertex_index", idx)
        counts = np.empty(len(me.polygons), dtype=np.int32)
        me.polygons.foreach_get("loop_total", counts)
    finally:
        ev.to_mesh_clear()
    m = np.array(obj.matrix_world, dtype=np.float64)
    world = pos.astype(np.float64).reshape(-1, 3) @ m[:3, :3].T + m[:3, 3]
    tri = idx.reshape(-1, 3) if len(counts) and (counts == 3).all() else idx
    return world * metres_per_unit(), tri


def world_mismatches(tolerance: float = 2e-5) -> list[str]:
    """How Blender's view differs from the core's document: objects
    missing or doubled, topology, or vertices off by more than `tolerance`
    (relative to the object's size, float32 storage allowed for)."""
    s = core_session()
    problems = []
    found = blender_objects_by_id()
    ids = s.object_ids()
    for oid in ids:
        objs = found.get(oid, [])
        if len(objs) != 1:
            problems.append(f"object {oid}: {len(objs)} Blender objects ({[o.name for o in objs]})")
            continue
        pos, tri = blender_world(objs[0])
        cpos, ctri = core_world(s, oid)
        if pos.shape != cpos.shape or np.asarray(tri).size != ctri.size:
            problems.append(f"object {oid} ({objs[0].name}): {len(pos)} vertices vs the core's {len(cpos)}")
            continue
        size = float(np.abs(cpos).max()) if len(cpos) else 1.0
        err = float(np.abs(pos - cpos).max()) if len(pos) else 0.0
        if err > tolerance * max(size, 1e-3):
            problems.append(f"object {oid} ({objs[0].name}): vertices {err:.3g} m from the core's")
    for oid, objs in found.items():
        if oid not in ids:
            problems.append(f"Blender object(s) {[o.name for o in objs]} for id {oid}, not in the document")
    return problems


def assert_world_synced(where: str = "") -> None:
    problems = world_mismatches()
    assert not problems, f"{where}: {problems}"


def op_names_of(s) -> list[str]:
    """The names of the session's ops, in order."""
    if hasattr(s, "op"):
        return [s.op(i)["op"] for i in range(len(s))]
    return [json.loads(x)["op"] for x in s.ops_jsonl().splitlines()]


def last_ops(s, n: int) -> list[dict]:
    if hasattr(s, "op"):
        return [s.op(i) for i in range(max(0, len(s) - n), len(s))]
    return [json.loads(x) for x in s.ops_jsonl().splitlines()[-n:]]


def add_solid(shape: str, location, size: float = 0.1) -> None:
    """Adds a solid through the add-on's operator, at `location` (scene
    units), `size` metres across (a torus a third as thick), as one undo
    step (before issue 34 the operator took a radius in metres)."""
    loc = tuple(location)
    d = size / metres_per_unit()
    dims = (d, d, d / 3 if shape == "torus" else d)
    try:
        r = bpy.ops.shapewright.add_solid(shape=shape, use_cursor=False, location=loc, dimensions=dims)
    except TypeError:
        r = bpy.ops.shapewright.add_solid(shape=shape, use_cursor=False, location=loc, radius=size / 2)
    step(r, f"add {shape}")


def select_only(obj) -> None:
    for o in bpy.context.view_layer.objects.selected:
        o.select_set(False)
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj


def assert_synced() -> None:
    """Every core object has one Blender object whose mesh is the core's
    mesh in the object's origin frame (identical topology, float32-rounded
    positions, the scene's units) and whose matrix is the core's origin;
    nothing else claims a core id; and Blender shows the core's document
    in world space (`world_mismatches`)."""
    import shapewright as sw

    s = core_session()
    objs = sw_objects()
    assert sorted(objs) == s.object_ids(), (sorted(objs), s.object_ids())
    sync = addon().sync
    k = 1.0 / metres_per_unit()
    for oid, obj in objs.items():
        pos, tri = sync.read_mesh(obj.data)
        cpos, ctri, _ = sw.mesh_arrays(s, oid, frame="origin", units_per_metre=k)
        assert np.array_equal(tri, ctri.astype(np.int32)), f"object {oid}: triangles differ"
        assert np.array_equal(pos, cpos.astype(np.float32).astype(np.float64)), (
            f"object {oid}: positions differ"
        )
        where = sw.Placement.from_matrix([list(r) for r in obj.matrix_world], metres_per_unit())
        assert where.close_to(s.object_origin(oid), 2e-6), (oid, where, s.object_origin(oid))
    assert bpy.context.scene.shapewright.cursor == s.cursor
    assert_world_synced("assert_synced")


def origin_matrix(oid: int):
    """The core's origin of `oid` as a Blender matrix (scene units)."""
    from mathutils import Matrix

    return Matrix(core_session().object_origin(oid).matrix(1.0 / metres_per_unit()))


def add(shape: str, x: float, **kw) -> None:
    """A solid of `shape` at (x, 0, 0.2) through the add-on's operator
    (`dimensions`, `segments`, ... as keywords), as one undo step."""
    step(
        bpy.ops.shapewright.add_solid(shape=shape, use_cursor=False, location=(x, 0.0, 0.2), **kw),
        f"add {shape}",
    )


def last_op() -> dict:
    s = core_session()
    return s.op(s.cursor - 1)
