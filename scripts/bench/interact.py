"""Ray picking: Shapewright's `interact::pick` vs a numpy-vectorized
Moller-Trumbore over all triangles (the usual Python approach), on the
same scene (16 spheres, 64 segments) and the same 32x32 ray grid, in the
same run. Prints both times and their ratio, and checks the hits agree.

`run(bin_path)` returns one row for scripts/bench/run_all.py: ours is the
mean over the example's 5 passes over the ray grid (it prints no spread),
the peer's median and 25th-75th percentiles over 5 passes; one thread each.

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
    """The STL's triangles in metres (ours are written in millimetres, as
    the header says: read as metres, the scene was 1000 times too large
    and the peer hit nothing, so the hits never agreed)."""
    data = pathlib.Path(path).read_bytes()
    (n,) = struct.unpack_from("<I", data, 80)
    rec = np.frombuffer(
        data, dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]), count=n, offset=84
    )
    scale = 1e-3 if b"millimetres" in data[:80] else 1.0
    return rec["v"].astype(np.float64) * scale


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


def run(bin_path=None, reps=5):
    """Both sides on the same scene and rays; one row for run_all.py."""
    import statistics

    if bin_path is None:
        subprocess.run(
            ["cargo", "build", "--release", "-q", "-p", "shapewright", "--example", "interact_pick"],
            cwd=ROOT,
            check=True,
        )
        bin_path = str(
            pathlib.Path(os.environ.get("CARGO_TARGET_DIR", str(ROOT / "target")))
            / "release"
            / "examples"
            / "interact_pick"
        )
    load_before = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as tmp:
        stl, hits = f"{tmp}/scene.stl", f"{tmp}/hits.txt"
        res = subprocess.run([bin_path, stl, hits], check=True, capture_output=True, text=True).stdout.split()
        rust_us = float(res[res.index("ns_per_ray") + 1]) / 1e3
        rust_t = np.loadtxt(hits)
        tris = read_stl(stl)
    origins, d = ray_grid()
    ts = []
    for _ in range(reps):
        start = time.perf_counter()
        np_t = pick_numpy(tris, origins, d)
        ts.append((time.perf_counter() - start) * 1e6 / len(origins))
    q = statistics.quantiles(ts, n=4, method="inclusive") if len(ts) > 1 else [ts[0]] * 3
    agree = hits_agree(rust_t, np_t)
    return [
        {
            "workload": f"ray pick, {len(tris)} tris, {len(origins)} rays (per ray)",
            "unit": "us",
            "ours": [rust_us] * 3,
            "ours_threads": 1,
            "peer": "NumPy vectorised Moller-Trumbore",
            "peer_value": [statistics.median(ts), q[0], q[2]],
            "peer_threads": 1,
            "note": f"ours: mean of 5 passes, no spread; hits agree: {agree}",
            "load_before": load_before,
            "load_after": os.getloadavg()[0],
        }
    ]


def ray_grid():
    """The 32 x 32 rays straight down onto the scene: origins, direction."""
    g = np.arange(32 * 32)
    origins = np.stack(
        [-0.2 + 1.3 * (g % 32) / 31.0, -0.2 + 1.3 * (g // 32) / 31.0, np.full(g.shape, 2.0)], axis=1
    )
    return origins, np.array([0.0, 0.0, -1.0])


def hits_agree(rust_t, np_t) -> bool:
    """Both hit the same rays, at the same distances (1e-5)."""
    return bool(
        np.all((rust_t < 0) == (np_t < 0)) and np.allclose(rust_t[rust_t >= 0], np_t[np_t >= 0], atol=1e-5)
    )


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
        origins, d = ray_grid()
        start = time.perf_counter()
        np_t = pick_numpy(tris, origins, d)
        np_ns = (time.perf_counter() - start) * 1e9 / len(origins)
    agree = hits_agree(rust_t, np_t)
    print(
        f"scene: {len(tris)} triangles, {len(origins)} rays, {int((rust_t >= 0).sum())} hits, hits agree: {agree}"
    )
    print(f"shapewright pick: {rust_ns / 1e3:.1f} us/ray")
    print(f"numpy vectorized: {np_ns / 1e3:.1f} us/ray")
    print(f"ratio numpy/shapewright: {np_ns / rust_ns:.1f}x")
    return 0 if agree else 1


if __name__ == "__main__":
    sys.exit(main())
