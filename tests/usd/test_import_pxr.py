"""Meshes written by Pixar's pxr import with the same triangles and volume.

Each case authors a stage with pxr (polygons of 3 to 6 sides including a
concave face, nested xformOps of every common kind, Y-up and centimetre
stages, usda and usdc). The expected world-space points come from pxr's own
ComputeLocalToWorldTransform plus the unit and up-axis conversion; the
expected volume is the divergence-theorem sum over pxr's polygons.
"""

import subprocess
from pathlib import Path

import pytest
from conftest import run_tool
from pxr import Gf, Sdf, Usd, UsdGeom, Vt

# A closed L-shaped prism: two concave hexagon caps and six quad sides.
L_PROFILE = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]


def l_prism() -> tuple[list, list, list]:
    n = len(L_PROFILE)
    points = [(x, y, 0.0) for x, y in L_PROFILE] + [(x, y, 1.0) for x, y in L_PROFILE]
    counts = [n, n]
    indices = list(reversed(range(n))) + [n + i for i in range(n)]
    for i in range(n):
        j = (i + 1) % n
        counts.append(4)
        indices += [i, j, n + j, n + i]
    return points, counts, indices


def cube() -> tuple[list, list, list]:
    points = [(x, y, z) for z in (0, 1) for y in (0, 1) for x in (0, 1)]
    quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ]
    return points, [4] * 6, [i for q in quads for i in q]


def add_mesh(stage: Usd.Stage, path: str, shape: tuple[list, list, list]) -> UsdGeom.Mesh:
    points, counts, indices = shape
    mesh = UsdGeom.Mesh.Define(stage, path)
    mesh.CreatePointsAttr(Vt.Vec3fArray([Gf.Vec3f(*p) for p in points]))
    mesh.CreateFaceVertexCountsAttr(Vt.IntArray(counts))
    mesh.CreateFaceVertexIndicesAttr(Vt.IntArray(indices))
    return mesh


def author(path: Path, up: str, mpu: float) -> None:
    stage = Usd.Stage.CreateNew(str(path))
    UsdGeom.SetStageUpAxis(stage, up)
    UsdGeom.SetStageMetersPerUnit(stage, mpu)
    root = UsdGeom.Xform.Define(stage, "/Root")
    stage.SetDefaultPrim(root.GetPrim())
    root.AddTranslateOp().Set(Gf.Vec3d(1.0, -2.0, 0.5))
    root.AddRotateXYZOp().Set(Gf.Vec3f(10.0, 20.0, 30.0))
    root.AddScaleOp().Set(Gf.Vec3f(2.0, 2.0, 2.0))

    a = UsdGeom.Xform.Define(stage, "/Root/A")
    a.AddOrientOp().Set(Gf.Quatf(0.9238795, 0.0, 0.3826834, 0.0))
    a.AddScaleOp().Set(Gf.Vec3f(1.0, 0.5, 3.0))
    add_mesh(stage, "/Root/A/Cube", cube())

    b = add_mesh(stage, "/Root/B", l_prism())
    m = Gf.Matrix4d().SetRotate(Gf.Rotation(Gf.Vec3d(1, 1, 0), 40.0))
    m.SetTranslateOnly(Gf.Vec3d(3.0, 0.0, -1.0))
    b.AddTransformOp().Set(m)
    b.AddRotateZYXOp().Set(Gf.Vec3f(5.0, -15.0, 70.0))

    c = add_mesh(stage, "/Root/C", cube())
    c.AddTranslateOp(opSuffix="pivot").Set(Gf.Vec3d(0.5, 0.5, 0.5))
    c.AddRotateYOp().Set(33.0)
    c.AddTranslateOp(opSuffix="pivot", isInverseOp=True)
    c.AddScaleOp(UsdGeom.XformOp.PrecisionDouble).Set(Gf.Vec3d(-1.0, 1.0, 1.0))

    points, counts, indices = cube()
    clockwise = [i for k in range(6) for i in reversed(indices[4 * k : 4 * k + 4])]
    left = add_mesh(stage, "/Root/Left", (points, counts, clockwise))
    left.CreateOrientationAttr(UsdGeom.Tokens.leftHanded)
    left.AddTranslateOp().Set(Gf.Vec3d(0.0, 0.0, 5.0))
    stage.GetRootLayer().Save()


def expected(path: Path, target_mpu: float) -> dict:
    stage = Usd.Stage.Open(str(path))
    scale = UsdGeom.GetStageMetersPerUnit(stage) / target_mpu
    fix = Gf.Matrix4d().SetScale(scale)
    if UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.y:
        fix = Gf.Matrix4d().SetRotate(Gf.Rotation(Gf.Vec3d(1, 0, 0), 90.0)) * fix
    out = {}
    cache = UsdGeom.XformCache()
    for prim in stage.Traverse():
        if not prim.IsA(UsdGeom.Mesh):
            continue
        mesh = UsdGeom.Mesh(prim)
        world = cache.GetLocalToWorldTransform(prim) * fix
        pts = [world.Transform(Gf.Vec3d(p)) for p in mesh.GetPointsAttr().Get()]
        counts = list(mesh.GetFaceVertexCountsAttr().Get())
        idx = list(mesh.GetFaceVertexIndicesAttr().Get())
        left = mesh.GetOrientationAttr().Get() == UsdGeom.Tokens.leftHanded
        flip = (world.GetDeterminant() < 0) != left
        volume = 0.0
        start = 0
        for c in counts:
            face = idx[start : start + c]
            start += c
            for k in range(1, c - 1):
                a, b, d = pts[face[0]], pts[face[k]], pts[face[k + 1]]
                volume += Gf.Dot(a, Gf.Cross(b, d)) / 6.0
        out[str(prim.GetPath())] = {
            "points": [tuple(p) for p in pts],
            "triangles": sum(c - 2 for c in counts),
            "volume": -volume if flip else volume,
        }
    return out


CASES = [("Z", 1.0, 1.0), ("Y", 0.01, 1.0), ("Y", 1.0, 0.001), ("Z", 0.3048, 1.0)]


@pytest.mark.parametrize("up,mpu,target", CASES)
@pytest.mark.parametrize("ext", ["usda", "usdc"])
def test_pxr_meshes_import(tool: Path, tmp_path: Path, up: str, mpu: float, target: float, ext: str) -> None:
    path = tmp_path / f"scene.{ext}"
    author(path, up, mpu)
    want = expected(path, target)
    got = run_tool(tool, "import", str(path), str(target))
    assert {m["path"] for m in got["meshes"]} == set(want)
    total_v = 0.0
    for m in got["meshes"]:
        w = want[m["path"]]
        assert m["triangles"] == w["triangles"], m["path"]
        assert abs(m["volume"] - w["volume"]) <= 1e-6 * abs(w["volume"]), m["path"]
        assert w["volume"] > 0, m["path"]
        size = max(max(abs(c) for c in p) for p in w["points"])
        for p, q in zip(m["points"], w["points"], strict=True):
            assert max(abs(a - b) for a, b in zip(p, q, strict=True)) <= 1e-6 * size
        total_v += w["volume"]
    assert got["triangles"] == sum(w["triangles"] for w in want.values())
    assert abs(got["volume"] - total_v) <= 1e-6 * total_v


def test_bad_mesh_is_a_clear_error(tool: Path, tmp_path: Path) -> None:
    path = tmp_path / "bad.usda"
    stage = Usd.Stage.CreateNew(str(path))
    mesh = add_mesh(stage, "/Bad", cube())
    mesh.GetFaceVertexIndicesAttr().Set(Vt.IntArray([0, 1, 2, 99] + [0] * 20))
    stage.GetRootLayer().Save()
    out = subprocess.run([str(tool), "import", str(path)], capture_output=True, text=True, check=False)
    assert out.returncode != 0
    assert "/Bad" in out.stderr and "out of range" in out.stderr
    layer = Sdf.Layer.FindOrOpen(str(path))
    assert layer is not None
