"""The bicubically blended Coons patch of Qin & Wright, Eq. (1).

    P(u,v) = [-1 f1(u) f2(u)] . | 0       p(u,0)  p(u,1) | . [-1 f1(v) f2(v)]^T
                                | p(0,v)  p(0,0)  p(0,1) |
                                | p(1,v)  p(1,0)  p(1,1) |

with the cubic Hermite blends f1(t) = 2t^3 - 3t^2 + 1 and f2(t) = -2t^3 + 3t^2 (f1 + f2 = 1).
Expanded, P = f1(u) p(0,v) + f2(u) p(1,v) + f1(v) p(u,0) + f2(v) p(u,1) - the bilinear-blended corners.

Boundary names follow the paper: ``bottom`` = p(u,0), ``top`` = p(u,1), ``left`` = p(0,v),
``right`` = p(1,v). A 3-sided patch is the special case whose ``top`` is one point (paper Fig. 4).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Union

import numpy as np
import numpy.typing as npt

from .errors import ProgSurfError
from .types import FloatArray, Polyline

Curve = Callable[[FloatArray], FloatArray]
"""A boundary curve: parameters (...,) in [0, 1] -> points (..., 3)."""


def f1(t: npt.ArrayLike) -> FloatArray:
    """Hermite blend f1(t) = 2t^3 - 3t^2 + 1 (paper, Eq. 1)."""
    t = np.asarray(t, dtype=float)
    return 2.0 * t**3 - 3.0 * t**2 + 1.0


def f2(t: npt.ArrayLike) -> FloatArray:
    """Hermite blend f2(t) = -2t^3 + 3t^2 = 1 - f1(t)."""
    t = np.asarray(t, dtype=float)
    return -2.0 * t**3 + 3.0 * t**2


def df1(t: npt.ArrayLike) -> FloatArray:
    t = np.asarray(t, dtype=float)
    return 6.0 * t**2 - 6.0 * t


def df2(t: npt.ArrayLike) -> FloatArray:
    return -df1(t)


def _as_curve(side: Union[Polyline, FloatArray, Curve]) -> Curve:
    """A polyline, an (n,3) point array (uniform index parameters, as the paper maps
    equalised points to the unit square) or a callable, as a callable curve."""
    if isinstance(side, Polyline):
        return side.evaluate
    if callable(side):
        return side
    pts = np.asarray(side, dtype=float).reshape(-1, 3)
    if len(pts) == 1:
        pts = np.vstack([pts, pts])
    return Polyline(pts, np.linspace(0.0, 1.0, len(pts))).evaluate


def _derivative(curve: Curve, t: FloatArray, h: float = 1e-6) -> FloatArray:
    """Central difference of a boundary curve, one-sided at the ends."""
    lo = np.clip(t - h, 0.0, 1.0)
    hi = np.clip(t + h, 0.0, 1.0)
    return (curve(hi) - curve(lo)) / (hi - lo)[..., None]


def coons_blend(u: FloatArray, v: FloatArray, sides: tuple, corners: FloatArray) -> FloatArray:
    """Eq. (1) at (u, v) (...,) from its sides' points there: sides = (p(u,0), p(1,v), p(u,1),
    p(0,v)), each (..., 3), and corners (4, 3) p(0,0), p(1,0), p(1,1), p(0,1) (or (4, ..., 3), one
    set per point: several patches at once)."""
    bottom, right, top, left = sides
    p00, p10, p11, p01 = corners
    fu1, fu2 = f1(u)[..., None], f2(u)[..., None]
    fv1, fv2 = f1(v)[..., None], f2(v)[..., None]
    ruled = fu1 * left + fu2 * right + fv1 * bottom + fv2 * top
    corner = fu1 * (fv1 * p00 + fv2 * p01) + fu2 * (fv1 * p10 + fv2 * p11)
    return ruled - corner


@dataclass(frozen=True)
class CoonsPatch:
    """Bicubically blended Coons patch P(u,v) on [0,1]^2 (Qin & Wright Eq. 1).

    bottom : p(u,0)    right : p(1,v)    top : p(u,1)    left : p(0,v)
    Each side is a callable t -> (..., 3); use :func:`coons_patch` to build from polylines.
    The four corners are taken from bottom and top, so left/right must meet them.
    """

    bottom: Curve
    right: Curve
    top: Curve
    left: Curve

    def corners(self) -> FloatArray:
        """(4, 3): p(0,0), p(1,0), p(1,1), p(0,1) (computed once: the sides do not change)."""
        cached = self.__dict__.get("_corners")
        if cached is None:
            b = self.bottom(np.array([0.0, 1.0]))
            t = self.top(np.array([0.0, 1.0]))
            cached = np.array([b[0], b[1], t[1], t[0]])
            cached.setflags(write=False)
            object.__setattr__(self, "_corners", cached)
        return cached

    def evaluate(self, u: npt.ArrayLike, v: npt.ArrayLike) -> FloatArray:
        """Points P(u,v); u and v broadcast together; returns (..., 3)."""
        u, v = np.broadcast_arrays(np.asarray(u, dtype=float), np.asarray(v, dtype=float))
        return coons_blend(u, v, (self.bottom(u), self.right(v), self.top(u), self.left(v)), self.corners())

    def grid(self, u: npt.ArrayLike, v: npt.ArrayLike) -> FloatArray:
        """Points on the tensor grid u x v: returns (len(u), len(v), 3)."""
        uu, vv = np.meshgrid(np.asarray(u, float), np.asarray(v, float), indexing="ij")
        return self.evaluate(uu, vv)

    def derivatives(self, u: npt.ArrayLike, v: npt.ArrayLike) -> tuple[FloatArray, FloatArray]:
        """First partials (P_u, P_v), each (..., 3). Boundary tangents by central differences."""
        u, v = np.broadcast_arrays(np.asarray(u, dtype=float), np.asarray(v, dtype=float))
        p00, p10, p11, p01 = self.corners()
        du1, du2 = df1(u)[..., None], df2(u)[..., None]
        dv1, dv2 = df1(v)[..., None], df2(v)[..., None]
        fu1, fu2 = f1(u)[..., None], f2(u)[..., None]
        fv1, fv2 = f1(v)[..., None], f2(v)[..., None]
        pu = (du1 * self.left(v) + du2 * self.right(v)
              + fv1 * _derivative(self.bottom, u) + fv2 * _derivative(self.top, u)
              - du1 * (fv1 * p00 + fv2 * p01) - du2 * (fv1 * p10 + fv2 * p11))
        pv = (fu1 * _derivative(self.left, v) + fu2 * _derivative(self.right, v)
              + dv1 * self.bottom(u) + dv2 * self.top(u)
              - fu1 * (dv1 * p00 + dv2 * p01) - fu2 * (dv1 * p10 + dv2 * p11))
        return pu, pv

    def normals(self, u: npt.ArrayLike, v: npt.ArrayLike) -> FloatArray:
        """Unit normals P_u x P_v / |P_u x P_v|, (..., 3); zero where degenerate."""
        pu, pv = self.derivatives(u, v)
        n = np.cross(pu, pv)
        length = np.linalg.norm(n, axis=-1, keepdims=True)
        return np.divide(n, length, out=np.zeros_like(n), where=length > 1e-300)


def coons_patch(bottom, right, top, left, tol: float = 1e-9) -> CoonsPatch:
    """Build a Coons patch from four sides oriented as bottom c0->c1, right c1->c2,
    top c3->c2, left c0->c3. Sides may be Polylines, (n,3) arrays or callables.

    Raises ProgSurfError if the sides do not meet at the four corners (gap > tol x size).
    """
    b, r, t, l = (_as_curve(s) for s in (bottom, right, top, left))
    ends = np.array([0.0, 1.0])
    bb, rr, tt, ll = b(ends), r(ends), t(ends), l(ends)
    size = float(np.ptp(np.vstack([bb, rr, tt, ll]), axis=0).max())
    pairs = {"c0 (bottom/left)": (bb[0], ll[0]), "c1 (bottom/right)": (bb[1], rr[0]),
             "c2 (top/right)": (tt[1], rr[1]), "c3 (top/left)": (tt[0], ll[1])}
    for name, (p, q) in pairs.items():
        gap = float(np.linalg.norm(p - q))
        if gap > tol * size:
            raise ProgSurfError(f"Coons patch sides do not meet at corner {name}: gap {gap:.3g} mm; "
                                "close the boundary first")
    return CoonsPatch(b, r, t, l)
