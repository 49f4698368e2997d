"""Writes the issue 22 reproducers that are too big to check in.

    python3 tests/data/abuse/make_big.py OUT_DIR [SHAPEWRIGHT_XR]

- gc_sections_20000.jsonl: a gc_create with 20,000 key sections (the
  skinning's dense interpolation system is quadratic in the section count:
  1e6 sections asked for 8 TB; 20,000 ask for about 3 GB and minutes);
- curve_network_scale_1e-9.trace.jsonl: the curve-network trace with its
  model placed at scale 1e-9 (strokes become 1e9 times longer in model
  space: 482 GB asked, killed by the kernel at 24 GB);
- far_sample.usda (needs the host binary): a saved curve network whose
  curve_draw op has a sample 1e12 m away and 1 mm resampling; `info`
  replays the log and aborts.
"""

import json
import pathlib
import subprocess
import sys

here = pathlib.Path(__file__).resolve().parent
data = here.parent
out = pathlib.Path(sys.argv[1])
out.mkdir(parents=True, exist_ok=True)

mug = [json.loads(line) for line in open(data / "mug.jsonl") if line.strip() and not line.startswith("#")]
gc = dict(next(o for o in mug if o["op"] == "gc_create"))
n = 20000
gc["sections"] = [{"profile": {"template": "circle", "radius": 0.04}, "v": i / (n - 1)} for i in range(n)]
(out / "gc_sections_20000.jsonl").write_text(json.dumps(gc, separators=(",", ":")) + "\n")

lines = (data / "curve_network.trace.jsonl").read_text().splitlines()
head = json.loads(lines[0])
head["model"]["scale"] = 1e-9
(out / "curve_network_scale_1e-9.trace.jsonl").write_text("\n".join([json.dumps(head)] + lines[1:]) + "\n")

if len(sys.argv) > 2:
    net = [
        json.loads(line)
        for line in open(data / "curve_network.jsonl")
        if line.strip() and not line.startswith("#")
    ]
    draw = next(o for o in net if o["op"] == "curve_draw")
    ok = out / "near_sample.jsonl"
    ok.write_text(json.dumps(net[0]) + "\n" + json.dumps(draw) + "\n")
    usda = out / "far_sample.usda"
    subprocess.run([sys.argv[2], "apply", str(ok), "--out", str(usda)], check=True)
    text = usda.read_text()
    # The saved op is serde's JSON (field order of the struct): rewrite it
    # by parsing the line's array instead of matching text.
    # Prepend a far sample to the saved curve_draw op and resample at 1 mm
    # (only in the op log: the snapshot and meshes stay as saved).
    out_lines = []
    for line in text.splitlines():
        if "shapewright:ops" in line:
            line = line.replace('"samples":[', '"samples":[[1000000000000.0,0.0,0.0],', 1)
            line = line.replace('"resample":null', '"resample":0.001', 1)
        out_lines.append(line)
    usda.write_text("\n".join(out_lines) + "\n")
print("written to", out)
