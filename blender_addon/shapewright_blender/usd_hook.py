"""Blender's own USD export and import carry the Shapewright document
(issue 20; ARCHITECTURE.md "USD mapping").

Export (`on_export`, File > Export > USD): when the scene has a Shapewright
log, the stage Blender is about to save gets what Shapewright's own usda
has (`shapewright.usd_text`, copied spec by spec with `Sdf.CopySpec`):
- the log prim `ShapewrightLog` (ops, cursor, snapshot), under Blender's
  root prim (the stage's default prim, `/root` unless the user changed
  it), so it travels with the default prim when the file is referenced;
- on each Shapewright object's prim, `shapewright:objectId` and
  `shapewright:kind`, and next to Blender's mesh the object's parametric
  prims (GC spines, key sections and skins as `NurbsCurves` /
  `NurbsPatch` with their own knots; curve-network curves and patches),
  each with the transform that puts it where the mesh is (Blender's prim
  carries the object's origin in the stage's units; ours are in the
  object's own frame in metres).
Blender's prims for the add-on's parametric helper objects are removed:
the exact prims are ours.

Import (`on_import`, File > Import > USD): when the stage holds a
Shapewright log (any root prim), the document is restored with its
history through `shapewright-usd` (which finds the log and the object
prims wherever Blender put them). The objects Blender's importer made for
Shapewright prims become the add-on's objects (their meshes rewritten from
the log), the prims Blender cannot show exactly (NURBS curves with their
knots, patches) are dropped and shown again as the add-on's helper
objects, built from the same data (curves with their exact shape,
patches as meshes). The import is the new start of the scene's history
for the panel's Undo. A scene that already has a Shapewright document
keeps it; the file's objects then stay plain Blender objects.

Blender's USD Python module (`pxr`) must be Blender's own: Blender hands
the hook a stage of its USD build. Inside Blender it is the `pxr` on
`sys.path`; with `bpy` as a Python module (tests) a separately installed
`usd-core` may shadow it, so `blender_pxr` loads Blender's from its
resource folder instead, and `_make_pxr_importable` lets Blender's C++
side find it where `bpy` 5.2 keeps it off `sys.path`.
"""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path

import bpy
import shapewright as sw

from . import adopt, history, notify, sync, units

LOG_PRIM = "ShapewrightLog"
SRC_WORLD = "/World"

# What the last import found (for the panel and tests): the scene, the
# log prim's path, the consistency report's lines and whether the objects
# were adopted.
last_import: dict = {}


def _bundled_pxr() -> Path | None:
    """Blender's own `pxr` package, when Blender ships one."""
    py = f"python{sys.version_info.major}.{sys.version_info.minor}"
    pkg = Path(bpy.utils.resource_path("LOCAL")) / "python" / "lib" / py / "site-packages" / "pxr"
    return pkg if (pkg / "__init__.py").is_file() else None


def blender_pxr():
    """(Sdf, Usd, Tf) of Blender's USD build. When another `pxr` (usd-core,
    first on `sys.path` of a `bpy` module install) was imported instead,
    its modules are set aside and Blender's are loaded: Blender's stage
    objects convert only to its own classes."""
    pkg = _bundled_pxr()
    loaded = sys.modules.get("pxr")
    if pkg is not None and (loaded is None or Path(getattr(loaded, "__file__", "")).parent != pkg):
        for name in [m for m in sys.modules if m == "pxr" or m.startswith("pxr.")]:
            del sys.modules[name]
        spec = importlib.util.spec_from_file_location(
            "pxr", pkg / "__init__.py", submodule_search_locations=[str(pkg)]
        )
        if spec is not None and spec.loader is not None:
            mod = importlib.util.module_from_spec(spec)
            sys.modules["pxr"] = mod
            spec.loader.exec_module(mod)
    from pxr import Sdf, Tf, Usd

    return Sdf, Usd, Tf


def _stage(context_obj):
    try:
        return context_obj.get_stage()
    except TypeError as e:
        raise RuntimeError(
            "Shapewright's USD hook needs Blender's own USD Python module, but another `pxr` "
            f"(e.g. from the usd-core package) is loaded in this Python: {e}"
        ) from e


def _object_prims(stage, Sdf, Tf, scene) -> dict[int, object]:
    """Shapewright object id -> the Xform prim Blender exported it as:
    by the custom property Blender writes (`userProperties:shapewright_id`),
    else by the object's name under the root prim."""
    found: dict[int, object] = {}
    for prim in stage.Traverse():
        attr = prim.GetAttribute("userProperties:shapewright_id")
        if attr and attr.HasAuthoredValue():
            found.setdefault(int(attr.Get()), prim)
    if found:
        return found
    root = stage.GetDefaultPrim()
    base = root.GetPath() if root else Sdf.Path.absoluteRootPath
    for obj in scene.objects:
        oid = obj.get(sync.ID_PROP)
        if oid is None:
            continue
        for name in (obj.name, Tf.MakeValidIdentifier(obj.name)):
            prim = stage.GetPrimAtPath(base.AppendChild(name))
            if prim:
                found[oid] = prim
                break
    return found


def export_document(stage, depsgraph) -> bool:
    """Adds the scene's Shapewright document to a stage Blender exports."""
    Sdf, Usd, Tf = blender_pxr()
    scene = depsgraph.scene
    if scene is None or not history.has_document(scene):
        return True
    s = history.session(scene)
    src = Sdf.Layer.CreateAnonymous("shapewright.usda")
    if not src.ImportFromString(sw.usd_text(s)):
        raise RuntimeError("Shapewright: the document's usda did not parse")
    dst = stage.GetEditTarget().GetLayer()
    root = stage.GetDefaultPrim()
    base = root.GetPath() if root else Sdf.Path.absoluteRootPath
    if not Sdf.CopySpec(src, Sdf.Path("/" + LOG_PRIM), dst, base.AppendChild(LOG_PRIM)):
        raise RuntimeError("Shapewright: could not write the log prim")
    prims = _object_prims(stage, Sdf, Tf, scene)
    moved = []
    for oid, prim in prims.items():
        src_obj = Sdf.Path(f"{SRC_WORLD}/Object_{oid}")
        spec = src.GetPrimAtPath(src_obj)
        if spec is None:
            continue  # a Blender object with a stale id: not in the document
        path = prim.GetPath()
        for prop in ("shapewright:objectId", "shapewright:kind"):
            Sdf.CopySpec(src, src_obj.AppendProperty(prop), dst, path.AppendProperty(prop))
        obj = sync.object_for(scene, oid)
        frame = _part_frame(scene, s, oid, obj)
        for child in spec.nameChildren:
            if child.name != "Mesh":
                Sdf.CopySpec(src, child.path, dst, path.AppendChild(child.name))
                _set_transform(dst, path.AppendChild(child.name), frame, Sdf)
    moved = [obj.name for _, obj in adopt.moved(scene, s)]
    _drop_helper_prims(stage, Tf)
    if moved:
        print(
            "Shapewright: objects moved in Blender but not committed as ops "
            f"(the log places them elsewhere): {', '.join(moved)}"
        )
    return True


def _drop_helper_prims(stage, Tf) -> None:
    """Removes the prims Blender wrote for the add-on's parametric helper
    objects (found by their custom property, else by name)."""
    coll = bpy.data.collections.get(sync.PARAMETRIC_COLLECTION)
    names = set()
    for obj in coll.objects if coll is not None else ():
        names |= {obj.name, Tf.MakeValidIdentifier(obj.name)}
    doomed = []
    for prim in stage.Traverse():
        tag = prim.GetAttribute(f"userProperties:{sync.PART_PROP}")
        if (tag and tag.HasAuthoredValue()) or (names and prim.GetName() in names):
            doomed.append(prim.GetPath())
    for path in doomed:
        stage.RemovePrim(path)


def _part_frame(scene, s, oid: int, obj) -> list[list[float]]:
    """The transform (rows) that puts a parametric prim (the object's own
    frame, metres) under Blender's prim of the object (its origin, scene
    units): Blender's matrix undone, metres to units, the object's
    placement."""
    import numpy as np

    k = units.units_per_metre(scene)
    placed = np.array(s.object_transform(oid).matrix(), dtype=np.float64)
    to_units = np.diag([k, k, k, 1.0])
    world = np.array(obj.matrix_world, dtype=np.float64) if obj is not None else np.eye(4)
    return (np.linalg.inv(world) @ to_units @ placed).tolist()


def _set_transform(layer, path, rows, Sdf) -> None:
    """Authors `xformOp:transform` (USD's row-vector convention: the
    transpose of `rows`) on the prim spec at `path`."""
    from pxr import Gf

    spec = layer.GetPrimAtPath(path)
    if spec is None:
        return
    m = Gf.Matrix4d(*[rows[j][i] for i in range(4) for j in range(4)])
    attr = spec.attributes.get("xformOp:transform") or Sdf.AttributeSpec(
        spec, "xformOp:transform", Sdf.ValueTypeNames.Matrix4d
    )
    attr.default = m
    order = spec.attributes.get("xformOpOrder") or Sdf.AttributeSpec(
        spec, "xformOpOrder", Sdf.ValueTypeNames.TokenArray, Sdf.VariabilityUniform
    )
    order.default = ["xformOp:transform"]


def _find_log(stage):
    for prim in stage.TraverseAll():
        if prim.GetName() == LOG_PRIM and prim.GetAttribute("shapewright:ops"):
            return prim
    return None


def import_document(stage, prim_map: dict) -> bool:
    """Restores the Shapewright document of a stage Blender imported.

    Runs inside Blender's import job, which still holds (and afterwards
    selects) the objects it made: only the scene's properties change here
    (the log, the cursor, and `import_fixup`, the objects to adopt and to
    drop, all part of the import's undo step). `finish_import` does the
    object work right after the job (a timer; and whenever the add-on runs
    next, and after undo/redo return to the import's state)."""
    Sdf, Usd, Tf = blender_pxr()
    log_prim = _find_log(stage)
    if log_prim is None:
        return True
    scene = bpy.context.scene
    imported = {str(k): list(v) for k, v in prim_map.items()}
    layer = next((sp.layer for sp in log_prim.GetPrimStack() if sp.layer), None)
    real = layer.realPath if layer is not None else ""
    if real and Path(real).is_file():
        s, report = sw.import_usd(real)
    else:
        s, report = sw.import_usd_text(layer.ExportToString())
    last_import.clear()
    last_import.update(scene=scene.name, log=str(log_prim.GetPath()), report=report, adopted=False)
    if history.has_document(scene):
        notify.warn(
            f"{scene.name} already has a document; the imported file's objects stay plain Blender "
            "objects (import it into an empty scene to edit its history)"
        )
        return True

    def names(path) -> list[str]:
        return [i.name for i in imported.get(str(path), []) if isinstance(i, bpy.types.Object)]

    drop = names(log_prim.GetPath())
    adopt: dict[int, str] = {}
    has_parametric = False
    for prim in stage.TraverseAll():
        attr = prim.GetAttribute("shapewright:objectId")
        if not (attr and attr.HasAuthoredValue()):
            continue
        oid = int(attr.Get())
        # Blender merges an Xform with one Mesh child into one mesh object;
        # with our parametric prims beside the mesh it makes an empty for
        # the Xform and a mesh object for the Mesh prim: adopt the mesh.
        meshes = [n for n in names(prim.GetPath()) if bpy.data.objects[n].type == "MESH"]
        for child in prim.GetChildren():
            if child.GetTypeName() == "Mesh":
                meshes += [n for n in names(child.GetPath()) if bpy.data.objects[n].type == "MESH"]
            elif child.GetTypeName() in ("NurbsCurves", "NurbsPatch", "BasisCurves"):
                has_parametric = True
                drop += names(child.GetPath())
        if meshes and oid not in adopt:
            adopt[oid] = meshes[0]
            drop += [n for n in names(prim.GetPath()) if n != meshes[0]]
    # Prims that only group ours (our `/World`) came in as empties.
    world = stage.GetPrimAtPath(SRC_WORLD)
    if world and not world.HasAttribute("shapewright:objectId"):
        drop += [n for n in names(SRC_WORLD) if bpy.data.objects[n].type == "EMPTY"]
    props = scene.shapewright
    history.adopt_session(scene, s)
    history.write_key(scene, history.session_key(s))
    props.gen = history._next_gen(scene)
    props.import_fixup = json.dumps(
        {"adopt": {str(k): v for k, v in adopt.items()}, "drop": drop, "parametric": has_parametric}
    )
    history.mark_base(scene)
    if not bpy.app.timers.is_registered(finish_imports):
        bpy.app.timers.register(finish_imports, first_interval=0.0)
    if report:
        notify.warn(
            f"the file's stored geometry differs from its log (rebuilt from the log): {'; '.join(report)}"
        )
    return True


def finish_import(scene: bpy.types.Scene) -> None:
    """The object work of an import (see `import_document`): Blender's
    objects for Shapewright prims become the add-on's, the objects standing
    in for the log and for parametric prims go, and the meshes are synced
    from the log (with the parametric parts shown exactly)."""
    props = scene.shapewright
    if not props.import_fixup:
        return
    fix = json.loads(props.import_fixup)
    props.import_fixup = ""
    coll = sync.collection(scene)
    adopted = []
    for oid, name in fix["adopt"].items():
        obj = bpy.data.objects.get(name)
        if obj is None:
            continue
        mw = obj.matrix_world.copy()
        obj.parent = None
        obj.matrix_world = mw
        obj[sync.ID_PROP] = int(oid)
        # Blender's importer brings our custom properties back; the name
        # props go too, so the log's name names the object (a prim name is
        # a valid identifier: "My mug" came in as "My_mug").
        for prop in (sync.KIND_PROP, sync.NAME_PROP, sync.SHOWN_PROP, sync.ORIGIN_PROP):
            if prop in obj:
                del obj[prop]
        for prop in (sync.SHAPE_PROP, sync.CHECK_PROP):
            if obj.data is not None and prop in obj.data:
                del obj.data[prop]
        for c in list(obj.users_collection):
            c.objects.unlink(obj)
        coll.objects.link(obj)
        adopted.append(obj)
    doomed = list(fix["drop"])
    # Stale ids from another document would collide with this one's.
    doomed += [o.name for o in scene.objects if sync.ID_PROP in o and o not in adopted]
    for name in dict.fromkeys(doomed):
        obj = bpy.data.objects.get(name)
        if obj is None or obj in adopted:
            continue
        for child in obj.children:
            mw = child.matrix_world.copy()
            child.parent = None
            child.matrix_world = mw
        sync._remove_object(obj)
    if fix["parametric"] and not props.show_parametric:
        props.show_parametric = True  # its update syncs
    sync.sync_scene(scene, history.session(scene))
    if last_import.get("scene") == scene.name:
        last_import["adopted"] = True


def finish_imports() -> None:
    """`finish_import` for every scene that has one pending (a timer)."""
    for scene in bpy.data.scenes:
        if scene.shapewright.import_fixup:
            finish_import(scene)
    return None


class SHAPEWRIGHT_USD_hook(bpy.types.USDHook):
    """Carries the Shapewright document through Blender's USD export and import"""

    bl_idname = "shapewright_usd"
    bl_label = "Shapewright document"
    bl_description = "Writes and reads the Shapewright op log and parametric prims"

    @staticmethod
    def on_export(export_context):
        blender_pxr()
        return export_document(_stage(export_context), export_context.get_depsgraph())

    @staticmethod
    def on_import(import_context):
        blender_pxr()
        return import_document(_stage(import_context), import_context.get_prim_map())


def _make_pxr_importable() -> None:
    """`bpy` 5.2 as a Python module keeps its own site-packages (where its
    `pxr` is) off `sys.path`; Blender's C++ side of the USD hooks then
    fails to import `pxr` and aborts the process on the first USD export
    or import. Appending that folder (last, so nothing is shadowed) lets
    the import find Blender's own `pxr`. Blender itself has it on the path
    already, and a `pxr` found elsewhere is left as it is."""
    pkg = _bundled_pxr()
    if pkg is None or importlib.util.find_spec("pxr") is not None:
        return
    site = str(pkg.parent)
    if site not in sys.path:
        sys.path.append(site)


classes = (SHAPEWRIGHT_USD_hook,)

_register, _unregister = bpy.utils.register_classes_factory(classes)

# Why the hook is not registered in this Blender ("" when it is).
unavailable = ""


def register() -> None:
    """Registers the hook when Blender's `pxr` can be imported. Blender's
    C++ side imports `pxr.Usd` before it calls any hook, and an import
    error there is not caught: it ends the process
    (`boost::python::error_already_set`) on the first USD export or
    import. `bpy` 4.2 from PyPI ships no `pxr` at all; there the hook is
    left out (USD export and import then work without the document)."""
    global unavailable
    _make_pxr_importable()
    if importlib.util.find_spec("pxr") is None:
        unavailable = (
            f"Blender {bpy.app.version_string} has no USD Python module (pxr): "
            "File > Export/Import > USD will not carry the Shapewright document"
        )
        print(f"Shapewright: {unavailable}")
        return
    unavailable = ""
    _register()


def unregister() -> None:
    if not unavailable:
        _unregister()
