"""Rust source read as text, for the house tests (test_house.py,
test_layering.py): comments and literals blanked so that a brace, a `//`
or a `crate::doc` inside a string or a comment is not read as code."""

from __future__ import annotations

import re

TOKEN = re.compile(r"""//[^\n]*|/\*|(?<!\w)b?r(#*)"|"|'(?:\\u\{[0-9a-fA-F]+\}|\\.|[^\\'\n])'""")
STRING_REST = re.compile(r'(?:\\.|[^"\\])*"?', re.S)
BLOCK = re.compile(r"/\*|\*/")


def blank(s: str) -> str:
    """`s` as spaces, its newlines kept."""
    return re.sub(r"[^\n]", " ", s)


def code_only(text: str, strings: bool = True) -> str:
    """`text` with comments blanked, and (with `strings`) the insides of
    string and char literals too; the length and the newlines are kept, so
    offsets and line numbers hold."""
    out, i = [], 0
    while m := TOKEN.search(text, i):
        out.append(text[i : m.start()])
        tok, i = m.group(), m.end()
        if tok.startswith("//"):
            out.append(blank(tok))
        elif tok == "/*":
            depth = 1
            for b in BLOCK.finditer(text, i):
                depth += 1 if b.group() == "/*" else -1
                i = b.end()
                if depth == 0:
                    break
            else:
                i = len(text)
            out.append(blank(text[m.start() : i]))
        elif tok.endswith('"'):
            if tok == '"':
                end = STRING_REST.match(text, i).end()
                close = 1 if text[end - 1 : end] == '"' and end > i else 0
            else:
                close = len(m.group(1)) + 1
                found = text.find('"' + m.group(1), i)
                end = len(text) if found < 0 else found + close
                close = close if found >= 0 else 0
            inside = text[i : end - close]
            out.append(tok + (blank(inside) if strings else inside) + text[end - close : end])
            i = end
        else:
            out.append("'" + blank(tok[1:-1]) + "'" if strings else tok)
    out.append(text[i:])
    return "".join(out)
