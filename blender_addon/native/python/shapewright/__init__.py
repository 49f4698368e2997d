"""Shapewright modeling core for Python.

`Session` is a document with its undoable op log; ops are JSON objects
(`{"op": "add_solid", ...}`). Meshes come back as numpy arrays that view
the buffers the core filled (one memcpy from Rust, none in Python).
"""

from __future__ import annotations

import json
import math
from typing import Any

import numpy as np

from ._native import (
    OP_FORMAT_VERSION,
    ExportJob,
    HistoryError,
    InputSession,
    OpRejected,
    ParseError,
    Session,
    SessionError,
    ShapewrightError,
    action_map_json,
    child_from_stroke,
    import_usd,
    import_usd_text,
    library_names,
    load_usd,
    match_section,
    op_names,
    op_schema_json,
    parametric_parts,
    profile_radius,
    replace_spine_from_stroke,
    save_usd,
    sketch_spine,
    tool_names,
    trace_format,
    usd_text,
    validate_buffers,
)

__all__ = [
    "OP_FORMAT_VERSION",
    "ExportJob",
    "HistoryError",
    "InputSession",
    "OpRejected",
    "ParseError",
    "Session",
    "SessionError",
    "ShapewrightError",
    "action_map_json",
    "apply",
    "check_finite",
    "child_from_stroke",
    "import_usd",
    "import_usd_text",
    "library_names",
    "load_usd",
    "match_section",
    "mesh_arrays",
    "op_names",
    "op_schema_json",
    "parametric_parts",
    "profile_radius",
    "replace_spine_from_stroke",
    "save_usd",
    "sketch_spine",
    "usd_text",
    "tool_names",
    "trace_format",
    "validate_arrays",
    "validate_buffers",
]


# Blender stores float properties as float32: `inf` typed into a field
# arrives as the largest float32 (3.4e38). Anything this large is an
# overflowed value, not a size.
FLOAT32_OVERFLOW = 3.0e38


def check_finite(value: Any, path: str = "") -> None:
    """Raises ParseError naming the field (e.g. `shape.radius`) when a
    number in an op is NaN, infinite, or a float32 overflow (what Blender
    makes of `inf`). JSON cannot carry NaN or infinity, so without this the
    core could only answer with a JSON syntax error."""
    if isinstance(value, dict):
        for k, v in value.items():
            check_finite(v, f"{path}.{k}" if path else str(k))
    elif isinstance(value, list | tuple):
        for i, v in enumerate(value):
            check_finite(v, f"{path}[{i}]")
    elif isinstance(value, float) and not isinstance(value, bool):
        if math.isnan(value):
            raise ParseError(f"{path or 'value'}: NaN is not a number; give a finite value")
        if math.isinf(value) or abs(value) >= FLOAT32_OVERFLOW:
            raise ParseError(f"{path or 'value'}: {value} is not finite; give a finite value")


def apply(session: Session, op: dict[str, Any]) -> int | None:
    """Applies an op given as a dict (or `{"op": "undo"}` / `{"op":
    "redo"}`, as in `.jsonl` scripts); returns the id it created, if any.
    Non-finite numbers are refused with the field's name."""
    check_finite(op)
    return session.apply_line(json.dumps(op))


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
