"""One idea per file, kept true (issue 36; docs/ARCHITECTURE.md).

Reads every production `.rs` file of the Rust crates (the test runtime
`testrt/`, the `testkit/` puppets, files named `tests.rs` or `*_tests.rs`,
and an inline `#[cfg(test)] mod` block to its end are test code and left
out) and checks:

- no file over 800 lines, unless its module doc says why in a line
  starting `Long file:`;
- no function over 150 lines, unless its module doc names it in a line
  `Long function: `name``;
- unit tests split out of a module live in `tests.rs` or `<topic>_tests.rs`
  (one naming convention; `tests_<topic>.rs` was the other);
- a `mod.rs` (test folders' too) holds module declarations (`mod x;`,
  `pub mod x;`, `pub(crate) mod x;`, with their `#[cfg(..)]`/`#[path]`
  attributes), `use`/`pub use` re-exports, inner attributes (`#![..]`) and
  comments, nothing else: the content lives in a file named for it, so a
  type or trait is found by file name. `TABLES` names the one exception;
  `KNOWN_CONTENT_MOD_RS` is a ratchet like test_layering.py's `KNOWN`.

Function length is read from rustfmt's layout: a `fn` line and the next
line holding only its indentation and `}`.
"""

from __future__ import annotations

import re
from pathlib import Path

from rustsrc import code_only

ROOT = Path(__file__).resolve().parents[2]
CRATES = ("core/src", "xr_host/src", "net/src", "usd/src", "atomic/src", "blender_addon/native/src")
MAX_FILE = 800
MAX_FN = 150
# A mod.rs may hold this table by name: every op declared once (the enum,
# names, kinds and dispatch from one line per op), which cannot be split.
TABLES = {"core/src/doc/ops/mod.rs": re.compile(r"macro_rules!\s*ops\b|ops!\s*\{")}
# mod.rs files that hold content today -> the move that empties each (issue
# 36). None since issue 36 moved the content out (interact/input/ was 984
# lines); the test fails on a new one, and on a listed one that is gone.
KNOWN_CONTENT_MOD_RS: dict[str, str] = {}
FN = re.compile(r"^(\s*)(?:pub(?:\([^)]*\))?\s+)?(?:(?:const|async|unsafe|extern \"C\")\s+)*fn\s+(\w+)")
CFG_TEST_INLINE = re.compile(r"^#\[cfg\(test\)\]\s*$")


def is_test_file(path: Path) -> bool:
    parts = set(path.parts)
    return (
        bool(parts & {"testrt", "testkit", "tests"})
        or path.name == "tests.rs"
        or path.name.endswith("_tests.rs")
    )


def production_lines(path: Path) -> list[str]:
    lines = path.read_text(encoding="utf-8").split("\n")
    for i, line in enumerate(lines[:-1]):
        if CFG_TEST_INLINE.match(line) and re.match(r"(?:pub(?:\([^)]*\))?\s+)?mod \w+ \{", lines[i + 1]):
            return lines[:i]
    return lines


def module_doc(lines: list[str]) -> str:
    return "\n".join(line for line in lines if line.startswith("//!"))


def long_functions(lines: list[str]) -> list[tuple[str, int]]:
    out = []
    for i, line in enumerate(lines):
        m = FN.match(line)
        if not m or line.rstrip().endswith(";"):
            continue
        close = m.group(1) + "}"
        for j in range(i + 1, len(lines)):
            if lines[j] == close:
                if j - i + 1 > MAX_FN:
                    out.append((m.group(2), j - i + 1))
                break
    return out


def findings(root: Path) -> list[str]:
    bad = []
    for crate in CRATES:
        for f in sorted((root / crate).rglob("*.rs")):
            rel = f.relative_to(root)
            if f.name.startswith("tests_"):
                bad.append(f"{rel}: test files are named `<topic>_tests.rs`")
            if is_test_file(rel):
                continue
            lines = production_lines(f)
            doc = module_doc(lines)
            if len(lines) > MAX_FILE and "//! Long file:" not in doc:
                bad.append(f"{rel}: {len(lines)} lines (over {MAX_FILE}; split it along its ideas)")
            for name, n in long_functions(lines):
                if f"Long function: `{name}`" not in doc:
                    bad.append(f"{rel}: fn {name} is {n} lines (over {MAX_FN})")
    return bad


OPEN, CLOSE = "([{", ")]}"
VIS = r"(?:pub(?:\s*\([^)]*\))?\s+)?"
DECLARATION = re.compile(VIS + r"(?:mod\s+\w+\s*;|use\b)")


def item_end(code: str, i: int, braces_end: bool) -> int:
    """The end of the item starting at `i`: its `;` at depth 0, or (when
    `braces_end`) the `}` closing its first top-level `{`."""
    depth = 0
    for j in range(i, len(code)):
        if code[j] in OPEN:
            depth += 1
        elif code[j] in CLOSE:
            depth -= 1
            if depth == 0 and code[j] == "}" and braces_end:
                return j + 1
        elif code[j] == ";" and depth == 0:
            return j + 1
    return len(code)


def bracket_end(code: str, i: int) -> int:
    """The index after the `]` closing the attribute `#[` or `#![` at `i`."""
    depth = 0
    for k in range(code.index("[", i), len(code)):
        depth += (code[k] in OPEN) - (code[k] in CLOSE)
        if depth == 0:
            return k + 1
    return len(code)


def mod_rs_content(text: str, table: re.Pattern[str] | None = None) -> list[tuple[int, int, str]]:
    """(first line, line count, first line's text) of each item of a
    `mod.rs` that is not a module declaration, a `use`, an inner attribute
    or a comment (`table` aside). An outer attribute goes with the item it
    is on: `#[cfg(test)] mod tests;` is a declaration, `#[cfg(test)] mod
    tests { .. }` and `#[derive(..)] struct` are content."""
    code = code_only(text)
    src = text.split("\n")
    out = []
    i, attrs = 0, None
    while True:
        while i < len(code) and code[i].isspace():
            i += 1
        if i >= len(code):
            return out
        if code.startswith("#", i):
            if attrs is None and not code.startswith("#!", i):
                attrs = i
            i = bracket_end(code, i)
            continue
        start = i if attrs is None else attrs
        declaration = DECLARATION.match(code, i)
        end = item_end(code, i, braces_end=not declaration)
        if not (declaration or (table and table.match(code, i))):
            line = code.count("\n", 0, start) + 1
            out.append((line, code.count("\n", start, end) + 1, src[line - 1].strip()))
        i, attrs = end, None


def content_mod_rs(root: Path) -> dict[str, list[str]]:
    """mod.rs path -> its items that are content."""
    out = {}
    for crate in CRATES:
        for f in sorted((root / crate).rglob("mod.rs")):
            rel = f.relative_to(root).as_posix()
            items = mod_rs_content(f.read_text(encoding="utf-8"), TABLES.get(rel))
            if items:
                out[rel] = [f"{rel}:{line}: `{text}` ({n} lines)" for line, n, text in items]
    return out


def test_one_idea_per_file():
    bad = findings(ROOT)
    assert not bad, "\n".join(bad)


def test_the_reader_sees_a_long_function_and_a_stray_test_name(tmp_path):
    """The check itself can fail."""
    src = tmp_path / "core" / "src"
    src.mkdir(parents=True)
    body = "\n".join(["    let x = 1;"] * 150)
    (src / "long.rs").write_text(f"//! A module.\n\npub fn long() {{\n{body}\n}}\n\nfn short() {{\n}}\n")
    (src / "tests_topic.rs").write_text("")
    (src / "ok_tests.rs").write_text(f"fn long_test() {{\n{body}\n}}\n")
    (src / "excused.rs").write_text(f"//! Long function: `long`: a table.\n\nfn long() {{\n{body}\n}}\n")
    bad = findings(tmp_path)
    assert bad == [
        "core/src/long.rs: fn long is 152 lines (over 150)",
        "core/src/tests_topic.rs: test files are named `<topic>_tests.rs`",
    ], bad


def test_a_mod_rs_declares_and_re_exports():
    found = content_mod_rs(ROOT)
    new = [item for rel, items in found.items() if rel not in KNOWN_CONTENT_MOD_RS for item in items]
    gone = sorted(rel for rel in KNOWN_CONTENT_MOD_RS if rel not in found)
    assert not new, "content in a mod.rs (move it into a file named for it):\n" + "\n".join(new)
    assert not gone, f"emptied, so delete from KNOWN_CONTENT_MOD_RS in {__file__}: {gone}"


def test_the_reader_sees_content_in_a_mod_rs(tmp_path):
    """The check itself can fail: items other than declarations, re-exports
    and the named table are caught; comments and strings do not fool it."""
    clean = """//! A folder.
#![allow(clippy::module_inception)]

/// The part.
#[cfg(test)]
#[path = "x{.rs"]
pub(crate) mod part; // fn not_an_item() {}
pub mod other;
/* struct Hidden; */
pub use part::{Part, deep::{A, B}};
use other as _;
"""
    content = """mod part;
pub use part::Part;

#[derive(Debug)]
pub struct Sanitizer {
    seen: u32,
}

const BRACE: char = '}';
fn open() -> &'static str { "{" }

#[cfg(test)]
mod tests {
    fn a() {}
}
"""
    table = """mod apply;

macro_rules! ops {
    ($($name:literal => $v:ident,)*) => { pub enum Op { $($v,)* } };
}

ops! {
    "add_solid" => AddSolid,
}

pub fn helper() {}
"""
    for rel, text in [
        ("core/src/clean/mod.rs", clean),
        ("xr_host/src/content/mod.rs", content),
        ("core/src/doc/ops/mod.rs", table),
        ("core/src/ops_elsewhere/mod.rs", table),
    ]:
        (tmp_path / rel).parent.mkdir(parents=True)
        (tmp_path / rel).write_text(text)
    found = content_mod_rs(tmp_path)
    assert found == {
        "core/src/doc/ops/mod.rs": ["core/src/doc/ops/mod.rs:11: `pub fn helper() {}` (1 lines)"],
        "core/src/ops_elsewhere/mod.rs": [
            "core/src/ops_elsewhere/mod.rs:3: `macro_rules! ops {` (3 lines)",
            "core/src/ops_elsewhere/mod.rs:7: `ops! {` (3 lines)",
            "core/src/ops_elsewhere/mod.rs:11: `pub fn helper() {}` (1 lines)",
        ],
        "xr_host/src/content/mod.rs": [
            "xr_host/src/content/mod.rs:4: `#[derive(Debug)]` (4 lines)",
            "xr_host/src/content/mod.rs:9: `const BRACE: char = '}';` (1 lines)",
            'xr_host/src/content/mod.rs:10: `fn open() -> &\'static str { "{" }` (1 lines)',
            "xr_host/src/content/mod.rs:12: `#[cfg(test)]` (4 lines)",
        ],
    }, found
