"""Running an op from an operator: the active object and the selection,
the op applied (or refused with the core's message in the status bar),
and the object it created made the active and only selected one."""

from __future__ import annotations

import shapewright as sw

from . import history, sync


def active_id(context) -> int | None:
    obj = context.active_object
    oid = obj.get(sync.ID_PROP) if obj is not None else None
    return int(oid) if oid is not None else None


def active_kind(context) -> str | None:
    return sync.kind_of(context.active_object)


def selected_ids(context, kind: str | None = None) -> list[int]:
    """Ids of the selected Shapewright objects (of `kind`), the active one
    first; the active object counts even when not selected."""
    objs = [context.active_object] if context.active_object is not None else []
    objs += [o for o in context.selected_objects if o is not context.active_object]
    out = []
    for o in objs:
        oid = o.get(sync.ID_PROP)
        if oid is not None and oid not in out and (kind is None or sync.kind_of(o) == kind):
            out.append(int(oid))
    return out


def scene_has_kind(context, kind: str) -> bool:
    scene = context.scene
    return scene is not None and any(sync.kind_of(o) == kind for o in scene.objects if sync.ID_PROP in o)


def run_op(operator, context, op: dict | sw.Built | list[dict | sw.Built]) -> set[str]:
    """Applies `op` (a form's built ops, or a list of them, all or none;
    an op dict where Blender itself made the op) to the scene; reports
    the core's message if it is refused. A created object becomes the
    active and only selected one."""
    scene = context.scene
    try:
        if isinstance(op, list):
            created = history.apply_all(scene, op)
        else:
            created = history.apply(scene, op)
    except sw.ShapewrightError as e:
        operator.report({"ERROR"}, str(e))
        return {"CANCELLED"}
    if created is not None:
        obj = sync.object_for(scene, created)
        if obj is not None:
            sync.select_only(context, obj)
    return {"FINISHED"}


def redraw() -> None:
    history.tag_redraw()
