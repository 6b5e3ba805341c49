"""Small immutable value types of the core, and numpy typing aliases."""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Optional, Sequence

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]
"""Any float64 array; shapes are given in each docstring."""


FIT_FRACTION = 1e-4
"""Automatic fit tolerance: this fraction of the sketch's bounding-box diagonal (0.013 mm on the
bundled examples, 0.1 mm on a 1 m sketch); tolerances that are all relative give the same surface,
scaled, for a sketch drawn at any size."""


SAG_FRACTION = 0.25
"""Strokes are faired, and the curves the network makes sampled, so that a chord sags at most this
fraction of the fit tolerance: the curve fit lets a smooth curve leave a chord by its sag, and the
Coons sub-patch is built on the chords, so the face and the sub-patch then agree within the fit
tolerance (a split curve of 32 chords sagged 1.5 times the fit tolerance on three_sided)."""


@dataclass(frozen=True)
class Tolerances:
    """All tolerances in one value, passed explicitly (never a module global).

    filter_mm : 3D distance threshold of the stroke filter (paper, section 2); None = automatic
    snap_mm   : distance under which a stroke end is taken to be on a boundary (step 2); None = automatic
    fit_mm    : how far an OCC B-spline face may lie from its Coons sub-patch; None = automatic
                (FIT_FRACTION of the sketch's diagonal, so that a sketch at any scale fits alike)
    fair_mm   : how far a faired stroke may lie from its filtered points; None = automatic
                (a fraction of the snap distance), 0 = no fairing
    param     : straightness tolerance of a pre-image in the unit square (step 6); the 3D stroke is
                interpolated exactly whatever it is, so it only trades parameter quality for patches
    gap_factor: the widest boundary gap that may be closed, as a fraction of the sketch diagonal
    """

    filter_mm: Optional[float] = None
    snap_mm: Optional[float] = None
    fit_mm: Optional[float] = None
    fair_mm: Optional[float] = None
    param: float = 0.08
    gap_factor: float = 0.25

    @property
    def sag_mm(self) -> Optional[float]:
        """How far a chord of a network polyline may sag from the smooth curve through its points
        (core.curve_fit.chord_sag): SAG_FRACTION of the fit tolerance; None while the fit
        tolerance is automatic and not yet resolved (core.pipeline.resolve_tolerances)."""
        return SAG_FRACTION * self.fit_mm if self.fit_mm else None

    @property
    def made_sag_mm(self) -> Optional[float]:
        """The sag the curves the network makes itself (splits along the old surface) are sampled
        to: sag_mm where the strokes are faired to it; None (the mesh density only) where they are
        not (fair_mm 0, or None outside the pipeline): an unfaired network is as coarse as its
        strokes, and denser splits on it only chase the ripples of its polyline sub-patches
        (1.75 times the poles on the benchmark's network)."""
        return self.sag_mm if self.fair_mm else None


def cross3(a: FloatArray, b: FloatArray) -> FloatArray:
    """np.cross of (..., 3) vectors, the same arithmetic (a1 b2 - a2 b1, a2 b0 - a0 b2, a0 b1 - a1 b0,
    each product rounded, then the difference), without np.cross's axis handling: footpoints and
    the fold checks call it thousands of times a stroke on small arrays."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    np.multiply(a1, b2, out=out[..., 0])
    out[..., 0] -= a2 * b1
    np.multiply(a2, b0, out=out[..., 1])
    out[..., 1] -= a0 * b2
    np.multiply(a0, b1, out=out[..., 2])
    out[..., 2] -= a1 * b0
    return out


def _span(params: FloatArray, t: FloatArray) -> tuple[FloatArray, np.ndarray]:
    """t clamped to the params' range and the index of the segment that holds it."""
    tc = np.minimum(np.maximum(t, params[0]), params[-1])
    return tc, np.minimum(np.searchsorted(params, tc, side="right") - 1, len(params) - 2)


def _lerp(points: FloatArray, params: FloatArray, k: np.ndarray, tc: FloatArray) -> FloatArray:
    """Points at tc on segments k (indices into points and params)."""
    # (take and in-place products: the same arithmetic as points[k] * (1 - w) + points[k + 1] * w,
    # in half the time; the interpolation of every sample of the fold checks goes through here)
    k1 = k + 1
    pk = params.take(k)
    w = ((tc - pk) / (params.take(k1) - pk))[..., None]
    out = points.take(k, axis=0)
    out *= 1.0 - w
    nxt = points.take(k1, axis=0)
    nxt *= w
    out += nxt
    return out


def evaluate_polylines(jobs: Sequence[tuple["Polyline", FloatArray]]) -> FloatArray:
    """Polyline.evaluate of several (polyline, parameters (k,)) at once, concatenated (sum k, 3)
    (the same values as one by one): long jobs one by one, many short ones through one search
    (evaluate_polyline_rows)."""
    jobs = [(poly, np.asarray(t, dtype=float).reshape(-1)) for poly, t in jobs]
    if not jobs:
        return np.zeros((0, 3))
    sizes = [len(t) for _, t in jobs]
    if sum(sizes) >= 256 * len(jobs):
        return np.concatenate([poly.evaluate(t) for poly, t in jobs]).reshape(-1, 3)
    return evaluate_polyline_rows([poly for poly, _ in jobs], np.repeat(np.arange(len(jobs)), sizes),
                                  np.concatenate([t for _, t in jobs]))


def evaluate_polyline_rows(polys: Sequence["Polyline"], rows: np.ndarray, t: FloatArray) -> FloatArray:
    """Points (k, 3): polys[rows[i]].evaluate(t[i]) for each i, the same values, the segment search
    of all of them in one searchsorted of keys (polyline, parameter), the interpolation of all
    of them together (the fold checks evaluate thousands of short runs of many sides)."""
    rows, t = np.asarray(rows, dtype=np.intp).reshape(-1), np.asarray(t, dtype=float).reshape(-1)
    group: dict = {}                         # each polyline's points once, however often it is used
    used, index = [], []
    for poly in polys:
        if id(poly) not in group:
            group[id(poly)] = len(used)
            used.append(poly)
        index.append(group[id(poly)])
    if not used:
        return np.zeros((0, 3))
    pts = np.concatenate([p.points for p in used])
    prm = np.concatenate([p.params for p in used])
    counts = np.array([len(p.params) for p in used])
    offsets = np.concatenate([[0], np.cumsum(counts)[:-1]])
    g = np.asarray(index, dtype=np.intp)[rows]
    first, last = prm[offsets], prm[offsets + counts - 1]
    tc = np.minimum(np.maximum(t, first[g]), last[g])
    # keys sort as complex numbers do: polyline first, then parameter
    keys = np.empty(len(prm), dtype=complex)
    keys.real, keys.imag = np.repeat(np.arange(len(used)), counts), prm
    query = np.empty(len(tc), dtype=complex)
    query.real, query.imag = g, tc
    k = np.minimum(np.searchsorted(keys, query, side="right") - 1, (offsets + counts - 2)[g])
    single = counts[g] < 2                   # one point (Polyline.evaluate): that point
    if not single.any():
        return _lerp(pts, prm, k, tc)
    out = np.empty((len(t), 3))
    out[single] = pts[offsets[g[single]]]
    out[~single] = _lerp(pts, prm, k[~single], tc[~single])
    return out


@dataclass(frozen=True)
class Polyline:
    """A 3D polyline with its pre-image parameters.

    points : (n, 3) float, millimetres
    params : (n,) float, strictly increasing from 0 to 1: the position of each point
             along the straight pre-image of the curve it belongs to.
    """

    points: FloatArray
    params: FloatArray

    def __post_init__(self) -> None:
        pts = np.array(self.points, dtype=float).reshape(-1, 3)
        prm = np.array(self.params, dtype=float).reshape(-1)
        pts.setflags(write=False)
        prm.setflags(write=False)
        object.__setattr__(self, "points", pts)
        object.__setattr__(self, "params", prm)

    def evaluate(self, t: npt.ArrayLike) -> FloatArray:
        """Piecewise-linear point(s) at parameter(s) t in [0, 1]; returns (..., 3)."""
        t = np.asarray(t, dtype=float)
        prm, pts = self.params, self.points
        if len(prm) < 2:
            return np.broadcast_to(pts[0], t.shape + (3,)).copy()
        tc, k = _span(prm, t)
        return _lerp(pts, prm, k, tc)

    def reversed(self) -> "Polyline":
        return Polyline(self.points[::-1], 1.0 - self.params[::-1])

    @cached_property
    def turning_deg(self) -> FloatArray:
        """(n,) read-only turning angle in degrees at each point over the kink window
        (core.continuity.turning_angles with KINK_WINDOW), made once: G1 mode tests every network
        edge for kinks at every build, and an unchanged edge keeps its polyline."""
        from .continuity import KINK_WINDOW, turning_angles

        out = turning_angles(self.points, KINK_WINDOW)
        out.setflags(write=False)
        return out
