"""Insertion of one straight stroke piece into the network, and the subdivision it causes
(Qin & Wright section 3, steps (3)-(5) and (7)-(8); motion-sketch text, Fig. 5 cases a-d).

Holds the piece's curve (its pre-image line from end to end, extended at free ends, with each
stroke point's parameter along it), the nodes it gets where it crosses the network (step (4):
later strokes win, interior curves are pulled to the stroke), the chords that split the regions
it crosses (Fig. 5/6 (a), (b), (d)), and the split of a pentagon left by a chord across two
adjacent sides into two 4-sided regions (Fig. 6 (c)).
"""
from __future__ import annotations

import numpy as np

from .errors import StrokeRejectedError, StrokeRunsAlongCurveError
from .fairing import fair_stroke, pchip
from .fold_repair import follow_surface, split_lens
from .network import OUTER_CURVES, PatchNetwork
from .node_planning import crossing_nodes, line_crossings
from .stroke_ends import StrokeEnd, extension
from .strokes import cumulative_length
from .types import FloatArray, Polyline, Tolerances


def line_params(net: PatchNetwork, pts: FloatArray, uv0: FloatArray, uv1: FloatArray,
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
        f = net.footpoint(pts[i], slack=snap, near_uv=uv0 + chord[i] * d)
        at.append(float((f.uv - uv0) @ d / (d @ d)))
    at.append(1.0)
    at = np.array(at)
    if np.any(np.diff(at) <= 1e-9):
        return chord
    return pchip(chord[idx], at, chord)


def _piece_curve(net: PatchNetwork, pts: FloatArray, start: StrokeEnd, end: StrokeEnd, tol: Tolerances,
                 snap: float, falloff: str) -> tuple[Polyline, FloatArray, FloatArray]:
    """The curve of one straight piece pts (n, 3): free ends extended to the boundary of their
    region (steps (7)-(8)), every point given its parameter along the pre-image line, and the
    whole faired as one curve. Returns (polyline with params 0..1 along the line, p0, p1 (2,) the
    line's ends)."""
    if not np.linalg.norm(end.uv - start.uv) > 1e-6:
        raise StrokeRejectedError("its pre-image has no length (both ends map to the same surface point)")
    # (faired, the extensions are resampled with the stroke to the sag allowance below)
    ext0_uv, ext0_xyz = (np.empty((0, 2)), np.empty((0, 3))) if start.snapped else \
        extension(net, start, start.uv - end.uv, falloff)
    ext1_uv, ext1_xyz = (np.empty((0, 2)), np.empty((0, 3))) if end.snapped else \
        extension(net, end, end.uv - start.uv, falloff)
    main_uv = start.uv + np.outer(line_params(net, pts, start.uv, end.uv, snap), end.uv - start.uv)
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
        fair, _ = fair_stroke(xyz, tol.fair_mm, tol.sag_mm, original_at=at)
        run = cumulative_length(fair)
        t_fair = np.clip(pchip(run[at], t, run), 0.0, 1.0)
        t_fair[0], t_fair[-1] = 0.0, 1.0
        if np.all(np.diff(t_fair) > 0):
            xyz, t = fair, t_fair
    return Polyline(xyz, t), p0, p1


def _place_nodes(net: PatchNetwork, full: Polyline, p0: FloatArray, line: FloatArray, crossings: list,
                 snap: float,
                 merge_ends: tuple = (False, False)) -> tuple[list[tuple[float, int]], set, list, list]:
    """Step (4): the nodes along the line, (t, node id) in order, the ids of the interior
    curves pulled to the stroke (later strokes win): a crossed interior edge is split at the
    stroke's point, a node the stroke goes through is moved onto it; the misses: (stroke
    point (3,), stroke point - curve point (3,)) where it crossed a curve made from a stroke; and
    the ends merged into a curve they retrace (node_planning._plan_nodes, where merge_ends (first,
    last) allows it): (curve id, fraction of the pre-image line, "first" or "last")."""
    nodes: list[tuple[float, int]] = []
    pulled: set = set()
    misses: list = []
    plan = crossing_nodes(net, crossings, p0, line, snap, merge_ends)
    merged = []
    if plan and plan[0][0] > 1e-6:
        merged.append((net.edges()[crossings[0][1]].curve_id, plan[0][0], "first"))
    if plan and plan[-1][0] < 1.0 - 1e-6:
        merged.append((net.edges()[crossings[-1][1]].curve_id, 1.0 - plan[-1][0], "last"))
    for tk, nid, eid, se_k in plan:
        at_end = tk <= 1e-6 or tk >= 1 - 1e-6
        stroke_xyz = full.evaluate(tk)
        if nid < 0:
            curve = net.edges()[eid].curve_id
            pull = not at_end and curve not in OUTER_CURVES
            if pull and net.curve_info(curve)["kind"] == "stroke":
                misses.append((stroke_xyz, stroke_xyz - net.edges()[eid].polyline.evaluate(se_k)))
            nid = net.split_edge(eid, se_k, stroke_xyz, pull)
            if pull:
                pulled.add(curve)
        elif not at_end and not net.is_outer_node(nid):
            edges = net.edges()
            curves = {edges[k].curve_id for k in net.incident_edges(nid)} - set(OUTER_CURVES)
            if any(net.curve_info(c)["kind"] == "stroke" for c in curves):
                misses.append((stroke_xyz, stroke_xyz - net.node_xyz(nid)))
            net.move_node(nid, stroke_xyz)
            pulled.update(curves)
        nodes.append((tk, nid))
    if len(nodes) < 2:
        raise StrokeRejectedError("its pre-image is shorter than the node spacing")
    return nodes, pulled, misses, merged


def _add_chords(net: PatchNetwork, old: PatchNetwork, full: Polyline, nodes: list[tuple[float, int]],
                curve_id: int, sag_mm: float | None = None) -> None:
    """Steps (4)-(5): split each region the line crosses along the stroke between two of its
    nodes (Fig. 5/6 (a)-(d)); the chord's points are the stroke's, ramped onto its end nodes."""
    for (ta, na), (tb, nb) in zip(nodes[:-1], nodes[1:]):
        if na == nb:
            continue
        if net.has_edge(na, nb):
            raise StrokeRunsAlongCurveError(
                f"its pre-image runs along curve {net.edges()[net.edge_between(na, nb)[0]].curve_id}")
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
        made = net.add_chord(rid, na, nb, curve_id, poly)
        for new in made:
            make_three_or_four_sided(net, old, new, na, nb, sag_mm)
        for new in made:
            if new in net.region_ids:
                split_lens(net, old, new, sag_mm)


def insert_piece(net: PatchNetwork, old: PatchNetwork, pts: FloatArray, start: StrokeEnd, end: StrokeEnd,
                 curve_id: int, tol: Tolerances, snap: float, falloff: str,
                 merge_ends: tuple = (False, False)) -> tuple[FloatArray, set, list, list]:
    """Steps (3)-(5) for one straight piece pts (n, 3) from start to end: extend, cross, pull,
    subdivide, rebuild, as curve curve_id. `old` is the network before the stroke. Returns the
    pre-image line's ends (2, 2), the ids of the earlier curves pulled to the piece, its misses
    of the stroke curves it crossed and its ends merged into a curve they retrace (_place_nodes;
    merge_ends (first, last): which ends may be)."""
    full, p0, p1 = _piece_curve(net, pts, start, end, tol, snap, falloff)
    line = p1 - p0
    crossings = line_crossings(net, p0, p1)
    nodes, pulled, misses, merged = _place_nodes(net, full, p0, line, crossings, snap, merge_ends)
    _add_chords(net, old, full, nodes, curve_id, tol.made_sag_mm)
    return np.array([p0, p1]), pulled, misses, merged


def make_three_or_four_sided(net: PatchNetwork, old: PatchNetwork, rid: int, a: int, b: int,
                             sag_mm: float | None = None) -> None:
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
    poly = follow_surface(old, uv0, uv1, net.node_xyz(opposite), net.node_xyz(m), n, sag_mm)
    curve = net.new_curve_id("split")
    for new in net.add_chord(rid, opposite, m, curve, poly):
        if len(net.region_corner_ids(new)) not in (3, 4):
            raise StrokeRejectedError("subdividing would leave a region that is not 3- or 4-sided")
