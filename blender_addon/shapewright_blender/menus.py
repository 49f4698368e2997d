"""Where Blender users look for tools:

- Shift-A > Shapewright: the solids, a generalized cylinder from a
  template, a CSG volume, a curve network, a sculpt base;
- File > Export > Shapewright: the printable model (STL, 3MF, OBJ, PLY,
  checked printable first) or the document with its history (USD);
- the object context menu (right click) > Shapewright: the edits of the
  active object's kind;
- Object > Shapewright: every operator of the add-on, by system, so F3
  (Blender's menu search) finds each one as "Shapewright: ...".
"""

from __future__ import annotations

import bpy
import shapewright as sw

from . import op_table, operators, schema, sync

SYSTEMS = (
    ("gc", "Generalized Cylinders", "gc_assembly"),
    ("csg", "CSG", "sdf_volume"),
    ("curve", "Curves and Surfaces", "curve_network"),
    ("sculpt", "Warp Brushes", "sculpt_mesh"),
)
CREATE = (
    ("gc_create", "Generalized Cylinder", "MESH_CYLINDER"),
    ("sdf_create", "CSG Volume", "MOD_BOOLEAN"),
    ("curve_network_create", "Curve Network", "CURVE_BEZCURVE"),
    ("sculpt_create", "Sculpt Base", "SCULPTMODE_HLT"),
)
SOLID_ICONS = {
    "box": "MESH_CUBE",
    "sphere": "MESH_UVSPHERE",
    "ellipsoid": "MESH_UVSPHERE",
    "cylinder": "MESH_CYLINDER",
    "cone": "MESH_CONE",
    "torus": "MESH_TORUS",
    "capsule": "MESH_CAPSULE",
}


def item(layout, idname: str, icon: str = "NONE", text: str | None = None):
    return layout.operator(idname, text=text or operators.short_label(idname), icon=icon)


def edits_of(kind: str | None) -> list[str]:
    """The operators that edit an object of `kind` (document edits for any)."""
    out = []
    if kind == "solid":
        out.append("shapewright.edit_solid")
    for spec in op_table.SPECS:
        if kind is not None and op_table.kind_of(spec) == kind:
            out.append(f"shapewright.{spec.op}")
    for op in operators.generic_ops():
        if schema.OPS[op]["kind"] == kind:
            out.append(f"shapewright.{op}")
    return out


DOCUMENT_EDITS = ("shapewright.move", "shapewright.duplicate", "shapewright.delete")


class VIEW3D_MT_shapewright_add(bpy.types.Menu):
    """Shift-A > Shapewright"""

    bl_idname = "VIEW3D_MT_shapewright_add"
    bl_label = "Shapewright"

    def draw(self, context):
        layout = self.layout
        layout.operator_context = "EXEC_REGION_WIN"
        for kind in sw.solid_kinds():
            op = layout.operator(
                "shapewright.add_solid", text=kind.capitalize(), icon=SOLID_ICONS.get(kind, "MESH_DATA")
            )
            op.shape = kind
        layout.separator()
        for op, text, icon in CREATE:
            item(layout, f"shapewright.{op}", icon, text)


class VIEW3D_MT_shapewright_object(bpy.types.Menu):
    """The right-click menu's Shapewright entries for the active object"""

    bl_idname = "VIEW3D_MT_shapewright_object"
    bl_label = "Shapewright"

    def draw(self, context):
        layout = self.layout
        kind = sync.kind_of(context.active_object)
        for idname in edits_of(kind):
            item(layout, idname)
        layout.separator()
        for idname in DOCUMENT_EDITS:
            item(layout, idname)
        for op in operators.generic_ops():
            if schema.OPS[op]["kind"] == "document":
                item(layout, f"shapewright.{op}")


def _system_menu(key: str, title: str, kind: str) -> type:
    def draw(self, context):
        layout = self.layout
        for spec in op_table.SPECS:
            if spec.category == key:
                item(layout, f"shapewright.{spec.op}")
        for op in operators.generic_ops():
            if schema.OPS[op]["kind"] == kind:
                item(layout, f"shapewright.{op}")

    return type(
        f"VIEW3D_MT_shapewright_{key}",
        (bpy.types.Menu,),
        {"bl_idname": f"VIEW3D_MT_shapewright_{key}", "bl_label": title, "draw": draw},
    )


SYSTEM_MENUS = tuple(_system_menu(k, t, kind) for k, t, kind in SYSTEMS)


class VIEW3D_MT_shapewright_all(bpy.types.Menu):
    """Object > Shapewright: every operator, so F3 finds each"""

    bl_idname = "VIEW3D_MT_shapewright_all"
    bl_label = "Shapewright"

    def draw(self, context):
        layout = self.layout
        layout.menu(VIEW3D_MT_shapewright_add.bl_idname, text="Add", icon="ADD")
        for menu in SYSTEM_MENUS:
            layout.menu(menu.bl_idname)
        layout.separator()
        item(layout, "shapewright.edit_solid")
        for idname in DOCUMENT_EDITS:
            item(layout, idname)
        for op in operators.generic_ops():
            if schema.OPS[op]["kind"] == "document":
                item(layout, f"shapewright.{op}")
        layout.separator()
        for idname in (
            "shapewright.sketch",
            "shapewright.undo",
            "shapewright.redo",
            "shapewright.export_mesh",
            "shapewright.render_png",
            "shapewright.run_script",
            "shapewright.apply_op",
            "shapewright.join",
            "shapewright.leave",
        ):
            item(layout, idname)


def _add_menu(self, context):
    self.layout.menu(VIEW3D_MT_shapewright_add.bl_idname, icon="MESH_CYLINDER")


def _export_menu(self, context):
    self.layout.operator("shapewright.export_mesh", text="Shapewright (.stl, .3mf, .usda)")


def _context_menu(self, context):
    if sync.kind_of(context.active_object) is not None:
        self.layout.separator()
        self.layout.menu(VIEW3D_MT_shapewright_object.bl_idname)


def _object_menu(self, context):
    self.layout.separator()
    self.layout.menu(VIEW3D_MT_shapewright_all.bl_idname)


classes = (VIEW3D_MT_shapewright_add, VIEW3D_MT_shapewright_object, *SYSTEM_MENUS, VIEW3D_MT_shapewright_all)
HOOKS = (
    ("VIEW3D_MT_add", _add_menu),
    ("TOPBAR_MT_file_export", _export_menu),
    ("VIEW3D_MT_object_context_menu", _context_menu),
    ("VIEW3D_MT_object", _object_menu),
)


def register() -> None:
    for cls in classes:
        bpy.utils.register_class(cls)
    for menu, fn in HOOKS:
        getattr(bpy.types, menu).append(fn)


def unregister() -> None:
    for menu, fn in HOOKS:
        getattr(bpy.types, menu).remove(fn)
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
