"""Sidebar panels (3D View > Sidebar > Shapewright): solids and object
edits, one sub-panel per geometry system listing the typed operators of
`op_table`, the desktop sketch tool, and history/output. Buttons are
shown where they apply: a system's edits only when the active object is
of its kind (its "new" operator always). Buttons show the operators'
short labels (F3 and the menus show "Shapewright: ..."). The History
panel's verdict is the export's own check (`checks.py`) with the print
size in millimetres and cubic centimetres."""

from __future__ import annotations

import bpy
import shapewright as sw

from . import checks, history, op_table, operators, schema, shared, sync
from .menus import item


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
        for key in sw.solid_kinds():
            grid.operator("shapewright.add_solid", text=key.capitalize()).shape = key
        obj = context.active_object
        kind = sync.kind_of(obj)
        box = layout.box()
        if kind is not None:
            box.label(text=f"{KIND_LABELS.get(kind, kind)} #{obj[sync.ID_PROP]}")
            if kind == "solid":
                item(box, "shapewright.edit_solid")
            item(box, "shapewright.move")
            row = box.row(align=True)
            item(row, "shapewright.duplicate")
            item(row, "shapewright.delete")
            for op in operators.generic_ops():
                if schema.OPS[op]["kind"] == "document":
                    item(box, f"shapewright.{op}")
        else:
            box.label(text="Select a Shapewright object to edit it")
        row = layout.row(align=True)
        item(row, "shapewright.run_script", "FILE_SCRIPT")
        item(row, "shapewright.apply_op", "CONSOLE")


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
                item(col, f"shapewright.{spec.op}")
        # The ops with a generic operator (built from the core's schema).
        for op in operators.generic_ops():
            if schema.OPS[op]["kind"] == kind and active:
                item(col, f"shapewright.{op}")
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
        scene = context.scene
        props = scene.shapewright
        layout.label(text=f"Op {props.cursor} of {props.op_count}")
        row = layout.row(align=True)
        item(row, "shapewright.undo", "LOOP_BACK")
        item(row, "shapewright.redo", "LOOP_FORWARDS")
        item(layout, "shapewright.export_mesh", "EXPORT")
        item(layout, "shapewright.render_png", "RENDER_STILL")
        layout.prop(props, "show_parametric")
        layout.prop(props, "xr_tool")
        box = layout.box()
        s = shared.joined(scene)
        if s is None:
            box.prop(context.window_manager.shapewright_join, "url")
            box.prop(context.window_manager.shapewright_join, "name")
            if scene.name in shared.joining:
                box.label(text="Joining…", icon="TIME")
            else:
                item(box, "shapewright.join", "COMMUNITY")
        else:
            box.label(text=s.shared_url or "", icon="COMMUNITY")
            state = shared.status.get(scene.name, "")
            people = ", ".join(name for _, name, _ in s.participants())
            box.label(text=f"{state}: {people}", icon="ERROR" if state != "online" else "NONE")
            item(box, "shapewright.leave")
        if history.has_document(scene):
            v = checks.verdict(scene)
            if v is None:
                layout.label(text="Checking printability…", icon="TIME")
            elif v["printable"]:
                layout.label(text="Printable", icon="CHECKMARK")
                x, y, z = v["size_mm"]
                layout.label(text=f"Size {x:.1f} × {y:.1f} × {z:.1f} mm")
                layout.label(text=f"Volume {v['volume_cm3']:.2f} cm³")
                for i, line in enumerate(_wrap(v.get("fit", ""), 48)):
                    icon = "ERROR" if i == 0 and not v["fits"] else "NONE"
                    layout.label(text=line[:1].upper() + line[1:] if i == 0 else line, icon=icon)
            else:
                col = layout.column(align=True)
                col.label(text="Not printable:", icon="ERROR")
                for line in _wrap(v["message"], 48):
                    col.label(text=line)


def _wrap(text: str, width: int) -> list[str]:
    lines, line = [], ""
    for word in text.split():
        if line and len(line) + 1 + len(word) > width:
            lines.append(line)
            line = word
        else:
            line = f"{line} {word}".strip()
    return [*lines, line] if line else lines


classes = (
    VIEW3D_PT_shapewright,
    VIEW3D_PT_shapewright_sketch,
    *(_category_panel(key, title) for key, title in op_table.CATEGORIES),
    VIEW3D_PT_shapewright_history,
)


register, unregister = bpy.utils.register_classes_factory(classes)
