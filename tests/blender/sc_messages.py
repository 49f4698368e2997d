"""True messages (issue 34): the History panel's verdict is the export's,
refusals made outside an operator reach the status bar, a new object is
active and selected in any scene (after File > New and File > Open too),
and an export never creates a folder nobody asked for."""

from __future__ import annotations

import os
from pathlib import Path

import bpy
from helpers import DATA, add_solid, core_session, module, step, sw_objects


def _verdict(scene) -> tuple[bool, str]:
    checks = module("checks")
    if checks is not None:
        v = checks.verdict(scene, wait=True)
        return v["printable"], v["message"]
    r = module("history").validation(scene, wait=True)  # before issue 34
    return r["closed_manifold"], r["problems"]


def scenario_verdict(work: Path) -> None:
    """For documents whose objects' own meshes have problems the print
    path removes (and one it refuses), the panel says what the export
    does."""
    for name in os.environ.get("SW_MODELS", "lampshade,teapot,csg_cup").split(","):
        bpy.ops.wm.read_homefile(use_empty=True)
        bpy.ops.ed.undo_push(message="empty")
        step(bpy.ops.shapewright.run_script(filepath=str(DATA / f"{name}.jsonl")), name)
        ok, message = _verdict(bpy.context.scene)
        out = work / f"{name}.stl"
        try:
            core_session().export_mesh(str(out))
            exported = True
        except Exception as e:  # noqa: BLE001 - the export's refusal, compared below
            exported, refusal = False, str(e)
        assert ok == exported, (
            f"{name}: the panel says {message!r}; the export {'wrote' if exported else 'refused'}"
        )
        if not exported:
            assert message.split(":")[0] in refusal, (message, refusal)
        print(
            f"{name}: panel {'printable' if ok else message!r}, export {'written' if exported else 'refused'}"
        )


def scenario_status_messages(work: Path) -> None:
    """A rename the core refuses is put back and said in the status bar
    (through the notify operator), not only printed to the console."""
    add_solid("sphere", (0.0, 0.0, 0.1))
    obj = sw_objects()[core_session().object_ids()[-1]]
    before = obj.name
    obj.name = "bad\x07name"
    bpy.context.view_layer.update()
    notify = module("notify")
    assert notify is not None, "no status-bar messages (refusals only printed to the console)"
    assert obj.name == before
    assert any("not taken as the name" in m for m in notify.messages), notify.messages
    notify.flush()  # what Blender's event loop runs (a timer)
    assert any("not taken as the name" in m for m in notify.shown), notify.shown


def _active_and_only_selected(where: str) -> None:
    oid = core_session().object_ids()[-1]
    obj = sw_objects()[oid]
    view_layer = bpy.context.view_layer
    assert view_layer.objects.active == obj, (where, view_layer.objects.active)
    assert list(view_layer.objects.selected) == [obj], (where, list(view_layer.objects.selected))


def scenario_new_objects_active(work: Path) -> None:
    """A new Shapewright object is the active and only selected object:
    in the startup scene (File > New, whose cube is selected), and after
    File > Open."""
    bpy.ops.wm.read_homefile()  # File > New: the general template
    bpy.ops.ed.undo_push(message="new file")
    add_solid("sphere", (0.0, 0.0, 0.5))
    _active_and_only_selected("after File > New")
    path = work / "opened.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path))
    bpy.ops.wm.read_homefile(use_empty=True)
    bpy.ops.wm.open_mainfile(filepath=str(path))
    bpy.ops.ed.undo_push(message="opened")
    bpy.ops.object.select_all(action="SELECT")
    add_solid("box", (0.5, 0.0, 0.5))
    _active_and_only_selected("after File > Open")


def scenario_export_folders(work: Path) -> None:
    """Exporting into a folder that does not exist is refused, naming the
    folder, and creates nothing."""
    add_solid("sphere", (0.0, 0.0, 0.1))
    missing = work / "no" / "such" / "folder"
    for ext in ("stl", "usda"):
        try:
            bpy.ops.shapewright.export_mesh(filepath=str(missing / f"model.{ext}"))
        except RuntimeError as e:
            assert "does not exist" in str(e), e
        else:
            raise AssertionError(f".{ext}: an export into a missing folder must be refused")
        assert not (work / "no").exists(), f".{ext}: the export created {work / 'no'}"
    try:
        core_session().export_mesh(str(missing / "direct.stl"))
    except Exception as e:  # noqa: BLE001 - the message is checked
        assert "does not exist" in str(e), e
    else:
        raise AssertionError("Session.export_mesh into a missing folder must be refused")
    assert not (work / "no").exists()
