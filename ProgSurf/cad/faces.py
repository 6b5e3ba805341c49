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

from ..core.bspline_surface import SurfaceDerivatives
from ..core.errors import FitError
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
    ~20x cheaper on single 3-vectors (seam measurement and G1 sample thousands of them); the rule
    of core.bspline_surface.unit_normals for many points."""
    ax, ay, az = surface.getDN(s, r, 1, 0)
    bx, by, bz = surface.getDN(s, r, 0, 1)
    nx, ny, nz = ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx
    ln = math.sqrt(nx * nx + ny * ny + nz * nz)
    scale = math.sqrt(ax * ax + ay * ay + az * az) * math.sqrt(bx * bx + by * by + bz * bz)
    if ln <= 1e-6 * max(scale, 1e-300):
        return None
    return np.array([nx / ln, ny / ln, nz / ln])


def full_knots(surface, direction: str) -> FloatArray:
    """The full knot vector of a B-spline surface in direction "U" or "V": each knot repeated by
    its multiplicity."""
    ks = getattr(surface, f"get{direction}Knots")()
    ms = getattr(surface, f"get{direction}Multiplicities")()
    return np.repeat(np.asarray(ks, dtype=float), ms)


def surface_derivatives(surface) -> SurfaceDerivatives:
    """The numpy evaluator (core.bspline_surface.SurfaceDerivatives) of a non-rational
    Part.BSplineSurface (see is_plain_bspline), from its poles and knots."""
    return SurfaceDerivatives(to_array(surface.getPoles()), full_knots(surface, "U"),
                              full_knots(surface, "V"), surface.UDegree, surface.VDegree)


def is_plain_bspline(surface) -> bool:
    """True for a non-rational B-spline surface of degree <= 3 (what surface_derivatives evaluates;
    ProgSurf's faces are bicubic, a peer's GeomPlate surface may be of degree 8)."""
    return (getattr(surface, "TypeId", "") == "Part::GeomBSplineSurface"
            and not surface.isURational() and not surface.isVRational()
            and surface.UDegree <= 3 and surface.VDegree <= 3)
