"""Core objects into Blender objects, with `foreach_set` (no Python loops
over vertices). Each core object is a mesh object (in the "Shapewright"
collection when the add-on makes it) carrying its core id and kind, named
by the core's name (`rename_object`) or `SW<id>`.

Origins. A Blender object's origin is the core's (`Session.object_origin`,
`shapewright::doc::Object::origin`): a solid's or sculpt's own transform
(its centre, rotation and scale), or, for GC assemblies, SDF volumes and
curve networks, their placement at the centre of their geometry's
bounding box. The object's matrix is that origin and its mesh is the
core's mesh in that frame (`mesh_buffers(id, "origin")`), so R and S
pivot about the object's own centre, the N panel shows its rotation and
scale, and Blender's USD export writes the same placement the core's
does. Both are in the scene's units (`units.py`).

Only what changed is rewritten: a mesh when the core's key of its
origin-frame mesh (`Session.shape_key`, with the scene's units) differs
from the one stored on the mesh datablock (stored on the mesh, not the
object, so whatever Blender's undo restores or keeps, the mesh and its
key travel together); a matrix when the core's origin differs from the
one last placed (stored on the object), so an edit Blender made that is
not recorded yet is never overwritten by a sync.

With the scene's "Show parametric parts" on, the parametric data of GC
assemblies and curve networks (the same `NurbsCurves` / `NurbsPatch` data
the USD files carry) are shown as helper objects in the "Shapewright
parametric" collection, parented to their owner: curves as Blender
`Curves` with exact knots (the core's Bézier segments in the
`ENDPOINT_BEZIER` knot mode) and patches as meshes. They are rebuilt when
their owner's shape changes and removed with it.
"""

from __future__ import annotations

import bpy
import numpy as np
import shapewright as sw
from mathutils import Matrix

from . import units

COLLECTION = "Shapewright"
PARAMETRIC_COLLECTION = "Shapewright parametric"
ID_PROP = "shapewright_id"
KIND_PROP = "shapewright_kind"
OWNER_PROP = "shapewright_owner"
PART_PROP = "shapewright_parametric"
NAME_PROP = "shapewright_name"
# On the mesh datablock: the key of the mesh written (core shape key and
# the scene's units), and a sample of it to notice edits made elsewhere.
SHAPE_PROP = "shapewright_shape"
CHECK_PROP = "shapewright_check"
# On the object: the core origin last placed (translate, rotate, scale).
ORIGIN_PROP = "shapewright_origin"
# The Blender name the add-on last gave the object (Blender may add a
# `.001` suffix to the core's name); a different name is a rename made in
# Blender, which `adopt.py` turns into a `rename_object` op.
SHOWN_PROP = "shapewright_shown_name"
# Vertices sampled to notice a mesh edited outside the add-on.
SAMPLES = 512

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


def _check(me: bpy.types.Mesh) -> str:
    """Counts and a sample of the mesh's vertices: what `mesh_is_current`
    compares (a full read of a big mesh on every depsgraph update would
    cost the UI)."""
    n = len(me.vertices)
    picks = range(0, n, max(1, n // SAMPLES))
    verts = me.vertices
    sample = tuple(round(c, 5) for i in picks for c in verts[i].co)
    return f"{n}:{len(me.polygons)}:{hash(sample):x}"


def mesh_is_current(obj: bpy.types.Object) -> bool:
    """Whether the object's mesh is still the one the add-on wrote."""
    me = obj.data
    stored = me.get(CHECK_PROP) if me is not None else None
    return stored is None or stored == _check(me)


def world_triangles(name: str = "") -> tuple[str, list, list]:
    """A Blender mesh object (by name; "" the selected mesh that is not a
    Shapewright object) as (name, world-space positions in metres,
    triangles), its faces triangulated with the winding kept (flipped
    under a mirroring matrix, so triangles stay counter-clockwise seen
    from outside). Raises ValueError when there is no such mesh."""
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
    world *= units.metres_per_unit(bpy.context.scene)
    tri = np.empty(len(me.loop_triangles) * 3, dtype=np.int32)
    me.loop_triangles.foreach_get("vertices", tri)
    tri = tri.reshape(-1, 3)
    if np.linalg.det(m[:3, :3]) < 0:
        tri = tri[:, ::-1]
    return obj.name, world.tolist(), tri.tolist()


def by_id(scene: bpy.types.Scene) -> dict[int, list[bpy.types.Object]]:
    """The scene's Shapewright objects by core id (two or more: copies
    Blender made that the add-on has not taken yet)."""
    out: dict[int, list] = {}
    for obj in scene.objects:
        oid = obj.get(ID_PROP)
        if oid is not None:
            out.setdefault(int(oid), []).append(obj)
    return out


def object_for(scene: bpy.types.Scene, object_id: int) -> bpy.types.Object | None:
    objs = by_id(scene).get(object_id)
    if not objs:
        return None
    return next((o for o in objs if o.name == shown_name(o)), objs[0])


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
    new objects), linking the add-on's collection into the view layer's
    scene if a new file left it out."""
    view_layer = context.view_layer
    for o in view_layer.objects.selected:
        o.select_set(False)
    if obj.name not in view_layer.objects:
        collection(context.scene)
        for layer_coll in view_layer.layer_collection.children:
            if layer_coll.collection.name == COLLECTION:
                layer_coll.exclude = False
    if obj.name in view_layer.objects:
        obj.hide_set(False)
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


def _origin_tuple(origin: sw.Placement) -> tuple:
    return (*origin.translate, *origin.rotate, *origin.scale)


def place(scene, obj: bpy.types.Object, origin: sw.Placement) -> None:
    """Puts the object's origin at the core's `origin` (scene units)."""
    rows = origin.matrix(units.units_per_metre(scene))
    obj.matrix_world = Matrix(rows)
    obj[ORIGIN_PROP] = _origin_tuple(origin)


def _shape_key(s: sw.Session, oid: int, k: float) -> str:
    return f"{s.shape_key(oid)}@{k:.17g}"


def rewrite(scene, s: sw.Session, obj: bpy.types.Object, oid: int) -> None:
    """Writes the core's mesh of `oid` (origin frame, scene units) into the
    object's mesh datablock (its own, if Blender shared it)."""
    k = units.units_per_metre(scene)
    me = obj.data
    if me.users > 1:
        me = obj.data = me.copy()
    pos, tri, _ = sw.mesh_arrays(s, oid, frame="origin", units_per_metre=k)
    write_mesh(me, pos, tri)
    me[SHAPE_PROP] = _shape_key(s, oid, k)
    me[CHECK_PROP] = _check(me)


def adopt_object(obj: bpy.types.Object, oid: int) -> None:
    """Makes a copy Blender made (Shift-D) the object of core id `oid`:
    its name and origin are then the core's at the next sync."""
    obj[ID_PROP] = oid
    for prop in (NAME_PROP, SHOWN_PROP, ORIGIN_PROP):
        if prop in obj:
            del obj[prop]
    if obj.data is not None and obj.data.users > 1:
        obj.data = obj.data.copy()


def sync_scene(scene: bpy.types.Scene, s: sw.Session) -> None:
    """Blender's objects follow the session: made, renamed, rewritten,
    placed and removed as the document says (see the module doc)."""
    k = units.units_per_metre(scene)
    found = by_id(scene)
    ids = s.object_ids()
    changed = set()
    coll = None
    for oid in ids:
        objs = found.get(oid)
        if objs:
            # Several: copies not taken yet; the original is ours.
            obj = next((o for o in objs if o.name == shown_name(o)), objs[0])
        else:
            coll = coll or collection(scene)
            me = bpy.data.meshes.new(f"SW{oid}")
            obj = bpy.data.objects.new(f"SW{oid}", me)
            obj[ID_PROP] = oid
            coll.objects.link(obj)
        if obj.get(KIND_PROP) is None:
            obj[KIND_PROP] = s.object_kind(oid)
        # The core's name names the Blender object; a rename in Blender
        # becomes that op (`adopt.py`).
        want = s.object_name(oid) or f"SW{oid}"
        if obj.get(NAME_PROP) != want:
            obj.name = want
            obj[NAME_PROP] = want
            obj[SHOWN_PROP] = obj.name
        if obj.data is None or obj.data.get(SHAPE_PROP) != _shape_key(s, oid, k) or obj.data.users > 1:
            rewrite(scene, s, obj, oid)
            changed.add(oid)
        origin = s.object_origin(oid)
        if tuple(obj.get(ORIGIN_PROP, ())) != _origin_tuple(origin) or oid in changed:
            place(scene, obj, origin)
    for oid, objs in found.items():
        if oid not in ids:
            for obj in objs:
                _remove_object(obj)
    sync_parametric(scene, s, changed)
    _units_seen[scene.name] = k


_units_seen: dict[str, float] = {}


def follow_units(scene: bpy.types.Scene) -> None:
    """Re-syncs a scene whose unit scale changed (meshes and origins are
    in its units)."""
    k = units.units_per_metre(scene)
    seen = _units_seen.get(scene.name)
    if seen is not None and seen != k:
        from . import history

        sync_scene(scene, history.session(scene))


def _helpers(scene: bpy.types.Scene) -> dict[tuple[int, str], bpy.types.Object]:
    coll = bpy.data.collections.get(PARAMETRIC_COLLECTION)
    if coll is None:
        return {}
    return {(o[OWNER_PROP], o[PART_PROP]): o for o in coll.objects if OWNER_PROP in o and PART_PROP in o}


def curves_data(name: str, curves: list[dict], to_local) -> bpy.types.Curves:
    """Blender `Curves` holding NURBS curves exactly: each curve's Bézier
    segments (with weights) in the ENDPOINT_BEZIER knot mode, whose knot
    vector is clamped with every interior knot of multiplicity order - 1.
    `to_local` maps the core's points (n, 3) into the owner's frame."""
    cd = bpy.data.hair_curves.new(name)
    cd.add_curves([len(c["bezier_points"]) for c in curves])
    pos = to_local(np.array([p for c in curves for p in c["bezier_points"]], dtype=np.float64))
    cd.position_data.foreach_set("vector", pos.astype(np.float32).ravel())
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


def _helper_data(name: str, part: dict, to_local):
    if part["kind"] == "curves":
        return curves_data(name, part["curves"], to_local)
    me = bpy.data.meshes.new(name)
    pos = to_local(np.frombuffer(part["positions"], dtype="<f8").reshape(-1, 3))
    tri = np.frombuffer(part["triangles"], dtype="<u4").reshape(-1, 3)
    write_mesh(me, pos, tri)
    return me


def _own_to_local(scene, s: sw.Session, oid: int):
    """Maps points of an object's own frame (metres; what `parametric_parts`
    gives) into its Blender object's local frame (origin frame, units)."""
    k = units.units_per_metre(scene)
    origin = np.array(s.object_origin(oid).matrix(), dtype=np.float64)
    placed = np.array(s.object_transform(oid).matrix(), dtype=np.float64)
    m = np.linalg.inv(origin) @ placed

    def to_local(p: np.ndarray) -> np.ndarray:
        return (p @ m[:3, :3].T + m[:3, 3]) * k

    return to_local


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
            for key in [k for k in helpers if k[0] == object_id]:
                wanted.add(key)
            if object_id in changed or not any(k[0] == object_id for k in helpers):
                parts = sw.parametric_parts(s, object_id)
                to_local = _own_to_local(scene, s, object_id)
                wanted = {k for k in wanted if k[0] != object_id}
                for part in parts:
                    key = (object_id, part["name"])
                    wanted.add(key)
                    old = helpers.pop(key, None)
                    if old is not None:
                        _remove_object(old)
                    coll = coll or collection(scene, PARAMETRIC_COLLECTION)
                    name = f"SW{object_id}_{part['name']}"
                    obj = bpy.data.objects.new(name, _helper_data(name, part, to_local))
                    obj[OWNER_PROP] = object_id
                    obj[PART_PROP] = part["name"]
                    obj.display_type = "WIRE" if part["kind"] == "patch" else "TEXTURED"
                    obj.hide_select = True
                    coll.objects.link(obj)
                    if owner is not None:
                        obj.parent = owner
    for key, obj in helpers.items():
        if key not in wanted:
            _remove_object(obj)
