"""Run by Blender's Python (bpy 5.0.1): build a scene, export it as USD.

Usage: python blender_export.py OUT_DIR

Writes scene_<mode>.usda and scene_<mode>.usdc for every xform op mode of
Blender's exporter, and expected.json with Blender's own world-space
triangle count and volume per object (from bmesh).
"""

import json
import math
import sys
from pathlib import Path

import bpy


def build() -> None:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(1.0, 2.0, 0.5))
    cube = bpy.context.object
    cube.rotation_euler = (0.3, 0.2, 0.9)
    cube.scale = (1.0, 2.0, 0.5)
    bpy.ops.mesh.primitive_monkey_add(location=(-2.0, 0.0, 1.0))
    monkey = bpy.context.object
    monkey.rotation_euler = (math.radians(90), 0.0, math.radians(30))
    bpy.ops.mesh.primitive_cylinder_add(
        vertices=12, radius=0.5, depth=1.5, end_fill_type="NGON", location=(0, -2, 0)
    )
    cyl = bpy.context.object
    cyl.parent = cube
    bpy.ops.mesh.primitive_torus_add(location=(3.0, 0.0, 0.0))


def expected() -> dict:
    import bmesh  # only importable once bpy is

    out = {}
    depsgraph = bpy.context.evaluated_depsgraph_get()
    for obj in bpy.context.scene.objects:
        if obj.type != "MESH":
            continue
        bm = bmesh.new()
        bm.from_object(obj, depsgraph)
        bm.transform(obj.matrix_world)
        # Relative to the bounding-box centre, as TriMesh::signed_volume
        # sums it (it matters for open meshes such as Suzanne).
        lo = [min(v.co[k] for v in bm.verts) for k in range(3)]
        hi = [max(v.co[k] for v in bm.verts) for k in range(3)]
        centre = [(a + b) / 2 for a, b in zip(lo, hi, strict=True)]
        for v in bm.verts:
            v.co = [v.co[k] - centre[k] for k in range(3)]
        tris = sum(len(f.verts) - 2 for f in bm.faces)
        # Non-planar quads (Suzanne) have a volume that depends on the
        # diagonal: split them as the importer does (0-2), and n-gons by
        # ear clipping (planar here, so any split gives the same volume).
        bmesh.ops.triangulate(bm, faces=bm.faces[:], quad_method="FIXED", ngon_method="EAR_CLIP")
        out[obj.name] = {"triangles": tris, "volume": bm.calc_volume(signed=True)}
        bm.free()
    return out


def main() -> None:
    out_dir = Path(sys.argv[-1])
    build()
    for mode in ("TRS", "TOS", "MAT"):
        for ext in ("usda", "usdc"):
            bpy.ops.wm.usd_export(
                filepath=str(out_dir / f"scene_{mode}.{ext}"),
                selected_objects_only=False,
                export_materials=False,
                xform_op_mode=mode,
            )
    (out_dir / "expected.json").write_text(json.dumps(expected()))


main()
