"""Blender-side checks of the Shapewright extension, one scenario per run:

    BLENDER_USER_RESOURCES=DIR python scenarios.py ZIP SCENARIO WORKDIR

Runs inside `bpy` (Blender 5.0.1 as a module, headless). Installs the
extension zip through Blender's extension API, enables it, then runs the
scenario; any failed assertion exits non-zero. Headless Blender does not
push undo steps for operators called from Python (the window manager does
that in the UI for 'UNDO' operators), so `step()` pushes one after each
operator, as the UI would.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import bpy
import numpy as np


def install(zip_path: str) -> None:
    bpy.ops.extensions.package_install_files(filepath=zip_path, repo="user_default", enable_on_install=True)
    assert "bl_ext.user_default.shapewright" in bpy.context.preferences.addons, "extension not enabled"
    bpy.ops.ed.undo_push(message="start")


def addon():
    import importlib

    return importlib.import_module("bl_ext.user_default.shapewright")


def step(result: set[str], label: str) -> None:
    assert result == {"FINISHED"}, f"{label}: {result}"
    bpy.ops.ed.undo_push(message=label)


def core_session():
    return addon().history.session(bpy.context.scene)


def sw_objects() -> dict[int, bpy.types.Object]:
    sync = addon().sync
    return {o[sync.ID_PROP]: o for o in sync.collection(bpy.context.scene).objects if sync.ID_PROP in o}


def assert_synced() -> None:
    """Every core object has a Blender mesh with identical topology and
    float32-rounded positions, and nothing else is in the collection."""
    import shapewright as sw

    s = core_session()
    objs = sw_objects()
    assert sorted(objs) == s.object_ids(), (sorted(objs), s.object_ids())
    sync = addon().sync
    for oid, obj in objs.items():
        pos, tri = sync.read_mesh(obj.data)
        cpos, ctri, _ = sw.mesh_arrays(s, oid)
        assert np.array_equal(tri, ctri.astype(np.int32)), f"object {oid}: triangles differ"
        assert np.array_equal(pos, cpos.astype(np.float32).astype(np.float64)), (
            f"object {oid}: positions differ"
        )
    assert bpy.context.scene.shapewright.cursor == s.cursor


def add(shape: str, x: float, **kw) -> None:
    step(
        bpy.ops.shapewright.add_solid(shape=shape, use_cursor=False, location=(x, 0.0, 0.2), **kw),
        f"add {shape}",
    )


def scenario_build(work: Path) -> None:
    add("sphere", 0.0, radius=0.2)
    add("box", 0.6, size=(0.3, 0.2, 0.4))
    add("torus", 1.2, radius=0.2, minor_radius=0.05)
    bpy.context.view_layer.objects.active = sw_objects()[2]
    step(bpy.ops.shapewright.move(offset=(0.0, 0.5, 0.0), angle_z=0.3, scale=1.5), "move")
    step(bpy.ops.shapewright.edit_solid(shape="cylinder", radius=0.1, height=0.5), "edit")
    step(bpy.ops.shapewright.duplicate(), "duplicate")
    assert_synced()
    report = core_session().validate()
    assert report["closed_manifold"], report
    # A refused op reports an error and changes nothing.
    before = core_session().content_hash()
    bpy.context.view_layer.objects.active = sw_objects()[1]
    try:
        bpy.ops.shapewright.edit_solid(shape="torus", radius=0.05, minor_radius=0.1)
    except RuntimeError as e:
        assert "smaller than major_radius" in str(e), e
    else:
        raise AssertionError("a self-intersecting torus must be refused")
    assert core_session().content_hash() == before
    assert_synced()


def scenario_undo(work: Path) -> None:
    add("sphere", 0.0, radius=0.2)
    add("box", 0.6)
    add("cone", 1.2)
    hashes = []
    s = core_session()
    for _ in range(3):
        hashes.append(s.content_hash())
        bpy.ops.ed.undo()
        s = core_session()
        assert_synced()
    assert s.cursor == 0 and not sw_objects()
    for k in range(3):
        bpy.ops.ed.redo()
        s = core_session()
        assert_synced()
        assert s.content_hash() == hashes[2 - k]
    # Undo twice, then a new op: the redo tail is dropped in both histories.
    bpy.ops.ed.undo()
    bpy.ops.ed.undo()
    add("capsule", 2.0)
    s = core_session()
    assert s.cursor == 2 and len(s) == 2, (s.cursor, len(s))
    assert_synced()
    ops = [json.loads(line)["op"] for line in s.ops_jsonl().splitlines()]
    assert ops == ["add_solid", "add_solid"], ops


def scenario_save_reload(work: Path) -> None:
    add("sphere", 0.0, radius=0.2)
    add("torus", 0.8, radius=0.2, minor_radius=0.05)
    add("box", 1.6)
    bpy.ops.ed.undo()
    s = core_session()
    want = (s.ops_jsonl(), s.cursor, s.content_hash())
    path = work / "model.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path))
    bpy.ops.wm.read_homefile(use_empty=True)
    bpy.ops.wm.open_mainfile(filepath=str(path))
    s = core_session()
    # The redo tail is not in the saved scene (Blender keeps no redo past a
    # save either); the applied history and the model are.
    assert s.cursor == want[1] and s.content_hash() == want[2], (s.cursor, want[1])
    assert want[0].startswith(s.ops_jsonl())
    assert_synced()
    bpy.ops.ed.undo_push(message="reopened")
    step(
        bpy.ops.shapewright.add_solid(shape="cone", use_cursor=False, location=(0, 1, 0)), "add after reopen"
    )
    bpy.ops.ed.undo()
    assert core_session().cursor == want[1]
    assert_synced()


def mesh_volume(pos: np.ndarray, tri: np.ndarray) -> float:
    a, b, c = pos[tri[:, 0]], pos[tri[:, 1]], pos[tri[:, 2]]
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


def scenario_usd_roundtrip(work: Path) -> None:
    add("sphere", 0.0, radius=0.2)
    add("torus", 0.8, radius=0.2, minor_radius=0.05)
    sync = addon().sync
    before = {}
    for obj in sw_objects().values():
        pos, tri = sync.read_mesh(obj.data)
        before[obj.name] = (len(tri), mesh_volume(pos, tri))
    path = work / "model.usda"
    bpy.ops.wm.usd_export(filepath=str(path), selected_objects_only=False)
    bpy.ops.wm.read_homefile(use_empty=True)
    bpy.ops.wm.usd_import(filepath=str(path))
    after = {}
    for obj in bpy.data.objects:
        if obj.type == "MESH" and obj.name in before:
            me = obj.data
            me.calc_loop_triangles()
            pos = np.empty(len(me.vertices) * 3, dtype=np.float32)
            me.vertices.foreach_get("co", pos)
            tri = np.empty(len(me.loop_triangles) * 3, dtype=np.int32)
            me.loop_triangles.foreach_get("vertices", tri)
            m = np.array(obj.matrix_world)
            p = pos.astype(np.float64).reshape(-1, 3) @ m[:3, :3].T + m[:3, 3]
            after[obj.name] = (len(tri) // 3, mesh_volume(p, tri.reshape(-1, 3)))
    assert set(after) == set(before), (after.keys(), before.keys())
    for name, (n, v) in before.items():
        assert after[name][0] == n, (name, after[name], n)
        assert abs(after[name][1] - v) <= 1e-6 * abs(v), (name, after[name][1], v)


def scenario_render(work: Path) -> None:
    add("sphere", 0.0, radius=0.2)
    add("box", 0.6)
    out = work / "render.png"
    step(bpy.ops.shapewright.render_png(filepath=str(out), resolution=320), "render")
    assert out.is_file() and out.stat().st_size > 1000
    img = bpy.data.images.load(str(out))
    px = np.array(img.pixels[:]).reshape(img.size[1], img.size[0], 4)[..., :3]
    frac = float((np.abs(px - px[0, 0]).max(axis=-1) > 0.05).mean())
    assert 0.03 < frac < 0.9, frac


def scenario_export(work: Path) -> None:
    add("sphere", 0.0, radius=0.2)
    out = work / "model.stl"
    bpy.ops.shapewright.export_mesh(filepath=str(out))
    assert out.is_file() and out.stat().st_size == 84 + 50 * core_session().validate()["triangles"]


DATA = Path(__file__).resolve().parents[1] / "data"
MODELS = ("teapot", "vase", "mug", "chair", "funnel", "csg_cup", "curve_network", "primitives")


def script_lines(name: str) -> list[str]:
    return [
        line
        for line in (DATA / f"{name}.jsonl").read_text().splitlines()
        if line.strip() and not line.startswith("#")
    ]


def scenario_models(work: Path) -> None:
    """The example models, op by op through the generic operator (undo lines
    through Blender's undo): the bpy meshes equal the core meshes and the
    document is bit-identical to running the script in the core."""
    import shapewright as sw

    for name in MODELS:
        bpy.ops.wm.read_homefile(use_empty=True)
        bpy.ops.ed.undo_push(message=f"start {name}")
        for line in script_lines(name):
            if json.loads(line)["op"] == "undo":
                bpy.ops.ed.undo()
            else:
                step(bpy.ops.shapewright.apply_op(op_json=line), f"{name}: {line[:40]}")
        want = sw.Session()
        want.run_script((DATA / f"{name}.jsonl").read_text())
        s = core_session()
        assert s.content_hash() == want.content_hash(), name
        assert s.ops_jsonl() == want.ops_jsonl()[: len(s.ops_jsonl())], name
        assert_synced()
        if name != "curve_network":
            assert s.validate()["closed_manifold"], (name, s.validate()["problems"])
        print(f"model {name}: {len(s.object_ids())} objects, {s.validate()['triangles']} triangles")


def last_op() -> dict:
    return json.loads(core_session().ops_jsonl().splitlines()[core_session().cursor - 1])


def activate(object_id: int) -> None:
    bpy.context.view_layer.objects.active = sw_objects()[object_id]


def scenario_typed(work: Path) -> None:
    """Every typed operator family through its generated operator: GC from a
    template and its edits, CSG with the library, curves drawn from a
    sketch and styled, a sculpt and a warp stroke."""
    ops = bpy.ops.shapewright
    step(
        ops.gc_create(template="circle", size_a=0.05, length=0.2, shape_type="container", thickness=0.004),
        "gc",
    )
    op = last_op()
    # Blender float properties are float32.
    assert op["sections"][0]["profile"]["template"] == "circle", op
    assert abs(op["sections"][0]["profile"]["radius"] - 0.05) < 1e-7, op
    assert abs(op["spine"][1][2] - 0.2) < 1e-7 and op["shape"]["type"] == "container", op
    activate(1)
    for label, result in (
        ("insert", lambda: ops.gc_insert_section(v=0.5)),
        ("bend", lambda: ops.gc_bend(section=1, to=(0.02, 0.0, 0.1))),
        ("resize", lambda: ops.gc_resize(section=1, factor=1.4)),
        ("shift", lambda: ops.gc_shift(section=1, v=0.45)),
        ("twist", lambda: ops.gc_twist(section=1, angle=0.3)),
        ("replace", lambda: ops.gc_replace_section(section=0, template="ellipse", size_a=0.05, size_b=0.04)),
        ("shape", lambda: ops.gc_set_shape(shape_type="solid")),
    ):
        before = core_session().cursor
        step(result(), label)
        assert core_session().cursor == before + 1, label
        assert_synced()
    assert core_session().validate(1)["closed_manifold"], core_session().validate(1)
    # A child on a straight cylinder's surface (radius 0.05 at x = 1), then
    # a mirrored instance of it.
    step(ops.gc_create(location=(1.0, 0.0, 0.0), template="circle", size_a=0.05, length=0.2), "gc 2")
    activate(2)
    step(
        ops.gc_add_child(parent=0, at=(1.05, 0.0, 0.1), length=0.08, template="circle", size_a=0.01), "child"
    )
    step(ops.gc_copy(part=1, mirror=True), "instance")
    assert core_session().validate(2)["closed_manifold"], core_session().validate(2)
    assert_synced()
    # A refused edit reports the core's message and changes nothing.
    h = core_session().content_hash()
    try:
        ops.gc_resize(section=0, factor=-1.0)
    except RuntimeError as e:
        assert "Error" in str(e), e
    else:
        raise AssertionError("a negative resize must be refused")
    assert core_session().content_hash() == h
    # CSG: a volume, a library component, a solid subtracted, a copy, operate.
    step(ops.sdf_create(step=0.01), "sdf")
    vol = core_session().object_ids()[-1]
    activate(vol)
    step(ops.sdf_add_operand(component="library", library="cylinder", location=(0.5, 0.0, 0.0)), "lib")
    step(
        ops.sdf_add_operand(
            component="solid", shape="sphere", size_a=0.04, csg="subtract", location=(0.5, 0.0, 0.1)
        ),
        "solid",
    )
    step(ops.sdf_copy_operand(operand=0, location=(0.75, 0.0, 0.0)), "copy")
    step(ops.sdf_update(), "operate")
    r = core_session().validate(vol)
    assert r["closed_manifold"] and r["volume"] > 0, r
    assert_synced()
    # Curves: a network, a sketched curve, a pull along a sketched path.
    step(ops.curve_network_create(resolution=24, surface_n=8), "network")
    net = core_session().object_ids()[-1]
    activate(net)
    pts = [[0.1 * i, -0.5, 0.02 * i * (4 - i)] for i in range(5)]
    step(ops.sketch(target="curve_draw", points=json.dumps(pts)), "sketch curve")
    assert last_op()["samples"] == pts, last_op()
    path = [[0.2, -0.5, 0.06 + 0.005 * i] for i in range(6)]
    step(ops.sketch(target="curve_pull", points=json.dumps(path)), "sketch pull")
    assert last_op()["op"] == "curve_pull" and last_op()["path"] == path
    # Warp brush: a sculpt sphere and a stroke along a sketch.
    step(ops.sculpt_create(base="sphere", size_a=0.15, edge_length=0.03, location=(0.0, 0.0, 0.0)), "sculpt")
    sc = core_session().object_ids()[-1]
    activate(sc)
    h0 = core_session().object_hash(sc)
    stroke = [[0.0, 0.0, 0.14 + 0.01 * i] for i in range(6)]
    step(ops.sketch(target="sculpt_stroke", points=json.dumps(stroke)), "stroke")
    assert core_session().validate(sc)["closed_manifold"] and core_session().object_hash(sc) != h0
    assert_synced()
    # Undo walks all of it back through Blender's undo, one op per step.
    n = core_session().cursor
    for k in range(n):
        bpy.ops.ed.undo()
        assert core_session().cursor == n - 1 - k
    assert_synced()


def scenario_sketch_projection(work: Path) -> None:
    """The modal sketch's geometry: view rays onto the plane, spacing."""
    from mathutils import Vector

    sk = addon().sketch
    hit = sk.project(
        Vector((0.3, -2.0, 1.0)), Vector((0.0, 1.0, -0.5)), Vector((0.0, 0.0, 0.0)), Vector((0, 0, 1))
    )
    assert (hit - Vector((0.3, 0.0, 0.0))).length < 1e-12, hit
    assert sk.project(Vector((0, 0, 1)), Vector((1, 0, 0)), Vector((0, 0, 0)), Vector((0, 0, 1))) is None
    assert sk.project(Vector((0, 0, 1)), Vector((0, 0, 1)), Vector((0, 0, 0)), Vector((0, 0, 1))) is None
    st = sk.Stroke(0.01)
    kept = [st.add(Vector((0.004 * i, 0.0, 0.0))) for i in range(10)]
    assert kept == [True, False, False, True, False, False, True, False, False, True], kept
    assert sk.plane_normal("XZ", None) == Vector((0, 1, 0))
    assert (sk.plane_normal("VIEW", Vector((0, 0, -2))) - Vector((0, 0, 1))).length < 1e-12


def trace_events(trace_path: Path):
    """A recorded controller trace as the XR event stream Blender delivers
    to the action map's modal operator: per frame the controller and viewer
    poses (world space, with the trace's model placement as the VR base
    pose) and, per float action, PRESS/hold events above the binding's
    threshold and one RELEASE when it drops."""
    lines = trace_path.read_text().splitlines()
    header = json.loads(lines[0])
    m = header["model"]
    xr = addon().xr
    threshold = {
        i["name"]: i["bindings"][0].get("threshold", 0.3) for i in xr.action_map()["items"] if i["bindings"]
    }
    from mathutils import Quaternion, Vector

    q = m["rotate"]
    inv = Quaternion((q[3], q[0], q[1], q[2])).inverted()
    t = Vector(m["translate"])

    def world(pose):
        # stage -> model (= world here), then world -> the add-on's stage frame
        p = inv @ (Vector(pose["p"]) - t)
        r = inv @ Quaternion((pose["q"][3], *pose["q"][:3]))
        return xr.to_stage(p, (r.w, r.x, r.y, r.z))

    held = [dict(), dict()]
    for line in lines[1:]:
        f = json.loads(line)
        ev = {
            "time": f["time"],
            "head": world(f["head"]) if f.get("head") else None,
            "poses": [],
            "actions": [],
        }
        for hand, c in enumerate(f["controllers"]):
            if c is None:
                ev["poses"].append(None)
                continue
            ev["poses"].append(
                {"grip": xr.from_stage(world(c["grip"])), "aim": xr.from_stage(world(c["aim"]))}
            )
            b = dict(c.get("buttons", {}))
            b["stick_x"], b["stick_y"] = b.get("stick", [0.0, 0.0])
            for action in ("select", "grab", "primary", "secondary", "menu", "stick_x", "stick_y"):
                v = float(b.get(action, 0.0))
                on = abs(v) > threshold.get(action, 0.3) if action not in xr.BUTTON_ACTIONS else bool(v)
                if on:
                    ev["actions"].append((action, xr.HANDS[hand], v, False))
                elif held[hand].get(action):
                    ev["actions"].append((action, xr.HANDS[hand], 0.0, True))
                held[hand][action] = on
        yield ev


def numbers(v) -> list[float]:
    if isinstance(v, dict):
        return [x for k in sorted(v) for x in numbers(v[k])]
    if isinstance(v, list):
        return [x for e in v for x in numbers(e)]
    return [float(v)] if isinstance(v, int | float) and not isinstance(v, bool) else []


def drive_xr_trace(trace: Path, tolerance: float) -> list[str]:
    """Drives the modal VR operator's input path (`XrDriver`) with a
    recorded controller trace as Blender's XR event stream; the ops must be
    the core's own replay of the trace, to float32 precision. Returns the
    names of the commands."""
    import shapewright as sw

    lines = trace.read_text().splitlines()
    header = json.loads(lines[0])
    want_doc = sw.Session()
    want = sw.InputSession(header["tool"], json.dumps(header["model"]))
    for line in lines[1:]:
        want.step(want_doc, line)
    xr = addon().xr
    d = xr.XrDriver(header["tool"])
    scene = bpy.context.scene
    for ev in trace_events(trace):
        for hand, p in enumerate(ev["poses"]):
            if p is not None:
                d.set_pose(hand, "grip", *p["grip"])
                d.set_pose(hand, "aim", *p["aim"])
        if ev["head"] is not None:
            d.set_head(*xr.from_stage(ev["head"]))
        for action, user_path, state, released in ev["actions"]:
            d.on_action(action, user_path, state, released)
        if d.step(scene, ev["time"]) is not None:
            bpy.ops.ed.undo_push(message="vr")
    s = core_session()
    assert all(err is None for _, err in d.commands), d.commands
    # Blender hands poses over as float32 (mathutils), so the ops match the
    # core's replay to float32 precision, not bit for bit.
    got, ref = s.ops_jsonl().splitlines(), want_doc.ops_jsonl().splitlines()
    assert len(got) == len(ref) and s.cursor == want_doc.cursor, (len(got), len(ref))
    for a, b in zip(got, ref, strict=True):
        fa, fb = np.array(numbers(json.loads(a))), np.array(numbers(json.loads(b)))
        assert json.loads(a)["op"] == json.loads(b)["op"] and fa.shape == fb.shape, (a, b)
        assert np.abs(fa - fb).max(initial=0.0) < tolerance, (a, b)
    assert_synced()
    return [json.loads(c)["op"] for c, _ in d.commands]


def scenario_xr_trace(work: Path) -> None:
    """The modal VR operator's input path driven by a recorded controller
    trace (the object tool): the same document as the core's replay."""
    names = drive_xr_trace(DATA / "primitives_session.trace.jsonl", 1e-6)
    assert len(names) >= 6, names
    assert "undo" in names and "add_solid" in names, names
    xr = addon().xr
    # The map the session-start handler registers comes from core data.
    amap = xr.action_map()
    profiles = {b["profile"] for i in amap["items"] for b in i["bindings"]}
    for p in (
        "oculus/touch_controller",
        "valve/index_controller",
        "htc/vive_controller",
        "microsoft/motion_controller",
    ):
        assert f"/interaction_profiles/{p}" in profiles, p
    assert xr.create_actions in bpy.app.handlers.xr_session_start_pre


def scenario_xr_gc_trace(work: Path) -> None:
    """The hand-gesture tool of paper 1 in Blender's VR session, which
    tracks controllers only: the buttons stand for the gestures (trigger
    POINT, grip FIST, A/X PINCH). A recorded controller session builds the
    teapot (body, spout, handle, lid with an inserted knob section)."""
    bpy.context.scene.shapewright.xr_tool = "gc"
    names = drive_xr_trace(DATA / "teapot_controller.trace.jsonl", 1e-5)
    assert names.count("gc_add_child") == 2 and "gc_insert_section" in names, names
    assert len(names) == 15, names
    objs = sw_objects()
    assert len(objs) == 2, objs


def scenario_history_usd(work: Path) -> None:
    """The log as USD beside the .blend on save, restored from a newer USD
    on load, and the autosave timer."""
    import shapewright as sw

    hist = addon().history
    assert bpy.app.timers.is_registered(hist.autosave_tick)
    add("sphere", 0.0, radius=0.2)
    add("box", 0.6)
    hist.autosave_tick()
    auto = sw.load_usd(str(hist.autosave_path()), verify_history=True)
    assert (
        auto.ops_jsonl() == core_session().ops_jsonl()
        and auto.content_hash() == core_session().content_hash()
    )
    path = work / "model.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path))
    usd = work / "model.shapewright.usda"
    assert usd.is_file(), list(work.iterdir())
    back = sw.load_usd(str(usd), verify_history=True)
    assert back.ops_jsonl() == core_session().ops_jsonl() and back.cursor == 2
    assert back.content_hash() == core_session().content_hash()
    # The USD is edited elsewhere (one more op) after the .blend was saved.
    import time

    time.sleep(0.05)
    back.apply(json.dumps({"op": "duplicate", "id": 1}))
    sw.save_usd(back, str(usd))
    bpy.ops.wm.read_homefile(use_empty=True)
    bpy.ops.wm.open_mainfile(filepath=str(path))
    s = core_session()
    assert s.cursor == 3 and s.content_hash() == back.content_hash(), s.cursor
    assert_synced()
    # Saving again writes the restored history beside it.
    bpy.ops.wm.save_mainfile()
    assert sw.load_usd(str(usd)).ops_jsonl() == s.ops_jsonl()


def scenario_screenshots(work: Path) -> None:
    """README pictures (not part of the test run): the teapot built through
    the add-on's operators and the scene the recorded VR trace built, both
    with the one-click Workbench render."""
    for line in script_lines("teapot"):
        step(bpy.ops.shapewright.apply_op(op_json=line), "teapot")
    render = bpy.ops.shapewright.render_png
    step(render(filepath=str(work / "blender_teapot.png"), resolution=640), "render")
    bpy.ops.wm.read_homefile(use_empty=True)
    scenario_xr_trace(work)
    step(render(filepath=str(work / "blender_vr_trace.png"), resolution=640), "render")


def main() -> int:
    zip_path, name, work = sys.argv[1], sys.argv[2], Path(sys.argv[3])
    install(zip_path)
    globals()[f"scenario_{name}"](work)
    print(f"scenario {name}: ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
