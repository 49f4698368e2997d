"""NurbsCurves / NurbsPatch prims next to the meshes (issue 7, parametric data).

The authored data are evaluated here with an independent de Boor (Cox-de
Boor basis, rational when `pointWeights` is authored, patch points with u
varying fastest) and compared with core's own NURBS evaluation printed by
`usd_tool nurbs`, at 9 parameters per curve and 7x7 per patch.
"""

from pathlib import Path

from conftest import run_tool
from pxr import Usd, UsdGeom

TOL = 1e-6


def find_span(n: int, p: int, t: float, knots: list[float]) -> int:
    """Index of the knot span holding t (The NURBS Book A2.1), n control points."""
    if t >= knots[n]:
        return n - 1
    lo, hi = p, n
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if t < knots[mid]:
            hi = mid
        else:
            lo = mid
    return lo


def basis(span: int, t: float, p: int, knots: list[float]) -> list[float]:
    """The p+1 non-zero basis functions at t (A2.2)."""
    n = [1.0] + [0.0] * p
    left = [0.0] * (p + 1)
    right = [0.0] * (p + 1)
    for j in range(1, p + 1):
        left[j] = t - knots[span + 1 - j]
        right[j] = knots[span + j] - t
        saved = 0.0
        for r in range(j):
            tmp = n[r] / (right[r + 1] + left[j - r])
            n[r] = saved + right[r + 1] * tmp
            saved = left[j - r] * tmp
        n[j] = saved
    return n


def curve_point(points, weights, order, knots, t):
    p = order - 1
    span = find_span(len(points), p, t, knots)
    b = basis(span, t, p, knots)
    acc = [0.0, 0.0, 0.0, 0.0]
    for k in range(p + 1):
        i = span - p + k
        w = weights[i] * b[k]
        for c in range(3):
            acc[c] += points[i][c] * w
        acc[3] += w
    return [acc[c] / acc[3] for c in range(3)]


def patch_point(patch: UsdGeom.NurbsPatch, u: float, v: float):
    nu = patch.GetUVertexCountAttr().Get()
    nv = patch.GetVVertexCountAttr().Get()
    pu = patch.GetUOrderAttr().Get() - 1
    pv = patch.GetVOrderAttr().Get() - 1
    ku = list(patch.GetUKnotsAttr().Get())
    kv = list(patch.GetVKnotsAttr().Get())
    points = [list(map(float, q)) for q in patch.GetPointsAttr().Get()]
    w_attr = patch.GetPointWeightsAttr().Get()
    weights = list(w_attr) if w_attr else [1.0] * len(points)
    su, sv = find_span(nu, pu, u, ku), find_span(nv, pv, v, kv)
    bu, bv = basis(su, u, pu, ku), basis(sv, v, pv, kv)
    acc = [0.0] * 4
    for a in range(pu + 1):
        for b in range(pv + 1):
            k = (sv - pv + b) * nu + (su - pu + a)  # u varies fastest
            w = weights[k] * bu[a] * bv[b]
            for c in range(3):
                acc[c] += points[k][c] * w
            acc[3] += w
    return [acc[c] / acc[3] for c in range(3)]


def dist(a, b) -> float:
    return max(abs(x - y) for x, y in zip(a, b, strict=True))


def parametric_files(written: list[Path]) -> list[Path]:
    out = []
    for f in written:
        stage = Usd.Stage.Open(str(f))
        kinds = {p.GetAttribute("shapewright:kind").Get() for p in stage.Traverse()}
        if kinds & {"gc_assembly", "curve_network"}:
            out.append(f)
    return out


def test_every_gc_and_network_has_curves_and_patches(written: list[Path]) -> None:
    files = parametric_files(written)
    assert len(files) >= 8, [f.name for f in files]
    for f in files:
        stage = Usd.Stage.Open(str(f))
        for obj in stage.GetPrimAtPath("/World").GetChildren():
            kind = obj.GetAttribute("shapewright:kind").Get()
            if kind not in ("gc_assembly", "curve_network"):
                continue
            children = obj.GetChildren()
            curves = [c for c in children if c.IsA(UsdGeom.NurbsCurves)]
            # A patch of more than 4 sides is not one NURBS surface: it is
            # stored as a Mesh prim named PatchK next to its boundary curves.
            patches = [
                c
                for c in children
                if c.IsA(UsdGeom.NurbsPatch)
                or (c.IsA(UsdGeom.Mesh) and c.GetName().startswith("Patch"))
            ]
            assert curves and patches, f"{f.name}: {obj.GetPath()}"
            if kind == "gc_assembly":
                names = {c.GetName() for c in children}
                parts = len(patches)
                for i in range(parts):
                    assert {f"Part{i}_Spine", f"Part{i}_Sections", f"Part{i}_Surface"} <= names
            for c in curves:
                nc = UsdGeom.NurbsCurves(c)
                counts = list(nc.GetCurveVertexCountsAttr().Get())
                orders = list(nc.GetOrderAttr().Get())
                knots = nc.GetKnotsAttr().Get()
                assert len(knots) == sum(counts) + sum(orders)
                assert len(nc.GetRangesAttr().Get()) == len(counts)
                assert len(nc.GetPointsAttr().Get()) == sum(counts)
            for p in patches:
                if p.IsA(UsdGeom.Mesh):
                    mesh = UsdGeom.Mesh(p)
                    assert len(mesh.GetPointsAttr().Get()) >= 3, p.GetPath()
                    continue
                np_ = UsdGeom.NurbsPatch(p)
                nu, nv = np_.GetUVertexCountAttr().Get(), np_.GetVVertexCountAttr().Get()
                assert len(np_.GetPointsAttr().Get()) == nu * nv
                assert len(np_.GetUKnotsAttr().Get()) == nu + np_.GetUOrderAttr().Get()
                assert len(np_.GetVKnotsAttr().Get()) == nv + np_.GetVOrderAttr().Get()


def test_authored_nurbs_evaluate_like_ours(tool: Path, written: list[Path]) -> None:
    checked = 0
    for f in parametric_files(written):
        ours = run_tool(tool, "nurbs", str(f))
        assert ours["consistent"], ours["report"]
        stage = Usd.Stage.Open(str(f))
        for prim in ours["prims"]:
            usd = stage.GetPrimAtPath(prim["prim"])
            assert usd and usd.GetTypeName() == prim["type"], prim["prim"]
            if prim["type"] == "NurbsCurves":
                nc = UsdGeom.NurbsCurves(usd)
                counts = list(nc.GetCurveVertexCountsAttr().Get())
                orders = list(nc.GetOrderAttr().Get())
                knots = list(nc.GetKnotsAttr().Get())
                ranges = nc.GetRangesAttr().Get()
                points = [list(map(float, q)) for q in nc.GetPointsAttr().Get()]
                w_attr = nc.GetPointWeightsAttr().Get()
                weights = list(w_attr) if w_attr else [1.0] * len(points)
                assert len(counts) == len(prim["curves"])
                pt = kt = 0
                for i, samples in enumerate(prim["curves"]):
                    n, o = counts[i], orders[i]
                    ck = knots[kt : kt + n + o]
                    assert tuple(ranges[i]) == (ck[o - 1], ck[n])
                    for t, *xyz in samples:
                        got = curve_point(points[pt : pt + n], weights[pt : pt + n], o, ck, t)
                        assert dist(got, xyz) < TOL, (prim["prim"], i, t, got, xyz)
                        checked += 1
                    pt += n
                    kt += n + o
            else:
                patch = UsdGeom.NurbsPatch(usd)
                for u, v, *xyz in prim["samples"]:
                    got = patch_point(patch, u, v)
                    assert dist(got, xyz) < TOL, (prim["prim"], u, v, got, xyz)
                    checked += 1
    assert checked > 1000


def test_edited_patch_is_reported(tool: Path, written: list[Path], tmp_path: Path) -> None:
    """Moving one control point of a NurbsPatch makes the load report a
    parametric mismatch (the log stays the truth)."""
    src = next(f for f in parametric_files(written) if "vase" in f.name)
    stage = Usd.Stage.Open(str(src))
    patch = next(p for p in stage.Traverse() if p.IsA(UsdGeom.NurbsPatch))
    attr = UsdGeom.NurbsPatch(patch).GetPointsAttr()
    points = attr.Get()
    points[0] = points[0] + (0.0, 0.0, 0.01)
    attr.Set(points)
    out = tmp_path / "edited.usda"
    stage.GetRootLayer().Export(str(out))
    seen = run_tool(tool, "dump", str(out))
    assert not seen["consistent"]
    assert f"parametric prim {patch.GetName()}: attribute `points` differs" in seen["report"]
