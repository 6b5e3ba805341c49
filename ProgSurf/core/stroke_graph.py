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
- a stroke lying within delta of a longer one along OVERSKETCH_COVER of its length is an
  over-sketch of it: merged (left out, recorded); a stroke whose end runs along another over more
  than PROXIMITY x delta is trimmed where it leaves it, and joined there, unless the two strokes
  end together there and part steadily, the rulings of a cone at its tip: they meet at that apex
  (core.stroke_nodes.apex_meeting);
- two strokes that run side by side, away from their ends, further apart than SIDE_GAP x delta
  (yet within delta) do not touch there: curves of one family drawn close together, a boom's
  guides (_side_by_side);
- a stroke end that stopped short of another stroke, heading for it, is extended to it (EXTEND);
  two that stopped short of their corner meet there (_corner_gaps); a ring whose ends stop short
  of its seam, heading for each other, is bridged (_ring_bridge); three or more ends whose lines
  pass close to one point near them meet at that point (_meeting_ends: a cone's tip, a box's corner),
  and so does an end stopped short of it heading its way (a body's guide curving into its tip);
- an end piece beyond the stroke's last node no longer than HOOK x delta and HOOK_FRACTION of the
  stroke is a hook: removed; a longer one stays as a dangling edge to an end node of degree 1.

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
from .continuity import hermite_basis
from .strokes import chord_length, cumulative_length, point_at_length
from .types import FloatArray

PROXIMITY = 2.0
"""A stroke end this many delta from another stroke is joined to it (CASSIE: proximity 2 delta)."""

HOOK = 3.0
"""An end piece beyond the last node up to this many delta ... (CASSIE: hooks up to 3 delta)"""

HOOK_FRACTION = 0.15
"""... and up to this fraction of its stroke is a hook, removed (CASSIE: 15 % of a stroke)."""

OVERSKETCH_COVER = 0.8
"""A stroke within delta of a longer stroke along this fraction of its length is an over-sketch."""

EXTEND = 3.0
"""A stroke end that no stroke comes within PROXIMITY x delta of, but whose own direction leads
to one within this many delta (EXTEND_DEG), stopped short of it: it is joined there (a ring drawn
round with a gap at its seam, a stroke stopped short of the curve it runs to)."""

RING_GAP = 0.1
"""A stroke whose ends lie apart by at most this share of its length, each end's own direction
leading to the other end within RING_DEG, is a ring drawn with a gap at its seam: the gap is
bridged (_ring_bridge; the paper closes a boundary's gaps by extending its strokes). A hand
drawing round a 600 mm rim stops 5-8 % short, 2-5 delta, beyond the reach of EXTEND, and the rim
was left a dangling chain: a tube with one of its strips missing and "quality: ok"."""

RING_DEG = 25.0
"""... plus the angle a circle's end makes with the chord of such a gap (180 deg times the gap's
share of the length: 11 deg for a gap of 6 %), the rest the hand's (both ends: a C whose ends
point past each other, or one end only, is not closed). Without that share, a rough rim 6 % short
whose end ran 35 deg off the gap stayed open (body_7011r)."""

MEET_ENDS = 3
"""At least this many stroke ends (of as many strokes) that lie within EXTEND x delta of one another,
near no other stroke's middle, and whose lines pass within delta of one point, meet at that point
(_meeting_ends): a cone's rulings drawn to its tip, a box's three edges to their corner, each
stopping short or running over by a few delta. Taken two at a time (T-nodes, corner gaps) they made
two or three nodes round the tip, and the loops between them were slivers or missing."""

CORNER_MISS = 1.0
"""Two free ends stopped short of their corner (_corner_gaps) meet there when their lines pass within
this many delta of each other (the lines of three or more ends, _meeting_ends, within delta of one
point): at 0.5 a rough hand's grid corners stayed open, the end directions over their last delta
skew by the drawing's jitter and drift (objects benchmark grid_1004r: lines 0.54 and 0.79 delta
apart, ends 2.2 delta apart)."""

LATE_DEG = 45.0
"""A stroke end that stopped short of a meeting of ends (MEET_ENDS), within EXTEND x delta of its
point, joins it when its direction (its last delta) points within this of the point."""

EXTEND_DEG = 15.0
"""How far off a stroke end's direction (its last delta) the curve it stopped short of may lie."""


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


class _Boxes:
    """The strokes' bounding boxes, found once, so that the pair tests (two strokes, or a stroke end
    and a stroke, cannot touch when their boxes lie further apart than the margin) are one
    vectorised comparison per stroke instead of two box computations per pair."""

    def __init__(self, strokes: list) -> None:
        self.lo = np.array([s.min(axis=0) for s in strokes]).reshape(-1, 3)
        self.hi = np.array([s.max(axis=0) for s in strokes]).reshape(-1, 3)

    def close_to(self, lo: FloatArray, hi: FloatArray, margin: float) -> np.ndarray:
        """(n_strokes,) bool: the strokes whose box comes within `margin` of the box [lo, hi]."""
        return np.all(lo - margin <= self.hi, axis=1) & np.all(self.lo - margin <= hi, axis=1)


def _oversketched(strokes: list, lengths: list, delta: float) -> dict:
    """{stroke: the longer stroke it over-sketches}: within delta of it along OVERSKETCH_COVER of
    its length (measured at its points and chord midpoints)."""
    merged: dict = {}
    order = sorted(range(len(strokes)), key=lambda i: -lengths[i])
    boxes = _Boxes(strokes)
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
            if np.mean(d <= delta) >= OVERSKETCH_COVER:
                merged[j] = i
    return merged


def _crossings(strokes: list, live: list, delta: float, cands: NodeCandidates, trims: dict) -> None:
    """Crossings, near-crossings and runs along another stroke, pair by pair (module docstring)."""
    cums = [cumulative_length(s) for s in strokes]
    boxes = _Boxes(strokes)
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
                if run and not apex_meeting(a, b, cums[i], cums[j], rows, cols, delta):
                    # a run along the other stroke: trim the stroke whose end lies in the run
                    _run_trim(i, j, rows, cols, s, t, cums, trims, cands, strokes)
                    continue
                pa = point_at_length(a, sa, cums[i])
                pb = point_at_length(b, sb, cums[j])
                cands.add(0.5 * (pa + pb), [(i, sa), (j, sb)])


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


def _run_trim(i: int, j: int, rows, cols, s, t, cums, trims: dict, cands: NodeCandidates, strokes: list) -> None:
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
            trims.setdefault(me, []).append((at_start, keep_from))
            p = point_at_length(strokes[me], keep_from, cum)
            d, s_other = nearest_on(p[None], strokes[other], cums[other])
            cands.add(0.5 * (p + point_at_length(strokes[other], s_other[0], cums[other])),
                      [(me, keep_from), (other, s_other[0])])
            return
    # a run in the middle of both: they touch along it; one node at its middle
    k = len(rows) // 2
    r, c = rows[k], cols[k]
    sa = cums[i][r] + s[r, c] * (cums[i][r + 1] - cums[i][r])
    sb = cums[j][c] + t[r, c] * (cums[j][c + 1] - cums[j][c])
    cands.add(0.5 * (point_at_length(strokes[i], sa, cums[i]) + point_at_length(strokes[j], sb, cums[j])),
              [(i, sa), (j, sb)])


def _meeting_ends(strokes: list, cums: dict, live: list, delta: float, cands: NodeCandidates,
                  boxes: "_Boxes") -> set:
    """Groups of MEET_ENDS or more stroke ends that meet at one point (MEET_ENDS): one node
    candidate each, at the point nearest to the ends' lines (each stroke attached at its place
    nearest that point: an end that ran over it is cut back there, a hook; one that ran over it
    further than a hook is cut, HOOK and HOOK_FRACTION, is not one of them: the two halves of a
    curve drawn in two overlapping strokes, where a third ends). An end that stopped short of such a
    point within EXTEND x delta, heading within LATE_DEG of it, joins it too. Strokes no longer
    than 4 EXTEND x delta and closed ones take no part. Returns the (stroke, end arc length) of the
    ends joined."""
    reach = EXTEND * delta
    closed = {i for i in live if np.linalg.norm(strokes[i][0] - strokes[i][-1]) <= PROXIMITY * delta}
    ends = []
    for i in live:
        total = float(cums[i][-1])
        if total <= 4 * reach or i in closed:
            continue        # short strokes and closed ones: the other rules
        for s_end, p in ((0.0, strokes[i][0]), (total, strokes[i][-1])):
            d = _end_direction(strokes[i], cums[i], s_end, delta)
            if d is None:
                continue
            # an end beside another stroke's middle (further from its ends than two reaches: one
            # may run over the meeting point by a reach; a closed stroke is all middle) is a
            # T-node, not one of a meeting of ends
            middle = False
            near = boxes.close_to(p, p, PROXIMITY * delta)
            for j in live:
                if j == i or not near[j]:
                    continue
                dist, sj = nearest_on(p[None], strokes[j], cums[j])
                if dist[0] <= PROXIMITY * delta and (min(sj[0], cums[j][-1] - sj[0]) > 2 * reach or j in closed):
                    middle = True
                    break
            if not middle:
                ends.append((i, s_end, p, d))
    if len(ends) < MEET_ENDS:
        return set()
    pts = np.array([e[2] for e in ends])
    links = Links(len(ends))
    for a, b in zip(*np.nonzero(np.triu(np.linalg.norm(pts[:, None] - pts[None], axis=2) <= 2 * reach, 1))):
        if ends[a][0] != ends[b][0]:        # (both within reach of one point)
            links.join(a, b)
    done: set = set()
    for group in links.groups():
        # one end per stroke: the one nearer the group (a stroke drawn out from it and back)
        centre = pts[group].mean(axis=0)
        ks = [min((k for k in group if ends[k][0] == i), key=lambda k: float(np.linalg.norm(pts[k] - centre)))
              for i in sorted({ends[k][0] for k in group})]
        x, places = None, {}
        while len(ks) >= MEET_ENDS:
            # the point nearest to the ends' lines (least squares); every line must pass within
            # delta of it, every end lie within reach and have run past it no further than a hook
            # is cut (arc length): else the end furthest off is left out
            a_sum, b_sum = np.zeros((3, 3)), np.zeros(3)
            for k in ks:
                _, _, p, d = ends[k]
                m = np.eye(3) - np.outer(d, d)
                a_sum += m
                b_sum += m @ p
            if np.linalg.cond(a_sum) > 1e6:
                break
            x = np.linalg.solve(a_sum, b_sum)
            off = []
            for k in ks:
                i, s_end, p, d = ends[k]
                _, s_near = nearest_on(x[None], strokes[i], cums[i])
                places[k] = float(s_near[0])
                past = abs(places[k] - s_end) if float(d @ (x - p)) < 0.0 else 0.0
                off.append(max(float(np.linalg.norm((np.eye(3) - np.outer(d, d)) @ (x - p))) / delta,
                               float(np.linalg.norm(x - p)) / reach,
                               past / min(HOOK * delta, HOOK_FRACTION * float(cums[i][-1]))))
            if max(off) <= 1.0:
                break
            ks = [k for k, o in zip(ks, off) if o < max(off)]
            x = None
        if x is None or len(ks) < MEET_ENDS:
            continue
        # an end that stopped short of the meeting, within reach of it and heading its way (within
        # LATE_DEG: a body's guide curves into its tip, so its line misses the tip by more than
        # delta) joins it too; left out, it dangled beside the tip and the loops there merged.
        # (Such an end lies within 2 reach of the members' ends, so it is one of the group's.)
        members = {ends[k][0] for k in ks}
        late = {}
        for k in group:
            i, s_end, p, d = ends[k]
            if i in members or i in late:
                continue
            to_x = x - p
            dist = float(np.linalg.norm(to_x))
            if delta < dist <= reach and float(d @ to_x) >= np.cos(np.radians(LATE_DEG)) * dist:
                late[i] = s_end
        if not late and max(float(np.linalg.norm(x - ends[k][2])) for k in ks) <= delta:
            continue        # (ends drawn to within delta of the point: they touch there, the other rules join them)
        attach = []
        for k in ks:
            i, s_end, _, _ = ends[k]
            attach.append((i, places[k] if abs(places[k] - s_end) <= reach else s_end))
            done.add((i, s_end))
        for i, s_end in late.items():
            attach.append((i, s_end))
            done.add((i, s_end))
        # the places where these strokes touch one another near the meeting (the crossings of ends
        # run over it, an end passing another) are that meeting: left to it alone (a second
        # candidate on one of their ends made a second node beside it, and a sliver between)
        place = dict(attach)
        end_of = {ends[k][0]: ends[k][1] for k in ks}
        end_of.update(late)

        def cut(i: int, sc: float) -> bool:
            """On stroke i's piece past the meeting: cut away."""
            return i in place and (sc < place[i] - 1e-9 if end_of[i] == 0.0 else sc > place[i] + 1e-9)

        def at_meeting(i: int, sc: float) -> bool:
            """Cut away, or within 2 delta of the meeting on stroke i."""
            return i in place and (cut(i, sc) or abs(sc - place[i]) <= 2 * delta)

        def late_end(i: int, sc: float) -> bool:
            """At the end of a stroke that joined the meeting late: its end is the meeting (where
            it passes the strokes converging there, it does not touch them)."""
            return i in late and abs(sc - late[i]) <= 2 * delta

        keep = [c for c in range(len(cands.points))
                if not (np.linalg.norm(cands.points[c] - x) <= 2 * reach
                        and (all(at_meeting(i, sc) for i, sc in cands.attach[c])
                             or any(cut(i, sc) or late_end(i, sc) for i, sc in cands.attach[c])))]
        cands.points[:] = [cands.points[c] for c in keep]
        cands.attach[:] = [cands.attach[c] for c in keep]
        cands.add(x, attach)
    return done


def _end_joins(strokes: list, live: list, delta: float, cands: NodeCandidates, keep: dict) -> None:
    """T-nodes and corners: each stroke end within PROXIMITY x delta of another stroke (or of its
    own other end, for a closed stroke) is joined to its nearest point there; ends that meet at one
    point (_meeting_ends) are joined there first. keep: stroke -> [lo, hi], the arc lengths of the
    part a trim leaves (an over-sketched run's cut-away piece joins nothing: the stroke it ran
    along lies there too)."""
    reach = PROXIMITY * delta
    boxes = _Boxes(strokes)
    cums = {i: cumulative_length(strokes[i]) for i in live}
    met = _meeting_ends(strokes, cums, live, delta, cands, boxes)
    free = []
    for i in live:
        total = chord_length(strokes[i])
        closes = total > 4 * reach and np.linalg.norm(strokes[i][0] - strokes[i][-1]) <= reach
        for s_end, p in ((0.0, strokes[i][0]), (total, strokes[i][-1])):
            if (i, 0.0 if s_end == 0.0 else float(cums[i][-1])) in met:
                continue
            best = None
            near = boxes.close_to(p, p, reach)
            for j in live:
                if j == i or not near[j]:
                    continue
                d, sj = _nearest_kept(p, strokes[j], cums[j], keep[j])
                if d <= reach and (best is None or d < best[0]):
                    best = (d, j, sj)
            if best is None and not closes:
                direction = _end_direction(strokes[i], cums[i], s_end, delta)
                best = _extension(strokes, cums, i, s_end, direction, live, boxes, delta)
                if best is not None:
                    _, j, sj = best
                    cands.add(point_at_length(strokes[j], sj, cums[j]), [(i, s_end), (j, sj)])
                    continue
                free.append((i, s_end, p, direction))
            if best is not None:
                _, j, sj = best
                cands.add(0.5 * (p + point_at_length(strokes[j], sj, cums[j])), [(i, s_end), (j, sj)])
        if closes:
            cands.add(0.5 * (strokes[i][0] + strokes[i][-1]), [(i, 0.0), (i, total)])
    _corner_gaps(free, delta, cands)


def _nearest_kept(p: FloatArray, stroke: FloatArray, cum: FloatArray, kept: list) -> tuple[float, float]:
    """(distance, arc length) of the point of a stroke's kept part [lo, hi] nearest p (3,)."""
    lo, hi = kept
    d, s = nearest_on(p[None], stroke, cum)
    if lo - 1e-9 <= s[0] <= hi + 1e-9:
        return float(d[0]), float(s[0])
    piece = _piece(stroke, cum, lo, hi, point_at_length(stroke, lo, cum), point_at_length(stroke, hi, cum))
    d, s = nearest_on(p[None], piece)
    return float(d[0]), lo + float(s[0])


def _end_direction(stroke: FloatArray, cum: FloatArray, s_end: float, delta: float) -> FloatArray | None:
    """The unit direction a stroke leaves by at its end s_end (over its last delta, at most half
    of it), or None."""
    total = float(cum[-1])
    p = point_at_length(stroke, s_end, cum)
    back = point_at_length(stroke, min(delta, 0.5 * total) if s_end == 0.0 else max(total - delta, 0.5 * total), cum)
    d = p - back
    size = float(np.linalg.norm(d))
    return d / size if size > 0 else None


def _ring_bridge(stroke: FloatArray, delta: float) -> FloatArray | None:
    """The points (m, 3) that close a ring drawn with a gap at its seam (RING_GAP, RING_DEG): a
    cubic Hermite arc from its end, leaving in the end's direction, to its start (the last point),
    arriving in the start's; None when the stroke is no such ring or its ends are within the
    closing reach (PROXIMITY x delta: closed as they are)."""
    cum = cumulative_length(stroke)
    total = float(cum[-1])
    gap = stroke[0] - stroke[-1]
    size = float(np.linalg.norm(gap))
    if not (PROXIMITY * delta < size <= RING_GAP * total and total > 4 * PROXIMITY * delta):
        return None
    leave_end = _end_direction(stroke, cum, total, delta)
    leave_start = _end_direction(stroke, cum, 0.0, delta)
    if leave_end is None or leave_start is None:
        return None
    # a circle's end runs off the chord of a gap of share f of it by 180 f deg; RING_DEG on top
    cos = np.cos(np.radians(RING_DEG + 180.0 * size / total))
    if float(leave_end @ gap) < cos * size or float(-(leave_start @ gap)) < cos * size:
        return None
    step = total / max(len(stroke) - 1, 1)      # (the mean: repeated points leave the median at 0)
    t = np.linspace(0.0, 1.0, min(max(int(np.ceil(size / step)), 2), len(stroke)) + 1)[1:]
    return hermite_basis(t) @ np.array([stroke[-1], size * leave_end, -size * leave_start, stroke[0]])


def _corner_gaps(free: list, delta: float, cands: NodeCandidates) -> None:
    """Two free stroke ends (no stroke near either, nor ahead of it) whose directions lead, each
    within EXTEND x delta, to one place where they pass within CORNER_MISS x delta of each other: two strokes
    that both stopped short of the corner they make. They meet at that place (the paper's closing
    extends such a gap). The closest pairs first; an end joins once."""
    reach = EXTEND * delta
    pairs = []
    for x in range(len(free)):
        i, si, p, d = free[x]
        for y in range(x + 1, len(free)):
            j, sj, q, e = free[y]
            if i == j or d is None or e is None or np.linalg.norm(p - q) > reach:
                continue
            # closest approach of the rays p + a d and q + b e
            w = p - q
            c = float(d @ e)
            den = 1.0 - c * c
            if den < 1e-6:
                continue
            a = (c * float(e @ w) - float(d @ w)) / den
            b = (float(e @ w) - c * float(d @ w)) / den
            if not (0.0 <= a <= reach and 0.0 <= b <= reach):
                continue
            gap = float(np.linalg.norm((p + a * d) - (q + b * e)))
            if gap <= CORNER_MISS * delta:
                pairs.append((a + b, x, y, 0.5 * ((p + a * d) + (q + b * e))))
    used: set = set()
    for _, x, y, point in sorted(pairs, key=lambda t: t[0]):
        if x in used or y in used:
            continue
        used |= {x, y}
        cands.add(point, [(free[x][0], free[x][1]), (free[y][0], free[y][1])])


def _extension(strokes: list, cums: dict, i: int, s_end: float, d: FloatArray | None, live: list,
               boxes: "_Boxes", delta: float) -> tuple | None:
    """(distance, stroke j, arc length on j) of the nearest stroke point ahead of stroke i's end at
    s_end along the end's own direction d (_end_direction; None: no direction, no extension):
    within EXTEND x delta of the end and EXTEND_DEG of that direction (a delta / 4 aside allowed for
    the strokes' noise); on stroke i itself only further than 4 x EXTEND x delta from the end along
    it. None when there is none."""
    if d is None:
        return None
    p = strokes[i][0] if s_end == 0.0 else strokes[i][-1]
    reach = EXTEND * delta
    near = boxes.close_to(p, p, reach)
    best = None
    for j in live:
        if not near[j]:
            continue
        step = 0.25 * delta
        s = np.arange(0.0, float(cums[j][-1]) + step, step)
        s = np.minimum(s, cums[j][-1])
        if j == i:
            s = s[np.abs(s - s_end) > 4 * reach]
            if not len(s):
                continue
        q = point_at_length(strokes[j], s, cums[j])
        v = q - p
        along = v @ d
        aside = np.linalg.norm(v - along[:, None] * d, axis=1)
        ok = (along > 0) & (along <= reach) & (aside <= along * np.tan(np.radians(EXTEND_DEG)) + 0.25 * delta)
        if ok.any():
            # the place closest to the end's line of sight, then its foot on the stroke
            k = int(np.flatnonzero(ok)[np.argmin(aside[ok] / along[ok])])
            _, foot = nearest_on((p + along[k] * d)[None], strokes[j], cums[j])
            if best is None or along[k] < best[0]:
                best = (float(along[k]), j, float(foot[0]))
    return best


def _piece(stroke: FloatArray, cum: FloatArray, s0: float, s1: float, p0: FloatArray, p1: FloatArray) -> FloatArray:
    """The stroke between arc lengths s0 < s1, its ends replaced by the node points p0, p1."""
    inner = stroke[(cum > s0) & (cum < s1)]
    return np.vstack([p0, inner, p1])


def build_stroke_graph(strokes: Sequence[npt.ArrayLike], delta: float) -> StrokeGraph:
    """The stroke network of filtered strokes (each (n_i, 3), mm) with touching distance delta (mm).

    See the module docstring for the rules; every stroke ends up with edges, or a note saying why
    it has none."""
    arrays = [np.asarray(s, dtype=float).reshape(-1, 3) for s in strokes]
    notes: dict = {}
    bridged: dict = {}
    for i, a in enumerate(arrays):
        bridge = _ring_bridge(a, delta) if len(a) >= 3 else None
        if bridge is not None:
            bridged[i] = f"ring closed across the gap of {np.linalg.norm(a[0] - a[-1]):.3g} mm at its seam"
            arrays[i] = np.vstack([a, bridge])
    lengths = [chord_length(a) for a in arrays]
    short = {i for i, L in enumerate(lengths) if L <= delta}
    for i in short:
        notes[i] = f"shorter ({lengths[i]:.3g} mm) than the touching distance {delta:.3g} mm: left out"
    merged = _oversketched([a if i not in short else a[:1].repeat(2, 0) for i, a in enumerate(arrays)],
                           [L if i not in short else 0.0 for i, L in enumerate(lengths)], delta)
    merged = {j: i for j, i in merged.items() if j not in short and i not in short}
    for j, i in merged.items():
        notes[j] = f"merged into stroke {i} (drawn over it)"
    live = [i for i in range(len(arrays)) if i not in short and i not in merged]

    cands = NodeCandidates()
    trims: dict = {}
    _crossings(arrays, live, delta, cands, trims)
    # a trimmed stroke keeps only the part out of its run along the other stroke
    keep_range = {i: [0.0, lengths[i]] for i in live}
    for i, cuts in trims.items():
        for at_start, s in cuts:
            if at_start:
                keep_range[i][0] = max(keep_range[i][0], s)
            else:
                keep_range[i][1] = min(keep_range[i][1], s)
            notes.setdefault(i, f"over-sketched run along another stroke trimmed ({'start' if at_start else 'end'})")
    _end_joins(arrays, live, delta, cands, keep_range)

    labels = merge_candidates(cands, arrays, delta)
    groups: dict = {}
    for k, lab in enumerate(labels):
        groups.setdefault(lab, []).append(k)
    node_points, node_attach = [], []
    for ks in groups.values():
        node_points.append(np.mean([cands.points[k] for k in ks], axis=0))
        node_attach.append([a for k in ks for a in cands.attach[k]])

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
    extra_points: list = []
    for i in live:
        cum = cumulative_length(arrays[i])
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
            pts = _piece(arrays[i], cum, s0, s1, all_points[n0], all_points[n1])
            if n0 == n1 and chord_length(pts) <= 2 * PROXIMITY * delta:
                continue
            out_edges.append((n0, n1, pts, i, s0, s1))

    all_points = node_points + extra_points
    edges = _merge_parallel(out_edges, delta)
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
            notes.setdefault(i, "no piece of it is left between nodes")
    for i, text in bridged.items():
        notes[i] = text + (f"; {notes[i]}" if i in notes else "")
    return StrokeGraph(tuple(nodes), graph_edges, float(delta), tuple(arrays), notes, merged)


def _passes_through(n: int, edges: list) -> bool:
    """True when some stroke has two edges at node n (it runs through it)."""
    count: dict = {}
    for n0, n1, _, i, _, _ in edges:
        count[i] = count.get(i, 0) + (n0 == n) + (n1 == n)
    return any(c >= 2 for c in count.values())


def _merge_parallel(edges: list, delta: float) -> list:
    """Edges joining the same two nodes and lying within delta of each other (over-sketched runs
    between the same nodes) are one: the first drawn is kept."""
    out: list = []
    for e in edges:
        n0, n1, pts = e[0], e[1], e[2]
        dup = False
        for f in out:
            if {f[0], f[1]} != {n0, n1} or n0 == n1:
                continue
            d, _ = nearest_on(pts, f[2])
            if np.mean(d <= delta) >= OVERSKETCH_COVER:
                dup = True
                break
        if not dup:
            out.append(e)
    return out
