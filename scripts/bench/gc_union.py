"""Assembly union, ours vs manifold3d, on the same part meshes in the same
run (issue 21: "union: at most 1.0x manifold3d with the same threads,
import included").

The Rust example `gc_union_parts` runs the teapot, chair and shelf GC scripts,
writes each part mesh of the assembly as raw arrays (f64 positions, u32
triangles: what our `TriMesh` holds) and times our union of them. The peer
(manifold3d, PyPI: C++ Manifold 3.5.4, the version manifold-rust is checked
against) unites the same arrays.

What each side's timer covers, per rep (one untimed warm-up rep on each
side first):
- ours (`shapewright::mesh::union`): import of every part (index and
  coordinate checks, `MeshGL64`, `Manifold::from_mesh_gl64` with Manifold's
  merge and manifold check, status checked), the batch union, export back
  to a `TriMesh` (positions, triangles, per-triangle sources; no vertex
  normals since issue 37's last change, as on the peer's side);
- peer: import of every part (`Mesh64` from the position array and the
  triangle array widened to u64, `Manifold(mesh)`, status checked), the
  batch union (`Manifold.batch_boolean(..., Add)`), export (`to_mesh64()`
  and its position and triangle arrays as NumPy arrays).
Not timed on either side: meshing the parts, reading the files.

The two sides take turns in 3 rounds per row (ours, the peer, ours, ...),
each process timing a third of the reps after its own untimed warm-up
rep; each side's reps are pooled for its median and spread. On a machine
whose speed drifts over minutes (this one's did by 1.3x within an hour,
2026-12-02), a ratio then compares times taken in the same minutes.

The *step* rows time the least a GC edit commit does once the rest of the
union is kept (issue 37): the last part added to the union of all the
others, which each side unites and imports before its timer. Timed: the
part's import, one boolean, the export (ours: `UnionOperand::import_group`,
`union`, `to_mesh`; peer: `Manifold(Mesh64)`, `+`, `to_mesh64()`).

Threads: ours unites in a fixed tree, the two halves of each node at once
on rayon's pool, which sizes itself from the process's CPU affinity, as
manifold3d's oneTBB pool does. The first row confines both processes to the
same single CPU (`os.sched_setaffinity`), so each runs one thread
(checked: each reports its thread count); the second lets both use every
CPU (their default), as a user's machine runs them.

`run(reps)` returns rows for scripts/bench/run_all.py.
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

ROOT = Path(__file__).resolve().parents[2]
# Name -> script under tests/data (the shelf is the 30-part assembly of
# issue 37, kept out of the folder the slicer, USD and Windows tests read).
WORKLOADS = {"teapot": "teapot.jsonl", "chair": "chair.jsonl", "shelf": "bench/shelf.jsonl"}


# Rounds in which both sides take turns (see run()).
ROUNDS = 3


def spread(ts: list[float]) -> list[float]:
    """Median, 25th and 75th percentiles."""
    q = statistics.quantiles(ts, n=4, method="inclusive") if len(ts) > 1 else [ts[0]] * 3
    return [statistics.median(ts), q[0], q[2]]


def peer(d: str, reps: int, cpus: int | None) -> dict:
    """The manifold3d side, in its own process (called via `--peer`): with
    `cpus`, the process is confined to that many CPUs before manifold3d
    (and its TBB pool) is loaded."""
    if cpus is not None:
        os.sched_setaffinity(0, sorted(os.sched_getaffinity(0))[:cpus])
    import manifold3d
    import numpy as np

    parts = []
    for p in sorted(Path(d).glob("part*.pos.f64")):
        pos = np.fromfile(p, dtype="<f8").reshape(-1, 3)
        tri = np.fromfile(str(p).replace(".pos.f64", ".tri.u32"), dtype="<u4").reshape(-1, 3)
        parts.append((pos, tri))

    def ms_of(parts):
        ms = []
        for pos, tri in parts:
            m = manifold3d.Manifold(manifold3d.Mesh64(vert_properties=pos, tri_verts=tri.astype(np.uint64)))
            if m.status() != manifold3d.Error.NoError:
                raise RuntimeError(f"manifold3d refused a part: {m.status()}")
            ms.append(m)
        return ms

    def once():
        u = manifold3d.Manifold.batch_boolean(ms_of(parts), manifold3d.OpType.Add)
        out = u.to_mesh64()
        return u, np.asarray(out.vert_properties), np.asarray(out.tri_verts)

    once()  # warm-up, untimed
    times = []
    for _ in range(reps):
        t = time.perf_counter()
        u, _, tris = once()
        times.append((time.perf_counter() - t) * 1e3)
    # The step (issue 37's floor of a GC commit): the last part added to
    # the union of the others, kept whole (united before the timer); the
    # part's import, one boolean, the export timed, as on our side.
    rest = manifold3d.Manifold.batch_boolean(ms_of(parts[:-1]), manifold3d.OpType.Add)
    rest.num_tri()  # manifold3d is lazy: unite the rest now, untimed
    step = []
    for _ in range(reps + 1):
        t = time.perf_counter()
        (last,) = ms_of(parts[-1:])
        out = (rest + last).to_mesh64()
        stepped = np.asarray(out.tri_verts)
        step.append((time.perf_counter() - t) * 1e3)
    threads = int(next(ln.split()[1] for ln in open("/proc/self/status") if ln.startswith("Threads:")))
    return {
        "step_ms": spread(step[1:]),
        "step_all_ms": step[1:],
        "step_output_triangles": len(stepped),
        "ms": spread(times),
        "all_ms": times,
        "output_triangles": len(tris),
        "genus": u.genus(),
        "threads": threads,
        "cpus": len(os.sched_getaffinity(0)),
    }


def _pin(cpus: int):
    def f():
        os.sched_setaffinity(0, sorted(os.sched_getaffinity(0))[:cpus])

    return f


def pair_row(
    workload: str, key: str, ours: dict, p: dict, same: bool, goal: str, note: str, load: tuple
) -> dict:
    """One row of run_all.py: our `key` timings against the peer's, both on
    one CPU (`same`) or on every CPU."""
    return {
        "workload": workload + ("" if same else ", every CPU on both sides"),
        "unit": "ms",
        "ours": ours[key],
        "ours_threads": ours["threads"],
        "peer": "manifold3d " + ("1 CPU" if same else f"{p['cpus']} CPUs"),
        "peer_value": p[key],
        "peer_threads": p["cpus"],
        "ratio": ours[key][0] / p[key][0],
        "goal": goal,
        "note": note + ("; both pinned to 1 CPU" if same else f"; ours on {ours['threads']} threads"),
        "load_before": load[0],
        "load_after": load[1],
    }


def union_row(name: str, ours: dict, p: dict, same: bool, load: tuple) -> dict:
    """The whole union of the parts."""
    return pair_row(
        f"union {name} ({ours['parts']} parts, {ours['input_triangles']} tris)",
        "ms",
        ours,
        p,
        same,
        # Issue 37: no slower at one CPU each, nor when both may use every core.
        "<= 1.0x",
        f"out: ours {ours['output_triangles']} tris genus {ours['genus']} closed {ours['closed']}, "
        f"manifold3d {p['output_triangles']} tris genus {p['genus']} (process threads: {p['threads']})",
        load,
    )


def step_row(name: str, ours: dict, p: dict, same: bool, load: tuple) -> dict:
    """The step: the last part added to the kept union of the others."""
    return pair_row(
        f"union step {name}: part {ours['parts']} added to the other {ours['parts'] - 1} "
        f"({ours['step_part_triangles']} tris to {ours['step_output_triangles']})",
        "step_ms",
        ours,
        p,
        same,
        # No goal of its own: the least a GC commit does when the rest of the
        # union is kept whole (issue 37's goal for a commit is < 30 ms).
        "",
        f"floor of a GC commit (goal < 30 ms): manifold3d's step alone is "
        f"{p['step_ms'][0] / 30.0:.1f}x that goal; part import + 1 boolean + export timed, the rest "
        f"kept whole; out: ours {ours['step_output_triangles']} tris, manifold3d "
        f"{p['step_output_triangles']} tris",
        load,
    )


def pooled(before: dict | None, new: dict) -> dict:
    """`new` (one process's output) with the reps of `before` (the same
    side's earlier rounds) added, and its spreads taken over all of them."""
    if before:
        for key in ("all_ms", "step_all_ms"):
            new[key] = before[key] + new[key]
    new["ms"], new["step_ms"] = spread(new["all_ms"]), spread(new["step_all_ms"])
    return new


def run(reps: int = 7, bin_path: str | None = None) -> list[dict]:
    """Both sides on the teapot, the chair and the shelf; rows for run_all.py."""
    if bin_path is None:
        subprocess.run(
            ["cargo", "build", "--release", "-q", "-p", "shapewright", "--example", "gc_union_parts"],
            cwd=ROOT,
            check=True,
        )
        target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
        bin_path = str(target / "release" / "examples" / "gc_union_parts")
    rows = []
    for name, file in WORKLOADS.items():
        with tempfile.TemporaryDirectory(prefix="gc_union_") as d:
            load_before = os.getloadavg()
            script = str(ROOT / "tests" / "data" / file)
            # Both sides alternate in rounds (ours, then the peer, ROUNDS
            # times, each process timing its share of the reps), so that a
            # machine whose speed drifts over minutes slows both alike; each
            # side's reps are pooled over its rounds.
            per_round = max(1, -(-reps // ROUNDS))
            ours_on, peers = {}, {}
            for label, cpus in (("same", 1), ("default", None)):
                for _ in range(ROUNDS):
                    ours = json.loads(
                        subprocess.run(
                            [bin_path, script, d, str(per_round)],
                            check=True,
                            capture_output=True,
                            text=True,
                            preexec_fn=_pin(cpus) if cpus else None,
                        ).stdout
                    )
                    cmd = [sys.executable, __file__, "--peer", d, str(per_round)] + (
                        [str(cpus)] if cpus else []
                    )
                    p = json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)
                    ours_on[label] = pooled(ours_on.get(label), ours)
                    peers[label] = pooled(peers.get(label), p)
            load = (load_before, os.getloadavg())
        # The union rows, then the step rows, each on one CPU and on every CPU.
        for make in (union_row, step_row):
            for label, p in peers.items():
                rows.append(make(name, ours_on[label], p, label == "same", load))
    return rows


def main() -> int:
    if len(sys.argv) > 1 and sys.argv[1] == "--peer":
        cpus = int(sys.argv[4]) if len(sys.argv) > 4 else None
        print(json.dumps(peer(sys.argv[2], int(sys.argv[3]), cpus)))
        return 0
    reps = int(sys.argv[1]) if len(sys.argv) > 1 else 7
    for r in run(reps):
        o, p = r["ours"], r["peer_value"]
        print(
            f"{r['workload']}: ours {o[0]:.1f} ms ({o[1]:.1f}-{o[2]:.1f}, {r['ours_threads']} thr) vs {r['peer']} "
            f"{p[0]:.1f} ms ({p[1]:.1f}-{p[2]:.1f}, {r['peer_threads']} thr): ratio {r['ratio']:.2f}; {r['note']}; "
            f"load {r['load_before'][0]:.2f} -> {r['load_after'][0]:.2f}"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
