#!/usr/bin/env python3
"""SDF CSG benchmark: ours vs NumPy + scikit-image and fast-surface-nets,
on the same grids, in the same run.

Runs `cargo run --release --example sdf_bench -- --dump DIR` (ours and
fast-surface-nets, timed in Rust), then on the grids it dumped times a NumPy
fusion (np.minimum / np.maximum over every operand's dense field) followed by
skimage.measure.marching_cubes, and prints the paper's Table 1 beside all
three, plus the full-grid extraction table with Mtri/s and the
classify-the-cells floor.

Needs: numpy, scikit-image (pip). Usage: python scripts/bench/sdf.py [--reps N]
"""

import argparse
import glob
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
from skimage.measure import marching_cubes

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# Paper 2, Table 1 (GTX 1070): fusion, extraction, total ms.
PAPER = {
    "cube_sphere": {0.012: (8, 14, 22), 0.01: (9, 22, 31), 0.008: (11, 46, 57), 0.006: (12, 98, 110)},
    "chair": {0.012: (26, 27, 53), 0.01: (28, 34, 62), 0.008: (35, 76, 111), 0.006: (45, 186, 231)},
    "cup": {0.012: (15, 24, 39), 0.01: (16, 45, 61), 0.008: (18, 89, 104), 0.006: (21, 208, 229)},
}


def load(d, tag):
    meta = json.load(open(os.path.join(d, tag + ".json")))
    nx, ny, nz = meta["dims"]
    a = np.fromfile(os.path.join(d, tag + ".f32"), dtype="<f4").reshape(nz, ny, nx)
    return a, meta


def best(f, reps):
    ts = []
    out = None
    for _ in range(reps):
        t = time.perf_counter()
        out = f()
        ts.append((time.perf_counter() - t) * 1e3)
    ts.sort()
    return ts[len(ts) // 2], out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--reps", type=int, default=7)
    ap.add_argument("--bin", help="prebuilt sdf_bench binary")
    args = ap.parse_args()
    d = tempfile.mkdtemp(prefix="sdf_bench_")
    if args.bin:
        cmd = [args.bin]
    else:
        cmd = ["cargo", "run", "-q", "--release", "-p", "shapewright", "--example", "sdf_bench", "--"]
    out = subprocess.run(
        cmd + ["--dump", d, "--reps", str(max(args.reps, 5))],
        cwd=ROOT,
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    rows = [json.loads(l) for l in out.splitlines() if l.startswith("{")]

    print(
        "Table 1 workloads: one update (all fusions + one extraction), ms; "
        f"ours on {rows[0]['threads']} threads"
    )
    hdr = (
        f"{'workload':12} {'step':>6} | {'paper fuse/extr/total':>22} | {'ours fuse/extr/total':>22} "
        f"| {'numpy+skimage f/e/total':>24} | {'fsn':>7} | {'x paper':>7} {'x skimage':>9} {'x fsn':>6}"
    )
    print(hdr)
    print("-" * len(hdr))
    for r in (r for r in rows if r["kind"] == "table1"):
        tag = r["tag"]
        ops = []
        for p in sorted(glob.glob(os.path.join(d, tag + "_op*.json"))):
            name = os.path.basename(p)[:-5]
            ops.append((name.rsplit("_", 1)[1], load(d, name)[0]))

        def fuse():
            acc = ops[0][1].copy()
            for csg, a in ops[1:]:
                if csg == "union":
                    np.minimum(acc, a, out=acc)
                elif csg == "intersect":
                    np.maximum(acc, a, out=acc)
                else:
                    np.maximum(acc, -a, out=acc)
            return acc

        tf, fused = best(fuse, args.reps)
        te, mc = best(lambda: marching_cubes(fused, 0.0), args.reps)
        pf, pe, pt = PAPER[r["workload"]][r["step"]]
        ours_total = r["update_ms"]
        print(
            f"{r['workload']:12} {r['step']:>6} | {pf:>6} {pe:>7} {pt:>7} | "
            f"{r['fusion_ms']:>6.2f} {r['extraction_ms']:>7.2f} {ours_total:>7.2f} | "
            f"{tf:>7.2f} {te:>7.2f} {tf + te:>8.2f} | {r['fsn_ms']:>7.2f} | "
            f"{pt / ours_total:>7.1f} {(tf + te) / ours_total:>9.1f} {r['fsn_ms'] / ours_total:>6.2f}"
        )
    print("(x columns: peer time / our total update time; >1 means we are faster.)")
    print("fast-surface-nets is extraction only, on our fused grid made dense.\n")

    print("Full-grid extraction, sphere minus torus")
    hdr = (
        f"{'N':>5} | {'ours ms':>8} {'1 thr':>8} {'Mtri/s':>7} | {'classify':>8} {'ours/floor':>10} | "
        f"{'skimage':>8} {'Mtri/s':>7} | {'fsn':>7} {'Mtri/s':>7}"
    )
    print(hdr)
    print("-" * len(hdr))
    for r in (r for r in rows if r["kind"] == "full"):
        a, _ = load(d, r["tag"])
        ts, (v, f, _, _) = best(lambda: marching_cubes(a, 0.0), max(3, args.reps // 2))
        print(
            f"{r['n']:>5} | {r['ours_ms']:>8.2f} {r['ours_1thread_ms']:>8.2f} "
            f"{r['triangles'] / r['ours_ms'] / 1e3:>7.1f} | {r['classify_ms']:>8.2f} "
            f"{r['ours_ms'] / r['classify_ms']:>10.2f} | {ts:>8.2f} {len(f) / ts / 1e3:>7.1f} | "
            f"{r['fsn_ms']:>7.2f} {r['fsn_triangles'] / r['fsn_ms'] / 1e3:>7.1f}"
        )
    print("classify = single-thread sign classification of every cell of the dense grid.")


if __name__ == "__main__":
    sys.exit(main())
