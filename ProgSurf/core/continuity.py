"""Tangent-continuous (G1) seams between sub-patches: shared cross-boundary flux, Gregory corners.

Beyond Qin & Wright (their sub-patches are G0 Coons patches, Eq. 1). Following Egorov, "Curve mesh
surfaces" (Hermitian forms, "Flux Function Estimation Methods" and "mixed derivatives"):

* A C1 (Hermite) Coons patch carries, besides its four boundary curves B(s)=P(s,0), T(s)=P(s,1),
  L(r)=P(0,r), R(r)=P(1,r), four cross-boundary derivative "flux" functions
  Db(s)=P_r(s,0), Dt(s)=P_r(s,1), Dl(r)=P_s(0,r), Dr(r)=P_s(1,r) (Egorov Eq. 1-4, Uv1 Uv2 Vu1 Vu2):

      P = sum_j h_j(r) [B, Db, Dt, T]_j(s) + sum_i h_i(s) [L, Dl, Dr, R]_i(r)
          - sum_ij h_i(s) h_j(r) M_ij(s, r)

  with the cubic Hermite basis h0 = f1, h1 = t - 2t^2 + t^3, h2 = t^3 - t^2, h3 = f2.
* Along an interior seam both faces share the boundary curve, so the tangent planes agree exactly
  when both fluxes lie in one plane containing the seam tangent. The "flux correction" removes from
  each side's G0 flux its component along a common normal n(t) (Egorov Eq. 13: "exclusion of the
  normal component from the flux vector"); n(t) is the mean of the two G0 normals, pulled at the
  seam's ends to the node normal (the plane of the curves meeting there) so that corners agree.
* The twist M_11 at a corner is ambiguous when the two fluxes meeting there have different
  derivatives (Egorov Eq. 24, Mullineux's review of Gregory patches): the Gregory corner term
  tw(s,r) = (s * Dl'(0) + r * Db'(0)) / (s + r) (and its mirror images) honours both.

Sharp features are not smoothed: a seam whose curve turns by more than ``KINK_ANGLE_DEG`` inside a
short window (a kink in a stroke) keeps its G0 flux, and so does the outer boundary (not a seam).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
import numpy.typing as npt

from .coons import f1, f2
from .errors import ProgSurfError
from .types import FloatArray, Polyline

KINK_ANGLE_DEG = 30.0
"""A curve turning by more than this within ``KINK_WINDOW`` of its length has an intended kink."""
KINK_WINDOW = 0.04
"""Half-width of the turning-angle window, as a fraction of the curve's length."""
SHARP_NODE_DEG = 1.0
"""Faces meeting at a node whose corner normals differ by more than this (the G1 target) meet at a sharp
node: the curves through it are not tangent-plane compatible, which no flux can repair."""

Flux = Callable[[FloatArray], FloatArray]
"""A cross-boundary derivative along one side: side parameter (...,) -> vectors (..., 3)."""


# ------------------------------------------------------------------------------ Hermite basis
def h1(t: npt.ArrayLike) -> FloatArray:
    """Hermite basis of the derivative at 0: h1(t) = t - 2t^2 + t^3 (h1'(0) = 1)."""
    t = np.asarray(t, dtype=float)
    return t - 2.0 * t**2 + t**3


def h2(t: npt.ArrayLike) -> FloatArray:
    """Hermite basis of the derivative at 1: h2(t) = t^3 - t^2 (h2'(1) = 1)."""
    t = np.asarray(t, dtype=float)
    return t**3 - t**2


def hermite_basis(t: npt.ArrayLike) -> FloatArray:
    """(..., 4): h0 = f1, h1, h2, h3 = f2 (position at 0, derivative at 0, derivative at 1, position at 1)."""
    return np.stack([f1(t), h1(t), h2(t), f2(t)], axis=-1)


# ------------------------------------------------------------------------------ flux along seams
def unit(v: npt.ArrayLike) -> FloatArray:
    """Unit vectors (..., 3); zero vectors stay zero."""
    v = np.asarray(v, dtype=float)
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    return np.divide(v, n, out=np.zeros_like(v), where=n > 1e-300)


def common_normals(normal_a: FloatArray, normal_b: FloatArray, tangent: FloatArray, t: FloatArray,
                   node0: FloatArray | None = None, node1: FloatArray | None = None) -> FloatArray:
    """The shared normal n(t) (m, 3) of a seam sampled at edge parameters t (m,) in [0, 1].

    normal_a, normal_b : (m, 3) unit normals of the two G0 faces (b is flipped to agree with a)
    tangent            : (m, 3) the seam tangent C'(t); n is made perpendicular to it
    node0, node1       : (3,) node normals at t=0 and t=1 (the plane of the curves meeting there),
                         or None to keep the mean there. The difference is distributed linearly,
                         as Qin & Wright distribute a positional difference (step 4).
    """
    a, b = unit(normal_a), unit(normal_b)
    b = np.where((np.sum(a * b, axis=-1) < 0.0)[..., None], -b, b)
    n = unit(a + b)
    t = np.asarray(t, dtype=float)[:, None]
    for node, end, weight in ((node0, 0, 1.0 - t), (node1, -1, t)):
        if node is not None:
            target = unit(node)
            target = -target if float(target @ n[end]) < 0.0 else target
            n = n + weight * (target - n[end])
    tan = unit(tangent)
    n = n - np.sum(n * tan, axis=-1, keepdims=True) * tan
    return unit(n)


def flux_correction(flux: FloatArray, normal: FloatArray) -> FloatArray:
    """delta = -(D . n) n (..., 3): added to a G0 flux D it leaves D's projection on the common
    tangent plane (Egorov Eq. 13, the normal component excluded)."""
    normal = unit(normal)
    return -np.sum(np.asarray(flux, dtype=float) * normal, axis=-1, keepdims=True) * normal


def compatible_twist(d_first: FloatArray, d_second: FloatArray, free_first: bool,
                     free_second: bool) -> FloatArray:
    """The one twist correction at a patch corner where two flux corrections meet, (3,).

    d_first, d_second : derivatives (along their sides, away from the corner) of the two flux
                        corrections at the corner. A free side (outer boundary, sharp seam,
                        degenerate side) follows the other; between two seams both give way by half
                        (the polynomial limit of the Gregory term when both twists agree)."""
    if free_first and free_second:
        return np.zeros(3)
    if free_first:
        return np.asarray(d_second, dtype=float)
    if free_second:
        return np.asarray(d_first, dtype=float)
    return 0.5 * (np.asarray(d_first, dtype=float) + np.asarray(d_second, dtype=float))


def normal_angle_deg(normal_a: FloatArray, normal_b: FloatArray) -> FloatArray:
    """(...,) angle between unit normals in degrees, orientation ignored (the G1 defect)."""
    c = np.abs(np.sum(unit(normal_a) * unit(normal_b), axis=-1))
    return np.degrees(np.arccos(np.clip(c, 0.0, 1.0)))


# ------------------------------------------------------------------------------ sharp features
def turning_angles(points: FloatArray, window: float = KINK_WINDOW) -> FloatArray:
    """(n,) angle in degrees between the chords entering and leaving each vertex over a window of
    ``window`` x the polyline length on each side (0 at the ends): a noise-robust turning angle."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    arc = np.concatenate([[0.0], np.cumsum(seg)])
    total = float(arc[-1])
    out = np.zeros(len(pts))
    if total <= 0.0 or len(pts) < 3:
        return out
    h = window * total
    i = np.arange(1, len(pts) - 1)
    lo = np.maximum(np.searchsorted(arc, arc[i] - h, side="right") - 1, 0)
    hi = np.minimum(np.searchsorted(arc, arc[i] + h, side="left"), len(pts) - 1)
    a, b = pts[i] - pts[lo], pts[hi] - pts[i]
    both = (np.linalg.norm(a, axis=1) > 0) & (np.linalg.norm(b, axis=1) > 0)
    cos = np.clip(np.sum(unit(a) * unit(b), axis=1), -1.0, 1.0)
    out[i] = np.where(both, np.degrees(np.arccos(cos)), 0.0)
    return out


def is_kinked(polyline: Polyline, angle_deg: float = KINK_ANGLE_DEG, window: float = KINK_WINDOW) -> bool:
    """True if the polyline turns by more than angle_deg within the window somewhere inside it
    (at the default window, by the polyline's own turning_deg, made once per polyline)."""
    if not angle_deg > 0:
        raise ProgSurfError(f"kink angle {angle_deg} must be a positive angle in degrees")
    angles = polyline.turning_deg if window == KINK_WINDOW else turning_angles(polyline.points, window)
    return bool(np.any(angles > angle_deg))


def sharp_edges(network, angle_deg: float = KINK_ANGLE_DEG) -> frozenset:
    """Ids of the interior network edges that lie on a kinked curve piece: intended sharp features
    that G1 mode leaves G0. The whole network curve is tested, so a kink at a node counts too;
    only the edges within the kink's window are marked."""
    edges = network.edges()
    by_curve: dict = {}
    for e in edges.values():
        by_curve.setdefault(e.curve_id, []).append(e)
    out = set()
    for cid, group in by_curve.items():
        if cid in (0, 1, 2, 3):
            continue
        for e in group:        # an unchanged edge keeps its polyline and the turning angles on it
            if is_kinked(e.polyline, angle_deg):
                out.add(e.id)
    return frozenset(out)


def node_normal(corner_normals: list) -> tuple[FloatArray | None, float]:
    """The normal of a node from the corner normals (3,) of the faces that have it as a corner,
    and the largest angle (deg) between them (> SHARP_NODE_DEG: a sharp node). (None, 0) if none."""
    ns = [unit(n) for n in corner_normals if n is not None and np.linalg.norm(n) > 0]
    if not ns:
        return None, 0.0
    ref = ns[0]
    ns = np.array([n if float(n @ ref) >= 0 else -n for n in ns])
    spread = float(normal_angle_deg(ns[:, None, :], ns[None, :, :]).max())
    return unit(np.sum(ns, axis=0)), spread


# ------------------------------------------------------------------------------ the Gregory patch
@dataclass(frozen=True)
class GregoryCoonsPatch:
    """C1 Hermite Coons patch with Gregory corner twists (Egorov Eq. 1-4 and 24).

    bottom, right, top, left : boundary curves, t -> (..., 3), oriented as in CoonsPatch
    d_bottom, d_top          : fluxes P_r(s,0), P_r(s,1) as functions of s
    d_left, d_right          : fluxes P_s(0,r), P_s(1,r) as functions of r
    The corner values must agree: d_bottom(0) = left'(0), d_left(0) = bottom'(0), and so on.
    The patch interpolates the four curves and the four fluxes exactly, whatever the fluxes' twists.
    """

    bottom: Callable
    right: Callable
    top: Callable
    left: Callable
    d_bottom: Flux
    d_right: Flux
    d_top: Flux
    d_left: Flux
    h: float = 1e-6

    def _dd(self, f: Flux, t: float) -> FloatArray:
        lo, hi = max(t - self.h, 0.0), min(t + self.h, 1.0)
        return (np.asarray(f(np.array(hi))) - np.asarray(f(np.array(lo)))) / (hi - lo)

    def _twists(self, s: FloatArray, r: FloatArray) -> dict:
        """Gregory twists at the four corners, (..., 3) each: the rational blend of the two flux
        derivatives meeting at the corner, weighted by the distance from the other side."""
        dd = self._dd
        eps = 1e-300
        s, r = s[..., None], r[..., None]
        return {
            (1, 1): (s * dd(self.d_left, 0.0) + r * dd(self.d_bottom, 0.0)) / np.maximum(s + r, eps),
            (2, 1): ((1 - s) * dd(self.d_right, 0.0) + r * dd(self.d_bottom, 1.0))
            / np.maximum(1 - s + r, eps),
            (1, 2): (s * dd(self.d_left, 1.0) + (1 - r) * dd(self.d_top, 0.0))
            / np.maximum(s + 1 - r, eps),
            (2, 2): ((1 - s) * dd(self.d_right, 1.0) + (1 - r) * dd(self.d_top, 1.0))
            / np.maximum(2 - s - r, eps),
        }

    def evaluate(self, s: npt.ArrayLike, r: npt.ArrayLike) -> FloatArray:
        """Points P(s, r), broadcast together; returns (..., 3)."""
        s, r = np.broadcast_arrays(np.asarray(s, dtype=float), np.asarray(r, dtype=float))
        hs, hr = hermite_basis(s), hermite_basis(r)
        ends = np.array([0.0, 1.0])
        b, t = self.bottom(ends), self.top(ends)
        loft_r = (hr[..., 0:1] * self.bottom(s) + hr[..., 1:2] * self.d_bottom(s)
                  + hr[..., 2:3] * self.d_top(s) + hr[..., 3:4] * self.top(s))
        loft_s = (hs[..., 0:1] * self.left(r) + hs[..., 1:2] * self.d_left(r)
                  + hs[..., 2:3] * self.d_right(r) + hs[..., 3:4] * self.right(r))
        # M_ij: rows = (P, P_s at s=0, P_s at s=1, P at s=1), columns the same in r (Egorov M0).
        m = np.zeros((4, 4) + s.shape + (3,))
        const = {(0, 0): b[0], (0, 3): t[0], (3, 0): b[1], (3, 3): t[1],
                 (0, 1): self.d_bottom(np.array(0.0)), (0, 2): self.d_top(np.array(0.0)),
                 (3, 1): self.d_bottom(np.array(1.0)), (3, 2): self.d_top(np.array(1.0)),
                 (1, 0): self.d_left(np.array(0.0)), (1, 3): self.d_left(np.array(1.0)),
                 (2, 0): self.d_right(np.array(0.0)), (2, 3): self.d_right(np.array(1.0))}
        for (i, j), value in const.items():
            m[i, j] = value
        for (i, j), value in self._twists(s, r).items():
            m[i, j] = value
        corner = np.einsum("...i,...j,ij...k->...k", hs, hr, m)
        return loft_r + loft_s - corner

    def derivatives(self, s: npt.ArrayLike, r: npt.ArrayLike, h: float = 1e-6) -> tuple[FloatArray, FloatArray]:
        """(P_s, P_r) by central differences (one-sided at the square's edges), (..., 3) each."""
        s, r = np.broadcast_arrays(np.asarray(s, dtype=float), np.asarray(r, dtype=float))
        s0, s1 = np.clip(s - h, 0, 1), np.clip(s + h, 0, 1)
        r0, r1 = np.clip(r - h, 0, 1), np.clip(r + h, 0, 1)
        ps = (self.evaluate(s1, r) - self.evaluate(s0, r)) / (s1 - s0)[..., None]
        pr = (self.evaluate(s, r1) - self.evaluate(s, r0)) / (r1 - r0)[..., None]
        return ps, pr


# ------------------------------------------------------------------------------ bounded corrections
BAND_PEAK = 27.0 / 256.0
"""Largest value of band_blend's shape x (1 - x)^3 (at x = 1/4): a band of width w moves the face by
at most BAND_PEAK * w * |flux correction|."""


def band_blend(t: npt.ArrayLike, width: float) -> FloatArray:
    """Blend of a flux correction across a band of `width` (0 < width <= 1) beside side t = 0:
    g(t) = width * x (1 - x)^3 with x = t / width, 0 beyond the band.

    g(0) = 0 and g'(0) = 1, as the Hermite h1 (Egorov Eq. 1-4): the cross-boundary derivative gets
    the correction exactly; g, g' and g'' vanish at the band's edge, so the correction fades out
    smoothly inside the face and moves it by at most BAND_PEAK * width times the correction. The
    blend of side t = 1 is -g(1 - t) (derivative 1 there, as h2)."""
    if not 0.0 < width <= 1.0:
        raise ProgSurfError(f"band width {width} must lie in (0, 1]")
    x = np.clip(np.asarray(t, dtype=float) / width, 0.0, 1.0)
    return width * x * (1.0 - x) ** 3
