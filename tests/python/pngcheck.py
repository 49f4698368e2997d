"""A minimal PNG decoder (8-bit RGB/RGBA, non-interlaced) for tests that
look at renders without pulling in an imaging library."""

from __future__ import annotations

import struct
import zlib
from pathlib import Path

import numpy as np


def read_png(path: Path) -> np.ndarray:
    """Returns an (h, w, channels) uint8 array."""
    data = Path(path).read_bytes()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG")
    pos, idat, header = 8, b"", None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos : pos + 4])
        kind = data[pos + 4 : pos + 8]
        body = data[pos + 8 : pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    if header is None:
        raise ValueError(f"{path}: no IHDR")
    w, h, depth, color, _, _, interlace = header
    channels = {2: 3, 6: 4, 0: 1, 4: 2}[color]
    if depth != 8 or interlace:
        raise ValueError(f"{path}: only 8-bit non-interlaced PNGs are supported")
    raw = zlib.decompress(idat)
    stride = w * channels
    out = np.zeros((h, stride), dtype=np.int32)
    prev = np.zeros(stride, dtype=np.int32)
    for y in range(h):
        row_start = y * (stride + 1)
        ftype = raw[row_start]
        row = np.frombuffer(raw, dtype=np.uint8, count=stride, offset=row_start + 1).astype(np.int32)
        if ftype == 0:
            cur = row
        elif ftype == 2:
            cur = (row + prev) & 255
        else:
            cur = np.zeros(stride, dtype=np.int32)
            for x in range(stride):
                a = cur[x - channels] if x >= channels else 0
                b = prev[x]
                c = prev[x - channels] if x >= channels else 0
                if ftype == 1:
                    pred = a
                elif ftype == 3:
                    pred = (a + b) // 2
                else:
                    p = a + b - c
                    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                    pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                cur[x] = (row[x] + pred) & 255
        out[y] = cur
        prev = cur
    return out.reshape(h, w, channels).astype(np.uint8)


def foreground_fraction(img: np.ndarray, tol: int = 12) -> float:
    """Fraction of pixels that differ from the top-left (background) pixel."""
    rgb = img[..., :3].astype(np.int32)
    bg = rgb[0, 0]
    return float((np.abs(rgb - bg).max(axis=-1) > tol).mean())
