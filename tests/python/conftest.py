"""Shared fixtures: repository paths and the release host binary."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(Path(__file__).parent))


@pytest.fixture(scope="session")
def root() -> Path:
    return ROOT


@pytest.fixture(scope="session")
def host_bin() -> Path:
    subprocess.run(["cargo", "build", "--release", "-q", "-p", "shapewright-xr"], cwd=ROOT, check=True)
    # Where cargo put it: CARGO_TARGET_DIR when set (a shared target dir).
    return Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target")) / "release" / "shapewright-xr"
