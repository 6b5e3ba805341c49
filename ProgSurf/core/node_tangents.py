"""One tangent for a stroke where it passes through a node of the stroke network.

A stroke crossing other strokes is cut into graph edges at its nodes (core.stroke_graph), and each
edge's curve is fitted on its own (cad.shared_edges.graph_curves). Two pieces of one smooth stroke
then meet at their node with a kink of a few degrees (the fits follow each piece's points, noise
included), and the four surfaces around a crossing of two such strokes each take their tangent
plane at that corner from a different pair of pieces: tangent continuity across a shared curve is
impossible there, and G1 mode left 1-3 deg at the ends of 16 of the 210 smooth shared sides of the
noisy TiGL helicopter.

Here each node a stroke passes through smoothly gets one direction, the faired stroke's chord
across it (over REACH_DELTA of the network's delta either side): both pieces' curves leave the node
along it, so their join is tangent-continuous and every surface at a crossing of two smooth strokes
has the plane of their two directions there. The direction depends on the faired stroke alone near
its node, not on how long its pieces are, so a stroke added elsewhere does not change it (the
surfaces it does not touch keep their curves).

A stroke that turns at its node by more than KINK_DEG (read over the same reach on each side) was
drawn with a corner there and gets no common direction.
"""
from __future__ import annotations

import numpy as np

from .continuity import KINK_ANGLE_DEG, unit
from .strokes import cumulative_length, point_at_length
from .types import FloatArray

REACH_DELTA = 0.5
"""The stroke's direction at a node is its chord over this many delta either side of the node."""
AGREE_DEG = 10.0
"""... and where both edges' polylines leave the node within this of that direction."""
LEAVE_SHARE = 0.1
"""A polyline's direction at its node is read at this share of its length (at most REACH_DELTA)."""
KINK_DEG = KINK_ANGLE_DEG
"""A stroke turning at a node by more than this (its chords on either side) is sharp there
(core.continuity.KINK_ANGLE_DEG, the rule for a stroke drawn with a kink)."""


def _leaves_along(points: FloatArray, direction: FloatArray, reach: float) -> bool:
    """Whether a polyline (n, 3) leaves its first point within AGREE_DEG of `direction`, read at
    LEAVE_SHARE of its length (at most `reach`)."""
    cum = cumulative_length(points)
    d = unit(point_at_length(points, min(LEAVE_SHARE * float(cum[-1]), reach), cum) - points[0])
    return bool(d.any()) and float(d @ direction) >= np.cos(np.radians(AGREE_DEG))


def node_tangents(graph, faired: list, arcs: dict, polylines: dict) -> dict:
    """{(graph edge id, end 0 or 1): (3,) unit direction of travel along the edge at that end}, for
    each end where the edge's stroke runs on into its next edge through the node, smoothly, and
    both edges' polylines leave the node along that direction (within AGREE_DEG).

    graph: core.stroke_graph.StrokeGraph; faired: per stroke its faired points (n, 3); arcs:
    core.objects._stroke_arcs (the graph's arc lengths carried onto the faired strokes);
    polylines: graph edge id -> its points (n, 3) (core.objects.edge_polylines)."""
    out: dict = {}
    reach = REACH_DELTA * graph.delta
    cos_kink = np.cos(np.radians(KINK_DEG))
    by_stroke: dict = {}
    for e in graph.edges:
        by_stroke.setdefault(e.stroke, []).append(e)
    for stroke, edges in by_stroke.items():
        edges.sort(key=lambda e: e.s0)
        src = faired[stroke]
        to_faired, cum = arcs[stroke]
        total = float(cum[-1])
        pairs = [(e, f) for e, f in zip(edges[:-1], edges[1:])
                 if e.node1 == f.node0 and abs(f.s0 - e.s1) <= 1e-9 * max(total, 1.0)]
        first, last = edges[0], edges[-1]
        length = float(cumulative_length(graph.strokes[stroke])[-1])
        # a ring (a closed stroke, its ends within delta of its seam node) runs on from its last
        # edge into its first through that node
        ring = (len(edges) > 1 and last.node1 == first.node0 and first.s0 <= graph.delta
                and length - last.s1 <= graph.delta)
        for e, f in pairs + ([(last, first)] if ring else []):
            a, b = float(to_faired(e.s1)), float(to_faired(f.s0))
            before = point_at_length(src, max(a - reach, 0.0), cum)
            at = 0.5 * (point_at_length(src, a, cum) + point_at_length(src, b, cum))
            after = point_at_length(src, min(b + reach, total), cum)
            din, dout = unit(at - before), unit(after - at)
            if not din.any() or not dout.any() or float(din @ dout) < cos_kink:
                continue
            t = unit(after - before)
            # the edges' points, cut to the node and eased, can leave it otherwise (a hook eased
            # away, a node beside the stroke): a curve held to the stroke's direction there
            # would turn back to its points within the fit tolerance, a crease
            if not (_leaves_along(polylines[e.id][::-1], -t, reach) and _leaves_along(polylines[f.id], t, reach)):
                continue
            out[(e.id, 1)] = t
            out[(f.id, 0)] = t
    return out


__all__ = ["AGREE_DEG", "KINK_DEG", "LEAVE_SHARE", "REACH_DELTA", "node_tangents"]
