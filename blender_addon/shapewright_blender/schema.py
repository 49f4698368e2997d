"""The core's op schema (`shapewright.op_schema()`, a dict, declared once in
`core/src/doc/ops/`) read for Blender: field docs, units (`x-unit`: `m`,
`rad`), ranges (`minimum`, `maximum`, `exclusiveMinimum`) and defaults.

Two uses:
- `info(path)`: what a property shows and checks for one schema field
  (tooltip, Blender unit and subtype, soft range). The typed operators of
  `op_table` name the field each property stands for; the schema is the
  only place a doc, unit or range is written.
- `fields(op)`: the fields of any op as flat, typed operator properties,
  so every op of the core gets an operator (`forms.generic_operator`) with
  no add-on edit: numbers, booleans, names and choices become properties,
  fixed-size number arrays vectors, quaternions Euler rotations (in the
  scene's angle unit), structs one property per member (at any depth),
  tagged unions a choice of kind plus the members of every kind (only the
  chosen kind's go into the op), optional values a choice with "None" or a
  "Use" switch, and lists of integers a comma-separated list. Only
  recorded strokes (lists of samples) stay JSON text.

Ranges are shown as soft ranges and checked before an op is built
(`check`): Blender's hard limits would clamp a bad value silently, and a
refused value must say which field and why. Nothing here computes
geometry.
"""

from __future__ import annotations

import dataclasses
import math
import re
from dataclasses import dataclass
from typing import Any

import shapewright as sw

SCHEMA: dict = sw.op_schema()
DEFS: dict = SCHEMA["defs"]
OPS: dict[str, dict] = {o["name"]: o for o in SCHEMA["ops"]}
# Blender (unit, float subtype, 3-vector subtype) of each core unit.
UNITS = {"m": ("LENGTH", "DISTANCE", "TRANSLATION"), "rad": ("ROTATION", "ANGLE", "EULER")}


def clean_doc(text: str | None) -> str:
    """A doc comment as a one-paragraph tooltip (rustdoc links and code
    marks dropped)."""
    if not text:
        return ""
    text = re.sub(r"\[`([^`\]]+)`\]", lambda m: m.group(1).rsplit("::", 1)[-1], text)
    text = text.replace("`", "")
    return " ".join(text.split())


def resolve(schema: dict) -> dict:
    """`schema` with `$ref`s followed; the referring schema's own keys
    (description, default, unit) win over the definition's."""
    out = dict(schema)
    for _ in range(16):
        ref = out.get("$ref")
        if not ref:
            break
        target = DEFS.get(ref.rsplit("/", 1)[-1], {})
        out = {**target, **{k: v for k, v in out.items() if k != "$ref"}}
        if "$ref" not in target:
            out.pop("$ref", None)
    return out


def members(schema: dict) -> dict[str, dict]:
    """The properties of an object schema; for a tagged union, those of
    every branch (the first branch naming a property wins)."""
    s = resolve(schema)
    out = dict(s.get("properties", {}))
    tags: dict[str, list] = {}
    for branch in s.get("oneOf", []):
        for k, v in resolve(branch).get("properties", {}).items():
            if "const" in v:
                tags.setdefault(k, []).append(v["const"])
            out.setdefault(k, v)
    # A union's tag: the union's doc, every branch's tag as a choice.
    for k, consts in tags.items():
        out[k] = {"type": "string", "enum": consts, "description": s.get("description", "")}
    return out


def field_schema(path: tuple[str, ...]) -> dict | None:
    """The schema at `path`: `(op, field, member, ...)`, or
    `("@Def", member, ...)` for a definition (a shape's radius, a
    transform's translation). None when there is no such field."""
    head, rest = path[0], path[1:]
    if head.startswith("@"):
        s: dict | None = DEFS.get(head[1:])
    else:
        op = OPS.get(head)
        if op is None or not rest:
            return None
        s = next((f["schema"] for f in op["fields"] if f["name"] == rest[0]), None)
        rest = rest[1:]
    for key in rest:
        if s is None:
            return None
        s = members(s).get(key)
    return resolve(s) if s is not None else None


def types(s: dict) -> list[str]:
    t = s.get("type")
    return [t] if isinstance(t, str) else list(t or [])


def choices(s: dict) -> tuple[str, ...] | None:
    """The strings an enum-like field takes (None: not an enum)."""
    s = resolve(s)
    if "enum" in s:
        return tuple(s["enum"])
    alts = s.get("oneOf")
    if alts and all("const" in resolve(a) for a in alts):
        return tuple(resolve(a)["const"] for a in alts)
    return None


@dataclass(frozen=True)
class Info:
    """What one operator property takes from its schema field."""

    doc: str = ""
    unit: str | None = None  # the core's unit: "m" or "rad"
    minimum: float | None = None
    maximum: float | None = None
    exclusive_minimum: float | None = None
    integer: bool = False

    def range_text(self) -> str:
        u = f" {self.unit}" if self.unit == "m" else ""
        lo = (
            f"> {self.exclusive_minimum:g}"
            if self.exclusive_minimum is not None
            else (f">= {self.minimum:g}" if self.minimum is not None else "")
        )
        if lo and self.maximum is not None:
            lo = lo.replace(">= ", "")
            return (
                f"{lo} to {self.maximum:g}{u}" if not lo.startswith(">") else f"{lo}, <= {self.maximum:g}{u}"
            )
        if self.maximum is not None:
            return f"<= {self.maximum:g}{u}"
        return f"{lo}{u}" if lo else ""

    def tooltip(self, fallback: str = "") -> str:
        doc = self.doc or fallback
        r = self.range_text()
        return f"{doc} Range: {r}." if r and r not in doc else doc

    def soft_range(self) -> tuple[float | None, float | None]:
        lo = self.minimum if self.minimum is not None else self.exclusive_minimum
        return lo, self.maximum

    def problem(self, x: float) -> str | None:
        """Why the core would refuse `x` for this field (None: in range)."""
        if isinstance(x, float) and not math.isfinite(x):
            return "is not a finite number"
        if self.minimum is not None and x < self.minimum:
            return f"is {x:g}, below the minimum {self.minimum:g}"
        if self.exclusive_minimum is not None and x <= self.exclusive_minimum:
            return f"is {x:g}; it must be greater than {self.exclusive_minimum:g}"
        if self.maximum is not None and x > self.maximum:
            return f"is {x:g}, above the maximum {self.maximum:g}"
        return None


def info_of(s: dict | None) -> Info:
    if s is None:
        return Info()
    s = resolve(s)
    items = s.get("items") if isinstance(s.get("items"), dict) else None
    bound = items if items is not None and "type" in items else {}

    def pick(k: str):
        return s.get(k, bound.get(k))

    return Info(
        doc=clean_doc(s.get("description")),
        unit=pick("x-unit"),
        minimum=pick("minimum"),
        maximum=pick("maximum"),
        exclusive_minimum=pick("exclusiveMinimum"),
        integer="integer" in types(s) or "integer" in types(bound),
    )


def info(path: tuple[str, ...]) -> Info:
    """The doc, unit and range of the field at `path` (see `field_schema`)."""
    return info_of(field_schema(path))


@dataclass(frozen=True)
class GenField:
    """One property of an op's form: where its value goes in the op
    (`path`), how it is shown (`kind`: target, int, float, bool, vec,
    rotation, enum, string, ints, json) and what the schema says of it.
    `when` (a tag's path and values) limits it to some kinds of a tagged
    union; `optional` fields may be left out (`None`)."""

    prop: str
    path: tuple[str, ...]
    kind: str
    info: Info
    default: Any
    required: bool
    size: int = 0
    items: tuple[str, ...] = ()
    when: tuple[tuple[str, ...], tuple[str, ...]] | None = None
    optional: bool = False
    # Data a person does not type (a mesh a brush was made from): scripts
    # pass it, the form does not show it.
    hidden: bool = False


NONE_ITEM = "none"


def _default(kind: str, s: dict, info: Info, size: int, items: tuple[str, ...] = ()) -> Any:
    if "default" in s and s["default"] is not None:
        d = s["default"]
        if kind == "vec":
            return tuple(d)
        if kind == "rotation":
            return tuple(d)
        if kind == "ints":
            return ", ".join(str(x) for x in d)
        return d
    if kind == "enum":
        # Blender's EnumProperty needs a default among its items.
        return items[0] if items else ""
    if kind == "int":
        lo = info.minimum if info.minimum is not None else 0
        return int(lo)
    if kind == "float":
        if info.minimum is not None and info.maximum is not None:
            return (info.minimum + info.maximum) / 2
        if info.minimum is not None:
            return float(info.minimum)
        if info.exclusive_minimum is not None:
            return info.exclusive_minimum + 1.0
        return 0.0
    if kind == "vec":
        return (0.0,) * size
    if kind == "rotation":
        return (0.0, 0.0, 0.0, 1.0)
    if kind == "bool":
        return False
    return ""


ROTATION_NAMES = ("rotate", "rotation", "q", "orientation")


def _leaf(name: str, s: dict) -> tuple[str, int, tuple[str, ...]]:
    """(kind, vector size, enum items) of a field that is not a struct."""
    s = resolve(s)
    if s.get("x-ref") == "object":
        return "target", 0, ()
    consts = choices(s)
    if consts is not None:
        return "enum", 0, consts
    t = [x for x in types(s) if x != "null"]
    if t == ["integer"]:
        return "int", 0, ()
    if t == ["number"]:
        return "float", 0, ()
    if t == ["boolean"]:
        return "bool", 0, ()
    if t == ["string"]:
        return "string", 0, ()
    items = s.get("items")
    if t == ["array"] and isinstance(items, dict):
        it = resolve(items)
        if types(it) == ["number"]:
            n = s.get("minItems")
            if n == 4 and s.get("maxItems") == 4 and name in ROTATION_NAMES:
                return "rotation", 4, ()
            if n is not None and n == s.get("maxItems") and 2 <= n <= 4:
                return "vec", n, ()
        if types(it) == ["integer"] or "integer" in types(resolve(items)):
            return "ints", 0, ()
    return "json", 0, ()


def _optional(s: dict) -> dict | None:
    """The schema an `X or null` field holds (None: not optional)."""
    if "null" in types(s) and len(types(s)) == 2:
        return {**s, "type": [t for t in types(s) if t != "null"][0]}
    for key in ("anyOf", "oneOf"):
        alts = s.get(key)
        if alts and len(alts) == 2 and any(resolve(a).get("type") == "null" for a in alts):
            other = next(a for a in alts if resolve(a).get("type") != "null")
            return {**resolve(other), "description": s.get("description", "")}
    return None


def _tag(s: dict) -> str | None:
    """The tag property of a tagged union (every branch has it as a const)."""
    branches = [resolve(b) for b in s.get("oneOf", [])]
    if not branches or not all(b.get("type") == "object" for b in branches):
        return None
    for key, v in branches[0].get("properties", {}).items():
        if "const" in v and all("const" in b.get("properties", {}).get(key, {}) for b in branches):
            return key
    return None


MAX_DEPTH = 5


def flatten(
    name: str,
    path: tuple[str, ...],
    schema: dict,
    required: bool,
    default: Any = None,
    when=None,
    depth: int = 0,
) -> list[GenField]:
    """The properties of the value at `path` (`schema`), named from `name`.
    `default` (a value of the op, e.g. an op table's defaults) wins over
    the schema's."""
    s = resolve(schema)
    if default is None and "default" in s:
        default = s["default"]
    inner = _optional(s)
    if inner is not None:
        out = flatten(name, path, inner, required, default, when, depth)
        if len(out) == 1 and out[0].kind == "enum":
            f = out[0]
            items = (NONE_ITEM, *f.items)
            d = NONE_ITEM if default is None else f.default
            return [GenField(f.prop, f.path, "enum", f.info, d, False, 0, items, when, True)]
        return [
            GenField(f.prop, f.path, f.kind, f.info, f.default, False, f.size, f.items, f.when, True)
            if f.path == path
            else f
            for f in out
        ]
    tag = _tag(s) if depth < MAX_DEPTH else None
    if tag is not None:
        branches = [resolve(b) for b in s["oneOf"]]
        consts = tuple(b["properties"][tag]["const"] for b in branches)
        chosen = default.get(tag) if isinstance(default, dict) else None
        info = Info(doc=clean_doc(s.get("description")))
        out = [
            GenField(
                f"{name}_{tag}" if name else tag,
                (*path, tag),
                "enum",
                info,
                chosen if chosen in consts else consts[0],
                required,
                0,
                consts,
                when,
            )
        ]
        members: dict[str, list] = {}
        for b, c in zip(branches, consts, strict=True):
            for k, sub in b.get("properties", {}).items():
                if k != tag:
                    members.setdefault(k, [sub, []])[1].append(c)
        per_kind: dict[str, list] = {c: [] for c in consts}
        for k, (sub, kinds) in members.items():
            d = default.get(k) if isinstance(default, dict) and chosen in kinds else None
            made = flatten(
                f"{name}_{k}" if name else k,
                (*path, k),
                sub,
                True,
                d,
                ((*path, tag), tuple(kinds)),
                depth + 1,
            )
            for c in kinds:
                per_kind[c] += made
            out += made
        # A kind that carries data (JSON: a mesh, samples) is made by the
        # core from other objects, not typed: its members are hidden.
        data = {id(f) for fs in per_kind.values() if any(f.kind == "json" for f in fs) for f in fs}
        return [dataclasses.replace(f, hidden=True) if id(f) in data else f for f in out]
    props = s.get("properties")
    if types(s) == ["object"] and props and "oneOf" not in s and depth < MAX_DEPTH:
        req = set(s.get("required", ()))
        out = []
        for k, sub in props.items():
            d = default.get(k) if isinstance(default, dict) else None
            out += flatten(
                f"{name}_{k}" if name else k, (*path, k), sub, required and k in req, d, when, depth + 1
            )
        return out
    kind, size, items = _leaf(path[-1] if path else name, s)
    inf = info_of(s)
    s2 = {**s, "default": default} if default is not None else s
    return [
        GenField(name, path, kind, inf, _default(kind, s2, inf, size, items), required, size, items, when)
    ]


def fields(op: str) -> tuple[GenField, ...]:
    """The fields of `op` as flat, typed operator properties."""
    out: list[GenField] = []
    for f in OPS[op]["fields"]:
        out += flatten(f["name"], (f["name"],), f["schema"], f["required"])
    return tuple(out)


def struct_fields(path: tuple[str, ...], prefix: str, default: Any = None) -> tuple[GenField, ...]:
    """The flat properties of one field of an op (`path` = (op, field)),
    named with `prefix`, for a typed form that shows a struct field typed
    (the op table's `struct` fields)."""
    s = field_schema(path)
    if s is None:
        return ()
    return tuple(flatten(prefix, (), s, True, default))


def assemble(fields_: tuple[GenField, ...], values: dict[str, Any]) -> dict:
    """The nested value of flat property values (`values` by prop name,
    already in the op's units): members of a tagged union's other kinds
    left out, optional fields set to None when not used."""
    out: dict = {}
    chosen = {f.path: values[f.prop] for f in fields_ if f.kind == "enum"}
    for f in fields_:
        if f.when is not None and chosen.get(f.when[0]) not in f.when[1]:
            continue
        v = values[f.prop]
        if f.optional and (v is None or (f.kind == "enum" and v == NONE_ITEM)):
            v = None
        if not f.path:
            return v
        d = out
        for k in f.path[:-1]:
            d = d.setdefault(k, {})
        d[f.path[-1]] = v
    return out
