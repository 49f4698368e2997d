"""The typed operators and the op schema: every operator's properties agree
with the core's schema (tooltips, units, ranges), Blender's conventions,
scripts' ids."""

from __future__ import annotations

import json
from pathlib import Path

import bpy
from helpers import add, addon, assert_synced, core_session, last_op, step, sw_objects

# The op schema (`shapewright.op_schema()`, issue 15) against the
# add-on's op table. Ops the add-on emits from hand-written operators, by
# the operator that emits them:
HAND_WRITTEN_OPS = {
    "add_solid": "add_solid",
    "edit_solid": "edit_solid",
    "transform_by": "move",
    "duplicate": "duplicate",
    "delete": "delete",
}


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
            component="solid",
            shape="sphere",
            dimensions=(0.08, 0.08, 0.08),
            csg="subtract",
            location=(0.5, 0.0, 0.1),
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


def scenario_conventions(work: Path) -> None:
    """Operators act on the active object, not on remembered ids; poll
    hides what does not apply; bad values are refused by name."""
    ops = bpy.ops.shapewright
    add("sphere", 0.0, dimensions=(0.2, 0.2, 0.2))
    add("box", 0.6)
    assert bpy.context.view_layer.objects.active == sw_objects()[2], "a new object is active"
    assert [o for o in bpy.context.selected_objects] == [sw_objects()[2]]
    step(ops.gc_create(location=(1.5, 0.0, 0.0)), "gc")
    step(ops.gc_create(location=(2.0, 0.0, 0.0)), "gc 2")
    # An id passed once is not remembered: the next call edits the active.
    step(ops.gc_resize(id=3, section=0, factor=1.5), "resize 3")
    assert last_op()["id"] == 3
    activate(4)
    step(ops.gc_resize(section=0, factor=1.5), "resize active")
    assert last_op()["id"] == 4, last_op()
    # Poll: solid edits need a solid; GC edits a GC (or a script's id).
    activate(3)
    assert not ops.edit_solid.poll() and ops.move.poll()
    registered = {c.bl_rna.identifier for c in bpy.types.Operator.__subclasses__()}
    assert "SHAPEWRIGHT_OT_move" in registered, sorted(registered)[:5]
    assert "SHAPEWRIGHT_OT_commit_transform" not in registered, "moves are recorded without a button"
    assert ops.gc_bend.poll() and not ops.sdf_update.poll() and not ops.curve_fill_auto.poll()
    activate(1)
    assert ops.edit_solid.poll()
    # Bad values: named and refused, nothing changes.
    h = core_session().content_hash()
    for kwargs, words in (
        ({"dimensions": (0.0, 0.0, 0.0)}, ("radius",)),
        ({"dimensions": (float("inf"),) * 3}, ("dimensions", "finite")),
        ({"dimensions": (float("nan"),) * 3}, ("dimensions", "NaN")),
        ({"dimensions": (-1.0, -1.0, -1.0)}, ("radius",)),
    ):
        try:
            ops.add_solid(shape="sphere", use_cursor=False, **kwargs)
        except RuntimeError as e:
            assert all(w in str(e) for w in words), (kwargs, str(e))
        else:
            raise AssertionError(f"{kwargs} must be refused")
    nan_line = '{"op":"add_solid","shape":{"kind":"sphere","radius":NaN}}'
    try:
        ops.apply_op(op_json=nan_line)
    except RuntimeError as e:
        assert "shape.radius" in str(e) and "NaN" in str(e), e
    else:
        raise AssertionError("NaN must be refused")
    assert core_session().content_hash() == h


def schema_consts(defs: dict, schema: dict) -> set[str] | None:
    """The string values an enum-like field accepts (None: not an enum)."""
    ref = schema.get("$ref")
    if ref:
        schema = defs[ref.rsplit("/", 1)[-1]]
    if "enum" in schema:
        return set(schema["enum"])
    alts = schema.get("oneOf")
    if alts and all("const" in a for a in alts):
        return {a["const"] for a in alts}
    return None


def in_range(f: dict, x: float) -> bool:
    lo, hi, ex = f.get("minimum"), f.get("maximum"), f.get("exclusiveMinimum")
    return (lo is None or x >= lo) and (hi is None or x <= hi) and (ex is None or x > ex)


def scenario_op_schema(work: Path) -> None:
    import shapewright as sw

    table = addon().op_table
    schema = sw.op_schema()
    defs = schema["defs"]
    ops = {o["name"]: {f["name"]: f for f in o["fields"]} for o in schema["ops"]}
    problems: list[str] = []

    # Every op a person writes has an operator (typed, hand-written or
    # generic, built from the schema); the table names only real ops. Ops
    # of kind `session` are written by shared sessions and have none.
    registered = set(dir(bpy.ops.shapewright))
    session_ops = {o["name"] for o in schema["ops"] if o["kind"] == "session"}
    assert session_ops == {"reserve_ids"}, session_ops
    for name in sorted(set(ops) - session_ops):
        operator = HAND_WRITTEN_OPS.get(name, name)
        if operator not in registered:
            problems.append(f"{name}: no operator shapewright.{operator}")
    for name in sorted(set(table.BY_OP) | set(HAND_WRITTEN_OPS)):
        if name not in ops:
            problems.append(f"{name}: not an op of the core's schema")

    for spec in table.SPECS:
        fields = ops.get(spec.op)
        if fields is None:
            continue
        verbatim = spec.build is None and spec.build_with is None
        for f in spec.fields:
            sf = fields.get(f.name)
            if sf is None or f.kind in ("target", "points", "pieces", "rotation"):
                continue
            # A field the op takes as it is: the core's default, range and
            # choices. (Builders translate some values, e.g. `end: auto`;
            # what they build is checked below, for every choice.)
            if sf["default"] is not None and f.default != sf["default"]:
                problems.append(f"{spec.op}.{f.name}: default {f.default!r}, the core's {sf['default']!r}")
            if verbatim and f.kind in ("int", "float") and not in_range(sf, f.default):
                problems.append(f"{spec.op}.{f.name}: default {f.default!r} outside the core's range")
            consts = schema_consts(defs, sf["schema"])
            if verbatim and f.kind == "enum" and consts is not None and set(f.items) != consts:
                problems.append(f"{spec.op}.{f.name}: choices {sorted(f.items)}, the core's {sorted(consts)}")
        if spec.needs_points and spec.build_with is not None:
            continue  # built by the core's sketch functions from a stroke
        if spec.from_blender:
            continue  # built from a Blender mesh: `check_import_component`
        # The op built from the defaults, and with each choice of each
        # enum field: only the op's fields, every required one, numbers in
        # the core's ranges and enum values the core knows.
        defaults = {}
        for f in spec.fields:
            if f.kind == "target":
                defaults[f.name] = 0
            elif f.kind == "points":
                defaults[f.name] = []
            else:  # struct defaults copied: builders may keep them
                defaults[f.name] = json.loads(json.dumps(f.default)) if f.kind == "struct" else f.default
        variants = [(None, None, defaults)] + [
            (f, item, {**defaults, f.name: item}) for f in spec.fields if f.kind == "enum" for item in f.items
        ]
        passed_as_is: dict[str, bool] = {}
        for f, item, values in variants:
            built = table.build_op(spec, values, None).dicts()
            first = built[0]
            if f is not None and f.name in fields:
                passed_as_is[f.name] = passed_as_is.get(f.name, True) and first.get(f.name) == item
            for op in built:
                got = ops[op["op"]]
                keys = set(op) - {"op"}
                problems += [f"{spec.op}: builds unknown field {k!r}" for k in sorted(keys - set(got))]
                missing = {k for k, sf in got.items() if sf["required"]} - keys
                problems += [f"{spec.op}: builds no {k!r} (required)" for k in sorted(missing)]
                for k in keys & set(got):
                    v = op[k]
                    if isinstance(v, (int, float)) and not isinstance(v, bool) and not in_range(got[k], v):
                        problems.append(f"{spec.op}.{k}: builds {v!r}, outside the core's range")
                    consts = schema_consts(defs, got[k]["schema"])
                    if isinstance(v, str) and consts is not None and v not in consts:
                        problems.append(f"{spec.op}.{k}: builds {v!r}, the core takes {sorted(consts)}")
        # An enum a builder passes on as it is offers all the core's choices.
        for name in (n for n, as_is in passed_as_is.items() if as_is and not verbatim):
            f = next(f for f in spec.fields if f.name == name)
            consts = schema_consts(defs, fields[name]["schema"])
            if consts is not None and set(f.items) != consts:
                problems.append(f"{spec.op}.{name}: choices {sorted(f.items)}, the core's {sorted(consts)}")
    problems += operator_property_problems(work)
    problems += core_bound_problems()
    check_import_component()
    check_rename()
    problems = sorted(set(problems))
    assert not problems, "operators disagree with the op schema:\n" + "\n".join(problems)
    print(f"checked {len(table.SPECS)} op-table entries against {len(ops)} schema ops")


def op_scene() -> dict[str, int]:
    """A scene with an object of every kind: the styled curve-network box
    (id 1, 6 patches), a sphere (2), a 4-section GC (3) and a CSG volume
    with one pending operand (4). Returns the id of each kind."""
    hist = addon().history
    scene = bpy.context.scene
    root = Path(__file__).resolve().parents[1] / "data"
    step(bpy.ops.shapewright.run_script(filepath=str(root / "curve_network.jsonl")), "curves")
    circle = {"template": "circle", "radius": 0.04}
    for op in (
        {"op": "add_solid", "shape": {"kind": "sphere", "radius": 0.1}},
        {
            "op": "gc_create",
            "spine": [[0.5, 0.0, 0.0], [0.5, 0.0, 0.2]],
            "plane_normal": [0.0, 1.0, 0.0],
            "sections": [{"profile": circle, "v": v} for v in (0.0, 0.4, 0.6, 1.0)],
        },
        {"op": "sdf_create", "step": 0.01},
        {
            "op": "sdf_add_operand",
            "volume": 4,
            "component": {"kind": "library", "name": "chair_seat"},
            "csg": "union",
        },
    ):
        hist.apply(scene, op)
    s = core_session()
    kinds = {s.object_kind(i): i for i in s.object_ids()}
    assert sorted(kinds) == ["curve_network", "gc_assembly", "sdf_volume", "solid"], kinds
    kinds["document"] = kinds["solid"]
    return kinds


def check_import_component() -> None:
    """A closed Blender mesh becomes a user component of a CSG volume (and
    an operand by its name); an open one is refused with the core's
    reason. Run after `op_scene` (volume 4)."""
    ops = bpy.ops.shapewright
    bpy.ops.mesh.primitive_cube_add(size=0.1, location=(2.0, 0.0, 0.05))
    cube = bpy.context.active_object
    step(ops.sdf_import_component(volume=4, mesh=cube.name, name="block"), "import component")
    assert "block" in str(core_session().object_params(4)), str(core_session().object_params(4))[:200]
    op = {
        "op": "sdf_add_operand",
        "volume": 4,
        "component": {"kind": "user", "name": "block"},
        "csg": "union",
    }
    step(ops.apply_op(op_json=json.dumps(op)), "add the component")
    bpy.ops.mesh.primitive_plane_add(size=0.1)
    before = core_session().content_hash()
    try:
        ops.sdf_import_component(volume=4, mesh=bpy.context.active_object.name)
    except RuntimeError as e:
        print(f"open mesh refused: {e}")
    else:
        raise AssertionError("an open mesh must be refused")
    assert core_session().content_hash() == before


def check_rename() -> None:
    """Rename (`rename_object`) names the Blender object; undo gives the
    old name back. Run after `op_scene` (solid 2)."""
    bpy.context.view_layer.objects.active = sw_objects()[2]
    step(bpy.ops.shapewright.rename_object(name="Ball"), "rename")
    assert core_session().object_name(2) == "Ball"
    assert sw_objects()[2].name == "Ball", sw_objects()[2].name
    log_undo()
    assert core_session().object_name(2) == ""
    assert sw_objects()[2].name == "SW2", sw_objects()[2].name


def log_undo() -> None:
    """Steps the op log back one op (an accepted trial value)."""
    bpy.ops.shapewright.apply_op(op_json='{"op": "undo"}')


def outside(inf) -> list[float]:
    """Values just outside a schema range: min - eps, the exclusive
    minimum itself, max + eps (1 for integers)."""

    def eps(x: float) -> float:  # seen through a float32 property
        return 1 if inf.integer else max(1e-6, abs(x) * 1e-5)

    out = []
    if inf.minimum is not None:
        out.append(inf.minimum - eps(inf.minimum))
    if inf.exclusive_minimum is not None:
        out.append(inf.exclusive_minimum)
    if inf.maximum is not None:
        out.append(inf.maximum + eps(inf.maximum))
    return out


def close(a: float, b: float) -> bool:
    return abs(a - b) <= 1e-6 * max(1.0, abs(b))


RANGE_WORDS = ("below the minimum", "above the maximum", "must be greater than")


def operator_property_problems(work: Path) -> list[str]:
    """Every property of every Shapewright operator has a tooltip; every
    property standing for a schema field shows its unit and range, and
    refuses (naming itself, changing nothing) the values just outside the
    range, while its own check accepts the bounds."""
    a = addon()
    schema, table = a.schema, a.op_table
    problems = []
    kinds = op_scene()
    for name in sorted(dir(bpy.ops.shapewright)):
        rna = getattr(bpy.ops.shapewright, name).get_rna_type()
        if not rna.description.strip():
            problems.append(f"shapewright.{name}: no description")
        for p in rna.properties:
            if p.identifier != "rna_type" and not p.description.strip():
                problems.append(f"shapewright.{name}.{p.identifier}: no tooltip")
        cls = getattr(bpy.types, f"SHAPEWRIGHT_OT_{name}", None)
        mapped = getattr(cls, "sw_schema", {}) if cls is not None else {}
        spec = table.BY_OP.get(name)
        if spec is not None:
            # A typed property named as its op's field stands for it.
            for f in spec.fields:
                typed = f.kind not in ("target", "points", "struct", "pieces", "rotation")
                if typed and schema.field_schema((name, f.name)) is not None:
                    if f.name not in mapped:
                        problems.append(f"shapewright.{name}.{f.name}: not mapped to its schema field")
            targets = [f.name for f in spec.fields if f.kind == "target"]
            none_at = {f.name: f.none_at for f in spec.fields}
        elif name in schema.OPS:
            targets = [g.prop for g in schema.fields(name) if g.kind == "target"]
            none_at = {}
        else:
            targets, none_at = [], {}
        kind = schema.OPS[name]["kind"] if name in schema.OPS else "solid"
        call = {t: kinds.get(kind, kinds["document"]) for t in targets}
        objs = sw_objects()
        bpy.context.view_layer.objects.active = objs[kinds.get(kind, kinds["document"])]
        if name in ("add_solid", "edit_solid"):
            call = {}  # hand-written: the active solid, no id field
        for prop, path in sorted(mapped.items()):
            rp = rna.properties.get(prop)
            if rp is None:
                problems.append(f"shapewright.{name}.{prop}: mapped to {path} but no such property")
                continue
            inf = schema.info(path)
            lo, hi = inf.soft_range()
            if inf.unit == "m" and (lo, hi) != (None, None) and "mm" not in rp.description:
                problems.append(f"shapewright.{name}.{prop}: a length's tooltip gives no range in mm")
            if rp.type in ("INT", "FLOAT") and inf.unit != "m":
                if lo is not None and not close(rp.soft_min, lo):
                    problems.append(f"shapewright.{name}.{prop}: soft_min {rp.soft_min}, the schema's {lo}")
                if hi is not None and not close(rp.soft_max, hi):
                    problems.append(f"shapewright.{name}.{prop}: soft_max {rp.soft_max}, the schema's {hi}")
            want_unit = {"m": "LENGTH", "rad": "ROTATION"}.get(inf.unit or "")
            if rp.type == "FLOAT" and want_unit and rp.unit != want_unit:
                problems.append(f"shapewright.{name}.{prop}: unit {rp.unit}, the schema's {inf.unit}")
            if rp.type not in ("INT", "FLOAT"):
                continue
            size = rp.array_length or 0

            def value(x, size=size, rp=rp):
                x = int(x) if rp.type == "INT" else float(x)
                return [x] * size if size else x

            before = core_session().content_hash()
            for x in outside(inf):
                if none_at.get(prop) is not None and x == none_at[prop]:
                    continue
                try:
                    getattr(bpy.ops.shapewright, name)(**call, **{prop: value(x)})
                except RuntimeError as e:
                    if prop not in str(e):
                        problems.append(f"shapewright.{name}.{prop}={x}: refused without naming it: {e}")
                else:
                    problems.append(f"shapewright.{name}.{prop}={x}: accepted, outside the schema's range")
                if core_session().content_hash() != before:
                    problems.append(f"shapewright.{name}.{prop}={x}: changed the document")
                    log_undo()
            for x in (inf.minimum, inf.maximum):
                if x is None:
                    continue
                try:
                    getattr(bpy.ops.shapewright, name)(**call, **{prop: value(x)})
                except RuntimeError as e:
                    if any(w in str(e) for w in RANGE_WORDS):
                        problems.append(
                            f"shapewright.{name}.{prop}={x}: the bound refused as out of range: {e}"
                        )
                if core_session().content_hash() != before:
                    log_undo()
                    assert core_session().content_hash() == before
    return problems


# A valid op for each op with ranged fields, on the scene of `op_scene`
# (ids: 1 curve network, 2 solid, 3 GC, 4 CSG volume).
CIRCLE = {"template": "circle", "radius": 0.04}
SMOOTH_PATH = [[0.0, -0.13, 0.1]] * 4
# A short arc drawn into the network (curve_draw, curve_draw_in_frame).
ARC_SAMPLES = [[0.3, 0.0, 0.0], [0.32, 0.0, 0.01], [0.34, 0.0, 0.015], [0.36, 0.0, 0.01], [0.38, 0.0, 0.0]]

BASE_OPS = {
    # Written by shared sessions (kind `session`): the first id of range 1.
    "reserve_ids": {"first": 16777217},
    "add_solid": {"shape": {"kind": "sphere", "radius": 0.1}, "segments": 64},
    "edit_solid": {"id": 2, "shape": {"kind": "sphere", "radius": 0.1}, "segments": 64},
    "gc_create": {
        "spine": [[0.9, 0.0, 0.0], [0.9, 0.0, 0.2]],
        "plane_normal": [0.0, 1.0, 0.0],
        "sections": [{"profile": CIRCLE, "v": 0.0}, {"profile": CIRCLE, "v": 1.0}],
        "resolution": {"u": 32, "v": 32},
    },
    "gc_resize": {"id": 3, "section": 1, "factor": 1.1},
    "gc_replace_section": {"id": 3, "part": 0, "section": 1, "profile": CIRCLE},
    "gc_set_shape": {"id": 3, "part": 0, "shape": {"type": "shell", "thickness": 0.004}},
    "sculpt_create": {"base": {"kind": "sphere", "radius": 0.1, "edge_length": 0.03}},
    "sculpt_stroke": {
        "id": 5,
        "settings": {
            "brush": {"kind": "sphere", "radius": 0.02},
            "brush_scale": 1.0,
            "influence": 0.05,
            "falloff": "smooth",
            "warp": {"kind": "drag"},
            "max_edge_rel": 0.1,
            "min_edge_rel": 0.03,
        },
        "samples": [
            {"position": [0.0, 0.0, 0.1 + 0.01 * k], "rotation": [0.0, 0.0, 0.0, 1.0], "pressure": 1.0}
            for k in range(2)
        ],
    },
    "sdf_add_operand": {
        "volume": 4,
        "component": {"kind": "solid", "shape": {"kind": "sphere", "radius": 0.05}},
        "csg": "union",
    },
    "gc_shift": {"id": 3, "section": 1, "v": 0.3},
    "gc_insert_section": {"id": 3, "v": 0.5},
    "gc_set_resolution": {"id": 3, "resolution": {"u": 32, "v": 32}},
    "gc_add_child": {
        "id": 3,
        "parent": 0,
        "at": [0.54, 0.0, 0.1],
        "spine": [[-0.004, 0.0], [0.05, 0.0]],
        "end": "free",
        "sections": [{"profile": {"template": "circle", "radius": 0.008}, "v": v} for v in (0.0, 1.0)],
        "tolerance": 1e-4,
        "end_tolerance": 1e-4,
        "resolution": {"u": 32, "v": 32},
    },
    "gc_copy": {"id": 3, "part": 0, "translate": [0.0, 0.3, 0.0], "tolerance": 1e-4},
    "gc_transform_part": {"id": 3, "part": 0, "translate": [0.0, 0.01, 0.0], "tolerance": 1e-4},
    "sdf_create": {"step": 0.01},
    "sdf_set_step": {"volume": 4, "step": 0.01},
    "curve_network_create": {"resolution": 24, "surface_n": 8},
    "curve_draw": {
        "id": 1,
        "samples": ARC_SAMPLES,
        "fit": {"mode": "interpolate"},
        "snap_tol": 0.002,
    },
    "curve_draw_in_frame": {
        "id": 1,
        "samples": ARC_SAMPLES,
        "frames": [{"origin": [0.0, 0.0, 0.0], "rotation": [0.0, 0.0, 0.0, 1.0]}],
        "fit": {"mode": "interpolate"},
        "snap_tol": 0.002,
    },
    "set_wall_thickness": {"thickness": 0.002},
    "curve_attract": {
        "id": 1,
        "curve": 1,
        "attractor": {"kind": "point", "p": [0.0, -0.2, 0.1]},
        "params": {"weight": 1.0, "wp0": 1.0, "wp1": 0.0, "alpha": 0.0, "keep_ends": True},
        "frames": 2,
    },
    "surface_smooth": {
        "id": 1,
        "patch": 0,
        "weights": {"wb": 1.0, "ws": 0.0},
        "f": 0.8,
        "wq_max": 1.0,
        "path": SMOOTH_PATH,
    },
    "surface_sharpen": {
        "id": 1,
        "patch": 0,
        "weights": {"wb": 1.0, "ws": 0.0},
        "f": 1.2,
        "wq_max": 2.0,
        "path": SMOOTH_PATH,
    },
    "surface_pull": {
        "id": 1,
        "patch": 2,
        "weights": {"wb": 1.0, "ws": 0.0},
        "wpp": 2000.0,
        "u0": 0.5,
        "v0": 0.5,
        "path": [[0.0, 0.0, 0.23], [0.0, 0.0, 0.235]],
    },
}


# Ops applied first for a BASE_OPS entry that edits an object `op_scene`
# does not make (the sculpt, id 5).
PRE_OPS = {
    "sculpt_stroke": (
        {"op": "sculpt_create", "base": {"kind": "sphere", "radius": 0.1, "edge_length": 0.03}},
    )
}


def core_bound_problems() -> list[str]:
    """The schema's ranges are the core's: every ranged number of every op
    (scalars and members of small structs, not ids) is refused by the core
    just outside its range, in an op that is otherwise valid (`BASE_OPS`).
    Run after `op_scene`."""
    import shapewright as sw

    schema = addon().schema
    s = core_session()
    problems = []
    checked = 0
    for op in schema.OPS:
        ranged = [
            g
            for g in schema.fields(op)
            if g.kind in ("int", "float")
            and schema.field_schema((op, *g.path)).get("x-ref") is None
            and (g.info.minimum, g.info.maximum, g.info.exclusive_minimum) != (None, None, None)
        ]
        if not ranged:
            continue
        base = BASE_OPS.get(op)
        if base is None:
            problems.append(
                f"{op}: ranged fields {[g.prop for g in ranged]} but no BASE_OPS entry to check them"
            )
            continue
        base = {"op": op, **base}
        trial_doc = s.snapshot()
        for pre in PRE_OPS.get(op, ()):
            trial_doc.apply(pre)
        try:
            trial_doc.snapshot().apply(base)
        except sw.ShapewrightError as e:
            problems.append(f"{op}: BASE_OPS entry refused: {e}")
            continue
        for g in ranged:
            for x in outside(g.info):
                trial = json.loads(json.dumps(base))
                if g.when is not None:  # a member of one kind of a tagged union
                    d = trial
                    for k in g.when[0][:-1]:
                        d = d.setdefault(k, {})
                    d[g.when[0][-1]] = g.when[1][0]
                d = trial
                for k in g.path[:-1]:
                    d = d.setdefault(k, {})
                d[g.path[-1]] = int(x) if g.info.integer else x
                checked += 1
                try:
                    trial_doc.snapshot().apply(trial)
                except sw.ShapewrightError:
                    continue
                except (ValueError, OverflowError, TypeError):
                    continue  # not even decodable (a negative u32)
                problems.append(
                    f"{op}.{'.'.join(g.path)}={x}: accepted by the core, outside the schema's range"
                )
    print(f"core bounds: {checked} out-of-range values tried")
    return problems
