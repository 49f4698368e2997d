"""Nothing freezes (issue 34): recording an op costs the same at op 10 as
at op 2,000; autosave costs the UI thread milliseconds on a big document
(the write runs on a thread of its own); an export's Esc stops it within
a second, with its progress moving through the union; Join returns at
once (the connection is made on a thread). The measurements are also the
bench's (`scripts/bench/blender.py` calls `measure_*` with bigger sizes)."""

from __future__ import annotations

import statistics
import time
from pathlib import Path

import bpy
from helpers import addon, core_session, module, step


def _solid(segments: int, x: float = 0.0, radius: float = 0.05) -> dict:
    return {
        "op": "add_solid",
        "shape": {"kind": "sphere", "radius": radius},
        "segments": segments,
        "transform": {"translate": [x, 0.0, 0.0]},
    }


def measure_record(counts: tuple[int, ...], reps: int = 25) -> dict[int, float]:
    """Median seconds of recording one op (a rename, through the add-on's
    `history.apply`: the op, the scene's history key, the sync) when the
    log already holds each of `counts` ops."""
    scene = bpy.context.scene
    hist = addon().history
    hist.apply(scene, _solid(16))
    out = {}
    have = 1
    for n in counts:
        s = core_session()
        lines = "".join(f'{{"op":"rename_object","id":1,"name":"r{k}"}}\n' for k in range(have, n))
        s.run_script(lines)
        hist.record(scene, s)
        have = n
        times = []
        for k in range(reps):
            t0 = time.perf_counter()
            hist.apply(scene, {"op": "rename_object", "id": 1, "name": f"m{n}_{k}"})
            times.append(time.perf_counter() - t0)
            have += 1
        out[n] = statistics.median(times)
    return out


def measure_autosave(segments: int, spheres: int = 1) -> tuple[float, int]:
    """Main-thread seconds of the autosave after one edit of a document
    of `spheres` spheres of about segments^2 triangles each, and the
    document's triangles."""
    scene = bpy.context.scene
    hist = addon().history
    for k in range(spheres):
        hist.apply(scene, _solid(segments, 0.2 * k))
    tris = core_session().validate()["triangles"]
    persist = module("persist")
    s = core_session()
    if persist is not None:
        persist.autosaver(scene).wait()
        s.apply({"op": "rename_object", "id": s.object_ids()[0], "name": "big"})
        t0 = time.perf_counter()
        persist.changed(scene, s)
        dt = time.perf_counter() - t0
        saver = persist.autosaver(scene)
        saver.wait()
        assert saver.last_error is None and saver.saves >= 1, saver.last_error
        assert Path(saver.path).stat().st_size > tris * 10
        return dt, tris
    # Before issue 34: the autosave timer wrote the file on the UI thread.
    s.apply_line('{"op":"rename_object","id":1,"name":"big"}')
    hist.record(scene, s)
    t0 = time.perf_counter()
    hist.autosave_tick()
    return time.perf_counter() - t0, tris


def measure_export_cancel(spheres: int, segments: int, whole: bool = True) -> tuple[float, float, float]:
    """(seconds from Esc to the export thread's end, the progress fraction
    when Esc came, the whole export's seconds or NaN when `whole` is
    False) for `spheres` overlapping spheres."""
    scene = bpy.context.scene
    hist = addon().history
    for k in range(spheres):
        hist.apply(scene, _solid(segments, 0.07 * k))
    owner = module("ops_export") or addon().operators
    out = Path(bpy.app.tempdir or "/tmp") / "cancel.stl"
    t0 = time.perf_counter()
    if whole:
        full = owner.ExportTask(core_session(), str(out))
        while not full.job.done():
            time.sleep(0.01)
    seconds = time.perf_counter() - t0 if whole else float("nan")
    task = owner.ExportTask(core_session(), str(out.with_name("cancel2.stl")))
    while task.progress()[1] < 0.3 and not task.job.done():
        time.sleep(0.002)
    at = task.progress()[1]
    t0 = time.perf_counter()
    task.cancel()
    while not task.job.done():
        time.sleep(0.001)
    return time.perf_counter() - t0, at, seconds


def scenario_record_flat(work: Path) -> None:
    """Recording an op costs about the same with 2,000 ops in the log as
    with 10 (the log is appended in the core, never re-serialized)."""
    t = measure_record((10, 2000))
    print(f"record: {t[10] * 1e3:.3f} ms at 10 ops, {t[2000] * 1e3:.3f} ms at 2,000 ops")
    assert t[2000] < 1.5 * t[10] + 0.0002, (
        f"{t[2000] * 1e3:.2f} ms at 2,000 ops vs {t[10] * 1e3:.2f} ms at 10"
    )


def scenario_autosave_off_thread(work: Path) -> None:
    """On a document of a million triangles the autosave costs the UI
    thread under 50 ms (the usda is written on a thread of its own)."""
    dt, tris = measure_autosave(1024)
    print(f"autosave: {dt * 1e3:.2f} ms on the main thread for {tris} triangles")
    assert tris > 900_000, tris
    assert dt < 0.05, f"the autosave held the UI for {dt * 1e3:.0f} ms"


def scenario_export_cancel(work: Path) -> None:
    """Esc stops an export within a second, from the middle of the union
    (its progress moves through the union first)."""
    latency, at, whole = measure_export_cancel(6, 200)
    print(f"export: whole {whole:.2f} s; Esc at {at:.0%} stopped it {latency * 1e3:.0f} ms later")
    assert 0.05 < at < 0.85, f"progress at Esc: {at:.0%} (it should move through the union)"
    assert latency < 1.0, f"the export stopped {latency:.2f} s after Esc"


def scenario_join_async(work: Path) -> None:
    """Join on an unreachable host returns at once; the refusal reaches
    the status bar when the connection gives up."""
    bpy.context.window_manager.shapewright_join.url = "nats://10.255.255.1:4222/doc"
    step(bpy.ops.shapewright.add_solid(shape="sphere", use_cursor=False), "sphere")
    t0 = time.perf_counter()
    try:
        bpy.ops.shapewright.join()
    except RuntimeError as e:
        print(f"join refused: {e}")
    dt = time.perf_counter() - t0
    print(f"join: returned after {dt * 1e3:.0f} ms")
    assert dt < 0.5, f"Join held the UI for {dt:.1f} s"
    shared, notify = module("shared"), module("notify")
    deadline = time.monotonic() + 60
    while shared.joining and time.monotonic() < deadline:
        time.sleep(0.1)
        shared.finish_joins()
    assert not shared.joining and shared.joined(bpy.context.scene) is None
    assert any("could not join" in m for m in notify.messages), notify.messages
