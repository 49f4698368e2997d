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
  (one naming convention; `tests_<topic>.rs` was the other).

Function length is read from rustfmt's layout: a `fn` line and the next
line holding only its indentation and `}`.
"""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
CRATES = ("core/src", "xr_host/src", "net/src", "usd/src", "atomic/src", "blender_addon/native/src")
MAX_FILE = 800
MAX_FN = 150
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
