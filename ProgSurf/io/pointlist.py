"""Point-list stroke files: .xyz, .txt, .csv, .asc.

Format (read and written):
  - one point per line, ``x y z`` in millimetres, separated by spaces, tabs, commas or semicolons;
  - strokes separated by one or more blank lines, OR a 4th integer column naming the stroke
    (points of one stroke keep their file order; strokes are returned in order of first appearance);
  - lines starting with ``#`` are comments; a comment line after points ends their stroke, as a
    blank line does (a "# stroke 2" line between strokes would otherwise join them); a first data line of column names (``x,y,z`` or
    ``x y z stroke`` ...) is recognised as a header and skipped.
Numpy only.
"""
from __future__ import annotations

import os
import re
from typing import Sequence

import numpy as np
import numpy.typing as npt

from ..core.errors import InvalidStrokeError, StrokeFileError
from ..core.types import FloatArray

_SPLIT = re.compile(r"[\s,;]+")
_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_.()\[\]-]*$")


def _token_float(tok: str) -> float | None:
    try:
        return float(tok)
    except ValueError:
        return None


def read_text(path: str | os.PathLike, not_binary: str, as_text: str) -> tuple[str, str]:
    """(file name, text) of a stroke text file; StrokeFileError for a missing or unreadable file, a
    binary one ("is a binary file, not <not_binary>") or one not UTF-8 ("save it as plain text
    <as_text>")."""
    name = os.path.basename(os.fspath(path))
    try:
        with open(path, "rb") as fh:
            raw = fh.read()
    except OSError as exc:
        raise StrokeFileError(f"cannot read stroke file {os.fspath(path)!r}: {exc.strerror or exc}") from None
    if b"\x00" in raw:
        raise StrokeFileError(f"{name} is a binary file, not {not_binary}")
    try:
        return name, raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise StrokeFileError(f"{name} is not UTF-8 text (byte {exc.start}); save it as plain text {as_text}") from None


def read_point_list(path: str | os.PathLike) -> list[FloatArray]:
    """Read the strokes of a point-list file; returns a list of (n, 3) float arrays (mm).

    Raises StrokeFileError naming the file and line for anything it cannot read: a missing or
    binary file, a line without 3 numbers, non-finite coordinates, a stroke column that is not an
    integer, a mix of 3- and 4-column lines, or a file with no points.
    """
    name, text = read_text(path, "a point list; give x y z text lines", "with x y z per line")

    strokes: list[list[list[float]]] = []
    by_id: dict[int, list[list[float]]] = {}
    current: list[list[float]] = []
    ncols: int | None = None
    ncols_line = 0
    seen_data = False
    for lineno, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip()
        if not stripped:
            if current:
                strokes.append(current)
                current = []
            continue
        if stripped.startswith("#"):
            if current:        # a comment between two strokes separates them, blank line or not
                strokes.append(current)
                current = []
            continue
        tokens = [t for t in _SPLIT.split(stripped) if t]
        values = [_token_float(t) for t in tokens]
        if not seen_data and all(v is None for v in values) and all(_NAME.match(t) for t in tokens):
            seen_data = True  # a header of column names, e.g. "x,y,z" or "X Y Z stroke"
            continue
        seen_data = True
        where = f"line {lineno} of {name}"
        if len(tokens) not in (3, 4):
            raise StrokeFileError(
                f"{where}: expected 3 numbers (x y z) or 4 (x y z stroke), got {len(tokens)} "
                f"fields {stripped[:60]!r}"
            )
        bad = [t for t, v in zip(tokens[:3], values[:3]) if v is None]
        if bad:
            raise StrokeFileError(f"{where}: expected 3 numbers, got {bad[0][:40]!r}")
        xyz = [float(v) for v in values[:3]]  # type: ignore[arg-type]
        if not all(np.isfinite(xyz)):
            raise StrokeFileError(f"{where}: coordinates {stripped[:60]!r} are not finite; give real numbers")
        if ncols is None:
            ncols, ncols_line = len(tokens), lineno
        elif ncols != len(tokens):
            raise StrokeFileError(
                f"{where}: has {len(tokens)} columns but line {ncols_line} has {ncols}; "
                "use x y z on every line, or x y z stroke on every line"
            )
        if ncols == 4:
            sid = values[3]
            if sid is None or not np.isfinite(sid) or sid != int(sid):
                raise StrokeFileError(f"{where}: stroke column {tokens[3][:40]!r} is not an integer")
            by_id.setdefault(int(sid), []).append(xyz)
        else:
            current.append(xyz)
    if current:
        strokes.append(current)
    if ncols == 4:
        strokes = list(by_id.values())
    if not strokes:
        raise StrokeFileError(f"{name} contains no points; give one 'x y z' line per point")
    return [np.array(s, dtype=float).reshape(-1, 3) for s in strokes]


def write_point_list(
    path: str | os.PathLike,
    strokes: Sequence[npt.ArrayLike],
    comments: Sequence[str] = (),
    decimals: int = 6,
) -> None:
    """Write strokes as a point list: '#' header comments, 'x y z' lines, one blank line between strokes.

    strokes  : sequence of (n, 3) float arrays, n >= 1, finite.
    comments : extra lines written (each prefixed with '# ') after the format line.
    Reading the file back with `read_point_list` returns the strokes to within 10**-decimals mm.
    """
    arrays = []
    for i, s in enumerate(strokes):
        try:
            arr = np.array(s, dtype=float)
        except (TypeError, ValueError):
            raise InvalidStrokeError(f"stroke {i} is not an array of numbers; cannot write it") from None
        if arr.ndim != 2 or arr.shape[1] != 3 or arr.shape[0] < 1:
            raise InvalidStrokeError(f"stroke {i} has shape {arr.shape}; only (n, 3) strokes with n >= 1 can be written")
        if not np.isfinite(arr).all():
            raise InvalidStrokeError(f"stroke {i} has NaN or infinite coordinates; cannot write it")
        arrays.append(arr)
    if not arrays:
        raise InvalidStrokeError("no strokes to write; give at least one (n, 3) stroke")
    npts = sum(a.shape[0] for a in arrays)
    lines = [f"# ProgSurf point list: {len(arrays)} strokes, {npts} points",
             "# format: one point per line 'x y z' (mm); one blank line separates strokes"]
    lines += [f"# {c}" if c else "#" for c in comments]
    fmt = f"{{:.{int(decimals)}f}}"
    for k, arr in enumerate(arrays):
        if k:
            lines.append("")
        lines.extend(" ".join(fmt.format(v) for v in p) for p in arr)
    try:
        with open(path, "w", encoding="utf-8", newline="\n") as fh:
            fh.write("\n".join(lines) + "\n")
    except OSError as exc:
        raise StrokeFileError(f"cannot write stroke file {os.fspath(path)!r}: {exc.strerror or exc}") from None
