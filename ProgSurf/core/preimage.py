"""Planar geometry of the pre-image plane (u, v) in [0,1]^2 (Qin & Wright, steps 3-4, Fig. 6-8).

Every curve's pre-image is a straight segment; every region is a convex 3- or 4-sided polygon.
"""
from __future__ import annotations

from typing import Sequence

import numpy as np
import numpy.typing as npt

from .types import FloatArray

CORNER_ANGLE = np.radians(2.0)
"""A polygon vertex whose direction turns by less than this is a T-junction, not a corner."""


def cross2(a: npt.ArrayLike, b: npt.ArrayLike) -> FloatArray:
    """z-component of the 2D cross product, broadcasting over leading axes."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def segment_intersections(p0: FloatArray, p1: FloatArray, a: FloatArray, b: FloatArray,
                          eps: float = 1e-12) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Intersections of the segment p0-p1 with m segments a_i-b_i.

    p0, p1 : (2,)    a, b : (m, 2)
    Returns (t, s, parallel): t (m,) along p0->p1, s (m,) along a->b (NaN where parallel),
    and parallel (m,) bool for (near-)parallel pairs.
    """
    d = p1 - p0
    e = b - a
    denom = cross2(d, e)
    w = a - p0
    parallel = np.abs(denom) <= eps * np.maximum(np.linalg.norm(e, axis=-1) * np.linalg.norm(d), 1e-300)
    safe = np.where(parallel, 1.0, denom)
    t = np.where(parallel, np.nan, cross2(w, e) / safe)
    s = np.where(parallel, np.nan, cross2(w, d) / safe)
    return t, s, parallel


def polygon_area(poly: FloatArray) -> float:
    """Signed area (counter-clockwise positive) of polygon (n, 2)."""
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def points_in_convex_polygon(pts: FloatArray, poly: FloatArray, eps: float = 1e-9) -> FloatArray:
    """(k,) bool: which of pts (k, 2) lie in the counter-clockwise convex polygon (n, 2)."""
    pts = np.atleast_2d(pts)
    edge = np.roll(poly, -1, axis=0) - poly                      # (n, 2)
    rel = pts[:, None, :] - poly[None, :, :]                     # (k, n, 2)
    side = cross2(edge[None, :, :], rel)                         # (k, n)
    scale = np.linalg.norm(edge, axis=-1)[None, :]
    return np.all(side >= -eps * np.maximum(scale, 1e-300), axis=1)


def turning_corners(poly: FloatArray, angle: float = CORNER_ANGLE) -> list[int]:
    """Indices of the vertices of polygon (n, 2) where the boundary turns by more than angle."""
    prev = poly - np.roll(poly, 1, axis=0)
    nxt = np.roll(poly, -1, axis=0) - poly
    turn = np.arctan2(cross2(prev, nxt), np.einsum("ij,ij->i", prev, nxt))
    return [i for i in range(len(poly)) if abs(turn[i]) > angle]


def bilinear(corners: FloatArray, s: npt.ArrayLike, r: npt.ArrayLike) -> FloatArray:
    """uv of the bilinear map of corners (4, 2) c0, c1, c2, c3 at local (s, r); (..., 2)."""
    s = np.asarray(s, dtype=float)[..., None]
    r = np.asarray(r, dtype=float)[..., None]
    c0, c1, c2, c3 = corners
    return (1 - s) * (1 - r) * c0 + s * (1 - r) * c1 + s * r * c2 + (1 - s) * r * c3


def clip01(x: FloatArray) -> FloatArray:
    """x clamped to [0, 1], as np.clip gives it (whose checks of its scalar bounds cost more
    than the arithmetic on the few points of a pre-image query)."""
    return np.minimum(np.maximum(x, 0.0), 1.0)


def inverse_bilinear(corners: FloatArray, uv: FloatArray, triangle: bool) -> tuple[FloatArray, FloatArray]:
    """Local (s, r) in [0,1]^2 of pre-image points uv (k, 2) in a region with corners (4, 2).

    A triangle (c3 == c2) maps r to the barycentric weight of the apex c2 and s along c0->c1,
    the collapsed top of Qin & Wright Fig. 4. Quads use Newton's method on the bilinear map.
    """
    return inverse_bilinear_sets([(corners, uv, triangle)])[0]


def inverse_bilinear_sets(sets: Sequence[tuple[FloatArray, FloatArray, bool]]) -> list[tuple[FloatArray, FloatArray]]:
    """:func:`inverse_bilinear` of several (corners (4, 2), uv (k, 2), triangle) at once: the quads'
    Newton iterations run together, each set stopping when its own steps are below 1e-14 (as it
    would alone), so every (s, r) is the one inverse_bilinear gives for its set alone."""
    out: list = [None] * len(sets)
    quads, tris = [], []
    for i, (corners, uv, triangle) in enumerate(sets):
        uv = np.atleast_2d(np.asarray(uv, dtype=float))
        corners = np.asarray(corners, dtype=float)
        if triangle:
            tris.append((i, corners, uv))
        elif len(uv):
            quads.append((i, corners, uv))
        else:
            out[i] = (np.zeros(0), np.zeros(0))
    if tris:
        # weights of c1, c2: the 2x2 system [c1 - c0, c2 - c0] lam = uv - c0 by Cramer's rule, for
        # every triangle's points at once (LAPACK's solve cost ~1 ms a call here)
        c = np.stack([corners for _, corners, _ in tris])
        a, b = c[:, 1] - c[:, 0], c[:, 2] - c[:, 0]
        det = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
        if np.any(det == 0.0):
            raise np.linalg.LinAlgError("Singular matrix")
        sizes = [len(uv) for _, _, uv in tris]
        a, b, c0, det = (np.repeat(x, sizes, axis=0) for x in (a, b, c[:, 0], det))
        d = np.concatenate([uv for _, _, uv in tris]) - c0
        lam0 = (d[:, 0] * b[:, 1] - d[:, 1] * b[:, 0]) / det
        lam1 = (a[:, 0] * d[:, 1] - a[:, 1] * d[:, 0]) / det
        r = clip01(lam1)
        base = 1.0 - lam1
        s = clip01(np.where(base > 1e-12, lam0 / np.where(base > 1e-12, base, 1.0), 0.5))
        at = 0
        for (i, _, _), k in zip(tris, sizes):
            out[i] = (s[at:at + k], r[at:at + k])
            at += k
    if not quads:
        return out
    sizes = np.array([len(uv) for _, _, uv in quads])
    uv = np.concatenate([uv for _, _, uv in quads])
    c0, c1, c2, c3 = np.repeat(np.stack([c for _, c, _ in quads], axis=1), sizes, axis=1)    # (4, k, 2)
    s_out = np.full(len(uv), 0.5)
    r_out = np.full(len(uv), 0.5)
    # the points of the sets still iterating (a set that has stopped is dropped from the arrays
    # once a quarter of their points have: the same steps, on fewer points). The arithmetic is
    # bilinear's and cross2's, written out: (1 - s) and (1 - r) are shared, not made twice.
    at = np.arange(len(uv))
    a = (uv, c0, c1, c2, c3, c1 - c0, c2 - c3, c3 - c0, c2 - c1, s_out.copy(), r_out.copy())
    set_sizes = sizes
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    running = np.ones(len(quads), dtype=bool)
    moving = None                                   # None: every point moves
    for _ in range(30):
        p, q0, q1, q2, q3, d10, d23, d30, d21, s, r = a
        S, R = s[:, None], r[:, None]
        S1, R1 = 1 - S, 1 - R
        f = S1 * R1 * q0 + S * R1 * q1 + S * R * q2 + S1 * R * q3 - p
        ds = R1 * d10 + R * d23
        dr = S1 * d30 + S * d21
        det = ds[:, 0] * dr[:, 1] - ds[:, 1] * dr[:, 0]
        det = np.where(np.abs(det) < 1e-300, 1e-300, det)
        step_s = (f[:, 0] * dr[:, 1] - f[:, 1] * dr[:, 0]) / det
        step_r = (ds[:, 0] * f[:, 1] - ds[:, 1] * f[:, 0]) / det
        if moving is None:
            s, r = s - step_s, r - step_r
        else:
            s, r = np.where(moving, s - step_s, s), np.where(moving, r - step_r, r)
        running &= ~(np.maximum.reduceat(np.abs(step_s) + np.abs(step_r), starts) < 1e-14)
        a = (p, q0, q1, q2, q3, d10, d23, d30, d21, s, r)
        if running.all():
            continue
        if not running.any():
            break
        moving = np.repeat(running, set_sizes)
        if moving.sum() < 0.75 * len(moving):
            s_out[at], r_out[at] = s, r
            at, a = at[moving], tuple(x[moving] for x in a)
            set_sizes, running = set_sizes[running], running[running]
            starts = np.concatenate([[0], np.cumsum(set_sizes)[:-1]])
            moving = None
    s_out[at], r_out[at] = a[-2], a[-1]
    s, r = clip01(s_out), clip01(r_out)
    for (i, _, _), k0, k in zip(quads, np.cumsum(np.concatenate([[0], sizes[:-1]])), sizes):
        out[i] = (s[k0:k0 + k], r[k0:k0 + k])
    return out


def ray_exit(p: FloatArray, direction: FloatArray, poly: FloatArray) -> float:
    """Distance parameter t >= 0 where the ray p + t*direction leaves the convex polygon (n, 2)."""
    a = poly
    b = np.roll(poly, -1, axis=0)
    t, s, parallel = segment_intersections(p, p + direction, a, b)
    ok = ~parallel & (s >= -1e-9) & (s <= 1 + 1e-9) & (t > 1e-12)
    if not np.any(ok):
        return 0.0
    return float(np.min(t[ok]))
