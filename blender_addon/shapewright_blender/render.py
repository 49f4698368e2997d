"""One-click Workbench render of the Shapewright collection to a PNG."""

from __future__ import annotations

import math
from pathlib import Path

import bpy
from mathutils import Vector

from . import sync


def render_png(context, filepath: str, width: int = 960) -> str:
    scene = context.scene
    coll = sync.collection(scene)
    objs = [o for o in coll.objects if o.type == "MESH"]
    if not objs:
        raise RuntimeError("nothing to render: the Shapewright collection is empty")
    corners = [o.matrix_world @ Vector(c) for o in objs for c in o.bound_box]
    lo = Vector([min(c[i] for c in corners) for i in range(3)])
    hi = Vector([max(c[i] for c in corners) for i in range(3)])
    center, radius = (lo + hi) / 2, max((hi - lo).length / 2, 1e-6)

    cam_data = bpy.data.cameras.get("ShapewrightCamera") or bpy.data.cameras.new("ShapewrightCamera")
    cam = bpy.data.objects.get("ShapewrightCamera") or bpy.data.objects.new("ShapewrightCamera", cam_data)
    if cam.name not in scene.collection.objects:
        scene.collection.objects.link(cam)
    az, el = math.radians(35), math.radians(25)
    fov = 2 * math.atan(cam_data.sensor_width / (2 * cam_data.lens))
    dist = radius / math.sin(fov / 2) * 1.05
    d = Vector((math.cos(el) * math.sin(az), -math.cos(el) * math.cos(az), math.sin(el)))
    cam.location = center + d * dist
    cam.rotation_euler = (-d).to_track_quat("-Z", "Y").to_euler()
    cam_data.clip_start, cam_data.clip_end = dist / 100, dist * 10

    previous_camera, previous_engine = scene.camera, scene.render.engine
    scene.camera = cam
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.render.resolution_x, scene.render.resolution_y = width, width * 3 // 4
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "PNG"
    out = str(Path(filepath).resolve())
    scene.render.filepath = out
    try:
        bpy.ops.render.render(write_still=True)
    finally:
        scene.camera, scene.render.engine = previous_camera, previous_engine
    return out
