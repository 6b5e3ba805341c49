"""CASSIE's ``.curves`` stroke files (VR sketches: Yu et al., CHI 2021; github.com/V-Sekai/cassie-data).

Format: for each stroke a line ``v N`` and then N lines ``x y z`` in metres. Strokes are returned in
file order, in millimetres (x 1000), their points as drawn. Numpy only.
"""
from __future__ import annotations

import os
from typing import Sequence

import numpy as np
import numpy.typing as npt

from ..core.errors import StrokeFileError
from ..core.types import FloatArray
from .pointlist import read_text

METRES_TO_MM = 1000.0
FORMAT = "a .curves file: 'v N' lines, each followed by N 'x y z' lines in metres"


def read_curves(path: str | os.PathLike) -> list[FloatArray]:
    """The strokes of a CASSIE .curves file as (n, 3) float arrays in mm.

    Raises StrokeFileError naming the file and line for what it cannot read: a missing file, a
    point before any ``v N`` line, a line that is not 3 numbers, non-finite coordinates, a stroke
    with more or fewer points than its ``v N`` line says, or a file with no points."""
    name, text = read_text(path, FORMAT, f"({FORMAT})")
    lines = text.splitlines()
    strokes: list[list[list[float]]] = []
    counts: list[tuple[int, int]] = []          # (points its 'v N' line announced, that line)
    for no, line in enumerate(lines, start=1):
        parts = line.split()
        if not parts or parts[0].startswith("#"):
            continue
        if parts[0] == "v":
            if len(parts) != 2 or not parts[1].isdigit():
                raise StrokeFileError(f"{name} line {no}: {line.strip()!r} should be 'v N' (N points follow)")
            strokes.append([])
            counts.append((int(parts[1]), no))
            continue
        if not strokes:
            raise StrokeFileError(f"{name} line {no}: a point before any 'v N' line; is this a .curves file?")
        try:
            xyz = [float(t) for t in parts]
        except ValueError:
            xyz = []
        if len(xyz) != 3 or not np.all(np.isfinite(xyz)):
            raise StrokeFileError(f"{name} line {no}: {line.strip()!r} is not 3 finite numbers (x y z in metres)")
        strokes[-1].append(xyz)
    for pts, (want, no) in zip(strokes, counts):
        if len(pts) != want:
            raise StrokeFileError(f"{name} line {no}: 'v {want}' but {len(pts)} point(s) follow it")
    if not any(strokes):
        raise StrokeFileError(f"{name} has no points")
    return [np.asarray(s, dtype=float).reshape(-1, 3) * METRES_TO_MM for s in strokes if s]


def write_curves(path: str | os.PathLike, strokes: Sequence[npt.ArrayLike]) -> None:
    """Write strokes ((n, 3) points in mm each) as a CASSIE .curves file (metres), read_curves'
    format: the points read back as written, to round-off."""
    with open(path, "w", encoding="utf-8") as fh:
        for stroke in strokes:
            pts = np.asarray(stroke, dtype=float).reshape(-1, 3) / METRES_TO_MM
            fh.write(f"v {len(pts)}\n" + "".join(f"{x!r} {y!r} {z!r}\n" for x, y, z in pts.tolist()))
