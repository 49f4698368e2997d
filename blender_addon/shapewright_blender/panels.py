"""Sidebar panels (3D View > Sidebar > Shapewright): solids and object
edits, one sub-panel per geometry system listing the typed operators of
`op_table`, the desktop sketch tool, and history/output. Buttons are
shown where they apply: a system's edits only when the active object is
of its kind (its "new" operator always)."""

from __future__ import annotations

import bpy

from . import history, op_table, operators, schema, shared, sync


class _Sidebar:
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Shapewright"


class _SubPanel(_Sidebar):
    bl_parent_id = "VIEW3D_PT_shapewright"


KIND_LABELS = {
    "solid": "Solid",
    "gc_assembly": "Generalized cylinders",
    "sdf_volume": "CSG volume",
    "curve_network": "Curve network",
    "sculpt_mesh": "Sculpt",
}


class VIEW3D_PT_shapewright(_Sidebar, bpy.types.Panel):
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
        kind = sync.kind_of(obj)
        box = layout.box()
        if kind is not None:
            box.label(text=f"{KIND_LABELS.get(kind, kind)} #{obj[sync.ID_PROP]}")
            if kind == "solid":
                box.operator("shapewright.edit_solid")
            box.operator("shapewright.move")
            row = box.row(align=True)
            row.operator("shapewright.duplicate")
            row.operator("shapewright.delete")
            for op in operators.generic_ops():
                if schema.OPS[op]["kind"] == "document":
                    box.operator(f"shapewright.{op}")
        else:
            box.label(text="Select a Shapewright object to edit it")
        row = layout.row(align=True)
        row.operator("shapewright.run_script", icon="FILE_SCRIPT")
        row.operator("shapewright.apply_op", icon="CONSOLE")


def sketch_targets(context) -> list[op_table.OpSpec]:
    """The sketch-driven ops that apply now: those that create, and the
    edits of the active object's kind."""
    kind = sync.kind_of(context.active_object)
    return [s for s in op_table.SPECS if s.sketch and op_table.kind_of(s) in (None, kind)]


class VIEW3D_PT_shapewright_sketch(_SubPanel, bpy.types.Panel):
    bl_label = "Sketch"

    def draw(self, context):
        layout = self.layout
        layout.label(text="Left-drag on a plane, then the op runs:")
        grid = layout.grid_flow(columns=2, align=True)
        for spec in sketch_targets(context):
            grid.operator("shapewright.sketch", text=spec.label, icon="GREASEPENCIL").target = spec.op


def _category_panel(key: str, title: str) -> type:
    kind = op_table.CATEGORY_KIND[key]

    def draw(self, context):
        col = self.layout.column(align=True)
        active = sync.kind_of(context.active_object) == kind
        for spec in op_table.SPECS:
            if spec.category != key:
                continue
            if op_table.kind_of(spec) is None or active:
                col.operator(f"shapewright.{spec.op}")
        # The ops with a generic operator (built from the core's schema).
        for op in operators.generic_ops():
            if schema.OPS[op]["kind"] == kind and active:
                col.operator(f"shapewright.{op}")
        if not active:
            col.label(text=f"Select a {KIND_LABELS[kind].lower()} to edit it")

    return type(
        f"VIEW3D_PT_shapewright_{key}",
        (_SubPanel, bpy.types.Panel),
        {"bl_label": title, "bl_options": {"DEFAULT_CLOSED"}, "draw": draw},
    )


class VIEW3D_PT_shapewright_history(_SubPanel, bpy.types.Panel):
    bl_label = "History and output"

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
        layout.prop(props, "show_parametric")
        layout.prop(props, "xr_tool")
        box = layout.box()
        s = shared.joined(context.scene)
        if s is None:
            box.prop(context.window_manager.shapewright_join, "url")
            box.prop(context.window_manager.shapewright_join, "name")
            box.operator("shapewright.join", icon="COMMUNITY")
        else:
            box.label(text=s.shared_url or "", icon="COMMUNITY")
            state = shared.status.get(context.scene.name, "")
            people = ", ".join(name for _, name, _ in s.participants())
            box.label(text=f"{state}: {people}", icon="ERROR" if state != "online" else "NONE")
            box.operator("shapewright.leave")
        if props.ops:
            report = history.validation(context.scene)
            if report is None:
                layout.label(text="Checking printability…", icon="TIME")
            elif report["closed_manifold"]:
                layout.label(text="Printable", icon="CHECKMARK")
            else:
                layout.label(text=f"Not printable: {report['problems']}", icon="ERROR")


classes = (
    VIEW3D_PT_shapewright,
    VIEW3D_PT_shapewright_sketch,
    *(_category_panel(key, title) for key, title in op_table.CATEGORIES),
    VIEW3D_PT_shapewright_history,
)


register, unregister = bpy.utils.register_classes_factory(classes)
