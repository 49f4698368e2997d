"""Shapewright modeling core for Python.

`Session` is a document with its undoable op log; ops are dicts
(`{"op": "add_solid", ...}`) checked and converted in Rust, never JSON
text. Placements, poses, input frames and presence are typed values
(`Placement`, `Pose`, `Controller`, `InputFrame`, `Presence`). Meshes come
back as numpy arrays that view the buffers the core filled (one memcpy
from Rust, none in Python). `_native.pyi` states the whole surface.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ._native import (
    OP_FORMAT_VERSION,
    PRESENCE_HZ,
    Autosaver,
    Built,
    Controller,
    ExportJob,
    HistoryError,
    InputFrame,
    InputSession,
    OpRejected,
    PaletteView,
    ParseError,
    Placement,
    Pose,
    Presence,
    Session,
    SessionError,
    ShapewrightError,
    action_map,
    build_form,
    import_usd,
    import_usd_text,
    library_names,
    load_usd,
    op_forms,
    op_names,
    op_schema,
    parametric_parts,
    save_usd,
    solid_kinds,
    tool_names,
    trace_format,
    usd_text,
    validate_buffers,
)

__all__ = [
    "OP_FORMAT_VERSION",
    "PRESENCE_HZ",
    "Autosaver",
    "Built",
    "Controller",
    "ExportJob",
    "HistoryError",
    "InputFrame",
    "InputSession",
    "OpRejected",
    "PaletteView",
    "ParseError",
    "Placement",
    "Pose",
    "Presence",
    "Session",
    "SessionError",
    "ShapewrightError",
    "action_map",
    "build_form",
    "import_usd",
    "import_usd_text",
    "library_names",
    "load_usd",
    "mesh_arrays",
    "op_forms",
    "op_names",
    "op_schema",
    "parametric_parts",
    "save_usd",
    "solid_kinds",
    "tool_names",
    "trace_format",
    "usd_text",
    "validate_arrays",
    "validate_buffers",
]


def mesh_arrays(
    session: Session,
    object_id: int | None = None,
    frame: str = "world",
    units_per_metre: float = 1.0,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """An object's mesh (or all objects') as (positions (n, 3) float64,
    triangles (m, 3) uint32, sources (m,) uint32), read-only views.
    `frame` is `world` or `origin` (see `Session.mesh_buffers`)."""
    pos, tri, src = session.mesh_buffers(object_id, frame, units_per_metre)
    return (
        np.frombuffer(pos, dtype="<f8").reshape(-1, 3),
        np.frombuffer(tri, dtype="<u4").reshape(-1, 3),
        np.frombuffer(src, dtype="<u4"),
    )


def validate_arrays(positions: np.ndarray, triangles: np.ndarray) -> dict[str, Any]:
    """Validates a mesh given as arrays (e.g. read from Blender)."""
    pos = np.ascontiguousarray(positions, dtype="<f8")
    tri = np.ascontiguousarray(triangles, dtype="<u4")
    return validate_buffers(pos.tobytes(), tri.tobytes())
