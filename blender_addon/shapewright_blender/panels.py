"""Sidebar panels (3D View > Sidebar > Shapewright)."""

from __future__ import annotations

import bpy

from . import history, sync


class VIEW3D_PT_shapewright(bpy.types.Panel):
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Shapewright"
    bl_label = "Shapewright"

    def draw(self, context):
        layout = self.layout
        col = layout.column(align=True)
        col.label(text="Add solid")
        grid = col.grid_flow(columns=2, align=True)
        for key, label, _ in (
            ("box", "Box", ""),
            ("sphere", "Sphere", ""),
            ("cylinder", "Cylinder", ""),
            ("cone", "Cone", ""),
            ("torus", "Torus", ""),
            ("capsule", "Capsule", ""),
            ("ellipsoid", "Ellipsoid", ""),
        ):
            grid.operator("shapewright.add_solid", text=label).shape = key
        obj = context.active_object
        box = layout.box()
        if obj is not None and sync.ID_PROP in obj:
            box.label(text=f"Object #{obj[sync.ID_PROP]}")
            box.operator("shapewright.edit_solid")
            box.operator("shapewright.move")
            box.operator("shapewright.commit_transform")
            row = box.row(align=True)
            row.operator("shapewright.duplicate")
            row.operator("shapewright.delete")
        else:
            box.label(text="Select a Shapewright object to edit it")
        layout.operator("shapewright.run_script", icon="FILE_SCRIPT")


class VIEW3D_PT_shapewright_history(bpy.types.Panel):
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Shapewright"
    bl_label = "History and output"
    bl_parent_id = "VIEW3D_PT_shapewright"

    def draw(self, context):
        layout = self.layout
        props = context.scene.shapewright
        total = props.ops.count("\n")
        layout.label(text=f"Op {props.cursor} of {total}")
        row = layout.row(align=True)
        row.operator("shapewright.undo", icon="LOOP_BACK")
        row.operator("shapewright.redo", icon="LOOP_FORWARDS")
        layout.operator("shapewright.export_mesh", icon="EXPORT")
        layout.operator("shapewright.render_png", icon="RENDER_STILL")
        if props.ops:
            report = history.session(context.scene).validate()
            layout.label(
                text="Printable" if report["closed_manifold"] else f"Not printable: {report['problems']}"
            )


classes = (VIEW3D_PT_shapewright, VIEW3D_PT_shapewright_history)


def register() -> None:
    for cls in classes:
        bpy.utils.register_class(cls)


def unregister() -> None:
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
