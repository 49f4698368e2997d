"""The History panel's verdict on the model: the export's own check.

The panel runs the core's print path without writing (`ExportJob` with no
path: the same union, thickening and validation at the precision STL and
3MF store), so it says "Printable" exactly when Export writes a file,
and otherwise the export's own refusal. With the verdict come the print
size (bounding box in millimetres, volume in cubic centimetres, whatever
the scene's units: slicers think in millimetres) and whether it fits the
document's printer (`set_printer`), all from the core.

It runs on a thread of its own on a snapshot of the document, once per
state of the log (the scene's key); a new state cancels a check still
running for an old one (the core stops it within one boolean).
"""

from __future__ import annotations

import bpy
import shapewright as sw

from . import history

# scene name -> (key, job or None, verdict or None)
_checks: dict[str, list] = {}
checks_run = 0  # how many checks ran to the end (tests check the cache)


def forget() -> None:
    for _, job, _ in _checks.values():
        if job is not None:
            job.cancel()
    _checks.clear()


def _verdict(job: sw.ExportJob) -> dict:
    global checks_run
    try:
        r = job.result()
    except sw.ShapewrightError as e:
        checks_run += 1
        return {"printable": False, "message": str(e)}
    checks_run += 1
    # Size, volume and bed fit are the core's (the export's summary).
    return {
        "printable": True,
        "message": "Printable",
        "size_mm": tuple(r.get("size_mm", (0.0, 0.0, 0.0))),
        "volume_cm3": r.get("volume_cm3", 0.0),
        "fits": r.get("fits", True),
        "fit": r.get("fit", ""),
        "triangles": r["triangles"],
    }


def _poll() -> float | None:
    running = False
    for entry in _checks.values():
        key, job, verdict = entry
        if job is not None and verdict is None:
            if job.done():
                entry[2] = _verdict(job)
                entry[1] = None
            else:
                running = True
    history.tag_redraw()
    return 0.25 if running else None


def verdict(scene: bpy.types.Scene, wait: bool = False) -> dict | None:
    """`{"printable", "message", "size_mm", "volume_cm3", "fits", "fit"}` for the scene's
    model, or None while it is being checked (a redraw follows). `wait`
    blocks until it is known (scripts, tests)."""
    key = (history.key_of(scene), scene.shapewright.gen)
    entry = _checks.get(scene.name)
    if entry is not None and entry[0] == key:
        if entry[2] is None and entry[1] is not None and (wait or entry[1].done()):
            entry[2] = _verdict(entry[1])
            entry[1] = None
        return entry[2]
    if entry is not None and entry[1] is not None:
        entry[1].cancel()
    job = sw.ExportJob(history.session(scene))
    _checks[scene.name] = [key, job, None]
    if wait:
        return verdict(scene, wait=True)
    if not bpy.app.timers.is_registered(_poll):
        bpy.app.timers.register(_poll, first_interval=0.25)
    return None


def unregister() -> None:
    if bpy.app.timers.is_registered(_poll):
        bpy.app.timers.unregister(_poll)
    forget()
