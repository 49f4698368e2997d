"""Export (File > Export > Shapewright) and the one-click render.

Mesh formats (.stl, .3mf, .obj, .ply, by extension) go through the core's
one print path on a thread of its own (`shapewright.ExportJob`): the
union, thickening and validation at the precision the format stores, and
a refusal naming the objects at fault, with nothing written. Blender's
progress bar follows the job object by object through the union; Esc
stops it at once (the operator returns, the core stops within one
boolean and writes nothing). `.usda` writes the document with its whole
history (`shapewright.save_usd`) and says whether it prints. No export
creates a folder: a path in a missing folder is refused.
"""

from __future__ import annotations

from pathlib import Path

import bpy
import shapewright as sw
from bpy.props import EnumProperty, FloatProperty, IntProperty, StringProperty

from . import checks, history

SKIP = {"SKIP_SAVE"}
PREFIX = "Shapewright: "
MESH_EXTENSIONS = (".stl", ".3mf", ".obj", ".ply")


class ExportTask:
    """One export on a thread of its own (the core's `ExportJob`), polled
    by the modal operator (or a test): `tick()` returns `running`,
    `done`, `failed` or `cancelled`; `message` says what happened."""

    def __init__(self, s: sw.Session, path: str, scale: float = 1.0, fit: bool = False) -> None:
        self.job = sw.ExportJob(s, path, scale=scale, fit=fit)
        self.message = ""
        self.summary: dict | None = None
        self.cancelled = False

    def progress(self) -> tuple[str, float]:
        return self.job.progress()

    def cancel(self) -> None:
        """Stops the job (returns at once; nothing is written)."""
        self.cancelled = True
        self.job.cancel()
        self.message = "export cancelled; nothing was written"

    def tick(self) -> str:
        if self.cancelled:
            return "cancelled"
        if not self.job.done():
            return "running"
        try:
            self.summary = self.job.result()
        except (sw.ShapewrightError, OSError) as e:
            self.message = str(e)
            return "failed"
        self.message = exported_message(self.summary)
        return "done"


def exported_message(summary: dict) -> str:
    """`exported N triangles to PATH`, and the scale when it is not 1."""
    msg = f"exported {summary['triangles']} triangles to {summary['path']}"
    if summary.get("scaled"):
        return f"{msg}; {summary['scaled']}"
    if summary.get("scale", 1.0) != 1.0:
        return f"{msg} at {summary['scale']:.1%}"
    return msg


def _folder_problem(path: str) -> str | None:
    folder = Path(path).parent
    if str(folder) and not folder.is_dir():
        return f"the folder {folder} does not exist; choose an existing folder (nothing was written)"
    return None


class SHAPEWRIGHT_OT_export(bpy.types.Operator):
    """Export the printable model (STL, 3MF, OBJ, PLY: checked printable first) or the document (USD)"""

    bl_idname = "shapewright.export_mesh"
    bl_label = PREFIX + "Export"
    short_label = "Export"

    filepath: StringProperty(
        description="Where to write; .stl, .3mf, .obj or .ply writes the printable model, .usda the document",
        subtype="FILE_PATH",
        options=SKIP,
    )
    filter_glob: StringProperty(
        default="*.stl;*.3mf;*.obj;*.ply;*.usda", description="Files the browser lists", options={"HIDDEN"}
    )
    # The printed size (meshes only; a .usda keeps the document as it is).
    size: EnumProperty(
        name="Size",
        description="The printed size of a mesh export (a .usda keeps the document as it is)",
        items=(
            ("TRUE", "True Size", "Print the model at the size it has in the scene"),
            (
                "FIT",
                "Fit the Printer",
                "Scale the model down to the document's printer when it is too big for it "
                "(walls of open surfaces keep their thickness)",
            ),
            ("SCALE", "Scale", "Print the model at the scale below"),
        ),
        default="TRUE",
    )
    scale: FloatProperty(
        name="Scale",
        description="The printed size as a percentage of the model's (with Size: Scale)",
        default=100.0,
        min=0.1,
        max=100000.0,
        subtype="PERCENTAGE",
    )

    _task: ExportTask | None = None
    _timer = None

    @classmethod
    def poll(cls, context):
        return context.scene is not None and history.has_document(context.scene)

    def invoke(self, context, event):
        if not self.filepath:
            self.filepath = bpy.path.ensure_ext(bpy.data.filepath or "untitled", ".stl")
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def _scale(self) -> dict:
        """The export's `scale` and `fit` for the core."""
        return {"scale": self.scale / 100.0 if self.size == "SCALE" else 1.0, "fit": self.size == "FIT"}

    def _usd(self, context) -> set[str]:
        s = history.session(context.scene)
        try:
            sw.save_usd(s, self.filepath)
        except (sw.ShapewrightError, OSError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        v = checks.verdict(context.scene, wait=True)
        if v is not None and not v["printable"]:
            self.report({"WARNING"}, f"wrote {self.filepath}; not printable: {v['message']}")
        else:
            self.report({"INFO"}, f"wrote {self.filepath} (printable)")
        return {"FINISHED"}

    def execute(self, context):
        problem = _folder_problem(self.filepath)
        if problem is not None:
            self.report({"ERROR"}, problem)
            return {"CANCELLED"}
        if Path(self.filepath).suffix.lower() in (".usda", ".usd"):
            return self._usd(context)
        s = history.session(context.scene)
        if context.window is None or bpy.app.background:
            # Scripts and headless runs: the same checks, on this thread.
            try:
                out = s.export_mesh(self.filepath, **self._scale())
            except (sw.ShapewrightError, OSError) as e:
                self.report({"ERROR"}, str(e))
                return {"CANCELLED"}
            self.report({"INFO"}, exported_message(out))
            return {"FINISHED"}
        try:
            self._task = ExportTask(s, self.filepath, **self._scale())
        except sw.ShapewrightError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        wm = context.window_manager
        wm.progress_begin(0.0, 1.0)
        self._timer = wm.event_timer_add(0.1, window=context.window)
        wm.modal_handler_add(self)
        context.workspace.status_text_set("Shapewright export: Esc cancels")
        return {"RUNNING_MODAL"}

    def _finish(self, context) -> None:
        wm = context.window_manager
        wm.progress_end()
        if self._timer is not None:
            wm.event_timer_remove(self._timer)
        context.workspace.status_text_set(None)

    def modal(self, context, event):
        task = self._task
        if task is None:
            return {"CANCELLED"}
        if event.type == "ESC":
            task.cancel()
        elif event.type != "TIMER":
            return {"PASS_THROUGH"}
        state = task.tick()
        if state == "running":
            phase, fraction = task.progress()
            context.window_manager.progress_update(fraction)
            context.workspace.status_text_set(f"Shapewright export: {phase} ({fraction:.0%}); Esc cancels")
            return {"RUNNING_MODAL"}
        self._finish(context)
        if state in ("failed", "cancelled"):
            self.report({"ERROR" if state == "failed" else "INFO"}, task.message)
            return {"CANCELLED"}
        self.report({"INFO"}, task.message)
        return {"FINISHED"}


class SHAPEWRIGHT_OT_render_png(bpy.types.Operator):
    """Render the Shapewright model to a PNG with Workbench (one click)"""

    bl_idname = "shapewright.render_png"
    bl_label = PREFIX + "Render PNG"
    short_label = "Render PNG"

    filepath: StringProperty(
        description="Where to write the PNG (// is the .blend's folder)",
        subtype="FILE_PATH",
        default="//shapewright.png",
        options=SKIP,
    )
    resolution: IntProperty(name="Width", description="Image width in pixels", default=960, min=64, max=8192)

    def execute(self, context):
        from . import render

        path = bpy.path.abspath(self.filepath)
        problem = _folder_problem(path)
        if problem is not None:
            self.report({"ERROR"}, problem)
            return {"CANCELLED"}
        try:
            out = render.render_png(context, path, self.resolution)
        except RuntimeError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        self.report({"INFO"}, f"rendered {out}")
        return {"FINISHED"}


classes = (SHAPEWRIGHT_OT_export, SHAPEWRIGHT_OT_render_png)
