"""The core's op schema (`shapewright.op_schema_json()`, declared once in
`core/src/doc/ops/`) read for Blender: field docs, units (`x-unit`: `m`,
`rad`), ranges (`minimum`, `maximum`, `exclusiveMinimum`) and defaults.

Two uses:
- `info(path)`: what a property shows and checks for one schema field
  (tooltip, Blender unit and subtype, soft range). The typed operators of
  `op_table` name the field each property stands for; the schema is the
  only place a doc, unit or range is written.
- `fields(op)`: the fields of any op as flat operator properties, so every
  op of the core gets an operator (`operators.generic_operator`) with no
  add-on edit: numbers, booleans, names and choices become properties,
  fixed-size number arrays become vectors, small structs (a transform, a
  resolution) are flattened to one property per member, and anything else
  (tagged unions, lists) is JSON text.

Ranges are shown as soft ranges and checked before an op is built
(`check`): Blender's hard limits would clamp a bad value silently, and a
refused value must say which field and why. Nothing here computes
geometry.
"""

from __future__ import annotations

import json
import math
import re
from dataclasses import dataclass
from typing import Any

import shapewright as sw

SCHEMA: dict = json.loads(sw.op_schema_json())
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
    """One property of a generic operator: where its value goes in the op
    (`path`), how it is shown (`kind`: target, int, float, bool, vec,
    enum, string, json) and what the schema says of it."""

    prop: str
    path: tuple[str, ...]
    kind: str
    info: Info
    default: Any
    required: bool
    size: int = 0
    items: tuple[str, ...] = ()


def _default(kind: str, s: dict, info: Info, size: int, items: tuple[str, ...] = ()) -> Any:
    if "default" in s:
        d = s["default"]
        return tuple(d) if kind == "vec" else d
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
    if kind == "bool":
        return False
    return ""


def _classify(s: dict) -> tuple[str, int, tuple[str, ...]]:
    """(kind, vector size, enum items) of a field schema."""
    s = resolve(s)
    if s.get("x-ref") == "object":
        return "target", 0, ()
    consts = choices(s)
    if consts is not None:
        return "enum", 0, consts
    t = types(s)
    if t == ["integer"]:
        return "int", 0, ()
    if t == ["number"]:
        return "float", 0, ()
    if t == ["boolean"]:
        return "bool", 0, ()
    if t == ["string"]:
        return "string", 0, ()
    items = s.get("items")
    if t == ["array"] and isinstance(items, dict) and types(resolve(items)) == ["number"]:
        n = s.get("minItems")
        if n is not None and n == s.get("maxItems") and 2 <= n <= 4:
            return "vec", n, ()
    return "json", 0, ()


def _flat(s: dict) -> bool:
    """A small struct whose members are all plain properties."""
    s = resolve(s)
    props = s.get("properties")
    return (
        types(s) == ["object"]
        and "oneOf" not in s
        and bool(props)
        and all(_classify(p)[0] not in ("json", "target") for p in props.values())
    )


def fields(op: str) -> tuple[GenField, ...]:
    """The fields of `op` as flat operator properties."""
    out = []
    for f in OPS[op]["fields"]:
        s = resolve(f["schema"])
        if _flat(s):
            req = set(s.get("required", ()))
            for k, sub in s["properties"].items():
                sub = resolve(sub)
                kind, size, items = _classify(sub)
                inf = info_of(sub)
                default = s.get("default", {}).get(k) if isinstance(s.get("default"), dict) else None
                sub = {**sub, "default": default} if default is not None else sub
                out.append(
                    GenField(
                        f"{f['name']}_{k}",
                        (f["name"], k),
                        kind,
                        inf,
                        _default(kind, sub, inf, size, items),
                        f["required"] and k in req,
                        size,
                        items,
                    )
                )
            continue
        kind, size, items = _classify(s)
        inf = info_of(s)
        default = _default(kind, s, inf, size, items)
        out.append(GenField(f["name"], (f["name"],), kind, inf, default, f["required"], size, items))
    return tuple(out)
