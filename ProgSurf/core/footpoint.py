"""Footpoints of 3D points on a faceted surface: Qin & Wright step (6), Eq. 2.

For a facet with corner P0 and edge vectors R, S (to P(u_i, v_j+1) and P(u_i+1, v_j)) and normal
N = R x S, the footpoint F of Q solves

    [R S N] . [k_r, k_s, d]^T = Q - P0,     F = P0 + k_r R + k_s S = Q - d N,

and F is a real footpoint when (k_r, k_s) lies in the facet triangle. The parameters of F follow
by the same barycentric weights. We solve Eq. 2 for every facet at once and keep the nearest real
footpoint; when no facet has one, the nearest point of the mesh decides: on the outer boundary
of the surface the point "projects outside the surface" (the paper rejects the stroke).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .types import FloatArray, cross3


@dataclass(frozen=True)
class Facets:
    """A triangulated surface with a pre-image for every vertex.

    xyz      : (m, 3, 3) the triangles' 3D corners
    uv       : (m, 3, 2) their pre-images
    region   : (m,) int, region id of each triangle
    solver   : optional (inverse (m, 3, 3), good (m,), edge length (m,)) from :func:`prepare`, so
               that many footpoints on the same facets cost one product each, not a solve
    """

    xyz: FloatArray
    uv: FloatArray
    region: np.ndarray
    solver: tuple | None = None


def prepare(tri: FloatArray) -> tuple[FloatArray, np.ndarray, FloatArray]:
    """The facet-only part of Eq. 2: the inverse of [R S N] per triangle (identity where the
    triangle is degenerate), the non-degenerate mask and the longer edge length."""
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    r_vec, s_vec = b - a, c - a
    n = cross3(r_vec, s_vec)
    nrm = np.linalg.norm(n, axis=1)
    good = nrm > 1e-300
    n_unit = n / np.where(good, nrm, 1.0)[:, None]
    # inverse of the column matrix [R S N] by cross products: rows (S x N, N x R, R x S) / det
    rows = np.stack([cross3(s_vec, n_unit), cross3(n_unit, r_vec), n], axis=1)
    det = np.einsum("ij,ij->i", r_vec, rows[:, 0])
    good &= np.abs(det) > 1e-300
    inv = rows / np.where(good, det, 1.0)[:, None, None]
    inv[~good] = np.eye(3)
    edge_len = np.maximum(np.linalg.norm(r_vec, axis=1), np.linalg.norm(s_vec, axis=1))
    return inv, good, edge_len


@dataclass(frozen=True)
class Footpoint:
    """The footpoint F of a point Q: F = xyz, its pre-image uv, signed distance d, region id.

    inside : False when Q projects outside the surface (no real footpoint; F is the nearest
             point of the surface boundary).
    """

    xyz: FloatArray
    uv: FloatArray
    distance: float
    region: int
    inside: bool


def _closest_on_triangles(q: FloatArray, tri: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Closest points of q (3,) on each triangle (m, 3, 3): barycentric (m, 3) and distances (m,)."""
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    best_w = None
    best_d = None
    # Candidates: interior projection and the three edges; pick the nearest valid one.
    ab, ac = b - a, c - a
    n = cross3(ab, ac)
    nn = np.einsum("ij,ij->i", n, n)
    nn_safe = np.where(nn > 1e-300, nn, 1.0)
    aq = q - a
    wb = np.einsum("ij,ij->i", cross3(aq, ac), n) / nn_safe
    wc = np.einsum("ij,ij->i", cross3(ab, aq), n) / nn_safe
    wa = 1.0 - wb - wc
    inside = (wa >= 0) & (wb >= 0) & (wc >= 0) & (nn > 1e-300)
    p = wa[:, None] * a + wb[:, None] * b + wc[:, None] * c
    d_in = np.where(inside, np.linalg.norm(q - p, axis=1), np.inf)
    best_w = np.column_stack([wa, wb, wc])
    best_d = d_in
    for i, j in ((0, 1), (1, 2), (2, 0)):
        p0, p1 = tri[:, i], tri[:, j]
        e = p1 - p0
        ee = np.einsum("ij,ij->i", e, e)
        t = np.clip(np.einsum("ij,ij->i", q - p0, e) / np.where(ee > 1e-300, ee, 1.0), 0.0, 1.0)
        pt = p0 + t[:, None] * e
        d = np.linalg.norm(q - pt, axis=1)
        better = d < best_d
        w = np.zeros((len(tri), 3))
        w[:, i] = 1.0 - t
        w[:, j] = t
        best_w = np.where(better[:, None], w, best_w)
        best_d = np.where(better, d, best_d)
    return best_w, best_d


TIE_FRACTION = 1e-7
"""Facets whose distances from a point differ by less than this fraction of the nearest one's
longer edge are equally near (sheets of the surface that lie on each other, up to round-off)."""


def real_footpoint(q: FloatArray, facets: Facets, slack: float = 0.0,
                   near_uv: FloatArray | None = None) -> Footpoint | None:
    """The nearest real footpoint of q (3,) on the facets (Eq. 2): among the facets whose
    projection of q falls inside them (within `slack` mm), the nearest point of the nearest
    facet; None if there is none.

    near_uv : (2,) where the caller expects the pre-image. Where the surface lies on itself (a
              boundary side filtered to a line out and back makes two coincident sheets), several
              facets are equally near at different pre-images, and round-off chose among them: a
              rotated sketch put a stroke's points on the other sheet (issue 17, TiGL fuselage1).
              Among facets equally near (TIE_FRACTION) the one whose footpoint's pre-image is
              nearest near_uv is taken; without near_uv, the first of them."""
    q = np.asarray(q, dtype=float)
    tri = facets.xyz
    inv, good, edge_len = facets.solver if facets.solver is not None else prepare(tri)
    # Eq. 2 for all facets at once: [R S N] [k_r k_s d]^T = Q - P0.
    sol = np.einsum("mij,mj->mi", inv, q - tri[:, 0])
    kr, ks, d = sol[:, 0], sol[:, 1], sol[:, 2]
    tol = np.where(edge_len > 0, slack / np.maximum(edge_len, 1e-300), 0.0) + 1e-9
    real = good & (kr >= -tol) & (ks >= -tol) & (kr + ks <= 1 + tol)
    if not np.any(real):
        return None
    idx = np.flatnonzero(real)
    # Within the slack a facet's plane may pass near q far from the facet itself (on a curved
    # surface a distant facet's plane can be nearer than the facet under q): rank the candidates
    # by the distance to the nearest point of each facet, not to its plane.
    w_all, dist_all = _closest_on_triangles(q, tri[idx])
    pick = int(np.argmin(dist_all))
    if near_uv is not None:
        tied = np.flatnonzero(dist_all <= dist_all[pick] + TIE_FRACTION * edge_len[idx[pick]])
        if len(tied) > 1:
            uvs = np.einsum("kj,kjd->kd", w_all[tied], facets.uv[idx[tied]])
            pick = int(tied[np.argmin(np.linalg.norm(uvs - near_uv, axis=1))])
    k = idx[pick]
    w = w_all[pick]
    foot = w @ tri[k]
    dist = float(np.copysign(dist_all[pick], d[k]))
    return Footpoint(xyz=foot, uv=w @ facets.uv[k], distance=dist, region=int(facets.region[k]), inside=True)


def footpoint(q: FloatArray, facets: Facets, slack: float = 0.0, near_uv: FloatArray | None = None) -> Footpoint:
    """The footpoint of q (3,) on the facets (Eq. 2), as described in the module docstring.

    slack : a real footpoint may lie this far (in mm) outside its facet, to absorb the
            faceting of a curved surface near the outer boundary.
    near_uv : the expected pre-image, which decides among equally near facets (real_footpoint)
    """
    q = np.asarray(q, dtype=float)
    found = real_footpoint(q, facets, slack, near_uv)
    if found is not None:
        return found
    return nearest_on_mesh(q, facets)


def nearest_on_mesh(q: FloatArray, facets: Facets) -> Footpoint:
    """The nearest point of the facets to q (3,), for a q that has no real footpoint: inside=False
    when it lies on the outer boundary of the surface (the boundary of the unit square)."""
    tri = facets.xyz
    w, dist = _closest_on_triangles(q, tri)
    k = int(np.argmin(dist))
    wk = w[k]
    uv = wk @ facets.uv[k]
    # The outer boundary of the surface is the boundary of the unit square in the pre-image.
    on_outer = bool(np.any(np.minimum(uv, 1.0 - uv) <= 1e-9))
    return Footpoint(xyz=wk @ tri[k], uv=uv, distance=float(dist[k]),
                     region=int(facets.region[k]), inside=not on_outer)
