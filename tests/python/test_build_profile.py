"""The dev profile optimizes what the tests run and nothing else (CI time).

Cargo.toml's block of build-time-only dependencies (proc macros, build
scripts' helpers; `scripts/dev/host_deps.py` writes it) lists exactly the
packages the workspace reaches only through a build dependency or a proc
macro: one missing is compiled at opt-level 3 for nothing (a cold `syn`
took 163 s so), one linked into a workspace target would run unoptimized.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
_spec = importlib.util.spec_from_file_location("host_deps", ROOT / "scripts/dev/host_deps.py")
host_deps = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(host_deps)


def test_the_host_only_block_is_up_to_date():
    names = host_deps.host_only()
    text = (ROOT / "Cargo.toml").read_text()
    assert host_deps.updated(text, names) == text, "run python3 scripts/dev/host_deps.py"
    # Proc macros and their parser are in it; what the tests run is not.
    assert {"syn", "serde_derive", "thiserror-impl"} <= set(names)
    assert not {"serde", "glam", "faer", "manifold-rust", "openusd"} & set(names)


def test_a_missing_or_extra_name_is_seen():
    names = host_deps.host_only()
    text = host_deps.updated((ROOT / "Cargo.toml").read_text(), names)
    without_syn = text.replace("\nsyn = { opt-level = 0 }", "")
    assert without_syn != text
    assert host_deps.updated(without_syn, names) == text
    assert host_deps.updated(text, [*names, "glam"]) != text
