"""Constrained least-squares cubic B-spline fit in numpy (the curve fit of the shared edges).

OCC's GeomAPI_PointsToBSpline approximates within a tolerance but cannot pass exactly through the
network nodes inside a curve; neighbouring faces need exactly that (a node where a stroke ends on, or
crosses, another curve is a corner of several Coons sub-patches). So each network curve is fitted once
here: minimise sum w_i^2 |C(t_i) - p_i|^2 + lam |second differences of poles|^2 subject to C(t_k) = node_k
(w_i = tol / the allowance of sample i),
refining knots where the residual exceeds the tolerance. The CAD adapter (cad.curves.fit_points) then
holds the result as a Part.BSplineCurve.
"""
from __future__ import annotations

from functools import lru_cache

import numpy as np

from .bspline import DEGREE, basis_matrix, span_samples
from .errors import FitError
from .types import FloatArray

__all__ = ["DEGREE", "basis_matrix", "chord_sag", "fit_cubic", "sample_to_sag"]


def _end_poles(knots: FloatArray, end_points: tuple, derivs: dict | None) -> dict | None:
    """Poles fixed by end derivatives: {pole index: (3,) pole}. At a clamped end the curve's
    first and second derivatives depend only on the first two and three poles (Piegl & Tiller
    eq. 3.8), so C(0), C'(0), C''(0) given fix P0, P1, P2 outright (likewise at t = 1).
    end_points: (C(0), C(1)). None when the knot vector has too few poles for both ends."""
    out: dict = {}
    n = len(knots) - DEGREE - 1
    for end, values in (derivs or {}).items():
        d1, d2 = values
        at_one = end >= 0.5
        ks = 1.0 - knots[::-1] if at_one else knots     # at t = 1: the mirrored curve C(1 - t)
        sign = -1.0 if at_one else 1.0
        u4, u5 = ks[DEGREE + 1], ks[DEGREE + 2]
        p0 = np.asarray(end_points[1 if at_one else 0], dtype=float)
        poles = [p0, p0 + sign * np.asarray(d1, dtype=float) * u4 / DEGREE]
        if d2 is not None:
            q1 = sign * np.asarray(d1, dtype=float) + np.asarray(d2, dtype=float) * u4 / (DEGREE - 1)
            poles.append(poles[1] + q1 * u5 / DEGREE)
        for k, pole in enumerate(poles):
            idx = n - 1 - k if at_one else k
            if idx in out:
                return None
            out[idx] = pole
    return out


@lru_cache(maxsize=256)
def _second_differences(n: int) -> FloatArray:
    """(n - 2, n) second-difference operator on n poles (read-only, shared)."""
    d = np.diff(np.eye(n), n=2, axis=0) if n >= 3 else np.zeros((0, n))
    d.setflags(write=False)
    return d


def _solve(a, c, pts, fixed_p, lam, end_poles=None, exact: bool = True):
    """Poles minimising |a P - pts|^2 + lam |second differences of P|^2 with c P = fixed_p exactly
    (KKT); a and c are basis matrices at the data and the fixed parameters; `end_poles`
    {index: pole} are given. exact False: a faster solve (LU, 5x), for the refinement rounds
    that only decide where knots go."""
    return _solve_system(_kkt_system(a, c, pts, fixed_p, lam, end_poles), exact)


def _kkt_system(a, c, pts, fixed_p, lam, end_poles=None) -> tuple:
    """The KKT system of _solve, made once for both of its solves: (kkt, rhs, given poles, free
    mask, constraint matrix on the free poles)."""
    n = a.shape[1]
    d = _second_differences(n)
    known = np.zeros((n, 3))
    free = np.ones(n, dtype=bool)
    for idx, pole in (end_poles or {}).items():
        known[idx], free[idx] = pole, False
    pts = pts - a @ known
    fixed_p = np.asarray(fixed_p, dtype=float).reshape(-1, 3) - c @ known
    smooth = -(d @ known)
    a, c, d = a[:, free], c[:, free], d[:, free]
    rows = np.abs(c).sum(axis=1) > 1e-12          # a point constraint on given poles only is met
    c, fixed_p = c[rows], fixed_p[rows]
    m, k = a.shape[1], c.shape[0]
    kkt = np.zeros((m + k, m + k))
    kkt[:m, :m] = 2.0 * (a.T @ a + lam * d.T @ d)
    kkt[:m, m:] = c.T
    kkt[m:, :m] = c
    rhs = np.vstack([2.0 * (a.T @ pts + lam * d.T @ smooth), fixed_p])
    return kkt, rhs, known, free, c


def _solve_system(system: tuple, exact: bool):
    """The poles of a _kkt_system (see _solve for `exact`)."""
    kkt, rhs, known, free, c = system
    k = c.shape[0]
    if exact or (k and np.linalg.matrix_rank(c) < k):
        # minimum-norm least squares: with more nodes in one knot span than it has poles the
        # system is singular, and this is the solution the knot refinement recovers from (LU on
        # it gave 1e22 mm poles or an error as the last bits fell, so the knots a sketch got
        # depended on its scale)
        sol = np.linalg.lstsq(kkt, rhs, rcond=None)[0]
    else:
        try:
            sol = np.linalg.solve(kkt, rhs)
        except np.linalg.LinAlgError:
            sol = np.linalg.lstsq(kkt, rhs, rcond=None)[0]
    known = known.copy()
    known[free] = sol[:free.sum()]
    return known


def _polyline_at(t: FloatArray, pts: FloatArray, x: FloatArray) -> FloatArray:
    return np.stack([np.interp(x, t, pts[:, k]) for k in range(3)], axis=1)


SAMPLE_MERGE = 1e-9
"""Samples of the fit closer than this (in the curve parameter, [0, 1]) are one sample, a vertex
where one of them is: a point inside a knot span that falls on a vertex up to round-off (uniform
parameters often do) is that vertex, whether or not the last bits agree (they differ with the
sketch's scale; counted twice, it weighed twice and moved the curve by 1 % of the tolerance)."""


def _samples(t: FloatArray, interior: FloatArray, per_span: int = 4) -> FloatArray:
    """Vertices, chord midpoints and `per_span` points inside every knot span: every span has data,
    so a span crowded against a corner of the polyline cannot wander between vertices. The
    vertices are exactly t; other samples within SAMPLE_MERGE of a vertex or of each other are
    left out."""
    inside = span_samples(np.concatenate([[0.0], interior, [1.0]]), per_span)
    extra = np.unique(np.concatenate([0.5 * (t[1:] + t[:-1]), inside]))
    extra = extra[np.concatenate([[True], np.diff(extra) > SAMPLE_MERGE])]
    at = np.minimum(np.maximum(np.searchsorted(t, extra), 1), len(t) - 1)
    near = np.minimum(np.abs(extra - t[at - 1]), np.abs(t[at] - extra)) <= SAMPLE_MERGE
    return np.sort(np.concatenate([np.unique(t), extra[~near]]))


SAG_CURVATURE_RATIO = 4.0
"""A chord's sag takes the curvature at its sharper end only up to this many times that at its
other end: one end alone turning sharply is a corner (two boundary strokes merged into one side)
or a cluster of short chords (a ramp onto a node), not a curve the chord samples. Without the
bound the fit cut a 42 deg corner between 9 mm chords by 1.8 times the fit tolerance
(sk_cyl_penta_4) and bulged 3.7 times its tolerance off a 20 mm chord beside a node
(sk_saddle_3); with the smaller curvature alone the benchmark's unfaired network took 44 % more
poles, with this bound 9 %."""


def chord_sag(pts: FloatArray) -> FloatArray:
    """(len(pts) - 1,) how far each chord of the polyline lies from a smooth curve through its
    vertices: L^2 k / 8 for a chord of length L, with k the larger curvature of the circles through
    the three vertices around each end, but at most SAG_CURVATURE_RATIO times the smaller (the
    polyline's end chords: their one inner end's). A stroke sampled every 2 mm on a surface curved
    like the benchmark's saddle sags 0.01 mm."""
    pts = np.asarray(pts, dtype=float)
    seg = np.diff(pts, axis=0)
    length = np.linalg.norm(seg, axis=1)
    if len(pts) < 3:
        return np.zeros(len(seg))
    a, b = seg[:-1], seg[1:]
    cross = np.linalg.norm(np.cross(a, b), axis=1)
    span = np.linalg.norm(a + b, axis=1) * length[:-1] * length[1:]
    k = np.divide(2.0 * cross, span, out=np.zeros(len(span)), where=span > 1e-300)
    k0 = np.concatenate([[k[0]], k])
    k1 = np.concatenate([k, [k[-1]]])
    both = np.minimum(np.maximum(k0, k1), SAG_CURVATURE_RATIO * np.minimum(k0, k1))
    return length ** 2 * both / 8.0


SAG_ROUNDS = 8
"""At most this many rounds of halving chords in sample_to_sag (a chord 256 times shorter)."""


def sample_to_sag(points_at, w: FloatArray, sag_mm: float | None,
                  rounds: int = SAG_ROUNDS) -> tuple[FloatArray, FloatArray]:
    """Sample a curve given pointwise (points_at: (m,) parameters -> (m, 3) points) at the sorted
    parameters w, halving every chord that sags more than sag_mm (chord_sag) until none does (at
    most `rounds` rounds). The curve fit lets a smooth curve leave a chord by its sag, and the
    Coons sub-patch is built on the chords: a curve the network makes itself (a split along the
    old surface, an extension to the boundary) is sampled so that the two agree to sag_mm, as the
    fairing samples the strokes. sag_mm None or 0: w as given. Returns (w, points)."""
    w = np.asarray(w, dtype=float)
    pts = np.asarray(points_at(w), dtype=float)
    if not sag_mm or sag_mm <= 0:
        return w, pts
    for _ in range(rounds):
        bad = chord_sag(pts) > sag_mm
        if not bad.any():
            break
        mid = 0.5 * (w[:-1] + w[1:])[bad]
        order = np.argsort(np.concatenate([w, mid]), kind="stable")
        w = np.concatenate([w, mid])[order]
        pts = np.vstack([pts, np.asarray(points_at(mid), dtype=float)])[order]
    return w, pts


MAX_KNOTS_PER_VERTEX = 2
"""The knot refinement of fit_cubic stops at this many interior knots per polyline vertex, plus
MAX_CORNER_KNOTS (and the C0 knots of its breaks): the sketches of the examples and the benchmark
take at most 0.4 knots a vertex; a tolerance the points cannot meet (below their round-off, or a
jump in the polyline) would otherwise double the knots every round, and the solve is cubic in them
(a 1e-9 mm tolerance ran for minutes)."""
MAX_CORNER_KNOTS = 64
"""Knots allowed beyond MAX_KNOTS_PER_VERTEX: a sharp corner of a short polyline crowds about two
knots per halving of its span until the curve hugs it (about 30 at 1e-4 of the span)."""


def fit_cubic(t: FloatArray, pts: FloatArray, fixed_t: FloatArray, fixed_p: FloatArray, tol: float,
              name: str = "curve", max_rounds: int = 40, breaks=(), derivs: dict | None = None,
              seed=(), best_effort: bool = False, hug: bool = False) -> tuple[FloatArray, FloatArray]:
    """Cubic B-spline C through fixed_p at fixed_t and within tol of the piecewise-linear polyline
    (t, pts) everywhere it is sampled (params in [0, 1]): the Coons sub-patch is built on that
    polyline, so the curve must follow it between the vertices too, within tol plus the chord's
    own sag (chord_sag): a smooth curve cannot, and need not, hug the corners of a coarse polyline.
    Knots are refined where the residual exceeds that allowance; near a corner of the polyline they
    crowd until the smooth curve hugs it.

    derivs : {0.0 and/or 1.0: (first derivative, second derivative or None)} the curve must have at
             that end (to join a neighbouring curve C1 or C2 when only a part of a curve is refitted).

    seed   : interior knots to start from (e.g. those of an earlier fit of the same curve), so that
             refinement starts near where it will end.

    hug    : within tol of the chords too, their sag not allowed (the curve follows the polyline's
             corners: more knots; for a face that came out past the fit tolerance, app.build.tighten_fit)

    best_effort : when the refinement stops short of tol (max_rounds, the knot cap
             MAX_KNOTS_PER_VERTEX, or spans too short to split), return the fit on the last knots
             instead of raising: the caller measures how far it lies (a face's fit deviation).

    Returns (full clamped knot vector, poles (n, 3)). Raises FitError if refinement does not reach tol
    (unless best_effort).
    """
    t = np.asarray(t, dtype=float)
    pts = np.asarray(pts, dtype=float)
    # the curve's size, for the node check (1e-9 of it); all points one point: their magnitude
    scale = float(np.ptp(pts, axis=0).max()) or float(np.abs(pts).max()) or 1.0
    # A kink of the polyline at a node (a curve pulled to a later stroke there) gets a C0 knot of
    # full multiplicity, instead of a crowd of knots that would chase the corner.
    interior = np.repeat(np.sort(np.asarray(breaks, dtype=float)), DEGREE)
    seed = np.unique(np.asarray(seed, dtype=float))
    seed = seed[(seed > 1e-9) & (seed < 1.0 - 1e-9)]
    if len(seed) and len(interior):
        seed = seed[np.min(np.abs(seed[:, None] - interior[None, :]), axis=1) > 1e-9]
    interior = np.sort(np.concatenate([interior, seed]))
    sag = chord_sag(pts) if len(t) > 1 and not hug else np.zeros(max(len(t) - 1, 1))
    max_knots = MAX_KNOTS_PER_VERTEX * len(t) + MAX_CORNER_KNOTS + DEGREE * len(breaks)
    last = None
    for _ in range(max_rounds):
        knots = np.concatenate([np.zeros(DEGREE + 1), interior, np.ones(DEGREE + 1)])
        x = _samples(t, interior)
        at = np.searchsorted(t, x)
        vertex = t[np.minimum(at, len(t) - 1)] == x          # t is sorted: x is a vertex or lies after t[at-1]
        allow = tol + np.where(vertex, 0.0, sag[np.minimum(np.maximum(at - 1, 0), len(sag) - 1)])
        data = _polyline_at(t, pts, x)
        lam = 1e-8 * len(x)
        end_poles = _end_poles(knots, (fixed_p[0], fixed_p[-1]), derivs)
        if end_poles is None:     # too few poles for the end derivatives: split every span
            bounds = np.concatenate([[0.0], interior, [1.0]])
            interior = np.sort(np.concatenate([interior, 0.5 * (bounds[1:] + bounds[:-1])]))
            continue
        a, c = basis_matrix(knots, x), basis_matrix(knots, fixed_t)
        # each sample weighs by how closely it must be met: a chord point, allowed its sag, must
        # not pull the curve off the vertices (equal weights crowded knots: 43 poles for 15 points)
        w = tol / allow
        last = (knots, a * w[:, None], c, data * w[:, None], lam, end_poles)
        system = _kkt_system(last[1], c, last[3], fixed_p, lam, end_poles)
        for exact in (False, True):   # the fast solve finds the knots, least squares the result
            poles = _solve_system(system, exact)
            res = np.linalg.norm(a @ poles - data, axis=1)
            fres = np.linalg.norm(c @ poles - fixed_p, axis=1)
            if not (np.all(res <= allow) and fres.max() <= 1e-9 * scale):
                break
            if exact:
                return knots, poles
        bounds = np.concatenate([[0.0], interior, [1.0]])
        # refine where the polyline is missed, and around nodes the curve cannot pass through yet
        # (two nodes close together on one curve need a knot between them)
        # (a point on a knot, up to the last bits, refines the spans on both sides of it)
        missed = np.concatenate([x[res > allow], fixed_t[fres > 1e-9 * scale]])
        bad = np.unique(np.clip(np.searchsorted(bounds, np.concatenate([missed - SAMPLE_MERGE, missed + SAMPLE_MERGE]),
                                                side="right") - 1, 0, len(bounds) - 2))
        new = 0.5 * (bounds[bad] + bounds[bad + 1])
        new = new[new - bounds[bad] > 1e-9]
        if len(new) == 0 or len(interior) + len(new) > max_knots:
            break
        interior = np.sort(np.concatenate([interior, new]))
    if best_effort and last is not None:
        knots, a, c, data, lam, end_poles = last
        return knots, _solve(a, c, data, fixed_p, lam, end_poles, True)
    raise FitError(f"{name}: no cubic B-spline within {tol:.3g} mm of its {len(t)}-point polyline after "
                   "knot refinement; raise --fit-tol or smooth the stroke")
