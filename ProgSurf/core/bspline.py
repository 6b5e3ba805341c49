"""Cubic B-spline basis functions in numpy (Cox-de Boor), shared by stroke fairing (core.fairing)
and the constrained curve fit of the CAD adapter (cad.fit)."""
from __future__ import annotations

import numpy as np

from .types import FloatArray

DEGREE = 3


def basis_matrix(knots: FloatArray, t: FloatArray, degree: int = DEGREE) -> FloatArray:
    """B-spline basis N_j(t_i), (m, n_poles), for a clamped full knot vector on [0, 1]: the degree+1
    basis functions that are non-zero in each point's knot span (Piegl & Tiller A2.2, vectorised
    over the points), scattered into a dense matrix."""
    return basis_matrices(knots, t, degree)[0]


def basis_matrices(knots: FloatArray, t: FloatArray, degree: int = DEGREE) -> tuple[FloatArray, FloatArray]:
    """(basis_matrix(knots, t, degree), basis_matrix(knots[1:-1], t, degree - 1)) in one pass: the
    lower-degree functions are the intermediate values of the same recursion. The second is the
    basis of a derivative's poles (a first derivative has degree - 1 on knots[1:-1])."""
    knots = np.asarray(knots, dtype=float)
    t = np.clip(np.ravel(np.asarray(t, dtype=float)), knots[0], knots[-1])
    m, n = len(t), len(knots) - degree - 1
    # the half-open span containing t; the last point belongs to the last non-empty span
    last = np.max(np.nonzero(knots[1:] > knots[:-1])[0])
    span = np.minimum(np.searchsorted(knots, t, side="right") - 1, last)
    local = np.zeros((m, degree + 1))
    local[:, 0] = 1.0
    left = np.zeros((m, degree + 1))
    right = np.zeros((m, degree + 1))
    rows = np.arange(m)[:, None]
    lower = np.zeros((m, max(n - 1, 0)))
    for j in range(1, degree + 1):
        if j == degree and n > 1:
            # degree - 1 functions N_{span-degree+1 .. span} on knots = indices - 1 on knots[1:-1]
            lower[rows, span[:, None] - degree + np.arange(degree)] = local[:, :degree]
        left[:, j] = t - knots[span + 1 - j]
        right[:, j] = knots[span + j] - t
        saved = np.zeros(m)
        for r in range(j):
            denom = right[:, r + 1] + left[:, j - r]
            temp = np.divide(local[:, r], denom, out=np.zeros(m), where=denom > 0)
            local[:, r] = saved + right[:, r + 1] * temp
            saved = left[:, j - r] * temp
        local[:, j] = saved
    out = np.zeros((m, n))
    out[rows, span[:, None] - degree + np.arange(degree + 1)] = local
    return out, lower


def uniform_knots(m: int, degree: int = DEGREE) -> FloatArray:
    """The clamped uniform knot vector on [0, 1] of m control points."""
    return np.concatenate([np.zeros(degree), np.linspace(0.0, 1.0, m - degree + 1), np.ones(degree)])
