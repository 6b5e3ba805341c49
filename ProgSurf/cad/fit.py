"""Constrained least-squares cubic B-spline fit in numpy (the curve fit of the shared edges).

OCC's GeomAPI_PointsToBSpline approximates within a tolerance but cannot pass exactly through the
network nodes inside a curve; neighbouring faces need exactly that (a node where a stroke ends on, or
crosses, another curve is a corner of several Coons sub-patches). So each network curve is fitted once
here: minimise sum |C(t_i) - p_i|^2 + lam |second differences of poles|^2 subject to C(t_k) = node_k,
refining knots where the residual exceeds the tolerance. OCC then holds the result as a Part.BSplineCurve.
"""
from __future__ import annotations

import numpy as np

from ..core.bspline import DEGREE, basis_matrix
from ..core.errors import FitError
from ..core.types import FloatArray

__all__ = ["DEGREE", "basis_matrix", "fit_cubic"]


def _solve(knots, t, pts, fixed_t, fixed_p, lam, weights):
    a = basis_matrix(knots, t) * weights[:, None]
    pts = pts * weights[:, None]
    c = basis_matrix(knots, fixed_t)
    n = a.shape[1]
    d = np.diff(np.eye(n), n=2, axis=0) if n >= 3 else np.zeros((0, n))
    h = a.T @ a + lam * d.T @ d
    k = len(fixed_t)
    kkt = np.block([[2.0 * h, c.T], [c, np.zeros((k, k))]])
    rhs = np.vstack([2.0 * a.T @ pts, fixed_p])
    sol = np.linalg.lstsq(kkt, rhs, rcond=None)[0]
    return sol[:n]


def _polyline_at(t: FloatArray, pts: FloatArray, x: FloatArray) -> FloatArray:
    return np.stack([np.interp(x, t, pts[:, k]) for k in range(3)], axis=1)


def _samples(t: FloatArray, interior: FloatArray, per_span: int = 4) -> FloatArray:
    """Vertices, chord midpoints and `per_span` points inside every knot span: every span has data,
    so a span crowded against a corner of the polyline cannot wander between vertices."""
    bounds = np.concatenate([[0.0], interior, [1.0]])
    inside = (bounds[:-1, None] + (bounds[1:] - bounds[:-1])[:, None]
              * (np.arange(1, per_span + 1) / (per_span + 1))[None, :]).ravel()
    return np.unique(np.concatenate([t, 0.5 * (t[1:] + t[:-1]), inside]))


def fit_cubic(t: FloatArray, pts: FloatArray, fixed_t: FloatArray, fixed_p: FloatArray, tol: float,
              name: str = "curve", max_rounds: int = 40, breaks=()) -> tuple[FloatArray, FloatArray]:
    """Cubic B-spline C through fixed_p at fixed_t and within tol of the piecewise-linear polyline
    (t, pts) everywhere it is sampled (params in [0, 1]): the Coons sub-patch is built on that
    polyline, so the curve must follow it between the vertices too. Knots are refined where the
    residual exceeds tol; near a corner of the polyline they crowd until the smooth curve hugs it.

    Returns (full clamped knot vector, poles (n, 3)). Raises FitError if refinement does not reach tol.
    """
    t = np.asarray(t, dtype=float)
    pts = np.asarray(pts, dtype=float)
    scale = max(float(np.ptp(pts, axis=0).max()), 1e-9)
    # A kink of the polyline at a node (a curve pulled to a later stroke there) gets a C0 knot of
    # full multiplicity, instead of a crowd of knots that would chase the corner.
    interior = np.repeat(np.sort(np.asarray(breaks, dtype=float)), DEGREE)
    for _ in range(max_rounds):
        knots = np.concatenate([np.zeros(DEGREE + 1), interior, np.ones(DEGREE + 1)])
        x = _samples(t, interior)
        data = _polyline_at(t, pts, x)
        lam = 1e-8 * len(x)
        poles = _solve(knots, x, data, fixed_t, fixed_p, lam, np.ones(len(x)))
        res = np.linalg.norm(basis_matrix(knots, x) @ poles - data, axis=1)
        fres = np.linalg.norm(basis_matrix(knots, fixed_t) @ poles - fixed_p, axis=1)
        if res.max() <= tol and fres.max() <= 1e-9 * scale:
            return knots, poles
        bounds = np.concatenate([[0.0], interior, [1.0]])
        # refine where the polyline is missed, and around nodes the curve cannot pass through yet
        # (two nodes close together on one curve need a knot between them)
        missed = np.concatenate([x[res > tol], fixed_t[fres > 1e-9 * scale]])
        bad = np.unique(np.clip(np.searchsorted(bounds, missed, side="right") - 1, 0, len(bounds) - 2))
        new = 0.5 * (bounds[bad] + bounds[bad + 1])
        new = new[new - bounds[bad] > 1e-9]
        if len(new) == 0:
            break
        interior = np.sort(np.concatenate([interior, new]))
    raise FitError(f"{name}: no cubic B-spline within {tol:.3g} mm of its {len(t)}-point polyline after "
                   "knot refinement; raise --fit-tol or smooth the stroke")
