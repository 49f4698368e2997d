"""The Blender extension, built with Blender's own tool, installed through
Blender's extension API into a temporary user directory and driven by its
operators in headless Blender (`bpy` 5.0.1)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def addon_zip() -> Path:
    subprocess.run(["bash", "scripts/build_addon.sh"], cwd=ROOT, check=True, capture_output=True)
    zips = sorted((ROOT / "out").glob("shapewright-*.zip"))
    assert zips, "build_addon.sh made no zip"
    return zips[-1]


@pytest.mark.parametrize(
    "scenario",
    [
        "build",
        "undo",
        "save_reload",
        "usd_roundtrip",
        "render",
        "export",
        "models",
        "typed",
        "sketch_projection",
        "xr_trace",
        "xr_gc_trace",
        "history_usd",
    ],
)
def test_scenario(scenario: str, addon_zip: Path, tmp_path: Path) -> None:
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(tmp_path / "blender"))
    r = subprocess.run(
        [
            sys.executable,
            str(Path(__file__).with_name("scenarios.py")),
            str(addon_zip),
            scenario,
            str(tmp_path),
        ],
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    assert f"scenario {scenario}: ok" in r.stdout
