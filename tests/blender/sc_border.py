"""The typed pyo3 border (issue 36): the `.pyi` stub states exactly the
native module's surface (every class, method, property and function with
its parameters), and values cross as Python objects, not JSON text."""

from __future__ import annotations

import ast
import inspect
from pathlib import Path

from helpers import core_session


def _stub(path: Path) -> dict[str, object]:
    """name -> parameter names (functions) or {member: params or
    "property"} (classes), from the stub."""

    def params(fn: ast.FunctionDef) -> tuple[str, ...]:
        a = fn.args
        names = [x.arg for x in a.posonlyargs + a.args + a.kwonlyargs]
        return tuple(n for n in names if n not in ("self", "cls"))

    out: dict[str, object] = {}
    for node in ast.parse(path.read_text()).body:
        if isinstance(node, ast.FunctionDef):
            out[node.name] = params(node)
        elif isinstance(node, ast.ClassDef):
            members: dict[str, object] = {}
            for m in node.body:
                if isinstance(m, ast.FunctionDef):
                    deco = {getattr(d, "id", "") for d in m.decorator_list}
                    members[m.name] = "property" if "property" in deco else params(m)
            out[node.name] = members
        elif isinstance(node, ast.AnnAssign):
            out[node.target.id] = "constant"
    return out


def _module(native) -> dict[str, object]:
    def params(obj) -> tuple[str, ...]:
        try:
            sig = inspect.signature(obj)
        except (TypeError, ValueError):
            return ("?",)
        return tuple(p for p in sig.parameters if p not in ("self", "cls", "$self", "$cls"))

    out: dict[str, object] = {}
    for name in dir(native):
        if name.startswith("_"):
            continue
        obj = getattr(native, name)
        if inspect.isclass(obj) and issubclass(obj, BaseException):
            out[name] = {}
        elif inspect.isclass(obj):
            members: dict[str, object] = {}
            for m, v in vars(obj).items():
                if m.startswith("__") and m not in ("__init__", "__len__"):
                    continue
                if inspect.isgetsetdescriptor(v) or isinstance(v, property):
                    members[m] = "property"
                elif callable(v) or isinstance(v, staticmethod):
                    members[m] = params(getattr(obj, m))
            if "__init__" not in members and obj.__text_signature__:
                members["__init__"] = params(obj)
            out[name] = members
        elif callable(obj):
            out[name] = params(obj)
        else:
            out[name] = "constant"
    return out


def scenario_native_stub(work: Path) -> None:
    import shapewright
    from shapewright import _native

    stub = _stub(Path(shapewright.__file__).with_name("_native.pyi"))
    real = _module(_native)
    problems = []
    for name in sorted(set(stub) | set(real)):
        if name not in real:
            problems.append(f"{name}: in the stub, not in the module")
        elif name not in stub:
            problems.append(f"{name}: in the module, not in the stub")
        elif isinstance(real[name], dict):
            s, r = stub[name], real[name]
            for m in sorted(set(s) | set(r)):
                if m == "__init__" and m not in r:
                    continue  # no constructor from Python (PaletteView)
                if m not in r or m not in s:
                    problems.append(f"{name}.{m}: {'only in the stub' if m in s else 'not in the stub'}")
                elif s[m] != r[m] and "?" not in r[m]:
                    problems.append(f"{name}.{m}: stub {s[m]}, module {r[m]}")
        elif stub[name] != real[name]:
            problems.append(f"{name}: stub {stub[name]}, module {real[name]}")
    assert not problems, "the stub is not the module:\n" + "\n".join(problems)
    # Values, not text: an op is a dict in and out; a placement a value.
    s = core_session()
    created = s.apply({"op": "add_solid", "shape": {"kind": "sphere", "radius": 0.1}})
    assert isinstance(s.op(0), dict) and s.op(0)["shape"]["radius"] == 0.1
    origin = s.object_origin(created)
    assert isinstance(origin, shapewright.Placement) and origin.translate == [0.0, 0.0, 0.0]
    for bad, words in (
        ({"op": "add_solid", "shape": {"kind": "sphere", "radius": float("nan")}}, "shape.radius"),
        ({"op": "add_solid", "shape": {"kind": "sphere", "radius": 3.4e38}}, "not finite"),
    ):
        try:
            s.apply(bad)
        except shapewright.ParseError as e:
            assert words in str(e), e
        else:
            raise AssertionError(f"{bad} must be refused")
