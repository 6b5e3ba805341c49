"""The ends of an interior stroke in the progressive update (Qin & Wright section 3).

Holds where each end of a stroke goes on the current network: step (2), an end on or crossing a
boundary curve snaps to it and the over-sketched part is trimmed; step (6), a free end is placed
at its footpoint F on the surface (motion-sketch text, Eq. 2), keeping its offset Q - F; steps
(7)-(8), the pre-image is extended from F to the boundary g of its region and the offset is
distributed from F to g.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from .errors import StrokeOutsideSurfaceError, StrokeRejectedError
from .network import DEGENERATE_ATOL, EdgeSegments, PatchNetwork
from .preimage import ray_exit, segment_intersections
from .strokes import cumulative_length, ramp
from .types import FloatArray

Snap = tuple
"""Where an end snapped (see :func:`snap_end`): (j, edge id, t, point), the stroke point index j,
the edge parameter t and the point (3,) on the edge."""

SNAP_TIE_FRACTION = 1e-6
"""Two snaps of one end whose distances, and whose points, differ by less than this fraction of
the snap distance are a tie (far above round-off, far below any drawn difference): the same place
reached on two edges, or twice on one edge that doubles back (see :func:`trim_ends`)."""


@dataclass
class StrokeEnd:
    """One end of a straight piece: on an edge (snapped) or free at a footpoint.

    uv     : (2,) its pre-image
    xyz    : (3,) its 3D point (the stroke's own point Q for a free end)
    snapped: on an edge (step 2) or free (step 6)
    edge, t: the edge it snapped to and the parameter there (-1, 0 for a free end)
    offset : |Q - F| of a free end (0 for a snapped one)
    region : the region of its footpoint (-1 for a snapped end)
    """

    uv: FloatArray
    xyz: FloatArray
    snapped: bool
    edge: int = -1
    t: float = 0.0
    offset: float = 0.0
    region: int = -1


UV_TIE = 1e-9
"""Pre-image distances (the unit square) that differ by less than this are equal."""


def snap_end(pts: FloatArray, snap: float, segs: EdgeSegments) -> Optional[Snap]:
    """Step (2): is the first end of pts on or crossing a boundary curve?

    Tests the distance from the points of the first half of the stroke to every current boundary
    (outer sides, earlier strokes). Over-sketch past an outer side may be any length; past an
    interior curve it may be at most 2 snap long, so a stroke that truly crosses an earlier
    one near its start is not cut there (a 15 % allowance had cut real stroke). Returns (j, edge id, t, point) or None."""
    tied = snap_candidates(pts, snap, segs)
    return tied[0] if tied else None


def snap_candidates(pts: FloatArray, snap: float, segs: EdgeSegments) -> list[Snap]:
    """The snaps of :func:`snap_end`, the nearest first, with every other one tied with it: as near
    to the stroke and at the same point, within SNAP_TIE_FRACTION of the snap distance (the same
    place on another edge, or on a stretch of edge that doubles back over another). Empty for a
    free end."""
    h = max(1, len(pts) // 2)
    p = pts[:h]
    # only the segments whose bounding box comes within the snap distance (and the tie allowance)
    # of the first half's: the others cannot be nearer than it, nor tied with a snap (the same
    # snaps, in the same order, without the distances to every segment of the network)
    reach = snap * (1.0 + 2.0 * SNAP_TIE_FRACTION) + 1e-9 * (float(np.abs(p).max()) + snap)
    lo, hi = p.min(axis=0) - reach, p.max(axis=0) + reach
    a, b = segs[0], segs[1]
    near_box = np.all(np.minimum(a, b) <= hi, axis=1) & np.all(np.maximum(a, b) >= lo, axis=1)
    if not near_box.any():
        return []
    a, b, eid, t0, t1, outer = (x[near_box] for x in segs)
    ab = b - a
    ll = np.einsum("ij,ij->i", ab, ab)
    w = np.einsum("hsk,sk->hs", p[:, None, :] - a[None], ab) / np.where(ll > 1e-300, ll, 1.0)
    w = np.clip(w, 0.0, 1.0)
    close = a[None] + w[..., None] * ab[None]
    d = np.linalg.norm(p[:, None, :] - close, axis=2)
    run = cumulative_length(pts)
    limit = 2.0 * snap
    allowed = outer[None, :] | (run[:h, None] <= limit)
    d = np.where(allowed, d, np.inf)
    j, s = np.unravel_index(int(np.argmin(d)), d.shape)
    if not d[j, s] < snap:
        return []
    tie = SNAP_TIE_FRACTION * snap
    near = (d <= d[j, s] + tie) & (np.linalg.norm(close - close[j, s], axis=2) <= tie)
    near[j, s] = False
    tied = [(j, s)] + list(zip(*np.nonzero(near)))
    return [(int(k), int(eid[q]), float(t0[q] + w[k, q] * (t1[q] - t0[q])), close[k, q]) for k, q in tied]


def trim_ends(net: PatchNetwork, pts: FloatArray, snap: float) -> tuple[FloatArray, Optional[Snap], Optional[Snap]]:
    """Step (2) at both ends of pts (n, 3): each end that is on or crosses a boundary is cut
    where it meets it, running smoothly into the snap point (run_into). Returns the trimmed points (first and last point on the boundary when
    snapped) and the snaps of the first and last end (None for a free end)."""
    segs = net.edge_segments()
    firsts = _at_apex(net, pts, snap_candidates(pts, snap, segs), snap, segs)
    if firsts:
        pts = run_into(pts, firsts[0][0], firsts[0][3])
    lasts = _at_apex(net, pts[::-1], snap_candidates(pts[::-1], snap, segs), snap, segs)
    if lasts:
        pts = run_into(pts[::-1], lasts[0][0], lasts[0][3])[::-1]
    if len(pts) < 2 or np.linalg.norm(pts[-1] - pts[0]) < 1e-9 * snap:
        raise StrokeRejectedError("nothing is left of it after trimming its over-sketched ends")
    first, last = _nearest_pair(net, firsts, lasts, pts, snap)
    return pts, first, last


APEX_REACH = 1.0
"""A snap within this many snap distances of a collapsed corner (the degenerate side of a 3-sided
patch, Fig. 4) is a stroke drawn to that corner: it goes to the collapsed side (:func:`_at_apex`)."""

APEX_AIM = (1.0, 4.0)
"""The stretch of a stroke, in snap distances along it from where it meets a collapsed corner,
whose footpoints give the direction it arrives from (:func:`_at_apex`)."""


def _collapsed_near(net: PatchNetwork, p: FloatArray, reach: float, segs: EdgeSegments) -> list:
    """(edge id, edge) of the degenerate edges within reach of p: pieces of the collapsed side of a
    3-sided patch, one point in 3D and a segment of the pre-image."""
    a, b, eid = segs[0], segs[1], segs[2]
    atol = DEGENERATE_ATOL * (1.0 + float(np.abs(p).max()))          # round-off, not geometry
    near = (np.abs(a - b).max(axis=1) <= atol) & (np.linalg.norm(a - p, axis=1) <= reach)
    edges = net.edges()
    return [(int(k), edges[int(k)]) for k in np.unique(eid[near])
            if not np.ptp(edges[int(k)].polyline.points, axis=0).max() > atol]


def _at_apex(net: PatchNetwork, pts: FloatArray, snaps: list, snap: float, segs: EdgeSegments) -> list:
    """The first end's snaps (snap_candidates), with a snap near a collapsed corner moved onto the
    collapsed side, where the stroke's own direction meets it in the pre-image.

    Every point of a 3-sided patch's degenerate side is the apex: the curves that run into the apex
    (the meridians of a pole) meet it along that side, each at its own pre-image point, in the
    direction they arrive from. A stroke drawn to the apex used to snap to whichever side passes
    nearest it (a point of a side next to the apex, a pre-image corner), and its pre-image ran
    diagonally across the patch instead of up to the side, squeezing a sliver that turned over
    (sketchgen octants: a meridian from the pole rejected as a fold). Here the stroke's footpoints
    APEX_AIM snap distances in give its pre-image direction; the line through them meets the
    collapsed side at the parameter the stroke takes. Unchanged when no collapsed side is within
    APEX_REACH snap distances, or when the line misses it."""
    if not snaps:
        return snaps
    j, _, _, p = snaps[0]
    near = _collapsed_near(net, p, APEX_REACH * snap, segs)
    if not near:
        return snaps
    run = cumulative_length(pts)
    h = max(2, len(pts) // 2)
    pick = np.flatnonzero((run >= run[j] + APEX_AIM[0] * snap) & (run <= run[j] + APEX_AIM[1] * snap))
    pick = pick[pick < h]
    if len(pick) < 2:
        return snaps
    pick = pick[np.unique(np.linspace(0, len(pick) - 1, min(len(pick), 5)).round().astype(int))]
    uv = []
    for i in pick:
        f = net.footpoint(pts[i], slack=snap)
        if f.inside:
            uv.append(f.uv)
    if len(uv) < 2:
        return snaps
    uv = np.array(uv)
    centre = uv.mean(axis=0)
    _, _, vt = np.linalg.svd(uv - centre)
    d = vt[0] if float(vt[0] @ (uv[0] - uv[-1])) >= 0.0 else -vt[0]     # towards the stroke's end
    a = np.array([e.uv0 for _, e in near], dtype=float)
    b = np.array([e.uv1 for _, e in near], dtype=float)
    lam, t, parallel = segment_intersections(centre, centre + d, a, b)
    hit = np.flatnonzero(~parallel & (lam > 0.0) & (t >= -UV_TIE) & (t <= 1.0 + UV_TIE))
    if not len(hit):
        return snaps
    k = hit[np.argmin(lam[hit])]
    eid, e = near[k]
    return [(j, eid, float(np.clip(t[k], 0.0, 1.0)), np.array(e.polyline.points[0], dtype=float))]


def _nearest_pair(net: PatchNetwork, firsts: list[Snap], lasts: list[Snap], pts: FloatArray,
                  snap: float) -> tuple[Optional[Snap], Optional[Snap]]:
    """The snaps of the two ends among tied ones (snap_candidates): the pair whose pre-images are
    nearest each other (the shortest pre-image of the stroke). A tie is one point reached at
    several pre-images, e.g. on a side that doubles back (a profile thinner than the filter
    distance, filtered to a line out and back): the nearest by distance, the first tried, was then
    a matter of round-off, and the rotated sketch ran a stroke to the other half of such a side,
    diagonally across its pre-image, and folded (issue 17, TiGL fuselage1). A free end counts at
    its footpoint (the candidate nearest by distance when it projects outside). The pre-image
    distance is the same whichever corner and direction the unit square's sides were given, so the
    choice follows the sketch, not the order or direction its strokes were drawn in."""
    if len(firsts) <= 1 and len(lasts) <= 1:
        return (firsts[0] if firsts else None), (lasts[0] if lasts else None)
    edges = net.edges()

    def uv(x: Snap) -> FloatArray:
        ev = edges[x[1]]
        return ev.uv0 + x[2] * (ev.uv1 - ev.uv0)

    def free(q: FloatArray) -> list:
        f = net.footpoint(q, slack=snap)
        return [None] if not f.inside else [f.uv]

    ends = [[(x, uv(x)) for x in firsts] or [(None, u) for u in free(pts[0])],
            [(x, uv(x)) for x in lasts] or [(None, u) for u in free(pts[-1])]]
    if any(u is None for _, u in ends[0] + ends[1]):
        return (firsts[0] if firsts else None), (lasts[0] if lasts else None)
    pairs = [(float(np.linalg.norm(ua - ub)), a, b) for (a, ua) in ends[0] for (b, ub) in ends[1]]
    # (pre-image distances equal to round-off, e.g. at a node that ends two edges, keep the
    # nearest snaps, the first pair)
    shortest = min(p[0] for p in pairs)
    _, a, b = next(p for p in pairs if p[0] <= shortest + UV_TIE)
    return a, b


def run_into(pts: FloatArray, j: int, target: FloatArray) -> FloatArray:
    """Step (2) for a snapped first end: trim the over-sketch before the stroke's closest approach
    to the curve and let the stroke run smoothly into the snap point.

    The cut is where the snap point projects onto the stroke (on the segments around vertex j),
    not at vertex j itself, so the kept part cannot turn back; the remaining offset from the cut
    to the snap point is spread over the stroke's first stretch (as the boundary closing spreads
    its corner offsets: strokes.ramp), instead of a jump in one segment (a hook)."""
    best = (np.inf, j, 0.0)
    for k in (j - 1, j):
        if 0 <= k < len(pts) - 1:
            a, b = pts[k], pts[k + 1]
            ab = b - a
            ll = float(ab @ ab)
            w = float(np.clip((target - a) @ ab / ll, 0.0, 1.0)) if ll > 1e-300 else 0.0
            d = float(np.linalg.norm(a + w * ab - target))
            if d < best[0]:
                best = (d, k, w)
    _, k, w = best
    cut = pts[k] + w * (pts[k + 1] - pts[k])
    kept = np.vstack([cut, pts[k + 1:]])
    # the cut on the next vertex up to round-off (of the coordinates: 1e-12 mm at 100 mm)
    if len(kept) > 2 and np.linalg.norm(kept[1] - kept[0]) <= 1e-14 * float(np.abs(kept[:2]).max()):
        kept = np.delete(kept, 1, axis=0)
    run = cumulative_length(kept)
    offset = ramp(run, np.asarray(target, dtype=float) - kept[0], float(run[-1]))
    out = kept.copy() if offset is None else kept + offset
    out[0] = target
    return out


def free_end(net: PatchNetwork, q: FloatArray, which: str, snap: float) -> StrokeEnd:
    """Step (6): the footpoint of a free end (Eq. 2); reject when it projects outside."""
    f = net.footpoint(q, slack=snap)
    if not f.inside:
        raise StrokeOutsideSurfaceError(
            f"its {which} end ({q[0]:.1f}, {q[1]:.1f}, {q[2]:.1f}) projects outside the surface "
            f"(nearest surface point is on the outer boundary, {abs(f.distance):.2f} mm away); "
            "draw interior strokes over the surface")
    return StrokeEnd(uv=f.uv, xyz=q, snapped=False, offset=float(abs(f.distance)), region=f.region)


def snapped_end(net: PatchNetwork, snapped: Snap) -> StrokeEnd:
    """The end found by :func:`snap_end`, on edge e at parameter t, as a StrokeEnd."""
    _, e, t, p = snapped
    ev = net.edges()[e]
    return StrokeEnd(uv=ev.uv0 + t * (ev.uv1 - ev.uv0), xyz=p, snapped=True, edge=e, t=t)


def end_of(net: PatchNetwork, snapped: Optional[Snap], q: FloatArray, which: str, snap: float) -> StrokeEnd:
    """The end at point q (3,): on its boundary when it snapped (step 2), else free (step 6)."""
    if snapped is None:
        return free_end(net, q, which, snap)
    return snapped_end(net, snapped)


def placed_end(net: PatchNetwork, pts: FloatArray, snap: float, which: str) -> StrokeEnd:
    """The end pts[0] on the current network: snapped when it is on a boundary, else free."""
    snapped = snap_end(pts, snap, net.edge_segments())
    if snapped is not None and snapped[0] == 0:
        return snapped_end(net, snapped)
    return free_end(net, pts[0], which, snap)


def extension(net: PatchNetwork, end: StrokeEnd, away: FloatArray, falloff: str) -> tuple[FloatArray, FloatArray]:
    """Steps (7)-(8): extend the pre-image from the footpoint F away from the stroke to the
    boundary g of the region it is in; the 3D points are the surface plus the offset Q - F,
    distributed evenly (linear) or smoothly (cubic) from F to g. Returns (uv (k,2), xyz (k,3)),
    from F (exclusive) to g (inclusive)."""
    norm = float(np.linalg.norm(away))
    if not norm > 1e-12:
        return np.empty((0, 2)), np.empty((0, 3))
    direction = away / norm
    rid = net.locate(end.uv)
    length = min(ray_exit(end.uv, direction, net.region_polygon(rid)), np.sqrt(2.0))
    if not length > 1e-9:
        return np.empty((0, 2)), np.empty((0, 3))
    k = max(4, int(np.ceil(length * 4 * net.mesh_density)))
    w = np.linspace(0.0, 1.0, k + 1)[1:]
    uv = end.uv + np.outer(w * length, direction)
    surface, at_end = net.evaluate_uv_sets([uv, end.uv])
    delta = end.xyz - at_end[0]
    fall = 1.0 - w if falloff == "linear" else 2 * w**3 - 3 * w**2 + 1
    return uv, surface + fall[:, None] * delta
