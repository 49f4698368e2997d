"""Shapewright modeling core for Python.

`Session` is a document with its undoable op log; ops are JSON objects
(`{"op": "add_solid", ...}`). Meshes come back as numpy arrays that view
the buffers the core filled (one memcpy from Rust, none in Python).
"""

from __future__ import annotations

import json
from typing import Any

import numpy as np

from ._native import (
    OP_FORMAT_VERSION,
    HistoryError,
    InputSession,
    OpRejected,
    ParseError,
    Session,
    ShapewrightError,
    action_map_json,
    library_names,
    load_usd,
    op_names,
    save_usd,
    tool_names,
    trace_format,
    validate_buffers,
)

__all__ = [
    "OP_FORMAT_VERSION",
    "HistoryError",
    "InputSession",
    "OpRejected",
    "ParseError",
    "Session",
    "ShapewrightError",
    "action_map_json",
    "apply",
    "library_names",
    "load_usd",
    "mesh_arrays",
    "op_names",
    "save_usd",
    "tool_names",
    "trace_format",
    "validate_arrays",
    "validate_buffers",
]


def apply(session: Session, op: dict[str, Any]) -> int | None:
    """Applies an op given as a dict; returns the id it created, if any."""
    return session.apply(json.dumps(op))


def mesh_arrays(session: Session, object_id: int | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """An object's mesh (or all objects') as (positions (n, 3) float64,
    triangles (m, 3) uint32, sources (m,) uint32), read-only views."""
    pos, tri, src = session.mesh_buffers(object_id)
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
