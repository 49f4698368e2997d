"""Ray picking: Shapewright's `interact::pick` vs a numpy-vectorized
Moller-Trumbore over all triangles (the usual Python approach), on the
same scene (16 spheres, 64 segments) and the same 32x32 ray grid, in the
same run. Prints both times and their ratio, and checks the hits agree.

Usage: python scripts/bench/interact.py   (needs numpy)
"""

import os
import pathlib
import struct
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]


def read_stl(path):
    data = pathlib.Path(path).read_bytes()
    (n,) = struct.unpack_from("<I", data, 80)
    rec = np.frombuffer(
        data, dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]), count=n, offset=84
    )
    return rec["v"].astype(np.float64)


def pick_numpy(tris, origins, d):
    a, b, c = tris[:, 0], tris[:, 1], tris[:, 2]
    e1, e2 = b - a, c - a
    out = []
    for o in origins:
        p = np.cross(d, e2)
        det = np.einsum("ij,ij->i", e1, p)
        ok = np.abs(det) > 1e-18
        inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
        s = o - a
        u = np.einsum("ij,ij->i", s, p) * inv
        q = np.cross(s, e1)
        v = (q @ d) * inv
        t = np.einsum("ij,ij->i", e2, q) * inv
        hit = ok & (u >= 0) & (u <= 1) & (v >= 0) & (u + v <= 1) & (t >= 0) & (t <= 10)
        out.append(t[hit].min() if hit.any() else -1.0)
    return np.array(out)


def main():
    target = os.environ.get("CARGO_TARGET_DIR", str(ROOT / "target"))
    subprocess.run(
        ["cargo", "build", "--release", "-q", "-p", "shapewright", "--example", "interact_pick"],
        cwd=ROOT,
        check=True,
    )
    exe = pathlib.Path(target) / "release" / "examples" / "interact_pick"
    with tempfile.TemporaryDirectory() as tmp:
        stl, hits = f"{tmp}/scene.stl", f"{tmp}/hits.txt"
        res = subprocess.run([str(exe), stl, hits], check=True, capture_output=True, text=True).stdout.split()
        rust_ns = float(res[res.index("ns_per_ray") + 1])
        rust_t = np.loadtxt(hits)
        tris = read_stl(stl)
        g = np.arange(32 * 32)
        origins = np.stack(
            [-0.2 + 1.3 * (g % 32) / 31.0, -0.2 + 1.3 * (g // 32) / 31.0, np.full(g.shape, 2.0)], axis=1
        )
        d = np.array([0.0, 0.0, -1.0])
        start = time.perf_counter()
        np_t = pick_numpy(tris, origins, d)
        np_ns = (time.perf_counter() - start) * 1e9 / len(origins)
    agree = np.all((rust_t < 0) == (np_t < 0)) and np.allclose(
        rust_t[rust_t >= 0], np_t[np_t >= 0], atol=1e-5
    )
    print(
        f"scene: {len(tris)} triangles, {len(origins)} rays, {int((rust_t >= 0).sum())} hits, hits agree: {agree}"
    )
    print(f"shapewright pick: {rust_ns / 1e3:.1f} us/ray")
    print(f"numpy vectorized: {np_ns / 1e3:.1f} us/ray")
    print(f"ratio numpy/shapewright: {np_ns / rust_ns:.1f}x")
    return 0 if agree else 1


if __name__ == "__main__":
    sys.exit(main())
