"""Resource-abuse sweep (issue 22): every abusive input the issue lists, at
extreme values, through the real CLI, each under an address-space limit and
a timeout.

    python3 scripts/abuse_sweep.py [--bin target/release/shapewright-xr]
        [--limit-gb 8] [--timeout 60] [--quick] [--only SUBSTR] [--work DIR]

Each case runs `shapewright-xr apply|replay|info|import ...` in its own
process group with RLIMIT_AS set (what `ulimit -v` sets) and is killed at
the timeout. The table gives, per case: the outcome

- `ok`: exit 0 (a bounded success),
- `error: ...`: exit 1 with the CLI's message (a typed error),
- `ABORT ...`: killed by a signal (allocation failure aborts with SIGABRT),
  any other exit code, or a Rust panic,
- `TIMEOUT`: still running at the timeout,

its wall time and peak RSS (from wait4). The script exits 1 when any case
is an ABORT or a TIMEOUT. `--quick` runs the subset that takes a few seconds
(what CI runs); the full sweep is run by hand and reported.
"""

import argparse
import json
import math
import os
import pathlib
import resource
import signal
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
DATA = ROOT / "tests" / "data"
ABUSE = DATA / "abuse"


def ops_of(path):
    return [json.loads(line) for line in open(path) if line.strip() and not line.startswith("#")]


def jsonl(ops):
    return "\n".join(json.dumps(o, separators=(",", ":")) for o in ops) + "\n"


def mug_gc():
    return dict(next(o for o in ops_of(DATA / "mug.jsonl") if o["op"] == "gc_create"))


def gc_with(sections=None, resolution=None, profile=None):
    gc = mug_gc()
    if sections is not None:
        prof = profile or (lambda i: {"template": "circle", "radius": 0.04})
        gc["sections"] = [{"profile": prof(i), "v": i / (sections - 1)} for i in range(sections)]
    if resolution is not None:
        gc["resolution"] = {"u": resolution[0], "v": resolution[1]}
    return [gc]


def points_profile(n, seed):
    # A wavy star loop of n points (distinct per section: no shared knots).
    pts = []
    for j in range(n):
        a = 2 * math.pi * j / n
        r = 0.04 * (1 + 0.1 * math.sin(7 * a + seed))
        pts.append([r * math.cos(a), r * math.sin(a)])
    return {"template": "points", "points": pts}


def curve_base():
    net = ops_of(DATA / "curve_network.jsonl")
    draw = next(o for o in net if o["op"] == "curve_draw")
    return net[0], draw


def curve_case(samples=None, resample=None, fit=None):
    create, draw = curve_base()
    draw = dict(draw)
    if samples is not None:
        draw["samples"] = samples
    if resample is not None:
        draw["resample"] = resample
    if fit is not None:
        draw["fit"] = fit
    return [create, draw]


def sculpt_base():
    """The far-sample reproducer with its last sample brought back next to
    the one before (a sane drag), so each case varies one thing only."""
    create, stroke = ops_of(ABUSE / "sculpt_far_sample.jsonl")
    samples = stroke["samples"]
    samples[-1]["position"] = [p + 0.01 for p in samples[-2]["position"]]
    return [create, stroke]


def sculpt_case(max_edge_rel=None, min_edge_rel=None, last=None, warp=None, samples=None):
    create, stroke = sculpt_base()
    stroke = json.loads(json.dumps(stroke))
    st = stroke["settings"]
    if max_edge_rel is not None:
        st["max_edge_rel"] = max_edge_rel
        st["min_edge_rel"] = min_edge_rel if min_edge_rel is not None else max_edge_rel / 4
    if warp is not None:
        st["warp"] = warp
    if samples is not None:
        stroke["samples"] = samples
    if last is not None:
        stroke["samples"][-1]["position"] = last
    return [create, stroke]


def long_stroke(n):
    out = []
    for i in range(n):
        a = 2 * math.pi * i / n
        out.append(
            {
                "position": [0.9 * math.cos(a), 0.9 * math.sin(a), 0.4],
                "rotation": [0.0, 0.0, 0.0, 1.0],
                "pressure": 1.0,
            }
        )
    return out


def nested_usda(n):
    s = ['#usda 1.0\n(\n    metersPerUnit = 1\n    upAxis = "Z"\n)\n']
    for i in range(n):
        s.append(
            f'def Xform "P{i}" {{\n double3 xformOp:translate = (0, 0, 0.001)\n'
            ' uniform token[] xformOpOrder = ["xformOp:translate"]\n'
        )
    s.append(
        'def Mesh "M" {\n int[] faceVertexCounts = [3,3,3,3]\n'
        " int[] faceVertexIndices = [0,2,1, 0,1,3, 1,2,3, 0,3,2]\n"
        " point3f[] points = [(0,0,0),(1,0,0),(0,1,0),(0,0,1)]\n}\n"
    )
    s.append("}\n" * n)
    return "".join(s)


def trace_at_scale(name, scale):
    lines = (DATA / name).read_text().splitlines()
    head = json.loads(lines[0])
    head["model"]["scale"] = scale
    return "\n".join([json.dumps(head)] + lines[1:]) + "\n"


def duplicates(n):
    ops = [{"op": "add_solid", "shape": {"kind": "sphere", "radius": 0.05}}]
    ops += [{"op": "duplicate", "id": 1} for _ in range(n)]
    return ops


def cases():
    """(name, quick, kind, payload): kind `apply` (ops or a file), `replay`
    (trace text), `info` (a usda file or text), `import` (usda text)."""
    far = [0.0, 0.0, 0.0]
    create, draw = curve_base()
    ring = [
        [0.1 * math.cos(2 * math.pi * i / 1e5), 0.1 * math.sin(2 * math.pi * i / 1e5), 0.0]
        for i in range(100_000)
    ]
    yield "gc resolution 4096x4096", True, "apply", ABUSE / "gc_resolution_4096.jsonl"
    yield "gc resolution 4096x4", True, "apply", gc_with(resolution=(4096, 4))
    yield "gc resolution 4x4096", True, "apply", gc_with(resolution=(4, 4096))
    yield "gc resolution 2000x2000", True, "apply", gc_with(resolution=(2000, 2000))
    yield "gc resolution 1000x1000 (under the grid limit)", False, "apply", gc_with(resolution=(1000, 1000))
    yield "gc resolution 2048x2048", True, "apply", gc_with(resolution=(2048, 2048))
    yield (
        "gc handle on a 1000x1000 body (over the time limit)",
        True,
        "apply",
        gc_with(resolution=(1000, 1000)) + [ops_of(DATA / "mug.jsonl")[1]],
    )
    yield "gc 256 sections (the limit)", False, "apply", gc_with(sections=256)
    yield "gc 257 sections", True, "apply", gc_with(sections=257)
    yield "gc 20,000 sections", True, "apply", gc_with(sections=20_000)
    yield "gc 1e6 sections", False, "apply", gc_with(sections=1_000_000)
    yield (
        "gc 64 sections of distinct 4096-point loops",
        False,
        "apply",
        gc_with(sections=64, profile=lambda i: points_profile(4096, i)),
    )
    yield (
        "gc 1024-gon sections at 4096x1000",
        False,
        "apply",
        gc_with(
            sections=4,
            resolution=(4096, 1000),
            profile=lambda i: {"template": "polygon", "sides": 1024, "radius": 0.04},
        ),
    )
    ins = mug_gc()
    yield (
        "gc_insert_section x300",
        False,
        "apply",
        [ins]
        + [
            {"op": "gc_insert_section", "id": 1, "part": 0, "v": 0.5 + 0.4 * (i + 1) / 301}
            for i in range(300)
        ],
    )
    yield "curve_draw resample 1e-9", True, "apply", ABUSE / "curve_draw_resample_tiny.jsonl"
    yield "curve_draw sample 1e12 m away", True, "apply", ABUSE / "curve_draw_far_sample.jsonl"
    yield (
        "curve_draw sample 9999 m away, resample 1 mm",
        True,
        "apply",
        curve_case(samples=draw["samples"] + [[9999.0, 0.0, 0.0]], resample=0.001),
    )
    yield "curve_draw samples +-1e200", True, "apply", ABUSE / "styling_curve_huge_sample.jsonl"
    yield "curve_draw 1e5 samples", True, "apply", curve_case(samples=ring, resample=None)
    yield "curve_draw 1e5 samples, resample 1e-4", False, "apply", curve_case(samples=ring, resample=1e-4)
    yield (
        "replay curve trace at model scale 1e-9",
        False,
        "replay",
        trace_at_scale("curve_network.trace.jsonl", 1e-9),
    )
    yield (
        "replay curve trace at model scale 1e-4",
        False,
        "replay",
        trace_at_scale("curve_network.trace.jsonl", 1e-4),
    )
    yield (
        "replay curve trace at model scale 1e4",
        False,
        "replay",
        trace_at_scale("curve_network.trace.jsonl", 1e4),
    )
    yield "replay sculpt trace at model scale 1e-4", False, "replay", trace_at_scale("bust.trace.jsonl", 1e-4)
    yield "sculpt max_edge_rel 1e-4", True, "apply", ABUSE / "sculpt_small_max_edge.jsonl"
    yield "sculpt max_edge_rel 1e-3 (the floor)", True, "apply", sculpt_case(max_edge_rel=1e-3)
    yield "sculpt max_edge_rel 0.02", False, "apply", sculpt_case(max_edge_rel=0.02)
    yield "sculpt sample 100 m away (drag)", True, "apply", ABUSE / "sculpt_far_sample.jsonl"
    yield "sculpt sample 9999 m away (drag)", True, "apply", sculpt_case(last=[9999.0, 0.0, 0.0])
    yield "sculpt explode delta 1e6", True, "apply", sculpt_case(warp={"kind": "explode", "delta": 1e6})
    yield "sculpt 1e5-sample stroke", False, "apply", sculpt_case(samples=long_stroke(100_000))
    yield (
        "sculpt_create box 1e4 m, edge 1 mm",
        True,
        "apply",
        [{"op": "sculpt_create", "base": {"kind": "box", "size": [1e4, 1.0, 1.0], "edge_length": 1e-3}}],
    )
    yield "sdf_create step 1e-6 + sphere operand", True, "apply", sdf_case(1e-6)
    yield "info: usda whose op has a far sample", True, "info", ABUSE / "info_far_sample.usda"
    yield "import 2,000 nested prims", True, "import", nested_usda(2000)
    yield "import 5,000 nested prims (over the limit)", True, "import", nested_usda(5000)
    yield "2,000 duplicated spheres", False, "apply", duplicates(2000)
    _ = far


def sdf_case(step):
    cup = ops_of(DATA / "csg_cup.jsonl")
    out = []
    for o in cup:
        if o["op"] == "sdf_create":
            o = dict(o, step=step)
        out.append(o)
        if o["op"] == "sdf_add_operand":
            break
    return out


def run(argv, limit_bytes, timeout):
    def child():
        resource.setrlimit(resource.RLIMIT_AS, (limit_bytes, limit_bytes))

    r, w = os.pipe()
    t0 = time.monotonic()
    pid = os.fork()
    if pid == 0:
        try:
            os.setsid()
            child()
            os.dup2(w, 2)
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, 1)
            os.close(r)
            os.execv(argv[0], argv)
        finally:
            os._exit(127)
    os.close(w)
    os.set_blocking(r, False)
    err = bytearray()
    timed_out = False
    while True:
        try:
            chunk = os.read(r, 65536)
            if chunk and len(err) < 1 << 20:
                err += chunk
        except BlockingIOError:
            pass
        done, status, usage = os.wait4(pid, os.WNOHANG)
        if done:
            break
        if time.monotonic() - t0 > timeout:
            timed_out = True
            os.killpg(pid, signal.SIGKILL)
            _, status, usage = os.wait4(pid, 0)
            break
        time.sleep(0.02)
    elapsed = time.monotonic() - t0
    try:
        while chunk := os.read(r, 65536):
            err += chunk
    except BlockingIOError:
        pass
    os.close(r)
    text = err.decode(errors="replace")
    rss_mb = usage.ru_maxrss / 1024
    if timed_out:
        outcome = "TIMEOUT"
    elif os.WIFSIGNALED(status):
        outcome = f"ABORT (signal {signal.Signals(os.WTERMSIG(status)).name})"
    elif "panicked" in text:
        outcome = "ABORT (panic: " + next(ln for ln in text.splitlines() if "panicked" in ln)[:120] + ")"
    elif os.WEXITSTATUS(status) == 0:
        outcome = "ok"
    elif os.WEXITSTATUS(status) == 1 and text.strip():
        lines = [ln for ln in text.strip().splitlines() if ln.strip()]
        outcome = "error: " + lines[-1].replace("shapewright-xr: ", "")
    else:
        outcome = f"ABORT (exit {os.WEXITSTATUS(status)})"
    return outcome, elapsed, rss_mb


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", default=str(ROOT / "target" / "release" / "shapewright-xr"))
    ap.add_argument("--limit-gb", type=float, default=8.0)
    ap.add_argument("--timeout", type=float, default=60.0)
    ap.add_argument("--quick", action="store_true", help="only the cases that take a few seconds (CI)")
    ap.add_argument("--only", default="", help="only cases whose name contains this")
    ap.add_argument("--work", default=None, help="directory for the generated inputs and outputs")
    ap.add_argument("--width", type=int, default=150, help="outcome column width")
    a = ap.parse_args()
    exe = str(pathlib.Path(a.bin).resolve())
    work = pathlib.Path(a.work or tempfile.mkdtemp(prefix="abuse_sweep_"))
    work.mkdir(parents=True, exist_ok=True)
    limit = int(a.limit_gb * (1 << 30))
    rows = []
    print(f"binary {exe}\nlimit {a.limit_gb} GiB address space, timeout {a.timeout:.0f} s, work {work}")
    print(f"load average before: {os.getloadavg()}")
    print(f"{'case':<48} {'time s':>7} {'peak MB':>8}  outcome")
    for i, (name, quick, kind, payload) in enumerate(cases()):
        if a.quick and not quick:
            continue
        if a.only and a.only not in name:
            continue
        stem = work / f"case{i:02d}"
        if kind == "apply":
            if isinstance(payload, pathlib.Path):
                inp = payload
            else:
                inp = stem.with_suffix(".jsonl")
                inp.write_text(jsonl(payload))
            argv = [exe, "apply", str(inp), "--out", str(stem.with_suffix(".out.stl"))]
        elif kind == "replay":
            inp = stem.with_suffix(".trace.jsonl")
            inp.write_text(payload)
            argv = [exe, "replay", str(inp), "--out", str(stem.with_suffix(".out.usda"))]
        elif kind == "info":
            argv = [exe, "info", str(payload)]
        elif kind == "import":
            inp = stem.with_suffix(".usda")
            inp.write_text(payload)
            argv = [
                exe,
                "import",
                str(inp),
                "--as",
                "component",
                "--into",
                str(stem.with_suffix(".doc.usda")),
            ]
        else:
            raise ValueError(kind)
        outcome, secs, rss = run(argv, limit, a.timeout)
        rows.append((name, outcome, secs, rss))
        print(f"{name:<48} {secs:7.2f} {rss:8.0f}  {outcome[: a.width]}", flush=True)
    bad = [r for r in rows if r[1].startswith(("ABORT", "TIMEOUT"))]
    ok = sum(r[1] == "ok" for r in rows)
    errs = sum(r[1].startswith("error") for r in rows)
    aborts = sum(r[1].startswith("ABORT") for r in rows)
    timeouts = sum(r[1] == "TIMEOUT" for r in rows)
    worst_t = max((r[2] for r in rows), default=0.0)
    worst_m = max((r[3] for r in rows), default=0.0)
    print(
        f"\n{len(rows)} cases: {ok} ok, {errs} typed errors, {aborts} aborts, {timeouts} timeouts; "
        f"slowest {worst_t:.1f} s, largest peak RSS {worst_m:.0f} MB; load average after: {os.getloadavg()}"
    )
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
