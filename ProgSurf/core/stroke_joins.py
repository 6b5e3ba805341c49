"""Where stroke ends join the stroke network (issue 18, part 1; core.stroke_graph builds the rest).

A stroke end within PROXIMITY x delta of another stroke is joined to its nearest point there (a
T-node, or a corner at the other's end); one that stopped short of a stroke, heading for it, is
extended to it (EXTEND); two that stopped short of their corner meet there (corner gaps); three or
more whose lines pass close to one point meet at that point, and so does an end stopped short of
it heading its way (meeting ends); a ring whose ends stop short of its seam, heading for each
other, is bridged (bridged_ring), one whose seam lies beside another stroke closes there (one
node), and one drawn on past its seam has the overlap cut away (ring_overlaps). An end near an
over-sketched run joins what the trim leaves of each stroke, never a cut-away piece. CASSIE (Yu
et al., CHI 2021) publishes the proximity and hook thresholds.
"""
from __future__ import annotations

import numpy as np

from .continuity import hermite_basis
from .stroke_nodes import Links, NodeCandidates, nearest_on
from .strokes import cumulative_length, point_at_length
from .types import FloatArray

PROXIMITY = 2.0
"""A stroke end this many delta from another stroke is joined to it (CASSIE: proximity 2 delta)."""

HOOK = 3.0
"""An end piece beyond the last node up to this many delta ... (CASSIE: hooks up to 3 delta)"""

HOOK_FRACTION = 0.15
"""... and up to this fraction of its stroke is a hook, removed (CASSIE: 15 % of a stroke)."""

EXTEND = 3.0
"""A stroke end that no stroke comes within PROXIMITY x delta of, but whose own direction leads
to one within this many delta (EXTEND_DEG), stopped short of it: it is joined there (a ring drawn
round with a gap at its seam, a stroke stopped short of the curve it runs to)."""

RING_GAP = 0.1
"""A stroke whose ends lie apart by at most this share of its length, each end's own direction
leading to the other end within RING_DEG, is a ring drawn with a gap at its seam: the gap is
bridged (bridged_ring; the paper closes a boundary's gaps by extending its strokes). A hand
drawing round a 600 mm rim stops 5-8 % short, 2-5 delta, beyond the reach of EXTEND, and the rim
was left a dangling chain: a tube with one of its strips missing and "quality: ok"."""

RING_DEG = 25.0
"""... plus the angle a circle's end makes with the chord of such a gap (180 deg times the gap's
share of the length: 11 deg for a gap of 6 %), the rest the hand's (both ends: a C whose ends
point past each other, or one end only, is not closed). Without that share, a rough rim 6 % short
whose end ran 35 deg off the gap stayed open (body_7011r)."""

RING_SLACK_DEG = 15.0
"""... and one end may be off by this much more where the other is closer (the two within twice
RING_DEG plus the circle's angle): a rough hand's rim 5.9 % short, one end 4.9 deg off its gap and
the other 43 deg (allowed 35.7), stayed a dangling chain and the body lost a loop (objects benchmark
body_5011r; body_25007r: 49.3 and 9.0 deg, allowed 34.4)."""

MEET_ENDS = 3
"""At least this many stroke ends (of as many strokes) that lie within EXTEND x delta of one another,
near no other stroke's middle, and whose lines pass within delta of one point, meet at that point
(_meeting_ends): a cone's rulings drawn to its tip, a box's three edges to their corner, each
stopping short or running over by a few delta. Taken two at a time (T-nodes, corner gaps) they made
two or three nodes round the tip, and the loops between them were slivers or missing."""

CORNER_MISS = 1.5
"""Two free ends stopped short of their corner (_corner_gaps) meet there when their lines pass within
this many delta of each other (the lines of three or more ends, _meeting_ends, within delta of one
point): at 0.5 a rough hand's grid corners stayed open, the end directions over their last delta
skew by the drawing's jitter and drift (objects benchmark grid_1004r: lines 0.54 and 0.79 delta
apart, ends 2.2 delta apart); at 1.0 too (grid_3003r: 1.02 delta apart)."""

MEET_REACH = 6.0
"""... each end within this many delta of the point (twice EXTEND: the lines passing within delta
of one point are the evidence; a rough hand's guides stop 3-4 delta short of a body's tip, and one
such end left out left it a dangling chain beside the tip, objects benchmark body_13011r)."""

LATE_REACH = 4.0
"""A stroke end that stopped short of a meeting of ends (MEET_ENDS), within this many delta of its
point, ..."""

LATE_DEG = 45.0
"""... joins it when its direction (its last delta, or its last EXTEND_BACK x delta) points within
this of the point. A rough hand's guides stop 3-4 delta short of a body's tip (MEET_REACH): at
EXTEND (3) delta a guide 3.2 delta short, heading 32 deg off the tip, joined the guide beside it
instead, and the tip's two nodes left a loop out (objects benchmark body_5009r)."""

EXTEND_BACK = 2.0
"""An end whose direction over its last delta leads to no stroke (EXTEND, EXTEND_DEG) is tried
with its direction over its last EXTEND_BACK x delta too."""

EXTEND_DEG = 15.0
"""How far off a stroke end's direction (its last delta) the curve it stopped short of may lie."""


class Boxes:
    """The strokes' bounding boxes, found once, so that the pair tests (two strokes, or a stroke end
    and a stroke, cannot touch when their boxes lie further apart than the margin) are one
    vectorised comparison per stroke instead of two box computations per pair."""

    def __init__(self, strokes: list) -> None:
        self.lo = np.array([s.min(axis=0) for s in strokes]).reshape(-1, 3)
        self.hi = np.array([s.max(axis=0) for s in strokes]).reshape(-1, 3)

    def close_to(self, lo: FloatArray, hi: FloatArray, margin: float) -> np.ndarray:
        """(n_strokes,) bool: the strokes whose box comes within `margin` of the box [lo, hi]."""
        return np.all(lo - margin <= self.hi, axis=1) & np.all(self.lo - margin <= hi, axis=1)


def _meeting_ends(strokes: list, cums: dict, live: list, delta: float, cands: NodeCandidates,
                  boxes: Boxes, kept: dict | None = None) -> set:
    """Groups of MEET_ENDS or more stroke ends that meet at one point (MEET_ENDS): one node
    candidate each, at the point nearest to the ends' lines (each stroke attached at its place
    nearest that point: an end that ran over it is cut back there, a hook; one that ran over it
    further than a hook is cut, HOOK and HOOK_FRACTION, is not one of them: the two halves of a
    curve drawn in two overlapping strokes, where a third ends). An end that stopped short of such a
    point within LATE_REACH x delta, heading within LATE_DEG of it, joins it too, and so does one
    that ran past it by up to LATE_REACH x delta, passing within CORNER_MISS x delta of it
    (attached where it passes nearest, the rest cut away: kept, the strokes' kept arc lengths as
    end_joins takes them, is trimmed). Strokes no longer
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
            d = end_direction(strokes[i], cums[i], s_end, delta)
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
                               float(np.linalg.norm(x - p)) / (MEET_REACH * delta),
                               past / min(HOOK * delta, HOOK_FRACTION * float(cums[i][-1]))))
            if max(off) <= 1.0:
                break
            # (the furthest off goes; of ends as far off to rounding, that of the last stroke: a
            # sketch drawn mirrored has its halves' ends tie, and which went varied with the
            # strokes' directions and the sketch's placement, fuzz benchmark 02-0-2 rigid)
            top = max(off)
            worst = max((k for k, o in zip(ks, off) if o >= top * (1.0 - 1e-9)), key=lambda k: ends[k][0])
            ks = [k for k in ks if k != worst]
            x = None
        if x is None or len(ks) < MEET_ENDS:
            continue
        # an end that stopped short of the meeting, within LATE_REACH of it and heading its way (within
        # LATE_DEG: a body's guide curves into its tip, so its line misses the tip by more than
        # delta) joins it too; left out, it dangled beside the tip and the loops there merged.
        # (Such an end lies within 2 reach of a member's end to be one of the group's.)
        members = {ends[k][0] for k in ks}
        late, over = {}, {}
        for k in group:
            i, s_end, p, d = ends[k]
            if i in members or i in late or i in over:
                continue
            to_x = x - p
            dist = float(np.linalg.norm(to_x))
            if float(d @ to_x) < 0.0:
                # an end that ran on past the meeting by up to LATE_REACH x delta (and HOOK_FRACTION
                # of its stroke), the stroke passing within CORNER_MISS x delta of its point: it is
                # attached where it passes nearest, the rest cut away (objects body_5002r: a guide 1.5 delta past its tip, 1.2
                # delta beside it, its line 1.4 delta off, made a T-node beside the tip;
                # body_29011r: a guide passing 0.2 delta from its tip ran 3 delta past it, a
                # hook's length, onto the guide beside it)
                off, s_near = nearest_on(x[None], strokes[i], cums[i])
                if (off[0] <= CORNER_MISS * delta
                        and abs(s_end - s_near[0]) <= min(LATE_REACH * delta, HOOK_FRACTION * float(cums[i][-1]))):
                    over[i] = (s_end, float(s_near[0]))
                continue
            if not delta < dist <= LATE_REACH * delta:
                continue
            # its direction over its last delta, or over EXTEND_BACK x delta (as an extension's):
            # a rough hand's last delta turns off by its jitter (objects body_23009r: a guide
            # 2.6 delta short of the tip heading 47 deg off it, its tip loops merged to one)
            back = end_direction(strokes[i], cums[i], s_end, EXTEND_BACK * delta)
            if any(v is not None and float(v @ to_x) >= np.cos(np.radians(LATE_DEG)) * dist for v in (d, back)):
                late[i] = s_end
        if not late and not over and max(float(np.linalg.norm(x - ends[k][2])) for k in ks) <= delta:
            continue        # (ends drawn to within delta of the point: they touch there, the other rules join them)
        attach = []
        for k in ks:
            i, s_end, _, _ = ends[k]
            attach.append((i, places[k] if abs(places[k] - s_end) <= reach else s_end))
            done.add((i, s_end))
        for i, s_end in late.items():
            attach.append((i, s_end))
            done.add((i, s_end))
        for i, (s_end, s_near) in over.items():
            attach.append((i, s_near))
            done.add((i, s_end))
            if kept is not None:        # (its run past the meeting cut away: left, it dangled
                # into the loop at the tip as a stroke inside it and folded it, body_5010r)
                kept[i][0 if s_end == 0.0 else 1] = (max(kept[i][0], s_near) if s_end == 0.0
                                                     else min(kept[i][1], s_near))
        # the places where these strokes touch one another near the meeting (the crossings of ends
        # run over it, an end passing another) are that meeting: left to it alone (a second
        # candidate on one of their ends made a second node beside it, and a sliver between)
        place = dict(attach)
        end_of = {ends[k][0]: ends[k][1] for k in ks}
        end_of.update(late)
        end_of.update({i: s_end for i, (s_end, _) in over.items()})

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


def ring_overlaps(strokes: list, live: list, delta: float, cands: NodeCandidates, keep: dict, cums: dict,
                  boxes: Boxes) -> dict:
    """Rings drawn round with an overlap at their seam: a stroke whose end, carried on along its
    own direction (_extension), meets the stroke itself within HOOK_FRACTION of its length from
    its other end, that other end lying behind it (the two ends ran past each other), further
    than its ends' closing reach apart (PROXIMITY x delta), the end near no other stroke (one
    that is joins that stroke, end_joins, and the ring closes there). Its seam is
    there: joined to itself, and the overlap beyond it cut away (keep is narrowed to the ring).
    Left whole, the overlap ran beside the ring's start and its end joined the curve crossing the
    ring there a little way off that crossing: two nodes on that curve, a sliver, and the ring's
    loops lost (objects benchmark body_13011r). Returns {stroke: True when its start was cut
    away, False when its end}: the trims' overlaps, for core.stroke_graph._off_cut_away. The
    seam's own end joins nothing else (end_joins skips it: done). cums: stroke -> cumulative
    lengths, boxes: the strokes' Boxes (both as end_joins takes them)."""
    cut: dict = {}
    for i in live:
        cum = cums[i]
        total = float(cum[-1])
        if total <= 4 * EXTEND * delta or np.linalg.norm(strokes[i][0] - strokes[i][-1]) <= PROXIMITY * delta:
            continue
        seams = []      # (overlap, end, seam) of each end that qualifies
        for s_end in (0.0, total):
            direction = end_direction(strokes[i], cum, s_end, delta)
            hit = _extension(strokes, cums, i, s_end, direction, [i], boxes, delta, keep)
            if hit is None:
                continue
            s_seam = hit[2]
            overlap = total - s_seam if s_end == 0.0 else s_seam
            other = strokes[i][-1] if s_end == 0.0 else strokes[i][0]
            here = strokes[i][0] if s_end == 0.0 else strokes[i][-1]
            if overlap > HOOK_FRACTION * total or float(direction @ (other - here)) >= 0.0:
                continue    # (the other end short of this one: a gap, which end_joins closes)
            if _nearest_join(here, i, strokes, cums, live, boxes, keep, PROXIMITY * delta) is not None:
                continue    # (an end beside another stroke joins it: end_joins; the seam is there)
            seams.append((overlap, s_end, s_seam))
        if not seams:
            continue
        # both ends may reach the stroke past the other: the shorter overlap is cut (the end tried
        # first was, and which that was followed the way the ring was drawn: objects benchmark
        # tube_1002r drawn the other way round had its seam 20 mm away, and a node more)
        _, s_end, s_seam = min(seams)
        cands.add(point_at_length(strokes[i], s_seam, cum), [(i, s_end), (i, s_seam)])
        if s_end == 0.0:
            keep[i][1] = min(keep[i][1], s_seam)
        else:
            keep[i][0] = max(keep[i][0], s_seam)
        cut[i] = s_end != 0.0
    return cut


def end_joins(strokes: list, live: list, delta: float, cands: NodeCandidates, keep: dict, cums: dict,
              boxes: Boxes, done: frozenset = frozenset()) -> None:
    """T-nodes and corners: each stroke end within PROXIMITY x delta of another stroke (or of its
    own other end, for a closed stroke) is joined to its nearest point there; ends that meet at one
    point (_meeting_ends) are joined there first. keep: stroke -> [lo, hi], the arc lengths of the
    part a trim leaves: an over-sketched run's cut-away piece joins nothing (the stroke it ran
    along lies there too), and an end it held joins nothing either (held at the cut, such a join
    tied the stroke to a place up to 300 mm beyond it). done: {(stroke, True for its start)}, the
    ends joined already (a ring's seam, ring_overlaps). A closed stroke whose end lies beside
    another stroke closes at that join: its other end joins there too. cums: stroke -> cumulative
    lengths (of every live stroke), boxes: the strokes' Boxes."""
    reach = PROXIMITY * delta
    met = _meeting_ends(strokes, cums, live, delta, cands, boxes, keep)
    free = []
    for i in live:
        total = float(cums[i][-1])
        closes = total > 4 * reach and np.linalg.norm(strokes[i][0] - strokes[i][-1]) <= reach
        seam = None     # a closed stroke's end join nearest its other stroke: (distance, candidate)
        for s_end, p in ((0.0, strokes[i][0]), (total, strokes[i][-1])):
            if (i, s_end) in met or (i, s_end == 0.0) in done:
                continue
            cut_away = keep[i][0] > 1e-9 * total if s_end == 0.0 else keep[i][1] < total * (1 - 1e-9)
            if cut_away:
                continue    # a trim cut this end away; the trim joined the stroke where it cut it
            best = _nearest_join(p, i, strokes, cums, live, boxes, keep, reach)
            if best is None and not closes:
                direction = end_direction(strokes[i], cums[i], s_end, delta)
                best = _extension(strokes, cums, i, s_end, direction, live, boxes, delta, keep)
                if best is None:
                    # the way it went over its last EXTEND_BACK delta: a rough hand's last delta
                    # swerves (grid_15008r: 26 deg off the border 2.03 delta ahead; over 2 delta, 9)
                    best = _extension(strokes, cums, i, s_end,
                                      end_direction(strokes[i], cums[i], s_end, EXTEND_BACK * delta),
                                      live, boxes, delta, keep)
                if best is not None:
                    _, j, sj = best
                    cands.add(point_at_length(strokes[j], sj, cums[j]), [(i, s_end), (j, sj)])
                    continue
                free.append((i, s_end, p, direction))
            if best is not None:
                _, j, sj = best
                joined = (0.5 * (p + point_at_length(strokes[j], sj, cums[j])), [(i, s_end), (j, sj)])
                if closes and (seam is None or best[0] < seam[0]):
                    if seam is not None:
                        cands.add(*seam[1])
                    seam = (best[0], joined)
                else:
                    cands.add(*joined)
        if closes:
            if seam is not None:
                # a ring whose seam lies beside another stroke closes there: one node (apart, the
                # seam and the join, up to 2 delta apart along the ring, were two nodes at one
                # place of it, one of them dropped, and the ring stayed open; its other end is
                # drawn to the join, up to 2.8 delta: a rim's seam moves so, 0.2-0.5 % of the
                # object's diagonal further from the truth in objects benchmark tube_2007)
                point, attach = seam[1]
                cands.add(point, attach + [(i, total if attach[0][1] == 0.0 else 0.0)])
            else:
                cands.add(0.5 * (strokes[i][0] + strokes[i][-1]), [(i, 0.0), (i, total)])
    _corner_gaps(free, delta, cands)


def _nearest_join(p: FloatArray, i: int, strokes: list, cums: dict, live: list, boxes: Boxes, keep: dict,
                  reach: float) -> tuple | None:
    """(distance, stroke j, arc length on j) of the point nearest p (3,) on the kept part of any live
    stroke but i within reach, or None (an end of stroke i beside another stroke)."""
    best = None
    near = boxes.close_to(p, p, reach)
    for j in live:
        if j == i or not near[j]:
            continue
        d, sj = _nearest_kept(p, strokes[j], cums[j], keep[j])
        if d <= reach and (best is None or d < best[0]):
            best = (d, j, sj)
    return best


def _nearest_kept(p: FloatArray, stroke: FloatArray, cum: FloatArray, kept: list) -> tuple[float, float]:
    """(distance, arc length) of the point of a stroke's kept part [lo, hi] nearest p (3,)."""
    lo, hi = kept
    if hi <= lo:
        return float("inf"), lo     # trims at both ends that overlap leave nothing
    d, s = nearest_on(p[None], stroke, cum)
    if lo - 1e-9 <= s[0] <= hi + 1e-9:
        return float(d[0]), float(s[0])
    piece = stroke_piece(stroke, cum, lo, hi, point_at_length(stroke, lo, cum), point_at_length(stroke, hi, cum))
    d, s = nearest_on(p[None], piece)
    return float(d[0]), lo + float(s[0])


def end_direction(stroke: FloatArray, cum: FloatArray, s_end: float, delta: float) -> FloatArray | None:
    """The unit direction a stroke leaves by at its end s_end (over its last delta, at most half
    of it), or None."""
    total = float(cum[-1])
    p = point_at_length(stroke, s_end, cum)
    back = point_at_length(stroke, min(delta, 0.5 * total) if s_end == 0.0 else max(total - delta, 0.5 * total), cum)
    d = p - back
    size = float(np.linalg.norm(d))
    return d / size if size > 0 else None


def bridged_ring(stroke: FloatArray, delta: float) -> FloatArray | None:
    """A ring drawn with a gap at its seam (RING_GAP, RING_DEG, RING_SLACK_DEG), closed: a cubic Hermite arc from
    its end, leaving in the end's direction, to its start, arriving in the start's, and the ring
    begun and ended halfway along that arc, the same place whichever way the ring ran (begun at
    its start, the seam node lay at one end of the gap or the other as it was drawn: objects
    benchmark tube_1002r, 6.5 mm). None when the stroke is no such ring or its ends are within
    the closing reach (PROXIMITY x delta: closed as they are)."""
    cum = cumulative_length(stroke)
    total = float(cum[-1])
    gap = stroke[0] - stroke[-1]
    size = float(np.linalg.norm(gap))
    if not (PROXIMITY * delta < size <= RING_GAP * total and total > 4 * PROXIMITY * delta):
        return None
    leave_end = end_direction(stroke, cum, total, delta)
    leave_start = end_direction(stroke, cum, 0.0, delta)
    if leave_end is None or leave_start is None:
        return None
    # a circle's end runs off the chord of a gap of share f of it by 180 f deg; RING_DEG on top
    allowed = RING_DEG + 180.0 * size / total
    off = [float(np.degrees(np.arccos(np.clip(v @ gap / size, -1.0, 1.0)))) for v in (leave_end, -leave_start)]
    if max(off) > allowed + RING_SLACK_DEG or sum(off) > 2.0 * allowed:
        return None
    step = total / max(len(stroke) - 1, 1)      # (the mean: repeated points leave the median at 0)
    n = min(max(int(np.ceil(size / step)), 2), len(stroke))
    t = np.linspace(0.0, 1.0, n + 1)[1:]         # (the arc at t = 1/n .. 1: its last point is stroke[0])
    bridge = hermite_basis(t) @ np.array([stroke[-1], size * leave_end, -size * leave_start, stroke[0]])
    # t = 0.5 is a sample for even n, halfway between two for odd n
    h = n // 2
    mid = 0.5 * (bridge[h - 1] + bridge[h]) if n % 2 else bridge[h - 1]
    before = bridge[:h] if n % 2 else bridge[:h - 1]
    return np.vstack([mid, bridge[h:-1], stroke, before, mid])


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
            # (each stopped up to a reach short: the ends lie up to two reaches apart, grid_9010r's
            # 3.2 delta apart, each 2 delta short of the corner)
            if i == j or d is None or e is None or np.linalg.norm(p - q) > 2 * reach:
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
               boxes: Boxes, delta: float, keep: dict) -> tuple | None:
    """(distance, stroke j, arc length on j) of the nearest stroke point ahead of stroke i's end at
    s_end along the end's own direction d (end_direction; None: no direction, no extension):
    within EXTEND x delta of the end and EXTEND_DEG of that direction (a delta / 4 aside allowed for
    the strokes' noise), on the part of stroke j a trim leaves (keep, as in end_joins); on stroke i
    itself only further than 4 x EXTEND x delta from the end along it. None when there is none."""
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
        lo, hi = keep[j]
        if hi <= lo:
            continue
        s = np.minimum(np.arange(lo, hi + step, step), hi)
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
            # (on the kept part: a ring's lap beside the overlap cut away from it held the foot
            # there, and the join was dropped with the piece, objects benchmark tube_3011r)
            _, foot = _nearest_kept(p + along[k] * d, strokes[j], cums[j], keep[j])
            if best is None or along[k] < best[0]:
                best = (float(along[k]), j, foot)
    return best


def stroke_piece(stroke: FloatArray, cum: FloatArray, s0: float, s1: float, p0: FloatArray,
                 p1: FloatArray) -> FloatArray:
    """The stroke between arc lengths s0 < s1, its ends replaced by the node points p0, p1 (a
    sample within 1e-9 of the stroke's length of s0 or s1 is one of those ends)."""
    tol = 1e-9 * max(float(cum[-1]), 1.0)
    inner = stroke[(cum > s0 + tol) & (cum < s1 - tol)]
    return np.vstack([p0, inner, p1])
