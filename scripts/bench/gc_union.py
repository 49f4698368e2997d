"""Teapot and chair: our final union (manifold-rust, via the Rust example
gc_union_parts) vs manifold3d (PyPI, C++ Manifold) on the same part meshes
in the same run; prints times and the ratio ours / manifold3d.

Usage: python scripts/bench/gc_union.py [RUNS]   (needs manifold3d, numpy)
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


def main() -> None:
    runs = int(sys.argv[1]) if len(sys.argv) > 1 else 5
    subprocess.run(
        ["cargo", "build", "--release", "-q", "-p", "shapewright", "--example", "gc_union_parts"],
        cwd=ROOT,
        check=True,
    )
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    exe = target / "release" / "examples" / "gc_union_parts"
    for name in ("teapot", "chair"):
        with tempfile.TemporaryDirectory() as d:
            out = subprocess.run(
                [str(exe), str(ROOT / "tests" / "data" / f"{name}.jsonl"), d, str(runs)],
                check=True,
                capture_output=True,
                text=True,
            ).stdout
            ours = json.loads(out)
            parts = []
            for p in sorted(Path(d).glob("part*.stl")):
                v, t = read_stl(p)
                m = manifold3d.Manifold(manifold3d.Mesh(vert_properties=v, tri_verts=t))
                assert m.status() == manifold3d.Error.NoError, (p, m.status())
                parts.append(m)
            times = []
            for _ in range(runs):
                t0 = time.perf_counter()
                u = manifold3d.Manifold.batch_boolean(parts, manifold3d.OpType.Add)
                u.num_tri()  # force evaluation
                times.append(time.perf_counter() - t0)
            theirs = statistics.median(times)
            print(
                f"{name}: {ours['parts']} parts, {ours['input_triangles']} input triangles -> "
                f"ours {ours['output_triangles']} tris {ours['median_s'] * 1e3:.1f} ms (closed {ours['closed']}, genus {ours['genus']}), "
                f"manifold3d {u.num_tri()} tris {theirs * 1e3:.1f} ms (genus {u.genus()}), "
                f"ratio ours/manifold3d = {ours['median_s'] / theirs:.2f}"
            )


if __name__ == "__main__":
    main()
