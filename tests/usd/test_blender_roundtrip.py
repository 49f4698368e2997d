"""A Shapewright document through Blender's own USD exporter and importer
(issue 20): a mug built in the add-on is exported with Blender's exporter
(the add-on's hook writes the op log and the parametric prims) as usda and
usdc, and also written by Shapewright itself; each file is opened in a
fresh Blender with Blender's importer, which gives the document back with
its history: undo three times and redo give the original's content hash
at each step, NURBS curves come in with their own shape, patches as
meshes. The Blender side is `tests/blender/scenarios.py` (`usd_make`,
`usd_open`); the fixtures are in `tests/conftest.py`."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest


@pytest.fixture(scope="module")
def made(tmp_path_factory: pytest.TempPathFactory, addon_zip: Path) -> Path:
    import os
    import subprocess
    import sys

    scenarios = Path(__file__).resolve().parents[1] / "blender" / "scenarios.py"
    work = tmp_path_factory.mktemp("mug")
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(work / "blender-make"))
    r = subprocess.run(
        [sys.executable, str(scenarios), str(addon_zip), "usd_make", str(work)],
        env=env,
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert r.returncode == 0 and "scenario usd_make: ok" in r.stdout, r.stdout[-3000:] + r.stderr[-3000:]
    return work


@pytest.mark.parametrize("source", ["mug_blender.usda", "mug_blender.usdc", "mug_ours.usda"])
def test_fresh_blender_opens_the_document(source: str, made: Path, run_scenario: Callable[..., str]) -> None:
    out = run_scenario("usd_open", work=made, SW_SOURCE=source)
    assert f"opened {source}" in out
