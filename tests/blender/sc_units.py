"""Units from the scene and origins at each object's own centre (issue
34): in a millimetre scene every length reads and types in millimetres
and reaches the core in metres; R and S pivot about the object's own
centre, which the core's origin carries."""

from __future__ import annotations

import math
from pathlib import Path

import bpy
import numpy as np
from helpers import (
    add_solid,
    addon,
    assert_synced,
    assert_world_synced,
    core_session,
    core_world,
    last_op,
    module,
    select_only,
    settle,
    step,
    sw_objects,
)
from mathutils import Vector


def millimetre_scene() -> None:
    us = bpy.context.scene.unit_settings
    us.system = "METRIC"
    us.scale_length = 0.001
    us.length_unit = "MILLIMETERS"


def scenario_units_mm(work: Path) -> None:
    """In a millimetre scene: an 8 mm grid step is accepted (and 20 mm
    refused in millimetres), a solid typed in millimetres is that size in
    metres in the core and in millimetres in Blender, defaults read in
    millimetres, a G move of 50 mm moves the core by 0.05 m."""
    millimetre_scene()
    ops = bpy.ops.shapewright
    step(ops.sdf_create(), "volume")
    vol = core_session().object_ids()[-1]
    select_only(sw_objects()[vol])
    step(ops.sdf_set_step(step=8.0), "8 mm step")
    op = last_op()
    assert op["op"] == "sdf_set_step" and abs(op["step"] - 0.008) < 1e-9, op
    try:
        ops.sdf_set_step(step=20.0)
    except RuntimeError as e:
        assert "20 mm" in str(e) and "12 mm" in str(e), e
    else:
        raise AssertionError("a 20 mm step must be refused")
    # A box typed in millimetres.
    step(
        ops.add_solid(
            shape="box", use_cursor=False, location=(100.0, 0.0, 20.0), dimensions=(20.0, 30.0, 40.0)
        ),
        "box",
    )
    op = last_op()
    assert np.allclose(op["shape"]["size"], [0.02, 0.03, 0.04], atol=1e-9), op
    assert np.allclose(op["transform"]["translate"], [0.1, 0.0, 0.02], atol=1e-9), op
    box = sw_objects()[core_session().object_ids()[-1]]
    assert np.allclose(tuple(box.dimensions), (20.0, 30.0, 40.0), atol=1e-4), tuple(box.dimensions)
    assert np.allclose(tuple(box.location), (100.0, 0.0, 20.0), atol=1e-4), tuple(box.location)
    assert_synced()
    # Defaults read in millimetres: a solid added without sizes is 100 mm.
    step(ops.add_solid(shape="sphere", use_cursor=False, location=(0.0, 200.0, 0.0)), "default sphere")
    assert last_op()["shape"]["radius"] == 0.05, last_op()
    sphere = sw_objects()[core_session().object_ids()[-1]]
    assert np.allclose(tuple(sphere.dimensions), (100.0,) * 3, rtol=1e-3), tuple(sphere.dimensions)
    # G by 50 mm.
    select_only(sphere)
    bpy.ops.ed.undo_push(message="Select")
    before = core_world(core_session(), core_session().object_ids()[-1])[0]
    assert bpy.ops.transform.translate(value=(50.0, 0.0, 0.0)) == {"FINISHED"}
    bpy.ops.ed.undo_push(message="Move")
    settle()
    after = core_world(core_session(), core_session().object_ids()[-1])[0]
    assert np.allclose(after - before, [0.05, 0.0, 0.0], atol=1e-7), (after - before)[:1]
    assert_synced()
    # A GC from a template, typed in millimetres.
    step(ops.gc_create(location=(0.0, -200.0, 0.0), template="circle", size_a=30.0, length=120.0), "gc")
    op = last_op()
    assert abs(op["sections"][0]["profile"]["radius"] - 0.03) < 1e-9, op
    assert abs(op["spine"][1][2] - op["spine"][0][2] - 0.12) < 1e-9, op
    assert abs(op["spine"][0][1] + 0.2) < 1e-9, op
    assert_synced()
    # The History panel's print size is in millimetres whatever the scene.
    v = addon().checks.verdict(bpy.context.scene, wait=True)
    assert v["printable"], v
    assert max(v["size_mm"]) > 250, v


def scenario_origins(work: Path) -> None:
    """Each object's origin is its own centre: a solid's at its centre, a
    GC's at the centre of its bounding box; R and S in Blender pivot about
    it (the centre stays), and the core's origin is what Blender shows."""
    add_solid("sphere", (0.3, 0.2, 0.1))
    sphere = sw_objects()[core_session().object_ids()[-1]]
    assert np.allclose(tuple(sphere.location), (0.3, 0.2, 0.1), atol=1e-6), tuple(sphere.location)
    step(
        bpy.ops.shapewright.gc_create(location=(0.6, 0.0, 0.0), template="circle", size_a=0.05, length=0.3),
        "gc",
    )
    gid = core_session().object_ids()[-1]
    gc = sw_objects()[gid]
    pos = core_world(core_session(), gid)[0]
    centre = (pos.min(axis=0) + pos.max(axis=0)) / 2
    assert np.allclose(tuple(gc.location), centre, atol=1e-6), (tuple(gc.location), centre)
    # R about its own centre (Blender's default pivot for one object: its
    # origin): the GC lies down, its centre stays.
    select_only(gc)
    bpy.ops.ed.undo_push(message="Select")
    assert bpy.ops.transform.rotate(value=math.pi / 2, orient_axis="X") == {"FINISHED"}
    bpy.ops.ed.undo_push(message="Rotate")
    settle()
    pos = core_world(core_session(), gid)[0]
    after = (pos.min(axis=0) + pos.max(axis=0)) / 2
    assert np.allclose(after, centre, atol=1e-6), (after, centre)
    extent = pos.max(axis=0) - pos.min(axis=0)
    assert extent[1] > 0.29 and extent[2] < 0.11, extent
    # S about its own centre.
    assert bpy.ops.transform.resize(value=(2.0, 2.0, 2.0)) == {"FINISHED"}
    bpy.ops.ed.undo_push(message="Scale")
    settle()
    pos = core_world(core_session(), gid)[0]
    assert np.allclose((pos.min(axis=0) + pos.max(axis=0)) / 2, centre, atol=1e-6)
    assert pos.max(axis=0)[1] - pos.min(axis=0)[1] > 0.59
    assert last_op()["op"] == "set_transform", last_op()
    assert_synced()
    assert_world_synced("after R and S")
    # Blender's own USD export places the object by its origin: the prim's
    # transform is the core's origin.
    from pxr import Usd, UsdGeom

    path = work / "origins.usda"
    bpy.ops.wm.usd_export(filepath=str(path), selected_objects_only=False)
    stage = Usd.Stage.Open(str(path))
    xf = None
    for prim in stage.Traverse():
        if prim.GetName() == gc.name.replace(".", "_") and prim.IsA(UsdGeom.Xformable):
            xf = np.array(UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(0.0)).T
            break
    assert xf is not None, [p.GetPath() for p in stage.Traverse()]
    want = np.array(core_session().object_origin(gid).matrix())
    assert np.allclose(xf, want, atol=1e-5), (xf, want)


def _text(name: str, body: str, parent, at, size: float, colour) -> None:
    """A flat text object fixed in front of the camera (the image's
    stand-in for Blender's N panel, which headless Blender cannot draw)."""
    curve = bpy.data.curves.new(name, "FONT")
    curve.body = body
    curve.size = size
    obj = bpy.data.objects.new(name, curve)
    obj.color = colour
    bpy.context.scene.collection.objects.link(obj)
    obj.parent = parent
    obj.location = at


def scenario_readme_mm_mug(work: Path) -> None:
    """The README's picture (not part of the test run): a mug made in a
    millimetre scene with the add-on's operators, every size typed in
    millimetres; rendered by Workbench with its N panel's values (what
    Blender shows for the selected mug, in millimetres) and the History
    panel's print verdict composed beside it. SW_PNG is the output."""
    import os

    from sc_usd import build_mug

    millimetre_scene()
    build_mug(1000.0)
    mug = sw_objects()[1]
    mug.name = "Mug"
    bpy.context.view_layer.update()
    bpy.ops.ed.undo_push(message="rename")
    assert_synced()
    scene = bpy.context.scene
    v = addon().checks.verdict(scene, wait=True)
    assert v["printable"], v

    def mm(x: float) -> str:  # Blender units are millimetres here
        return f"{x:.1f} mm"

    loc, rot, dims = mug.location, mug.rotation_euler, mug.dimensions
    lines = [
        "Item: Mug",
        f"Location   X {mm(loc.x)}   Y {mm(loc.y)}   Z {mm(loc.z)}",
        "Rotation   X {:.0f}°   Y {:.0f}°   Z {:.0f}°".format(*(abs(math.degrees(a)) for a in rot)),
        f"Scale   {mug.scale.x:.3f}   {mug.scale.y:.3f}   {mug.scale.z:.3f}",
        f"Dimensions   X {mm(dims.x)}   Y {mm(dims.y)}   Z {mm(dims.z)}",
        "",
        "Shapewright > History:  " + ("Printable" if v["printable"] else v["message"]),
        "Size  {:.1f} × {:.1f} × {:.1f} mm".format(*v["size_mm"]),
        f"Volume  {v['volume_cm3']:.2f} cm³",
    ]
    print("\n".join(lines))
    out = Path(os.environ.get("SW_PNG", str(work / "mug_mm.png")))
    # The model's own render, then the panel in front of the camera.
    module("render").render_png(bpy.context, str(out), 960)
    cam = bpy.data.objects["ShapewrightCamera"]
    scene.camera = cam
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.display.shading.color_type = "OBJECT"
    scene.display.shading.show_specular_highlight = False
    mug.color = (0.80, 0.55, 0.35, 1.0)
    # Back off and shift the view so the mug sits right of the panel.
    centre = mug.matrix_world @ (0.125 * sum((Vector(c) for c in mug.bound_box), Vector()))
    cam.location = centre + (cam.location - centre) * 1.45
    d = cam.data
    d.shift_x = -0.27
    depth = d.clip_start * 4
    half = depth * d.sensor_width / (2 * d.lens)  # half the frame's width at that depth
    plane = bpy.data.meshes.new("panel")
    w, h = 0.98 * half, 0.62 * half
    plane.from_pydata([(0, 0, 0), (w, 0, 0), (w, h, 0), (0, h, 0)], [], [(0, 1, 2, 3)])
    back = bpy.data.objects.new("Panel", plane)
    back.color = (0.012, 0.013, 0.015, 1.0)
    scene.collection.objects.link(back)
    back.parent = cam
    # The frame spans x in (2 shift_x -+ 1) half, y in -+0.75 half.
    x0, y0 = (2 * d.shift_x - 0.97) * half, 0.70 * half - h
    back.location = (x0, y0, -depth - 1e-3 * depth)
    size = 0.042 * half
    for k, line in enumerate(lines):
        _text(
            f"panel_{k}",
            line,
            cam,
            (x0 + 0.04 * half, y0 + h - (k + 1.6) * size * 1.3, -depth),
            size,
            (0.95, 0.95, 0.95, 1.0),
        )
    scene.render.filepath = str(out)
    bpy.ops.render.render(write_still=True)
    print(f"rendered {out}")
