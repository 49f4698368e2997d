#!/usr/bin/env python3
"""Styling solves: Shapewright (faer sparse LDLT, reused symbolic analysis)
versus SciPy SuperLU (scipy.sparse.linalg.splu) on the same systems, in the
same run.

The Rust example `styling_systems` builds the curve smoother systems (50,
200, 1000 control points; 3 unknowns per point) and the surface smoother
systems (32^2, 64^2, 128^2 control points; 3 right-hand sides), times its
numeric factorization and its per-frame solve (which includes eliminating
the fixed control points and one refinement step), and writes each
eliminated matrix and right-hand side as Matrix Market files. This script
then times splu (factor) and lu.solve (per-frame solve) on those files and
prints the ratios (> 1: Shapewright is faster).

Needs: numpy, scipy (pip). Usage: python scripts/bench/styling.py
"""

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


def med(f, reps):
    ts = []
    for _ in range(reps):
        t = time.perf_counter()
        f()
        ts.append(time.perf_counter() - t)
    return statistics.median(ts)


def main():
    out = tempfile.mkdtemp(prefix="styling_systems_")
    env = dict(os.environ)
    cmd = ["cargo", "run", "--release", "-q", "-p", "shapewright", "--example", "styling_systems", "--", out]
    res = subprocess.run(cmd, cwd=ROOT, env=env, check=True, capture_output=True, text=True)
    rows = [json.loads(l) for l in res.stdout.splitlines() if l.startswith("{")]
    print(
        f"{'system':<14}{'unknowns':>9}{'rhs':>4} | {'factor ms (ours / SuperLU / ratio)':>36} | {'per-frame solve ms (ours / SuperLU / ratio)':>44} | max |x diff|"
    )
    for r in rows:
        name = r["name"]
        a = scipy.io.mmread(os.path.join(out, f"{name}.mtx")).tocsc()
        b = np.asarray(scipy.io.mmread(os.path.join(out, f"{name}_rhs.mtx")))
        x_ours = np.asarray(scipy.io.mmread(os.path.join(out, f"{name}_x.mtx")))
        reps = 5 if a.shape[0] > 20000 else 15
        lu = spla.splu(a)
        t_factor = med(lambda: spla.splu(a), reps)
        t_solve = med(lambda: lu.solve(b), reps * 3)
        x = lu.solve(b)
        diff = float(np.max(np.abs(x - x_ours)))
        f_ours, s_ours = r["factor_ms"], r["solve_ms"]
        print(
            f"{name:<14}{r['n']:>9}{r['rhs']:>4} | {f_ours:>10.3f} / {t_factor * 1e3:>9.3f} / {t_factor * 1e3 / f_ours:>6.2f}x"
            f"     | {s_ours:>10.3f} / {t_solve * 1e3:>9.3f} / {t_solve * 1e3 / s_ours:>6.2f}x           | {diff:.1e}"
        )
    print(
        "(symbolic analysis, done once per tool activation: "
        + ", ".join(f"{r['name']} {r['symbolic_ms']:.2f} ms" for r in rows)
        + ")"
    )


if __name__ == "__main__":
    sys.exit(main())
