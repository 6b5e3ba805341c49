"""From an unordered set of rough strokes to a closed four-sided boundary loop.

Qin & Wright (2006, "Progressive surface modelling from unorganised curves"), section 2.1, and the
motion-sketch paper, section 2 (Fig. 2: boundary search and closing; Fig. 3: merge; Fig. 4: three
sides):

1. project all strokes onto their best-fit plane (`best_fit_plane`), not a fixed XY plane;
2. classify boundary vs interior strokes by rays from the centroid of the projection: the furthest
   stroke a ray hits is a boundary stroke (`classify_strokes`, Fig. 2a);
3. order and orient the boundary strokes into one loop, cut crossing strokes at their intersection
   and extend short ends in the projection plane until they meet; the corner is the 3D midpoint
   (`close_boundary`, Fig. 2b);
4. merge adjacent sides of closest chord orientation until four are left, ties to the shortest
   total chord length; three sides get a degenerate fourth (`merge_to_four`, Fig. 4);
5. give opposite sides equal point counts by inserting midpoints on the longest chord (`equalise`).

`make_boundary` runs all of it and returns a `BoundaryLoop` oriented for the Coons patch of Eq. (1).
The 2D geometry of steps 2-3 lives in `closing.py`.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

from .fairing import fair_stroke, stroke_tolerance
from .closing import ClosedSide, close_loop, project
from .errors import DegenerateSketchError, InvalidOptionError, OpenBoundaryError
from .strokes import (APEX_TIE_DEG, auto_filter_threshold, chord_length, corner_angle_deg, filter_stroke,
                      resample_arclength, round_points, sketch_diagonal, validate_stroke)
from .types import FloatArray, Tolerances

__all__ = ["Plane", "BoundaryLoop", "best_fit_plane", "classify_strokes", "close_boundary",
           "merge_to_four", "triangle_apex", "turn_to_apex", "apex_holds", "stroke_end_pairs", "equalise",
           "resample_arclength", "make_boundary"]

N_RAYS = 720
"""Rays cast from the centroid in `classify_strokes` (one every half degree)."""

MIN_RAY_HITS = 2
"""A boundary stroke is the furthest hit of at least this many rays ..."""

MIN_FURTHEST_FRACTION = 0.5
"""... and of at least this fraction of the rays that hit it at all.  An interior stroke seen through
a gap at a corner is the furthest only for the few rays that slip through the gap, while it is hit
(in front of the boundary) by every ray across its angular extent; a boundary stroke is the furthest
for nearly all the rays that hit it."""

TIE_RAD = 1e-6
"""Orientation differences closer than this are a tie in the merge criterion (2006, step 3)."""


@dataclass(frozen=True)
class Plane:
    """The projection plane.

    origin : (3,) float, the centroid of the points
    normal : (3,) float, unit
    axes   : (2, 3) float, orthonormal in-plane axes with axes[0] x axes[1] = normal
    """

    origin: FloatArray
    normal: FloatArray
    axes: FloatArray

    def __post_init__(self) -> None:
        for name, shape in (("origin", (3,)), ("normal", (3,)), ("axes", (2, 3))):
            arr = np.array(getattr(self, name), dtype=float).reshape(shape)
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)

    def project(self, points: npt.ArrayLike) -> FloatArray:
        """In-plane coordinates of (..., 3) points: (..., 2)."""
        return project(points, self.origin, self.axes)

    def flipped(self) -> "Plane":
        """The same plane with the opposite normal (axes[1] reversed to stay right-handed)."""
        return Plane(self.origin, -self.normal, np.stack([self.axes[0], -self.axes[1]]))


def best_fit_plane(points: npt.ArrayLike) -> Plane:
    """Least-squares plane of (n, 3) points by SVD of the centred points.

    The normal is the singular vector of the smallest singular value.  Raises DegenerateSketchError
    when the points coincide or lie on one line (no plane to project on).
    """
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    if pts.shape[0] == 0 or not np.isfinite(pts).all():
        raise DegenerateSketchError("the sketch has no finite points; give strokes with x y z coordinates")
    origin = pts.mean(axis=0)
    centred = pts - origin
    _, sv, vt = np.linalg.svd(centred, full_matrices=False)
    scale = float(np.abs(centred).max())
    if pts.shape[0] < 2 or sv[0] <= 1e-12 * max(scale, 1e-300) or scale == 0.0:
        raise DegenerateSketchError(
            f"all {pts.shape[0]} points of the sketch coincide at {origin.round(6).tolist()}; "
            "draw strokes that span a surface"
        )
    if pts.shape[0] < 3 or sv[1] <= 1e-9 * sv[0]:
        raise DegenerateSketchError(
            f"all {pts.shape[0]} points of the sketch lie on one line (direction {vt[0].round(4).tolist()}); "
            "a surface needs strokes that span two directions"
        )
    a0 = vt[0] * (1.0 if vt[0][np.argmax(np.abs(vt[0]))] > 0 else -1.0)
    normal = vt[2] * (1.0 if vt[2][np.argmax(np.abs(vt[2]))] > 0 else -1.0)
    a1 = np.cross(normal, a0)
    return Plane(origin, normal, np.stack([a0, a1]))


def classify_strokes(
    strokes: Sequence[npt.ArrayLike], plane: Plane, n_rays: int = N_RAYS, min_hits: int = MIN_RAY_HITS,
    min_fraction: float = MIN_FURTHEST_FRACTION,
) -> tuple[list[int], list[int]]:
    """Boundary and interior stroke indices (motion-sketch paper, section 2, Fig. 2a).

    Rays are cast from the centroid of the projected points at `n_rays` equal angles; the stroke
    with the furthest intersection along a ray is a boundary candidate; candidates that are the
    furthest for at least `min_hits` rays and for at least `min_fraction` of the rays crossing them
    are boundary strokes, all others interior.
    """
    arrays = [np.asarray(s, dtype=float).reshape(-1, 3) for s in strokes]
    uv = [plane.project(a) for a in arrays]
    allpts = np.concatenate(uv) if uv else np.zeros((0, 2))
    if allpts.shape[0] == 0:
        raise DegenerateSketchError("no strokes to classify; give at least three boundary strokes")
    centre = allpts.mean(axis=0)
    starts = np.concatenate([u[:-1] for u in uv if u.shape[0] > 1] or [np.zeros((0, 2))])
    ends = np.concatenate([u[1:] for u in uv if u.shape[0] > 1] or [np.zeros((0, 2))])
    owner = np.concatenate([np.full(u.shape[0] - 1, i) for i, u in enumerate(uv) if u.shape[0] > 1]
                           or [np.zeros(0, int)])
    theta = 2.0 * np.pi * (np.arange(n_rays) + 0.5) / n_rays
    dirs = np.stack([np.cos(theta), np.sin(theta)], axis=1)
    hits = np.zeros(len(arrays), dtype=int)
    crossed = np.zeros(len(arrays), dtype=int)
    if starts.shape[0]:
        e = ends - starts  # (M, 2)
        w = starts - centre
        with np.errstate(divide="ignore", invalid="ignore"):
            den = dirs[:, None, 0] * e[None, :, 1] - dirs[:, None, 1] * e[None, :, 0]  # (K, M)
            t = (w[None, :, 0] * e[None, :, 1] - w[None, :, 1] * e[None, :, 0]) / den
            s = (w[None, :, 0] * dirs[:, None, 1] - w[None, :, 1] * dirs[:, None, 0]) / den
        ok = np.isfinite(t) & np.isfinite(s) & (t > 0) & (s >= 0) & (s <= 1)
        t = np.where(ok, t, -np.inf)
        best = np.argmax(t, axis=1)
        hit_rays = np.isfinite(t[np.arange(n_rays), best])
        np.add.at(hits, owner[best[hit_rays]], 1)
        for i in range(len(arrays)):
            crossed[i] = int(ok[:, owner == i].any(axis=1).sum())
    boundary = [i for i in range(len(arrays))
                if hits[i] >= min_hits and hits[i] >= min_fraction * crossed[i]]
    if not boundary:
        boundary = [i for i in range(len(arrays)) if hits[i] > 0]
    if not boundary:
        raise OpenBoundaryError(
            "no stroke surrounds the centre of the sketch, so no boundary was found; "
            "draw the boundary strokes around the surface or name them explicitly"
        )
    interior = [i for i in range(len(arrays)) if i not in set(boundary)]
    return boundary, interior


def close_boundary(
    strokes_3d: Sequence[npt.ArrayLike], plane: Plane, tol: Tolerances = Tolerances(),
    diagonal: Optional[float] = None,
) -> list[FloatArray]:
    """The boundary strokes as one closed, oriented loop of sides (Fig. 2b); see `closing.close_loop`.

    strokes_3d : boundary strokes, (n_i, 3) each, any order and direction
    diagonal   : sketch diagonal for the gap limit (default: that of these strokes)
    Returns the sides in loop order; side k ends exactly where side k+1 starts.
    """
    arrays = [validate_stroke(s, i) for i, s in enumerate(strokes_3d)]
    if diagonal is None:
        diagonal = sketch_diagonal(np.concatenate(arrays)) if arrays else 0.0
    sides, _ = close_loop(arrays, list(range(len(arrays))), plane, tol, diagonal)
    return [s.points.copy() for s in sides]


def _chord_angle(side: FloatArray, plane: Plane) -> float:
    chord = plane.project(side[-1]) - plane.project(side[0])
    return float(np.arctan2(chord[1], chord[0]))


def _merge_groups(sides: Sequence[FloatArray], plane: Plane) -> tuple[list[list[int]], list[str]]:
    """2006 paper, section 2.1 steps (1)-(4) as groups of consecutive side indices (cyclic)."""
    groups = [[i] for i in range(len(sides))]
    pts = [np.asarray(s, dtype=float) for s in sides]
    notes = []
    while len(groups) > 4:
        comp = [np.concatenate([pts[i] for i in g]) for g in groups]
        ang = [_chord_angle(np.stack([pts[g[0]][0], pts[g[-1]][-1]]), plane) for g in groups]
        length = [chord_length(c) for c in comp]
        m = len(groups)
        diff = [abs((ang[(k + 1) % m] - ang[k] + np.pi) % (2 * np.pi) - np.pi) for k in range(m)]
        best = min(diff)
        tied = [k for k in range(m) if diff[k] - best <= TIE_RAD]
        k = min(tied, key=lambda k: (min(length[k], length[(k + 1) % m]), length[k] + length[(k + 1) % m]))
        j = (k + 1) % m
        notes.append(f"merged sides of strokes {groups[k]} and {groups[j]}: chord orientations differ by "
                     f"{np.degrees(diff[k]):.1f} deg, the closest of {m} sides")
        merged = groups[k] + groups[j]
        if j == 0:
            groups = [merged] + groups[1:k]
        else:
            groups = groups[:k] + [merged] + groups[j + 1:]
    return groups, notes


def _join(parts: Sequence[FloatArray]) -> FloatArray:
    """Concatenate sides that meet end to start, dropping the shared points."""
    out = [np.asarray(parts[0], dtype=float)]
    out += [np.asarray(p, dtype=float)[1:] for p in parts[1:]]
    return np.concatenate(out)


APEX_NEAR = 0.05
"""A stroke end within this fraction of a 3-sided loop's longest side from a corner, or aimed at
it that closely, reaches the corner (triangle_apex)."""
APEX_FAR = 0.4
"""A stroke end this fraction of the longest side or more from a corner leaves it alone."""


def triangle_apex(sides: Sequence[npt.ArrayLike], ends: Optional[npt.ArrayLike] = None) -> int:
    """The corner a 3-sided loop collapses at (Fig. 4), as the index i of the side it ends
    (sides in loop order, side i ending at corner i where side i+1 starts).

    By geometry alone, so that neither the order nor the direction in which the sides were drawn
    changes the surface (issue 17). The candidates are the corners within APEX_TIE_DEG of the
    sharpest: a Coons triangle collapsed anywhere else squeezes a sharp corner between a regular
    bottom and side, and turns over there. Among them, the most strokes that end at the corner
    (within APEX_NEAR of it: the curves of a pole, such as an octant's meridians, meet where the
    triangle collapses), then the fewest near misses, then the longest opposite side (by chord). `ends` are the interior strokes' ends, (k, 2, 3): each end point and
    a point a little inside its stroke. A near miss is an end that heads for the corner and stops
    near it (closer than APEX_FAR of the longest side) without reaching it: neither within
    APEX_NEAR of it nor aimed at it that closely. Extended to the loop, such a stroke cuts a sliver off the collapsed
    corner, where the patch's parametrisation degenerates, and folds it (on `three_sided`, a
    stroke along the bottom that ends 0.24 of a side from a lower corner); a stroke that runs
    into the apex is an isoparametric line of the triangle and does no harm."""
    pts = [np.asarray(s, dtype=float).reshape(-1, 3) for s in sides]
    angles = np.array([corner_angle_deg(pts[i][::-1], pts[(i + 1) % 3]) for i in range(3)])
    chords = np.array([float(np.linalg.norm(p[-1] - p[0])) for p in pts])
    opposite = chords[[(i + 2) % 3 for i in range(3)]]        # corner i joins sides i and i+1
    candidates = [i for i in range(3) if angles[i] <= angles.min() + APEX_TIE_DEG]
    if len(candidates) == 1:
        return candidates[0]
    size = float(chords.max())
    pairs = np.asarray(ends if ends is not None else np.zeros((0, 2, 3)), dtype=float).reshape(-1, 2, 3)

    def hits_and_misses(i: int) -> tuple[int, int]:
        corner = pts[i][-1]
        to_corner = corner - pairs[:, 0]
        dist = np.linalg.norm(to_corner, axis=1)
        out = pairs[:, 0] - pairs[:, 1]
        out /= np.maximum(np.linalg.norm(out, axis=1), 1e-300)[:, None]
        along = np.einsum("ij,ij->i", to_corner, out)
        miss = np.linalg.norm(to_corner - along[:, None] * out, axis=1)
        hits = int(np.sum(dist <= APEX_NEAR * size))
        return -hits, int(np.sum((along > 0) & (dist < APEX_FAR * size) & (dist > APEX_NEAR * size)
                                 & (miss > APEX_NEAR * size)))

    # an exact tie (a triangle drawn by a program) keeps the loop's own corner after sides[1]
    return min(candidates, key=lambda i: (*hits_and_misses(i), -opposite[i], i != 1))


def merge_to_four(sides: Sequence[npt.ArrayLike], plane: Optional[Plane] = None,
                  apex: Optional[int] = None) -> list[FloatArray]:
    """N sides of a closed loop (in loop order, each ending where the next starts) to exactly four.

    More than four: Qin & Wright 2006, section 2.1: repeatedly merge the two adjacent sides whose
    chord directions (in the projection plane) differ least; ties go to the pair holding the curve
    with the shortest total chord length.  Three sides: a degenerate side (one point repeated) is
    inserted after sides[1], so that the result reads bottom, right, top (degenerate), left-reversed
    with c3 == c2 (Fig. 4: F(u,1) = F1); the loop is first turned so that the corner after
    sides[1] is `apex`, by default `triangle_apex(sides)` (callers that keep per-side data choose
    it, with the interior strokes' ends, and turn that data the same way: `turn_to_apex`).  Four:
    returned as copies.  Fewer than three: OpenBoundaryError.
    """
    pts = [np.array(s, dtype=float).reshape(-1, 3) for s in sides]
    if len(pts) < 3:
        raise OpenBoundaryError(f"a boundary of {len(pts)} side(s) cannot bound a surface; it needs 3 or more")
    if len(pts) == 3:
        pts = turn_to_apex(pts, triangle_apex(pts) if apex is None else apex)
        tip = pts[1][-1]
        return [pts[0], pts[1], np.stack([tip, tip]), pts[2]]
    if plane is None:
        plane = best_fit_plane(np.concatenate(pts))
    groups, _ = _merge_groups(pts, plane)
    return [_join([pts[i] for i in g]) for g in groups]


def turn_to_apex(items: Sequence, apex: int) -> list:
    """The three per-side items of a 3-sided loop turned so that corner `apex` comes after item 1."""
    return [items[(apex - 1 + k) % 3] for k in range(3)]


def equalise(a: npt.ArrayLike, b: npt.ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Opposite sides with equal point counts (2006, section 2.1): points are added to the side with
    fewer, each at the middle of its currently longest chord, one at a time.  All original points are
    kept in order; returns new arrays."""
    a2 = np.array(a, dtype=float).reshape(-1, 3)
    b2 = np.array(b, dtype=float).reshape(-1, 3)
    swap = a2.shape[0] > b2.shape[0]
    short, long_ = (b2, a2) if swap else (a2, b2)
    if short.shape[0] < 2 and short.shape[0] < long_.shape[0]:
        short = np.repeat(short[:1], 2, axis=0) if short.shape[0] else short
    while 2 <= short.shape[0] < long_.shape[0]:
        chords = np.linalg.norm(np.diff(short, axis=0), axis=1)
        # the first of the longest chords; lengths equal to rounding count as equal (halves of a split
        # chord), so the choice does not change under a rigid motion of the sketch
        k = int(np.flatnonzero(chords >= chords.max() * (1.0 - 1e-9))[0])
        short = np.insert(short, k + 1, 0.5 * (short[k] + short[k + 1]), axis=0)
    return (long_, short) if swap else (short, long_)


@dataclass(frozen=True)
class BoundaryLoop:
    """Four boundary sides oriented for the Coons patch of Eq. (1).

    bottom : (n, 3) P(u,0), corner c0 -> c1      right : (m, 3) P(1,v), c1 -> c2
    top    : (n, 3) P(u,1), corner c3 -> c2      left  : (m, 3) P(0,v), c0 -> c3
    Corners are shared exactly; a triangle has top = n copies of c2 (== c3).
    plane  : the projection plane, its normal oriented so the loop bottom, right, top, left runs
             counter-clockwise around it (normal ~ dP/du x dP/dv)
    source : input stroke indices making up (bottom, right, top, left)
    notes  : what was cut, extended, split and merged, in order
    used   : {input stroke index: [(k, 3) arrays]}: the pieces of each boundary stroke kept in the
             loop (faired, over-sketch trimmed, before any gap extension is added to them)
    params : per side, its points' parameters (0..1) on the unit square's side, or () (by point
             index, the paper's mapping): a whole object's loop (boundary_from_sides) maps its sides
             by arc length along the curves they were cut from, which two surfaces share
             (cad.shared_edges fits each curve once, by that arc length)
    """

    bottom: FloatArray
    right: FloatArray
    top: FloatArray
    left: FloatArray
    plane: Plane
    source: tuple[tuple[int, ...], ...] = ()
    notes: tuple[str, ...] = field(default=())
    used: dict = field(default_factory=dict, compare=False)
    params: tuple = field(default=(), compare=False)

    def side_params(self) -> tuple:
        """Per side, its points' parameters (params), or None (by index)."""
        return tuple(self.params) if self.params else (None,) * 4

    def __post_init__(self) -> None:
        for name in ("bottom", "right", "top", "left"):
            arr = np.array(getattr(self, name), dtype=float).reshape(-1, 3)
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)
        object.__setattr__(self, "source", tuple(tuple(int(i) for i in s) for s in self.source))
        object.__setattr__(self, "notes", tuple(str(n) for n in self.notes))

    @property
    def corners(self) -> FloatArray:
        """(4, 3) c0, c1, c2, c3."""
        return np.stack([self.bottom[0], self.bottom[-1], self.top[-1], self.top[0]])

    @property
    def triangle(self) -> bool:
        """True when the top side is degenerate (three-sided boundary, Fig. 4)."""
        return bool(np.all(self.top == self.top[0]))

    @property
    def sides(self) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        return self.bottom, self.right, self.top, self.left


def _pieces_at_corners(points: FloatArray, degrees: float = 20.0) -> list[int]:
    """Indices where a side turns by more than `degrees` at one vertex (stroke junctions of a merged
    side, cut or extended corners), with both ends: these vertices are kept by `equalise_uniform`."""
    a = points[1:-1] - points[:-2]
    b = points[2:] - points[1:-1]
    la, lb = np.linalg.norm(a, axis=1), np.linalg.norm(b, axis=1)
    cos = np.einsum("ij,ij->i", a, b) / np.maximum(la * lb, 1e-300)
    sharp = np.flatnonzero((cos < np.cos(np.radians(degrees))) & (la > 0) & (lb > 0)) + 1
    return [0] + [int(i) for i in sharp] + [len(points) - 1]


def _resample_keeping_corners(points: FloatArray, n: int, keep: Sequence[int] = ()) -> FloatArray:
    """n points evenly spaced in arc length along a polyline, with its corner vertices (and the
    vertices `keep`) kept exactly."""
    cuts = sorted(set(_pieces_at_corners(points)) | {int(k) for k in keep if 0 < k < len(points) - 1})
    pieces = list(zip(cuts[:-1], cuts[1:]))
    # each piece's cumulative lengths, summed as its own would be (strokes.cumulative_length)
    seg = np.linalg.norm(np.diff(points, axis=0), axis=1)
    cums = [np.concatenate([[0.0], np.cumsum(seg[a:b])]) for a, b in pieces]
    lengths = np.array([c[-1] for c in cums])
    segs = len(lengths)
    total = n - 1
    # segments per piece, proportional to length, at least one each (largest remainder)
    share = lengths / max(lengths.sum(), 1e-300) * max(total - segs, 0)
    count = np.floor(share).astype(int) + 1
    rest = total - count.sum()
    if rest > 0:
        count[np.argsort(-(share - np.floor(share)))[:rest]] += 1
    out: list = [points[:1]]
    straight = [i for i, (a, b) in enumerate(pieces) if b == a + 1 and lengths[i] > 0]
    if len(straight) > 1:
        # the pieces of one segment (a side keeping every vertex has hundreds) in one go, with
        # resample_arclength's arithmetic: its linspace's steps and np.interp's slope on them
        at = np.array([pieces[i][0] for i in straight])
        k = count[straight]
        step = lengths[straight] / k
        slope = (points[at + 1] - points[at]) / lengths[straight][:, None]
        row = np.repeat(np.arange(len(straight)), k)
        j = np.arange(len(row)) - np.repeat(np.cumsum(k) - k, k) + 1          # 1..k per piece
        made = slope[row] * (j * step[row])[:, None] + points[at][row]
        last = np.cumsum(k) - 1
        made[last] = points[at + 1]
        done = dict(zip(straight, np.split(made, np.cumsum(k)[:-1])))
    else:
        done = {}
    for i, ((a, b), k, cum) in enumerate(zip(pieces, count, cums)):
        out.append(done[i] if i in done else resample_arclength(points[a:b + 1], int(k) + 1, cum)[1:])
    return np.vstack(out)


ARC_BLOCK = 64
"""arc_positions locates this many points at a time."""


def arc_positions(original: npt.ArrayLike, points: npt.ArrayLike):
    """Parameters (0..1) of points that lie on the polyline `original`, in order along it (its
    resampling, equalise_uniform): their arc length along it over its length, strictly increasing.
    None for a polyline of no length (a triangle's degenerate top: mapped by index)."""
    orig = np.asarray(original, dtype=float).reshape(-1, 3)
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    step = np.linalg.norm(np.diff(orig, axis=0), axis=1)
    total = float(step.sum())
    if len(pts) < 2 or not total > 0:
        return None
    cum = np.concatenate([[0.0], np.cumsum(step)])
    a, d = orig[:-1], np.diff(orig, axis=0)
    dd = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
    out, k = [], 0
    for first in range(0, len(pts), ARC_BLOCK):
        # each point's segment is at or after the last one's (the points run along the polyline):
        # a block of points against the segments from the block's first one's, each point's own
        # arithmetic (its projection on each segment and its distance to it) as one at a time
        block = pts[first:first + ARC_BLOCK]
        rel = block[:, None, :] - a[None, k:]
        # (x + z, then y: the order np.einsum("ij,ij->i") adds a row's three products in)
        dot = rel[..., 0] * d[k:, 0] + rel[..., 2] * d[k:, 2] + rel[..., 1] * d[k:, 1]
        t = np.minimum(np.maximum(dot / dd[k:], 0.0), 1.0)
        gap = np.linalg.norm(a[k:] + t[..., None] * d[k:] - block[:, None, :], axis=-1)
        base = k
        for row in range(len(block)):
            j = int(np.argmin(gap[row, k - base:]))
            k += j
            out.append(cum[k] + t[row, k - base] * step[k])
    prm = np.asarray(out) / total
    prm[0], prm[-1] = 0.0, 1.0
    # two points at one place (a zero-length segment) still need two parameters: each is kept a
    # hair (1e-9 of the side) after the one before it
    tiny = 1e-9 / len(prm)
    for i in range(1, len(prm)):
        prm[i] = max(prm[i], prm[i - 1] + tiny)
    return prm / prm[-1]


def equalise_uniform(a: npt.ArrayLike, b: npt.ArrayLike, keep: tuple = ((), ())) -> tuple[FloatArray, FloatArray]:
    """Opposite sides with equal point counts, both evenly spaced in arc length (corners kept).

    For faired sides (smooth curves sampled densely) this replaces the paper's midpoint insertion:
    the index parameter of Eq. (1) then runs at an even speed along both sides, so the Coons
    sub-patches and the B-spline edges fitted to them stay light.
    keep: per side, vertex indices kept exactly too (boundary_from_sides keeps every vertex: the
    side with fewer points gets more between its own)."""
    a2 = np.array(a, dtype=float).reshape(-1, 3)
    b2 = np.array(b, dtype=float).reshape(-1, 3)
    n = max(len(a2), len(b2), len(set(_pieces_at_corners(a2)) | set(keep[0])),
            len(set(_pieces_at_corners(b2)) | set(keep[1])), 2)
    out = []
    for side, kept in zip((a2, b2), keep):
        if np.all(side == side[0]):               # the degenerate top of a triangle
            out.append(np.repeat(side[:1], n, axis=0))
        else:
            out.append(_resample_keeping_corners(side, n, kept))
    return out[0], out[1]


BoundarySpec = Union[None, int, Sequence[int]]


def boundary_indices(spec: BoundarySpec, n: int) -> Optional[list[int]]:
    """The stroke indices a boundary spec names (None: classify automatically); raises
    InvalidOptionError for a spec that names no strokes of an n-stroke sketch."""
    if spec is None:
        return None
    if isinstance(spec, (bool, np.bool_)):
        raise InvalidOptionError(f"boundary={spec!r}; give None, a count N or a list of stroke indices")
    if isinstance(spec, (int, np.integer)):
        if not 1 <= spec <= n:
            raise InvalidOptionError(f"boundary={int(spec)} but the sketch has {n} strokes; give 1..{n}")
        return list(range(int(spec)))
    try:
        idx = [int(i) for i in spec]
    except (TypeError, ValueError):
        raise InvalidOptionError(f"boundary={spec!r}; give None, a count N or a list of stroke indices") from None
    if any(isinstance(i, (bool, float)) for i in spec):
        raise InvalidOptionError(f"boundary={spec!r} must list integer stroke indices")
    bad = [i for i in idx if not 0 <= i < n]
    if bad or not idx:
        raise InvalidOptionError(f"boundary={spec!r}: index {bad[0] if bad else '(none)'} is not a stroke "
                                 f"of this sketch (0..{n - 1}); give at least one valid index")
    if len(set(idx)) != len(idx):
        raise InvalidOptionError(f"boundary={spec!r} names a stroke twice; give each boundary stroke once")
    return idx


def make_boundary(
    strokes: Sequence[npt.ArrayLike], boundary: BoundarySpec = None, tol: Tolerances = Tolerances(),
    candidates: Optional[Sequence[int]] = None,
) -> tuple[BoundaryLoop, list[int]]:
    """Steps 1-5 of the module docstring: the BoundaryLoop and the (sorted) interior stroke indices.

    boundary : None = classify by rays; N = the first N strokes; list = these stroke indices.
    candidates : with boundary None, classify only these strokes (the others are interior
                 whatever their place); None = all strokes.
    Strokes are validated (InvalidStrokeError names the bad one) and filtered with tol.filter_mm
    or `auto_filter_threshold`; the input arrays are not modified.
    """
    arrays = [validate_stroke(s, i) for i, s in enumerate(strokes)]
    if not arrays:
        raise InvalidOptionError("no strokes given; a boundary needs at least one stroke")
    chosen = boundary_indices(boundary, len(arrays))
    threshold = auto_filter_threshold(arrays) if tol.filter_mm is None else float(tol.filter_mm)
    filtered = [filter_stroke(a, threshold) for a in arrays]
    pool = list(chosen) if chosen is not None else list(range(len(arrays))) if candidates is None else \
        sorted({int(i) for i in candidates})
    if not pool or not all(0 <= i < len(arrays) for i in pool):
        raise InvalidOptionError(f"candidates={candidates!r}: give indices of strokes of this sketch "
                                 f"(0..{len(arrays) - 1})")
    # the plane and size of the sketch come from the strokes that may bound it (the named boundary
    # strokes, when named: a later interior stroke does not move the boundary)
    allpts = np.concatenate([filtered[i] for i in pool])
    plane = best_fit_plane(allpts)
    diagonal = sketch_diagonal(allpts)
    notes = [f"filtered strokes with a 3D distance threshold of {threshold:.4g} mm"]
    if chosen is None:
        found, _ = classify_strokes([filtered[i] for i in pool], plane)
        chosen = [pool[i] for i in found]
        notes.append(f"rays from the centroid found boundary strokes {chosen}")
    interior = sorted(set(range(len(arrays))) - set(chosen))
    faired = bool(tol.fair_mm and tol.fair_mm > 0 and tol.snap_mm)
    if faired:
        # Curve fairness beyond the paper: each boundary stroke becomes a light cubic B-spline
        # within its own tolerance (raised to a few times its jitter), sampled densely.
        sag = tol.sag_mm
        for i in chosen:
            ftol = stroke_tolerance(filtered[i], tol.fair_mm, tol.snap_mm)
            # rounded (1e-9 mm on the examples): a save/reopen round trip fairs the same
            filtered[i] = fair_stroke(round_points(filtered[i], tol.fit_mm), ftol, sag)[0]
        notes.append("faired boundary strokes (Kamiya & Aoyama / Mullineux fairness, see core.fairing)")
    sides, close_notes = close_loop([filtered[i] for i in chosen], chosen, plane, tol, diagonal)
    notes += close_notes
    loop = _orient_to_first_stroke(sides)
    used: dict = {}
    for side in loop:
        if len(side.source) == 1:
            used.setdefault(side.source[0], []).append(side.points)
    pts = [s.points for s in loop]
    sources = [s.source for s in loop]
    if len(loop) > 4:
        groups, merge_notes = _merge_groups(pts, plane)
        notes += merge_notes
        start = min(range(len(groups)), key=lambda g: min(loop[i].key for i in groups[g]))
        groups = groups[start:] + groups[:start]
        pts = [_join([loop[i].points for i in g]) for g in groups]
        sources = [tuple(sorted({j for i in g for j in loop[i].source})) for g in groups]
    if len(pts) == 3:
        apex = triangle_apex(pts, stroke_end_pairs(arrays, interior))
        pts, sources = turn_to_apex(pts, apex), turn_to_apex(sources, apex)
        notes.append(f"three-sided boundary: top side degenerate at corner {pts[1][-1].round(3).tolist()} (Fig. 4)")
        sources.insert(2, ())
    s0, s1, s2, s3 = merge_to_four(pts, plane, apex=1)
    even = equalise_uniform if faired else equalise
    bottom, top = even(s0, s2[::-1])
    right, left = even(s1, s3[::-1])
    area_normal = _loop_normal(np.concatenate([s0, s1[1:], s2[1:], s3[1:-1]]), plane)
    out_plane = plane if area_normal >= 0 else plane.flipped()
    return BoundaryLoop(bottom, right, top, left, out_plane, tuple(sources), tuple(notes), used), interior


def _orient_to_first_stroke(sides: list[ClosedSide]) -> list[ClosedSide]:
    """Rotate the loop so the side holding the lowest stroke index (and its first part) comes first,
    and reverse it if that stroke was drawn the other way.  Depends only on stroke order and drawing
    direction, so the result is invariant under rigid motions and scaling."""
    k = min(range(len(sides)), key=lambda i: sides[i].key)
    loop = sides[k:] + sides[:k]
    if loop[0].reversed_input:
        loop = [loop[0].reversed()] + [s.reversed() for s in reversed(loop[1:])]
    return loop


def _loop_normal(loop3d: FloatArray, plane: Plane) -> float:
    """Signed area of the closed loop projected on the plane (> 0: counter-clockwise about normal)."""
    uv = plane.project(loop3d)
    x, y = uv[:, 0], uv[:, 1]
    return float(0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def apex_holds(loop: "BoundaryLoop", ends: npt.ArrayLike) -> bool:
    """Whether a loop made earlier still collapses where `triangle_apex` would collapse it now,
    with the ends (`stroke_end_pairs`) of the interior strokes there are now (always, for four
    sides): a loop kept from an earlier build (the progressive path) must be the loop a build from
    scratch makes."""
    if not loop.triangle:
        return True
    return triangle_apex([loop.bottom, loop.right, loop.left[::-1]], ends) == 1


def stroke_end_pairs(strokes: Sequence[npt.ArrayLike], which: Sequence[int]) -> FloatArray:
    """The ends of each stroke in `which`, for triangle_apex: (2k, 2, 3), each end point with the
    stroke's point a tenth of its length inside."""
    out = []
    for i in which:
        a = np.asarray(strokes[i], dtype=float).reshape(-1, 3)
        if len(a) < 2:
            continue
        s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(a, axis=0), axis=1))])
        k0 = min(int(np.searchsorted(s, 0.1 * s[-1])), len(a) - 1)
        k1 = max(int(np.searchsorted(s, 0.9 * s[-1])) - 1, 0)
        out += [(a[0], a[k0]), (a[-1], a[k1])]
    return np.array(out, dtype=float).reshape(-1, 2, 3)


def boundary_from_sides(sides: Sequence[npt.ArrayLike], sources: Sequence[int],
                        inside: Sequence[npt.ArrayLike] = (), apex: Optional[int] = None) -> BoundaryLoop:
    """The BoundaryLoop of a loop that is closed already (issue 18: a cycle of the stroke network,
    whose sides meet at its nodes exactly): steps 4-5 of the module docstring without the closing
    of step 3, which would cut or extend sides that two surfaces share.

    sides   : (n_k, 3) each, in loop order, each starting where the previous one ends
    sources : the stroke (or network edge) index of each side, for BoundaryLoop.source
    inside  : the strokes inside the loop (their ends help choose a triangle's apex: triangle_apex)
    apex    : of three sides, the corner that is the apex (0-2, the corner after side apex - 1);
              None = triangle_apex's choice
    Sides are faired, densely sampled polylines. Every point of them is kept: of two opposite
    sides, the one with fewer points gets more, evenly in arc length between its own
    (equalise_uniform with every vertex kept), and each side is mapped to the unit square by arc
    length (BoundaryLoop.params), so that the surface follows the very points its neighbour on the
    same curve follows, with the parameter of the one curve fitted to them (cad.shared_edges)."""
    pts = [np.array(s, dtype=float).reshape(-1, 3) for s in sides]
    if len(pts) < 3:
        raise OpenBoundaryError(f"a loop of {len(pts)} side(s) cannot bound a surface; it needs 3 or more")
    plane = best_fit_plane(np.concatenate(pts))
    groups = [[k] for k in range(len(pts))]
    notes: list = []
    if len(pts) > 4:
        groups, notes = _merge_groups(pts, plane)
        pts = [_join([pts[i] for i in g]) for g in groups]
    srcs = [tuple(sorted({int(sources[i]) for i in g})) for g in groups]
    if len(pts) == 3:
        if apex is None:
            apex = triangle_apex(pts, stroke_end_pairs(inside, range(len(inside))))
        pts, srcs = turn_to_apex(pts, apex), turn_to_apex(srcs, apex)
        notes.append(f"three-sided loop: top side degenerate at corner {pts[1][-1].round(3).tolist()} (Fig. 4)")
        srcs.insert(2, ())
    s0, s1, s2, s3 = merge_to_four(pts, plane, apex=1)
    # Every point of the sides is kept (the side with fewer gets more, evenly in arc length) and
    # the sides are mapped by arc length (params): the two surfaces on a curve then bound
    # themselves by that curve's very points, and by the one B-spline fitted to them
    # (cad.shared_edges), where an even resampling would cut the corners of a sparse stroke.
    def every(side):
        return range(1, len(side) - 1)

    bottom, top = equalise_uniform(s0, s2[::-1], (every(s0), every(s2)))
    right, left = equalise_uniform(s1, s3[::-1], (every(s1), every(s3)))
    params = tuple(arc_positions(orig, side) for orig, side in
                   ((s0, bottom), (s1, right), (s2[::-1], top), (s3[::-1], left)))
    area_normal = _loop_normal(np.concatenate([s0, s1[1:], s2[1:], s3[1:-1]]), plane)
    out_plane = plane if area_normal >= 0 else plane.flipped()
    return BoundaryLoop(bottom, right, top, left, out_plane, tuple(srcs), tuple(notes), {}, params=params)
