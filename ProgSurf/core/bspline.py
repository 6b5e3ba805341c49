"""Cubic B-spline basis functions in numpy (Cox-de Boor), shared by stroke fairing (core.fairing)
and the constrained curve fit of the shared edges (core.curve_fit)."""
from __future__ import annotations

import numpy as np

from .types import FloatArray

DEGREE = 3


def basis_matrix(knots: FloatArray, t: FloatArray, degree: int = DEGREE) -> FloatArray:
    """B-spline basis N_j(t_i), (m, n_poles), for a clamped full knot vector on [0, 1]: the degree+1
    basis functions that are non-zero in each point's knot span (Piegl & Tiller A2.2, vectorised
    over the points), scattered into a dense matrix."""
    return _basis(knots, t, degree, False)[0]


def basis_matrices(knots: FloatArray, t: FloatArray, degree: int = DEGREE) -> tuple[FloatArray, FloatArray]:
    """(basis_matrix(knots, t, degree), basis_matrix(knots[1:-1], t, degree - 1)) in one pass: the
    lower-degree functions are the intermediate values of the same recursion. The second is the
    basis of a derivative's poles (a first derivative has degree - 1 on knots[1:-1])."""
    return _basis(knots, t, degree, True)


def _basis(knots: FloatArray, t: FloatArray, degree: int, with_lower: bool) -> tuple:
    """basis_matrices; the lower-degree matrix only when asked for (else None): basis_matrix is
    called thousands of times by the knot refinement of core.curve_fit."""
    knots = np.asarray(knots, dtype=float)
    # np.minimum/np.maximum: np.clip's same values, without its per-call checks
    t = np.minimum(np.maximum(np.ravel(np.asarray(t, dtype=float)), knots[0]), knots[-1])
    m, n = len(t), len(knots) - degree - 1
    # the half-open span containing t; the last point belongs to the last non-empty span
    last = np.max(np.nonzero(knots[1:] > knots[:-1])[0])
    span = np.minimum(np.searchsorted(knots, t, side="right") - 1, last)
    local = np.zeros((m, degree + 1))
    local[:, 0] = 1.0
    left = np.zeros((m, degree + 1))
    right = np.zeros((m, degree + 1))
    rows = np.arange(m)[:, None]
    lower = np.zeros((m, max(n - 1, 0))) if with_lower else None
    for j in range(1, degree + 1):
        if with_lower and j == degree and n > 1:
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


def span_samples(breaks: FloatArray, per_span: int) -> FloatArray:
    """`per_span` parameters evenly inside each span between consecutive `breaks` (sorted): data in
    every span, however short, so that no basis function is left without samples."""
    b = np.asarray(breaks, dtype=float)
    return (b[:-1, None] + np.diff(b)[:, None] * (np.arange(1, per_span + 1) / (per_span + 1))[None, :]).ravel()


def uniform_knots(m: int, degree: int = DEGREE) -> FloatArray:
    """The clamped uniform knot vector on [0, 1] of m control points."""
    return np.concatenate([np.zeros(degree), np.linspace(0.0, 1.0, m - degree + 1), np.ones(degree)])


class SpanBasis:
    """basis_matrices for one fixed knot vector, many times: each non-empty knot span's basis
    functions (and those of the derivative basis) as polynomials in the span's local parameter,
    found once by interpolating basis_matrices at four points of the span (exact for polynomials
    of degree <= 3), then evaluated with one product per call."""

    _U = np.array([0.0, 0.25, 0.5, 0.75])

    def __init__(self, knots: FloatArray, degree: int = DEGREE):
        if degree > 3:
            raise ValueError("SpanBasis interpolates with cubics: degree <= 3")
        knots = np.asarray(knots, dtype=float)
        self.knots, self.degree = knots, degree
        self.n = len(knots) - degree - 1
        self.starts = np.flatnonzero(knots[1:] > knots[:-1])
        self.last = int(self.starts.max())
        self.pos = np.full(len(knots), -1)
        self.pos[self.starts] = np.arange(len(self.starts))
        a = knots[self.starts]
        self.width = knots[self.starts + 1] - a
        t = (a[:, None] + self.width[:, None] * self._U[None, :]).ravel()
        full, lower = basis_matrices(knots, t, degree)
        span = np.repeat(self.starts, 4)
        rows = np.arange(len(t))[:, None]
        local = full[rows, span[:, None] - degree + np.arange(degree + 1)].reshape(-1, 4, degree + 1)
        inv = np.linalg.inv(np.vander(self._U, 4, increasing=True))
        self.coef = np.einsum("kj,sjf->skf", inv, local)                # (spans, powers, functions)
        if self.n > 1:
            low = lower[rows, span[:, None] - degree + np.arange(degree)].reshape(-1, 4, degree)
            self.coef_low = np.einsum("kj,sjf->skf", inv, low)
        else:
            self.coef_low = None

    def __call__(self, t: FloatArray) -> tuple[FloatArray, FloatArray]:
        """(basis (m, n), derivative basis (m, n - 1)) at t, as basis_matrices(knots, t, degree)."""
        k, p = self.knots, self.degree
        t = np.clip(np.ravel(np.asarray(t, dtype=float)), k[0], k[-1])
        span = np.minimum(np.searchsorted(k, t, side="right") - 1, self.last)
        s = self.pos[span]
        u = (t - k[span]) / self.width[s]
        powers = u[:, None] ** np.arange(4)[None, :]
        rows = np.arange(len(t))[:, None]
        out = np.zeros((len(t), self.n))
        out[rows, span[:, None] - p + np.arange(p + 1)] = np.einsum("mk,mkf->mf", powers, self.coef[s])
        lower = np.zeros((len(t), max(self.n - 1, 0)))
        if self.coef_low is not None:
            lower[rows, span[:, None] - p + np.arange(p)] = np.einsum("mk,mkf->mf", powers, self.coef_low[s])
        return out, lower
