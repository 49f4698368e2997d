"""Printable checks (issue 17; issue 21 asks that validation stay fast):
our validation of the teapot's printable mesh and of a 1M-triangle sphere
(topology, exact self-intersection search, both, and at float32; via the
Rust example print_validate) against manifold3d's import of the same STL
files in the same run (its manifold check; it has no self-intersection
search, so the ratio compares our full check with its partial one).

`run(runs, threads, bin_path)` returns one row per mesh for
scripts/bench/run_all.py: ours is the example's median (it prints min and
max, not quartiles: they are in the note), the peer's median and
25th-75th percentiles; ours on `threads` (default all CPUs), manifold3d on
its default (oneTBB, all CPUs).

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
    rec = np.frombuffer(
        data[84 : 84 + 50 * n], dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
    )
    verts, inv = np.unique(rec["v"].reshape(-1, 3), axis=0, return_inverse=True)
    return verts.astype(np.float32), inv.reshape(-1, 3).astype(np.uint32)


def run(runs: int = 5, threads: int | None = None, bin_path: str | None = None) -> list[dict]:
    """Our full validation vs manifold3d's import of the same STL; rows for run_all.py."""
    threads = threads or os.cpu_count() or 1
    if bin_path is None:
        subprocess.run(
            ["cargo", "build", "--release", "-q", "-p", "shapewright", "--example", "print_validate"],
            cwd=ROOT,
            check=True,
        )
        bin_path = str(
            Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
            / "release"
            / "examples"
            / "print_validate"
        )
    rows = []
    load_before = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as d:
        out = subprocess.run(
            [bin_path, d, str(runs), str(threads)], check=True, capture_output=True, text=True
        )
        ours = json.loads(out.stdout)
        for name in ("teapot", "sphere_1m"):
            o = ours[name]
            verts, tris = read_stl(Path(o["stl"]))
            times = []
            for _ in range(max(runs, 3)):
                t = time.perf_counter()
                m = manifold3d.Manifold(manifold3d.Mesh(vert_properties=verts, tri_verts=tris))
                assert m.status() == manifold3d.Error.NoError
                times.append((time.perf_counter() - t) * 1e3)
            q = statistics.quantiles(times, n=4, method="inclusive")
            v = o["validate_ms"]
            rows.append(
                {
                    "workload": f"printable validation {name} ({o['triangles']} tris)",
                    "unit": "ms",
                    "ours": [v["median"]] * 3,
                    "ours_threads": threads,
                    "peer": "manifold3d import (manifold check only)",
                    "peer_value": [statistics.median(times), q[0], q[2]],
                    "peer_threads": os.cpu_count(),
                    "note": f"ours: full check incl. exact self-intersection search, {runs} runs, min {v['min']:.2f} max {v['max']:.2f}; "
                    f"topology only {o['topology_ms']['median']:.2f} ms",
                    "load_before": load_before,
                    "load_after": os.getloadavg()[0],
                }
            )
    return rows


def main() -> None:
    runs = int(sys.argv[1]) if len(sys.argv) > 1 else 5
    threads = sys.argv[2] if len(sys.argv) > 2 else "2"
    subprocess.run(
        ["cargo", "build", "--release", "-q", "-p", "shapewright", "--example", "print_validate"],
        cwd=ROOT,
        check=True,
    )
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    exe = target / "release" / "examples" / "print_validate"
    print("load average:", os.getloadavg())
    with tempfile.TemporaryDirectory() as d:
        out = subprocess.run([str(exe), d, str(runs), threads], check=True, capture_output=True, text=True)
        ours = json.loads(out.stdout)
        print(
            f"teapot print_document (union + checks): {ours['teapot_print_document_ms']} ms, {threads} threads"
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
            peer = statistics.median(times)
            print(f"{name} ({o['triangles']} triangles):")
            for key in ("topology_ms", "self_intersection_ms", "validate_ms", "at_float32_ms"):
                s = o[key]
                print(f"  ours {key[:-3]:<18} {s['median']:9.2f} ms (min {s['min']:.2f}, max {s['max']:.2f})")
            print(f"  manifold3d import  {peer:9.2f} ms (min {min(times):.2f}, max {max(times):.2f})")
            print(f"  ratio validate / manifold3d import: {o['validate_ms']['median'] / peer:.2f}")
    print("load average:", os.getloadavg())


if __name__ == "__main__":
    main()
