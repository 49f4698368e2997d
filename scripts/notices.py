#!/usr/bin/env python3
"""Third-party notices for one release artifact, generated from `cargo metadata`.

    scripts/notices.py --package shapewright-py --target x86_64-pc-windows-gnu \
        [--target ...] [--extra FILE:TITLE ...] --out NOTICES.txt

Lists every crate compiled into the artifact (the package's normal
dependencies, followed transitively, on each given target; build scripts and
dev-dependencies are not shipped) with its version, licence expression and
source, then the licence texts themselves: each crate's own LICENSE/COPYING/
NOTICE files, identical texts printed once with the crates that carry them.
Crates that ship no licence file get the licence's standard text named by
their expression (from Debian's common-licenses where it exists) and are
flagged, so a missing copyright line is visible rather than silent.

Why not `cargo about`: it is not installed here and compiles for minutes
from a fresh clone; this reads the same metadata with the Python standard
library only and runs in about a second.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LICENSE_NAME = re.compile(r"^(licen[cs]e|copying|notice|copyright|authors)([-_.].*)?$", re.IGNORECASE)
COMMON = Path("/usr/share/common-licenses")
# Crates that compile C or C++ sources of another project into the binary:
# that project's licence files, inside the crate.
BUNDLED = {
    "openxr-sys": ["OpenXR-SDK/LICENSE", "OpenXR-SDK/src/external/jsoncpp/LICENSE"],
    "libmimalloc-sys": ["c_src/mimalloc/v3/LICENSE"],
}


def metadata(target: str) -> dict:
    out = subprocess.run(
        ["cargo", "metadata", "--format-version", "1", "--locked", "--filter-platform", target],
        cwd=ROOT,
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    return json.loads(out)


def shipped(meta: dict, package: str) -> set[str]:
    """Package ids reached from `package` through normal (non-build, non-dev) edges."""
    by_id = {p["id"]: p for p in meta["packages"]}
    roots = [
        p["id"] for p in meta["packages"] if p["name"] == package and p["id"] in meta["workspace_members"]
    ]
    if not roots:
        raise SystemExit(f"notices: no workspace package named {package!r}")
    nodes = {n["id"]: n for n in meta["resolve"]["nodes"]}
    seen: set[str] = set()
    todo = list(roots)
    while todo:
        pid = todo.pop()
        if pid in seen:
            continue
        seen.add(pid)
        for dep in nodes[pid]["deps"]:
            if any(k["kind"] is None for k in dep["dep_kinds"]) and dep["pkg"] in by_id:
                todo.append(dep["pkg"])
    return seen


def licence_files(pkg: dict) -> list[Path]:
    crate_dir = Path(pkg["manifest_path"]).parent
    files = [p for p in sorted(crate_dir.iterdir()) if p.is_file() and LICENSE_NAME.match(p.name)]
    if pkg.get("license_file"):
        lf = crate_dir / pkg["license_file"]
        if lf.is_file() and lf not in files:
            files.append(lf)
    files += [crate_dir / f for f in BUNDLED.get(pkg["name"], []) if (crate_dir / f).is_file()]
    # A LICENSES/ folder (REUSE layout).
    sub = crate_dir / "LICENSES"
    if sub.is_dir():
        files += sorted(p for p in sub.iterdir() if p.is_file())
    return files


def standard_text(pkg: dict) -> list[tuple[str, str]]:
    """Standard texts for the SPDX ids in a crate's licence expression; MIT's
    (which Debian does not keep) with the crate's authors as its copyright line."""
    out = []
    expr = pkg.get("license") or ""
    for spdx in sorted(set(re.findall(r"[A-Za-z0-9.\-+]+", expr)) - {"OR", "AND", "WITH"}):
        f = COMMON / spdx
        if f.is_file():
            out.append((spdx, f.read_text(errors="replace")))
        elif spdx == "MIT":
            mit = (ROOT / "LICENSE-MIT").read_text().split("\n", 3)[3]
            who = ", ".join(pkg.get("authors") or []) or f"the {pkg['name']} authors"
            out.append((spdx, f"MIT License\n\nCopyright (c) {who}\n{mit}"))
    return out


def same_text(text: str) -> str:
    """Key that treats texts differing only in whitespace as one."""
    return hashlib.sha256(" ".join(text.split()).encode()).hexdigest()


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument(
        "--package", required=True, action="append", help="workspace package shipped (repeatable)"
    )
    ap.add_argument("--target", required=True, action="append", help="target triple (repeatable)")
    ap.add_argument("--title", default="Shapewright", help="what the notices are for")
    ap.add_argument("--extra", action="append", default=[], help="FILE:TITLE of a bundled non-crate work")
    ap.add_argument("--out", required=True)
    args = ap.parse_args()

    pkgs: dict[str, dict] = {}
    for target in args.target:
        meta = metadata(target)
        by_id = {p["id"]: p for p in meta["packages"]}
        for package in args.package:
            for pid in shipped(meta, package):
                pkgs[pid] = by_id[pid]
    ours = {p["name"] for p in pkgs.values() if p["source"] is None}
    crates = sorted(
        (p for p in pkgs.values() if p["source"] is not None), key=lambda p: (p["name"], p["version"])
    )

    texts: dict[str, tuple[str, str, list[str]]] = {}
    no_file: list[str] = []
    lines = [
        f"Third-party notices for {args.title}",
        f"Targets: {', '.join(args.target)}. Generated by scripts/notices.py from `cargo metadata`.",
        "",
        "Shapewright itself (" + ", ".join(sorted(ours)) + ") is licensed MIT OR Apache-2.0 (LICENSE-MIT,",
        "LICENSE-APACHE); the Blender add-on's Python code is GPL-3.0-or-later (its LICENSE).",
        "",
        f"== {len(crates)} crates compiled into this artifact",
        "",
    ]
    for p in crates:
        key = f"{p['name']} {p['version']}"
        src = p.get("repository") or p["source"]
        lines.append(f"{key:<40} {p.get('license') or '(no licence field)'}  <{src}>")
        files = licence_files(p)
        if not files:
            no_file.append(key)
            for spdx, text in standard_text(p):
                h = same_text(text)
                texts.setdefault(h, (f"{spdx} (standard text)", text, []))[2].append(key)
        for f in files:
            text = f.read_text(errors="replace")
            h = same_text(text)
            texts.setdefault(h, (f.name, text, []))[2].append(key)
    lines.append("")
    if no_file:
        lines.append(
            "Crates whose package carries no licence file (the standard text of their licence is given):"
        )
        lines += [f"  {k}" for k in no_file]
        lines.append("")

    for extra in args.extra:
        path, _, title = extra.partition(":")
        lines += [
            "",
            "=" * 78,
            f"== {title or path}",
            "=" * 78,
            "",
            Path(path).read_text(errors="replace").rstrip(),
            "",
        ]

    lines += ["", f"== Licence texts ({len(texts)} distinct)", ""]
    for name, text, users in sorted(texts.values(), key=lambda t: (t[2][0], t[0])):
        lines += ["=" * 78, f"{name}, used by: {', '.join(sorted(set(users)))}", "=" * 78, ""]
        lines += [text.rstrip(), ""]
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text("\n".join(lines) + "\n", encoding="utf-8")
    counts = f"{len(crates)} crates, {len(texts)} licence texts, {len(no_file)} without a file"
    print(f"notices: {counts} -> {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
