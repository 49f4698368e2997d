"""The Blender extension, built with Blender's own tool, installed through
Blender's extension API into a temporary user directory and driven by its
operators in headless Blender (`bpy` 5.0.1). The fixtures are in
`tests/conftest.py`."""

from __future__ import annotations

from collections.abc import Callable

import pytest


@pytest.mark.parametrize(
    "scenario",
    [
        "build",
        "undo",
        "save_reload",
        "usd_roundtrip",
        "render",
        "export",
        "models",
        "typed",
        "sketch_projection",
        "xr_trace",
        "xr_gc_trace",
        # issue 19: the lamp modeler session through the VR input path
        "xr_lamp_session",
        "history_usd",
        # issue 20
        "reopen_undo",
        "sketch_arc",
        "sketch_edits",
        "conventions",
        "export_job",
        "rename",
        "transform_kinds",
        "transform_auto",
        # issue 20: also run in the newest bpy by scripts/blender_newest.sh
        "smoke",
        # issue 15: the op table agrees with the core's op schema
        "op_schema",
    ],
)
def test_scenario(scenario: str, run_scenario: Callable[..., str]) -> None:
    run_scenario(scenario)
