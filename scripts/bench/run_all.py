#!/usr/bin/env python3
"""The one honest bench (issue 21; goals from issue 37): every peer
comparison and every goal measurement, in one run, one table.

Rows (what each measures is in the module that makes it):
- SDF update, Table 1 scenes (Cube-Sphere, Chair, Cup) at steps 0.01,
  0.006, 0.004: ours (`sdf_bench`, every operand resampled inside the
  timer) vs NumPy + SciPy `map_coordinates` + scikit-image `marching_cubes`
  on the same operand grids (scripts/bench/sdf.py);
- full-grid extraction at 128^3 and 256^3 vs the single-thread "classify
  every cell" floor, fast-surface-nets and scikit-image (sdf.py);
- assembly union, teapot, chair and the 30-part shelf, vs manifold3d with the same threads
  (import + union + export timed on both sides) and with its default
  threads (scripts/bench/gc_union.py); and the *step* on the same parts,
  the last part added to the kept union of the others (one part import,
  one boolean, the export), the least a GC edit commit does: no goal of
  its own, the floor under the commit's (same file);
- styling per-frame solve vs SciPy SuperLU, curve and surface systems
  (scripts/bench/styling.py; the SuperLU-SPD ratio in the note);
- goals without a peer: sculpt bench stroke at 2M and 5M vertices, p99
  frame (`perf_goals sculpt`); GC edit commit p99 on the teapot trace, the
  chair script and the 30-part shelf (`perf_goals gc-commit`); history bytes per 1,000 ops in
  the 20-object session (`history_bytes`);
- shared sessions (issue 23, `session_bench` against a real nats-server
  on loopback): op round trip p99 (one person's edit applied by every
  other) with 2 and 16 people at 10 ops/s each, goal one 90 Hz frame;
  joining a 10,000-op document from the latest snapshot vs replaying the
  whole stream; the single-user apply of the same op in the note;
- printable validation vs manifold3d's import (scripts/bench/print.py),
  goal <= 1.0x (issue 37); an informative peer without a goal: ray
  picking vs NumPy (scripts/bench/interact.py);
- the Blender add-on (issue 34, scripts/bench/blender.py, inside bpy):
  recording an op at 10 and at 10,000 ops, the autosave's UI-thread time
  on a 6.3 M-triangle document, and an export's Esc latency.

Each row: workload, our median and 25-75% spread, the peer's, the ratio
ours/peer (< 1: we are faster), threads on each side, the goal (issue 37's
"Goals": they replace issue 21's where both set one; issue 21's stand where
37 keeps them met) and met/gap, and the 1-minute load average before and
after the measurement that produced the row (rows from one batch share it).
The header gives the date, `nproc`, the CPU model and the commit.

`--quick`: tiny reps and the smaller sizes only (5M sculpt and the
printable validation skipped), for a smoke run; its numbers are not for
the README. Not in scripts/test.sh: it needs the release examples (a cold
release build is minutes) and takes about 2 minutes on a busy 2-core
machine. The default is the full
run; `--markdown PATH` writes the table as markdown for the README's
Performance section; `--json PATH` writes every row.

Usage: python scripts/bench/run_all.py [--quick] [--markdown PATH] [--json PATH]
Needs numpy, scipy, scikit-image, manifold3d (scripts/bench/requirements.txt).
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import re
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
sys.path.insert(0, str(HERE))

EXAMPLES = [
    "sdf_bench",
    "gc_union_parts",
    "perf_goals",
    "history_bytes",
    "styling_systems",
    "interact_pick",
    "print_validate",
    "session_bench",
]
MIB = 2**20


def build() -> Path:
    subprocess.run(
        ["cargo", "build", "--release", "-q", "--workspace"]
        + [a for e in EXAMPLES for a in ("--example", e)],
        cwd=ROOT,
        check=True,
    )
    return Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target")) / "release" / "examples"


def load() -> float:
    return os.getloadavg()[0]


def machine() -> dict:
    model = ""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    try:
        commit = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "status", "--porcelain"], cwd=ROOT, capture_output=True, text=True
        ).stdout
        commit += " (uncommitted changes)" if dirty.strip() else ""
    except OSError:
        commit = "?"
    return {
        "date": datetime.datetime.now().astimezone().isoformat(timespec="seconds"),
        "nproc": os.cpu_count(),
        "cpu": model,
        "commit": commit,
        "load_start": os.getloadavg(),
    }


def met(row: dict) -> bool | None:
    """Checks the row's goal: `<= Kx` / `< Kx` on the ratio, `< N ms` or
    `< N MiB` on our median."""
    m = re.match(r"\s*(<=|<)\s*([\d.]+)\s*(x|ms|MiB)", row.get("goal") or "")
    if not m:
        return None
    op, k, unit = m.group(1), float(m.group(2)), m.group(3)
    v = row["ratio"] if unit == "x" else row["ours"][0]
    if v is None:
        return None
    return v <= k if op == "<=" else v < k


def row(
    workload,
    unit,
    ours,
    ours_threads,
    peer="",
    peer_value=None,
    peer_threads=None,
    goal="",
    note="",
    lb=0.0,
    la=0.0,
):
    return {
        "workload": workload,
        "unit": unit,
        "ours": list(ours),
        "ours_threads": ours_threads,
        "peer": peer,
        "peer_value": list(peer_value) if peer_value else None,
        "peer_threads": peer_threads,
        "ratio": ours[0] / peer_value[0] if peer_value else None,
        "goal": goal,
        "note": note,
        "load_before": lb,
        "load_after": la,
    }


# --- sources -----------------------------------------------------------------


def sdf_rows(ex: Path, quick: bool) -> list[dict]:
    import sdf

    reps = 3 if quick else 9
    out = []
    batches = [(dict(steps=[s], table1=True, full=False)) for s in (0.01, 0.006, 0.004)]
    batches.append(dict(steps=[0.01], table1=False, full=True))
    for kw in batches:
        lb = load()
        rows = sdf.run(reps, bin_path=str(ex / "sdf_bench"), **kw)
        la = load()
        for r in rows:
            note = ""
            if "parts_ms" in r:
                pm = r["parts_ms"]
                note = (
                    f"1 thread {r['ours_1t_ms'][0]:.2f} ms; resample {pm['sample_ms']:.2f}, fuse {pm['fuse_ms']:.2f}, "
                    f"extract {pm['extract_ms']:.2f}, drag frame {pm['drag_ms']:.2f} ms; {r['triangles']} tris "
                    f"(peer {r['peer_triangles']}); grid {r['memory_bytes']['grid_bytes'] / MIB:.1f} MiB"
                )
            else:
                note = f"1 thread {r['ours_1t_ms'][0]:.2f} ms; {r['triangles']} tris"
            out.append(
                row(
                    r["workload"],
                    "ms",
                    r["ours_ms"],
                    r["ours_threads"],
                    r["peer"],
                    r["peer_ms"],
                    r["peer_threads"],
                    r["goal"],
                    note,
                    lb,
                    la,
                )
            )
    return out


def union_rows(ex: Path, quick: bool) -> list[dict]:
    import gc_union

    out = []
    for r in gc_union.run(3 if quick else 9, bin_path=str(ex / "gc_union_parts")):
        out.append(
            row(
                r["workload"],
                "ms",
                r["ours"],
                r["ours_threads"],
                r["peer"],
                r["peer_value"],
                r["peer_threads"],
                r["goal"],
                r["note"],
                r["load_before"][0],
                r["load_after"][0],
            )
        )
    return out


def styling_rows(ex: Path, quick: bool) -> list[dict]:
    import styling

    out = []
    for r in styling.run(0.2 if quick else 1.0, bin_path=str(ex / "styling_systems")):
        q = r["ours"]["solve_ms"]  # [p25, median, p75]
        p = r["peers"]["superlu"]["solve_ms"]
        out.append(
            row(
                f"styling per-frame solve {r['name']} ({r['unknowns']} unknowns, {r['rhs']} rhs)",
                "ms",
                [q[1], q[0], q[2]],
                1,
                "SciPy SuperLU (splu, default COLAMD)",
                [p[1], p[0], p[2]],
                1,
                "<= 1.0x",
                f"vs SuperLU told SPD: {r['ratio_solve_spd']:.2f}; factor ours/SuperLU {r['ratio_factor']:.2f}",
                r["load"][0],
                r["load"][1],
            )
        )
    return out


def goal_rows(ex: Path, quick: bool) -> list[dict]:
    out = []

    def json_lines(cmd):
        lb = load()
        text = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
        la = load()
        return [json.loads(x) for x in text.splitlines() if x.startswith("{")], lb, la

    sizes = [(2_000_000, 1 if quick else 5)] + ([] if quick else [(5_000_000, 3)])
    for verts, reps in sizes:
        (r,), lb, la = json_lines([str(ex / "perf_goals"), "sculpt", str(verts), str(reps)])
        out.append(
            row(
                f"sculpt bench stroke p99 frame, {r['vertices']:,} vertices",
                "ms",
                r["p99_ms"],
                r["threads"],
                goal="< 11.1 ms",
                note=f"{r['reps']} strokes of {r['frames']} frames, spread over strokes; p50 frame {r['p50_ms'][0]:.2f} ms, "
                f"max {r['max_ms'][0]:.2f} ms; up to {r['max_moved_per_frame']:,} vertices moved per frame",
                lb=lb,
                la=la,
            )
        )
    if quick:
        out.append(
            row(
                "sculpt bench stroke p99 frame, 4,998,492 vertices",
                "ms",
                [float("nan")] * 3,
                None,
                note="skipped in --quick",
            )
        )
    rs, lb, la = json_lines([str(ex / "perf_goals"), "gc-commit", str(1 if quick else 5)])
    for r in rs:
        out.append(
            row(
                f"GC edit commit p99, {r['session']} ({r['ops']} ops)",
                "ms",
                r["p99_ms"],
                r["threads"],
                goal="< 30 ms",
                note=f"{r['reps']} replays, spread over replays; all commits p50 {r['p50_all_ms']:.1f} ms, max {r['max_ms']:.1f} ms "
                f"({r['slowest_op']}); ops: {', '.join(r['op_kinds'])}",
                lb=lb,
                la=la,
            )
        )
    (r,), lb, la = json_lines([str(ex / "history_bytes"), str(2000 if quick else 20000)])
    v = r["bytes_per_1000_ops"] / MIB
    out.append(
        row(
            f"history per 1,000 ops, {r['objects']}-object session ({r['ops']:,} ops)",
            "MiB",
            [v, v, v],
            1,
            goal="< 1 MiB",
            note=f"deterministic bytes (no spread); slope {r['slope_bytes_per_1000_ops'] / MIB:.2f} MiB per 1,000 ops; "
            f"document itself {r['document_bytes'] / MIB:.2f} MiB; undo+redo {r['undo_redo_us']:.1f} us at {r['ops']:,} ops "
            f"vs {r['undo_redo_us_at_1000']:.1f} us at 1,000",
            lb=lb,
            la=la,
        )
    )
    return out


def session_rows(ex: Path, quick: bool) -> list[dict]:
    lb = load()
    cmd = [str(ex / "session_bench"), "2" if quick else "5", "1" if quick else "3"]
    text = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    la = load()
    rs = {}
    for x in text.splitlines():
        if x.startswith("{"):
            r = json.loads(x)
            rs.setdefault(r["row"], []).append(r)
    apply = rs["single_user_apply"][0]
    out = []
    for r in rs["round_trip"]:
        p99, lo, hi = r["p99_ms"]
        out.append(
            row(
                f"shared session op round trip p99, {r['people']} people at {r['rate_hz']} ops/s each",
                "ms",
                [p99, lo, hi],
                r["people"],
                goal="< 11.1 ms",
                note=f"nats-server 2.9 on loopback over TLS (team CA, per-person subjects), one thread per person; p99 median (min-max) over {r['reps']} runs of "
                f"{r['secs']:g} s, {r['samples']} round trips; p50 {r['p50_ms']:.2f} ms, max {r['max_ms']:.1f} ms; "
                f"the same op applied alone (single user): p50 {apply['p50_ms'] * 1000:.0f} us",
                lb=lb,
                la=la,
            )
        )
    (j,) = rs["join"]
    out.append(
        row(
            f"joining a {j['entries']:,}-entry session: snapshot + tail ({j['tail']} entries)",
            "ms",
            [j["snapshot_ms"], *j["snapshot_spread"]],
            1,
            peer="replaying the whole stream",
            peer_value=[j["replay_ms"], *j["replay_spread"]],
            peer_threads=1,
            note=f"{j['reps']} joins each (median, min-max), over TLS; both end bit-identical to the writer; "
            f"the background check of the snapshot against the stream ends {j['checked_ms']:.0f} ms after the join starts",
            lb=lb,
            la=la,
        )
    )
    return out


def other_rows(ex: Path, quick: bool) -> list[dict]:
    import interact
    import print as print_bench

    out = []
    found = interact.run(str(ex / "interact_pick"), reps=1 if quick else 5)
    if quick:
        # The 1M-triangle validation alone takes most of a minute.
        out.append(
            row(
                "printable validation (teapot, sphere_1m)",
                "ms",
                [float("nan")] * 3,
                None,
                note="skipped in --quick",
            )
        )
    else:
        # Issue 37: validation (its exact self-intersection search included)
        # no slower than manifold3d's import check; print.py's other rows
        # (the whole print path, the edit-time fold check) have no peer.
        found += [
            dict(r, goal="<= 1.0x") if r["workload"].startswith("printable validation") else r
            for r in print_bench.run(5, bin_path=str(ex / "print_validate"))
        ]
    for r in found:
        out.append(
            row(
                r["workload"],
                r["unit"],
                r["ours"],
                r["ours_threads"],
                r["peer"],
                r["peer_value"],
                r["peer_threads"],
                r.get("goal", ""),
                r["note"],
                r["load_before"],
                r["load_after"],
            )
        )
    return out


# --- output ------------------------------------------------------------------


def fmt(v: list[float] | None, unit: str) -> str:
    if not v:
        return "-"
    if v[0] != v[0]:  # NaN: not measured
        return "-"
    d = 3 if unit == "MiB" or v[0] < 1 else (2 if v[0] < 100 else 1)
    if v[1] == v[0] == v[2]:
        return f"{v[0]:.{d}f} {unit}"
    return f"{v[0]:.{d}f} ({v[1]:.{d}f}-{v[2]:.{d}f}) {unit}"


def verdict(r: dict) -> str:
    m = r["met"]
    if m is None:
        return ""
    if m:
        return "met"
    mm = re.match(r"\s*(<=|<)\s*([\d.]+)\s*(x|ms|MiB)", r["goal"])
    k, unit = float(mm.group(2)), mm.group(3)
    v = r["ratio"] if unit == "x" else r["ours"][0]
    return f"gap {v / k:.2f}x"


def table(rows: list[dict]) -> list[list[str]]:
    out = []
    for r in rows:
        out.append(
            [
                r["workload"],
                fmt(r["ours"], r["unit"]),
                "" if r["ours_threads"] is None else str(r["ours_threads"]),
                r["peer"] or "-",
                fmt(r["peer_value"], r["unit"]),
                "" if r["peer_threads"] is None else str(r["peer_threads"]),
                "-" if r["ratio"] is None else f"{r['ratio']:.2f}",
                r["goal"] or "-",
                verdict(r),
                f"{r['load_before']:.2f} / {r['load_after']:.2f}",
                r["note"],
            ]
        )
    return out


HEAD = [
    "workload",
    "ours median (25-75%)",
    "thr",
    "peer",
    "peer median (25-75%)",
    "thr",
    "ratio",
    "goal",
    "met/gap",
    "load before/after",
    "note",
]


def header(m: dict, quick: bool, elapsed: float) -> list[str]:
    return [
        f"Shapewright honest bench{' (--quick: smoke run, not for the README)' if quick else ''}",
        f"date {m['date']}; commit {m['commit']}; nproc {m['nproc']}; CPU {m['cpu']}; "
        f"load average at start {m['load_start'][0]:.2f} {m['load_start'][1]:.2f} {m['load_start'][2]:.2f}; "
        f"run took {elapsed:.0f} s",
        "ratio = ours / peer (below 1: we are faster); thr = threads on each side; "
        "spread = 25th-75th percentile over reps; load = 1-minute load average before / after the batch that made the row.",
    ]


def print_text(rows: list[dict], head: list[str]) -> None:
    cells = table(rows)
    widths = [max(len(HEAD[i]), *(len(c[i]) for c in cells)) for i in range(len(HEAD) - 1)]
    for h in head:
        print(h)
    line = " | ".join(HEAD[i].ljust(widths[i]) for i in range(len(widths))) + " | note"
    print(line)
    print("-" * len(line))
    for c in cells:
        print(" | ".join(c[i].ljust(widths[i]) for i in range(len(widths))) + " | " + c[-1])


def markdown(rows: list[dict], head: list[str]) -> str:
    lines = [h + "  " for h in head] + [""]
    lines.append("| " + " | ".join(HEAD) + " |")
    lines.append("|" + "---|" * len(HEAD))
    for c in table(rows):
        lines.append("| " + " | ".join(x.replace("|", "/") for x in c) + " |")
    return "\n".join(lines) + "\n"


def blender_rows(ex: Path, quick: bool) -> list[dict]:
    import blender

    lb = load()
    rs = {r["row"]: r for r in blender.rows(quick)}
    la = load()

    def spread(v: list[float]) -> list[float]:
        v = sorted(v)
        return [v[len(v) // 2], v[len(v) // 4], v[(3 * len(v)) // 4]]

    rec = rs["record"]
    small, big = [m[0] for m in rec["ms"]], [m[1] for m in rec["ms"]]
    out = [
        row(
            f"Blender: record one op with {rec['big']:,} ops in the log",
            "ms",
            spread(big),
            1,
            peer=f"the same with {rec['small']} ops",
            peer_value=spread(small),
            peer_threads=1,
            goal="<= 1.5x",
            note="median of 25 renames through the add-on (op, the scene's history key, the sync) per run; "
            "spread over runs (one bpy process each)",
            lb=lb,
            la=la,
        ),
        row(
            f"Blender: autosave UI-thread time after an edit, {rs['autosave']['triangles']:,} triangles",
            "ms",
            spread(rs["autosave"]["ms"]),
            1,
            goal="< 50 ms",
            note="the usda is written on the autosave's own thread (shapewright.Autosaver); spread over runs",
            lb=lb,
            la=la,
        ),
        row(
            "Blender: export Esc to the thread's end, 6 overlapping spheres",
            "ms",
            spread(rs["cancel"]["ms"]),
            2,
            goal="< 1000 ms",
            note=f"Esc once the progress passed 30% (in the union; at {min(rs['cancel']['at']):.0%} to "
            f"{max(rs['cancel']['at']):.0%}); spread over runs",
            lb=lb,
            la=la,
        ),
    ]
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="tiny reps, smaller sizes: a smoke run (< 2 min)")
    ap.add_argument("--markdown", help="write the table as markdown here")
    ap.add_argument("--json", help="write every row as JSON here")
    ap.add_argument(
        "--only", help="comma list of sources: sdf,union,styling,goals,session,other,blender (default all)"
    )
    args = ap.parse_args()
    start = time.time()
    m = machine()
    ex = build()
    sources = {
        "sdf": sdf_rows,
        "union": union_rows,
        "styling": styling_rows,
        "goals": goal_rows,
        "session": session_rows,
        "other": other_rows,
        "blender": blender_rows,
    }
    chosen = args.only.split(",") if args.only else list(sources)
    rows: list[dict] = []
    for name in chosen:
        t = time.time()
        rows += sources[name](ex, args.quick)
        print(f"[{name}: {time.time() - t:.0f} s]", file=sys.stderr)
    for r in rows:
        r["met"] = met(r)
    head = header(m, args.quick, time.time() - start)
    print_text(rows, head)
    if args.markdown:
        Path(args.markdown).write_text(markdown(rows, head))
    if args.json:
        Path(args.json).write_text(json.dumps({"machine": m, "rows": rows}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
