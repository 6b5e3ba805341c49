"""Re-planning the regions around a fold a stroke made (core.folds), before giving the stroke up.

A Coons sub-patch (Eq. 1, Hermite blends) takes its cross-boundary tangent along a side from the
end tangents of the two adjacent sides only. When a stroke cuts a large curved region (a diagonal
across a cylinder panel, say), that blend is a poor guess far from the corners and the two new
sub-patches meet along the stroke at a crease that the surface before the stroke did not have.

The cure follows the paper's own case (c) split (progressive.py, Fig. 6 (c)): a creased region is
split by a curve from the middle of the creased side to the middle of the opposite side (or to the
opposite corner of a 3-sided region). The new curve follows the surface as it was before the
stroke, with the offsets at its ends distributed linearly, so its tangent where it meets the
stroke carries the old surface's cross direction into both new sub-patches, and the interpolated
stretch is halved. This is repeated a few rounds; a fold that is still there then rejects the
stroke (progressive.add_stroke), and the surface stays as it was.
"""
from __future__ import annotations

import numpy as np

from .curve_fit import sample_to_sag
from .errors import StrokeRejectedError
from .folds import FACE_SAMPLES, Fold, find_folds, surface_turn_deg
from .types import FloatArray, Polyline

ROUNDS = 3
"""Rounds of splitting before a stroke that still folds the surface is rejected."""

FOLLOW_POINTS = 32
"""At least this many segments on a curve that follows the old surface (more where its chords
would sag more than the stroke's sag allowance: follow_surface)."""

REUSE_UV = 0.02
"""A side's middle closer than this (pre-image) to an existing node of the side uses that node."""


def _side_nodes(cycle: tuple, a: int, b: int) -> list[int]:
    """Nodes of the cycle from corner a to corner b, in cycle order (both included)."""
    n = len(cycle)
    i, j = cycle.index(a), cycle.index(b)
    return [cycle[(i + k) % n] for k in range((j - i) % n + 1)]


def _node_at(net, nodes: list[int], target: FloatArray) -> int:
    """A node at the pre-image point target on the polyline of nodes: an existing one within
    REUSE_UV, else a new one splitting the edge that holds target (no pull: the curve stays)."""
    uvs = np.array([net.node_uv(k) for k in nodes])
    d = np.linalg.norm(uvs - target, axis=1)
    inner = d[1:-1]
    if len(inner) and inner.min() < REUSE_UV:
        return nodes[1 + int(np.argmin(inner))]
    best = None
    for p, q in zip(nodes[:-1], nodes[1:]):
        a, b = net.node_uv(p), net.node_uv(q)
        ab = b - a
        t = float(np.clip((target - a) @ ab / max(ab @ ab, 1e-300), 0.0, 1.0))
        dist = float(np.linalg.norm(a + t * ab - target))
        if best is None or dist < best[0]:
            best = (dist, p, q, t)
    _, p, q, t = best
    eid, rev = net.edge_between(p, q)
    t = 1.0 - t if rev else t
    if not 1e-3 < t < 1 - 1e-3:
        return p if (t < 0.5) != rev else q
    return net.split_edge(eid, t, net.edges()[eid].polyline.evaluate(t), pull=False)


def follow_surface(old, uv0: FloatArray, uv1: FloatArray, xyz0: FloatArray, xyz1: FloatArray,
                   n: int, sag_mm: float | None) -> Polyline:
    """The curve along the straight pre-image uv0 -> uv1 on the surface `old`, moved to start at
    xyz0 and end at xyz1 (the offsets at its ends spread linearly), as a polyline of at least n
    segments whose chords sag at most sag_mm (curve_fit.sample_to_sag; None: n segments)."""
    uv0, uv1 = np.asarray(uv0, dtype=float), np.asarray(uv1, dtype=float)
    ends = old.evaluate_uv(np.array([uv0, uv1]))
    off0, off1 = np.asarray(xyz0, dtype=float) - ends[0], np.asarray(xyz1, dtype=float) - ends[1]

    def points_at(w: FloatArray) -> FloatArray:
        pts = old.evaluate_uv(uv0 + np.outer(w, uv1 - uv0))
        return pts + (1 - w)[:, None] * off0 + w[:, None] * off1

    w, pts = sample_to_sag(points_at, np.linspace(0.0, 1.0, n + 1), sag_mm)
    pts[0], pts[-1] = xyz0, xyz1
    return Polyline(pts, w)


def _follow_old(net, old, a: int, b: int, sag_mm: float | None = None) -> Polyline:
    """The curve a -> b along the surface before the stroke, its end offsets spread linearly."""
    uv0, uv1 = net.node_uv(a), net.node_uv(b)
    # dense enough that its chords do not sag off the surface (a short pre-image may be long in 3D)
    n = max(FOLLOW_POINTS, int(np.ceil(np.linalg.norm(uv1 - uv0) * 4 * net.mesh_density)))
    return follow_surface(old, uv0, uv1, net.node_xyz(a), net.node_xyz(b), n, sag_mm)


def _split_across(net, old, rid: int, m: int, sag_mm: float | None = None) -> None:
    """Split region rid by a curve from node m (on one of its sides) across the region."""
    corners = list(net.region_corner_ids(rid))
    cycle = net.region_cycle(rid)
    k = len(corners)
    side = None
    for i in range(k):
        nodes = _side_nodes(cycle, corners[i], corners[(i + 1) % k])
        if m in nodes:
            side = i
            break
    if side is None:
        return
    if m in corners:
        return
    if k == 3:
        far = corners[(side + 2) % 3]
    else:
        a, b = corners[(side + 2) % 4], corners[(side + 3) % 4]
        nodes = _side_nodes(cycle, a, b)
        far = _node_at(net, nodes, 0.5 * (net.node_uv(a) + net.node_uv(b)))
        cycle = net.region_cycle(rid)
    if far == m or net.has_edge(m, far):
        return
    _add_split(net, old, rid, m, far, sag_mm, "re-planning a fold")


def _add_split(net, old, rid: int, a: int, b: int, sag_mm: float | None, what: str) -> None:
    """Split region rid along a new curve from node a to node b that follows the surface before
    the stroke (_follow_old); `what` names the step in the rejection when a region it leaves is
    not 3- or 4-sided."""
    curve = net.new_curve_id("split")
    for new in net.add_chord(rid, a, b, curve, _follow_old(net, old, a, b, sag_mm)):
        if len(net.region_corner_ids(new)) not in (3, 4):
            raise StrokeRejectedError(f"{what} would leave a region that is not 3- or 4-sided")


def split_lens(net, old, rid: int, sag_mm: float | None = None) -> None:
    """Split a lens (NetworkViews.lens: two curves that meet at a 3-sided sketch's apex and cross
    at q) across its middle, by a curve that follows the surface before the stroke from the middle
    of one curve to the middle of the other: a triangle with its apex at q and a 4-sided region
    whose side at the apex is a point, so that each sharp tip is a collapsed corner, as in a
    3-sided patch. Left as it was, the lens's Coons patch is ruled between the two curves: its
    normals along both are undefined, their limits 50-80 deg off its neighbours' (sketchgen 153000
    sk_octant_3 and _8, a fin the fold checks could not see); with one tip as a regular corner
    instead, the patch turns over next to that tip."""
    found = net.lens(rid)
    if found is None:
        return
    a, b, q = found
    cycle = net.region_cycle(rid)
    first = _side_nodes(cycle, b, q)
    m1 = _node_at(net, first, 0.5 * (net.node_uv(b) + net.node_uv(q)))
    cycle = net.region_cycle(rid)
    second = _side_nodes(cycle, q, a)
    m2 = _node_at(net, second, 0.5 * (net.node_uv(q) + net.node_uv(a)))
    if len({m1, m2, q, a, b}) < 5 or net.has_edge(m1, m2):
        return
    _add_split(net, old, rid, m1, m2, sag_mm, "splitting a lens")


def _middle(net, rid: int) -> tuple[int, FloatArray]:
    """(a corner, the middle of the longer pair of opposite sides' first side) for a face fold."""
    corners = list(net.region_corner_ids(rid))
    uv = np.array([net.node_uv(c) for c in corners])
    lengths = np.linalg.norm(np.roll(uv, -1, axis=0) - uv, axis=1)
    i = int(np.argmax(lengths))
    return i, 0.5 * (uv[i] + uv[(i + 1) % len(corners)])


def _repair(net, old, fold: Fold, sag_mm: float | None = None) -> None:
    live = set(net.region_ids)
    if not set(fold.regions) <= live:
        return
    if fold.kind == "seam":
        edges = net.edges()
        if fold.edge not in edges:
            return
        e = edges[fold.edge]
        m = net.split_edge(fold.edge, 0.5, e.polyline.evaluate(0.5), pull=False)
        for rid in fold.regions:
            _split_across(net, old, rid, m, sag_mm)
        return
    rid = fold.regions[0]
    i, target = _middle(net, rid)
    corners = list(net.region_corner_ids(rid))
    nodes = _side_nodes(net.region_cycle(rid), corners[i], corners[(i + 1) % len(corners)])
    m = _node_at(net, nodes, target)
    if m not in corners:
        _split_across(net, old, rid, m, sag_mm)


FACE_MARGIN_DEG = 10.0
"""A region that turns (core.folds.face_turn_deg) no more than this beyond what the surface before
the stroke turned over the same part of the pre-image is not folded by the stroke: a tube or a
deep dome turns a lot on its own."""


def _turn_before(net, old, fold: Fold) -> float:
    """How much the surface before the stroke turned over the pre-image of a face fold's region."""
    g = np.linspace(0.0, 1.0, FACE_SAMPLES)
    s, r = (a.ravel() for a in np.meshgrid(g, g, indexing="ij"))
    return surface_turn_deg(old, net.local_to_uv(fold.regions[0], s, r))


def _made_by_stroke(net, old, fold: Fold) -> bool:
    return fold.kind != "face" or fold.angle_deg > _turn_before(net, old, fold) + FACE_MARGIN_DEG


def repair_folds(net, old, touched: set, sharp_curves=(), sag_mm: float | None = None) -> list[Fold]:
    """Split the regions of every new fold among ``touched`` (regions a stroke made or reshaped)
    for up to ROUNDS rounds; returns the folds that are left (empty when the surface is clean).
    Folds that ``old`` already had in the same regions are not the stroke's and are left alone.
    sag_mm: how far a chord of a splitting curve may sag (follow_surface)."""
    before = None      # the old network's folds, looked for only once the new one has any
    for round_ in range(ROUNDS + 1):
        live = set(net.region_ids)
        found = find_folds(net, touched & live, sharp_curves)
        if found and before is None:
            before = {(f.kind, f.regions) for f in find_folds(old, touched & set(old.region_ids), sharp_curves)}
        made = [f for f in found if (f.kind, f.regions) not in before and _made_by_stroke(net, old, f)]
        if not made:
            return []
        if round_ == ROUNDS:
            return made
        seams = [f for f in made if f.kind == "seam"]
        if not seams:            # a face that turns over is not mended by splitting it
            return made
        for fold in sorted(seams, key=lambda f: -f.angle_deg):
            _repair(net, old, fold, sag_mm)
        touched = touched | {r for r in net.region_ids if r not in live}
    return made
