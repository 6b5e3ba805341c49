"""Corners of a loop whose two sides leave them the wrong way round the loop, opened (issue 18).

A Coons patch maps the corners of its parameter square onto the loop's corners: where the two
sides leave a corner the wrong way round the loop (the one that should turn left of the other
turns right of it), the patch turns over there, whatever fills the rest. On rough VR sketches
that is most often local: two strokes that meet nearly tangent cross once more just by their
node, or a stroke's last few millimetres bend back past the other's, and a little further along
the sides leave the right way. Of the 961 4-sided loops with nothing inside on the 82 CASSIE
sketches not in ../shared (session 32), 56 had such a corner, read CORNER_READ along the sides,
and 43 of those folded (77 %); of the other 905, 29 (3 %).

:func:`open_corners` reads every corner of every chosen loop CORNER_READ along its two sides,
against the normal of the loop's vector area; where they leave the wrong way, and the right way
once both are eased over a share of OPEN_SHARES (the smaller first; the points before it replaced
by a cubic from the node along the chord to the point there, arriving in the side's own
direction: :func:`ease_over`, as core.objects eases a hook at an edge's end), at every one of
CHECKS reads up to that share, the two are eased so; and only if every other loop's corner on
those two edge ends that left the right way still does. The curve is the graph's edge, so the
surface on its other side gets the same curve and the two still share it exactly. Left as they
are: a loop with more than half its corners wrong (its way round is in doubt: a band that
twists), a corner the wrong way still at the largest share (a reflex corner: the loop's own
shape), and a corner where a stroke runs on through its node: its two sides pieces of one stroke
(opened, a synthetic body's ring creased 69 deg between the surfaces either side of it), or one
side a piece whose direction there the G1 build keeps (core.node_tangents).
"""
from __future__ import annotations

import numpy as np

from .continuity import hermite_basis, unit
from .stroke_cycles import Cycle, CycleChoice, vector_area
from .strokes import cumulative_length, point_at_length
from .types import FloatArray

CORNER_READ = 0.08
"""A corner's sides are read this share of their lengths along them (the fold census's reading)."""

OPEN_SHARES = (0.2, 0.3, 0.4)
"""The shares of its sides' lengths over which a wrong-way corner is tried eased, the smaller
first; the first after which its sides leave it the right way at every one of CHECKS reads up to
that share is taken."""

CHECKS = 8
"""How many reads, evenly from 1 % of the sides to the share eased, a corner opened must pass."""


def ease_over(pts: FloatArray, share: float) -> FloatArray:
    """pts with the points before `share` of its length replaced by a cubic Hermite arc from its
    start along the chord to the point there, arriving in the polyline's direction there (as many
    points as they were, at least 4); its start kept exactly."""
    cum = cumulative_length(pts)
    reach = share * float(cum[-1])
    at = point_at_length(pts, reach, cum)
    chord = unit(at - pts[0])
    h = 0.5 * reach
    tangent = unit(point_at_length(pts, reach + h, cum) - point_at_length(pts, reach - h, cum))
    if not tangent.any() or not chord.any():
        return pts
    k = max(int(np.count_nonzero(cum < reach)), 4)
    span = float(np.linalg.norm(at - pts[0]))
    arc = hermite_basis(np.linspace(0.0, 1.0, k + 1)[:-1]) @ np.array([pts[0], span * chord, span * tangent, at])
    return np.vstack([arc, at, pts[cum > reach]])


def _leaving(pts: FloatArray, share: float) -> FloatArray:
    cum = cumulative_length(pts)
    return unit(point_at_length(pts, share * float(cum[-1]), cum) - pts[0])


def _right(leaving: FloatArray, other: FloatArray, share: float, normal: FloatArray) -> bool:
    """Whether two sides leaving one corner (`leaving` the side after it round the loop, `other`
    the side before it, reversed) leave it the right way round `normal`, read `share` along them."""
    return float(np.cross(_leaving(leaving, share), _leaving(other, share)) @ normal) > 0.0


def _ends(cycle: Cycle, k: int) -> tuple:
    """The two edge ends at corner k of a loop, (edge id, end 0 or 1) each: side k starts there
    (its edge's first point, end 0, unless it runs reversed), side k - 1 ends there (its edge's
    last point, end 1, unless reversed)."""
    (e_out, r_out), (e_in, r_in) = cycle.sides[k], cycle.sides[k - 1]
    return (e_out, int(r_out)), (e_in, int(not r_in))


def _eased_end(points: FloatArray, end: int, share: float) -> FloatArray:
    """An edge's points eased over `share` of it from its end 0 or 1 (ease_over)."""
    return ease_over(points[::-1], share)[::-1] if end else ease_over(points, share)


def open_corners(choice: CycleChoice, polylines: dict, strokes: dict, tangents: dict) -> tuple[dict, list]:
    """(polylines with the wrong-way corners of the chosen loops opened, [(edge id, edge id)]: the
    two sides of each corner opened; module docstring). polylines: {edge id: (n, 3) points};
    strokes: {edge id: the input stroke it is a piece of}; tangents: core.node_tangents ({(edge
    id, end 0 or 1): direction} where the edge's stroke runs on through the node there)."""
    cycles = choice.cycles
    out = dict(polylines)
    normals = [unit(vector_area(np.vstack([p[:-1] for p in c.polylines_from(out)]))) for c in cycles]
    corners_at: dict = {}             # (edge id, end) -> [(loop, corner)] of the loops' corners there
    for i, cycle in enumerate(cycles):
        for k in range(len(cycle.sides)):
            for end in _ends(cycle, k):
                corners_at.setdefault(end, []).append((i, k))

    def right(i: int, k: int, share: float, lines: dict) -> bool:
        cycle = cycles[i]
        (e_out, r_out), (e_in, r_in) = cycle.sides[k], cycle.sides[k - 1]
        leaving = lines[e_out][::-1] if r_out else lines[e_out]
        other = lines[e_in] if r_in else lines[e_in][::-1]
        return _right(leaving, other, share, normals[i])

    opened = []
    for i, cycle in enumerate(cycles):
        n = len(cycle.sides)
        if n < 3 or not normals[i].any():
            continue
        bad = [k for k in range(n) if not right(i, k, CORNER_READ, out)]
        if not bad or 2 * len(bad) > n:
            continue
        for k in bad:
            ends = _ends(cycle, k)
            (e_out, _), (e_in, _) = ends
            if strokes[e_out] == strokes[e_in] or any(end in tangents for end in ends):
                continue                  # a stroke running on through the node
            # the other loops' corners on these two edge ends, that leave the right way now
            others = [(j, m) for end in ends for j, m in corners_at[end]
                      if (j, m) != (i, k) and normals[j].any() and right(j, m, CORNER_READ, out)]
            for share in OPEN_SHARES:
                trial = dict(out)
                for e, end in ends:
                    trial[e] = _eased_end(out[e], end, share)
                if (all(right(i, k, read, trial) for read in np.linspace(0.01, share, CHECKS))
                        and all(right(j, m, CORNER_READ, trial) for j, m in others)):
                    out = trial
                    opened.append((e_in, e_out))
                    break
    return out, opened
