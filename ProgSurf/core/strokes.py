"""Strokes: validation, the paper's distance filter, and small polyline helpers.

A stroke is an ordered (n, 3) float array in millimetres (Qin & Wright, section 2: "3D sketch points").
Nothing here modifies its input in place.
"""
from __future__ import annotations

from typing import Sequence

import numpy as np
import numpy.typing as npt

from .errors import DegenerateSketchError, InvalidOptionError, InvalidStrokeError
from .types import FloatArray

AUTO_FILTER_FRACTION = 0.005
"""Automatic filter threshold as a fraction of the sketch diagonal (see `auto_filter_threshold`)."""

AUTO_FILTER_STROKE_FRACTION = 0.05
"""... but never more than this fraction of the median stroke length."""

ROUND_FRACTION = 1e-7
"""Stroke points are rounded (round_points) to the power of ten at or below this fraction of the
fit tolerance: 1e-9 mm for the bundled examples (fit tolerance 0.014 mm), 1e-6 mm for the same
sketch drawn 1000 times larger."""


def round_points(points: npt.ArrayLike, tol_mm: float) -> FloatArray:
    """Points rounded to the power of ten at or below ROUND_FRACTION * tol_mm (the fit tolerance),
    so that a save/reopen round trip (last-bit differences) fairs the same, at any scale (a fixed
    1e-9 mm is nothing on a 1 m sketch and a visible step on a 0.1 mm one). tol_mm not positive:
    the points unrounded."""
    pts = np.asarray(points, dtype=float)
    if not (np.isfinite(tol_mm) and tol_mm > 0):
        return pts
    # (+1e-6: a tolerance that is a power of ten up to round-off, such as 0.01, rounds as that power)
    decimals = -int(np.floor(np.log10(ROUND_FRACTION * tol_mm) + 1e-6))
    return np.round(pts, decimals)


def validate_stroke(points: npt.ArrayLike, index: int) -> FloatArray:
    """Return a float64 copy of stroke `index` as an (n, 3) array, or raise InvalidStrokeError.

    points : (n, 3) array-like, millimetres, n >= 2, all coordinates finite.
    index  : the stroke's position in the input, used only in the error message.
    """
    try:
        arr = np.array(points, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InvalidStrokeError(
            f"stroke {index} is not an array of numbers ({exc}); give an (n, 3) array of x y z in mm"
        ) from None
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise InvalidStrokeError(
            f"stroke {index} has shape {arr.shape}; a stroke must be an (n, 3) array of x y z points"
        )
    n = arr.shape[0]
    if n < 2:
        raise InvalidStrokeError(
            f"stroke {index} has {n} point{'s' if n != 1 else ''}; a stroke needs at least 2"
        )
    bad = ~np.isfinite(arr).all(axis=1)
    if bad.any():
        first = int(np.flatnonzero(bad)[0])
        raise InvalidStrokeError(
            f"stroke {index} has {int(bad.sum())} point(s) with NaN or infinite coordinates "
            f"(first at point {first}: {arr[first].tolist()}); remove or repair them"
        )
    return arr


def chord_length(points: npt.ArrayLike) -> float:
    """Total chord length of a polyline: the sum of |p[i+1] - p[i]| (the paper's "total chord length")."""
    pts = np.asarray(points, dtype=float)
    if pts.shape[0] < 2:
        return 0.0
    # (summed as cumulative_length sums, so that a stroke's length is the last of its cumulative
    # lengths to the bit: a mark at one end, s == length, then cuts the piece beside it the same
    # whichever way the sketch is turned; np.sum's pairwise rounding differed in the last bits)
    return float(np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))[-1])


def cumulative_length(points: npt.ArrayLike) -> FloatArray:
    """Arc length at each point of a polyline: (n,) float starting at 0."""
    pts = np.asarray(points, dtype=float)
    seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    return np.concatenate([[0.0], np.cumsum(seg)])


APEX_TIE_DEG = 10.0
"""A 3-sided region (and a 3-sided boundary) collapses at its sharpest 3D corner when that is
this much sharper than the corner the pre-image or the loop order would pick, else at the latter."""


def corner_angle_deg(a: npt.ArrayLike, b: npt.ArrayLike, reach: float = 0.1) -> float:
    """The angle (deg) at the common first point of polylines a and b (n, 3) between their
    chords to the point at `reach` of each one's length (not their first segments, so jitter or a
    hook at the corner does not decide); 180 where either has no length."""
    dirs = []
    for p in (np.asarray(a, dtype=float), np.asarray(b, dtype=float)):
        cum = cumulative_length(p)
        # (point_at_length of one length; min/max clamp one value as np.clip does, without its
        # checks, which cost more than the rest: this runs for every corner of every new triangle)
        at = min(max(reach * cum[-1], 0.0), cum[-1])
        d = np.array([np.interp(at, cum, p[:, k]) for k in range(p.shape[1])]) - p[0]
        n = float(np.linalg.norm(d))
        if not n > 0:
            return 180.0
        dirs.append(d / n)
    return float(np.degrees(np.arccos(min(max(dirs[0] @ dirs[1], -1.0), 1.0))))


RAMP_SLOPE = 0.05
"""An offset given to a stroke's end (a boundary stroke's end moved to its corner, the closing; an
interior stroke's cut end moved to its snap point, step (2)) is spread over the stroke's last
stretch, |offset| / RAMP_SLOPE long (at most a third of the stroke), instead of a jump in its last
segment (a hook)."""


def ramp(dist: FloatArray, delta: FloatArray, total: float) -> FloatArray | None:
    """The offsets (n, 3) that move stroke points at arc length dist (n,) from one end by delta (3,)
    there, fading to none at min(|delta| / RAMP_SLOPE, total / 3) along the stroke (total: its
    length) by a smoothstep, so that the stroke's slope has no jump where the ramp starts.
    None when there is nothing to spread (delta 0, or no length to spread it over)."""
    delta = np.asarray(delta, dtype=float)
    size = float(np.linalg.norm(delta))
    if size <= 0:
        return None
    reach = min(size / RAMP_SLOPE, total / 3.0)
    if not reach > 0:
        return None
    w = np.clip(1.0 - dist / reach, 0.0, 1.0)
    return (w * w * (3.0 - 2.0 * w))[:, None] * delta


def point_at_length(points: npt.ArrayLike, s: npt.ArrayLike, cum: FloatArray | None = None) -> FloatArray:
    """Point(s) at arc length s along a polyline (clamped to its ends); returns (..., d).
    cum: cumulative_length(points), when the caller has it already."""
    pts = np.asarray(points, dtype=float)
    return _point_at(pts, cumulative_length(pts) if cum is None else cum, s)


def _point_at(pts: FloatArray, cum: FloatArray, s: npt.ArrayLike) -> FloatArray:
    """point_at_length of pts (n, d) whose cumulative_length is cum (n,)."""
    s = np.minimum(np.maximum(np.asarray(s, dtype=float), 0.0), cum[-1])     # (np.clip, without its overhead)
    return np.stack([np.interp(s, cum, pts[:, k]) for k in range(pts.shape[1])], axis=-1)


def segment_projections(points: npt.ArrayLike, polyline: npt.ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Every point projected onto every segment of a polyline: the clamped segment parameter
    w (k, m) in [0, 1] and the distance d (k, m), for k points and m segments."""
    pts = np.asarray(points, dtype=float)
    poly = np.asarray(polyline, dtype=float)
    a, ab = poly[:-1], np.diff(poly, axis=0)
    ll = np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300)
    w = np.clip(np.einsum("kij,ij->ki", pts[:, None, :] - a[None], ab) / ll, 0.0, 1.0)
    d = np.linalg.norm(a[None] + w[..., None] * ab[None] - pts[:, None, :], axis=2)
    return w, d


def sketch_diagonal(points: npt.ArrayLike) -> float:
    """Diagonal of the bounding box of `points` (n, 3) in its own principal axes.

    Unlike an axis-aligned box this does not change when the sketch is rotated, so every
    tolerance derived from it is invariant under rigid motions and scales with the sketch.
    """
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    if pts.shape[0] < 2:
        return 0.0
    centred = pts - pts.mean(axis=0)
    _, _, vt = np.linalg.svd(centred, full_matrices=False)
    local = centred @ vt.T
    return float(np.linalg.norm(local.max(axis=0) - local.min(axis=0)))


def _filter_from_start(pts: FloatArray, threshold: float) -> FloatArray:
    """The paper's greedy filter run from the first point (see filter_stroke)."""
    n = pts.shape[0]
    if n <= 2:
        return pts
    keep = [0]
    last = pts[0]
    for i in range(1, n - 1):
        if np.linalg.norm(pts[i] - last) >= threshold:
            keep.append(i)
            last = pts[i]
    if len(keep) > 1 and np.linalg.norm(pts[-1] - last) < threshold:
        keep.pop()
    keep.append(n - 1)
    return pts[keep]


def filter_stroke(points: npt.ArrayLike, threshold: float) -> FloatArray:
    """Qin & Wright, section 2: drop sketch points closer than `threshold` (mm, 3D distance)
    to the last kept point. The first and the last point are always kept; when the last point
    falls within `threshold` of the last kept interior point, that interior point gives way to it
    so that no segment is shorter than needed.

    The filter runs from both ends towards the stroke's middle point (for an even number of
    points, the two middle points, or the point halfway between them when they are closer than
    the threshold), which is kept: a stroke drawn the other way keeps the same
    points, so the direction of drawing does not change the surface (issue 17; run from the first
    point only, it kept another subset of a rough stroke, and the fair curve through it moved the
    rough4 example's surface by 26 times the fit tolerance). Only the gaps next to the middle
    point(s) may be shorter than the threshold.

    points : (n, 3) float, n >= 1.  Returns a new (m, 3) array, m <= n: input points, in order,
    but for that one halfway point.
    """
    if not np.isfinite(threshold) or threshold < 0:
        raise InvalidOptionError(
            f"filter threshold {threshold!r} mm is invalid; give a finite distance >= 0 (or None for automatic)"
        )
    pts = np.array(points, dtype=float).reshape(-1, 3)
    n = pts.shape[0]
    if n <= 2:
        return pts
    h = n // 2
    if n % 2 == 0 and np.linalg.norm(pts[h] - pts[h - 1]) < threshold:
        # two middle points closer than the threshold: one point between them, on the stroke
        pts = np.vstack([pts[:h], 0.5 * (pts[h - 1] + pts[h]), pts[h:]])
        n += 1
    if n % 2:
        head = _filter_from_start(pts[:h + 1], threshold)
        tail = _filter_from_start(pts[h:][::-1], threshold)[::-1]
        return np.vstack([head, tail[1:]])
    return np.vstack([_filter_from_start(pts[:h], threshold), _filter_from_start(pts[h:][::-1], threshold)[::-1]])


def auto_filter_threshold(strokes: Sequence[npt.ArrayLike]) -> float:
    """The filter threshold chosen from the sketch's size (the paper: "determined by experiments and
    related to surface size").

    threshold = min(0.5 % of the sketch diagonal, 5 % of the median stroke length).

    Why: 0.5 % of the diagonal keeps at most ~200 points across the sketch, enough to resolve any
    shape feature larger than ~1 % of the part, while removing the dense clusters a motion-capture
    system records when the hand slows down (fixed capture rate, varying speed: section 2).  Hand
    noise of free 3D sketching is typically 0.5-2 % of the sketch size, so nothing real is lost.  The
    second bound keeps a typical stroke at >= ~20 points when strokes are short compared with the
    sketch (e.g. many small guide curves), so corners and ends stay well sampled.

    Raises DegenerateSketchError when all points coincide.
    """
    arrays = [np.asarray(s, dtype=float).reshape(-1, 3) for s in strokes]
    arrays = [a for a in arrays if a.shape[0] > 0]
    if not arrays:
        raise DegenerateSketchError("the sketch has no points; give at least one stroke with 2 or more points")
    allpts = np.concatenate(arrays)
    if not np.isfinite(allpts).all():
        raise InvalidStrokeError("the sketch has NaN or infinite coordinates; repair the strokes first")
    diag = sketch_diagonal(allpts)
    if not diag > 0:
        raise DegenerateSketchError(
            f"all {allpts.shape[0]} points of the sketch coincide at {allpts[0].tolist()}; "
            "there is nothing to build a surface from"
        )
    lengths = [chord_length(a) for a in arrays if a.shape[0] >= 2]
    lengths = [x for x in lengths if x > 0]
    threshold = AUTO_FILTER_FRACTION * diag
    if lengths:
        threshold = min(threshold, AUTO_FILTER_STROKE_FRACTION * float(np.median(lengths)))
    return float(threshold)


def resample_arclength(points: npt.ArrayLike, n: int, cum: FloatArray | None = None) -> FloatArray:
    """n points equally spaced in arc length along a polyline, first and last kept exactly.
    cum: cumulative_length(points), when the caller has it already.

    An optional alternative to the paper's midpoint insertion (`boundary.equalise`).
    """
    if int(n) != n or n < 2:
        raise InvalidOptionError(f"cannot resample to {n!r} points; give an integer >= 2")
    pts = np.asarray(points, dtype=float)
    cum = cumulative_length(pts) if cum is None else cum
    # (its last is chord_length(pts) to the bit)
    out = _point_at(pts, cum, np.linspace(0.0, cum[-1], int(n)))
    out[0], out[-1] = pts[0], pts[-1]
    return out
