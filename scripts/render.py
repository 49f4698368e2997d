"""Render a mesh file (STL, OBJ or PLY) to PNG with Blender Workbench.

Usage: python scripts/render.py IN.stl OUT.png [--size 960x720] [--azimuth 35]
       [--elevation 25] [--color 0.8,0.55,0.35]

Runs headless through the `bpy` module from PyPI (Blender 5.0.1). Z is up,
as in Blender and in Shapewright's USD files. The camera frames the mesh's
bounding sphere from the given azimuth and elevation (degrees).
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path


def parse_args(argv: list[str]) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("input", type=Path)
    p.add_argument("output", type=Path)
    p.add_argument("--size", default="960x720", help="WIDTHxHEIGHT in pixels")
    p.add_argument("--azimuth", type=float, default=35.0)
    p.add_argument("--elevation", type=float, default=25.0)
    p.add_argument("--color", default="0.80,0.55,0.35", help="r,g,b in 0..1")
    return p.parse_args(argv)


def import_mesh(bpy, path: Path):
    ext = path.suffix.lower()
    if ext == ".stl":
        bpy.ops.wm.stl_import(filepath=str(path))
    elif ext == ".obj":
        bpy.ops.wm.obj_import(filepath=str(path), forward_axis="Y", up_axis="Z")
    elif ext == ".ply":
        bpy.ops.wm.ply_import(filepath=str(path), forward_axis="Y", up_axis="Z")
    else:
        raise SystemExit(f"render.py: unsupported mesh format {ext!r} (use .stl, .obj or .ply)")
    objs = [o for o in bpy.context.scene.objects if o.type == "MESH"]
    if not objs:
        raise SystemExit(f"render.py: {path} holds no mesh")
    return objs


def render(args: argparse.Namespace) -> None:
    import bpy
    from mathutils import Vector

    bpy.ops.wm.read_factory_settings(use_empty=True)
    objs = import_mesh(bpy, args.input)
    color = tuple(float(c) for c in args.color.split(",")) + (1.0,)
    for o in objs:
        for poly in o.data.polygons:
            poly.use_smooth = False
        o.color = color

    corners = [o.matrix_world @ Vector(c) for o in objs for c in o.bound_box]
    lo = Vector([min(c[i] for c in corners) for i in range(3)])
    hi = Vector([max(c[i] for c in corners) for i in range(3)])
    center = (lo + hi) / 2
    radius = max((hi - lo).length / 2, 1e-6)

    scene = bpy.context.scene
    cam_data = bpy.data.cameras.new("cam")
    cam_data.lens = 50
    cam = bpy.data.objects.new("cam", cam_data)
    scene.collection.objects.link(cam)
    scene.camera = cam
    az, el = math.radians(args.azimuth), math.radians(args.elevation)
    fov = 2 * math.atan(cam_data.sensor_width / (2 * cam_data.lens))
    dist = radius / math.sin(fov / 2) * 1.05
    direction = Vector((math.cos(el) * math.sin(az), -math.cos(el) * math.cos(az), math.sin(el)))
    cam.location = center + direction * dist
    cam.rotation_euler = (-direction).to_track_quat("-Z", "Y").to_euler()
    cam_data.clip_start = dist / 100
    cam_data.clip_end = dist * 10

    w, h = (int(x) for x in args.size.lower().split("x"))
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.render.resolution_x, scene.render.resolution_y = w, h
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False
    shading = scene.display.shading
    shading.light = "STUDIO"
    shading.color_type = "OBJECT"
    shading.show_cavity = True
    shading.show_shadows = True
    shading.show_specular_highlight = True
    scene.display.render_aa = "8"
    world = bpy.data.worlds.new("world")
    world.color = (0.93, 0.94, 0.96)
    scene.world = world
    scene.render.image_settings.file_format = "PNG"
    args.output.parent.mkdir(parents=True, exist_ok=True)
    scene.render.filepath = str(args.output.resolve())
    bpy.ops.render.render(write_still=True)


def main(argv: list[str] | None = None) -> int:
    args = parse_args(sys.argv[1:] if argv is None else argv)
    if not args.input.is_file():
        print(f"render.py: no such file {args.input}", file=sys.stderr)
        return 2
    render(args)
    print(f"rendered {args.input} -> {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
