"""The floors of docs/ARCHITECTURE.md, read from the code (issue 36).

Reads every production `.rs` file of `core/src` (test modules left out: a
file declared under `#[cfg(test)]`, and an inline `#[cfg(test)] mod` block
to its end) and collects which top-level folder names which (`crate::x`,
`use crate::{x, ..}`, `super::super::x` is not used in core). Three rules:

- a geometry module (math, nurbs, sketch, solid, gc, assembly, sdf,
  styling, sculpt, mesh, print) never names `crate::doc` or
  `crate::interact`;
- `core` never names a host or transport crate (`shapewright_xr`,
  `shapewright_py`, `shapewright_net`, `shapewright_usd`), in code or in
  its Cargo.toml;
- no import circle between two folders.

`KNOWN` lists the crossings that exist today with the change that removes
each. It is a ratchet, not an allowance: the test fails when a new crossing
appears and also when a listed one is gone (then delete its line), so the
list can only shrink.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

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
HOSTS = ("shapewright_xr", "shapewright_py", "shapewright_net", "shapewright_usd")

# (kind, from, to) -> why it is still here and what removes it.
KNOWN: dict[tuple[str, str, str], str] = {}

CFG_TEST_MOD = re.compile(r"#\[cfg\(test\)\]\s*(?:#\[[^\]]*\]\s*)*(?:pub(?:\([^)]*\))?\s+)?mod\s+(\w+)\s*;")
CFG_TEST_INLINE = re.compile(r"#\[cfg\(test\)\]\s*(?:#\[[^\]]*\]\s*)*(?:pub(?:\([^)]*\))?\s+)?mod\s+\w+\s*\{")
PATH_ATTR = re.compile(r'#\[path\s*=\s*"([^"]+)"\]\s*(?:#\[cfg\(test\)\]\s*)?mod\s+(\w+)\s*;')
CRATE_PATH = re.compile(r"\bcrate::(\w+)")
USE_GROUP = re.compile(r"\buse\s+crate::\{([^;]*)\};", re.S)


def strip_comments(text: str) -> str:
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    return re.sub(r"//[^\n]*", "", text)


def cfg_test_files() -> set[Path]:
    """Files that are only compiled for tests (declared `#[cfg(test)] mod x;`)."""
    out: set[Path] = set()
    for f in SRC.rglob("*.rs"):
        text = strip_comments(f.read_text(encoding="utf-8"))
        here = f.parent if f.name in ("mod.rs", "lib.rs") else f.with_suffix("")
        for name in CFG_TEST_MOD.findall(text):
            for cand in (here / f"{name}.rs", here / name / "mod.rs"):
                if cand.exists():
                    out.add(cand)
            if (here / name).is_dir():
                out.update((here / name).rglob("*.rs"))
        for rel, _name in PATH_ATTR.findall(text):
            if "cfg(test)" in text:
                cand = (f.parent / rel).resolve()
                if cand.exists() and re.search(r"#\[cfg\(test\)\]\s*#\[path\s*=\s*\"" + re.escape(rel), text):
                    out.add(cand)
    return out


def production_text(f: Path) -> str:
    text = strip_comments(f.read_text(encoding="utf-8"))
    m = CFG_TEST_INLINE.search(text)
    return text[: m.start()] if m else text


def edges() -> dict[tuple[str, str], set[str]]:
    skip = cfg_test_files()
    found: dict[tuple[str, str], set[str]] = {}
    for f in sorted(SRC.rglob("*.rs")):
        if f in skip:
            continue
        rel = f.relative_to(SRC)
        top = rel.parts[0].removesuffix(".rs")
        text = production_text(f)
        names = set(CRATE_PATH.findall(text))
        for group in USE_GROUP.findall(text):
            for part in group.split(","):
                head = re.split(r"::|\s|\{", part.strip())[0]
                if head:
                    names.add(head)
        for name in names:
            if name != top and (SRC / name).is_dir():
                found.setdefault((top, name), set()).add(str(rel))
    return found


def crossings(found: dict[tuple[str, str], set[str]]) -> dict[tuple[str, ...], set[str]]:
    bad = {}
    for (a, b), files in found.items():
        if a in GEOMETRY and b in ("doc", "interact"):
            bad[("up", a, b)] = files
        if (b, a) in found and a < b:
            bad[("circle", a, b)] = files | found[(b, a)]
    return bad


def test_the_floors_hold_except_the_listed_crossings():
    bad = crossings(edges())
    new = {k: sorted(v) for k, v in bad.items() if k not in KNOWN}
    gone = sorted(k for k in KNOWN if k not in bad)
    assert not new, f"new import crossing(s) against docs/ARCHITECTURE.md's floors: {new}"
    assert not gone, f"fixed, so delete from KNOWN in {__file__}: {gone}"


def test_core_names_no_host_crate():
    manifest = (ROOT / "core" / "Cargo.toml").read_text(encoding="utf-8")
    for host in HOSTS:
        assert host.replace("_", "-") not in manifest, host
    for f in SRC.rglob("*.rs"):
        text = strip_comments(f.read_text(encoding="utf-8"))
        for host in HOSTS:
            assert host not in text, f"{f.relative_to(ROOT)} names {host}"


def test_the_reader_sees_a_crossing(tmp_path, monkeypatch):
    """The check itself can fail: a geometry file naming the document is caught."""
    fake = tmp_path / "src"
    (fake / "sdf").mkdir(parents=True)
    (fake / "doc").mkdir()
    (fake / "sdf" / "mod.rs").write_text("mod field;\n#[cfg(test)]\nmod tests;\n")
    (fake / "sdf" / "field.rs").write_text("use crate::{doc::Document, math};\n")
    (fake / "sdf" / "tests.rs").write_text("use crate::interact::Session;\n")
    (fake / "doc" / "mod.rs").write_text("use crate::sdf::Field;\n")
    monkeypatch.setattr(sys.modules[__name__], "SRC", fake)
    bad = crossings(edges())
    assert set(bad) == {("up", "sdf", "doc"), ("circle", "doc", "sdf")}
