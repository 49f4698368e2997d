"""Fixtures for the USD interchange tests: the Rust helper and saved files.

The helper is the `usd_tool` example of the `shapewright-usd` crate, built
once per session (honours CARGO_TARGET_DIR; set USD_TOOL to use a prebuilt
binary).
"""

import json
import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _target_dir() -> Path:
    return Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))


@pytest.fixture(scope="session")
def tool() -> Path:
    prebuilt = os.environ.get("USD_TOOL")
    if prebuilt:
        return Path(prebuilt)
    subprocess.run(
        ["cargo", "build", "-q", "-p", "shapewright-usd", "--example", "usd_tool"],
        cwd=ROOT,
        check=True,
    )
    return _target_dir() / "debug" / "examples" / "usd_tool"


def run_tool(tool: Path, *args: str) -> dict:
    out = subprocess.run([str(tool), *args], capture_output=True, text=True, check=False)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


def scripts() -> list[Path]:
    found = []
    for d in (ROOT / "usd" / "tests" / "data", ROOT / "tests" / "data"):
        found.extend(p for p in sorted(d.glob("*.jsonl")) if not p.name.endswith(".trace.jsonl"))
    return found


@pytest.fixture(scope="session")
def written(tool: Path, tmp_path_factory: pytest.TempPathFactory) -> list[Path]:
    out_dir = tmp_path_factory.mktemp("written")
    files = []
    for script in scripts():
        out = out_dir / (script.stem + ".usda")
        run_tool(tool, "save", str(script), str(out))
        files.append(out)
    assert len(files) >= 3
    return files
