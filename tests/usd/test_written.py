"""Files we write: usdchecker passes, pxr reads the same meshes and log."""

import importlib.util
import json
import os
import shutil
import struct
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest
from conftest import ROOT, run_tool
from pxr import Sdf, Usd, UsdGeom, UsdValidation


def _usdchecker() -> str | None:
    here = Path(sys.executable).parent / "usdchecker"
    if here.exists():
        return str(here)
    return shutil.which("usdchecker")


def _validation_errors(path: Path) -> list[str]:
    """Errors of every registered UsdValidation validator: what usdchecker
    runs in USD 26 (the PyPI usd-core wheel does not ship the binary)."""
    registry = UsdValidation.ValidationRegistry()
    context = UsdValidation.ValidationContext(registry.GetOrLoadAllValidators())
    errors = context.Validate(Usd.Stage.Open(str(path)))
    return [
        f"{e.GetName()}: {e.GetMessage()}"
        for e in errors
        if e.GetType() == UsdValidation.ValidationErrorType.Error
    ]


def _compliance_checker():
    """`UsdUtils.ComplianceChecker`, the engine of the classic usdchecker.

    usd-core 26.11 from PyPI ships neither the `usdchecker` binary nor
    `pxr/UsdUtils/complianceChecker.py` (USD 26 replaced it by UsdValidation).
    Blender 5.0's bundled USD still has the pure-Python module; it is loaded
    here on top of usd-core's `pxr`, whose APIs it uses.
    """
    spec = importlib.util.find_spec("bpy")
    assert spec is not None and spec.origin, "bpy (for complianceChecker.py) is not installed"
    found = sorted(
        Path(spec.origin).parent.glob("*/python/lib/python3*/site-packages/pxr/UsdUtils/complianceChecker.py")
    )
    assert found, "complianceChecker.py not found in bpy"
    mod_spec = importlib.util.spec_from_file_location("sw_compliance_checker", found[-1])
    assert mod_spec is not None and mod_spec.loader is not None
    module = importlib.util.module_from_spec(mod_spec)
    mod_spec.loader.exec_module(module)
    return module.ComplianceChecker


def test_compliance_checker_passes(written: list[Path], tmp_path: Path) -> None:
    checker_class = _compliance_checker()
    for f in written:
        checker = checker_class(
            arkit=False,
            skipARKitRootLayerCheck=False,
            rootPackageOnly=False,
            skipVariants=False,
            verbose=False,
        )
        checker.CheckCompliance(str(f))
        assert checker.GetErrors() == [], f"{f.name}: {checker.GetErrors()}"
        assert checker.GetFailedChecks() == [], f"{f.name}: {checker.GetFailedChecks()}"
    # It does find problems: no upAxis, no metersPerUnit, a dangling defaultPrim.
    bad = tmp_path / "bad.usda"
    bad.write_text('#usda 1.0\n(\n    defaultPrim = "Nope"\n)\ndef Xform "World" {}\n')
    checker = checker_class(
        arkit=False, skipARKitRootLayerCheck=False, rootPackageOnly=False, skipVariants=False
    )
    checker.CheckCompliance(str(bad))
    assert len(checker.GetFailedChecks()) == 3, checker.GetFailedChecks()


def test_usdchecker_reports_no_errors(written: list[Path], tmp_path: Path) -> None:
    checker = _usdchecker()
    for f in written:
        assert _validation_errors(f) == [], f.name
        if checker:
            out = subprocess.run(
                [checker, str(f)],
                capture_output=True,
                text=True,
                check=False,
                env={**os.environ, "PYTHONWARNINGS": "ignore"},
            )
            text = out.stdout + out.stderr
            assert out.returncode == 0, f"{f.name}: {text}"
            assert "Error" not in text and "Failed" not in text, f"{f.name}: {text}"
    # The validators do catch problems: the same file without stage
    # metadata fails.
    bare = tmp_path / "bare.usda"
    layer = Sdf.Layer.FindOrOpen(str(written[0]))
    layer.Export(str(bare))
    layer = Sdf.Layer.FindOrOpen(str(bare))
    root = layer.pseudoRoot
    for key in ("upAxis", "metersPerUnit"):
        root.ClearInfo(key)
    layer.Save()
    assert _validation_errors(bare), "validators flagged nothing on a bare layer"


def test_stage_metadata(written: list[Path]) -> None:
    for f in written:
        stage = Usd.Stage.Open(str(f))
        assert UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.z
        assert UsdGeom.GetStageMetersPerUnit(stage) == 1.0
        assert stage.GetDefaultPrim().GetPath() == "/World"


def test_pxr_reads_identical_points_and_indices(tool: Path, written: list[Path]) -> None:
    for f in written:
        ours = run_tool(tool, "dump", str(f))
        assert ours["consistent"], ours["report"]
        stage = Usd.Stage.Open(str(f))
        # Object meshes (a patch of more than 4 sides is also a Mesh prim,
        # PatchK, beside its boundary curves: a parametric part).
        meshes = [p for p in stage.Traverse() if p.IsA(UsdGeom.Mesh) and not p.GetName().startswith("Patch")]
        assert len(meshes) == len(ours["meshes"])
        for m in ours["meshes"]:
            mesh = UsdGeom.Mesh(stage.GetPrimAtPath(m["prim"]))
            assert mesh, m["prim"]
            points = [tuple(p) for p in mesh.GetPointsAttr().Get()]
            assert points == [tuple(p) for p in m["points"]], m["prim"]
            assert list(mesh.GetFaceVertexIndicesAttr().Get()) == m["indices"]
            counts = list(mesh.GetFaceVertexCountsAttr().Get())
            assert counts == [3] * (len(m["indices"]) // 3)
            assert len(mesh.GetNormalsAttr().Get()) == len(points)
            assert mesh.GetNormalsInterpolation() == UsdGeom.Tokens.vertex
            if not points:
                # An object with nothing to show yet (an empty mesh).
                continue
            lo, hi = mesh.GetExtentAttr().Get()
            assert tuple(lo) == tuple(min(c) for c in zip(*points, strict=False))
            assert tuple(hi) == tuple(max(c) for c in zip(*points, strict=False))


def _stored_json(text: str) -> object:
    """An op or snapshot as stored: JSON, or `hex:` + its UTF-8 bytes in
    hex when the JSON holds a backslash (readers disagree on escapes)."""
    if text.startswith("hex:"):
        text = bytes.fromhex(text[4:]).decode("utf-8")
    return json.loads(text)


def test_pxr_reads_the_op_log(tool: Path, written: list[Path]) -> None:
    for f in written:
        ours = run_tool(tool, "dump", str(f))
        stage = Usd.Stage.Open(str(f))
        log = stage.GetPrimAtPath("/ShapewrightLog")
        ops = [_stored_json(s) for s in log.GetAttribute("shapewright:ops").Get()]
        assert ops == ours["ops"]
        types = list(log.GetAttribute("shapewright:opTypes").Get())
        assert types == [op["op"] for op in ops]
        assert log.GetAttribute("shapewright:cursor").Get() == ours["cursor"]
        assert log.GetAttribute("shapewright:opCount").Get() == len(ops)
        assert log.GetAttribute("shapewright:formatVersion").Get() == 1
        snapshot = _stored_json(log.GetAttribute("shapewright:snapshot").Get())
        assert [o["id"] for o in snapshot["objects"]] == [m["id"] for m in ours["meshes"]]


def test_pxr_resave_still_loads(tool: Path, written: list[Path], tmp_path: Path) -> None:
    """A file re-exported by Pixar (usda and usdc) still opens with history."""
    for f in written:
        ours = run_tool(tool, "dump", str(f))
        for ext in ("usda", "usdc"):
            out = tmp_path / f"{f.stem}.{ext}"
            stage = Usd.Stage.Open(str(f))
            assert stage.GetRootLayer().Export(str(out))
            again = run_tool(tool, "dump", str(out))
            assert again["ops"] == ours["ops"]
            assert again["cursor"] == ours["cursor"]
            assert again["consistent"], again["report"]


# Every USD file the command line writes (issue 31): each extension that
# `--help` lists opens in Pixar USD and passes its validators, or is refused
# naming the extensions that work, with nothing written.


def _host(host_bin: Path, *args: object) -> subprocess.CompletedProcess:
    return subprocess.run([str(host_bin), *map(str, args)], capture_output=True, text=True, check=False)


def _opens_in_pxr(path: Path, objects: int) -> None:
    stage = Usd.Stage.Open(str(path))
    assert stage, path
    assert _validation_errors(path) == [], path.name
    assert UsdGeom.GetStageMetersPerUnit(stage) == 1.0
    meshes = [
        p for p in stage.Traverse() if p.IsA(UsdGeom.Mesh) and p.GetParent().GetParent().GetName() == "World"
    ]
    assert len(meshes) >= objects, (path.name, [str(m.GetPath()) for m in meshes])
    assert stage.GetPrimAtPath("/ShapewrightLog"), path.name


def _usdz_layout(path: Path) -> None:
    """USDZ: a zip whose first entry is the root layer, every entry stored
    (uncompressed) with its data 64-byte aligned."""
    with zipfile.ZipFile(path) as z:
        infos = z.infolist()
        assert infos[0].filename.endswith((".usda", ".usdc", ".usd")), infos[0].filename
        raw = path.read_bytes()
        for i in infos:
            assert i.compress_type == zipfile.ZIP_STORED, i.filename
            name_len, extra_len = struct.unpack_from("<HH", raw, i.header_offset + 26)
            assert (i.header_offset + 30 + name_len + extra_len) % 64 == 0, i.filename


@pytest.mark.parametrize("ext", ["usda", "usd", "usdz"])
def test_every_written_usd_file_opens_in_pixar(host_bin: Path, tmp_path: Path, ext: str) -> None:
    data = ROOT / "tests" / "data"
    apply_out = tmp_path / f"apply.{ext}"
    r = _host(host_bin, "apply", data / "primitives.jsonl", "--out", apply_out)
    assert r.returncode == 0, r.stderr
    replay_out = tmp_path / f"replay.{ext}"
    r = _host(host_bin, "replay", data / "csg_cup.trace.jsonl", "--out", replay_out)
    assert r.returncode == 0, r.stderr
    # import --into a new document and again into the one just written.
    into = tmp_path / f"into.{ext}"
    for _ in range(2):
        r = _host(
            host_bin, "import", apply_out, "--as", "base", "--prefix", "/World/Object_1", "--into", into
        )
        assert r.returncode == 0, r.stderr
    for path, objects in ((apply_out, 8), (replay_out, 1), (into, 2)):
        _opens_in_pxr(path, objects)
        if ext == "usdz":
            _usdz_layout(path)
        # ... and reopens in Shapewright with its history.
        r = _host(host_bin, "info", path)
        assert r.returncode == 0, r.stderr
        assert "replaying the history gives the snapshot" in r.stdout, r.stdout
    # export reads each of them.
    stl = tmp_path / f"from_{ext}.stl"
    r = _host(host_bin, "export", apply_out, "--stl", stl)
    assert r.returncode == 0, r.stderr


def test_usdc_is_refused_naming_what_works(host_bin: Path, tmp_path: Path) -> None:
    data = ROOT / "tests" / "data"
    out = tmp_path / "x.usdc"
    for args in (
        ("apply", data / "primitives.jsonl", "--out", out),
        ("replay", data / "csg_cup.trace.jsonl", "--out", out),
        ("import", ROOT / "tests" / "data" / "missing.usda", "--as", "base", "--into", out),
    ):
        r = _host(host_bin, *args)
        assert r.returncode != 0, args
        assert ".usda" in r.stderr and ".usdz" in r.stderr, r.stderr
        assert "panicked" not in r.stderr
        assert not out.exists(), args
