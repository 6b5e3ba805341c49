"""Exact B-spline form of the bicubically blended Coons patch of four B-spline sides.

Qin & Wright Eq. (1) with sides C0 = p(s,0) (bottom), C1 = p(s,1) (top), D0 = p(0,r) (left),
D1 = p(1,r) (right) and Hermite blends f1, f2:

    P(s,r) = f1(r) C0(s) + f2(r) C1(s) + f1(s) D0(r) + f2(s) D1(r)
             - [f1(s) f2(s)] [[P00, P01], [P10, P11]] [f1(r) f2(r)]^T

f1 and f2 are cubic polynomials: in the cubic Bernstein basis f1 = B0 + B1 and f2 = B2 + B3. Writing
them, and the opposite sides, in one common B-spline basis per direction (degree elevation and knot
insertion done by OCC on copies) makes every term a tensor product of known coefficients, so the
poles of P follow by adding arrays: the surface IS the Coons patch, no sampling and no fitting.
(This is what OCC's GeomFill_Coons does; GeomFill refuses curves with fewer than 4 poles, this does not.)
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core.errors import FitError
from ..core.memo import per_object
from ..core.types import FloatArray
from ._occ import Part
from .curves import DEGREE, _knots_mults, make_compatible, to_array, to_vectors


def _blend_curves() -> tuple:
    """f1 and f2 as cubic Bezier 'curves' whose x coordinate is the blend value."""
    out = []
    for coef in ((1.0, 1.0, 0.0, 0.0), (0.0, 0.0, 1.0, 1.0)):
        c = Part.BSplineCurve()
        c.buildFromPolesMultsKnots(to_vectors(np.array([[x, 0.0, 0.0] for x in coef])),
                                   [4, 4], [0.0, 1.0], False, DEGREE)
        out.append(c)
    return tuple(out)


@dataclass(frozen=True)
class _Basis:
    """One direction of the common tensor basis: knots, mults, degree, and the coefficients of
    the two sides (n, 3) and of the blends f1, f2 (n,) in it."""

    knots: list
    mults: list
    degree: int
    side0: FloatArray
    side1: FloatArray
    f1: FloatArray
    f2: FloatArray


def _basis(side0, side1) -> _Basis:
    b1, b2 = _blend_curves()
    c0, c1, g1, g2 = make_compatible([side0, side1, b1, b2])
    knots, mults = _knots_mults(c0)
    for c in (c1, g1, g2):
        if c.NbPoles != c0.NbPoles:
            raise FitError(f"could not make opposite Coons sides compatible ({c.NbPoles} vs "
                           f"{c0.NbPoles} poles); report this sketch")
    return _Basis(knots, mults, c0.Degree, to_array(c0.getPoles()), to_array(c1.getPoles()),
                  to_array(g1.getPoles())[:, 0], to_array(g2.getPoles())[:, 0])


def coons_poles(bottom, right, top, left) -> tuple[FloatArray, _Basis, _Basis]:
    """Poles (nu, nv, 3) of the Coons patch of four Part.BSplineCurve sides on [0,1], oriented
    bottom c0->c1, right c1->c2, top c3->c2, left c0->c3 (as ProgSurf.core.coons.coons_patch)."""
    u = _basis(bottom, top)      # s direction: C0 = bottom, C1 = top
    v = _basis(left, right)      # r direction: D0 = left, D1 = right
    p00, p10 = u.side0[0], u.side0[-1]
    p01, p11 = u.side1[0], u.side1[-1]
    ruled_r = u.side0[:, None, :] * v.f1[None, :, None] + u.side1[:, None, :] * v.f2[None, :, None]
    ruled_s = u.f1[:, None, None] * v.side0[None, :, :] + u.f2[:, None, None] * v.side1[None, :, :]
    corner = (u.f1[:, None, None] * (v.f1[None, :, None] * p00 + v.f2[None, :, None] * p01)
              + u.f2[:, None, None] * (v.f1[None, :, None] * p10 + v.f2[None, :, None] * p11))
    return ruled_r + ruled_s - corner, u, v


def coons_surface(bottom, right, top, left):
    """The exact B-spline surface S(s,r) on [0,1]^2 of the Coons patch of four B-spline sides
    (Qin & Wright Eq. 1); S(s,0) = bottom(s), S(1,r) = right(r), S(s,1) = top(s), S(0,r) = left(r)."""
    poles, u, v = coons_poles(bottom, right, top, left)
    surface = Part.BSplineSurface()
    surface.buildFromPolesMultsKnots(np.asarray(poles, dtype=float).tolist(), u.mults, v.mults,
                                     u.knots, v.knots, False, False, u.degree, v.degree)
    return surface


def unit_normal(surface, s: float, r: float) -> FloatArray | None:
    """Unit normal S_s x S_r / |.| of a surface at (s, r), None where degenerate (the apex of a
    3-sided face). Plain-float arithmetic: the same operations as np.cross and np.linalg.norm,
    ~20x cheaper on single 3-vectors (seam measurement and G1 sample thousands of them)."""
    ax, ay, az = surface.getDN(s, r, 1, 0)
    bx, by, bz = surface.getDN(s, r, 0, 1)
    nx, ny, nz = ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx
    ln = math.sqrt(nx * nx + ny * ny + nz * nz)
    scale = math.sqrt(ax * ax + ay * ay + az * az) * math.sqrt(bx * bx + by * by + bz * bz)
    if ln <= 1e-6 * max(scale, 1e-300):
        return None
    return np.array([nx / ln, ny / ln, nz / ln])


class SurfaceDerivatives:
    """First derivatives S_s, S_r of a non-rational B-spline surface at many (s, r) at once, in
    numpy from its poles (the derivative surfaces' poles, Piegl & Tiller eq. 3.17): the same values
    as OCC's getDN to round-off, without one Python call per point (G1 samples thousands)."""

    def __init__(self, surface):
        from .curves import to_array
        from ..core.bspline import SpanBasis

        poles = to_array(surface.getPoles())
        self.p, self.q = surface.UDegree, surface.VDegree
        self.ku = np.repeat(np.asarray(surface.getUKnots(), dtype=float), surface.getUMultiplicities())
        self.kv = np.repeat(np.asarray(surface.getVKnots(), dtype=float), surface.getVMultiplicities())
        self.poles = poles
        self._span = {"u": SpanBasis(self.ku, self.p), "v": SpanBasis(self.kv, self.q)}
        self.du = self._diff(poles, self.ku, self.p, axis=0)
        self.dv = self._diff(poles, self.kv, self.q, axis=1)
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
        """Unit normals (m, 3) and (m,) True where defined, by unit_normal's rule."""
        return unit_normals(*self.derivatives(s, r))


def unit_normals(ds: FloatArray, dr: FloatArray) -> tuple[FloatArray, np.ndarray]:
    """unit_normal for many points from their derivatives S_s, S_r (m, 3): unit normals (m, 3)
    and (m,) True where defined (zero rows where not)."""
    n = np.cross(ds, dr)
    ln = np.linalg.norm(n, axis=1)
    ok = ln > 1e-6 * np.maximum(np.linalg.norm(ds, axis=1) * np.linalg.norm(dr, axis=1), 1e-300)
    return np.divide(n, ln[:, None], out=np.zeros_like(n), where=ok[:, None]), ok


_DERIVATIVES: dict = {}


def derivatives_of(surface) -> SurfaceDerivatives:
    """The SurfaceDerivatives of a surface, kept while the surface object lives (faces are reused
    between builds)."""
    return per_object(_DERIVATIVES, (surface,), lambda: SurfaceDerivatives(surface))


def is_plain_bspline(surface) -> bool:
    """True for a non-rational B-spline surface of degree <= 3 (what SurfaceDerivatives evaluates;
    ProgSurf's faces are bicubic, a peer's GeomPlate surface may be of degree 8)."""
    return (getattr(surface, "TypeId", "") == "Part::GeomBSplineSurface"
            and not surface.isURational() and not surface.isVRational()
            and surface.UDegree <= 3 and surface.VDegree <= 3)
