#!/usr/bin/env python3
"""Styling per-frame solves: Shapewright (faer sparse LDLT, symbolic
analysis and numeric factors reused across frames) versus SciPy SuperLU
(scipy.sparse.linalg.splu) on the same systems, in the same run.

The Rust example `styling_systems` builds the curve smoother systems (50,
200, 1000 control points; 3 unknowns per point) and the surface smoother
systems (32^2, 64^2, 128^2 control points; 3 right-hand sides), times its
numeric factorization and its per-frame solve (which includes eliminating
the fixed control points and the refinement test), and writes each
eliminated matrix and right-hand side as Matrix Market files. This script
then times splu (factor) and lu.solve (per-frame solve) on those files.

Ratios are ours / peer: below 1 means Shapewright is faster. Both sides run
on one thread (faer with Par::Seq; SuperLU is sequential). Two peers: SuperLU
as scipy configures it by default (COLAMD, partial pivoting: the peer of
issue 21) and SuperLU told the matrix is symmetric positive definite
(MMD on A^T + A, diagonal pivots), its best setting for these systems.

`run()` returns one dict per system (for scripts/bench/run_all.py); `main()`
prints the table. Needs numpy and scipy.
Usage: python scripts/bench/styling.py [--reps-scale K]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
import scipy.io
import scipy.sparse.linalg as spla

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def quartiles(f, reps):
    ts = []
    for _ in range(reps):
        t = time.perf_counter()
        f()
        ts.append((time.perf_counter() - t) * 1e3)
    q = statistics.quantiles(ts, n=4, method="inclusive")
    return [q[0], statistics.median(ts), q[2]]


def load():
    return os.getloadavg()[0]


def build_systems(out: str, bin_path: str | None = None) -> list[dict]:
    if bin_path:
        cmd = [bin_path, out]
    else:
        cmd = [
            "cargo",
            "run",
            "--release",
            "-q",
            "-p",
            "shapewright",
            "--example",
            "styling_systems",
            "--",
            out,
        ]
    res = subprocess.run(cmd, cwd=ROOT, check=True, capture_output=True, text=True)
    return [json.loads(line) for line in res.stdout.splitlines() if line.startswith("{")]


def run(reps_scale: float = 1.0, bin_path: str | None = None) -> list[dict]:
    """Builds and times both sides; one row per system."""
    out = tempfile.mkdtemp(prefix="styling_systems_")
    load_before = load()
    rows = build_systems(out, bin_path)
    result = []
    for r in rows:
        name = r["name"]
        a = scipy.io.mmread(os.path.join(out, f"{name}.mtx")).tocsc()
        b = np.asarray(scipy.io.mmread(os.path.join(out, f"{name}_rhs.mtx")))
        x_ours = np.asarray(scipy.io.mmread(os.path.join(out, f"{name}_x.mtx")))
        reps = max(5, int((5 if a.shape[0] > 20000 else 15) * reps_scale))
        peers = {}
        for peer, kw in (
            ("superlu", {}),
            (
                "superlu_spd",
                {"permc_spec": "MMD_AT_PLUS_A", "diag_pivot_thresh": 0.0, "options": {"SymmetricMode": True}},
            ),
        ):
            lu = spla.splu(a, **kw)
            x = lu.solve(b)
            peers[peer] = {
                "factor_ms": quartiles(lambda kw=kw: spla.splu(a, **kw), reps),
                "solve_ms": quartiles(lambda lu=lu: lu.solve(b), reps * 3),
                "max_x_diff": float(np.max(np.abs(x - x_ours))),
                "fill": int(lu.L.nnz + lu.U.nnz),
            }
        result.append(
            {
                "name": name,
                "unknowns": r["n"],
                "rhs": r["rhs"],
                "ours": {
                    "factor_ms": r["factor_ms"],
                    "solve_ms": r["solve_ms"],
                    "symbolic_ms": r["symbolic_ms"],
                    "factor": r["factor"],
                },
                "peers": peers,
                "ratio_solve": r["solve_ms"][1] / peers["superlu"]["solve_ms"][1],
                "ratio_solve_spd": r["solve_ms"][1] / peers["superlu_spd"]["solve_ms"][1],
                "ratio_factor": r["factor_ms"][1] / peers["superlu"]["factor_ms"][1],
                "threads": {"ours": 1, "peer": 1},
            }
        )
    load_after = load()
    for row in result:
        row["load"] = [load_before, load_after]
    return result


def fmt(q):
    return f"{q[1]:8.3f} [{q[0]:.3f}-{q[2]:.3f}]"


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--reps-scale", type=float, default=1.0)
    args = p.parse_args(argv)
    rows = run(args.reps_scale)
    print(
        f"styling per-frame solves, 1 thread each side, load {rows[0]['load'][0]:.2f} -> {rows[0]['load'][1]:.2f}"
    )
    print("times in ms: median [p25-p75]; ratio = ours / peer (< 1: Shapewright faster)")
    print(
        f"{'system':<12}{'unknowns':>9}{'rhs':>4} | {'ours solve':>24} | {'SuperLU solve':>24} | {'ratio':>6} |"
        f" {'SuperLU-SPD solve':>24} | {'ratio':>6} | {'ours factor':>24} | {'SuperLU factor':>24} | {'ratio':>6}"
    )
    for r in rows:
        o, s, d = r["ours"], r["peers"]["superlu"], r["peers"]["superlu_spd"]
        print(
            f"{r['name']:<12}{r['unknowns']:>9}{r['rhs']:>4} | {fmt(o['solve_ms']):>24} | {fmt(s['solve_ms']):>24} |"
            f" {r['ratio_solve']:>6.2f} | {fmt(d['solve_ms']):>24} | {r['ratio_solve_spd']:>6.2f} |"
            f" {fmt(o['factor_ms']):>24} | {fmt(s['factor_ms']):>24} | {r['ratio_factor']:>6.2f}"
        )
    for r in rows:
        print(
            f"  {r['name']}: ours {r['ours']['factor']}, symbolic {r['ours']['symbolic_ms']:.2f} ms once per"
            f" activation; SuperLU fill {r['peers']['superlu']['fill']}, max |x diff| {r['peers']['superlu']['max_x_diff']:.1e}"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
