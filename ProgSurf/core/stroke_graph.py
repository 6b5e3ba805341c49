"""The stroke network: a sketch's strokes as a graph of nodes and stroke pieces (issue 18, part 1).

A designer who draws a whole object draws the curves of all its surfaces at once; where curves
cross or nearly cross they share a point of the object. This module turns filtered strokes
(core.strokes.filter_stroke) into that graph, with one sketch-relative distance delta (the snap
distance of core.pipeline: SNAP_FRACTION of the sketch's diagonal), following the thresholds that
CASSIE (Yu et al., CHI 2021) publishes:

- crossings and near-crossings closer than delta become shared nodes (one per run of close
  segments; the closest pair of points of the run, their midpoint the node; a run that continues
  across a closed stroke's seam is one run: core.stroke_nodes.seam_twins);
- a stroke end within PROXIMITY x delta of another stroke becomes a T-node on that stroke (or a
  shared corner when it is near the other stroke's end); node candidates closer than delta merge,
  but two that would make one node of two places of a stroke merge only within a few times the
  gap the strokes leave there (core.stroke_nodes.merge_candidates), so that a feature smaller
  than delta, drawn precisely, keeps its nodes apart;
- a stroke that zigzags along another (stitching, a scribble) is left out (core.stroke_zigzags);
- a stroke lying within delta of a longer one along OVERSKETCH_COVER of its length is an
  over-sketch of it: merged (left out, recorded), unless it carries the curve on past the other
  by more than a hook (_tail); a stroke whose end runs along another over more than PROXIMITY x
  delta, or overlaps another's end head to head (_head_to_head), is trimmed where it leaves it,
  and joined there, unless the two strokes
  end together there and part steadily, the rulings of a cone at its tip: they meet at that apex
  (core.stroke_nodes.apex_meeting); where the other runs on well past the cut-away piece, what
  crosses that piece crosses the other instead (_off_cut_away);
- two strokes that run side by side, away from their ends, further apart than SIDE_GAP x delta
  (yet within delta) do not touch there: curves of one family drawn close together, a boom's
  guides (_side_by_side);
- stroke ends join the network where they stop near a stroke, stopped short of one, or meet
  other ends at one point; rings drawn with a gap at their seam are bridged (core.stroke_joins);
- an end piece beyond the stroke's last node no longer than HOOK x delta and HOOK_FRACTION of the
  stroke is a hook: removed; a longer one stays as a dangling edge to an end node of degree 1;
  an end piece that loops back to the node it left, no longer than HOOK_FRACTION of the stroke
  or lying along the stroke's own other part (a ring drawn on past its seam), is removed too.

Edges are the stroke pieces between consecutive nodes; their end points are the node points
exactly, so that edges meeting at a node meet there to round-off.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Sequence

import numpy as np
import numpy.typing as npt

from .stroke_nodes import (Links, NodeCandidates, apex_meeting, components, ends_in, merge_candidates, nearest_on,
                           seam_twins, segment_distances)
from .stroke_joins import (EXTEND, HOOK, HOOK_FRACTION, PROXIMITY, Boxes, bridged_ring, end_direction, end_joins,
                           ring_overlaps, stroke_piece)
from .stroke_zigzags import zigzags
from .strokes import chord_length, cumulative_length, point_at_length
from .types import FloatArray

OVERSKETCH_COVER = 0.8
"""A stroke within delta of a longer stroke along this fraction of its length is an over-sketch."""

HEAD_DEG = 30.0
"""Two strokes whose ends overlap, leaving them within this of opposite ways, are head to head
(_head_to_head)."""

SAME_PLACE = 1.5
"""Node candidates that attach to one place of a stroke within this many delta of each other are
one node (_one_place_one_node): a rough box's corner 1.07 delta apart (box_25006r). At 3 delta (the
reach of an end's extension) CASSIE 02-0-2 lost three strokes and 04-1-1 one: nodes 1.7-2.6 delta
apart on strokes drawn past each other are two corners of the sketch."""

SAME_ARC = 0.5
"""... or this many delta along it from its end (_one_place_one_node). Only from an end: two
crossings 0.47 delta apart along a profile of TiGL's clean helicopter, 0.16 delta from its end,
are two nodes (merged, it lost two surfaces)."""

SAME_ARC_ENDS = 1.0
"""... or this many delta, at most a hook's share (HOOK_FRACTION) of the strokes there, when the
node inside is made of stroke ends alone (no other stroke passes through it; _one_place_one_node):
a rough box's corner was the end of one edge and, 0.54 delta along it, the T where a second edge's
end met it (box_31009r). Two crossings (strokes passing through) 0.55 delta apart by a ring's seam
on TiGL's fuselage are two nodes; so are the ends of a VR lamp's stroke 1.3 delta long between a
corner and a T (10-2-1: merged, it and its neighbour were lost and a loop with them)."""

SIDE_GAP = 0.5
"""Two strokes that come no closer than this many delta, away from their ends, ..."""

SIDE_DEG = 30.0
"""... and run there within this of one direction are side by side, not touching (_side_by_side)."""


@dataclass(frozen=True)
class GraphNode:
    """A node of the stroke network.

    id    : index in StrokeGraph.nodes
    point : (3,) float, mm
    kind  : "crossing" (two or more strokes pass through), "T" (a stroke end on another stroke),
            "corner" (stroke ends meeting only), "end" (the free end of a dangling piece)
    """

    id: int
    point: FloatArray
    kind: str


@dataclass(frozen=True)
class GraphEdge:
    """A stroke piece between two nodes.

    points : (n, 3) float, n >= 2; points[0] is node0's point and points[-1] node1's, exactly
    stroke : the input stroke index it was cut from; s0 < s1 its arc-length range along that
             (filtered) stroke, in mm
    """

    id: int
    node0: int
    node1: int
    points: FloatArray
    stroke: int
    s0: float
    s1: float

    @property
    def length(self) -> float:
        return chord_length(self.points)

    def other(self, node: int) -> int:
        return self.node1 if node == self.node0 else self.node0

    def from_node(self, node: int) -> FloatArray:
        """The points oriented away from `node`: (n, 3)."""
        return self.points if node == self.node0 else self.points[::-1]


@dataclass(frozen=True)
class StrokeGraph:
    """The stroke network of a sketch.

    nodes   : GraphNode per node       edges : GraphEdge per edge
    delta   : the distance (mm) under which curves count as touching (places of one stroke
              closer than it can still be distinct nodes: core.stroke_nodes.merge_candidates)
    strokes : the (filtered) stroke polylines the graph was made from, in input order
    notes   : {stroke index: what became of it}: "merged into stroke k (over-sketch)", "hook of
              x mm removed at its start/end", "isolated (touches no other stroke)", ...
    merged  : {stroke index: the stroke it was merged into}
    """

    nodes: tuple
    edges: tuple
    delta: float
    strokes: tuple
    notes: dict = field(default_factory=dict)
    merged: dict = field(default_factory=dict)

    def incident(self) -> dict:
        """node id -> [edge ids] (an edge from a node to itself appears twice)."""
        out: dict = {n.id: [] for n in self.nodes}
        for e in self.edges:
            out[e.node0].append(e.id)
            out[e.node1].append(e.id)
        return out

    def degree(self, node: int) -> int:
        return sum((e.node0 == node) + (e.node1 == node) for e in self.edges)

    def edges_of_stroke(self, stroke: int) -> list:
        return [e for e in self.edges if e.stroke == stroke]


def _oversketched(strokes: list, lengths: list, delta: float) -> dict:
    """{stroke: the longer stroke it over-sketches}: within delta of it along OVERSKETCH_COVER of
    its length (measured at its points and chord midpoints)."""
    merged: dict = {}
    order = sorted(range(len(strokes)), key=lambda i: -lengths[i])
    boxes = Boxes(strokes)
    for rank, i in enumerate(order):
        if i in merged:
            continue
        near = boxes.close_to(boxes.lo[i], boxes.hi[i], delta)
        for j in order[rank + 1:]:
            if j in merged or not near[j]:
                continue
            pj = strokes[j]
            probe = np.vstack([pj, 0.5 * (pj[1:] + pj[:-1])])
            # a probe outside stroke i's box grown by delta is further than delta from it: when
            # too few lie inside, the distances cannot reach the cover (the margin covers round-off)
            reach = delta * (1.0 + 1e-9)
            inbox = np.all((probe >= boxes.lo[i] - reach) & (probe <= boxes.hi[i] + reach), axis=1)
            if np.mean(inbox) < OVERSKETCH_COVER:
                continue
            d, _ = nearest_on(probe, strokes[i])
            if np.mean(d <= delta) >= OVERSKETCH_COVER and not _tail(pj, d[:len(pj)] <= delta, delta, [
                    strokes[k] for k in range(len(strokes)) if k not in (i, j) and lengths[k] > 0.0]):
                merged[j] = i
    return merged


def _tail(stroke: FloatArray, close: np.ndarray, delta: float, others: list) -> bool:
    """Whether a stroke whose points are within delta of another where `close` holds leaves it at
    an end for longer than a hook (HOOK, HOOK_FRACTION): it carries the curve on past the other's
    end (a guide drawn again from 7 delta short of its tip, the first stroke reaching it) or off
    it. Merged, that piece was lost; a run trim keeps it (_run_trim). A piece that runs along one
    of the `others` (OVERSKETCH_COVER of it within delta: a short stroke joining two halves of a
    border) is no tail. (A shorter piece that carries the curve on is spliced onto the other:
    _carried_on.)"""
    if not close.any():
        return False
    cum = cumulative_length(stroke)
    first, last = int(np.argmax(close)), len(close) - 1 - int(np.argmax(close[::-1]))
    hook = min(HOOK * delta, HOOK_FRACTION * float(cum[-1]))
    for piece, length in ((stroke[:first + 1], float(cum[first])), (stroke[last:], float(cum[-1] - cum[last]))):
        if length > hook and not any(np.mean(nearest_on(piece, o)[0] <= delta) >= OVERSKETCH_COVER for o in others):
            return True
    return False


CARRY_DEG = 30.0
"""An over-sketch's end piece that leaves the stroke it was merged into at that stroke's end and
heads within this of the way that stroke ended carries it on (_carried_on)."""


def _carried_on(longer: FloatArray, over: FloatArray, delta: float) -> tuple[FloatArray, list]:
    """The longer stroke carried on by the end pieces of an over-sketch merged into it (within
    delta of it along OVERSKETCH_COVER of its length) that leave it at one of its ends, longer than
    delta, heading on the way it ended (within CARRY_DEG): [(at its start?, mm added)]. The
    over-sketch reached further along the curve than the stroke it was drawn over; merged without
    that piece, the curve stopped where the longer stroke did (a rough tube's ruling drawn in two
    strokes dangled 4.2 delta short of its rim, its over-sketch reaching 1.9 delta of it,
    tube_31004r; a body's guide 4.6 delta short of its tip, the over-sketch 2.8, body_33010r).
    The piece is moved to start at the longer stroke's end, the move fading out along it, so that
    it ends where it was drawn."""
    added: list = []
    for _ in range(2):                  # (one end, then perhaps the other)
        found = _carry_once(longer, over, delta)
        if found is None:
            break
        longer, at_start, mm = found
        added.append((at_start, mm))
    return longer, added


def _carry_once(longer: FloatArray, over: FloatArray, delta: float) -> tuple | None:
    """(the longer stroke carried on, at its start?, mm added) by the first end piece of `over`
    that carries it on (_carried_on), or None."""
    d, at = nearest_on(over, longer)
    close = d <= delta
    if not close.any():
        return None
    cum = cumulative_length(longer)
    total = float(cum[-1])
    first, last = int(np.argmax(close)), len(close) - 1 - int(np.argmax(close[::-1]))
    for piece, s in ((over[:first + 1][::-1], float(at[first])), (over[last:], float(at[last]))):
        go = piece[-1] - piece[0]
        size = float(np.linalg.norm(go))
        if len(piece) < 2 or chord_length(piece) <= delta or size <= 0.0:
            continue
        for s_end in (0.0, total):
            way = end_direction(longer, cum, s_end, delta)     # (outwards)
            if abs(s - s_end) > delta or way is None or float(go @ way) / size < np.cos(np.radians(CARRY_DEG)):
                continue
            end = longer[0] if s_end == 0.0 else longer[-1]
            beyond = piece[1:][np.asarray((piece[1:] - end) @ way > 0.0)]
            if len(beyond) < 1:
                continue
            w = cumulative_length(np.vstack([end, beyond]))[1:]
            if not w[-1] > 0.0:
                continue
            moved = beyond + (end - piece[0])[None] * (1.0 - w / w[-1])[:, None]
            longer = np.vstack([moved[::-1], longer]) if s_end == 0.0 else np.vstack([longer, moved])
            return longer, s_end == 0.0, float(w[-1])
    return None


def _crossings(strokes: list, live: list, delta: float, cands: NodeCandidates, trims: dict, cums: list,
               boxes: Boxes) -> None:
    """Crossings, near-crossings and runs along another stroke, pair by pair (module docstring);
    cums: the strokes' cumulative lengths, boxes: their Boxes."""
    tips = np.array([[i, *strokes[i][k]] for i in live for k in (0, -1)]).reshape(-1, 4)    # (stroke, x, y, z)
    for x, i in enumerate(live):
        near = boxes.close_to(boxes.lo[i], boxes.hi[i], delta)
        for j in live[x + 1:]:
            a, b = strokes[i], strokes[j]
            if not near[j]:
                continue
            dist, s, t = segment_distances(a, b)
            comps = components(dist <= delta)
            runs = [_is_run(cums[i], cums[j], rows, cols, delta) for rows, cols in comps]
            kept = seam_twins(comps, dist, np.linalg.norm(a[0] - a[-1]) <= delta,
                              np.linalg.norm(b[0] - b[-1]) <= delta, runs)
            spans = {k: (cums[i][comps[k][0].min()], cums[i][comps[k][0].max() + 1],
                         cums[j][comps[k][1].min()], cums[j][comps[k][1].max() + 1]) for k in kept}
            for k_comp in kept:
                (rows, cols), run = comps[k_comp], runs[k_comp]
                k = int(np.argmin(dist[rows, cols]))
                r, c = rows[k], cols[k]
                sa = cums[i][r] + s[r, c] * (cums[i][r + 1] - cums[i][r])
                sb = cums[j][c] + t[r, c] * (cums[j][c + 1] - cums[j][c])
                if (not any(ends_in(cums[i], rows) + ends_in(cums[j], cols)) and not _again(spans, k_comp)
                        and _side_by_side(a, b, cums[i], cums[j], sa, sb, float(dist[r, c]), delta)):
                    continue
                if (run and not apex_meeting(a, b, cums[i], cums[j], rows, cols, delta)) or _head_to_head(
                        a, b, cums[i], cums[j], rows, cols, delta, tips, (i, j)):
                    # a run along the other stroke: trim the stroke whose end lies in the run
                    _run_trim(i, j, rows, cols, s, t, cums, trims, cands, strokes, delta)
                    continue
                pa = point_at_length(a, sa, cums[i])
                pb = point_at_length(b, sb, cums[j])
                cands.add(0.5 * (pa + pb), [(i, sa), (j, sb)])


def _head_to_head(a: FloatArray, b: FloatArray, cum_a: FloatArray, cum_b: FloatArray, rows: np.ndarray,
                  cols: np.ndarray, delta: float, tips: FloatArray, pair: tuple) -> bool:
    """Whether a close component of two strokes (rows of a, cols of b) holds one end of each and the
    strokes leave those ends within HEAD_DEG of opposite ways: a curve drawn in two strokes, their
    ends overlapping by less than a run (_is_run). Such an overlap is trimmed as a run is
    (_run_trim): one joint. As a crossing, each end joined the other stroke apart, up to 2.3
    delta, and where a third curve crossed there the joint was three nodes and a sliver (objects
    benchmark tube_15002r). Not where other strokes end too (tips: (k, 4) rows of stroke and end
    point, those of strokes not in `pair` within 2 EXTEND x delta of the overlap's ends): the guides
    of a body meet at its tip, two from opposite sides overlapping so (trimmed, the tip's meeting
    lost 5 of 20 loops, body_1003r)."""
    ea, eb = ends_in(cum_a, rows), ends_in(cum_b, cols)
    if sum(ea) != 1 or sum(eb) != 1:
        return False
    here = 0.5 * ((a[0] if ea[0] else a[-1]) + (b[0] if eb[0] else b[-1]))
    other_ends = tips[(tips[:, 0] != pair[0]) & (tips[:, 0] != pair[1]), 1:]
    if len(other_ends) and np.min(np.linalg.norm(other_ends - here, axis=1)) <= 2 * EXTEND * delta:
        return False
    da = end_direction(a, cum_a, 0.0 if ea[0] else float(cum_a[-1]), delta)
    db = end_direction(b, cum_b, 0.0 if eb[0] else float(cum_b[-1]), delta)
    return da is not None and db is not None and float(da @ db) <= -np.cos(np.radians(HEAD_DEG))


def _again(spans: dict, k: int) -> bool:
    """Whether component k of two strokes' close pairs (spans: component -> its (a0, a1, b0, b1)
    arc-length ranges) shares a stretch of either stroke with another component: one stroke passes
    that place of the other twice or more (a wheel drawn round four times, passing a body stroke
    each time)."""
    a0, a1, b0, b1 = spans[k]
    return any(x != k and (min(o[1], a1) > max(o[0], a0) or min(o[3], b1) > max(o[2], b0))
               for x, o in spans.items())


def _side_by_side(a: FloatArray, b: FloatArray, cum_a: FloatArray, cum_b: FloatArray, sa: float, sb: float,
                  gap: float, delta: float) -> bool:
    """Whether two strokes whose closest approach (gap, at arc lengths sa, sb) lies between
    SIDE_GAP x delta and delta run side by side there: within SIDE_DEG of one direction over a
    delta either side. Two curves of a family drawn close together (the guides of the TiGL
    helicopter's tail boom, 0.5-1 delta apart over 1 m, meeting only at its tip) come in and out
    of delta along each other: each place would be a node pinching them together, and a sliver
    face between them. A near-crossing at an angle, or closer than SIDE_GAP x delta, touches."""
    if gap <= SIDE_GAP * delta:
        return False
    da = point_at_length(a, min(sa + delta, cum_a[-1]), cum_a) - point_at_length(a, max(sa - delta, 0.0), cum_a)
    db = point_at_length(b, min(sb + delta, cum_b[-1]), cum_b) - point_at_length(b, max(sb - delta, 0.0), cum_b)
    na, nb = float(np.linalg.norm(da)), float(np.linalg.norm(db))
    if na == 0.0 or nb == 0.0:
        return False
    return abs(float(da @ db)) / (na * nb) >= np.cos(np.radians(SIDE_DEG))


def _is_run(cum_a: FloatArray, cum_b: FloatArray, rows: np.ndarray, cols: np.ndarray, delta: float) -> bool:
    """Whether a component of close segment pairs (rows of a, cols of b) follows both strokes over
    more than 2 PROXIMITY delta: a crossing covers about 2 delta of each at most."""
    along_a = cum_a[rows.max() + 1] - cum_a[rows.min()]
    along_b = cum_b[cols.max() + 1] - cum_b[cols.min()]
    return min(along_a, along_b) > 2 * PROXIMITY * delta


def _run_trim(i: int, j: int, rows, cols, s, t, cums, trims: dict, cands: NodeCandidates, strokes: list,
              delta: float) -> None:
    """A stroke that runs along another over part of its length (an over-sketched run): the one
    whose end lies in the run is cut where the run leaves it and joined to the other there."""
    for me, other, mine, theirs, sp, tp in ((i, j, rows, cols, s, t), (j, i, cols, rows, t.T, s.T)):
        cum = cums[me]
        lo = cum[mine.min()]
        hi = cum[mine.max() + 1]
        total = cum[-1]
        if lo <= 1e-9 * total or hi >= total * (1 - 1e-9):
            at_start = lo <= 1e-9 * total
            keep_from = hi if at_start else lo
            p = point_at_length(strokes[me], keep_from, cum)
            d, s_other = nearest_on(p[None], strokes[other], cums[other])
            # the cut-away end lies within a hook (HOOK delta or HOOK_FRACTION of the longer
            # stroke's length, the larger) of an end of the other: both end there (guides
            # converging on a tip, one drawn in two pieces) or the run is that short; else the
            # other runs on well past it both ways (a curve drawn again over part of it).
            # (Measured towards the other's end beyond the cut-away end only, rough bodies lost
            # loops at their tips: 262 -> 256 of 288; of the other's length alone, 262.)
            cut_end = strokes[me][0] if at_start else strokes[me][-1]
            _, s_foot = nearest_on(cut_end[None], strokes[other], cums[other])
            beyond = min(s_foot[0], cums[other][-1] - s_foot[0])
            together = beyond <= max(HOOK * delta, HOOK_FRACTION * max(cums[other][-1], cums[me][-1]))
            trims.setdefault(me, []).append((at_start, keep_from, together))
            cands.add(0.5 * (p + point_at_length(strokes[other], s_other[0], cums[other])),
                      [(me, keep_from), (other, s_other[0])])
            return
    # a run in the middle of both: they touch along it; one node at its middle (by arc length on
    # stroke i: the middle pair of the component's list moved 17 mm with the strokes' directions,
    # fuzz benchmark 02-0-2)
    sa = 0.5 * (cums[i][rows.min()] + cums[i][rows.max() + 1])
    pa = point_at_length(strokes[i], sa, cums[i])
    _, sb = nearest_on(pa[None], strokes[j], cums[j])
    cands.add(0.5 * (pa + point_at_length(strokes[j], sb[0], cums[j])), [(i, sa), (j, float(sb[0]))])


def build_stroke_graph(strokes: Sequence[npt.ArrayLike], delta: float) -> StrokeGraph:
    """The stroke network of filtered strokes (each (n_i, 3), mm) with touching distance delta (mm).

    See the module docstring for the rules; every stroke ends up with edges, or a note saying why
    it has none."""
    arrays = [np.asarray(s, dtype=float).reshape(-1, 3) for s in strokes]
    notes: dict = {}
    bridged: dict = {}
    for i, a in enumerate(arrays):
        ring = bridged_ring(a, delta) if len(a) >= 3 else None
        if ring is not None:
            bridged[i] = f"ring closed across the gap of {np.linalg.norm(a[0] - a[-1]):.3g} mm at its seam"
            arrays[i] = ring
    cums = [cumulative_length(a) for a in arrays]
    lengths = [float(c[-1]) for c in cums]
    short = {i for i, L in enumerate(lengths) if L <= delta}
    for i in short:
        notes[i] = f"shorter ({lengths[i]:.3g} mm) than the touching distance {delta:.3g} mm: left out"
    merged = _oversketched([a if i not in short else a[:1].repeat(2, 0) for i, a in enumerate(arrays)],
                           [L if i not in short else 0.0 for i, L in enumerate(lengths)], delta)
    merged = {j: i for j, i in merged.items() if j not in short and i not in short}
    for j, i in merged.items():
        notes[j] = f"merged into stroke {i} (drawn over it)"
        arrays[i], added = _carried_on(arrays[i], arrays[j], delta)
        for at_start, mm in added:
            notes[j] += f"; it carries stroke {i} on {mm:.3g} mm past its {'start' if at_start else 'end'}"
        if added:
            cums[i] = cumulative_length(arrays[i])
            lengths[i] = float(cums[i][-1])
    live = [i for i in range(len(arrays)) if i not in short and i not in merged]
    zigzag = zigzags(arrays, live, delta, OVERSKETCH_COVER)
    for j, i in zigzag.items():
        notes[j] = (f"a zigzag along stroke {i} (stitching or a scribble: it touches that curve and "
                    f"leaves it again and again): it draws no curve of its own, left out")
    live = [i for i in live if i not in zigzag]

    cands = NodeCandidates()
    trims: dict = {}
    boxes = Boxes(arrays)
    _crossings(arrays, live, delta, cands, trims, cums, boxes)
    # a trimmed stroke keeps only the part out of its run along the other stroke
    keep_range = {i: [0.0, lengths[i]] for i in live}
    overlaps: dict = {}
    for i, cuts in trims.items():
        for at_start, s, together in cuts:
            if not together:
                overlaps.setdefault(i, set()).add(at_start)
            if at_start:
                keep_range[i][0] = max(keep_range[i][0], s)
            else:
                keep_range[i][1] = min(keep_range[i][1], s)
            notes.setdefault(i, f"over-sketched run along another stroke trimmed ({'start' if at_start else 'end'})")
        if keep_range[i][1] <= keep_range[i][0]:
            notes[i] = "drawn over other strokes from both ends, the runs overlapping: nothing of it is left"
    seams = ring_overlaps(arrays, live, delta, cands, keep_range, cums, boxes)
    for i, at_start in seams.items():
        overlaps.setdefault(i, set()).add(at_start)
        notes.setdefault(i, f"ring drawn on over its seam: the overlap at its {'start' if at_start else 'end'} cut away")
    cands = _off_cut_away(cands, keep_range, overlaps, delta)
    end_joins(arrays, live, delta, cands, keep_range, cums, boxes,
              frozenset((i, not at_start) for i, at_start in seams.items()))

    labels = merge_candidates(cands, arrays, delta)
    groups: dict = {}
    for k, lab in enumerate(labels):
        groups.setdefault(lab, []).append(k)
    node_points, node_attach = _one_place_one_node(list(groups.values()), cands, keep_range, lengths, delta)

    # per stroke: the nodes along it at their arc lengths (one attachment per node and place)
    along: dict = {i: [] for i in live}
    for nid, att in enumerate(node_attach):
        for i, s in att:
            lo, hi = keep_range[i]
            s = min(max(s, lo), hi)
            if any(n == nid and abs(s - s2) <= PROXIMITY * delta for n, s2 in along[i]):
                continue
            along[i].append((nid, s))

    nodes_kind: dict = {}
    out_edges: list = []
    looped: set = set()     # strokes with a piece left out as a loop back to its node
    extra_points: list = []
    for i in live:
        cum = cums[i]
        lo, hi = keep_range[i]
        marks = sorted(along[i], key=lambda x: x[1])
        # merge marks of different nodes that fall at (nearly) the same place: the first wins
        kept: list = []
        for nid, s in marks:
            if kept and abs(s - kept[-1][1]) <= 1e-9 * lengths[i] and kept[-1][0] != nid:
                continue
            kept.append((nid, s))
        marks = kept
        if not marks:
            notes.setdefault(i, "isolated: it touches no other stroke")
        # free end pieces: hooks are removed, longer pieces dangle from an end node
        ends = []
        if marks:
            first, last = marks[0][1], marks[-1][1]
            for piece_len, at_start in ((first - lo, True), (hi - last, False)):
                if piece_len <= 1e-9 * max(lengths[i], 1.0):
                    continue
                if piece_len <= min(HOOK * delta, HOOK_FRACTION * lengths[i]):
                    note = f"hook of {piece_len:.3g} mm removed at its {'start' if at_start else 'end'}"
                    notes[i] = notes[i] + "; " + note if i in notes else note
                    continue
                ends.append(at_start)
        else:
            ends = [True, False]
        for at_start in ends:
            nid = len(node_points) + len(extra_points)
            s = lo if at_start else hi
            extra_points.append(point_at_length(arrays[i], s))
            nodes_kind[nid] = "end"
            marks = [(nid, s)] + marks if at_start else marks + [(nid, s)]
        all_points = node_points + extra_points
        for (n0, s0), (n1, s1) in zip(marks[:-1], marks[1:]):
            if s1 - s0 <= 1e-9 * max(lengths[i], 1.0):
                continue
            pts = stroke_piece(arrays[i], cum, s0, s1, all_points[n0], all_points[n1])
            if n0 == n1 and (chord_length(pts) <= 2 * PROXIMITY * delta
                             or ((s0 <= lo or s1 >= hi) and (s1 - s0 <= HOOK_FRACTION * lengths[i]
                                                             or _along_itself(arrays[i], cum, s0, s1, delta)))):
                looped.add(i)
                continue    # (a loop back to its node at the stroke's end: a ring run on past its seam)
            out_edges.append((n0, n1, pts, i, s0, s1))

    all_points = node_points + extra_points
    edges, drawn_over = _merge_parallel(out_edges, delta)
    used_nodes = sorted({n for e in edges for n in (e[0], e[1])})
    renum = {n: k for k, n in enumerate(used_nodes)}
    strokes_at: dict = {}
    for n0, n1, _, i, _, _ in edges:
        strokes_at.setdefault(n0, set()).add(i)
        strokes_at.setdefault(n1, set()).add(i)
    deg: dict = {}
    for n0, n1, *_ in edges:
        deg[n0] = deg.get(n0, 0) + 1
        deg[n1] = deg.get(n1, 0) + 1
    nodes = []
    for n in used_nodes:
        if nodes_kind.get(n) == "end":
            kind = "end"
        elif deg[n] >= 4 or (deg[n] == 3 and len(strokes_at[n]) >= 2 and _passes_through(n, edges)):
            kind = "crossing" if deg[n] >= 4 else "T"
        else:
            kind = "corner"
        nodes.append(GraphNode(renum[n], np.array(all_points[n]), kind))
    graph_edges = tuple(GraphEdge(k, renum[n0], renum[n1], np.asarray(p), i, float(s0), float(s1))
                        for k, (n0, n1, p, i, s0, s1) in enumerate(edges))
    for i in live:
        if not any(e.stroke == i for e in graph_edges):
            note = _why_no_piece(i, drawn_over, looped)
            notes[i] = notes[i] + "; " + note if i in notes else note
    for i, text in bridged.items():
        notes[i] = text + (f"; {notes[i]}" if i in notes else "")
    return StrokeGraph(tuple(nodes), graph_edges, float(delta), tuple(arrays), notes, merged)


def _one_place_one_node(groups: list, cands: NodeCandidates, keep_range: dict, lengths: list,
                        delta: float) -> tuple[list, list]:
    """The nodes' points and attachments from the groups of node candidates that merge: groups
    that attach to one place of a stroke (after the attachment is moved into what is kept of the
    stroke, keep_range), within SAME_PLACE x delta of each other, are one node. Two nodes there
    make one stroke end in both, and one of them lost it (the first mark at a place is kept): a
    box's edge drawn as two strokes ended on a T-node made beside the corner on a third edge whose
    run past the corner was cut back to it; that end dangled 1.07 delta from the corner, and the
    box lost two of its faces (objects benchmark box_25006r). So are groups of which one attaches
    to a stroke's kept end and the other within SAME_ARC x delta of it: a corner of three edges
    whose ends all ran over or stopped short by a little was two nodes joined by a piece of one
    edge 1 mm long, and the loops beside it were not found (box_25004r, box_9001r, box_9011r: 5 of
    their 6 faces)."""
    points = [np.mean([cands.points[k] for k in ks], axis=0) for ks in groups]
    links = Links(len(groups))
    placed: dict = {}
    for g, ks in enumerate(groups):
        for k in ks:
            for i, s in cands.attach[k]:
                if i not in keep_range:
                    continue
                lo, hi = keep_range[i]
                placed.setdefault(i, []).append((min(max(s, lo), hi), g))

    def ends_reach(g: int, along: int) -> float:
        """How far along `along` from its end a node of group g may lie and be its end's node
        (SAME_ARC_ENDS): 0 unless every other stroke g attaches to ends there (none passes
        through); at most a hook's share (HOOK_FRACTION) of `along` and of each of them (a VR
        car's stroke 1.3 delta long across the corner of two others, vintage_car's stroke 2, would
        have moved by half its length)."""
        ats = [(i, s) for k in groups[g] for i, s in cands.attach[k] if i in keep_range and i != along]
        if not ats or any(keep_range[i][0] + 1e-9 * lengths[i] < s < keep_range[i][1] - 1e-9 * lengths[i]
                          for i, s in ats):
            return 0.0
        kept = [keep_range[i][1] - keep_range[i][0] for i, _ in ats] + [keep_range[along][1] - keep_range[along][0]]
        return min(SAME_ARC_ENDS * delta, HOOK_FRACTION * min(kept))

    for i, marks in placed.items():
        marks.sort()
        lo, hi = keep_range[i]
        tiny = 1e-9 * lengths[i]
        for (s0, g0), (s1, g1) in zip(marks[:-1], marks[1:]):
            if g0 != g1 and s1 - s0 <= tiny and np.linalg.norm(points[g0] - points[g1]) <= SAME_PLACE * delta:
                links.join(g0, g1)      # one place
        # one of them at the stroke's (kept) end and the other within SAME_ARC x delta of it: the
        # piece between them is a hook's (it would be removed as one). By group, not by neighbouring
        # marks: a group may attach at the end and again just inside it, beyond the other's mark
        # (box_31009r: 24.4, 24.9 and 25.6 mm of a 25.6 mm edge, the last two one corner's)
        for end, inside in ((lo, lambda s: s - lo), (hi, lambda s: hi - s)):
            at_end = {g for s, g in marks if inside(s) <= tiny}
            for s, g in marks if at_end else ():
                far = inside(s)
                if g in at_end or far > max(SAME_ARC, SAME_ARC_ENDS) * delta or (
                        far > SAME_ARC * delta and far > ends_reach(g, i)):
                    continue
                for g_end in at_end:
                    if np.linalg.norm(points[g] - points[g_end]) <= SAME_PLACE * delta:
                        links.join(g, g_end)
    node_points, node_attach = [], []
    for gs in links.groups():
        ks = [k for g in gs for k in groups[g]]
        node_points.append(np.mean([cands.points[k] for k in ks], axis=0))
        node_attach.append([a for k in ks for a in cands.attach[k]])
    return node_points, node_attach


def _along_itself(stroke: FloatArray, cum: FloatArray, s0: float, s1: float, delta: float) -> bool:
    """Whether the stroke's piece [s0, s1] lies within PROXIMITY x delta of the rest of the stroke
    along OVERSKETCH_COVER of it: a ring drawn on over its own start (a VR sketch's loop ran 56 mm,
    15.2 % of it, back over its start: kept as a loop on its seam node, the surface it bounded
    was lost)."""
    piece = stroke[(cum >= s0) & (cum <= s1)]
    rest = [stroke[cum < s0], stroke[cum > s1]]
    rest = [r for r in rest if len(r) >= 2]
    if len(piece) < 2 or not rest:
        return False
    d = np.min([nearest_on(piece, r)[0] for r in rest], axis=0)
    return float(np.mean(d <= PROXIMITY * delta)) >= OVERSKETCH_COVER


def _off_cut_away(cands: NodeCandidates, keep_range: dict, overlaps: dict, delta: float) -> NodeCandidates:
    """The node candidates without their attachments further than PROXIMITY x delta into a piece
    that a trim cut away from a stroke drawn over part of another (overlaps: stroke -> the ends,
    True for its start, cut where the other runs on well past it): a stroke crossing that piece
    crosses the other there too and gets its node on it; held at the cut, the attachment made an
    edge of the cut stroke beside the other. Where both end together (guides converging on a tip)
    it stays: the cut stroke's way to the tip. Candidates left joining one stroke by it are dropped."""
    out = NodeCandidates()
    reach = PROXIMITY * delta
    for point, att in zip(cands.points, cands.attach):
        kept = [(i, s) for i, s in att
                if not ((s < keep_range[i][0] - reach and True in overlaps.get(i, ()))
                        or (s > keep_range[i][1] + reach and False in overlaps.get(i, ())))]
        if len(kept) == len(att) or len({i for i, _ in kept}) >= 2:
            out.add(point, kept)
    return out


def _passes_through(n: int, edges: list) -> bool:
    """True when some stroke has two edges at node n (it runs through it)."""
    count: dict = {}
    for n0, n1, _, i, _, _ in edges:
        count[i] = count.get(i, 0) + (n0 == n) + (n1 == n)
    return any(c >= 2 for c in count.values())


def covered(points: FloatArray, poly: FloatArray, reach: float) -> bool:
    """Whether the points (k, 3) lie within reach of the polyline along OVERSKETCH_COVER of them:
    a piece drawn over another (_merge_parallel, core.twice_drawn)."""
    return float(np.mean(nearest_on(points, poly)[0] <= reach)) >= OVERSKETCH_COVER


def kept_first(stroke: int, points: FloatArray) -> tuple:
    """Sort key of parallel edges, the one kept first: that of the earliest stroke, of one stroke's
    the longest (a stroke drawn there and back between two nodes: the piece first along it was
    kept, and which that was followed the way it was drawn, 07-2-2's stroke 22)."""
    return stroke, -chord_length(points)


def _why_no_piece(i: int, drawn_over: dict, looped: set) -> str:
    """The note of live stroke i that has no edge left: its pieces lay over other strokes' between
    the same nodes (drawn_over: {stroke: strokes kept instead}), looped back to their node, or what
    the trims and hooks left of it touches one node alone."""
    if drawn_over.get(i):
        over = ", ".join(str(k) for k in sorted(drawn_over[i]))
        return (f"its pieces between nodes lie within the touching distance of stroke {over}'s between the "
                f"same nodes (drawn over it): merged into it")
    if i in looped:
        return "what is left of it between nodes loops back to the node it leaves: no piece of it is left"
    return "what is left of it meets the network at one place only: no piece of it is left between nodes"


def _merge_parallel(edges: list, delta: float) -> tuple[list, dict]:
    """Edges joining the same two nodes and lying within delta of each other (over-sketched runs
    between the same nodes) are one: the first by kept_first is kept. Returned in their order, with
    {stroke: the strokes whose edges were kept instead of one of its own}."""
    drawn_over: dict = {}
    kept: list = []
    for k in sorted(range(len(edges)), key=lambda k: kept_first(edges[k][3], edges[k][2])):
        n0, n1, pts = edges[k][0], edges[k][1], edges[k][2]
        dup = False
        for f in (edges[x] for x in kept):
            if {f[0], f[1]} != {n0, n1} or n0 == n1:
                continue
            if covered(pts, f[2], delta):
                dup = True
                if f[3] != edges[k][3]:
                    drawn_over.setdefault(edges[k][3], set()).add(f[3])
                break
        if not dup:
            kept.append(k)
    return [edges[k] for k in sorted(kept)], drawn_over
