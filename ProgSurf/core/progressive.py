"""Progressive update of the patch network by one interior stroke: Qin & Wright section 3
(2006 text, steps (1)-(9), Fig. 5-8; motion-sketch text, Eq. 2 and Fig. 5 cases a-d).

One call of :func:`add_stroke` either accepts the stroke and changes the network, or rejects it
with a reason and leaves the network exactly as it was.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from .fairing import fair_stroke, pchip
from .errors import ProgSurfError, StrokeOutsideSurfaceError, StrokeRejectedError
from .network import OUTER_CURVES, PatchNetwork
from .strokes import cumulative_length
from .preimage import ray_exit, segment_intersections
from .types import FloatArray, Polyline, Tolerances

NODE_MERGE_UV = 2e-3
"""A crossing closer than this (in the unit square) along the pre-image line to the node before it
gets no node of its own."""

NODE_SNAP_UV = 0.02
"""A crossing closer than this to an end node of the crossed edge (in the unit square, about the
automatic snap distance on a typical sketch), and within the snap distance of it in 3D, goes
through that node: strokes drawn through (nearly) one point meet there, instead of leaving
near-duplicate nodes and sliver regions whose sub-patches fold."""

MAX_DEPTH = 5
"""Recursion depth of the pre-image straightness test (up to 32 straight pieces)."""


@dataclass(frozen=True)
class StrokeRecord:
    """What happened to one stroke.

    index   : the stroke's position in the input
    role    : "boundary" or "interior"
    status  : "accepted" or "rejected"
    reason  : why it was rejected, or a short note of what was done
    pre_image : (k, 2) the pre-image polyline in the unit square (with extensions), or None
    curve_ids : network curves made from this stroke (one per straight piece)
    regions_created, regions_removed : region ids
    pulled_curves : ids of earlier curves pulled to this stroke (later strokes win)
    ends    : how each end was placed: "snapped" (on/crossing a boundary) or "footpoint"
    end_offsets_mm : |Q - F| at each end placed by a footpoint (0 for snapped ends)
    points  : (n, 3) the stroke as it was used (filtered, faired, trimmed), or None
    fair_deviation_mm : largest distance of the filtered stroke from its faired curve
    """

    index: int
    role: str
    status: str
    reason: str = ""
    pre_image: Optional[FloatArray] = None
    curve_ids: tuple = ()
    regions_created: tuple = ()
    regions_removed: tuple = ()
    pulled_curves: tuple = ()
    ends: tuple = ()
    end_offsets_mm: tuple = ()
    points: Optional[FloatArray] = None
    fair_deviation_mm: float = 0.0


@dataclass
class _End:
    """One end of a straight piece: on an edge (snapped) or free at a footpoint."""

    uv: FloatArray
    xyz: FloatArray
    snapped: bool
    edge: int = -1
    t: float = 0.0
    offset: float = 0.0
    region: int = -1


@dataclass
class _Work:
    pre_image: list = field(default_factory=list)
    curve_ids: list = field(default_factory=list)
    pulled: set = field(default_factory=set)
    ends: list = field(default_factory=list)
    offsets: list = field(default_factory=list)


def _snap_end(net: PatchNetwork, pts: FloatArray, snap: float, segs) -> Optional[tuple]:
    """Step (2): is the first end of pts on or crossing a boundary curve?

    Tests the distance from the points of the first half of the stroke to every current boundary
    (outer sides, earlier strokes). Over-sketch past an outer side may be any length; past an
    interior curve it may be at most max(2 snap, 15% of the stroke), so a stroke that truly
    crosses an earlier one is not cut there. Returns (j, edge id, t, point) or None."""
    a, b, eid, t0, t1, outer = segs
    h = max(1, len(pts) // 2)
    p = pts[:h]
    ab = b - a
    ll = np.einsum("ij,ij->i", ab, ab)
    w = np.einsum("hsk,sk->hs", p[:, None, :] - a[None], ab) / np.where(ll > 1e-300, ll, 1.0)
    w = np.clip(w, 0.0, 1.0)
    close = a[None] + w[..., None] * ab[None]
    d = np.linalg.norm(p[:, None, :] - close, axis=2)
    run = cumulative_length(pts)
    limit = max(2.0 * snap, 0.15 * run[-1])
    allowed = outer[None, :] | (run[:h, None] <= limit)
    d = np.where(allowed, d, np.inf)
    j, s = np.unravel_index(int(np.argmin(d)), d.shape)
    if not d[j, s] < snap:
        return None
    t = t0[s] + w[j, s] * (t1[s] - t0[s])
    return int(j), int(eid[s]), float(t), close[j, s]


def _free_end(net: PatchNetwork, q: FloatArray, which: str, snap: float) -> _End:
    """Step (6): the footpoint of a free end (Eq. 2); reject when it projects outside."""
    f = net.footpoint(q, slack=snap)
    if not f.inside:
        raise StrokeOutsideSurfaceError(
            f"its {which} end ({q[0]:.1f}, {q[1]:.1f}, {q[2]:.1f}) projects outside the surface "
            f"(nearest surface point is on the outer boundary, {abs(f.distance):.2f} mm away); "
            "draw interior strokes over the surface")
    return _End(uv=f.uv, xyz=q, snapped=False, offset=float(abs(f.distance)), region=f.region)


def _straight_pieces(net: PatchNetwork, pts: FloatArray, uv0: FloatArray, uv1: FloatArray,
                     i0: int, i1: int, tol: float, snap: float, depth: int = 0) -> list[int]:
    """Step (6), last paragraph: split at the middle point recursively until each piece's
    pre-image is straight within tol. Returns interior break indices."""
    if i1 - i0 < 2 or depth >= MAX_DEPTH:
        return []
    m = (i0 + i1) // 2
    f = net.footpoint(pts[m], slack=snap)
    if not f.inside:
        raise StrokeOutsideSurfaceError(
            f"its point {m} ({pts[m][0]:.1f}, {pts[m][1]:.1f}, {pts[m][2]:.1f}) projects outside the surface")
    d = uv1 - uv0
    length = np.linalg.norm(d)
    off = abs(float(d[0] * (f.uv[1] - uv0[1]) - d[1] * (f.uv[0] - uv0[0]))) / max(length, 1e-300)
    if off <= tol:
        return []
    return (_straight_pieces(net, pts, uv0, f.uv, i0, m, tol, snap, depth + 1) + [m]
            + _straight_pieces(net, pts, f.uv, uv1, m, i1, tol, snap, depth + 1))


def _extension(net: PatchNetwork, end: _End, away: FloatArray, falloff: str) -> tuple[FloatArray, FloatArray]:
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
    surface = net.evaluate_uv(uv)
    delta = end.xyz - net.evaluate_uv(end.uv)
    fall = 1.0 - w if falloff == "linear" else 2 * w**3 - 3 * w**2 + 1
    return uv, surface + fall[:, None] * delta


def _crossing_nodes(net: PatchNetwork, crossings: list, p0: FloatArray, line: FloatArray,
                    snap: float) -> list[tuple[float, int, int, float]]:
    """Where the pre-image line p0 + t * line meets the network, decided before anything changes.

    crossings : (t along the line, edge id, s along the edge), in order along the line
    Returns (t, node, edge id, s) in order along the line, one entry per node; node -1 means
    "split the edge at s". A crossing within NODE_SNAP_UV (pre-image) and snap (3D, along the
    crossed curve) of an end node of its edge goes through that node instead (see
    :func:`_plan_nodes`). When two such nodes clash (the stroke would run along the curve between
    them, or they are out of order along the line), one of them is not used: the one whose
    crossings then leave the wider node spacing, if that is at least NODE_SNAP_UV / 2. Otherwise
    the stroke is rejected, as it would leave a sliver region."""
    edges = net.edges()
    near: dict[int, tuple[float, int]] = {}          # edge id -> (distance, end node) within reach
    for tk, eid, se in crossings:
        e = edges[eid]
        span = float(np.linalg.norm(e.uv1 - e.uv0))
        here = e.polyline.evaluate(se)
        for node, dist in ((e.node0, se * span), (e.node1, (1.0 - se) * span)):
            if (dist <= NODE_SNAP_UV and np.linalg.norm(net.node_xyz(node) - here) <= snap
                    and dist < near.get(eid, (np.inf, -1))[0]):
                near[eid] = (dist, node)
    exact = {node for dist, node in near.values() if dist <= 1e-9}   # the line passes through these

    def without(node: int) -> dict:
        return {eid: v for eid, v in near.items() if v[1] != node}

    while True:
        plan, clash, reason = _plan_nodes(net, edges, crossings, near, p0, line)
        if not reason:
            return plan
        options = [(_spacing(net, edges, _plan_nodes(net, edges, crossings, without(n), p0, line)[0]), n)
                   for n in sorted(clash - exact)]     # (spacing without node n, n)
        gap, drop = max(options, default=(0.0, -1))
        if gap < 0.5 * NODE_SNAP_UV:
            raise StrokeRejectedError(reason)
        near = without(drop)


def _plan_nodes(net: PatchNetwork, edges: dict, crossings: list, near: dict, p0: FloatArray,
                line: FloatArray) -> tuple[list, set, str]:
    """One plan for :func:`_crossing_nodes` in which the existing nodes ``near`` (edge id ->
    (distance, node)) are used by their crossings. The stroke then passes through each such node,
    so every crossing of an edge ending there is that node too (a straight piece from the node
    meets such an edge nowhere else), and its t is the node's projection onto the line. The
    pre-image leaves the line by less than NODE_SNAP_UV there, and every region stays convex: the
    node already has curves on both sides of any line through it. Returns (plan, set(), ""), or
    (the plan so far, the used nodes that clash, the reason to reject the stroke if no other plan
    is found)."""
    via = {node for _, node in near.values()}
    plan: list[tuple[float, int, int, float]] = []
    too_close = "its pre-image passes too close to an existing node"
    for tk, eid, se in crossings:
        e = edges[eid]
        at_end = tk <= 1e-6 or tk >= 1 - 1e-6
        # an end of the stroke stays where it is unless it is itself within reach of a node
        ends = [n for n in (e.node0, e.node1) if n in via and (eid in near or not at_end)]
        if not ends:
            if not plan or abs(tk - plan[-1][0]) * np.linalg.norm(line) > NODE_MERGE_UV:
                plan.append((tk, -1, eid, se))
            continue
        node = near[eid][1] if eid in near else ends[0]
        t = tk if at_end else float(np.clip((net.node_uv(node) - p0) @ line / (line @ line), 0.0, 1.0))
        if plan and plan[-1][1] == node:              # the same node again: an end keeps its t
            if at_end:
                plan[-1] = (tk, node, eid, se)
            continue
        if any(entry[1] == node for entry in plan):
            return plan, {node}, too_close
        plan.append((t, node, eid, se))
    for (ta, na, ea, _), (tb, nb, eb, _) in zip(plan[:-1], plan[1:]):
        if tb <= ta:
            return plan, {na, nb} & via, too_close
        # The piece between them would run along an edge: one joining two used nodes, or the edge
        # a stroke end splits when it ends at the used node next to it.
        along = None
        if na >= 0 and nb >= 0 and (na, nb) in net._edge_index:
            along = net.edge_between(na, nb)[0]
        elif na < 0 <= nb and nb in (edges[ea].node0, edges[ea].node1):
            along = ea
        elif nb < 0 <= na and na in (edges[eb].node0, edges[eb].node1):
            along = eb
        if along is not None:
            return plan, {na, nb} & via, f"its pre-image runs along curve {edges[along].curve_id} near a node"
    return plan, set(), ""


def _spacing(net: PatchNetwork, edges: dict, plan: list) -> float:
    """The smallest pre-image distance a plan leaves between a new node and the ends of the edge
    it splits, or between two nodes next to each other along the line."""
    points, gaps = [], [np.inf]
    for _, node, eid, se in plan:
        if node >= 0:
            points.append(net.node_uv(node))
            continue
        e = edges[eid]
        points.append(e.uv0 + se * (e.uv1 - e.uv0))
        gaps.append(min(se, 1.0 - se) * float(np.linalg.norm(e.uv1 - e.uv0)))
    gaps += [float(np.linalg.norm(b - a)) for a, b in zip(points[:-1], points[1:])]
    return min(gaps)


def _line_params(net: PatchNetwork, pts: FloatArray, uv0: FloatArray, uv1: FloatArray,
                 snap: float, anchors: int = 3) -> FloatArray:
    """Where each stroke point lies along its straight pre-image uv0 -> uv1, in [0, 1].

    The footpoints of a few anchor points (Eq. 2) are projected onto the line, and chord length
    interpolates between them, so a crossing in the pre-image plane meets the stroke where its
    footpoint is, not where its arc length happens to be. Falls back to chord length alone when
    the anchors' projections are not in order."""
    run = cumulative_length(pts)
    if run[-1] <= 0:
        raise StrokeRejectedError("it has zero length")
    chord = run / run[-1]
    idx = np.unique(np.linspace(0, len(pts) - 1, min(len(pts), anchors)).round().astype(int))
    if len(idx) <= 2:
        return chord
    d = uv1 - uv0
    at = [0.0]
    for i in idx[1:-1]:
        f = net.footpoint(pts[i], slack=snap)
        at.append(float((f.uv - uv0) @ d / (d @ d)))
    at.append(1.0)
    at = np.array(at)
    if np.any(np.diff(at) <= 1e-9):
        return chord
    return pchip(chord[idx], at, chord)


def _insert_piece(net: PatchNetwork, old: PatchNetwork, pts: FloatArray, start: _End, end: _End,
                  curve_id: int, tol: Tolerances, snap: float, falloff: str, work: _Work) -> None:
    """Steps (3)-(5) for one straight piece: extend, cross, pull, subdivide, rebuild."""
    if not np.linalg.norm(end.uv - start.uv) > 1e-6:
        raise StrokeRejectedError("its pre-image has no length (both ends map to the same surface point)")
    ext0_uv, ext0_xyz = (np.empty((0, 2)), np.empty((0, 3))) if start.snapped else \
        _extension(net, start, start.uv - end.uv, falloff)
    ext1_uv, ext1_xyz = (np.empty((0, 2)), np.empty((0, 3))) if end.snapped else \
        _extension(net, end, end.uv - start.uv, falloff)
    main_uv = start.uv + np.outer(_line_params(net, pts, start.uv, end.uv, snap), end.uv - start.uv)
    uv = np.vstack([ext0_uv[::-1], main_uv, ext1_uv])
    xyz = np.vstack([ext0_xyz[::-1], pts, ext1_xyz])
    p0, p1 = uv[0], uv[-1]
    line = p1 - p0
    length = float(np.linalg.norm(line))
    if length < 1e-6:
        raise StrokeRejectedError("its pre-image has no length (both ends map to the same surface point)")
    t = np.clip((uv - p0) @ line / length**2, 0.0, 1.0)
    keep = np.concatenate([[True], np.diff(t) > 1e-12])
    keep[-1] = True
    t, xyz = t[keep], xyz[keep]
    t = np.maximum.accumulate(t)
    t[0], t[-1] = 0.0, 1.0
    if len(t) > 2 and np.any(np.diff(t) <= 0):
        xyz = np.vstack([xyz[0], xyz[1:-1][np.diff(t[:-1]) > 0], xyz[-1]])
        t = np.concatenate([[0.0], t[1:-1][np.diff(t[:-1]) > 0], [1.0]])
    if tol.fair_mm and (len(ext0_uv) or len(ext1_uv)) and len(xyz) >= 4:
        # Fair the stroke with its extensions as one curve, so the joins at the footpoints
        # carry no corner; parameters follow C1 through the ones just found.
        at: list = []
        fair, _ = fair_stroke(xyz, tol.fair_mm, tol.fit_mm / 4.0, original_at=at)
        run = cumulative_length(fair)
        t_fair = np.clip(pchip(run[at], t, run), 0.0, 1.0)
        t_fair[0], t_fair[-1] = 0.0, 1.0
        if np.all(np.diff(t_fair) > 0):
            xyz, t = fair, t_fair
    full = Polyline(xyz, t)
    work.pre_image.append(np.array([p0, p1]))

    # Crossings of the pre-image line with every edge (step 3: affected regions).
    edges = net.edges()
    ids = np.array(list(edges))
    a = np.array([edges[k].uv0 for k in ids])
    b = np.array([edges[k].uv1 for k in ids])
    tl, se, parallel = segment_intersections(p0, p1, a, b)
    rel0 = np.abs((a - p0) @ np.array([-line[1], line[0]])) / length
    rel1 = np.abs((b - p0) @ np.array([-line[1], line[0]])) / length
    overlap = parallel & (rel0 < 1e-9) & (rel1 < 1e-9)
    if np.any(overlap):
        proj = np.column_stack([(a - p0) @ line, (b - p0) @ line]) / length**2
        lo, hi = proj.min(axis=1), proj.max(axis=1)
        runs_along = overlap & (np.minimum(hi, 1) - np.maximum(lo, 0) > 1e-6)
        if np.any(runs_along):
            cid = edges[ids[np.flatnonzero(runs_along)[0]]].curve_id
            raise StrokeRejectedError(f"its pre-image runs along curve {cid}")
    eps = 1e-9
    hit = ~parallel & (se >= -eps) & (se <= 1 + eps) & (tl >= -1e-7) & (tl <= 1 + 1e-7)
    crossings = sorted((float(tl[k]), int(ids[k]), float(np.clip(se[k], 0, 1))) for k in np.flatnonzero(hit))
    if not crossings or crossings[0][0] > 1e-6 or crossings[-1][0] < 1 - 1e-6:
        raise StrokeRejectedError("its pre-image does not end on a boundary (internal inconsistency)")

    # Nodes along the line; later strokes win (step 4): interior curves are pulled to the stroke.
    nodes: list[tuple[float, int]] = []
    for tk, nid, eid, se_k in _crossing_nodes(net, crossings, p0, line, snap):
        at_end = tk <= 1e-6 or tk >= 1 - 1e-6
        stroke_xyz = full.evaluate(tk)
        if nid < 0:
            curve = net.edges()[eid].curve_id
            pull = not at_end and curve not in OUTER_CURVES
            nid = net.split_edge(eid, se_k, stroke_xyz, pull)
            if pull:
                work.pulled.add(curve)
        elif not at_end and not net.is_outer_node(nid):
            net.move_node(nid, stroke_xyz)
            edges = net.edges()
            work.pulled.update(edges[k].curve_id for k in net.incident_edges(nid)
                               if edges[k].curve_id not in OUTER_CURVES)
        nodes.append((tk, nid))
    if len(nodes) < 2:
        raise StrokeRejectedError("its pre-image is shorter than the node spacing")

    for (ta, na), (tb, nb) in zip(nodes[:-1], nodes[1:]):
        if na == nb:
            continue
        if (na, nb) in net._edge_index:
            raise StrokeRejectedError(f"its pre-image runs along curve {net.edges()[net.edge_between(na, nb)[0]].curve_id}")
        inner = (full.params > ta + 1e-12) & (full.params < tb - 1e-12)
        sub_t = np.concatenate([[ta], full.params[inner], [tb]])
        sub_p = np.vstack([full.evaluate(ta), full.points[inner], full.evaluate(tb)])
        poly = Polyline(sub_p, (sub_t - ta) / (tb - ta))
        t_col = poly.params[:, None]
        poly = Polyline(poly.points + (1 - t_col) * (net.node_xyz(na) - sub_p[0])
                        + t_col * (net.node_xyz(nb) - sub_p[-1]), poly.params)
        mid = 0.5 * (net.node_uv(na) + net.node_uv(nb))
        rid = net.locate(mid)
        cyc = net.region_cycle(rid)
        if na not in cyc or nb not in cyc:
            raise StrokeRejectedError("its pre-image passes too close to an existing node")
        for new in net.add_chord(rid, na, nb, curve_id, poly):
            _make_three_or_four_sided(net, old, new, na, nb)


def _make_three_or_four_sided(net: PatchNetwork, old: PatchNetwork, rid: int, a: int, b: int) -> None:
    """Step (4), Fig. 6(c): a chord across two adjacent sides leaves a pentagon; split it into
    two 4-sided regions by a curve from the corner opposite the chord to the chord's middle M.
    The new curve follows the old surface with the offset at M distributed linearly."""
    corners = net.region_corner_ids(rid)
    if len(corners) in (3, 4):
        return
    if len(corners) != 5 or a not in corners or b not in corners:
        raise StrokeRejectedError(f"subdividing would leave a {len(corners)}-sided region")
    k = list(corners)
    i = k.index(a)
    k = k[i:] + k[:i]                      # a first
    if k[-1] != b:                         # orientation: chord is the side b -> a
        k = [k[0]] + k[1:][::-1]
    opposite = k[2]
    eid, rev = net.edge_between(a, b)
    m = net.split_edge(eid, 0.5, net.edges()[eid].polyline.evaluate(0.5), pull=False)
    uv0, uv1 = net.node_uv(opposite), net.node_uv(m)
    n = max(4, int(np.ceil(np.linalg.norm(uv1 - uv0) * 4 * net.mesh_density)))
    w = np.linspace(0.0, 1.0, n + 1)
    uv = uv0 + np.outer(w, uv1 - uv0)
    pts = old.evaluate_uv(uv)
    pts = pts + (1 - w)[:, None] * (net.node_xyz(opposite) - pts[0]) + w[:, None] * (net.node_xyz(m) - pts[-1])
    curve = net.new_curve_id("split")
    for new in net.add_chord(rid, opposite, m, curve, Polyline(pts, w)):
        if len(net.region_corner_ids(new)) not in (3, 4):
            raise StrokeRejectedError("subdividing would leave a region that is not 3- or 4-sided")


def add_stroke(net: PatchNetwork, stroke: FloatArray, index: int, tol: Tolerances, snap: float,
               falloff: str = "linear") -> StrokeRecord:
    """Add one interior stroke (steps (1)-(9)); never raises for a bad stroke: the record says why.

    stroke : (n, 3) filtered points of the stroke, in drawing order
    snap   : snap distance in mm (step 2)
    falloff: "linear" (the paper's even distribution) or "smooth" (cubic) for the end offsets
    """
    snap_state = net.snapshot()
    old = net.clone()
    net.take_log()
    work = _Work()
    pts = np.array(stroke, dtype=float)
    try:
        if len(pts) < 2:
            raise StrokeRejectedError(f"it has {len(pts)} point(s) after filtering; a stroke needs at least 2")
        pieces = [pts]
        if len(pts) >= 4 and np.linalg.norm(pts[0] - pts[-1]) < snap:
            far = int(np.argmax(np.linalg.norm(pts - pts[0], axis=1)))
            pieces = [pts[: far + 1], pts[far:]]          # a closed stroke: two open pieces
        used = []
        for piece in pieces:
            used.append(_add_open(net, old, piece, index, tol, snap, falloff, work))
    except ProgSurfError as err:
        net.restore(snap_state)
        return StrokeRecord(index, "interior", "rejected", str(err), points=pts)
    log = net.take_log()
    created = tuple(r for kind, r in log if kind == "created" and r in net.region_ids)
    removed = tuple(r for kind, r in log if kind == "removed" and r in old.region_ids)
    note = f"{len(work.curve_ids)} straight piece(s); ends: {', '.join(work.ends)}"
    if work.pulled:
        note += f"; pulled curve(s) {sorted(work.pulled)} to it"
    return StrokeRecord(index, "interior", "accepted", note, np.vstack(work.pre_image),
                        tuple(work.curve_ids), created, removed, tuple(sorted(work.pulled)),
                        tuple(work.ends), tuple(work.offsets), np.vstack(used))


def _snapped_end(net: PatchNetwork, snapped: tuple) -> _End:
    """The end found by :func:`_snap_end`, on edge e at parameter t, as an _End."""
    _, e, t, p = snapped
    ev = net.edges()[e]
    return _End(uv=ev.uv0 + t * (ev.uv1 - ev.uv0), xyz=p, snapped=True, edge=e, t=t)


def _placed(net: PatchNetwork, pts: FloatArray, snap: float, which: str) -> _End:
    """The end pts[0] on the current network: snapped when it is on a boundary, else free."""
    snapped = _snap_end(net, pts, snap, net.edge_segments())
    if snapped is not None and snapped[0] == 0:
        return _snapped_end(net, snapped)
    return _free_end(net, pts[0], which, snap)


def _add_open(net: PatchNetwork, old: PatchNetwork, pts: FloatArray, index: int, tol: Tolerances,
              snap: float, falloff: str, work: _Work) -> FloatArray:
    """One open stroke: snap/trim its ends, find its straight pieces, insert them in turn."""
    segs = net.edge_segments()
    first = _snap_end(net, pts, snap, segs)
    if first is not None:
        j, eid, t, p = first
        pts = np.vstack([p, pts[j + 1:]])
    last = _snap_end(net, pts[::-1], snap, segs)
    if last is not None:
        j, eid2, t2, p2 = last
        pts = np.vstack([pts[: len(pts) - 1 - j], p2])
    if len(pts) < 2 or np.linalg.norm(pts[-1] - pts[0]) < 1e-9:
        raise StrokeRejectedError("nothing is left of it after trimming its over-sketched ends")

    def end_of(snapped, q, which):
        if snapped is None:
            return _free_end(net, q, which, snap)
        return _snapped_end(net, snapped)

    start, end = end_of(first, pts[0], "first"), end_of(last, pts[-1], "last")
    breaks = _straight_pieces(net, pts, start.uv, end.uv, 0, len(pts) - 1, tol.param, snap)
    if breaks:
        # A gently bent pre-image can leave a later piece running along the extension of an
        # earlier one; then the whole stroke is taken as one straight piece instead.
        state = net.snapshot()
        marks = (len(work.ends), len(work.offsets), len(work.curve_ids), len(work.pre_image), set(work.pulled))
        try:
            _insert_pieces(net, old, pts, start, end, [0] + breaks + [len(pts) - 1], index, tol, snap,
                           falloff, work)
            return pts
        except StrokeRejectedError as err:
            if "runs along" not in str(err):
                raise
            net.restore(state)
            del work.ends[marks[0]:], work.offsets[marks[1]:], work.curve_ids[marks[2]:], work.pre_image[marks[3]:]
            work.pulled = marks[4]
    _insert_pieces(net, old, pts, start, end, [0, len(pts) - 1], index, tol, snap, falloff, work)
    return pts


def _insert_pieces(net: PatchNetwork, old: PatchNetwork, pts: FloatArray, start: _End, end: _End,
                   bounds: list, index: int, tol: Tolerances, snap: float, falloff: str, work: _Work) -> None:
    """Insert the straight pieces pts[bounds[k]:bounds[k+1]+1] one after the other."""
    for k in range(len(bounds) - 1):
        piece = pts[bounds[k]: bounds[k + 1] + 1]
        if k == 0 and len(bounds) == 2:
            s, e = start, end
        else:
            # The network has changed since the ends were found: place them again on it. A break
            # point lies on the previous piece, so it snaps there without trimming.
            s = start if k == 0 else _placed(net, piece, snap, "first")
            e = _placed(net, piece[::-1], snap, "last")
        work.ends.extend(["snapped" if x.snapped else "footpoint" for x in (s, e)])
        work.offsets.extend([x.offset for x in (s, e)])
        cid = net.new_curve_id("stroke", index)
        work.curve_ids.append(cid)
        _insert_piece(net, old, piece, s, e, cid, tol, snap, falloff, work)
