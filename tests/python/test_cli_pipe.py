"""Every subcommand that prints ends quietly when its reader goes away
(issue 31): `shapewright-xr ops --json | head` exited 101 with "failed
printing to stdout: Broken pipe". Each command here writes into a pipe
whose reading end is already closed (what `| head` leaves once it has
its lines): it must exit 0 or 141 (128 + SIGPIPE, what a shell shows for
`yes | head`), print no panic, and still do its work."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pytest

DATA = Path(__file__).resolve().parents[2] / "tests" / "data"


def closed_pipe_run(cmd: list) -> subprocess.CompletedProcess:
    read_end, write_end = os.pipe()
    os.close(read_end)
    try:
        return subprocess.run(
            [str(c) for c in cmd], stdout=write_end, stderr=subprocess.PIPE, text=True, timeout=600
        )
    finally:
        os.close(write_end)


def commands(host_bin: Path, work: Path) -> list[list]:
    stl, usda = work / "p.stl", work / "p.usda"
    return [
        [host_bin, "ops"],
        [host_bin, "ops", "--json"],
        [host_bin, "--help"],
        [host_bin, "apply", DATA / "primitives.jsonl", "--out", stl],
        [host_bin, "apply", DATA / "primitives.jsonl", "--out", usda],
        [host_bin, "info", stl],
        [host_bin, "info", usda],
        [host_bin, "export", usda, "--3mf", work / "p.3mf"],
        [host_bin, "replay", DATA / "csg_cup.trace.jsonl", "--out", work / "cup.usda"],
    ]


@pytest.mark.parametrize("k", range(9))
def test_a_closed_pipe_ends_quietly(host_bin: Path, tmp_path: Path, k: int) -> None:
    cmds = commands(host_bin, tmp_path)
    # The files the later commands read.
    for c in cmds[3:5]:
        assert subprocess.run([str(x) for x in c], capture_output=True).returncode == 0
    cmd = cmds[k]
    r = closed_pipe_run(cmd)
    assert r.returncode in (0, 141), (cmd, r.returncode, r.stderr)
    assert "panicked" not in r.stderr and "Broken pipe" not in r.stderr, r.stderr
    if cmd[1] == "export":
        assert (tmp_path / "p.3mf").stat().st_size > 1000, "the work was done before the output"
