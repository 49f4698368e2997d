"""Where Blender users look (issue 34): Shift-A, File > Export, the
context menu and Object > Shapewright reach every operator (so F3 finds
each as "Shapewright: ..."), no label repeats one of Blender's own, every
field a person types is a typed property (JSON only for recorded
strokes), and buttons that change an object start from its current
values."""

from __future__ import annotations

from pathlib import Path

import bpy
import numpy as np
from helpers import add_solid, core_session, core_world, select_only, step, sw_objects

CLASHES = {"Delete", "Duplicate", "Join", "Undo", "Redo", "Draw Curve"}
# String properties that are not typed values: file paths, names, a
# pasted script line, and recorded strokes (JSON by design).
# A picked loop's pieces are "curve from to" triples (no Blender property
# holds a list of triples).
STRINGS_OK = {"filepath", "filter_glob", "name", "mesh", "op_json", "points", "tool", "pieces"}


class FakeLayout:
    """Records what a menu's `draw` puts in it."""

    def __init__(self) -> None:
        self.operators: list[str] = []
        self.menus: list[str] = []
        self.operator_context = "INVOKE_DEFAULT"

    def operator(self, idname, text="", icon="NONE"):
        self.operators.append(idname)
        return type("Props", (), {})()

    def menu(self, idname, text="", icon="NONE"):
        self.menus.append(idname)

    def separator(self):
        pass


def reachable(menu: str, context) -> set[str]:
    """Operators a menu and its submenus offer."""
    seen, todo, out = set(), [menu], set()
    while todo:
        name = todo.pop()
        if name in seen:
            continue
        seen.add(name)
        cls = getattr(bpy.types, name)
        fake = type("M", (), {"layout": FakeLayout()})()
        cls.draw(fake, context)
        out |= set(fake.layout.operators)
        todo += fake.layout.menus
    return out


def operator_classes() -> dict[str, type]:
    return {
        name: getattr(bpy.types, f"SHAPEWRIGHT_OT_{name}")
        for name in dir(bpy.ops.shapewright)
        if hasattr(bpy.types, f"SHAPEWRIGHT_OT_{name}")
    }


def scenario_menus(work: Path) -> None:
    """Shift-A > Shapewright, File > Export, the context menu and Object >
    Shapewright; every operator a person uses is in a menu (F3's menu
    search then finds it); labels are "Shapewright: ..." and none repeats
    Blender's own."""
    context = bpy.context
    hooks = {
        "VIEW3D_MT_add": "VIEW3D_MT_shapewright_add",
        "VIEW3D_MT_object": "VIEW3D_MT_shapewright_all",
    }
    for menu, ours in hooks.items():
        assert hasattr(bpy.types, ours), ours
        funcs = getattr(bpy.types, menu).draw._draw_funcs
        assert any(getattr(f, "__module__", "").endswith("menus") for f in funcs), (menu, funcs)
    export = bpy.types.TOPBAR_MT_file_export.draw._draw_funcs
    assert any(getattr(f, "__module__", "").endswith("menus") for f in export), export
    add = reachable("VIEW3D_MT_shapewright_add", context)
    for op in ("add_solid", "gc_create", "sdf_create", "curve_network_create", "sculpt_create"):
        assert f"shapewright.{op}" in add, (op, add)
    everything = reachable("VIEW3D_MT_shapewright_all", context)
    problems = []
    for name, cls in operator_classes().items():
        internal = "INTERNAL" in getattr(cls, "bl_options", set()) or name == "xr_tool"
        label = cls.bl_label
        if not label.startswith("Shapewright: "):
            problems.append(f"shapewright.{name}: label {label!r} is not 'Shapewright: ...'")
        short = getattr(cls, "short_label", label)
        for text in (label.removeprefix("Shapewright: "), short):
            if text in CLASHES:
                problems.append(f"shapewright.{name}: label {text!r} repeats Blender's own")
        if not internal and f"shapewright.{name}" not in everything:
            problems.append(f"shapewright.{name}: in no menu (F3 cannot find it)")
    # The context menu offers the active object's edits.
    add_solid("sphere", (0.0, 0.0, 0.1))
    select_only(sw_objects()[core_session().object_ids()[-1]])
    ctx = reachable("VIEW3D_MT_shapewright_object", context)
    assert "shapewright.edit_solid" in ctx and "shapewright.set_transform" in ctx, ctx
    assert not problems, "\n".join(problems)


def scenario_typed_fields(work: Path) -> None:
    """Every field a person types is a typed property: no JSON text but
    recorded strokes, rotations as Euler (not quaternions), kinds as
    choices."""
    problems = []
    for name, cls in operator_classes().items():
        if "INTERNAL" in getattr(cls, "bl_options", set()):
            continue
        for p in getattr(bpy.ops.shapewright, name).get_rna_type().properties:
            if p.identifier == "rna_type":
                continue
            hidden = p.is_hidden
            if p.type == "STRING" and p.identifier not in STRINGS_OK and not hidden:
                problems.append(f"shapewright.{name}.{p.identifier}: text ({p.description[:60]})")
            if p.type == "FLOAT" and getattr(p, "array_length", 0) == 4 and "rot" in p.identifier:
                problems.append(f"shapewright.{name}.{p.identifier}: a quaternion to type")
    rot = bpy.ops.shapewright.set_transform.get_rna_type().properties["transform_rotate"]
    assert rot.subtype == "EULER" and rot.array_length == 3, (rot.subtype, rot.array_length)
    assert not problems, f"{len(problems)} untyped fields:\n" + "\n".join(problems)


def scenario_safe_defaults(work: Path) -> None:
    """A button that changes an object starts from its current values:
    "Mesh Resolution" with nothing typed keeps a GC's triangles, "Set
    Placement" keeps an object where it is, "Edit Solid" keeps a solid."""
    ops = bpy.ops.shapewright
    step(ops.gc_create(location=(0.0, 0.0, 0.0), template="circle", size_a=0.05, length=0.2), "gc")
    gid = core_session().object_ids()[-1]
    select_only(sw_objects()[gid])
    tris = core_session().validate(gid)["triangles"]
    assert tris > 10000, tris
    step(ops.gc_set_resolution(), "mesh resolution")
    assert core_session().validate(gid)["triangles"] == tris, (
        core_session().validate(gid)["triangles"],
        tris,
    )
    add_solid("box", (0.3, 0.2, 0.1))
    sid = core_session().object_ids()[-1]
    select_only(sw_objects()[sid])
    step(ops.move(rotation=(0.0, 0.0, 0.5)), "turn")
    before = core_world(core_session(), sid)[0]
    step(ops.set_transform(), "set placement")
    err = float(np.abs(core_world(core_session(), sid)[0] - before).max())
    assert err < 1e-6, f"Set Placement with nothing typed moved the object by {err} m"
    step(ops.edit_solid(), "edit solid")
    err = float(np.abs(core_world(core_session(), sid)[0] - before).max())
    assert err < 1e-6, f"Edit Solid with nothing typed changed the solid by {err} m"
