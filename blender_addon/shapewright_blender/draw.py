"""Visual feedback with gpu draw handlers: the controller rays, the sketch
in progress and the moving-object preview, in the 3D Viewport and in the
VR view (region type 'XR'). The modal operators only set the state below;
the handlers draw whatever it holds. Nothing is registered in background
mode (no GPU there)."""

from __future__ import annotations

import bpy

_state: dict = {"sketch": [], "rays": [], "preview": None}
_handles: list = []


def set_sketch(points: list[list[float]]) -> None:
    _state["sketch"] = [tuple(p) for p in points]


def set_rays(rays: list[tuple[tuple, tuple, float, bool]]) -> None:
    """Rays as (origin, direction, length, hit), Blender world space."""
    _state["rays"] = list(rays)


def set_preview(triangles: list[tuple] | None) -> None:
    """Triangle-soup corners (world space) of the object being dragged."""
    _state["preview"] = triangles


def state() -> dict:
    return _state


def _draw() -> None:
    import gpu
    from gpu_extras.batch import batch_for_shader

    shader = gpu.shader.from_builtin("UNIFORM_COLOR")
    gpu.state.line_width_set(2.0)
    gpu.state.depth_test_set("LESS_EQUAL")
    if len(_state["sketch"]) >= 2:
        batch = batch_for_shader(shader, "LINE_STRIP", {"pos": _state["sketch"]})
        shader.uniform_float("color", (1.0, 0.55, 0.1, 1.0))
        batch.draw(shader)
    for origin, direction, length, hit in _state["rays"]:
        end = tuple(o + d * length for o, d in zip(origin, direction, strict=True))
        batch = batch_for_shader(shader, "LINES", {"pos": [tuple(origin), end]})
        shader.uniform_float("color", (0.2, 1.0, 0.3, 1.0) if hit else (0.6, 0.6, 1.0, 0.8))
        batch.draw(shader)
    if _state["preview"]:
        gpu.state.blend_set("ALPHA")
        batch = batch_for_shader(shader, "TRIS", {"pos": _state["preview"]})
        shader.uniform_float("color", (0.3, 0.7, 1.0, 0.35))
        batch.draw(shader)
        gpu.state.blend_set("NONE")
    gpu.state.depth_test_set("NONE")
    gpu.state.line_width_set(1.0)


def register() -> None:
    if bpy.app.background:
        return
    for region in ("WINDOW", "XR"):
        try:
            _handles.append((region, bpy.types.SpaceView3D.draw_handler_add(_draw, (), region, "POST_VIEW")))
        except (TypeError, ValueError):
            pass  # a Blender build without XR support has no 'XR' region


def unregister() -> None:
    for region, h in _handles:
        bpy.types.SpaceView3D.draw_handler_remove(h, region)
    _handles.clear()
    set_sketch([])
    set_rays([])
    set_preview(None)
