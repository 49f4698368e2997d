"""Printable checks (issue 17; issue 21 asks that validation stay fast):
our validation of the teapot's printable mesh and of a 1M-triangle sphere
(topology, exact self-intersection search, both, and at float32; via the
Rust example print_validate) against manifold3d's import of the same STL
files in the same run (its manifold check; it has no self-intersection
search, so the ratio compares our full check with its partial one).

Also the edit-time fold check (issue 17: GC and sculpt edits that would
fold their object are refused) per edit on the teapot, chair and bust
scripts and the teapot and bust traces, beside each edit's apply time.

`run()` returns one dict per row for scripts/bench/run_all.py.

Usage: python scripts/bench/print.py [RUNS] [THREADS]   (needs manifold3d, numpy)
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import manifold3d
import numpy as np

ROOT = Path(__file__).resolve().parents[2]


def read_stl(path: Path):
    data = path.read_bytes()
    n = int.from_bytes(data[80:84], "little")
    rec = np.frombuffer(data[84 : 84 + 50 * n], dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]))
    verts, inv = np.unique(rec["v"].reshape(-1, 3), axis=0, return_inverse=True)
    return verts.astype(np.float32), inv.reshape(-1, 3).astype(np.uint32)


def run(runs: int = 5, threads: int | str = 2, bin_path: str | None = None) -> list[dict]:
    """Runs the comparison once; one dict per row (for scripts/bench/run_all.py).

    Rows: for each mesh (teapot, sphere_1m) our four checks and manifold3d's
    import of the same STL, with the ratio of our full validation to it; the
    teapot's whole print_document; and, per script or trace, the edit-time
    fold check's cost per GC/sculpt edit beside the edit's own apply time.
    Times in ms as [min, median, max]; load averages before and after.
    """
    threads = str(threads)
    if bin_path:
        exe = Path(bin_path)
    else:
        subprocess.run(
            ["cargo", "build", "--release", "-q", "-p", "shapewright", "--example", "print_validate"],
            cwd=ROOT,
            check=True,
        )
        target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
        exe = target / "release" / "examples" / "print_validate"
    load_before = os.getloadavg()
    rows: list[dict] = []
    with tempfile.TemporaryDirectory(prefix="print_bench_") as d:
        out = subprocess.run([str(exe), d, str(runs), threads], check=True, capture_output=True, text=True)
        ours = json.loads(out.stdout)
        span = lambda s: [s["min"], s["median"], s["max"]]  # noqa: E731
        rows.append(
            {
                "workload": "print_document teapot (union + checks at float32)",
                "ours_ms": [ours["teapot_print_document_ms"]] * 3,
                "ours_threads": ours["threads"],
            }
        )
        for name in ("teapot", "sphere_1m"):
            o = ours[name]
            verts, tris = read_stl(Path(o["stl"]))
            times = []
            for _ in range(runs):
                t = time.perf_counter()
                m = manifold3d.Manifold(manifold3d.Mesh(vert_properties=verts, tri_verts=tris))
                assert m.status() == manifold3d.Error.NoError
                times.append((time.perf_counter() - t) * 1e3)
            peer = [min(times), statistics.median(times), max(times)]
            rows.append(
                {
                    "workload": f"validate {name} ({o['triangles']} triangles)",
                    "ours_ms": span(o["validate_ms"]),
                    "ours_threads": ours["threads"],
                    "parts_ms": {k[:-3]: span(o[k]) for k in ("topology_ms", "self_intersection_ms", "at_float32_ms")},
                    "peer": "manifold3d Manifold(Mesh) import (no self-intersection search)",
                    "peer_ms": peer,
                    "peer_threads": 1,
                    "ratio": o["validate_ms"]["median"] / peer[1],
                    "triangles": o["triangles"],
                }
            )
        for source, e in ours["edit_check"].items():
            if not e.get("edits"):
                continue
            rows.append(
                {
                    "workload": f"edit-time fold check per GC/sculpt edit, {source}",
                    "edits": e["edits"],
                    "ours_ms": span(e["check_ms"]),
                    "ours_threads": ours["threads"],
                    "apply_ms": span(e["apply_ms"]),
                    "check_over_apply": span(e["check_over_apply"]),
                    "triangles": span(e["triangles"]),
                }
            )
    load_after = os.getloadavg()
    for r in rows:
        r["load"] = [load_before[0], load_after[0]]
    return rows


def main() -> None:
    runs = int(sys.argv[1]) if len(sys.argv) > 1 else 5
    threads = sys.argv[2] if len(sys.argv) > 2 else "2"
    print("load average:", os.getloadavg())
    for r in run(runs, threads):
        line = f"{r['workload']}: ours {r['ours_ms'][1]:.2f} ms [{r['ours_ms'][0]:.2f}-{r['ours_ms'][2]:.2f}], {r['ours_threads']} threads"
        if "peer_ms" in r:
            line += f"; {r['peer']} {r['peer_ms'][1]:.2f} ms; ratio {r['ratio']:.2f}"
        if "apply_ms" in r:
            line += (
                f"; {r['edits']} edits, apply {r['apply_ms'][1]:.2f} ms median,"
                f" check/apply median {r['check_over_apply'][1]:.3f} (max {r['check_over_apply'][2]:.3f}),"
                f" {r['triangles'][1]:.0f} triangles median"
            )
        print(line)
    print("load average:", os.getloadavg())


if __name__ == "__main__":
    main()
