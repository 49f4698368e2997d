"""The floors of docs/ARCHITECTURE.md, read from the code (issue 36).

Reads every production `.rs` file of `core/src` (test modules left out: a
file declared under `#[cfg(test)]`, an inline `#[cfg(test)] mod` block to
its end, and a `use` under `#[cfg(test)]`) and collects which module each
file names: `use` trees (`use crate::{a, b::{c, d}}`, `super::`, `self::`,
and 2018 paths that start at a child module) and paths in code
(`crate::x::y`). A name the module re-exports or imports (`interact::Tool`,
from `interact/mod.rs`'s `pub use tools::..`) counts as the module it comes
from. Three rules:

- a geometry module (math, nurbs, sketch, solid, gc, assembly, sdf,
  styling, sculpt, mesh, print) never names `crate::doc` or
  `crate::interact`;
- `core` never names a host, transport or file-writing crate
  (`shapewright_xr`, `shapewright_py`, `shapewright_net`,
  `shapewright_usd`, `shapewright_atomic`: core does no I/O), in code or in
  its Cargo.toml;
- no import circle between two sibling modules of one folder, at any depth
  (`interact/input` and `interact/tools`, or `doc/log` and `doc/shared` before
  the single-user history moved to `doc/linear.rs`), when
  at least one of the two is a folder; sibling files of one folder may name
  each other.

`KNOWN` and `KNOWN_FOLDER_CIRCLES` list the crossings that exist today with
the change that removes each. They are a ratchet, not an allowance: the
test fails when a new crossing appears and also when a listed one is gone
(then delete its line), so the lists can only shrink.
"""

from __future__ import annotations

import functools
import re
from pathlib import Path

from rustsrc import code_only

ROOT = Path(__file__).resolve().parents[2]
SRC = ROOT / "core" / "src"
GEOMETRY = {
    "math",
    "nurbs",
    "sketch",
    "solid",
    "gc",
    "assembly",
    "sdf",
    "styling",
    "sculpt",
    "mesh",
    "print",
}
# `shapewright_atomic` writes files: core does no I/O (atomic/src/lib.rs).
HOSTS = ("shapewright_xr", "shapewright_py", "shapewright_net", "shapewright_usd", "shapewright_atomic")

# ("up", from, to): a geometry module naming doc or interact -> what removes it.
KNOWN: dict[tuple[str, str, str], str] = {}

# (module, module), sorted, as paths under core/src: sibling modules that
# name each other today -> the move that breaks the circle. None since issue
# 36 split the single-user history (doc/linear.rs) from the routing OpLog
# (doc/log.rs): the test fails on any new circle.
KNOWN_FOLDER_CIRCLES: dict[tuple[str, str], str] = {}

Module = tuple[str, ...]

CFG_TEST_MOD = re.compile(r"#\[cfg\(test\)\]\s*(?:#\[[^\]]*\]\s*)*(?:pub(?:\([^)]*\))?\s+)?mod\s+(\w+)\s*;")
CFG_TEST_INLINE = re.compile(r"#\[cfg\(test\)\]\s*(?:#\[[^\]]*\]\s*)*(?:pub(?:\([^)]*\))?\s+)?mod\s+\w+\s*\{")
CFG_TEST_USE = re.compile(r"#\[cfg\(test\)\]\s*(?:pub(?:\([^)]*\))?\s+)?use\b[^;]*;")
PATH_ATTR = re.compile(r'#\[path\s*=\s*"([^"]+)"\]\s*(?:#\[cfg\(test\)\]\s*)?mod\s+(\w+)\s*;')
USE = re.compile(r"\buse\s+([^;]*);")
IN_CODE = re.compile(r"(?<![\w:$])(?:crate|self|super)(?:\s*::\s*\w+)+")


def cfg_test_files(src: Path) -> set[Path]:
    """Files that are only compiled for tests (declared `#[cfg(test)] mod x;`)."""
    out: set[Path] = set()
    for f in src.rglob("*.rs"):
        text = code_only(f.read_text(encoding="utf-8"), strings=False)
        here = f.parent if f.name in ("mod.rs", "lib.rs") else f.with_suffix("")
        for name in CFG_TEST_MOD.findall(text):
            for cand in (here / f"{name}.rs", here / name / "mod.rs"):
                if cand.exists():
                    out.add(cand)
            if (here / name).is_dir():
                out.update((here / name).rglob("*.rs"))
        for rel, _name in PATH_ATTR.findall(text):
            if re.search(r"#\[cfg\(test\)\]\s*#\[path\s*=\s*\"" + re.escape(rel), text):
                cand = (f.parent / rel).resolve()
                if cand.exists():
                    out.add(cand)
    return out


def production_code(f: Path) -> str:
    """The file's code (comments and literals blanked), its inline test
    module and `#[cfg(test)]` imports blanked too; offsets are kept."""
    code = code_only(f.read_text(encoding="utf-8"))
    m = CFG_TEST_INLINE.search(code)
    if m:
        code = code[: m.start()] + re.sub(r"[^\n]", " ", code[m.start() :])
    return CFG_TEST_USE.sub(lambda m: re.sub(r"[^\n]", " ", m.group()), code)


def module_of(rel: Path) -> Module:
    """The module path of a file under src: `a/b/mod.rs` and `a/b.rs` are
    `a::b`, `lib.rs` the crate root."""
    parts = list(rel.with_suffix("").parts)
    if parts[-1] in ("mod", "lib"):
        parts.pop()
    return tuple(parts)


@functools.cache
def children(src: Path, m: Module) -> frozenset[str]:
    """The modules declared under `m`, as files and folders."""
    d = src.joinpath(*m)
    if not d.is_dir():
        return frozenset()
    return frozenset(
        p.stem for p in d.iterdir() if (p.is_dir() or p.suffix == ".rs") and p.stem not in ("mod", "lib")
    )


def module_file(src: Path, m: Module) -> Path | None:
    for f in (src.joinpath(*m).with_suffix(".rs") if m else src / "lib.rs", src.joinpath(*m) / "mod.rs"):
        if f.is_file():
            return f
    return None


def use_paths(tree: str) -> list[tuple[list[str], str | None]]:
    """The paths of a `use` tree with the name each binds:
    `crate::{a, b::{c as d, *}}` -> (crate::a, a), (crate::b::c, d), (crate::b, None)."""
    tree = re.sub(r"\s+", " ", tree).strip()
    out: list[tuple[list[str], str | None]] = []

    def walk(prefix: list[str], t: str) -> None:
        t = t.strip()
        if not t:
            return
        if "{" in t and (t.find("{") < t.find(" as ") or " as " not in t):
            head, body = t[: t.index("{")], t[t.index("{") + 1 : t.rindex("}")]
            base = prefix + [s.strip() for s in head.split("::") if s.strip()]
            depth, start = 0, 0
            for i, c in enumerate(body):
                depth += (c == "{") - (c == "}")
                if c == "," and depth == 0:
                    walk(base, body[start:i])
                    start = i + 1
            walk(base, body[start:])
            return
        path, _, alias = t.partition(" as ")
        segs = prefix + [s.strip() for s in path.split("::") if s.strip()]
        if segs and segs[-1] == "*":
            out.append((segs[:-1], None))
        elif segs and segs[-1] == "self":
            out.append((segs[:-1], alias.strip() or (segs[-2] if len(segs) > 1 else None)))
        elif segs:
            out.append((segs, alias.strip() or segs[-1]))

    walk([], tree)
    return out


def absolute(src: Path, here: Module, segs: list[str], relative_ok: bool) -> Module | None:
    """`segs` named in module `here`, from the crate root; None for another
    crate."""
    if not segs:
        return None
    if segs[0] == "crate":
        return tuple(segs[1:])
    if segs[0] == "self":
        return here + tuple(segs[1:])
    if segs[0] == "super":
        k = 0
        while k < len(segs) and segs[k] == "super":
            k += 1
        return here[: len(here) - k] + tuple(segs[k:])
    if relative_ok and segs[0] in children(src, here):
        return here + tuple(segs)
    return None


class Floors:
    """Who names whom among the modules of one `src` folder."""

    def __init__(self, src: Path):
        self.src = src
        self.skip = cfg_test_files(src)
        self._imports: dict[Module, dict[str, Module]] = {}

    def imports(self, m: Module) -> dict[str, Module]:
        """Name -> absolute path of what module `m` imports or re-exports
        (names a child module may reach as `super::name`)."""
        if m not in self._imports:
            self._imports[m] = {}
            f = module_file(self.src, m)
            if f is not None and f not in self.skip:
                for tree in USE.findall(production_code(f)):
                    for segs, name in use_paths(tree):
                        target = absolute(self.src, m, segs, relative_ok=True)
                        if name and name != "_" and target is not None:
                            self._imports[m][name] = target
        return self._imports[m]

    def sibling_edge(self, here: Module, target: Module) -> tuple[Module, str, str] | None:
        """(parent, a, b) when module `here` names `target` inside sibling
        module b of its own ancestor a, both under `parent`."""
        for _ in range(16):
            n = 0
            while n < min(len(here), len(target)) and here[n] == target[n]:
                n += 1
            if n == len(here) or n == len(target):
                return None
            parent, b = here[:n], target[n]
            if b in children(self.src, parent):
                return parent, here[n], b
            via = self.imports(parent).get(b)
            if via is None or via[: n + 1] == target[: n + 1]:
                return None
            target = via + target[n + 1 :]
        return None

    def edges(self) -> dict[tuple[Module, str, str], set[str]]:
        """(parent, a, b) -> `file:line` of each naming of b in a."""
        found: dict[tuple[Module, str, str], set[str]] = {}
        for f in sorted(self.src.rglob("*.rs")):
            if f in self.skip:
                continue
            rel = f.relative_to(self.src)
            here = module_of(rel)
            code = production_code(f)
            named: list[tuple[int, Module | None]] = []
            for m in USE.finditer(code):
                for segs, _ in use_paths(m.group(1)):
                    named.append((m.start(), absolute(self.src, here, segs, relative_ok=True)))
            code = USE.sub(lambda m: re.sub(r"[^\n]", " ", m.group()), code)
            for m in IN_CODE.finditer(code):
                segs = [s.strip() for s in m.group().split("::")]
                named.append((m.start(), absolute(self.src, here, segs, relative_ok=False)))
            for at, target in named:
                edge = self.sibling_edge(here, target) if target else None
                if edge:
                    line = code.count("\n", 0, at) + 1
                    found.setdefault(edge, set()).add(f"core/src/{rel.as_posix()}:{line}")
        return found


def crossings(found: dict[tuple[Module, str, str], set[str]]) -> dict[tuple[str, str, str], set[str]]:
    """("up", geometry module, doc or interact) -> where."""
    return {
        ("up", a, b): files
        for (parent, a, b), files in found.items()
        if parent == () and a in GEOMETRY and b in ("doc", "interact")
    }


def circles(src: Path, found: dict[tuple[Module, str, str], set[str]]) -> dict[tuple[str, str], list[str]]:
    """(module, module) -> where each names the other, for sibling modules
    that name each other when one of them is a folder."""
    out = {}
    for (parent, a, b), files in found.items():
        back = found.get((parent, b, a))
        if back is None or a > b:
            continue
        if not (src.joinpath(*parent, a).is_dir() or src.joinpath(*parent, b).is_dir()):
            continue
        pa, pb = "/".join(parent + (a,)), "/".join(parent + (b,))
        out[(pa, pb)] = [f"{pa} -> {pb}: {w}" for w in sorted(files)] + [
            f"{pb} -> {pa}: {w}" for w in sorted(back)
        ]
    return out


def host_names(core: Path) -> list[str]:
    """Where core (its Cargo.toml and src) names a host crate."""
    bad = []
    manifest = (core / "Cargo.toml").read_text(encoding="utf-8")
    for host in HOSTS:
        if host.replace("_", "-") in manifest or host in manifest:
            bad.append(f"core/Cargo.toml names {host}")
    for f in sorted((core / "src").rglob("*.rs")):
        text = code_only(f.read_text(encoding="utf-8"), strings=False)
        for host in HOSTS:
            if host in text:
                bad.append(f"core/src/{f.relative_to(core / 'src').as_posix()} names {host}")
    return bad


def test_the_floors_hold_except_the_listed_crossings():
    bad = crossings(Floors(SRC).edges())
    new = {k: sorted(v) for k, v in bad.items() if k not in KNOWN}
    gone = sorted(k for k in KNOWN if k not in bad)
    assert not new, f"new import crossing(s) against docs/ARCHITECTURE.md's floors: {new}"
    assert not gone, f"fixed, so delete from KNOWN in {__file__}: {gone}"


def test_no_new_circle_between_folders():
    found = circles(SRC, Floors(SRC).edges())
    new = [line for k, where in found.items() if k not in KNOWN_FOLDER_CIRCLES for line in where]
    gone = sorted(k for k in KNOWN_FOLDER_CIRCLES if k not in found)
    assert not new, "new import circle(s) between sibling modules:\n" + "\n".join(new)
    assert not gone, f"circle gone, so delete from KNOWN_FOLDER_CIRCLES in {__file__}: {gone}"


def test_core_names_no_host_crate():
    bad = host_names(ROOT / "core")
    assert not bad, "\n".join(bad)


def write(root: Path, files: dict[str, str]) -> None:
    for rel, text in files.items():
        (root / rel).parent.mkdir(parents=True, exist_ok=True)
        (root / rel).write_text(text)


def test_the_reader_sees_a_crossing(tmp_path):
    """The check itself can fail: a geometry file naming the document is caught."""
    write(
        tmp_path,
        {
            "sdf/mod.rs": "mod field;\n#[cfg(test)]\nmod tests;\n",
            "sdf/field.rs": "use crate::{doc::Document, math};\n",
            "sdf/tests.rs": "use crate::interact::Session;\n",
            "doc/mod.rs": "use crate::sdf::Field;\n",
            "math/mod.rs": "",
        },
    )
    found = Floors(tmp_path).edges()
    assert set(crossings(found)) == {("up", "sdf", "doc")}
    assert set(circles(tmp_path, found)) == {("doc", "sdf")}


def test_the_reader_sees_geometry_naming_interact(tmp_path):
    """A geometry module naming `crate::interact`, in a path in code or
    through a name `interact` re-exports, is caught; in a comment, a string
    or an inline test module it is not."""
    write(
        tmp_path,
        {
            "interact/mod.rs": "mod session;\npub use session::Session;\n",
            "interact/session.rs": "pub struct Session;\n",
            "gc/mod.rs": "mod edit;\nmod bend;\n",
            "gc/edit.rs": "fn f() { let _ = crate::interact::session::new(); } // crate::doc\n"
            'const S: &str = "crate::doc";\n',
            "gc/bend.rs": "use super::super::interact::Session;\n"
            "#[cfg(test)]\nmod tests {\n    use crate::doc::X;\n}\n",
            "doc/mod.rs": "",
        },
    )
    found = Floors(tmp_path).edges()
    assert crossings(found) == {("up", "gc", "interact"): {"core/src/gc/edit.rs:1", "core/src/gc/bend.rs:1"}}


def test_the_reader_sees_core_naming_a_host(tmp_path):
    """Core naming a host crate, in its manifest or its code, is caught."""
    write(
        tmp_path,
        {
            "Cargo.toml": '[dependencies]\nshapewright-atomic = { path = "../atomic" }\n',
            "src/lib.rs": "pub mod doc;\n",
            "src/doc/mod.rs": "// shapewright_usd in a comment is fine\nuse shapewright_xr::Host;\n",
        },
    )
    assert host_names(tmp_path) == [
        "core/Cargo.toml names shapewright_atomic",
        "core/src/doc/mod.rs names shapewright_xr",
    ]


def test_the_reader_sees_a_circle_at_any_depth(tmp_path):
    """Sibling folders deep down (`interact/input` and `interact/tools`,
    reached by `crate::`, `super::` and a re-export), and a folder and a
    sibling file (`doc/log.rs` and `doc/shared/`), are circles; two sibling
    files naming each other are not."""
    write(
        tmp_path,
        {
            "interact/mod.rs": "mod input;\nmod tools;\npub use tools::Tool;\n",
            "interact/input/mod.rs": "mod ctl;\n",
            "interact/input/ctl.rs": "use crate::interact::Tool;\n",
            "interact/tools/mod.rs": "mod context;\npub use context::Tool;\n",
            "interact/tools/context.rs": "pub trait Tool {}\nuse super::super::{input::ctl};\n",
            "doc/mod.rs": "mod log;\nmod shared;\nmod object;\nmod document;\n",
            "doc/log.rs": "use super::shared::Replica;\n",
            "doc/shared/mod.rs": "fn f() { crate::doc::log::apply(); }\n",
            "doc/object.rs": "use super::document::Document;\n",
            "doc/document.rs": "use super::object::Object;\n",
        },
    )
    assert circles(tmp_path, Floors(tmp_path).edges()) == {
        ("interact/input", "interact/tools"): [
            "interact/input -> interact/tools: core/src/interact/input/ctl.rs:1",
            "interact/tools -> interact/input: core/src/interact/tools/context.rs:2",
        ],
        ("doc/log", "doc/shared"): [
            "doc/log -> doc/shared: core/src/doc/log.rs:1",
            "doc/shared -> doc/log: core/src/doc/shared/mod.rs:1",
        ],
    }
