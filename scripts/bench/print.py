"""Printable checks (issue 17; issue 21 asks that validation stay fast):
our validation of the teapot's printable mesh and of a 1M-triangle sphere
(topology, exact self-intersection search, both, and at float32; via the
Rust example print_validate) against manifold3d's import of the same STL
files in the same run (its manifold check; it has no self-intersection
search, so the ratio compares our full check with its partial one).

Also the teapot's whole `print_document` (union + checks at float32) and
the edit-time fold check (issue 17: GC and sculpt edits that would fold
their object are refused) per edit on the teapot, chair and bust scripts
and the teapot and bust traces, beside each edit's apply time.

`run(runs, threads, bin_path)` returns one row per workload for
scripts/bench/run_all.py: `ours` is [median, min, max] (the example
prints min and max, not quartiles; the note says so), the peer's median
and 25th-75th percentiles; ours on `threads` (default all CPUs),
manifold3d on its default (oneTBB, all CPUs).

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


def build() -> str:
    subprocess.run(
        ["cargo", "build", "--release", "-q", "--workspace", "--example", "print_validate"],
        cwd=ROOT,
        check=True,
    )
    return str(
        Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target")) / "release" / "examples" / "print_validate"
    )


def run(runs: int = 5, threads: int | None = None, bin_path: str | None = None) -> list[dict]:
    """One dict per row (the run_all.py contract: workload, unit, ours, ours_threads,
    peer, peer_value, peer_threads, note, load_before, load_after)."""
    threads = threads or os.cpu_count() or 1
    bin_path = bin_path or build()
    rows: list[dict] = []
    load_before = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="print_bench_") as d:
        out = subprocess.run(
            [bin_path, d, str(runs), str(threads)], check=True, capture_output=True, text=True
        )
        ours = json.loads(out.stdout)

        def span(s):
            return [s["median"], s["min"], s["max"]]

        doc_ms = ours["teapot_print_document_ms"]
        rows.append(
            {
                "workload": "print_document teapot (union + checks at float32)",
                "unit": "ms",
                "ours": [doc_ms] * 3,
                "ours_threads": threads,
                "peer": "",
                "peer_value": None,
                "peer_threads": "",
                "note": "one run",
            }
        )
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
                    "ours": span(v),
                    "ours_threads": threads,
                    "peer": "manifold3d import (manifold check only)",
                    "peer_value": [statistics.median(times), q[0], q[2]],
                    "peer_threads": os.cpu_count(),
                    "note": f"ours: full check incl. exact self-intersection search, {runs} runs, spread is min-max; "
                    f"topology only {o['topology_ms']['median']:.2f} ms, "
                    f"self-intersection {o['self_intersection_ms']['median']:.2f} ms",
                }
            )
        for source, e in ours["edit_check"].items():
            if not e.get("edits"):
                continue
            c = e["check_over_apply"]
            rows.append(
                {
                    "workload": f"edit-time fold check per GC/sculpt edit, {source}",
                    "unit": "ms",
                    "ours": span(e["check_ms"]),
                    "ours_threads": threads,
                    "peer": "",
                    "peer_value": None,
                    "peer_threads": "",
                    "note": f"{e['edits']} edits, spread min-max; check/apply median {c['median']:.3f} (max {c['max']:.3f}), "
                    f"apply median {e['apply_ms']['median']:.2f} ms",
                }
            )
    load_after = os.getloadavg()[0]
    for r in rows:
        r["load_before"], r["load_after"] = load_before, load_after
    return rows


def main() -> None:
    runs = int(sys.argv[1]) if len(sys.argv) > 1 else 5
    threads = int(sys.argv[2]) if len(sys.argv) > 2 else None
    print("load average:", os.getloadavg())
    for r in run(runs, threads):
        med, lo, hi = r["ours"]
        line = f"{r['workload']}: ours {med:.2f} ms [{lo:.2f}-{hi:.2f}], {r['ours_threads']} threads"
        if r["peer_value"]:
            p = r["peer_value"][0]
            line += f"; {r['peer']} {p:.2f} ms, {r['peer_threads']} threads; ratio {med / p:.2f}"
        print(line + f" ({r['note']})")
    print("load average:", os.getloadavg())


if __name__ == "__main__":
    main()
