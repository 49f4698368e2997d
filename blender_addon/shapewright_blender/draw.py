"""Visual feedback with gpu draw handlers: the controller rays, the sketch
in progress and the moving-object preview, in the 3D Viewport and in the
VR view (region type 'XR'). The modal operators only set the state below;
the handlers draw whatever it holds. Nothing is registered in background
mode (no GPU there)."""

from __future__ import annotations

import bpy

_state: dict = {"sketch": [], "rays": [], "preview": None, "palette": None}
# Palette colours (the headset host's, linear RGB).
# blf's font size for palette labels: the text is measured (xr.py) and
# drawn at it, one unit of font size mapping to 1/BLF_SIZE em.
BLF_SIZE = 64
_handles: list = []


def set_sketch(points: list[list[float]]) -> None:
    _state["sketch"] = [tuple(p) for p in points]


def set_rays(rays: list[tuple[tuple, tuple, float, bool]]) -> None:
    """Rays as (origin, direction, length, hit), Blender world space."""
    _state["rays"] = list(rays)


def set_preview(triangles: list[tuple] | None) -> None:
    """Triangle-soup corners (world space) of the object being dragged."""
    _state["preview"] = triangles


def set_palette(palette: dict | None) -> None:
    """The open palette as `xr.palette_geometry` builds it, or None."""
    _state["palette"] = palette


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
    if _state["palette"]:
        _draw_palette(shader, batch_for_shader)
    gpu.state.depth_test_set("NONE")
    gpu.state.line_width_set(1.0)


def _draw_palette(shader, batch_for_shader) -> None:
    import blf
    import gpu
    from mathutils import Matrix, Vector

    # The core's draw list, its colours included (xr.palette_geometry).
    for corners, _role, rgb in _state["palette"]["quads"]:
        a, b, c, d = corners
        batch = batch_for_shader(shader, "TRIS", {"pos": [a, b, c, a, c, d]})
        shader.uniform_float("color", (*rgb, 1.0))
        batch.draw(shader)
    # Labels: blf draws in the current matrix, BLF_SIZE units of font size
    # to the em the core placed the label at.
    for text, origin, right_end, top, rgb in _state["palette"]["labels"]:
        o = Vector(origin)
        x, y = (Vector(right_end) - o) / BLF_SIZE, (Vector(top) - o) / BLF_SIZE
        m = Matrix(((x[0], y[0], 0, o[0]), (x[1], y[1], 0, o[1]), (x[2], y[2], 0, o[2]), (0, 0, 0, 1)))
        with gpu.matrix.push_pop():
            gpu.matrix.multiply_matrix(m)
            blf.size(0, BLF_SIZE)
            blf.color(0, *rgb, 1.0)
            blf.position(0, 0, 0, 0)
            blf.draw(0, text)


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
    set_palette(None)
