"""Core meshes into Blender meshes, with `foreach_set` (no Python loops over
vertices). Each core object is a mesh object in the "Shapewright"
collection carrying its core id and kind, named by the core's name
(`rename_object`) or `SW<id>` (renaming the Blender object records a
`rename_object` op: `history.adopt_renames`); only objects whose content hash changed
are rewritten.

With the scene's "Show parametric parts" on, the parametric data of GC
assemblies and curve networks (the same `NurbsCurves` / `NurbsPatch` data
the USD files carry) are shown as helper objects in the "Shapewright
parametric" collection, parented to their owner: curves as Blender
`Curves` with exact knots (the core's Bézier segments in the
`ENDPOINT_BEZIER` knot mode) and patches as meshes. They are rebuilt when
their owner changes and removed with it.
"""

from __future__ import annotations

import bpy
import numpy as np
import shapewright as sw

COLLECTION = "Shapewright"
PARAMETRIC_COLLECTION = "Shapewright parametric"
ID_PROP = "shapewright_id"
HASH_PROP = "shapewright_hash"
KIND_PROP = "shapewright_kind"
OWNER_PROP = "shapewright_owner"
PART_PROP = "shapewright_parametric"
NAME_PROP = "shapewright_name"
# The Blender name the add-on last gave the object (Blender may add a
# `.001` suffix to the core's name); a different name is a rename made in
# Blender, which `history.adopt_renames` turns into a `rename_object` op.
SHOWN_PROP = "shapewright_shown_name"

# Blender's knot mode value `KnotsMode::NURBS_KNOT_MODE_ENDPOINT_BEZIER`.
KNOTS_ENDPOINT_BEZIER = 3


def collection(scene: bpy.types.Scene, name: str = COLLECTION) -> bpy.types.Collection:
    coll = bpy.data.collections.get(name)
    if coll is None:
        coll = bpy.data.collections.new(name)
    if coll.name not in scene.collection.children:
        scene.collection.children.link(coll)
    return coll


def write_mesh(me: bpy.types.Mesh, positions: np.ndarray, triangles: np.ndarray) -> None:
    me.clear_geometry()
    me.vertices.add(len(positions))
    me.vertices.foreach_set("co", positions.astype(np.float32).ravel())
    me.loops.add(triangles.size)
    me.loops.foreach_set("vertex_index", triangles.astype(np.int32).ravel())
    me.polygons.add(len(triangles))
    me.polygons.foreach_set("loop_start", np.arange(0, triangles.size, 3, dtype=np.int32))
    me.update()


def read_mesh(me: bpy.types.Mesh) -> tuple[np.ndarray, np.ndarray]:
    """A Blender mesh of triangles as (positions float64 (n,3), triangles (m,3))."""
    pos = np.empty(len(me.vertices) * 3, dtype=np.float32)
    me.vertices.foreach_get("co", pos)
    idx = np.empty(len(me.loops), dtype=np.int32)
    me.loops.foreach_get("vertex_index", idx)
    return pos.astype(np.float64).reshape(-1, 3), idx.reshape(-1, 3)


def world_triangles(name: str = "") -> tuple[str, list, list]:
    """A Blender mesh object (by name; "" the selected mesh that is not a
    Shapewright object) as (name, world-space positions, triangles), its
    faces triangulated with the winding kept (flipped under a mirroring
    matrix, so triangles stay counter-clockwise seen from outside).
    Raises ValueError when there is no such mesh."""
    if name:
        obj = bpy.data.objects.get(name)
    else:
        obj = next((o for o in bpy.context.selected_objects if o.type == "MESH" and ID_PROP not in o), None)
    if obj is None or obj.type != "MESH":
        raise ValueError(
            f"no mesh object {name!r}" if name else "select a mesh that is not a Shapewright object"
        )
    me = obj.data
    me.calc_loop_triangles()
    pos = np.empty(len(me.vertices) * 3, dtype=np.float32)
    me.vertices.foreach_get("co", pos)
    m = np.array(obj.matrix_world, dtype=np.float64)
    world = pos.astype(np.float64).reshape(-1, 3) @ m[:3, :3].T + m[:3, 3]
    tri = np.empty(len(me.loop_triangles) * 3, dtype=np.int32)
    me.loop_triangles.foreach_get("vertices", tri)
    tri = tri.reshape(-1, 3)
    if np.linalg.det(m[:3, :3]) < 0:
        tri = tri[:, ::-1]
    return obj.name, world.tolist(), tri.tolist()


def object_for(scene: bpy.types.Scene, object_id: int) -> bpy.types.Object | None:
    for obj in collection(scene).objects:
        if obj.get(ID_PROP) == object_id:
            return obj
    return None


def shown_name(obj: bpy.types.Object) -> str | None:
    """The name the add-on last gave a Shapewright object in Blender."""
    return obj.get(SHOWN_PROP, obj.get(NAME_PROP))


def kind_of(obj: bpy.types.Object | None) -> str | None:
    """The core kind of a Shapewright object (None for other objects)."""
    if obj is None or ID_PROP not in obj:
        return None
    return obj.get(KIND_PROP)


def select_only(context, obj: bpy.types.Object) -> None:
    """Makes `obj` the active and only selected object (Blender's rule for
    new objects)."""
    view_layer = context.view_layer
    for o in view_layer.objects.selected:
        o.select_set(False)
    if obj.name in view_layer.objects:
        obj.select_set(True)
        view_layer.objects.active = obj


def _remove_object(obj: bpy.types.Object) -> None:
    data = obj.data
    bpy.data.objects.remove(obj)
    if data is not None and data.users == 0:
        if isinstance(data, bpy.types.Mesh):
            bpy.data.meshes.remove(data)
        elif isinstance(data, bpy.types.Curves):
            bpy.data.hair_curves.remove(data)


def sync_scene(scene: bpy.types.Scene, s: sw.Session) -> None:
    coll = collection(scene)
    existing = {obj[ID_PROP]: obj for obj in coll.objects if ID_PROP in obj}
    ids = s.object_ids()
    changed = []
    for object_id in ids:
        digest = format(s.object_hash(object_id), "016x")
        obj = existing.get(object_id)
        if obj is None:
            me = bpy.data.meshes.new(f"SW{object_id}")
            obj = bpy.data.objects.new(f"SW{object_id}", me)
            obj[ID_PROP] = object_id
            coll.objects.link(obj)
        if obj.get(KIND_PROP) is None:
            obj[KIND_PROP] = s.object_kind(object_id)
        # The core's name (`rename_object`) names the Blender object; a
        # rename in Blender becomes that op (`history.adopt_renames`).
        want = s.object_name(object_id) or f"SW{object_id}"
        if obj.get(NAME_PROP) != want:
            obj.name = want
            obj[NAME_PROP] = want
            obj[SHOWN_PROP] = obj.name
        if obj.get(HASH_PROP) != digest:
            pos, tri, _ = sw.mesh_arrays(s, object_id)
            write_mesh(obj.data, pos, tri)
            obj[HASH_PROP] = digest
            obj.matrix_world.identity()
            changed.append(object_id)
    for object_id, obj in existing.items():
        if object_id not in ids:
            _remove_object(obj)
    sync_parametric(scene, s, set(changed))


def _helpers(scene: bpy.types.Scene) -> dict[tuple[int, str], bpy.types.Object]:
    coll = bpy.data.collections.get(PARAMETRIC_COLLECTION)
    if coll is None:
        return {}
    return {(o[OWNER_PROP], o[PART_PROP]): o for o in coll.objects if OWNER_PROP in o and PART_PROP in o}


def curves_data(name: str, curves: list[dict]) -> bpy.types.Curves:
    """Blender `Curves` holding NURBS curves exactly: each curve's Bézier
    segments (with weights) in the ENDPOINT_BEZIER knot mode, whose knot
    vector is clamped with every interior knot of multiplicity order - 1."""
    cd = bpy.data.hair_curves.new(name)
    cd.add_curves([len(c["bezier_points"]) for c in curves])
    pos = np.array([p for c in curves for p in c["bezier_points"]], dtype=np.float32)
    cd.position_data.foreach_set("vector", pos.ravel())
    attrs = cd.attributes

    def attr(aname: str, dtype: str, domain: str, values) -> None:
        a = attrs.get(aname) or attrs.new(aname, dtype, domain)
        a.data.foreach_set("value", np.asarray(values))

    # Through the API, not the `curve_type` attribute: Blender caches the
    # count of each type, and a stale count crashes its evaluation.
    cd.set_types(type="NURBS")
    attr("nurbs_order", "INT8", "CURVE", np.array([c["order"] for c in curves], dtype=np.int8))
    attr("knots_mode", "INT8", "CURVE", np.full(len(curves), KNOTS_ENDPOINT_BEZIER, dtype=np.int8))
    weights = np.array([w for c in curves for w in c["bezier_weights"]], dtype=np.float32)
    attr("nurbs_weight", "FLOAT", "POINT", weights)
    radius = attrs.get("radius") or attrs.new("radius", "FLOAT", "POINT")
    radius.data.foreach_set("value", np.full(len(pos), 0.001, dtype=np.float32))
    return cd


def _helper_data(name: str, part: dict):
    if part["kind"] == "curves":
        return curves_data(name, part["curves"])
    me = bpy.data.meshes.new(name)
    pos = np.frombuffer(part["positions"], dtype="<f8").reshape(-1, 3)
    tri = np.frombuffer(part["triangles"], dtype="<u4").reshape(-1, 3)
    write_mesh(me, pos, tri)
    return me


def sync_parametric(scene: bpy.types.Scene, s: sw.Session, changed: set[int]) -> None:
    """Keeps the parametric helper objects in step with their owners (only
    owners in `changed`, or missing helpers, are rebuilt)."""
    helpers = _helpers(scene)
    show = scene.shapewright.show_parametric
    ids = set(s.object_ids()) if show else set()
    wanted: set[tuple[int, str]] = set()
    if show:
        coll = None
        for object_id in sorted(ids):
            if s.object_kind(object_id) not in ("gc_assembly", "curve_network"):
                continue
            owner = object_for(scene, object_id)
            parts = None
            for key in [k for k in helpers if k[0] == object_id]:
                wanted.add(key)
            if object_id in changed or not any(k[0] == object_id for k in helpers):
                parts = sw.parametric_parts(s, object_id)
                wanted = {k for k in wanted if k[0] != object_id}
                for part in parts:
                    key = (object_id, part["name"])
                    wanted.add(key)
                    old = helpers.pop(key, None)
                    if old is not None:
                        _remove_object(old)
                    coll = coll or collection(scene, PARAMETRIC_COLLECTION)
                    name = f"SW{object_id}_{part['name']}"
                    obj = bpy.data.objects.new(name, _helper_data(name, part))
                    obj[OWNER_PROP] = object_id
                    obj[PART_PROP] = part["name"]
                    obj.display_type = "WIRE" if part["kind"] == "patch" else "TEXTURED"
                    coll.objects.link(obj)
                    if owner is not None:
                        obj.parent = owner
    for key, obj in helpers.items():
        if key not in wanted:
            _remove_object(obj)
