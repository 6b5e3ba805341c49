"""Curves that two surfaces of a whole object share, fitted once (issue 18: "surfaces that share a
curve share that edge exactly").

Each graph edge of the stroke network (core.stroke_graph) bounds up to two surfaces. Fitted by each
surface as part of its own boundary side (cad.edges), the two fits differ by up to the fit
tolerance, and the shell between them holds only as far as the sewing tolerance reaches. Here each
graph edge is fitted ONCE (:func:`graph_curves`); every surface then takes the edges of its
boundary as exact pieces of those curves (:func:`outer_edges`): each boundary node of its network
(a corner, or where an interior stroke meets the boundary) is put on the curve at its nearest
point, and each boundary edge is the curve between its two nodes (the pieces of two or more curves
joined C0 where the edge runs over a node of the graph). The interior curves of the surface are
fitted to those node points (cad.edges.fit_edges(given=)), so each face is still an exact Coons
face of its four curves, and two surfaces on one graph edge meet on the very same curve.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from ..core.network_views import OUTER_CURVES
from ..core.types import FloatArray
from ._occ import Vector
from .curves import collapsed, constant_curve, curve_points, fit_points, join_side, unit_segment
from .edges import EDGE_FIT_FRACTION

DENSE_SPACING = 20.0
"""Each graph edge's points are fitted with points added along its segments at most this many fit
tolerances apart (_dense): 0.2 % of the sketch's diagonal at the default fit tolerance, a little
under the spacing the surfaces' sides have. A function of the tolerance alone, so that a curve is
the same whichever other surfaces are built with it (an edited sketch rebuilds only some)."""

SHORTEST = 1e-8
"""A piece of a graph curve shorter than this share of it (a node found a round-off before the
graph node where the next curve starts) is left out of a boundary edge: OCC cannot cut it."""

SAMPLES = 64
"""Points per graph curve for the first guess of a node's nearest point (then OCC's projection)."""


def graph_curves(polylines: dict, fit_mm: float, tangents: dict | None = None) -> dict:
    """graph edge id -> SharedCurve: a cubic Part.BSplineCurve on [0, 1] fitted to its points (n, 3) within
    EDGE_FIT_FRACTION of fit_mm, through its two end points (the graph's nodes) exactly; the
    parameter is the points' cumulative chord length. tangents: {(graph edge id, end 0 or 1): (3,)
    unit direction of travel} at the nodes its stroke runs through smoothly (core.node_tangents):
    the curve has that direction there, so two pieces of one stroke join tangent-continuously."""
    tangents = tangents or {}
    out = {}
    spacing = DENSE_SPACING * fit_mm
    for gid, pts in polylines.items():
        pts = _dense(np.asarray(pts, dtype=float), spacing)
        step = np.linalg.norm(np.diff(pts, axis=0), axis=1)
        total = float(step.sum())
        prm = np.concatenate([[0.0], np.cumsum(step)]) / total if total > 0 else np.linspace(0.0, 1.0, len(pts))
        prm[-1] = 1.0
        # the derivative's size is the chord length (the parameter's speed), its direction the node's
        derivs = {float(end): (np.asarray(tangents[(gid, end)], dtype=float) * total, None)
                  for end in (0, 1) if (gid, end) in tangents and total > 0}
        curve = fit_points(prm, pts, fit_mm * EDGE_FIT_FRACTION, {0.0: pts[0], 1.0: pts[-1]},
                           name=f"network curve {gid}", derivs=derivs or None, best_effort=True)
        out[gid] = SharedCurve(curve, total)
    return out


@dataclass(frozen=True)
class SharedCurve:
    """A graph edge's curve (Part.BSplineCurve on [0, 1], parameter in proportion to the chord
    length of its points) and that chord length, mm: a piece [t0, t1] of it stands for
    length * (t1 - t0) of the side it is part of, as the surface's own side parameter counts it
    (core.boundary.BoundaryLoop.params)."""

    curve: object
    length: float


def _dense(pts: FloatArray, spacing: float) -> FloatArray:
    """The polyline with points added along every segment longer than `spacing` (the vertices
    kept). A faired stroke's end cut to its node can leave one long segment and a sharp turn (a
    hook the graph shortened), and a short stroke may be a few points; the fit allows each vertex
    the sag of its chord (core.curve_fit), which at such a corner is the long segment's, while each
    surface samples its sides evenly and holds its faces to the sag of its own, short, chords
    (cad.analysis.fit_allowance)."""
    if len(pts) < 2 or not spacing > 0:
        return pts
    step = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    out = [pts[:1]]
    for a, b, length in zip(pts[:-1], pts[1:], step):
        k = max(int(np.ceil(length / spacing)), 1)
        out.append(a + np.outer(np.arange(1, k + 1) / k, b - a))
    dense = np.vstack(out)
    dense[-1] = pts[-1]
    return dense


class _Loop:
    """A surface's boundary as the graph curves in loop order: position lam = k + tau on side k
    (tau from 0 to 1 in the loop's direction; lam counts on past the last side, round again)."""

    def __init__(self, sides: Sequence[tuple], curves: dict) -> None:
        self.sides = [(curves[gid].curve, bool(rev)) for gid, rev in sides]
        self.lengths = [curves[gid].length for gid, _ in sides]
        tau = np.linspace(0.0, 1.0, SAMPLES)
        pts = [curve_points(c, 1.0 - tau if rev else tau) for c, rev in self.sides]
        # positions and points of the samples, round the loop twice (a node is searched ahead of
        # the one before it), and their arc length from the loop's start
        self.lam = np.concatenate([k + tau for k in range(2 * len(self))])
        self.points = np.vstack(pts + pts)
        step = np.r_[0.0, np.linalg.norm(np.diff(self.points, axis=0), axis=1)]
        step[np.arange(1, 2 * len(self)) * SAMPLES] = 0.0          # the sides meet at the graph's nodes
        self.arc = np.cumsum(step)
        self.length = float(self.arc[len(self) * SAMPLES - 1])

    def __len__(self) -> int:
        return len(self.sides)

    def arc_at(self, lam: float) -> float:
        return float(np.interp(lam, self.lam, self.arc))

    def lam_at(self, arc: float) -> float:
        return float(np.interp(arc, self.arc, self.lam))

    def locate(self, point: FloatArray, lo: float = 0.0, hi: float | None = None) -> float:
        """The loop position in [lo, hi] (default: the first lap) of the curve point nearest
        `point`: the nearest sample there, then OCC's projection on its side (on both sides when
        that sample is a graph node, the nearer kept), kept in [lo, hi]."""
        hi = float(len(self)) if hi is None else hi
        inside = np.flatnonzero((self.lam >= lo - 1e-12) & (self.lam <= hi + 1e-12))
        if not len(inside):
            return lo
        i = inside[int(np.argmin(np.linalg.norm(self.points[inside] - point, axis=1)))]
        at = float(self.lam[i])
        node = abs(at - round(at)) < 1e-12
        sides = [int(round(at)) - 1, int(round(at))] if node else [int(np.floor(at))]
        best, best_d = at, float(np.linalg.norm(self.points[i] - point))
        for k in sides:
            if k < 0 or k >= 2 * len(self):
                continue
            curve, rev = self.sides[k % len(self)]
            t = min(max(float(curve.parameter(Vector(*map(float, point)))), 0.0), 1.0)
            lam = k + (1.0 - t if rev else t)
            if abs(lam - at) >= 1.0 or not lo - 1e-12 <= lam <= hi + 1e-12:
                continue
            d = float(np.linalg.norm(np.array(tuple(curve.value(t)), dtype=float) - point))
            if d < best_d:
                best, best_d = lam, d
        return min(max(best, lo), hi)

    def point(self, lam: float) -> FloatArray:
        k = int(np.floor(lam))
        tau = lam - k
        if tau < 1e-12 and k > 0:                # a graph node: the end of the side before it
            k, tau = k - 1, 1.0
        curve, rev = self.sides[k % len(self)]
        return np.array(tuple(curve.value(1.0 - tau if rev else tau)), dtype=float)

    def piece(self, a: float, b: float):
        """The loop from position a forward to position b (b > a, at most one lap) as one curve on
        [0, 1]: a piece of one graph curve, or pieces of several joined C0 at the graph's nodes
        (each over its share of the chord length between them, SharedCurve)."""
        parts, shares, at = [], [], a
        while at < b - 1e-12:
            k = int(np.floor(at + 1e-12))
            end = min(b, k + 1.0)
            curve, rev = self.sides[k % len(self)]
            t0, t1 = max(at - k, 0.0), min(end - k, 1.0)
            at = end
            if t1 - t0 < SHORTEST:
                continue            # a sliver of a side at a graph node: the next piece starts there
            if rev:
                parts.append((unit_segment(curve, 1.0 - t1, 1.0 - t0), True))
            else:
                parts.append((unit_segment(curve, t0, t1), False))
            shares.append(self.lengths[k % len(self)] * (t1 - t0))
        if not parts:               # two nodes at one place: a point
            return constant_curve(self.point(a))
        if len(parts) == 1:
            seg, rev = parts[0]
            if rev:
                seg = seg.copy()
                seg.reverse()
                seg = unit_segment(seg, seg.FirstParameter, seg.LastParameter)
            return seg
        lengths = np.maximum(np.array(shares), 1e-300)
        breaks = np.concatenate([[0.0], np.cumsum(lengths)]) / lengths.sum()
        breaks[-1] = 1.0
        return join_side([s for s, _ in parts], [r for _, r in parts], breaks)


def _perimeter(uv) -> float:
    """Position (0..4) of a point of the unit square's boundary, counter-clockwise from (0, 0):
    bottom, right, top (backwards), left (backwards): the loop's direction (core.boundary)."""
    u, v = float(uv[0]), float(uv[1])
    if v <= 1e-12:
        return u
    if u >= 1.0 - 1e-12:
        return 1.0 + v
    if v >= 1.0 - 1e-12:
        return 3.0 - u
    return 4.0 - v


def outer_edges(network, sides: Sequence[tuple], curves: dict) -> tuple[dict, dict]:
    """The boundary of one surface's network as pieces of the graph curves (module docstring).

    network : the surface's PatchNetwork; sides: its cycle's ((graph edge id, reversed), ...) in
    loop order; curves: graph_curves. Returns (edge id -> Part.BSplineCurve on [0, 1], param 0 at
    node0, for every boundary edge; node id -> (3,) point, for every boundary node).

    The boundary nodes are taken round the unit square from the corner c0 (core.network), which
    runs the loop's way; each is looked for on the loop ahead of the one before it, near where the
    arc length of the network's boundary so far puts it (a loop may pass one place twice: two
    closed strokes drawn over each other)."""
    loop = _Loop(sides, curves)
    edges = {e.id: e for e in network.edges().values() if e.curve_id in OUTER_CURVES}
    uv, xyz, length = {}, {}, {}
    for e in edges.values():
        uv[e.node0], uv[e.node1] = e.uv0, e.uv1
        xyz.setdefault(e.node0, e.polyline.points[0])
        xyz.setdefault(e.node1, e.polyline.points[-1])
        length[e.id] = float(np.linalg.norm(np.diff(e.polyline.points, axis=0), axis=1).sum())
    order = sorted(uv, key=lambda n: _perimeter(uv[n]))
    # the network's boundary length from c0 to each node, along its outer edges
    by_pair = {frozenset((e.node0, e.node1)): e for e in edges.values()}
    run = [0.0]
    for a, b in zip(order, order[1:] + order[:1]):
        e = by_pair.get(frozenset((a, b)))
        run.append(run[-1] + (length[e.id] if e is not None else float(np.linalg.norm(xyz[b] - xyz[a]))))
    total = max(run[-1], 1e-300)
    window = 0.1 * loop.length

    def walk(start: float) -> tuple[dict, float]:
        """Every node's loop position, c0 at `start`, and how far the edges' middles then lie
        from the loop pieces the walk gives them (a wrong start for c0 shows there)."""
        where, prev = {order[0]: start}, start
        for nid, s in zip(order[1:], run[1:-1]):
            guess = loop.arc_at(start) + s / total * loop.length
            lo = max(loop.lam_at(guess - window), prev)
            hi = max(loop.lam_at(guess + window), lo)
            prev = where[nid] = loop.locate(np.asarray(xyz[nid], dtype=float), lo, hi)
        miss = 0.0
        for e in edges.values():
            mid = np.asarray(e.polyline.points[len(e.polyline.points) // 2], dtype=float)
            a, b, _ = span(e, where, start + len(loop))
            miss += float(np.linalg.norm(loop.point(loop.locate(mid, a, b)) - mid))
        return where, miss

    def span(e, where: dict, end: float) -> tuple[float, float, bool]:
        """(a, b, forward): boundary edge e runs over the loop from position a to b (a <= b; the edge
        back to c0 ends at `end`, c0's position one lap on); forward when node0 is at a."""
        i, j = position[e.node0], position[e.node1]
        forward = j == (i + 1) % len(order)
        first, last = (e.node0, e.node1) if forward else (e.node1, e.node0)
        return where[first], (where[last] if position[last] != 0 else end), forward

    position = {nid: i for i, nid in enumerate(order)}
    # c0 is where the loop's first side starts, but a loop may pass that point again (a closed
    # stroke): every place the loop passes it is tried, and the walk that fits the edges kept
    c0 = np.asarray(xyz[order[0]], dtype=float)
    near = [float(k) for k in range(len(loop)) if np.linalg.norm(loop.point(float(k)) - c0) <= 1e-6 * loop.length]
    starts = near or [loop.locate(c0)]
    where, _ = min((walk(st) for st in starts), key=lambda w: w[1])
    # a node a round-off from a graph node is that node (OCC cannot cut a piece of 1e-8 of a side)
    where = {nid: float(round(lam)) if abs(lam - round(lam)) < SHORTEST else lam for nid, lam in where.items()}
    start = where[order[0]]
    end = start + len(loop)
    nodes = {nid: loop.point(lam) for nid, lam in where.items()}
    out = {}
    for e in edges.values():
        if collapsed(e.polyline.points):
            out[e.id] = constant_curve(nodes[e.node0])      # the collapsed top of a 3-sided region
            continue
        a, b, forward = span(e, where, end)
        c = loop.piece(a, b)
        if not forward:
            c = c.copy()
            c.reverse()
            c = unit_segment(c, c.FirstParameter, c.LastParameter)
        out[e.id] = c
    return out, nodes


__all__ = ["SharedCurve", "graph_curves", "outer_edges"]
