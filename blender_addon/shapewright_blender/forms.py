"""Operator forms: the properties of the add-on's operators, made from the
core's op schema (`schema.py`), and their values turned into ops.

Two kinds of operator share this:
- typed operators (`typed_operator`), one per core form Blender gives
  a label (`op_table.py`): a form (templates, sketches, placements)
  that the core builds into the op (`shapewright.build_form`);
- generic operators (`generic_operator`), one for every other op of the
  schema: the op's fields flattened into typed properties
  (`schema.fields`), so a new core op gets an operator with no add-on
  edit.

Conventions (Blender's, and the issue's):
- every person-typed field is a typed property: numbers, vectors,
  choices, Euler rotations in the scene's angle unit (turned into the
  op's quaternion here); JSON text only for recorded strokes;
- lengths are `unit='LENGTH'` properties: shown and typed in the scene's
  units, turned into metres once, here (`units.py`); their defaults are
  metres, set in the scene's units when the operator runs; soft ranges
  are left to the tooltip, which states the range in millimetres (a
  static range would be wrong in any scene but one);
- no property is remembered between calls (`SKIP_SAVE`); no hard limits
  (they would clamp silently): values outside the schema's range are
  refused by field name, in the scene's units;
- an operator that changes an object starts from the object's current
  values (`current.py`): pressing it without typing anything changes
  nothing;
- NaN, infinity and Blender's float32 overflow of `inf` are refused by
  the core, naming the field.
"""

from __future__ import annotations

import dataclasses
import json
import math

import bpy
import shapewright as sw
from bpy.props import (
    BoolProperty,
    EnumProperty,
    FloatProperty,
    FloatVectorProperty,
    IntProperty,
    StringProperty,
)

from . import current, history, op_table, run, schema, units

SKIP = {"SKIP_SAVE"}
TARGET_DOC = "Object id, for scripts; -1 (the default): the active object"
PREFIX = "Shapewright: "


def _range_text(inf: schema.Info) -> str:
    """The schema's range, lengths in millimetres."""
    if inf.unit != "m":
        return inf.range_text()
    mm = dataclasses.replace(
        inf,
        unit=None,
        minimum=None if inf.minimum is None else inf.minimum * 1000,
        maximum=None if inf.maximum is None else inf.maximum * 1000,
        exclusive_minimum=None if inf.exclusive_minimum is None else inf.exclusive_minimum * 1000,
    )
    r = mm.range_text()
    return f"{r} mm" if r else ""


def tooltip(kind: str, inf: schema.Info, label: str) -> str:
    if kind == "target":
        return f"{inf.doc} {TARGET_DOC}".strip() if inf.doc and inf.doc != "The object." else TARGET_DOC
    if kind == "points":
        return "A sketch as JSON [[x, y, z], ...] in metres (the Sketch operator fills it); empty: none"
    doc = inf.doc or label
    r = _range_text(inf)
    if kind == "json":
        return f"{doc} (a recorded stroke: JSON, metres)"
    if kind == "ints":
        return f"{doc} (numbers separated by commas)"
    return f"{doc} Range: {r}." if r and r not in doc else doc


def _quat_to_euler(q) -> tuple[float, float, float]:
    from mathutils import Quaternion

    x, y, z, w = q
    e = Quaternion((w, x, y, z)).to_euler()
    return (e.x, e.y, e.z)


def make_property(kind: str, label: str, inf: schema.Info, default, items=(), size: int = 0, hidden=False):
    """One bpy property (see the module doc). Recorded data (JSON) and
    `hidden` fields are for scripts: the form does not show them."""
    if kind == "json" or hidden:
        options = {"SKIP_SAVE", "HIDDEN"}
    else:
        options = SKIP
    return _property(kind, label, inf, default, items, size, options)


def _property(kind: str, label: str, inf: schema.Info, default, items, size: int, SKIP):  # noqa: N803
    desc = tooltip(kind, inf, label)
    length = inf.unit == "m"
    rng = {}
    if kind in ("int", "float", "vec") and not length:
        lo, hi = inf.soft_range()
        cast = int if kind == "int" else float
        if lo is not None:
            rng["soft_min"] = cast(lo)
        if hi is not None:
            rng["soft_max"] = cast(hi)
    if kind == "target":
        return IntProperty(name=label, default=-1, description=desc, options=SKIP)
    if kind == "int":
        return IntProperty(name=label, default=int(default), description=desc, options=SKIP, **rng)
    if kind == "float":
        extra = {"subtype": "DISTANCE", "unit": "LENGTH"} if length else {}
        if inf.unit == "rad":
            extra = {"subtype": "ANGLE", "unit": "ROTATION"}
        return FloatProperty(
            name=label, default=float(default), precision=4, description=desc, options=SKIP, **extra, **rng
        )
    if kind == "bool":
        return BoolProperty(name=label, default=bool(default), description=desc, options=SKIP)
    if kind == "rotation":
        return FloatVectorProperty(
            name=label,
            default=_quat_to_euler(default),
            size=3,
            subtype="EULER",
            unit="ROTATION",
            description=f"{inf.doc or label} (Euler XYZ)".strip(),
            options=SKIP,
        )
    if kind in ("vec", "vec3"):
        n = size or 3
        extra = {"subtype": "TRANSLATION", "unit": "LENGTH"} if length and n == 3 else {}
        if inf.unit == "rad" and n == 3:
            extra = {"subtype": "EULER", "unit": "ROTATION"}
        return FloatVectorProperty(
            name=label, default=tuple(default), size=n, description=desc, options=SKIP, **extra, **rng
        )
    if kind == "enum":
        return EnumProperty(
            name=label,
            items=[(i, i.replace("_", " ").capitalize(), "") for i in items],
            default=default,
            description=desc,
            options=SKIP,
        )
    if kind == "library":
        return EnumProperty(
            name=label,
            items=[(n, n, "") for n in sw.library_names()],
            default=default,
            description=desc,
            options=SKIP,
        )
    if kind == "json":
        text = "" if default in (None, "", []) else json.dumps(default)
        return StringProperty(name=label, default=text, description=desc, options=SKIP)
    if kind == "ints":
        text = default if isinstance(default, str) else ", ".join(str(x) for x in default or ())
        return StringProperty(name=label, default=text, description=desc, options=SKIP)
    return StringProperty(name=label, default=default or "", description=desc, options=SKIP)


snap32 = units.snap32


def check_value(scene, label: str, inf: schema.Info, v, none_at=None) -> None:
    """Refuses (ValueError naming the field) a number or vector component
    outside the schema's range; lengths are said in the scene's units."""
    if none_at is not None and v == none_at:
        return
    for x in v if isinstance(v, (list, tuple)) else [v]:
        if isinstance(x, (int, float)) and not isinstance(x, bool):
            problem = inf.problem(x)
            if problem is not None:
                if inf.unit == "m" and math.isfinite(x):
                    problem = _length_problem(scene, inf, x)
                raise ValueError(f"{label} {problem}")


def _length_problem(scene, inf: schema.Info, x: float) -> str:
    t = lambda m: units.length_text(scene, m)  # noqa: E731
    if inf.minimum is not None and x < inf.minimum:
        return f"is {t(x)}, below the minimum {t(inf.minimum)}"
    if inf.exclusive_minimum is not None and x <= inf.exclusive_minimum:
        return f"is {t(x)}; it must be greater than {t(inf.exclusive_minimum)}"
    return f"is {t(x)}, above the maximum {t(inf.maximum)}"


def to_core(scene, g: schema.GenField, raw, label: str):
    """A property value as the op holds it: metres, quaternions, lists."""
    k = units.metres_per_unit(scene)
    if g.kind == "json":
        if not raw.strip():
            return None
        try:
            return json.loads(raw)
        except json.JSONDecodeError as e:
            raise ValueError(f"{label}: {g.prop} is not JSON: {e}") from e
    if g.kind == "ints":
        try:
            return [int(x) for x in raw.replace(";", ",").split(",") if x.strip()]
        except ValueError as e:
            raise ValueError(f"{label}: {g.prop} must be whole numbers separated by commas") from e
    if g.kind == "rotation":
        from mathutils import Euler

        q = Euler(tuple(raw)).to_quaternion()
        return [q.x, q.y, q.z, q.w]
    if g.kind in ("vec", "vec3"):
        v = [snap32(float(x)) for x in raw]
        return [x * k for x in v] if g.info.unit == "m" else v
    if g.kind == "float":
        v = snap32(float(raw))
        return v * k if g.info.unit == "m" else v
    return raw


def length_defaults(fields_: tuple[schema.GenField, ...]) -> dict[str, object]:
    """Metre defaults of the length properties (set in scene units when an
    operator runs: `units.fill_defaults`)."""
    return {g.prop: g.default for g in fields_ if g.info.unit == "m" and g.kind in ("float", "vec", "vec3")}


def resolve_target(operator, context, prop: str, want: str | None, label: str) -> int:
    raw = getattr(operator, prop)
    if raw >= 0:
        return raw
    oid = run.active_id(context)
    if oid is None or (want is not None and run.active_kind(context) != want):
        what = (want or "Shapewright object").replace("_", " ")
        raise ValueError(f"{label}: make a {what} the active object (or pass {prop})")
    return oid


def generic_values(operator, op: str, fields_: tuple[schema.GenField, ...], context) -> dict:
    """The op dict of a generic operator (see the module doc). Raises
    ValueError with a message for the person."""
    kind = schema.OPS[op]["kind"]
    want = None if kind == "document" else kind
    label = op_table.label_of(op)
    scene = context.scene
    values: dict = {}
    missing = []
    for g in fields_:
        if g.kind == "target":
            values[g.prop] = resolve_target(operator, context, g.prop, want, label)
            continue
        v = to_core(scene, g, getattr(operator, g.prop), label)
        if v is None and g.kind == "json" and g.required and g.when is None:
            missing.append(g.prop)
        if g.kind in ("int", "float", "vec"):
            check_value(scene, f"{label}: {g.prop}", g.info, v)
        values[g.prop] = v
    if missing:
        raise ValueError(f"{label}: give {', '.join(missing)} (JSON, from a script)")
    return {"op": op, **schema.assemble(fields_, values)}


def _run_generic(self, context):
    op = self.op_name
    fields_ = schema.fields(op)
    try:
        current.fill(self, context, op, fields_)
        units.fill_defaults(self, context.scene, length_defaults(fields_))
        built = generic_values(self, op, fields_, context)
    except ValueError as e:  # also sw.ShapewrightError
        self.report({"ERROR"}, str(e))
        return {"CANCELLED"}
    return run.run_op(self, context, built)


def generic_operator(op: str) -> type:
    """An operator for any op of the core's schema, its properties built
    from the schema: a new core op gets one with no add-on edit."""
    fields_ = schema.fields(op)
    kind = schema.OPS[op]["kind"]
    label = op_table.label_of(op)
    attrs = {
        "__doc__": schema.clean_doc(schema.OPS[op]["doc"]) or label,
        "bl_idname": f"shapewright.{op}",
        "bl_label": PREFIX + label,
        "bl_options": {"REGISTER", "UNDO"},
        "op_name": op,
        "short_label": label,
        "__annotations__": {
            g.prop: make_property(
                g.kind, g.prop.replace("_", " ").capitalize(), g.info, g.default, g.items, g.size
            )
            for g in fields_
        },
        "execute": _run_generic,
        "sw_schema": {g.prop: (op, *g.path) for g in fields_ if g.kind != "target"},
    }
    if any(g.kind == "target" for g in fields_):
        want = None if kind == "document" else kind

        def poll(cls, context):
            if want is None:
                return run.active_kind(context) is not None
            return run.active_kind(context) == want or run.scene_has_kind(context, want)

        attrs["poll"] = classmethod(poll)
    return type(f"SHAPEWRIGHT_OT_{op}", (bpy.types.Operator,), attrs)


# Typed operators (the op table's forms).


def field_info(spec: op_table.OpSpec, f: op_table.Field) -> schema.Info:
    """The schema's doc, unit and range for one op-table field (the field
    it stands for, `f.like`, or the op's field of the same name), with
    Blender's own text and unit where the field is the add-on's own."""
    path = f.like or (spec.op, f.name)
    inf = schema.info(path) if schema.field_schema(path) is not None else schema.Info()
    return dataclasses.replace(inf, doc=f.doc or inf.doc, unit=f.unit or inf.unit)


def schema_path(spec: op_table.OpSpec, f: op_table.Field) -> tuple[str, ...] | None:
    """The schema field a typed operator's property stands for (None: a
    field of the add-on's own)."""
    path = f.like or (spec.op, f.name)
    return path if schema.field_schema(path) is not None else None


def struct_parts(spec: op_table.OpSpec, f: op_table.Field) -> tuple[schema.GenField, ...]:
    """The flat properties of a `struct` field, with the field's own unit
    overrides (`f.units`: member -> unit) for members the schema leaves
    without one."""
    parts = schema.struct_fields(f.like or (spec.op, f.name), f.name, f.default)
    out = []
    for g in parts:
        unit = f.units.get(g.prop[len(f.name) + 1 :])
        out.append(dataclasses.replace(g, info=dataclasses.replace(g.info, unit=unit)) if unit else g)
    return tuple(out)


def spec_fields(spec: op_table.OpSpec) -> list[tuple[op_table.Field, schema.GenField]]:
    """Every property of a typed form: (the op-table field, the property)."""
    out = []
    for f in spec.fields:
        if f.kind == "struct":
            out += [(f, g) for g in struct_parts(spec, f)]
            continue
        inf = field_info(spec, f)
        kind = "vec" if f.kind == "vec3" else f.kind
        out.append(
            (
                f,
                schema.GenField(
                    f.name, (f.name,), kind, inf, f.default, False, 3 if kind == "vec" else 0, f.items
                ),
            )
        )
    return out


def op_values(operator, spec: op_table.OpSpec, context) -> dict:
    """The flat values of a typed operator in the op's units (metres,
    quaternions), with targets resolved and structs assembled. Raises
    ValueError with a message for the person."""
    values: dict = {}
    kind = op_table.kind_of(spec)
    scene = context.scene
    flat = spec_fields(spec)
    for f, g in flat:
        if f.kind == "target":
            values[f.name] = resolve_target(operator, context, f.name, kind, spec.label)
        elif f.kind == "points":
            raw = getattr(operator, f.name)
            try:
                pts = json.loads(raw) if raw.strip() else []
            except json.JSONDecodeError as e:
                raise ValueError(f"{spec.label}: {f.name} is not JSON: {e}") from e
            values[f.name] = units.to_metres(scene, pts) if pts else []
        elif f.kind == "struct":
            continue
        else:
            v = to_core(scene, g, getattr(operator, g.prop), spec.label)
            if f.kind == "vec3":
                v = tuple(v)
            if f.kind in ("int", "float", "vec3"):
                check_value(scene, f"{spec.label}: {f.name}", g.info, v, f.none_at)
            values[f.name] = v
    for f in spec.fields:
        if f.kind == "struct":
            parts = [g for ff, g in flat if ff is f]
            raw = {}
            for g in parts:
                v = to_core(scene, g, getattr(operator, g.prop), spec.label)
                if g.kind in ("int", "float", "vec"):
                    check_value(scene, f"{spec.label}: {g.prop}", g.info, v)
                raw[g.prop] = v
            values[f.name] = schema.assemble(tuple(parts), raw)
        if f.kind == "points" and not values[f.name] and spec.needs_points:
            raise ValueError(f"{spec.label}: sketch it (Sketch panel) or give {f.name}")
    return values


def _typed_execute(self, context):
    spec = op_table.BY_OP[self.op_name]
    try:
        # A struct's members are named relative to it: not current values.
        current.fill(self, context, spec.op, [g for f, g in spec_fields(spec) if f.kind != "struct"])
        defaults = {
            g.prop: g.default
            for f, g in spec_fields(spec)
            if g.info.unit == "m" and g.kind in ("float", "vec")
        }
        units.fill_defaults(self, context.scene, defaults)
        values = op_values(self, spec, context)
        s = history.session(context.scene) if spec.build_with is not None else None
        op = op_table.build_op(spec, values, s)
    except ValueError as e:  # also sw.ShapewrightError (a ValueError)
        self.report({"ERROR"}, str(e))
        return {"CANCELLED"}
    return run.run_op(self, context, op)


def _typed_poll(spec: op_table.OpSpec):
    kind = op_table.kind_of(spec)
    if kind is None:
        return None

    def poll(cls, context):
        # The active object's kind for buttons and menus; a script may
        # pass an id while something else is active.
        return run.active_kind(context) == kind or run.scene_has_kind(context, kind)

    return classmethod(poll)


def typed_operator(spec: op_table.OpSpec) -> type:
    """A thin operator class for one op spec: its fields as properties,
    execute = build the op dict and apply it."""
    annotations = {}
    for f, g in spec_fields(spec):
        if f.kind == "struct":
            label = g.prop[len(f.name) + 1 :].replace("_", " ").capitalize()
            kind = g.kind
        else:
            label = f.label or f.name.replace("_", " ").capitalize()
            kind = f.kind
        annotations[g.prop] = make_property(kind, label, g.info, g.default, g.items, g.size, g.hidden)
    attrs = {
        "__doc__": spec.description,
        "bl_idname": f"shapewright.{spec.op}",
        "bl_label": PREFIX + spec.label,
        "bl_options": {"REGISTER", "UNDO"},
        "op_name": spec.op,
        "short_label": spec.label,
        "__annotations__": annotations,
        "execute": _typed_execute,
        # Which schema field each property stands for (tests check the
        # properties' tooltips and ranges against it).
        "sw_schema": {
            f.name: p
            for f in spec.fields
            if f.kind not in ("target", "points", "struct") and (p := schema_path(spec, f)) is not None
        },
    }
    poll = _typed_poll(spec)
    if poll is not None:
        attrs["poll"] = poll
    return type(f"SHAPEWRIGHT_OT_{spec.op}", (bpy.types.Operator,), attrs)
