"""Node planning of the progressive update (Qin & Wright section 3, steps (3)-(4)).

Holds where the straight pre-image line of a stroke piece meets the network (step (3): the edges
it crosses, hence the affected regions) and which node each crossing becomes, decided before
anything changes: a new node splitting the crossed edge (step (4)), or an existing node near the
crossing that the stroke goes through, so that strokes drawn through (nearly) one point meet there
instead of leaving near-duplicate nodes and sliver regions whose sub-patches fold.
"""
from __future__ import annotations

from typing import Optional

import numpy as np

from .errors import StrokeRejectedError, StrokeRunsAlongCurveError
from .network import PatchNetwork
from .preimage import segment_intersections
from .types import FloatArray

NODE_MERGE_UV = 2e-3
"""A crossing closer than this (in the unit square) along the pre-image line to the node before it
gets no node of its own."""

NODE_SNAP_UV = 0.03
"""A crossing closer than this to an end node of the crossed edge (in the unit square, about the
automatic snap distance on a typical sketch), and within the snap distance of it in 3D, goes
through that node: strokes drawn through (nearly) one point meet there, instead of leaving
near-duplicate nodes and sliver regions whose sub-patches fold. (0.02 until sketchgen seed base
61000: on sk_dome_0 four strokes drawn through the dome's top, crossing 2-3 % of the square apart,
left slivers whose wrinkle turned a face 91 deg from the truth; with 0.03 none, and the families
of seed bases 45000, 53000 and 61000 stay unfolded.)"""

NODE_SPACING_UV = 0.01
"""When going through nearby nodes clashes, a plan without one of them is taken if it leaves its
new nodes at least this far (unit square) from the nodes next to them; otherwise the stroke would
leave a sliver and is rejected. (Half of NODE_SNAP_UV while that was 0.02.)"""

Crossing = tuple
"""(t along the pre-image line, edge id, s along the edge) of one crossing."""

PlannedNode = tuple
"""(t along the pre-image line, node id or -1 for "split the edge at s", edge id, s)."""


def line_crossings(net: PatchNetwork, p0: FloatArray, p1: FloatArray) -> list[Crossing]:
    """Step (3): the crossings of the pre-image line p0 -> p1 (2,) with every edge, in order along
    the line. Rejects a line that runs along an edge, and one whose ends are not on edges."""
    line = p1 - p0
    length = float(np.linalg.norm(line))
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
            raise StrokeRunsAlongCurveError(f"its pre-image runs along curve {cid}")
    eps = 1e-9
    hit = ~parallel & (se >= -eps) & (se <= 1 + eps) & (tl >= -1e-7) & (tl <= 1 + 1e-7)
    crossings = sorted((float(tl[k]), int(ids[k]), float(np.clip(se[k], 0, 1))) for k in np.flatnonzero(hit))
    if not crossings or crossings[0][0] > 1e-6 or crossings[-1][0] < 1 - 1e-6:
        raise StrokeRejectedError("its pre-image does not end on a boundary (internal inconsistency)")
    return crossings


def crossing_nodes(net: PatchNetwork, crossings: list[Crossing], p0: FloatArray, line: FloatArray,
                   snap: float, merge_ends: tuple = (False, False)) -> list[PlannedNode]:
    """Where the pre-image line p0 + t * line meets the network, decided before anything changes.

    crossings : (t along the line, edge id, s along the edge), in order along the line
    Returns (t, node, edge id, s) in order along the line, one entry per node; node -1 means
    "split the edge at s". A crossing within NODE_SNAP_UV (pre-image) and snap (3D, along the
    crossed curve) of an end node of its edge goes through that node instead (see
    :func:`_plan_nodes`). When two such nodes clash (the stroke would run along the curve between
    them, or they are out of order along the line), one of them is not used: the one whose
    crossings then leave the wider node spacing, if that is at least NODE_SPACING_UV. Otherwise
    the stroke is rejected, as it would leave a sliver region; unless it only runs along a curve
    at an end that merge_ends (first, last) allows to merge, which then stops at the node where it
    leaves that curve (_plan_nodes(merge_ends=)): the stroke's own ends, not the break points where
    its straight pieces meet."""
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
        plan, clash, error = _plan_nodes(net, edges, crossings, near, p0, line)
        if error is None:
            return plan
        options = [(_spacing(net, edges, _plan_nodes(net, edges, crossings, without(n), p0, line)[0]), n)
                   for n in sorted(clash - exact)]     # (spacing without node n, n)
        gap, drop = max(options, default=(0.0, -1))
        if gap < NODE_SPACING_UV:
            if isinstance(error, StrokeRunsAlongCurveError) and any(merge_ends):
                plan, _, merged_error = _plan_nodes(net, edges, crossings, near, p0, line, merge_ends)
                if merged_error is None:
                    return plan
            raise error
        near = without(drop)


def _plan_nodes(net: PatchNetwork, edges: dict, crossings: list, near: dict, p0: FloatArray,
                line: FloatArray,
                merge_ends: tuple = (False, False)) -> tuple[list, set, Optional[StrokeRejectedError]]:
    """One plan for :func:`crossing_nodes` in which the existing nodes ``near`` (edge id ->
    (distance, node)) are used by their crossings. The stroke then passes through each such node,
    so every crossing of an edge ending there is that node too (a straight piece from the node
    meets such an edge nowhere else), and its t is the node's projection onto the line. The
    pre-image leaves the line by less than NODE_SNAP_UV there, and every region stays convex: the
    node already has curves on both sides of any line through it. Returns (plan, set(), None), or
    (the plan so far, the used nodes that clash, the error that rejects the stroke if no other
    plan is found). merge_ends (first, last): such an end of the line that runs along a curve into
    a used node stops at that node (the last resort of crossing_nodes before rejecting the stroke)."""
    via = {node for _, node in near.values()}
    plan: list[tuple[float, int, int, float]] = []
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
            return plan, {node}, _too_close()
        plan.append((t, node, eid, se))
    k = 0
    trimmed = (None, None)          # the curves the first and the last end were merged into
    while k < len(plan) - 1:
        (ta, na, ea, _), (tb, nb, eb, _) = plan[k], plan[k + 1]
        if tb <= ta:
            return plan, {na, nb} & via, _too_close()
        # The piece between them would run along an edge: one joining two used nodes, or the edge
        # a stroke end splits when it ends at the used node next to it.
        along = None
        if na >= 0 and nb >= 0 and net.has_edge(na, nb):
            along = net.edge_between(na, nb)[0]
        elif na < 0 <= nb and nb in (edges[ea].node0, edges[ea].node1):
            along = ea
        elif nb < 0 <= na and na in (edges[eb].node0, edges[eb].node1):
            along = eb
        if along is not None:
            # An end of the pre-image that runs along a curve into the node next to it retraces
            # that curve (an over-sketch of it, within the snap distance at both ends): the stroke
            # starts, or ends, at that node instead of being rejected (sketchgen: a short diagonal
            # drawn along an earlier one from near the corner to the middle).
            # (Node by node, while it keeps retracing the same curve.)
            curve = edges[along].curve_id
            if (merge_ends[0] and len(plan) > 2 and k == 0
                    and ((na < 0 and ta <= 1e-6) or trimmed[0] == curve)):
                plan, trimmed = plan[1:], (curve, trimmed[1])
                continue
            if (merge_ends[1] and len(plan) > 2 and k == len(plan) - 2
                    and ((nb < 0 and tb >= 1.0 - 1e-6) or trimmed[1] == curve)):
                plan, trimmed = plan[:-1], (trimmed[0], curve)
                continue
            return plan, {na, nb} & via, StrokeRunsAlongCurveError(
                f"its pre-image runs along curve {curve} near a node")
        k += 1
    return plan, set(), None


def _too_close() -> StrokeRejectedError:
    return StrokeRejectedError("its pre-image passes too close to an existing node")


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


