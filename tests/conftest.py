"""Shared fixtures for the Blender tests (tests/blender, tests/usd): the
extension zip, built once per session with Blender's own tool, a runner
for the Blender-side scenarios (`tests/blender/scenarios.py`), each in a
fresh Python with `bpy`, and the standalone host binary every suite
drives.

SHAPEWRIGHT_ADDON_ZIP=path skips the build and uses that zip (iterating
locally on the Python side).
SHAPEWRIGHT_TEST_PROFILE=dev (set by scripts/test.sh) tests the host and
the linux wheel as cargo's dev profile builds them, the one `cargo test`
just built (no second, optimized build of the core; the heavy geometry is
in dependencies, optimized in every profile); unset, the release build."""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SCENARIOS = ROOT / "tests" / "blender" / "scenarios.py"


def host_binary() -> Path:
    """The `shapewright-xr` the tests drive, in SHAPEWRIGHT_TEST_PROFILE
    (default release, built here when needed) under CARGO_TARGET_DIR when
    set (a shared target dir)."""
    profile = os.environ.get("SHAPEWRIGHT_TEST_PROFILE", "release")
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    path = target / ("debug" if profile == "dev" else profile) / "shapewright-xr"
    # dev: the binary `cargo test --workspace` built, with the features
    # that build unified; rebuilding it alone would compile the core again.
    if profile != "dev" or not path.exists():
        build = ["cargo", "build", "--profile", profile, "-q", "-p", "shapewright-xr"]
        subprocess.run(build, cwd=ROOT, check=True)
    return path


@pytest.fixture(scope="session")
def host_bin() -> Path:
    return host_binary()


@pytest.fixture(scope="session")
def addon_zip() -> Path:
    prebuilt = os.environ.get("SHAPEWRIGHT_ADDON_ZIP")
    if prebuilt:
        return Path(prebuilt)
    subprocess.run(["bash", "scripts/build_addon.sh"], cwd=ROOT, check=True, capture_output=True)
    zips = sorted((ROOT / "out").glob("shapewright-*.zip"))
    assert zips, "build_addon.sh made no zip"
    return zips[-1]


@pytest.fixture
def run_scenario(addon_zip: Path, tmp_path: Path) -> Callable[..., str]:
    """Runs one Blender scenario in a fresh `bpy` process (its own user
    resources under tmp_path); returns its stdout. Extra environment
    variables go to the scenario."""

    def run(name: str, work: Path | None = None, **env: str) -> str:
        work = work or tmp_path
        full = dict(os.environ, BLENDER_USER_RESOURCES=str(tmp_path / f"blender-{name}"), **env)
        r = subprocess.run(
            [sys.executable, str(SCENARIOS), str(addon_zip), name, str(work)],
            env=full,
            capture_output=True,
            text=True,
            timeout=900,
        )
        assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
        assert f"scenario {name}: ok" in r.stdout
        # A Python error in Blender's handlers, timers or operators prints
        # a traceback without failing the call that caused it.
        assert "Traceback" not in r.stderr + r.stdout, r.stderr[-3000:]
        return r.stdout

    return run
