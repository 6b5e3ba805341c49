"""A stroke drawn off the surface: one that misses every earlier stroke it crosses by about the
same distance, on the same side.

Qin & Wright pull the curves a new stroke misses to it (later strokes win, step (4)): the designer
reshapes by drawing over. A stroke drawn beside the surface rather than on it (lifted off it, as a
hand in the air or a pen over a tablet's depth often does) misses every curve it crosses the same
way, and pulling them to it folds a ridge or a trough along it that nobody drew. On the hand-like
sketches of `../shared/tools/sketchgen` (one stroke lifted by 1.5 % of the diagonal) that lifted
stroke was two thirds of the deviation from the truth: the median RMS deviation was 0.48 % of the
diagonal with it and 0.16 % with it left out (seed base 17000, 18 sketches).

So when a stroke misses the drawn curves it meets (the earlier strokes it crosses, and the
boundary or stroke curve a snapped end runs into) at least ``MIN_CROSSINGS`` times, all on one
side of the surface, each miss along the surface's normal within ``SPREAD`` of their mean and that
mean between ``OFF_RANGE`` snap distances (more than drawing noise, less than the distance within
which ends snap anyway), it is read as drawn off the surface: it is moved onto the curves it crosses (each miss removed where it crossed, spread linearly between
the crossings, held beyond the first and last) and added again. A stroke drawn further off than the
snap distance, or unevenly, or across fewer curves, reshapes the surface as the paper has it.
"""
from __future__ import annotations

from typing import Optional, Sequence

import numpy as np

from .folds import surface_normal_vectors
from .strokes import cumulative_length, point_at_length, segment_projections
from .types import FloatArray

NOTE_START = "it missed the "
NOTE_END = "(drawn off the surface): moved onto them"
"""An accepted stroke's note (StrokeRecord.reason) ends "...; it missed the N drawn curves it meets by
X mm alike (drawn off the surface): moved onto them" when it was moved (moved_note)."""

MIN_CROSSINGS = 2
OFF_RANGE = (0.5, 1.0)
SPREAD = 0.5


def may_be_off(misses: Sequence[tuple], snap: float) -> bool:
    """Whether the misses could say drawn off (drawn_off), by their lengths alone: the cheap test
    every stroke takes before the surface normals are looked up."""
    if len(misses) < MIN_CROSSINGS:
        return False
    size = np.linalg.norm(np.array([x[1] for x in misses], dtype=float), axis=1)
    return bool(size.mean() >= OFF_RANGE[0] * snap * (1.0 - SPREAD))


def drawn_off(misses: Sequence[tuple], normals: FloatArray, snap: float) -> Optional[float]:
    """The mean miss (mm) when the misses ((stroke point (3,), stroke point - curve point (3,)) where
    it crossed an earlier stroke curve or snapped to a drawn curve) say the stroke was drawn off the
    surface, else None. normals (k, 3): the surface's unit normal at each curve point.

    Drawn off: at least MIN_CROSSINGS misses, each along its normal on the same side, each within
    SPREAD of their mean, and the mean within OFF_RANGE snap distances. (Along the normal: a
    surface that curves turns its normal, and a stroke held off it turns its misses alike.)"""
    if len(misses) < MIN_CROSSINGS:
        return None
    m = np.array([x[1] for x in misses], dtype=float)
    along = np.einsum("ij,ij->i", m, np.asarray(normals, dtype=float))
    mean = float(along.mean())
    size = abs(mean)
    if not OFF_RANGE[0] * snap <= size <= OFF_RANGE[1] * snap:
        return None
    if np.abs(along - mean).max() > SPREAD * size:
        return None
    return size


def normals_at(net, points: FloatArray) -> FloatArray:
    """Unit normals (k, 3) of the network's surface at its points nearest `points` (k, 3) (their
    footpoints), from folds.surface_normal_vectors. (Not at the pre-image point where the stroke met the
    curve: on a 3-sided patch that can be the collapsed apex, where no normal is defined; a8fdf73
    tried it and the octants' deviation from the truth went from 0.17-0.19 to 0.49-0.59 % on two
    sketches of seed base 17000.)"""
    uv = np.array([net.footpoint(np.asarray(p, dtype=float)).uv for p in points], dtype=float)
    n = surface_normal_vectors(net, uv)
    return n / np.maximum(np.linalg.norm(n, axis=1), 1e-300)[:, None]


def _nearest(pts: FloatArray, run: FloatArray, p: FloatArray) -> tuple[FloatArray, float]:
    """The point of the polyline pts (n, 3) nearest p (3,), and its arc length (run: pts'
    cumulative_length)."""
    w, d = segment_projections(np.asarray(p, dtype=float)[None, :], pts)
    k = int(d[0].argmin())
    return pts[k] + w[0, k] * (pts[k + 1] - pts[k]), float(run[k] + w[0, k] * (run[k + 1] - run[k]))


def as_drawn(pts: FloatArray, misses: Sequence[tuple], reach: float) -> list:
    """The misses measured from the stroke as drawn, pts (n, 3): a crossing's stroke point is on the
    stroke as inserted, whose snapped ends already run into their snap points (stroke_ends.run_into),
    so its miss is short by that ramp there. Each (p, v) becomes (q, m): q the point of pts nearest
    p, m = q - (p - v) across the stroke (its part along the stroke's direction at q left out: an
    end that stops short of a curve or runs over it misses it along the stroke, not off the
    surface). The stroke's direction at q is its chord over `reach` (mm) on either side of q,
    steadier than one segment of a jittery stroke."""
    pts = np.asarray(pts, dtype=float)
    run = cumulative_length(pts)
    out = []
    for p, v in misses:
        q, at = _nearest(pts, run, p)
        a, b = point_at_length(pts, [at - reach, at + reach], run)
        m = q - (np.asarray(p, dtype=float) - np.asarray(v, dtype=float))
        chord = b - a
        length = float(np.linalg.norm(chord))
        if length > 0.0:
            m = m - (m @ chord) / length**2 * chord
        out.append((q, m))
    return out


def onto_crossings(pts: FloatArray, misses: Sequence[tuple],
                   normals: Optional[FloatArray] = None) -> FloatArray:
    """pts (n, 3) moved onto the curves it crossed: at each crossing (the stroke point nearest it)
    by minus its miss (its part along the surface normal there, with normals (k, 3)), linearly in
    arc length between crossings, by the first and last miss beyond."""
    pts = np.asarray(pts, dtype=float)
    run = cumulative_length(pts)
    at, shift = [], []
    for p, v in misses:
        at.append(_nearest(pts, run, p)[1])
        shift.append(-np.asarray(v, dtype=float))
    if normals is not None:
        normals = np.asarray(normals, dtype=float)
        shift = [n * float(v @ n) for v, n in zip(shift, normals)]
    order = np.argsort(at, kind="stable")
    at, shift = np.asarray(at)[order], np.asarray(shift)[order]
    move = np.column_stack([np.interp(run, at, shift[:, c]) for c in range(3)])
    return pts + move


def end_misses(net, pts: FloatArray, snaps: Sequence) -> list:
    """The misses of a stroke's snapped ends (stroke_ends.trim_ends: (j, edge, t, snap point) or
    None per end) whose edge is a drawn curve (the boundary's or a stroke's): (the stroke's point
    nearest the snap point (3,), that point - the snap point (3,))."""
    out = []
    edges = net.edges()
    run = cumulative_length(pts)
    for sn in snaps:
        if sn is None or net.curve_info(edges[sn[1]].curve_id)["kind"] not in ("outer", "stroke"):
            continue
        target = np.asarray(sn[3], dtype=float)
        q, _ = _nearest(pts, run, target)
        out.append((q, q - target))
    return out


def note(count: int, off_mm: float) -> str:
    """The part of an accepted stroke's note that says it was moved onto the surface."""
    return f"{NOTE_START}{count} drawn curves it meets by {off_mm:.3g} mm alike {NOTE_END}"


def moved_note(reason: str) -> Optional[str]:
    """The "it missed ... moved onto them" part of a stroke's note, or None when it was not moved."""
    if not reason.endswith(NOTE_END) or NOTE_START not in reason:
        return None
    return reason[reason.rindex(NOTE_START):]
