"""Cubic B-spline basis functions in numpy (Cox-de Boor), shared by stroke fairing (core.fairing)
and the constrained curve fit of the CAD adapter (cad.fit)."""
from __future__ import annotations

import numpy as np

from .types import FloatArray

DEGREE = 3


def basis_matrix(knots: FloatArray, t: FloatArray, degree: int = DEGREE) -> FloatArray:
    """B-spline basis N_j(t_i), (m, n_poles), for a clamped full knot vector on [0, 1] (Cox-de Boor)."""
    knots = np.asarray(knots, dtype=float)
    t = np.clip(np.asarray(t, dtype=float), knots[0], knots[-1])[:, None]
    n = len(knots) - degree - 1
    # degree 0: the half-open span containing t; the last point belongs to the last non-empty span
    last = np.max(np.nonzero(knots[1:] > knots[:-1])[0])
    span = np.minimum(np.searchsorted(knots, t[:, 0], side="right") - 1, last)
    basis = np.zeros((len(t), len(knots) - 1))
    basis[np.arange(len(t)), span] = 1.0
    for p in range(1, degree + 1):
        lo, hi = knots[: len(knots) - 1 - p], knots[p: len(knots) - 1]
        lo1, hi1 = knots[1: len(knots) - p], knots[p + 1:]
        d0, d1 = hi - lo, hi1 - lo1
        a = np.divide(t - lo, d0, out=np.zeros((len(t), len(d0))), where=d0 > 0)
        b = np.divide(hi1 - t, d1, out=np.zeros((len(t), len(d1))), where=d1 > 0)
        basis = a * basis[:, :-1] + b * basis[:, 1:]
    return basis[:, :n]


def uniform_knots(m: int, degree: int = DEGREE) -> FloatArray:
    """The clamped uniform knot vector on [0, 1] of m control points."""
    return np.concatenate([np.zeros(degree), np.linspace(0.0, 1.0, m - degree + 1), np.ones(degree)])
