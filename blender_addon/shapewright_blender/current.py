"""What an edit's form starts from: the object's current values, so an
operator run without typing anything changes nothing ("Mesh Resolution"
used to drop a GC from 12,480 triangles to 40; "Set Placement" sent an
object to the origin). Each entry reads the current values of one op's
fields from the core (`Session.object_params`, `Session.object_transform`)
and gives them as the form shows them (the scene's units, Euler
rotations); only the properties a caller did not set are filled.
"""

from __future__ import annotations

from collections.abc import Callable

from . import history, run, units


def _euler(rotate) -> tuple[float, float, float]:
    from mathutils import Quaternion

    x, y, z, w = rotate
    e = Quaternion((w, x, y, z)).to_euler()
    return (e.x, e.y, e.z)


def _placement(scene, s, oid, _operator) -> dict:
    t = s.object_transform(oid)
    return {
        "transform_translate": tuple(units.to_units(scene, list(t.translate))),
        "transform_rotate": _euler(t.rotate),
        "transform_scale": tuple(t.scale),
    }


def _part(s, oid, operator) -> dict:
    parts = s.object_params(oid).get("parts", [])
    k = getattr(operator, "part", 0)
    return parts[k]["gc"] if 0 <= k < len(parts) else {}


def _resolution(scene, s, oid, operator) -> dict:
    r = _part(s, oid, operator).get("resolution", {})
    return {f"resolution_{k}": v for k, v in r.items()}


def _shape_type(scene, s, oid, operator) -> dict:
    shape = _part(s, oid, operator).get("shape", {})
    out = {"shape_type": shape.get("type")}
    if "thickness" in shape:
        out["thickness"] = units.to_units(scene, shape["thickness"])
    if "closed_end" in shape:
        out["closed_end"] = shape["closed_end"]
    return {k: v for k, v in out.items() if v is not None}


def _step(scene, s, oid, _operator) -> dict:
    step = s.object_params(oid).get("step")
    return {} if step is None else {"step": units.to_units(scene, step)}


CURRENT: dict[str, Callable] = {
    "set_transform": _placement,
    "gc_set_resolution": _resolution,
    "gc_set_shape": _shape_type,
    "sdf_set_step": _step,
}
TARGETS = ("id", "volume")


def fill(operator, context, op: str, _fields=None) -> None:
    """Sets the properties of `operator` the caller did not set to the
    target object's current values (see the module doc)."""
    read = CURRENT.get(op)
    if read is None:
        return
    props = operator.properties
    target = next((t for t in TARGETS if t in props.bl_rna.properties), None)
    oid = getattr(operator, target) if target else -1
    if oid is None or oid < 0:
        oid = run.active_id(context)
    if oid is None:
        return
    s = history.session(context.scene)
    if oid not in s.object_ids():
        return
    for name, value in read(context.scene, s, oid, operator).items():
        if name in props.bl_rna.properties and not props.is_property_set(name):
            setattr(operator, name, value)
