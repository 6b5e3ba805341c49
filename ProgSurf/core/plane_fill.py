"""A fold-free refill of a face whose Coons patch turns over, where its loop lies over a plane.

A Coons patch (Qin & Wright Eq. 1) is linear in its sides: seen along a normal n it is the plane
Coons patch of the sides' projections plus the Coons patch of their heights. The height part
cannot turn a face over; where the face turns over while its loop, projected on its own plane (the
plane of its vector area), is a simple polygon, the plane part folds: the Coons map of the square
onto that polygon is not one to one (a reflex corner, a side that bows in, sides of very unequal
speed). Of the 384 faces whose Coons patch folded on the 82 unseen CASSIE sketches (not in
../shared), 172 have such a simple projected loop.

A one-to-one map exists for every simple polygon: Tutte's embedding (Floater 2003, mean value
weights) of a triangulation of the polygon onto the convex parameter square, with each boundary
point sent to its own (s, r) on the face's sides, is one to one; its inverse is the refill's plane
part, and its height along n is the same weighted mean of the border's heights (a plane loop gets
a plane face). The face's poles are solved for so that it passes through the refill at their
Greville points, its border poles held (and the next row too, where that is enough: the face
then leaves its sides as the Coons patch did, and a neighbour across a side meets it as before),
so that its sides, and every edge it shares, stay exactly as they were. The caller keeps a refill
only where it does not fold (cad.patch_faces.refilled_face).

A loop that crosses itself seen along n (a flap of the loop bent over the rest) may not seen from
a direction tilted away from n: the refill then looks along the nearest such direction
(simple_frame). One that crosses itself from every side often does so only in a small loop by a
corner, where two sides drawn past each other cross: seen along n, the polygon without such
loops is simple (untangled), its border points cut off are then sent nowhere and the face's
inside is refilled as before. Either way the refill keeps the face's tangent plane along its
sides.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from .bspline import basis_matrix
from .types import FloatArray

HELD = (2, 1)
"""Rows of poles kept at each side, in the order the refills are tried: with the face's tangent
plane along its sides kept, a neighbour across a side meets it as before (on the 82 unseen CASSIE
sketches: 86 fewer folding surfaces, creases between surfaces as they were); with the sides alone
more faces unfold (106 fewer) but 8 more creases appeared (cad.patch_faces tries them in turn)."""

TARGET_POINTS = 700
"""About this many points inside the projected loop are triangulated (their spacing h follows its
area); the loop is resampled every h / 2."""

INNER_CLEARANCE = 0.6
"""Points of the inner grid closer than this many h to the loop are left out, so that the
triangulation keeps the loop's own segments as edges."""


def greville(knots: FloatArray, degree: int, count: int) -> FloatArray:
    """The Greville abscissae (count,) of a B-spline basis of `degree` on its full knot vector."""
    k = np.asarray(knots, dtype=float)
    return np.array([k[i + 1:i + degree + 1].mean() for i in range(count)])


def loop_plane(points: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray] | None:
    """(centre, e1, e2, n) of a closed loop (m, 3): n along its vector area (so the loop runs
    counter-clockwise round n), e1, e2 completing a right-handed frame; None with no area."""
    c = points.mean(axis=0)
    area = 0.5 * np.cross(points - c, np.roll(points, -1, axis=0) - c).sum(axis=0)
    size = float(np.linalg.norm(area))
    if size <= 1e-300:
        return None
    return (c, *_frame(area / size))


def _frame(n: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    e1 = np.cross(n, [1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.cross(n, [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(n, e1), n


def _cross2(a: FloatArray, b: FloatArray) -> FloatArray:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _crossings(polygon: FloatArray) -> np.ndarray:
    """(m, m) bool: which pairs of non-adjacent segments of a closed plane polygon (m, 2) cross
    (segment k from point k to point k + 1)."""
    a = np.asarray(polygon, dtype=float)
    d = np.roll(a, -1, axis=0) - a
    m = len(a)
    # segments i and j cross where the ends of each lie on both sides of the other's line
    # (rel[i, j] = a_j - a_i; s1, s2: the sides of segment j's ends from segment i's line)
    rel = a[None, :, :] - a[:, None, :]
    s1 = _cross2(d[:, None], rel)
    s2 = _cross2(d[:, None], rel + d[None, :])
    straddles = s1 * s2 < 0
    crosses = straddles & straddles.T
    index = np.arange(m)
    apart = np.abs(index[:, None] - index[None, :])
    return crosses & (apart > 1) & (apart < m - 1)


def is_simple(polygon: FloatArray) -> bool:
    """Whether a closed plane polygon (m, 2) has no two non-adjacent segments crossing."""
    return not bool(_crossings(polygon).any())


def untangled(xy: FloatArray, values: FloatArray, most: float) -> tuple[FloatArray, FloatArray] | None:
    """The closed plane polygon xy (m, 2) made simple by cutting off the small loops it makes where
    it crosses itself (two sides that cross just by their corner), each at its crossing, with the
    values (m, k) at its points (a cut's point gets the value along the segment before it); None
    where that cuts off more than `most` of its length (or leaves it turning clockwise)."""
    xy, values = np.asarray(xy, dtype=float), np.asarray(values, dtype=float)
    allowed = most * float(np.linalg.norm(np.roll(xy, -1, axis=0) - xy, axis=1).sum())
    while True:
        pairs = np.argwhere(np.triu(_crossings(xy)))
        if not len(pairs):
            break
        m = len(xy)
        seg = np.roll(xy, -1, axis=0) - xy
        cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(seg, axis=1))])
        i, j = pairs[:, 0], pairs[:, 1]
        d, e = seg[i], seg[j]
        # the crossing lies at t of segment i and at u of segment j: the loop from it along i to
        # point i + 1, on to point j and along j back to it is this long, the rest of the polygon
        # the remainder
        t = _cross2(xy[j] - xy[i], e) / _cross2(d, e)
        u = _cross2(xy[j] - xy[i], d) / _cross2(d, e)
        inner = (1.0 - t) * (cum[i + 1] - cum[i]) + (cum[j] - cum[i + 1]) + u * (cum[j + 1] - cum[j])
        cut = np.minimum(inner, cum[-1] - inner)
        k = int(np.argmin(cut))
        allowed -= cut[k]
        if allowed < 0.0:
            return None
        i, j, t = int(i[k]), int(j[k]), float(t[k])
        at = (xy[i] + t * d[k])[None]
        value = (values[i] + t * (values[(i + 1) % m] - values[i]))[None]
        if inner[k] <= cum[-1] - inner[k]:     # cut off i + 1 .. j
            xy = np.vstack([xy[:i + 1], at, xy[j + 1:]])
            values = np.vstack([values[:i + 1], value, values[j + 1:]])
        else:                                  # keep only them
            xy = np.vstack([at, xy[i + 1:j + 1]])
            values = np.vstack([value, values[i + 1:j + 1]])
    if float(np.sum(_cross2(xy, np.roll(xy, -1, axis=0)))) <= 0.0:
        return None
    return xy, values


MAX_TILT_DEG = 75.0
"""A loop that crosses itself seen along its vector area's normal n may not seen from the side: the
refill looks along the direction nearest n, within this angle of it, in which it does not. Of the
214 four-sided folding faces of the 82 unseen CASSIE sketches whose loop crosses itself seen
along n, 139 have such a direction (half of them within 32 deg)."""

TILT_DIRECTIONS = 300
"""Directions over the half sphere round n (a Fibonacci lattice, ~8 deg apart) tried in turn."""

TILT_SAMPLES = 96
"""A direction is tried first on about this many of the loop's points, then on all of them."""


UNTANGLE_MOST = 0.02
"""A loop that crosses itself seen from every side is refilled over the polygon without its small
loops (untangled) where they make up at most this fraction of its length: of the 75 four-sided
folding faces of the 82 unseen CASSIE sketches whose loops cross themselves seen from every side,
23 have only such small loops (26 within 5 %: the same 13 more surfaces unfolded)."""


@lru_cache(maxsize=1)
def _half_sphere(count: int) -> FloatArray:
    """(count, 3) unit vectors spread evenly over the half sphere z > 0 (a Fibonacci lattice)."""
    i = np.arange(count) + 0.5
    polar = np.arccos(1.0 - i / count)
    turn = np.pi * (1.0 + 5.0 ** 0.5) * i
    return np.column_stack([np.cos(turn) * np.sin(polar), np.sin(turn) * np.sin(polar), np.cos(polar)])


def simple_frame(border: FloatArray, c: FloatArray, n: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray] | None:
    """(e1, e2, d): a right-handed frame whose d is n itself, if the closed loop `border` (m, 3)
    seen along n (its vector area's normal, centre c) is a simple polygon, else the first of the
    lattice's directions, in order of their angle from n (at most MAX_TILT_DEG), along which it is
    one (read first on about TILT_SAMPLES of its points: a direction where those cross is passed
    over); None where none is. Seen along d (d . n > 0) the loop still runs counter-clockwise."""
    def simple(d: FloatArray, points: FloatArray) -> bool:
        e1, e2, _ = _frame(d)
        return is_simple(np.column_stack([(points - c) @ e1, (points - c) @ e2]))

    if simple(n, border):
        return _frame(n)
    dirs = _half_sphere(TILT_DIRECTIONS) @ np.stack(_frame(n))
    tilt = dirs @ n
    coarse = border[::max(1, len(border) // TILT_SAMPLES)]
    for k in np.argsort(-tilt):
        if tilt[k] < np.cos(np.radians(MAX_TILT_DEG)):
            break
        if simple(dirs[k], coarse) and simple(dirs[k], border):
            return _frame(dirs[k])
    return None


def inside_polygon(points: FloatArray, polygon: FloatArray) -> np.ndarray:
    """(k,) bool: points (k, 2) inside a closed simple plane polygon (m, 2) (matplotlib's test; a
    point on the polygon may fall either way)."""
    from matplotlib.path import Path

    return Path(np.asarray(polygon, dtype=float), closed=False).contains_points(np.asarray(points, dtype=float))


def _distance_to_loop(points: FloatArray, polygon: FloatArray) -> FloatArray:
    a = polygon
    d = np.roll(polygon, -1, axis=0) - a
    t = np.clip(((points[:, None] - a[None]) * d[None]).sum(-1) / np.maximum((d * d).sum(-1), 1e-300), 0.0, 1.0)
    return np.linalg.norm(points[:, None] - (a[None] + t[..., None] * d[None]), axis=-1).min(axis=1)


def _resampled(xy: FloatArray, uv: FloatArray, step: float) -> tuple[FloatArray, FloatArray]:
    """The closed loop xy (m, 2) with values uv (m, k) at its points, resampled every ~step by
    length."""
    closed_xy = np.vstack([xy, xy[:1]])
    closed_uv = np.vstack([uv, uv[:1]])
    cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(closed_xy, axis=0), axis=1))])
    count = max(int(np.ceil(cum[-1] / step)), 16)
    t = np.linspace(0.0, cum[-1], count, endpoint=False)
    return (np.column_stack([np.interp(t, cum, closed_xy[:, k]) for k in (0, 1)]),
            np.column_stack([np.interp(t, cum, closed_uv[:, k]) for k in range(uv.shape[1])]))


def _triangulation(border: FloatArray, h: float) -> tuple[FloatArray, np.ndarray] | None:
    """(points (k, 2): the border (b, 2) first, then an inner grid of spacing h; triangles (t, 3)
    counter-clockwise) of the polygon `border`, or None where a border segment is no edge."""
    from matplotlib.tri import Triangulation     # (qhull's Delaunay; matplotlib is a dependency)

    lo, hi = border.min(axis=0), border.max(axis=0)
    gx, gy = np.meshgrid(np.arange(lo[0] + h / 2, hi[0], h), np.arange(lo[1] + h / 2, hi[1], h))
    grid = np.column_stack([gx.ravel(), gy.ravel()])
    grid = grid[inside_polygon(grid, border)]
    if len(grid):
        grid = grid[_distance_to_loop(grid, border) > INNER_CLEARANCE * h]
    if len(grid) < 4:
        return None
    points = np.vstack([border, grid])
    tri = Triangulation(points[:, 0], points[:, 1]).triangles
    tri = tri[inside_polygon(points[tri].mean(axis=1), border)]
    p = points[tri]
    cw = _cross2(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]) < 0
    tri[cw] = tri[cw][:, [0, 2, 1]]
    nb = len(border)
    edges = np.sort(np.vstack([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1)
    have = set(map(tuple, edges.tolist()))
    if any((min(i, (i + 1) % nb), max(i, (i + 1) % nb)) not in have for i in range(nb)):
        return None
    return points, tri


def _tutte(points: FloatArray, tri: np.ndarray, border_uv: FloatArray) -> FloatArray:
    """Values (k, c) at every point: the border's given (b, c), the inner ones each the mean value
    weighted mean of its neighbours' (Floater 2003: for (s, r) on a convex border, positive weights
    give a one-to-one map)."""
    n, nb = len(points), len(border_uv)
    w = np.zeros((n, n))
    for k in range(3):
        i, j, l = tri[:, k], tri[:, (k + 1) % 3], tri[:, (k + 2) % 3]
        vj, vl = points[j] - points[i], points[l] - points[i]
        lj, ll = np.linalg.norm(vj, axis=1), np.linalg.norm(vl, axis=1)
        half = np.tan(0.5 * np.arccos(np.clip((vj * vl).sum(1) / (lj * ll), -1.0, 1.0)))
        np.add.at(w, (i, j), half / lj)
        np.add.at(w, (i, l), half / ll)
    inner = np.arange(nb, n)
    system = np.diag(w[inner].sum(axis=1)) - w[np.ix_(inner, inner)]
    return np.vstack([border_uv, np.linalg.solve(system, w[np.ix_(inner, np.arange(nb))] @ border_uv)])


def _inverse(points: FloatArray, tri: np.ndarray, uv: FloatArray, query: FloatArray) -> FloatArray | None:
    """The points (q, d) that the map points (k, d) -> uv (k, 2) (one to one on the triangles)
    sends to query (q, 2), or None where the map turned a triangle over."""
    p0, p1, p2 = uv[tri[:, 0]], uv[tri[:, 1]], uv[tri[:, 2]]
    det = _cross2(p1 - p0, p2 - p0)
    if np.any(det < -1e-12 * max(float(np.abs(det).max()), 1e-300)):
        return None
    keep = det > 1e-14
    tri, p0, p1, p2, det = tri[keep], p0[keep], p1[keep], p2[keep], det[keep]
    from matplotlib.tri import Triangulation

    found = np.full(len(query), -1)
    try:
        found = Triangulation(uv[:, 0], uv[:, 1], tri).get_trifinder()(query[:, 0], query[:, 1])
    except (ValueError, RuntimeError):    # (a triangulation its trapezoid map refuses)
        pass
    lost = np.nonzero(found < 0)[0]
    rows = 256
    for s in range(0, len(lost), rows):   # outside every triangle by round-off: the nearest one
        q = query[lost[s:s + rows], None]
        l0 = _cross2(p1 - q, p2 - q) / det
        l1 = _cross2(p2 - q, p0 - q) / det
        found[lost[s:s + rows]] = np.minimum(np.minimum(l0, l1), 1.0 - l0 - l1).argmax(axis=1)
    a, b, c = p0[found], p1[found], p2[found]
    l0 = _cross2(b - query, c - query) / det[found]
    l1 = _cross2(c - query, a - query) / det[found]
    lam = np.column_stack([l0, l1, 1.0 - l0 - l1])
    return np.einsum("qk,qkd->qd", lam, points[tri[found]])


@dataclass(frozen=True)
class PlaneMap:
    """A loop's one-to-one map onto the parameter square (plane_map): its triangulated polygon
    `points` (k, 2) in the frame (centre, axes: rows e1, e2, d), their heights along d and their
    (s, r) `uv` (k, 2); `reshaped` where the loop was seen from a tilted d or untangled (a refill
    then keeps 2 rows of poles at each side, not fewer, unless refill_poles is told `loose`)."""

    centre: FloatArray
    axes: FloatArray
    points: FloatArray
    heights: FloatArray
    uv: FloatArray
    triangles: np.ndarray
    reshaped: bool


def plane_map(border: FloatArray, border_uv: FloatArray) -> PlaneMap | None:
    """The map of a face's loop onto its parameter square that its plane refill inverts (module
    docstring), or None where the loop lies over no plane as a simple polygon (simple_frame,
    untangled) or its triangulation fails. border, border_uv: as plane_refill's."""
    plane = loop_plane(border)
    if plane is None:
        return None
    c, e1, e2, n = plane
    frame, cut = simple_frame(border, c, n), None
    if frame is None:
        # crossing itself seen from every side: where it does so only in small loops (two sides
        # that cross just by their corner), the polygon without them, seen along n
        frame = (e1, e2, n)
        cut = untangled(np.column_stack([(border - c) @ e1, (border - c) @ e2]),
                        np.column_stack([border_uv, (border - c) @ n]), UNTANGLE_MOST)
        if cut is None:
            return None
    # seen from the side or untangled, only the refill that keeps the face's tangent plane along
    # its sides is tried: refilling within the border alone (held 1) too, on the 82 unseen CASSIE
    # sketches 14 more surfaces unfolded but 3 more creases between surfaces appeared (such a refill
    # is made only where asked, `loose`, and then checked against the neighbours: cad.object_shell)
    reshaped = cut is not None or float(frame[2] @ n) < 1.0 - 1e-12
    e1, e2, d = frame
    if cut is None:
        xy = np.column_stack([(border - c) @ e1, (border - c) @ e2])
        along = np.column_stack([border_uv, (border - c) @ d])
    else:
        xy, along = cut
    area = 0.5 * float(np.sum(_cross2(xy, np.roll(xy, -1, axis=0))))
    for h in (np.sqrt(area / TARGET_POINTS), 0.5 * np.sqrt(area / TARGET_POINTS)):
        bxy, buv = _resampled(xy, along, 0.5 * h)
        if len(bxy) > 4 * TARGET_POINTS:
            return None
        mesh = _triangulation(bxy, h)
        if mesh is not None:
            break
    else:
        return None
    points, tri = mesh
    # each inner point's (s, r), and its height along d, the mean value weighted mean of its
    # neighbours' (the heights so reproduce a plane: a flat loop gets a flat face)
    solved = _tutte(points, tri, buv)
    return PlaneMap(c, np.stack([e1, e2, d]), points, solved[:, 2], solved[:, :2], tri, reshaped)


def refill_poles(mapped: PlaneMap, poles: FloatArray, knots: tuple[FloatArray, FloatArray],
                 degrees: tuple[int, int], held: tuple[int, ...] = HELD,
                 loose: bool = False) -> dict[int, FloatArray]:
    """plane_refill's pole grids from the loop's map (plane_map), for a face of these poles, full
    knot vectors and degrees (the same surface with more knots has the same map), by the rows of
    poles held (those of `held` that give one). A reshaped map gives grids with 2 rows held or more,
    unless `loose` (the caller checks the refill against the neighbours: cad.object_shell)."""
    poles = np.asarray(poles, dtype=float)
    nu, nv = poles.shape[:2]
    c, frame = mapped.centre, mapped.axes
    gu, gv = (greville(k, d, m) for k, d, m in zip(knots, degrees, (nu, nv)))
    su, sv = np.meshgrid(gu, gv, indexing="ij")
    target = _inverse(np.column_stack([mapped.points, mapped.heights]), mapped.triangles, mapped.uv,
                      np.column_stack([su.ravel(), sv.ravel()]))
    if target is None:
        return {}
    target = target.reshape(nu, nv, 3)
    bu_all = basis_matrix(knots[0], gu, degrees[0])
    bv_all = basis_matrix(knots[1], gv, degrees[1])
    out = {}
    for k in held:
        if mapped.reshaped and k < 2 and not loose:
            continue
        mu, mv = nu - 2 * k, nv - 2 * k
        if mu < 1 or mv < 1:
            continue
        bu, bv = bu_all[k:-k], bv_all[k:-k]
        kept = (poles - c) @ frame.T            # (nu, nv, 3) in the loop's frame
        kept[k:-k, k:-k] = 0.0
        rhs = target[k:-k, k:-k] - np.einsum("jl,ilc->ijc", bv, np.einsum("ik,klc->ilc", bu, kept))
        # bu X bv^T = rhs for the moved poles X, one coordinate at a time
        step = np.linalg.solve(bu[:, k:-k], rhs.reshape(mu, -1)).reshape(mu, mv, 3)
        moved = np.linalg.solve(bv[:, k:-k], step.transpose(1, 0, 2).reshape(mv, -1))
        grid = poles.copy()
        grid[k:-k, k:-k] = c + moved.reshape(mv, mu, 3).transpose(1, 0, 2) @ frame
        out[k] = grid
    return out


def plane_refill(poles: FloatArray, knots: tuple[FloatArray, FloatArray], degrees: tuple[int, int],
                 border: FloatArray, border_uv: FloatArray, held: tuple[int, ...] = HELD) -> list[FloatArray]:
    """Pole grids (nu, nv, 3) of a face refilled over its loop's plane (module docstring), one per
    entry of `held`: that many rows of poles at each side kept as they were (1: the border, the
    sides themselves; 2: the face's tangent plane along its sides too); none where the loop does
    not lie over that plane, or over one tilted from it (simple_frame), or over that plane but for
    small loops (untangled), as a simple polygon (or holds too few poles to move). Tilted or
    untangled, only with 2 rows held (refill_poles loose: 1 too).

    knots, degrees : the face's full knot vectors (on [0, 1]) and degrees in s and r
    border (m, 3)  : the face's boundary in order, bottom, right, top, left (s, r from 0 to 1 along
                     bottom and right, back along top and left), with its (s, r) border_uv (m, 2).

    The moved poles are solved for so that the face passes through the refill at their Greville
    points (s_i, r_j) (collocation there has one solution: Schoenberg-Whitney). Placed at the
    refill's points themselves, the poles next to a side that turns sharply (a corner inside a
    side) left the face turned over along it."""
    mapped = plane_map(border, border_uv)
    return [] if mapped is None else list(refill_poles(mapped, poles, knots, degrees, held).values())
