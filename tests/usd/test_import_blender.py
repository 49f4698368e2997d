"""Meshes written by Blender's own USD exporter import correctly.

Needs a Python with `bpy` 5.0.1 (set BLENDER_PYTHON; default: the
Python running the tests, which is the project venv with bpy); skipped when there is none.
"""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import run_tool

BLENDER_PYTHON = Path(os.environ.get("BLENDER_PYTHON", sys.executable))


def _has_bpy() -> bool:
    if not BLENDER_PYTHON.exists():
        return False
    probe = subprocess.run([str(BLENDER_PYTHON), "-c", "import bpy"], capture_output=True, check=False)
    return probe.returncode == 0


pytestmark = pytest.mark.skipif(not _has_bpy(), reason="no Python with bpy")


@pytest.fixture(scope="module")
def exported(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("blender")
    script = Path(__file__).with_name("blender_export.py")
    run = subprocess.run(
        [str(BLENDER_PYTHON), str(script), str(out)],
        capture_output=True,
        text=True,
        check=False,
    )
    assert run.returncode == 0, run.stderr[-2000:]
    return out


@pytest.mark.parametrize("mode", ["TRS", "TOS", "MAT"])
@pytest.mark.parametrize("ext", ["usda", "usdc"])
def test_blender_export_imports(tool: Path, exported: Path, mode: str, ext: str) -> None:
    want = json.loads((exported / "expected.json").read_text())
    got = run_tool(tool, "import", str(exported / f"scene_{mode}.{ext}"))
    by_object = {}
    for m in got["meshes"]:
        # Blender writes /root/<Object>/<Mesh data>; a child object nests
        # under its parent's prim.
        parts = m["path"].strip("/").split("/")
        names = [p for p in parts if p.replace("_", ".") in want or p in want]
        assert names, m["path"]
        by_object[names[-1]] = m
    assert set(by_object) == set(want)
    for name, w in want.items():
        m = by_object[name]
        assert m["triangles"] == w["triangles"], name
        assert abs(m["volume"] - w["volume"]) <= 1e-6 * abs(w["volume"]), (
            name,
            m["volume"],
            w["volume"],
        )


@pytest.mark.parametrize("what", ["component", "base"])
def test_blender_usdc_through_the_op(tool: Path, exported: Path, tmp_path: Path, what: str) -> None:
    """Blender's closed torus (usdc) as a component and as a sculpt base:
    same triangles and volume as Blender's bmesh, and the document reloads."""
    want = json.loads((exported / "expected.json").read_text())["Torus"]
    doc = tmp_path / "doc.usda"
    got = run_tool(tool, "import-into", str(exported / "scene_TRS.usdc"), str(doc), what, "/root/Torus")
    assert got["triangles"] == want["triangles"]
    assert abs(got["volume"] - want["volume"]) <= 1e-6 * abs(want["volume"])
    again = run_tool(tool, "dump", str(doc))
    assert again["consistent"], again["report"]
    assert again["ops"][-1]["op"] == got["op"]
