"""Blender-side checks of the Shapewright extension, one scenario per run:

    BLENDER_USER_RESOURCES=DIR python scenarios.py ZIP SCENARIO WORKDIR

Runs inside `bpy` (Blender 5.0.1 as a module, headless). Installs the
extension zip through Blender's extension API, enables it, then runs the
scenario `scenario_<SCENARIO>` of one of the `sc_*.py` modules beside
this file (one module per idea: `sc_keys` Blender's own keys, `sc_units`
units and origins, `sc_edits` renames and moves, `sc_usd` USD, ...); any
failed assertion exits non-zero. `helpers.py` has what they share.
"""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

from helpers import install

MODULES = sorted(p.stem for p in Path(__file__).resolve().parent.glob("sc_*.py"))


def find(name: str):
    for m in MODULES:
        fn = getattr(importlib.import_module(m), f"scenario_{name}", None)
        if fn is not None:
            return fn
    raise SystemExit(f"no scenario {name!r} in {', '.join(MODULES)}")


def main() -> int:
    zip_path, name, work = sys.argv[1], sys.argv[2], Path(sys.argv[3])
    scenario = find(name)
    install(zip_path)
    scenario(work)
    print(f"scenario {name}: ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
