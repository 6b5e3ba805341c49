"""Strokes from C3D motion-capture files: one stroke per run of frames where a marker is seen.

Qin & Wright sketch with reflective markers; the designer switches drawing on and off by
covering and uncovering a marker, so an occluded sample is pen-up. A marker sample is invalid
(occluded) when its residual is negative, a coordinate is NaN, or it is zero-filled (0, 0, 0).
Each maximal run of valid samples is one stroke. Points are converted to millimetres from
POINT:UNITS, optionally smoothed (ends fixed) and then thinned with the paper's 3D distance
threshold ("unorganised curves" paper, section 2: "we used a 3D distance threshold to filter
out 3D sketch points between two successive wanted points").

File parsing uses the PyPI package `c3d` (MIT licence, pure Python, also has a Writer that the
tests use). It is imported when a file is read, so this module imports with numpy alone.
"""
from __future__ import annotations

import struct
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Optional, Sequence, Union

import numpy as np

from ..core.errors import InvalidOptionError, StrokeFileError
from ..core.strokes import auto_filter_threshold, filter_stroke
from ..core.types import FloatArray
from ..optional import require

FEATURE = "reading C3D files"
"""What needs the optional package 'c3d' (ProgSurf.optional)."""

_UNIT_TO_MM = {
    "mm": 1.0, "millimeter": 1.0, "millimeters": 1.0, "millimetre": 1.0, "millimetres": 1.0,
    "cm": 10.0, "centimeter": 10.0, "centimeters": 10.0, "centimetre": 10.0, "centimetres": 10.0,
    "m": 1000.0, "meter": 1000.0, "meters": 1000.0, "metre": 1000.0, "metres": 1000.0,
}

# What the c3d library raises on malformed headers and parameters (it checks with assert).
_PARSE_ERRORS = (struct.error, AssertionError, ValueError, KeyError, IndexError,
                 AttributeError, TypeError, UnicodeDecodeError, OverflowError)

MIN_DURATION_S = 0.1
"""Default of read_c3d's min_duration_s: shorter pen-down runs are dropped (seconds)."""
MIN_LENGTH_MM = 5.0
"""Default of read_c3d's min_length_mm: shorter pen-down runs are dropped (mm)."""

_C3D_MAGIC = 0x50
_BLOCK = 512
_PROCESSORS = (84, 85, 86)  # C3D parameter header byte 4: Intel, DEC, MIPS


@dataclass(frozen=True)
class DroppedRun:
    """A run of valid samples that did not become a stroke.

    marker : label of the marker
    frames : (first, last) file frame numbers, inclusive
    reason : why it was dropped, e.g. "lasts 0.05 s, shorter than min_duration_s 0.1 s"
    """

    marker: str
    frames: tuple[int, int]
    reason: str


@dataclass(frozen=True)
class C3DStrokes:
    """Everything read from one C3D file, for the GUI and the build report.

    strokes    : tuple of (n_i, 3) float arrays in mm (read-only), ordered by first frame
    markers    : label of the marker that drew each stroke
    frames     : (first, last) file frame numbers of each stroke, inclusive (before filtering)
    frame_rate : POINT:RATE, frames per second
    units      : POINT:UNITS as found ("mm" when missing); points are converted to mm
    labels     : every marker label in the file, in file order
    path_mm    : path length (mm) of every marker over its valid frames, aligned with labels
    filter_mm  : the distance threshold used (None when filtering was off)
    dropped    : runs that were not kept, with reasons
    """

    strokes: tuple[FloatArray, ...]
    markers: tuple[str, ...]
    frames: tuple[tuple[int, int], ...]
    frame_rate: float
    units: str
    labels: tuple[str, ...]
    path_mm: tuple[float, ...]
    filter_mm: Optional[float]
    dropped: tuple[DroppedRun, ...]


@dataclass(frozen=True)
class _Capture:
    """Raw marker data of one file.

    xyz   : (n_frames, n_markers, 3) float32 in the file's units (kept compact for long captures)
    valid : (n_frames, n_markers) bool, False where the marker is occluded
    to_mm : factor from the file's units to mm
    """

    labels: tuple[str, ...]
    xyz: np.ndarray
    valid: np.ndarray
    frame_rate: float
    units: str
    to_mm: float
    first_frame: int

    def marker_mm(self, m: int) -> FloatArray:
        """(n_frames, 3) float64 trajectory of marker m in mm (invalid samples included)."""
        return self.xyz[:, m].astype(np.float64) * self.to_mm


def _c3d_module():
    """The optional c3d library, imported when a file is read (MissingPackageError if absent)."""
    return require("c3d", FEATURE)


def _check_layout(path: Path, handle) -> int:
    """Reject non-C3D and truncated files before the library sees them (it asserts); returns size."""
    handle.seek(0, 2)
    size = handle.tell()
    handle.seek(0)
    head = handle.read(_BLOCK)
    if len(head) < 2 or head[1] != _C3D_MAGIC:
        got = f"0x{head[1]:02x}" if len(head) >= 2 else "missing"
        raise StrokeFileError(
            f"{path} is not a C3D file: byte 2 is {got}, a C3D file has 0x50 there; "
            "export the capture as .c3d or use a stroke text file")
    if size < _BLOCK:
        raise StrokeFileError(
            f"{path} is truncated: {size} bytes, a C3D file has at least a {_BLOCK}-byte header")
    pblock = head[0]
    start = (pblock - 1) * _BLOCK
    if pblock < 2 or start + 4 > size:
        raise StrokeFileError(
            f"{path} is truncated or corrupt: its parameter section (block {pblock}) "
            f"is not inside the file of {size} bytes")
    handle.seek(start)
    _, _, nblocks, processor = handle.read(4)
    if processor not in _PROCESSORS:
        raise StrokeFileError(
            f"{path} is not a readable C3D file: processor type {processor} in its parameter "
            "section is none of 84 (Intel), 85 (DEC), 86 (MIPS); the file is corrupt")
    if start + nblocks * _BLOCK > size:
        raise StrokeFileError(
            f"{path} is truncated: the parameter section needs {nblocks} blocks of {_BLOCK} bytes "
            f"from byte {start}, the file has {size} bytes")
    handle.seek(0)
    return size


def _labels(reader, n_points: int) -> tuple[str, ...]:
    """POINT:LABELS (+ LABELS2, LABELS3, ... past 255 markers); blanks become POINT<i>."""
    found: list[str] = []
    for name in ["POINT:LABELS"] + [f"POINT:LABELS{k}" for k in range(2, 100)]:
        param = reader.get(name)
        if param is None:
            break
        found.extend(str(s).strip() for s in np.ravel(param.string_array))
    found = found[:n_points] + [""] * max(0, n_points - len(found))
    return tuple(s if s else f"POINT{i + 1}" for i, s in enumerate(found))


def _units(reader, path: Path) -> tuple[str, float]:
    param = reader.get("POINT:UNITS")
    units = param.string_value.strip() if param is not None else ""
    if not units:
        return "mm", 1.0
    factor = _UNIT_TO_MM.get(units.lower())
    if factor is None:
        raise StrokeFileError(
            f"{path}: POINT:UNITS is '{units}'; ProgSurf reads m, cm or mm. "
            "Re-export the capture in one of these units")
    return units, factor


def _frame_bytes(reader) -> int:
    word = 4 if reader.point_scale < 0 else 2
    return word * (4 * reader.point_used + reader.analog_used * reader.analog_per_frame)


def _open_reader(path: Path, handle):
    c3d = _c3d_module()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return c3d.Reader(handle)
    except _PARSE_ERRORS as exc:
        raise StrokeFileError(
            f"{path} is not a readable C3D file (truncated or corrupt header/parameters: {exc})"
        ) from None


def _load(path: Union[str, Path]) -> _Capture:
    """Read every marker of every frame; mm, with occluded samples marked invalid."""
    path = Path(path)
    if not path.is_file():
        raise StrokeFileError(f"{path}: no such C3D file")
    with open(path, "rb") as handle:
        size = _check_layout(path, handle)
        reader = _open_reader(path, handle)
        try:
            n_points = int(reader.point_used)
            n_frames = int(reader.frame_count)
            first = int(reader.first_frame)
            rate = float(reader.point_rate)
        except _PARSE_ERRORS as exc:
            raise StrokeFileError(f"{path}: unreadable C3D parameters ({exc})") from None
        if not (np.isfinite(rate) and rate > 0):     # the c3d reader divides by it for every frame
            raise StrokeFileError(f"{path}: POINT:RATE is {rate:g} frames per second, so its frames "
                                  "cannot be read; write the capture rate into the file")
        try:
            data_start = (int(reader.header.data_block) - 1) * _BLOCK
            frame_bytes = _frame_bytes(reader)
            labels = _labels(reader, n_points)
        except _PARSE_ERRORS as exc:
            raise StrokeFileError(f"{path}: unreadable C3D parameters ({exc})") from None
        if data_start < 0:        # the reader would seek before the file's start (OSError)
            raise StrokeFileError(f"{path}: its header puts the frame data at block "
                                  f"{data_start // _BLOCK + 1}; C3D blocks count from 1")
        if n_points == 0:
            raise StrokeFileError(
                f"{path} has no 3D points (POINT:USED is 0); record at least one marker")
        if n_frames <= 0:
            raise StrokeFileError(f"{path} has no frames (frame count {n_frames})")
        units, to_mm = _units(reader, path)
        held = max(0, size - data_start) // frame_bytes
        if held < n_frames:
            raise StrokeFileError(
                f"{path} is truncated: its header announces {n_frames} frames, "
                f"the file holds only {held}")
        # Preallocated float32 buffers: 100k frames x 10 markers is 12 MB, not a list of frames.
        xyz = np.empty((n_frames, n_points, 3), np.float32)
        residual = np.empty((n_frames, n_points), np.float32)
        count = 0
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                for _, points, _ in reader.read_frames(copy=False, check_nan=True):
                    if count == n_frames:
                        break
                    xyz[count] = points[:, :3]
                    residual[count] = points[:, 3]
                    count += 1
        except _PARSE_ERRORS as exc:
            raise StrokeFileError(f"{path}: unreadable C3D frame data ({exc})") from None
    if count < n_frames:
        raise StrokeFileError(
            f"{path} is truncated: {count} of the announced {n_frames} frames could be read")
    valid = (residual >= 0) & np.all(np.isfinite(xyz), axis=2) & np.any(xyz != 0, axis=2)
    return _Capture(labels, xyz, valid, rate, units, to_mm, first)


def list_markers(path: Union[str, Path]) -> list[str]:
    """Marker labels of a C3D file, in file order (POINT:LABELS; blanks named POINT<i>)."""
    path = Path(path)
    if not path.is_file():
        raise StrokeFileError(f"{path}: no such C3D file")
    with open(path, "rb") as handle:
        _check_layout(path, handle)
        reader = _open_reader(path, handle)
        try:
            return list(_labels(reader, int(reader.point_used)))
        except _PARSE_ERRORS as exc:
            raise StrokeFileError(f"{path}: unreadable C3D parameters ({exc})") from None


def _runs(valid: np.ndarray) -> list[tuple[int, int]]:
    """Maximal runs of True as (first, last) indices, inclusive."""
    edges = np.diff(np.concatenate(([0], valid.astype(np.int8), [0])))
    starts = np.flatnonzero(edges == 1)
    stops = np.flatnonzero(edges == -1) - 1
    return list(zip(starts.tolist(), stops.tolist()))


def _path_length(points: np.ndarray, valid: np.ndarray) -> float:
    """Length of a marker's path over its valid frames, not bridging occluded gaps."""
    both = valid[1:] & valid[:-1]
    steps = np.linalg.norm(np.diff(points, axis=0), axis=1)
    return float(steps[both].sum())


def _choose(capture: _Capture, markers: Optional[Sequence[str]], path: Path,
            lengths: Sequence[float]) -> list[int]:
    labels = capture.labels
    if markers is None:
        best = int(np.argmax(lengths))
        if not capture.valid.any():
            raise StrokeFileError(
                f"{path} has no valid marker sample: every point is occluded, NaN or (0, 0, 0)")
        return [best]
    if isinstance(markers, str):
        markers = [markers]
    if len(markers) == 0:
        raise InvalidOptionError("markers is an empty list; give marker labels, or None for the "
                            "most-moving marker")
    folded = [s.strip().casefold() for s in labels]
    chosen: list[int] = []
    for name in markers:
        key = str(name).strip().casefold()
        if key not in folded:
            raise StrokeFileError(
                f"{path} has no marker '{name}'; available labels: {', '.join(labels)}")
        index = folded.index(key)
        if index not in chosen:
            chosen.append(index)
    return chosen


def smooth_stroke(points: FloatArray, window: int) -> FloatArray:
    """Centred moving average of `window` samples whose half-width shrinks to 0 at the ends.

    Removes tracker jitter; points[0] and points[-1] are returned unchanged, so the stroke
    ends that the boundary step (Qin & Wright step 2) snaps together do not move.
    points : (n, 3) float; window <= 1 returns a copy.
    """
    pts = np.asarray(points, dtype=np.float64)
    n = len(pts)
    half = int(window) // 2
    if half < 1 or n < 3:
        return pts.copy()
    i = np.arange(n)
    h = np.minimum(half, np.minimum(i, n - 1 - i))
    origin = pts[0]
    csum = np.vstack([np.zeros((1, 3)), np.cumsum(pts - origin, axis=0)])
    out = origin + (csum[i + h + 1] - csum[i - h]) / (2 * h + 1)[:, None]
    out[[0, -1]] = pts[[0, -1]]  # exact: the running sums would leave a rounding error
    return out


def _check_options(min_duration_s: float, min_length_mm: float, filter_mm: Optional[float],
                   smooth: int) -> None:
    for name, value in (("min_duration_s", min_duration_s), ("min_length_mm", min_length_mm)):
        if not np.isfinite(value) or value < 0:
            raise InvalidOptionError(f"{name} is {value}; it must be a finite number >= 0")
    if filter_mm is not None and (not np.isfinite(filter_mm) or filter_mm < 0):
        raise InvalidOptionError(f"filter_mm is {filter_mm}; give a distance >= 0 in mm, "
                            "0 for no filtering, or None for automatic")
    if int(smooth) != smooth or smooth < 0:
        raise InvalidOptionError(f"smooth is {smooth}; it must be a whole number of samples >= 0")


def read_c3d(
    path: Union[str, Path],
    markers: Optional[Sequence[str]] = None,
    min_duration_s: float = MIN_DURATION_S,
    min_length_mm: float = MIN_LENGTH_MM,
    filter_mm: Optional[float] = None,
    smooth: int = 0,
) -> C3DStrokes:
    """Read a C3D file into strokes with their provenance (markers, frames, dropped runs).

    markers        : labels to use (case-insensitive, stripped); None = the most-moving marker
                     (largest path length over valid frames)
    min_duration_s : runs with fewer than min_duration_s * rate samples are dropped
    min_length_mm  : runs whose path is shorter than this are dropped
    filter_mm      : the paper's 3D distance threshold (section 2); None = automatic
                     (auto_filter_threshold of the kept strokes), 0 = keep every sample
    smooth         : moving-average window in samples (0 or 1 = off); stroke ends stay fixed
    A run always needs 2 samples. Smoothing is applied to the raw samples, then filtering.
    """
    _check_options(min_duration_s, min_length_mm, filter_mm, smooth)
    path = Path(path)
    capture = _load(path)
    lengths = [_path_length(capture.marker_mm(m), capture.valid[:, m])
               for m in range(len(capture.labels))]
    chosen = _choose(capture, markers, path, lengths)
    rate = capture.frame_rate
    if min_duration_s > 0 and not (np.isfinite(rate) and rate > 0):
        raise StrokeFileError(f"{path}: POINT:RATE is {rate}, so run durations are unknown; "
                              "pass min_duration_s=0")

    kept: list[tuple[int, int, str, tuple[int, int], FloatArray]] = []
    dropped: list[DroppedRun] = []
    for order, m in enumerate(chosen):
        label = capture.labels[m]
        trajectory = capture.marker_mm(m)
        for a, b in _runs(capture.valid[:, m]):
            frames = (capture.first_frame + a, capture.first_frame + b)
            pts = trajectory[a : b + 1]
            n = len(pts)
            length = float(np.linalg.norm(np.diff(pts, axis=0), axis=1).sum())
            reason = None
            if n < 2:
                reason = "has 1 sample; a stroke needs at least 2"
            elif min_duration_s > 0 and n / rate < min_duration_s:
                reason = (f"lasts {n / rate:.3g} s ({n} frames), shorter than "
                          f"min_duration_s {min_duration_s:g} s")
            elif length < min_length_mm:
                reason = f"is {length:.3g} mm long, shorter than min_length_mm {min_length_mm:g} mm"
            if reason is not None:
                dropped.append(DroppedRun(label, frames, reason))
                continue
            kept.append((a, order, label, frames, smooth_stroke(pts, smooth)))
    kept.sort(key=lambda item: (item[0], item[1]))

    strokes = [item[4] for item in kept]
    threshold: Optional[float] = None
    if strokes and filter_mm != 0:
        threshold = float(auto_filter_threshold(strokes)) if filter_mm is None else float(filter_mm)
        if threshold > 0:
            strokes = [np.asarray(filter_stroke(s, threshold), dtype=np.float64) for s in strokes]
        else:
            threshold = None
    for s in strokes:
        s.setflags(write=False)
    return C3DStrokes(
        strokes=tuple(strokes),
        markers=tuple(item[2] for item in kept),
        frames=tuple(item[3] for item in kept),
        frame_rate=rate,
        units=capture.units,
        labels=capture.labels,
        path_mm=tuple(lengths),
        filter_mm=threshold,
        dropped=tuple(dropped),
    )


def read_c3d_strokes(path: Union[str, Path], **options: Any) -> list[np.ndarray]:
    """Strokes of a C3D file as (n, 3) float arrays in mm; the options are `read_c3d`'s
    (markers, min_duration_s, min_length_mm, filter_mm, smooth), defined there only.

    Raises StrokeFileError when no stroke is left, naming why the runs were dropped.
    """
    result = read_c3d(path, **options)
    if not result.strokes:
        why = "; ".join(f"{d.marker} frames {d.frames[0]}-{d.frames[1]} {d.reason}"
                        for d in result.dropped[:5])
        raise StrokeFileError(
            f"{path}: no stroke left: {len(result.dropped)} run(s) of valid samples, all dropped"
            + (f" ({why})" if why else " (the marker is never visible)")
            + "; lower min_duration_s or min_length_mm, or choose another marker")
    return [np.array(s) for s in result.strokes]
