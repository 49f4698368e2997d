#!/usr/bin/env python3
"""Keeps the build-time-only dependencies out of the dev profile's
`opt-level = 3` (CI time):

    python3 scripts/dev/host_deps.py [--check]

Cargo.toml optimizes every dependency in the dev profile
(`[profile.dev.package."*"]`): the geometry the tests run is theirs. Cargo
applies that override to proc macros and build scripts' helpers too (it
takes precedence over `build-override`), so `syn`, `serde_derive` and
their kind were compiled at opt-level 3: 56 units, 35% of the unit time
of a cold `cargo test --workspace --no-run` here (1,146 of 3,294 s,
2026-12-02), and most of a cold `cargo clippy`, which compiles nothing
else in full. Their speed matters only while compiling.

This lists every package that is built only for the build (reached from
the workspace only through a build dependency or a proc macro) and writes
`name = { opt-level = 0 }` for each into the marked block of Cargo.toml;
a package also linked into a workspace target stays optimized. With
`--check` it writes nothing and exits 1 when the block is out of date (a
dependency added or dropped): the house test runs that.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
CARGO_TOML = ROOT / "Cargo.toml"
BEGIN = "# host-only dependencies: begin (scripts/dev/host_deps.py writes this block)"
END = "# host-only dependencies: end"


def host_only() -> list[str]:
    """The names of the packages the workspace uses only at build time."""
    out = subprocess.run(
        ["cargo", "metadata", "--format-version", "1", "--locked", "-q"],
        cwd=ROOT,
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    meta = json.loads(out)
    packages = {p["id"]: p for p in meta["packages"]}
    members = set(meta["workspace_members"])
    nodes = {n["id"]: n for n in meta["resolve"]["nodes"]}

    def proc_macro(pid: str) -> bool:
        return any("proc-macro" in t["kind"] for t in packages[pid]["targets"])

    def deps(pid: str, kinds: tuple) -> list[str]:
        return [d["pkg"] for d in nodes[pid]["deps"] if any(k["kind"] in kinds for k in d["dep_kinds"])]

    # What the workspace's targets link: members' normal and dev
    # dependencies and their normal dependencies, on any platform, not
    # through a proc macro (its dependencies run in the compiler).
    linked: set[str] = set()
    todo = [d for m in members for d in deps(m, (None, "dev"))]
    while todo:
        pid = todo.pop()
        if pid in linked or pid in members or proc_macro(pid):
            continue
        linked.add(pid)
        todo += deps(pid, (None,))
    names = {packages[p]["name"] for p in set(nodes) - members - linked}
    # A name is one override for all its versions: leave out a name that
    # is also linked.
    return sorted(names - {packages[p]["name"] for p in linked})


def block(names: list[str]) -> str:
    lines = [
        BEGIN,
        "# Built only for the build (proc macros, build scripts' helpers):",
        "# unoptimized, as cargo's build-override would have them, which the",
        '# package."*" override above takes precedence over.',
        "[profile.dev.package]",
        *(f"{n} = {{ opt-level = 0 }}" for n in names),
        END,
    ]
    return "\n".join(lines)


def updated(text: str, names: list[str]) -> str:
    """Cargo.toml's `text` with its block listing `names`."""
    want = block(names)
    if BEGIN in text:
        head, rest = text.split(BEGIN, 1)
        return head + want + rest.split(END, 1)[1]
    anchor = "\n[profile.release]"
    return text.replace(anchor, "\n" + want + "\n" + anchor, 1)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--check", action="store_true", help="exit 1 when Cargo.toml is out of date")
    args = ap.parse_args()
    text = CARGO_TOML.read_text()
    names = host_only()
    new = updated(text, names)
    if new == text:
        return 0
    if args.check:
        print(
            "host_deps: Cargo.toml's host-only block is out of date; run python3 scripts/dev/host_deps.py",
            file=sys.stderr,
        )
        return 1
    CARGO_TOML.write_text(new)
    print(f"host_deps: {len(names)} host-only packages written to Cargo.toml")
    return 0


if __name__ == "__main__":
    sys.exit(main())
