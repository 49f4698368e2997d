"""Queued SDF operands print (issue 33): the host's export fuses a
volume's queue as the next update would, so a cup whose update was never
pressed exports as the cup (manifold3d: one piece, genus 1, the updated
cup's volume), not as nothing."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest
from test_print import read_stl  # millimetres, as the host writes STL

manifold3d = pytest.importorskip("manifold3d")

DATA = Path(__file__).resolve().parents[2] / "tests" / "data"


def export(host_bin: Path, script: Path, out: Path) -> manifold3d.Manifold:
    cmd = [str(host_bin), "apply", str(script), "--out", str(out)]
    r = subprocess.run(cmd, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    verts, tris = read_stl(out)
    m = manifold3d.Manifold(manifold3d.Mesh(vert_properties=verts, tri_verts=tris))
    assert m.status() == manifold3d.Error.NoError, m.status()
    return m


def test_queued_operands_are_exported(host_bin: Path, tmp_path: Path) -> None:
    lines = (DATA / "csg_cup.jsonl").read_text().splitlines()
    queued = tmp_path / "queued_cup.jsonl"
    queued.write_text("\n".join(x for x in lines if "sdf_update" not in x) + "\n")
    got = export(host_bin, queued, tmp_path / "queued.stl")
    want = export(host_bin, DATA / "csg_cup.jsonl", tmp_path / "updated.stl")
    assert len(got.decompose()) == 1
    assert got.genus() == 1
    assert abs(got.volume() / want.volume() - 1.0) < 1e-6, (got.volume(), want.volume())
