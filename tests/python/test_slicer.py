"""A real slicer reads our printable exits at true size (issue 31).

Each model is exported (`export --stl --3mf --scale-to-fit`: true size,
or scaled down to fit the document's printer as a user prints a model too
big for the bed, like the 4 m sculpted bust) and handed to Debian's
PrusaSlicer 2.5 (`prusa-slicer`, headless), which must:
- read it (`--info`) at the size and volume the print path reported for
  the document (the bounding box to 0.02 mm, the volume to 0.1%), every
  object `manifold = yes`;
- slice it (exit 0) into G-code whose extruding moves (read from the
  G-code itself) span the model's bounding box in x and y to within one
  extrusion width, whose top layer is within one layer of the model's
  height, and whose layer count is the height over the layer height.

The checker must fail a file written in metres (the old behaviour: a
0.35 mm teapot) and a 3MF with a part missing; both are tested.

CI slices a few models (`SLICE_CI`); `scripts/slice_all.sh` sets
`SHAPEWRIGHT_SLICE_ALL=1` to slice every example model, the lamp session
and the thickened lampshade. Coarse settings keep it fast: 0.8 mm nozzle,
0.6 mm layers, one perimeter, no infill, one solid layer at the top and
bottom, no skirt or brim, and a bed
large enough for any example (bed fit is the print path's own check).
"""

from __future__ import annotations

import os
import re
import shutil
import struct
import subprocess
import sys
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
from gcode_preview import extrusions  # noqa: E402

PRUSA = shutil.which("prusa-slicer")
pytestmark = pytest.mark.skipif(
    PRUSA is None, reason="prusa-slicer is not installed (scripts/setup.sh installs it)"
)

DATA = Path(__file__).resolve().parents[2] / "tests" / "data"
LAYER = 0.6
NOZZLE = 0.8
SLICE_ARGS = [
    "--dont-arrange",
    "--skirts", "0",
    "--brim-width", "0",
    "--nozzle-diameter", str(NOZZLE),
    "--layer-height", str(LAYER),
    "--first-layer-height", str(LAYER),
    "--first-layer-extrusion-width", "0",
    "--perimeters", "1",
    "--fill-density", "0%",
    "--top-solid-layers", "1",
    "--bottom-solid-layers", "1",
    "--bed-shape", "0x0,800x0,800x800,0x800",
    "--max-print-height", "800",
]  # fmt: skip

# Every example: op scripts, the lamp session (a recorded headset trace).
ALL = sorted(p.name for p in DATA.glob("*.jsonl") if not p.name.endswith(".trace.jsonl")) + [
    "lamp_session.trace.jsonl"
]
# CI: a small GC model, the thickened lampshade and the lamp session
# (several objects on one plate: `test_3mf_objects_carry_the_document_names`).
SLICE_CI = ["mug.jsonl", "lampshade.jsonl", "lamp_session.trace.jsonl"]
MODELS = ALL if os.environ.get("SHAPEWRIGHT_SLICE_ALL") else SLICE_CI


@dataclass
class Expected:
    """The print path's own numbers for the document (mm, cm³)."""

    size: tuple[float, float, float]
    volume: float


def run(cmd: list, timeout: float = 600) -> subprocess.CompletedProcess:
    return subprocess.run([str(c) for c in cmd], capture_output=True, text=True, timeout=timeout)


SIZE = re.compile(r"printed size ([\d.]+) x ([\d.]+) x ([\d.]+) mm, ([\d.]+) cm³")


def expected_of(summary: str) -> Expected:
    m = SIZE.search(summary)
    assert m, summary
    return Expected(size=(float(m[1]), float(m[2]), float(m[3])), volume=float(m[4]))


def export(host_bin: Path, name: str, work: Path) -> tuple[Path, Path, Expected]:
    """The model as STL and 3MF, and what the print path says of it."""
    usda = work / f"{name}.usda"
    src = DATA / name
    if name.endswith(".trace.jsonl"):
        r = run([host_bin, "replay", src, "--out", usda])
    else:
        r = run([host_bin, "apply", src, "--out", usda])
    assert r.returncode == 0, r.stderr
    stl, tmf = work / f"{name}.stl", work / f"{name}.3mf"
    r = run([host_bin, "export", usda, "--stl", stl, "--3mf", tmf, "--scale-to-fit"])
    assert r.returncode == 0, r.stderr
    return stl, tmf, expected_of(r.stdout)


def prusa_info(path: Path) -> list[dict[str, str]]:
    """`prusa-slicer --info`: one dict per object."""
    r = run([PRUSA, "--info", path])
    assert r.returncode == 0, r.stderr
    objects: list[dict[str, str]] = []
    for line in r.stdout.splitlines():
        # `[file.stl]` opens an object's section; `[date] [thread] [trace]`
        # lines are PrusaSlicer's log.
        if re.fullmatch(r"\[[^\]]+\]", line.strip()):
            objects.append({})
        elif "=" in line and objects:
            k, v = line.split("=", 1)
            objects[-1][k.strip()] = v.strip()
    return objects


def gcode_extent(gcode: str) -> tuple[np.ndarray, np.ndarray, float, int, float]:
    """Low and high corners (x, y, z) of the extruding moves of the
    model's own features, the top layer's z, the layer count and the
    external perimeter width, all read from the G-code (by
    scripts/gcode_preview.py's reader)."""
    ex = extrusions(gcode)
    assert ex.width is not None, "no external perimeter width in the G-code"
    assert len(ex.moves), "no extruding moves in the G-code"
    starts = ex.moves[:, [0, 1, 4]]
    ends = ex.moves[:, [2, 3, 4]]
    lo = np.minimum(starts.min(axis=0), ends.min(axis=0))
    hi = np.maximum(starts.max(axis=0), ends.max(axis=0))
    return lo, hi, float(hi[2]), ex.layers, ex.width


def check(path: Path, expected: Expected, work: Path, always_slice: bool = True) -> list[str]:
    """What PrusaSlicer disagrees with; empty when the file prints at
    true size. With `always_slice` false, a file PrusaSlicer already reads
    wrong is not sliced."""
    problems: list[str] = []
    info = prusa_info(path)
    if not info:
        return [f"{path.name}: prusa-slicer --info read no object"]
    for o in info:
        if o.get("manifold") != "yes":
            problems.append(f"{path.name}: an object is not manifold ({o.get('manifold')})")
    mins = np.array([[float(o[f"min_{a}"]) for a in "xyz"] for o in info])
    maxs = np.array([[float(o[f"max_{a}"]) for a in "xyz"] for o in info])
    size = maxs.max(axis=0) - mins.min(axis=0)
    want = np.array(expected.size)
    if np.abs(size - want).max() > 0.02:
        problems.append(f"{path.name}: --info size {size.round(3)} mm, the document's {want}")
    volume = sum(float(o["volume"]) for o in info) / 1000.0
    if abs(volume - expected.volume) > 1e-3 * expected.volume + 1e-3:
        problems.append(f"{path.name}: --info volume {volume:.3f} cm³, the document's {expected.volume}")
    if problems and not always_slice:
        return problems
    gcode = work / (path.name + ".gcode")
    r = run([PRUSA, "--export-gcode", "--output", gcode, *SLICE_ARGS, path])
    if r.returncode != 0 or not gcode.exists():
        tail = (r.stdout + r.stderr).strip().splitlines()[-3:]
        return problems + [f"{path.name}: slicing failed (exit {r.returncode}): {' / '.join(tail)}"]
    lo, hi, top, layers, width = gcode_extent(gcode.read_text())
    # The moves are the extrusions' centre lines: the printed part reaches
    # half a width beyond them on each side.
    printed = hi[:2] - lo[:2] + width
    for k, axis in enumerate("xy"):
        if abs(printed[k] - want[k]) > width:
            problems.append(
                f"{path.name}: the G-code prints {printed[k]:.3f} mm in {axis} (its extruding moves "
                f"span {printed[k] - width:.3f} mm, lines {width} mm wide), the model is {want[k]:.3f} mm"
            )
    # The slicer sets every object on the bed: the top is the tallest
    # object's height (one object for an STL).
    height = float(max(maxs[:, 2] - mins[:, 2]))
    if abs(top - height) > LAYER:
        problems.append(f"{path.name}: top layer at z {top:.3f} mm, the model is {height:.3f} mm tall")
    if abs(layers - height / LAYER) > 1.0:
        problems.append(f"{path.name}: {layers} layers, {height:.3f} mm / {LAYER} mm is {height / LAYER:.1f}")
    return problems


@pytest.mark.parametrize("name", MODELS)
def test_slices_at_true_size(name: str, host_bin: Path, tmp_path: Path) -> None:
    stl, tmf, expected = export(host_bin, name, tmp_path)
    problems = check(stl, expected, tmp_path) + check(tmf, expected, tmp_path)
    assert not problems, "\n".join(problems)


def test_a_model_too_big_for_the_bed_is_scaled_to_fit(host_bin: Path, tmp_path: Path) -> None:
    """`export --scale-to-fit`: the sculpted bust (4 m tall as authored)
    comes out as large as the document's printer (Prusa MK4, 250 x 210 x
    220 mm) takes, at the volume the scale implies, and PrusaSlicer reads
    it at that size (slicing it is `scripts/slice_all.sh`'s)."""
    usda = tmp_path / "bust.usda"
    assert run([host_bin, "apply", DATA / "bust.jsonl", "--out", usda]).returncode == 0
    true_size = tmp_path / "true.3mf"
    r = run([host_bin, "export", usda, "--3mf", true_size])
    assert r.returncode == 0, r.stderr
    assert "does NOT fit the Prusa MK4" in r.stdout, r.stdout
    full = expected_of(r.stdout)
    fitted = tmp_path / "fitted.3mf"
    r = run([host_bin, "export", usda, "--3mf", fitted, "--scale-to-fit"])
    assert r.returncode == 0, r.stderr
    m = re.search(r"scaled to ([\d.]+)% to fit the Prusa MK4", r.stdout)
    assert m, r.stdout
    scale = float(m[1]) / 100.0
    assert "printer    fits the Prusa MK4" in r.stdout, r.stdout
    got = expected_of(r.stdout)
    # As large as fits: the scale is the fitting one rounded down to 0.1%,
    # so the tightest axis is within that rounding of the bed.
    bed = np.array([250.0, 210.0, 220.0])
    size = np.array(got.size)
    assert np.all(size <= bed + 1e-6) or np.all(size[[1, 0, 2]] <= bed + 1e-6), got
    assert max(size / bed) >= 1 - 1e-3 / scale, (got.size, scale)
    assert np.allclose(got.size, np.array(full.size) * scale, rtol=1e-4), (got.size, full.size, scale)
    assert abs(got.volume / (full.volume * scale**3) - 1) < 1e-3, (got.volume, full.volume, scale)
    info = prusa_info(fitted)
    size = np.array([float(info[0][f"size_{a}"]) for a in "xyz"])
    assert np.abs(size - np.array(got.size)).max() < 0.02, (size, got.size)


def scale_stl(src: Path, dst: Path, factor: float) -> None:
    data = bytearray(src.read_bytes())
    n = struct.unpack_from("<I", data, 80)[0]
    rec = np.frombuffer(
        bytes(data[84 : 84 + 50 * n]), dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
    )
    rec = rec.copy()
    rec["v"] *= np.float32(factor)
    dst.write_bytes(bytes(data[:84]) + rec.tobytes())


def test_a_file_in_metres_fails_the_checker(host_bin: Path, tmp_path: Path) -> None:
    """The old behaviour (STL coordinates in metres) is caught."""
    stl, _, expected = export(host_bin, "teapot.jsonl", tmp_path)
    metres = tmp_path / "teapot_in_metres.stl"
    scale_stl(stl, metres, 1e-3)
    problems = check(metres, expected, tmp_path)
    assert any("--info size" in p for p in problems), problems
    assert any("slicing failed" in p or "the G-code prints" in p for p in problems), problems


TWO_OBJECTS = (
    '{"op":"add_solid","shape":{"kind":"box","size":[0.04,0.04,0.02]},"transform":{"translate":[0,0,0.01]}}\n'
    '{"op":"add_solid","shape":{"kind":"cylinder","radius":0.015,"height":0.05},"transform":{"translate":[0.08,0,0.025]}}\n'
    '{"op":"rename_object","id":1,"name":"Base plate"}\n'
    '{"op":"rename_object","id":2,"name":"Peg"}\n'
)


def test_a_missing_part_fails_the_checker(host_bin: Path, tmp_path: Path) -> None:
    """A 3MF that lost one of its objects (object and build item) is caught;
    the whole file passes."""
    script = tmp_path / "two.jsonl"
    script.write_text(TWO_OBJECTS)
    usda = tmp_path / "two.usda"
    assert run([host_bin, "apply", script, "--out", usda]).returncode == 0
    tmf = tmp_path / "two.3mf"
    r = run([host_bin, "export", usda, "--3mf", tmf])
    assert r.returncode == 0, r.stderr
    expected = expected_of(r.stdout)
    assert check(tmf, expected, tmp_path) == []
    with zipfile.ZipFile(tmf) as z:
        parts = {n: z.read(n) for n in z.namelist()}
    model = parts["3D/3dmodel.model"].decode()
    ids = re.findall(r'<item objectid="(\d+)"/>', model)
    assert len(ids) == 2, model[:2000]
    last = ids[-1]
    model = re.sub(rf'  <object id="{last}".*?</object>\n', "", model, flags=re.S)
    model = model.replace(f'  <item objectid="{last}"/>\n', "")
    parts["3D/3dmodel.model"] = model.encode()
    broken = tmp_path / "two_missing_one.3mf"
    with zipfile.ZipFile(broken, "w") as z:
        for n, b in parts.items():
            z.writestr(n, b)
    problems = check(broken, expected, tmp_path)
    assert any("volume" in p for p in problems), problems
    assert any("--info size" in p for p in problems), problems


def test_3mf_objects_carry_the_document_names(host_bin: Path, tmp_path: Path) -> None:
    """Several objects on one plate, named after the document's objects."""
    script = tmp_path / "named.jsonl"
    script.write_text(TWO_OBJECTS)
    tmf = tmp_path / "named.3mf"
    r = run([host_bin, "apply", script, "--out", tmf])
    assert r.returncode == 0, r.stderr
    with zipfile.ZipFile(tmf) as z:
        model = z.read("3D/3dmodel.model").decode()
    assert 'unit="millimeter"' in model
    assert re.findall(r'name="([^"]+)"', model)[1:] == ["Base plate", "Peg"], model
    info = prusa_info(tmf)
    assert len(info) == 2
    sizes = sorted(tuple(round(float(o[f"size_{a}"]), 2) for a in "xyz") for o in info)
    assert sizes == [(30.0, 30.0, 50.0), (40.0, 40.0, 20.0)], sizes


def test_info_agrees_with_prusaslicer(host_bin: Path, tmp_path: Path) -> None:
    """`info x.stl` and `info x.3mf` print the size PrusaSlicer reads."""
    stl, tmf, expected = export(host_bin, "mug.jsonl", tmp_path)
    for path in (stl, tmf):
        r = run([host_bin, "info", path])
        assert r.returncode == 0, r.stderr
        m = re.search(r"size:\s+([\d.]+) x ([\d.]+) x ([\d.]+) mm", r.stdout)
        assert m, r.stdout
        ours = np.array([float(m[i]) for i in (1, 2, 3)])
        info = prusa_info(path)
        theirs = np.array([float(info[0][f"size_{a}"]) for a in "xyz"])
        assert np.abs(ours - theirs).max() < 0.01, (ours, theirs)
        assert np.abs(ours - np.array(expected.size)).max() < 0.02
