"""A shared session with a headset host on a real nats-server."""

from __future__ import annotations

import os
from pathlib import Path

import bpy
from helpers import add, addon, assert_synced


def scenario_shared_session(work: Path) -> None:
    """Issue 23: Blender and a headset host in one shared session, both
    headless. The headset host plays a recorded session (`shapewright-xr
    replay --join`) while Blender joins through the panel's Join, adds
    solids and undoes its own last one: both end with the same document,
    bit for bit, holding both people's work; each drew the other's
    presence; Blender's own undo cannot take a shared edit back."""
    import subprocess
    import time

    url = os.environ["SHAPEWRIGHT_JOIN_URL"]
    shared = addon().shared
    scene = bpy.context.scene
    wm = bpy.context.window_manager.shapewright_join
    wm.url, wm.name = url, "Bea"
    assert bpy.ops.shapewright.join() == {"FINISHED"}
    # Join connects on a thread (issue 34); the add-on's timer, which
    # Blender's event loop runs, takes the session once it is connected.
    t0 = time.monotonic()
    while shared.joining:
        assert time.monotonic() - t0 < 60, "Join did not finish"
        time.sleep(0.05)
        shared.finish_joins()
    s = shared.joined(scene)
    assert s is not None and s.shared_url == url, s
    headset = subprocess.Popen(
        [os.environ["SHAPEWRIGHT_HOST_BIN"], "replay", os.environ["SHAPEWRIGHT_TRACE"]]
        + ["--join", url, "--me", "hal", "--name", "Hal", "--quiet-secs", "2"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    add("box", 0.3)
    add("sphere", 0.6)
    add("cone", 0.9)
    # Bea's undo takes back her cone, whatever the headset did meanwhile.
    assert bpy.ops.shapewright.undo() == {"FINISHED"}
    people = 0
    t0 = time.monotonic()
    while headset.poll() is None:
        shared.pump(scene)
        coll = bpy.data.collections.get(shared.PEOPLE)
        people = max(people, len(coll.objects) if coll else 0)
        assert time.monotonic() - t0 < 300, "the headset host did not finish"
        time.sleep(0.01)
    out, err = headset.communicate()
    assert headset.returncode == 0, out + err
    want = next(line.split()[1] for line in out.splitlines() if line.startswith("content "))
    hal_drew = int(next(line.split()[1] for line in out.splitlines() if line.startswith("people ")))
    while f"{s.content_hash():016x}" != want:
        shared.pump(scene)
        assert time.monotonic() - t0 < 330, f"Blender has {s.content_hash():016x}, the headset {want}"
        time.sleep(0.01)
    assert_synced()
    ids = s.object_ids()
    slots = {pid: i + 1 for i, (pid, _, _) in enumerate(s.participants())}
    bea = [i for i in ids if i >> 24 == slots["Bea"]]
    hal = [i for i in ids if i >> 24 == slots["hal"]]
    kinds = sorted(s.object_params(i)["shape"]["kind"] for i in bea)
    assert kinds == ["box", "sphere"], kinds
    assert hal, f"no object of the headset's in {ids}"
    assert people >= 1, "Blender showed no empty for the headset's presence"
    assert hal_drew >= 1, "the headset drew nobody for Blender's presence"
    # Blender's own undo steps do not take a shared edit back.
    before = s.content_hash()
    bpy.ops.ed.undo()
    scene = bpy.context.scene  # Blender's undo made the scene anew
    assert s.content_hash() == before
    assert_synced()
    assert bpy.ops.shapewright.leave() == {"FINISHED"}
    assert addon().history.session(scene).content_hash() == before
    print(f"shared: {len(bea)} of Bea's, {len(hal)} of Hal's objects, {people} people empties, hash {want}")
