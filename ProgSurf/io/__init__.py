"""Stroke readers and writers (numpy only).

`read_strokes(path, **options)` picks the reader from the file extension:
  .xyz .txt .csv .asc  point lists (`pointlist.read_point_list`, no options)
  .c3d                 motion-capture markers (`c3d.read_c3d_strokes(path, **options)`)
  .curves              CASSIE's VR sketches, metres (`curves.read_curves`, no options)
"""
from __future__ import annotations

import os
from typing import Any

from ..core.errors import StrokeFileError
from ..core.types import FloatArray
from .pointlist import read_point_list, write_point_list

POINT_LIST_EXTENSIONS = (".xyz", ".txt", ".csv", ".asc")
SUPPORTED_EXTENSIONS = POINT_LIST_EXTENSIONS + (".c3d", ".curves")

__all__ = ["read_strokes", "read_point_list", "write_point_list", "SUPPORTED_EXTENSIONS"]


def read_strokes(path: str | os.PathLike, **options: Any) -> list[FloatArray]:
    """Read the strokes of a file as a list of (n, 3) float arrays in mm, choosing the reader by extension.

    options are passed to the C3D reader; point-list files take none.
    """
    ext = os.path.splitext(os.fspath(path))[1].lower()
    if options and ext in SUPPORTED_EXTENSIONS and ext != ".c3d":
        raise StrokeFileError(f"options {sorted(options)} do not apply to {ext} files; they are only for .c3d files")
    if ext in POINT_LIST_EXTENSIONS:
        return read_point_list(path)
    if ext == ".curves":
        from .curves import read_curves

        return read_curves(path)
    if ext == ".c3d":
        from .c3d import read_c3d_strokes  # lazy: only C3D users pay for that module

        return read_c3d_strokes(path, **options)
    raise StrokeFileError(
        f"cannot read {os.path.basename(os.fspath(path))!r}: unknown extension {ext or '(none)'!r}; "
        f"supported extensions are {', '.join(SUPPORTED_EXTENSIONS)}"
    )
