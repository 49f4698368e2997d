"""Meshes from pxr-authored files imported through the ops: as an SDF
library component (`sdf_import_component`) and as a sculpt base mesh
(`sculpt_create`), into a document that is saved and reloaded.

Same triangle count and the same volume (1e-6 relative) as pxr computes;
the document reopens with the op and agrees with its geometry.
"""

from pathlib import Path

import pytest
from conftest import run_tool
from pxr import Usd, UsdGeom
from test_import_pxr import add_mesh, cube, expected, l_prism


def author_closed(path: Path) -> None:
    """A Y-up centimetre stage with a closed L prism under xformOps."""
    stage = Usd.Stage.CreateNew(str(path))
    UsdGeom.SetStageUpAxis(stage, "Y")
    UsdGeom.SetStageMetersPerUnit(stage, 0.01)
    root = UsdGeom.Xform.Define(stage, "/Root")
    stage.SetDefaultPrim(root.GetPrim())
    root.AddTranslateOp().Set((10.0, -20.0, 5.0))
    root.AddRotateXYZOp().Set((10.0, 20.0, 30.0))
    root.AddScaleOp().Set((20.0, 20.0, 20.0))
    add_mesh(stage, "/Root/L", l_prism())
    stage.GetRootLayer().Save()


@pytest.mark.parametrize("what", ["component", "base"])
@pytest.mark.parametrize("ext", ["usda", "usdc"])
def test_pxr_mesh_through_the_op(tool: Path, tmp_path: Path, what: str, ext: str) -> None:
    src = tmp_path / f"l.{ext}"
    author_closed(src)
    (want,) = expected(src, 1.0).values()
    doc = tmp_path / "doc.usda"
    got = run_tool(tool, "import-into", str(src), str(doc), what)
    assert got["op"] == ("sdf_import_component" if what == "component" else "sculpt_create")
    assert got["triangles"] == want["triangles"]
    assert abs(got["volume"] - want["volume"]) <= 1e-6 * want["volume"]
    # A component goes into a new volume (sdf_create + the import).
    assert got["ops"] == (2 if what == "component" else 1)
    again = run_tool(tool, "dump", str(doc))
    assert again["consistent"], again["report"]
    assert [op["op"] for op in again["ops"]][-1] == got["op"]
    # A second import into the same document appends to it.
    if what == "base":
        more = run_tool(tool, "import-into", str(src), str(doc), what)
        assert more["ops"] == 2 and more["objects"] == 2
        assert more["triangles"] == want["triangles"]


def test_open_mesh_is_refused_as_component(tool: Path, tmp_path: Path) -> None:
    import subprocess

    src = tmp_path / "open.usda"
    stage = Usd.Stage.CreateNew(str(src))
    UsdGeom.SetStageUpAxis(stage, "Z")
    points, counts, indices = cube()
    add_mesh(stage, "/Open", (points, counts[:5], indices[:20]))
    stage.GetRootLayer().Save()
    doc = tmp_path / "doc.usda"
    out = subprocess.run(
        [str(tool), "import-into", str(src), str(doc), "component"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert out.returncode != 0
    assert "sdf_import_component" in out.stderr
    assert not doc.exists()
