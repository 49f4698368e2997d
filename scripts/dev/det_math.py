#!/usr/bin/env python3
"""Rewrites std transcendental float calls to their deterministic twins
(issue 32, core/src/math/fm.rs):

    python3 scripts/dev/det_math.py [--check] [--skip FILE]... [PATH]...

`x.sin()` becomes `x.fsin()`, `f64::atan2` becomes `f64::fatan2`, and so
on for every method of `DetMath`; each module that gains a call gets
`use crate::math::fm::DetMath as _;` (in the core's own sources) or
`use shapewright::math::fm::DetMath as _;` (everywhere else). PATHs are
files or directories (default: every workspace crate); comments, strings
and character literals are left alone; running it twice changes nothing.
`--check` rewrites nothing and exits 1 when something would change.

The rewrite is by name, not by type: a method of the same name on a
non-float type (glam's `DVec3::powf`, say) would be renamed too and fail
to compile, which is the signal to look. `log` is not rewritten (the
workspace's `.log()` are the op log; clippy flags a float `log(base)`).
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
CRATES = ["core", "usd", "atomic", "net", "xr_host", "blender_addon/native"]
# The module itself calls std on purpose (its tests compare against it).
ALWAYS_SKIP = {ROOT / "core/src/math/fm.rs"}
NAMES = {
    "sin", "cos", "tan", "sin_cos", "asin", "acos", "atan", "atan2",
    "sinh", "cosh", "tanh", "asinh", "acosh", "atanh",
    "exp", "exp2", "exp_m1", "ln", "ln_1p", "log2", "log10",
    "powf", "powi", "cbrt", "hypot",
}  # fmt: skip
TRAIT = "math::fm::DetMath"


def code_mask(src: str) -> list[bool]:
    """True for each character of code (not comment, string or char literal)."""
    mask = [True] * len(src)
    i, n = 0, len(src)

    def blank(a: int, b: int) -> None:
        for k in range(a, min(b, n)):
            mask[k] = False

    while i < n:
        c = src[i]
        if src.startswith("//", i):
            j = src.find("\n", i)
            j = n if j < 0 else j
            blank(i, j)
            i = j
        elif src.startswith("/*", i):
            depth, j = 1, i + 2
            while j < n and depth:
                if src.startswith("/*", j):
                    depth, j = depth + 1, j + 2
                elif src.startswith("*/", j):
                    depth, j = depth - 1, j + 2
                else:
                    j += 1
            blank(i, j)
            i = j
        elif m := re.compile(r'b?r(#*)"').match(src, i):
            if i > 0 and (src[i - 1].isalnum() or src[i - 1] == "_"):
                i += 1
                continue
            end = '"' + m.group(1)
            j = src.find(end, m.end())
            j = n if j < 0 else j + len(end)
            blank(i, j)
            i = j
        elif c == '"':
            j = i + 1
            while j < n and src[j] != '"':
                j += 2 if src[j] == "\\" else 1
            blank(i, j + 1)
            i = j + 1
        elif c == "'":
            # A char literal ('a', '\n', '\u{..}'), not a lifetime ('a).
            m = re.compile(r"'(\\u\{[0-9a-fA-F]+\}|\\.|[^\\'])'").match(src, i)
            if m:
                blank(i, m.end())
                i = m.end()
            else:
                i += 1
        else:
            i += 1
    return mask


CALL = re.compile(r"(\.\s*|\b(?:f64|f32)\s*::\s*)(" + "|".join(sorted(NAMES, key=len, reverse=True)) + r")\b")
MOD_OPEN = re.compile(r"\bmod\s+[A-Za-z_][A-Za-z0-9_]*\s*\{")


def rewrite(src: str, crate_path: str) -> str:
    mask = code_mask(src)
    hits = []
    for m in CALL.finditer(src):
        if not mask[m.start()]:
            continue
        # A method call or a path (`f64::sin` as a function value); not a
        # field (`.sin` followed by something other than `(` or `::<`).
        after = src[m.end() :].lstrip()
        if m.group(1).startswith(".") and not (after.startswith("(") or after.startswith("::<")):
            continue
        hits.append(m.start(2))
    if not hits:
        return src

    # Module scopes: the file, and each inline `mod name { ... }`.
    scopes = []  # (open brace index or -1, close index)
    stack: list[tuple[int, bool]] = []
    for i, c in enumerate(src):
        if not mask[i]:
            continue
        if c == "{":
            m = None
            for mm in MOD_OPEN.finditer(src, max(0, i - 200), i + 1):
                if mm.end() == i + 1 and mask[mm.start()]:
                    m = mm
            stack.append((i, m is not None))
        elif c == "}" and stack:
            start, is_mod = stack.pop()
            if is_mod:
                scopes.append((start, i))

    def scope_of(pos: int) -> int:
        inner = [s for s in scopes if s[0] < pos < s[1]]
        return max(inner)[0] if inner else -1

    need = {scope_of(h) for h in hits}
    # A module that glob-imports its parent (`use super::*;`) sees the
    # parent's import; its own would be unused.
    line = f"use {crate_path}::{TRAIT} as _;"
    imported = set(need)
    if line in src.split("\n"):
        imported.add(-1)
    for start in sorted(need):
        if start < 0:
            continue
        end = next(e for b, e in scopes if b == start)
        if scope_of(start) in imported and re.search(r"\buse\s+super::\*;", src[start:end]):
            need.discard(start)
    out = src
    # Rename from the end so earlier offsets stay valid.
    for h in sorted(hits, reverse=True):
        out = out[:h] + "f" + out[h:]
    # Imports, from the last scope to the first (offsets in `out` shift by
    # one per renamed call before them).
    for start in sorted(need, reverse=True):
        shift = sum(1 for h in hits if h < start)
        if start < 0:
            out = insert_file_use(out, line)
        else:
            at = start + shift + 1
            body_end = find_close(out, at - 1)
            if re.search(re.escape(line), out[at:body_end]):
                continue
            indent = " " * (indent_of(out, start + shift) + 4)
            # After the module's inner docs and attributes (`//!`, `#![..]`).
            while True:
                nl = out.find("\n", at)
                nxt = out[nl + 1 : out.find("\n", nl + 1)].strip() if nl >= 0 else ""
                if nl >= 0 and (nxt.startswith("//!") or nxt.startswith("#![")):
                    at = out.find("\n", nl + 1)
                else:
                    break
            out = out[:at] + "\n" + indent + line + out[at:]
    return out


def indent_of(src: str, pos: int) -> int:
    bol = src.rfind("\n", 0, pos) + 1
    return len(src[bol:pos]) - len(src[bol:pos].lstrip(" "))


def find_close(src: str, open_at: int) -> int:
    mask = code_mask(src)
    depth = 0
    for i in range(open_at, len(src)):
        if not mask[i]:
            continue
        if src[i] == "{":
            depth += 1
        elif src[i] == "}":
            depth -= 1
            if depth == 0:
                return i
    return len(src)


def insert_file_use(src: str, line: str) -> str:
    lines = src.split("\n")
    # Already imported at file level (an unindented line).
    if line in lines:
        return src
    # Before the first top-level `use`, so rustfmt sorts it into that group.
    for k, text in enumerate(lines):
        if text.startswith("use ") or text.startswith("pub use "):
            # Above the attributes and docs of that `use`, which would
            # otherwise apply to ours.
            while k > 0 and (lines[k - 1].startswith("#[") or lines[k - 1].startswith("///")):
                k -= 1
            lines.insert(k, line)
            return "\n".join(lines)
    # No imports: after the inner docs and attributes.
    k = 0
    while k < len(lines) and (
        lines[k].startswith("//!") or lines[k].startswith("#![") or not lines[k].strip()
    ):
        k += 1
    lines[k:k] = [line, ""]
    return "\n".join(lines)


def rust_files(paths: list[Path]) -> list[Path]:
    files: list[Path] = []
    for p in paths:
        if p.is_dir():
            files += sorted(q for q in p.rglob("*.rs") if "target" not in q.relative_to(ROOT).parts)
        else:
            files.append(p)
    return files


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("paths", nargs="*", type=Path)
    ap.add_argument("--skip", action="append", default=[], type=Path, help="a file or folder to leave alone")
    ap.add_argument("--check", action="store_true", help="report, rewrite nothing")
    args = ap.parse_args()
    paths = [p.resolve() for p in args.paths] or [ROOT / c for c in CRATES]
    skip = {p.resolve() for p in args.skip} | ALWAYS_SKIP
    changed = []
    for f in rust_files(paths):
        if any(f.resolve() == s or s in f.resolve().parents for s in skip):
            continue
        rel = f.resolve().relative_to(ROOT)
        crate_path = "crate" if rel.parts[:2] == ("core", "src") else "shapewright"
        src = f.read_text()
        new = rewrite(src, crate_path)
        if new != src:
            changed.append(rel)
            if not args.check:
                f.write_text(new)
    for rel in changed:
        print(("would rewrite " if args.check else "rewrote ") + str(rel))
    return 1 if args.check and changed else 0


if __name__ == "__main__":
    sys.exit(main())
