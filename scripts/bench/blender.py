"""Blender add-on rows of the bench (issue 34: nothing freezes), measured
inside Blender (`bpy` 5.0.1 headless, the extension zip installed as a
user installs it) by the same functions the tests assert with
(`tests/blender/sc_freeze.py`), at the issue's sizes:

- op record: the median time of recording one op (a rename through the
  add-on: the core's op, the scene's history key, the sync) with 10 and
  with 10,000 ops in the log, 25 ops each; goal: flat (the 10,000-op
  median under 1.5 x the 10-op one, as the test asserts at 2,000);
- autosave: the UI thread's time of the autosave after one edit of a
  6.3 M-triangle document (6 spheres of 1,024 segments); the usda is
  written on a thread of its own; goal < 50 ms;
- export cancel: the time from Esc to the export thread's end, pressed
  once the progress passed 30% (in the union) of 6 overlapping spheres of
  400 segments; goal < 1 s (1,000 ms).

One bpy process per row (so one row's document does not slow the
next), `nice`d as the others. Prints JSON lines; `rows()` is what
run_all.py calls.

Usage: python scripts/bench/blender.py [--quick]   (needs out/shapewright-*.zip
or builds it with scripts/build_addon.sh)
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
TESTS = ROOT / "tests" / "blender"

DRIVER = """
import json, sys
sys.path.insert(0, {tests!r})
from helpers import install
install({zip!r})
import sc_freeze
kind = {kind!r}
if kind == "record":
    t = sc_freeze.measure_record(({small}, {big}))
    print(json.dumps({{"row": "record", "small": {small}, "big": {big}, "ms": [t[{small}] * 1e3, t[{big}] * 1e3]}}))
elif kind == "autosave":
    dt, tris = sc_freeze.measure_autosave({segments}, {spheres})
    print(json.dumps({{"row": "autosave", "ms": dt * 1e3, "triangles": tris}}))
else:
    latency, at, whole = sc_freeze.measure_export_cancel({spheres}, {segments}, whole=False)
    print(json.dumps({{"row": "cancel", "ms": latency * 1e3, "at": at}}))
"""


def addon_zip() -> Path:
    zips = sorted((ROOT / "out").glob("shapewright-*.zip"))
    if not zips:
        subprocess.run(["bash", "scripts/build_addon.sh"], cwd=ROOT, check=True, capture_output=True)
        zips = sorted((ROOT / "out").glob("shapewright-*.zip"))
    return zips[-1]


def measure(kind: str, reps: int = 1, **sizes) -> list[dict]:
    """Runs one measurement `reps` times, each in a fresh bpy process."""
    out = []
    for _ in range(reps):
        with tempfile.TemporaryDirectory() as tmp:
            script = DRIVER.format(tests=str(TESTS), zip=str(addon_zip()), kind=kind, **sizes)
            env = dict(os.environ, BLENDER_USER_RESOURCES=tmp)
            r = subprocess.run(
                ["nice", sys.executable, "-c", script], env=env, capture_output=True, text=True, timeout=3600
            )
            lines = [x for x in r.stdout.splitlines() if x.startswith("{")]
            if r.returncode != 0 or not lines:
                raise RuntimeError(f"{kind}: {r.stdout[-2000:]}{r.stderr[-2000:]}")
            out.append(json.loads(lines[-1]))
    return out


def rows(quick: bool = False) -> list[dict]:
    """The measurements run_all.py turns into rows."""
    big = 1000 if quick else 10_000
    reps = 1 if quick else 3
    record = measure("record", reps, small=10, big=big, segments=0, spheres=0)
    save = measure("autosave", reps, small=0, big=0, segments=256 if quick else 1024, spheres=6)
    cancel = measure("cancel", reps, small=0, big=0, segments=150 if quick else 400, spheres=6)
    return [
        {"row": "record", "small": 10, "big": big, "ms": [r["ms"] for r in record]},
        {"row": "autosave", "triangles": save[0]["triangles"], "ms": [r["ms"] for r in save]},
        {"row": "cancel", "ms": [r["ms"] for r in cancel], "at": [r["at"] for r in cancel]},
    ]


if __name__ == "__main__":
    for r in rows("--quick" in sys.argv):
        print(json.dumps(r))
