#!/usr/bin/env python3
"""Link stubs for the two macOS frameworks the wheel's dependencies link.

    scripts/macos_stubs.py OUT_DIR      -> OUT_DIR/{Security,CoreFoundation}.framework/*.tbd

No macOS SDK can be fetched here, and zig (maturin `--zig`) carries only
libSystem's stub. `async-nats` always compiles `rustls-native-certs`, which
on macOS reads the system's trust store through `security-framework`, and
its `-sys` crates ask the linker for `-framework Security` and
`-framework CoreFoundation`. An SDK's `.tbd` file is a text list of what a
system library exports and where it is installed; this writes that list for
each framework from the `-sys` crates' own extern declarations (the same
Apple headers the crates were written from), so the linker records the
frameworks' real install names and binds each symbol to its framework,
exactly as with the SDK. Only symbols the code references end up in the
binary; listing a declared one it does not use changes nothing.

Pass the folder to the linker with `-F OUT_DIR` (scripts/build_addon.sh does).
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FRAMEWORKS = {"security-framework-sys": "Security", "core-foundation-sys": "CoreFoundation"}
DECL = re.compile(r"^\s*pub\s+(?:fn|static(?:\s+mut)?)\s+([A-Za-z_][A-Za-z0-9_]*)", re.MULTILINE)
EXTERN = re.compile(r'extern\s+"C"\s*\{(.*?)^\}', re.MULTILINE | re.DOTALL)
TARGETS = "[ x86_64-macos, arm64-macos ]"


def crate_dirs() -> dict[str, Path]:
    meta = json.loads(
        subprocess.run(
            ["cargo", "metadata", "--format-version", "1", "--locked"]
            + ["--filter-platform", "aarch64-apple-darwin"],
            cwd=ROOT,
            check=True,
            capture_output=True,
            text=True,
        ).stdout
    )
    found = {p["name"]: Path(p["manifest_path"]).parent for p in meta["packages"] if p["name"] in FRAMEWORKS}
    missing = set(FRAMEWORKS) - set(found)
    if missing:
        sys.exit(f"macos_stubs: {sorted(missing)} not in the dependency graph (did the TLS stack change?)")
    return found


def symbols(crate: Path) -> list[str]:
    names: set[str] = set()
    for src in sorted((crate / "src").rglob("*.rs")):
        for block in EXTERN.findall(src.read_text()):
            names.update(DECL.findall(block))
    return sorted(names)


def main() -> int:
    out = Path(sys.argv[1])
    for crate_name, crate in crate_dirs().items():
        fw = FRAMEWORKS[crate_name]
        names = symbols(crate)
        if len(names) < 50:
            sys.exit(f"macos_stubs: only {len(names)} declarations found in {crate}; the parser needs a look")
        d = out / f"{fw}.framework"
        d.mkdir(parents=True, exist_ok=True)
        body = ",\n".join(f"                       _{n}" for n in names)
        (d / f"{fw}.tbd").write_text(
            "--- !tapi-tbd\n"
            "tbd-version:     4\n"
            f"targets:         {TARGETS}\n"
            f"install-name:    '/System/Library/Frameworks/{fw}.framework/Versions/A/{fw}'\n"
            "exports:\n"
            f"  - targets:         {TARGETS}\n"
            f"    symbols:         [\n{body} ]\n"
            "...\n"
        )
        print(f"macos_stubs: {fw}: {len(names)} symbols from {crate.name}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
