"""Core meshes into Blender meshes, with `foreach_set` (no Python loops over
vertices). Each core object is a mesh object in the "Shapewright"
collection carrying its core id; only objects whose content hash changed
are rewritten."""

from __future__ import annotations

import bpy
import numpy as np
import shapewright as sw

COLLECTION = "Shapewright"
ID_PROP = "shapewright_id"
HASH_PROP = "shapewright_hash"


def collection(scene: bpy.types.Scene) -> bpy.types.Collection:
    coll = bpy.data.collections.get(COLLECTION)
    if coll is None:
        coll = bpy.data.collections.new(COLLECTION)
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


def object_for(scene: bpy.types.Scene, object_id: int) -> bpy.types.Object | None:
    for obj in collection(scene).objects:
        if obj.get(ID_PROP) == object_id:
            return obj
    return None


def sync_scene(scene: bpy.types.Scene, s: sw.Session) -> None:
    coll = collection(scene)
    existing = {obj[ID_PROP]: obj for obj in coll.objects if ID_PROP in obj}
    ids = s.object_ids()
    for object_id in ids:
        digest = format(s.object_hash(object_id), "016x")
        obj = existing.get(object_id)
        if obj is None:
            me = bpy.data.meshes.new(f"SW{object_id}")
            obj = bpy.data.objects.new(f"SW{object_id}", me)
            obj[ID_PROP] = object_id
            coll.objects.link(obj)
        if obj.get(HASH_PROP) != digest:
            pos, tri, _ = sw.mesh_arrays(s, object_id)
            write_mesh(obj.data, pos, tri)
            obj[HASH_PROP] = digest
            obj.matrix_world.identity()
    for object_id, obj in existing.items():
        if object_id not in ids:
            me = obj.data
            bpy.data.objects.remove(obj)
            if me is not None and me.users == 0:
                bpy.data.meshes.remove(me)
