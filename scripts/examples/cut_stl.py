"""Cuts a closed STL mesh in half with a plane (manifold3d's trim_by_plane:
the cut face is filled, so the result is closed and shows the wall) and
writes the half that lies on the normal's side as binary STL, for pictures
of a model's inside.

Usage: python scripts/examples/cut_stl.py IN.stl OUT.stl [--normal 0,-1,0] [--offset 0]
"""

from __future__ import annotations

import argparse
import struct
from pathlib import Path

import manifold3d
import numpy as np


def read_stl(path: Path) -> manifold3d.Manifold:
    data = path.read_bytes()
    n = int.from_bytes(data[80:84], "little")
    rec = np.frombuffer(data[84 : 84 + 50 * n], dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]))
    verts, inv = np.unique(rec["v"].reshape(-1, 3), axis=0, return_inverse=True)
    m = manifold3d.Manifold(manifold3d.Mesh(vert_properties=verts.astype(np.float32), tri_verts=inv.reshape(-1, 3).astype(np.uint32)))
    if m.status() != manifold3d.Error.NoError:
        raise SystemExit(f"cut_stl.py: {path} is not a closed 2-manifold ({m.status()})")
    return m


def write_stl(m: manifold3d.Manifold, path: Path) -> None:
    mesh = m.to_mesh()
    v = np.asarray(mesh.vert_properties)[:, :3].astype(np.float32)
    t = np.asarray(mesh.tri_verts).astype(np.int64)
    out = bytearray(b"cut_stl.py".ljust(80, b" "))
    out += struct.pack("<I", len(t))
    for a, b, c in t:
        n = np.cross(v[b] - v[a], v[c] - v[a])
        n = n / (np.linalg.norm(n) or 1.0)
        out += struct.pack("<12fH", *n, *v[a], *v[b], *v[c], 0)
    path.write_bytes(bytes(out))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("input", type=Path)
    p.add_argument("output", type=Path)
    p.add_argument("--normal", default="0,-1,0")
    p.add_argument("--offset", type=float, default=0.0)
    a = p.parse_args()
    normal = tuple(float(x) for x in a.normal.split(","))
    half = read_stl(a.input).trim_by_plane(normal, a.offset)
    write_stl(half, a.output)


if __name__ == "__main__":
    main()
