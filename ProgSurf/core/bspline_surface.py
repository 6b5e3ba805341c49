"""A non-rational B-spline surface of degree <= 3 in numpy: points, first derivatives and unit
normals at many parameters at once, and the projection of points onto it.

The CAD adapter hands ProgSurf's faces over as arrays (cad.faces.surface_derivatives); G1 mode
(cad.g1) samples thousands of seam normals per face and the quality report (cad.analysis) projects
every stroke sample onto the faces, which one OCC call per point would make slow.
"""
from __future__ import annotations

import numpy as np

from .bspline import SpanBasis
from .types import FloatArray


class SurfaceDerivatives:
    """First derivatives S_s, S_r of a non-rational B-spline surface at many (s, r) at once, from
    its poles (the derivative surfaces' poles, Piegl & Tiller eq. 3.17): the same values as OCC's
    getDN to round-off, without one Python call per point.

    poles  : (nu, nv, 3) float
    ku, kv : (nu + p + 1,), (nv + q + 1,) float, the full clamped knot vectors (knots repeated by
             their multiplicities)
    p, q   : the degrees in s and r (<= 3)
    """

    def __init__(self, poles: FloatArray, ku: FloatArray, kv: FloatArray, p: int, q: int):
        self.p, self.q = p, q
        self.ku = np.asarray(ku, dtype=float)
        self.kv = np.asarray(kv, dtype=float)
        self.poles = np.asarray(poles, dtype=float)
        self._span = {"u": SpanBasis(self.ku, self.p), "v": SpanBasis(self.kv, self.q)}
        self.du = self._diff(self.poles, self.ku, self.p, axis=0)
        self.dv = self._diff(self.poles, self.kv, self.q, axis=1)
        # round-off of a derivative that is zero (along a collapsed side: the apex of a 3-sided
        # face), below which it is set to the exact 0 that OCC gives there
        self._tiny = tuple(1e-12 * max(float(np.abs(d).max()), 1e-300) for d in (self.du, self.dv))

    @staticmethod
    def _diff(poles, knots, degree, axis):
        n = poles.shape[axis]
        span = knots[degree + 1:degree + n] - knots[1:n]
        scale = np.divide(degree, span, out=np.zeros_like(span), where=span > 0)
        d = np.diff(poles, axis=axis)
        shape = [1, 1, 1]
        shape[axis] = n - 1
        return d * scale.reshape(shape)

    def derivatives(self, s, r) -> tuple[FloatArray, FloatArray]:
        """(S_s, S_r), each (m, 3), at parameters s, r (m,)."""
        return self.evaluate(s, r, values=False)[1:]

    def evaluate(self, s, r, values: bool = True) -> tuple:
        """(S or None, S_s, S_r), each (m, 3), at parameters s, r (m,)."""
        s, r = np.atleast_1d(np.asarray(s, dtype=float)), np.atleast_1d(np.asarray(r, dtype=float))
        if len(s) > 1 and np.all(s == s[0]):          # along an iso-line s = const (a side)
            bu, bu1 = self._row("u", s[0])
            bv, bv1 = self._span["v"](r)
            q = (self._iso(bu, self.poles, bv, 0) if values else None)
            ds, dr = self._iso(bu1, self.du, bv, 0), self._iso(bu, self.dv, bv1, 0)
        elif len(r) > 1 and np.all(r == r[0]):        # along r = const
            bv, bv1 = self._row("v", r[0])
            bu, bu1 = self._span["u"](s)
            q = (self._iso(bv, self.poles, bu, 1) if values else None)
            ds, dr = self._iso(bv, self.du, bu1, 1), self._iso(bv1, self.dv, bu, 1)
        else:
            bu, bu1 = self._span["u"](s)
            bv, bv1 = self._span["v"](r)
            q = self._contract(bu, self.poles, bv) if values else None
            ds, dr = self._contract(bu1, self.du, bv), self._contract(bu, self.dv, bv1)
        for d, tiny in ((ds, self._tiny[0]), (dr, self._tiny[1])):
            d[np.abs(d).max(axis=1) <= tiny] = 0.0
        return q, ds, dr

    def _row(self, direction: str, t: float) -> tuple[FloatArray, FloatArray]:
        """Basis and derivative basis (1, n) at one parameter; at 0 or 1 (clamped ends) only the
        end functions are 1."""
        basis = self._span[direction]
        if t in (0.0, 1.0):
            b, b1 = np.zeros((1, basis.n)), np.zeros((1, basis.n - 1))
            b[0, -1 if t == 1.0 else 0] = b1[0, -1 if t == 1.0 else 0] = 1.0
            return b, b1
        return basis(np.array([t]))

    @staticmethod
    def _iso(row: FloatArray, poles: FloatArray, basis: FloatArray, axis: int) -> FloatArray:
        """sum over both pole indices with the fixed direction's basis `row` (1, n_axis) and the
        other direction's `basis` (m, n_other): the iso-curve's poles first, then its points."""
        curve = np.tensordot(row[0], poles, axes=([0], [axis]))        # (n_other, 3)
        return basis @ curve

    @staticmethod
    def _contract(bu: FloatArray, poles: FloatArray, bv: FloatArray) -> FloatArray:
        """sum_ij bu[m, i] poles[i, j] bv[m, j] -> (m, 3), as one matrix product and a row sum."""
        rows = (bu @ poles.reshape(poles.shape[0], -1)).reshape(len(bu), poles.shape[1], 3)
        return np.einsum("mjd,mj->md", rows, bv)

    def normals(self, s, r) -> tuple[FloatArray, np.ndarray]:
        """Unit normals (m, 3) and (m,) True where defined, by unit_normals' rule."""
        return unit_normals(*self.derivatives(s, r))


def unit_normals(ds: FloatArray, dr: FloatArray) -> tuple[FloatArray, np.ndarray]:
    """Unit normals S_s x S_r / |.| (m, 3) of many points from their derivatives S_s, S_r (m, 3),
    and (m,) True where defined (zero rows where not: |S_s x S_r| <= 1e-6 |S_s| |S_r|, the apex of
    a 3-sided face); the rule of cad.faces.unit_normal at one point."""
    n = np.cross(ds, dr)
    ln = np.linalg.norm(n, axis=1)
    ok = ln > 1e-6 * np.maximum(np.linalg.norm(ds, axis=1) * np.linalg.norm(dr, axis=1), 1e-300)
    return np.divide(n, ln[:, None], out=np.zeros_like(n), where=ok[:, None]), ok


def project_points(surface: SurfaceDerivatives, bounds: tuple, p: FloatArray, uv: FloatArray,
                   iterations: int = 12) -> FloatArray:
    """(m,) distance from each point p (m, 3) to the surface patch over bounds (u0, u1, v0, v1):
    clamped Gauss-Newton from the starts uv (m, 2), all points at once (the footpoint of Qin &
    Wright Eq. 2 on the built surface). Each step solves the 2x2 normal equations
    [S_u.S_u S_u.S_v; S_u.S_v S_v.S_v] (du, dv) = (S_u.r, S_v.r) of the residual r = p - S(u, v),
    clamped to bounds; a point stops when its step is below 1e-13 or the system is singular. The
    smallest |r| seen is returned (the last step's included)."""
    u0, u1, v0, v1 = bounds
    u, v = uv[:, 0].astype(float).copy(), uv[:, 1].astype(float).copy()
    best = np.full(len(p), np.inf)
    live = np.ones(len(p), dtype=bool)
    for _ in range(iterations):
        idx = np.flatnonzero(live)
        if not len(idx):
            break
        q, a, b = surface.evaluate(u[idx], v[idx])
        r = p[idx] - q
        best[idx] = np.minimum(best[idx], np.linalg.norm(r, axis=1))
        aa, ab, bb = (a * a).sum(1), (a * b).sum(1), (b * b).sum(1)
        ar, br = (a * r).sum(1), (b * r).sum(1)
        det = aa * bb - ab * ab
        ok = det > 1e-300 * np.maximum(aa * bb, 1e-300)
        safe = np.where(ok, det, 1.0)
        nu = np.clip(u[idx] + (bb * ar - ab * br) / safe, u0, u1)
        nv = np.clip(v[idx] + (aa * br - ab * ar) / safe, v0, v1)
        moving = ok & (np.abs(nu - u[idx]) + np.abs(nv - v[idx]) >= 1e-13)
        u[idx] = np.where(moving, nu, u[idx])
        v[idx] = np.where(moving, nv, v[idx])
        live[idx] = moving
    q = surface.evaluate(u, v)[0]
    return np.minimum(best, np.linalg.norm(p - q, axis=1))
