"""Where two strokes of the network touch, and which touching places are one node (issue 18, part 1).

The stroke network (core.stroke_graph) finds, with one sketch-relative distance delta, every
place where two strokes come within delta of each other: the runs of close segment pairs of
`segment_distances`. This module holds the tests that decide, place by place, what such a run is
and which of the node candidates found are one node; each judges a place by what the strokes
there show, so that a feature smaller than delta (the nose of a 38 m fuselage drawn with a
delta of 766 mm) keeps its nodes apart, while a sketch drawn loosely keeps delta's reach:

- apex_meeting: two strokes that end together and part steadily (the rulings of a cone at its
  tip) meet at an apex, however long they stay within delta of each other; strokes drawn over
  one another stay close along the run instead;
- seam_twins: a run that continues across the seam of a closed stroke (its first and last
  segments are neighbours) is one place, not two;
- merge_candidates: node candidates closer than delta merge, but two that would join two places
  of one stroke merge only within JUNCTION_SPREAD times the imprecision of the strokes there (how
  far apart they pass: the candidates' gaps).
"""
from __future__ import annotations

from typing import Sequence

import numpy as np

from .strokes import cumulative_length, point_at_length
from .types import FloatArray

JUNCTION_SPREAD = 3.0
"""Node candidates that would join two places of one stroke are one node when no farther apart than
this many times the largest gap among them (and, where three or more strokes meet, among a
candidate of their other strokes nearby): strokes drawn through one place with an imprecision g
meet there in candidates a few g apart. Measured on the 12 real sketches of ../shared/data (delta
2 % of the diagonal): at 3 the six VR sketches get the networks that merging every candidate
within delta gives them; at 1.5 and 2, 02-0-2 gains 3 edges and a loop, at 1 10-2-1 has 11 fewer
strokes on loops; the noisy TiGL fuselage's nose keeps its profile's crossings apart up to 4
(the wrong junctions there span 4.35 to 4.68 times their largest gap) and opens at 5."""

SPREAD_FLOOR = 0.05
"""The imprecision merge_candidates allows a place at least: this share of delta. Strokes that
cross exactly (gaps of 0) still cross at points a chord's sag apart where they are curved and
sampled: three curved spokes drawn exactly through one point, overshooting it, left three nodes
5e-4 delta apart and a sliver surface between them. (The noisy fuselage's nose places it keeps
apart lie 0.6-0.95 delta from one another, far beyond JUNCTION_SPREAD times this.)"""

MIDDLE_REACH = 2.0
"""Three strokes that cross one another pairwise within delta, each crossing farther than this
many delta from the ends of its strokes, are one junction drawn through one place however
precisely they cross: a clean sketchgen dome has three strokes crossing in their middles (13-14
delta from their ends) in a triangle of 0.7 delta, which kept apart made a sliver loop, loops
facing every way, and a sketch of one surface built as several (exit 3). Near the strokes' ends
the rules above stand: the guides of the noisy TiGL fuselage converge to its nose in triangles of
0.6-0.95 delta with crossings 0-0.8 delta from their ends (the 2 delta of a T-node's reach,
core.stroke_joins.PROXIMITY, separates them)."""

APEX_PARTING = 0.25
"""Two strokes that end together in a run along each other meet at an apex when, halfway along the
run, their separation has grown by at least this share of its growth over the whole run (strokes
parting at a steady angle: one half; drawn over one another: about none). On the 12 real
sketches 0.1 and 0.25 give the same networks; at 0.4 the TiGL helibody's boom keeps 101 of its
115 loops, at 0.45 its shell opens; the VR sketches do not change from 0.1 to 0.45."""


def segment_distances(a: FloatArray, b: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Closest points between every segment of polyline a (m-1 segments) and of b (k-1 segments):
    (distance (m-1, k-1), parameter s in [0, 1] along a's segment, t along b's). Ericson,
    "Real-time collision detection", 5.1.9, vectorised; parallel segments take s from a's start."""
    p1, d1 = a[:-1, None, :], np.diff(a, axis=0)[:, None, :]
    p2, d2 = b[None, :-1, :], np.diff(b, axis=0)[None, :, :]
    r = p1 - p2
    aa = np.einsum("ijk,ijk->ij", d1, d1) + np.zeros((1, len(b) - 1))
    ee = np.einsum("ijk,ijk->ij", d2, d2) + np.zeros((len(a) - 1, 1))
    ff = np.einsum("ijk,ijk->ij", d2, r)
    cc = np.einsum("ijk,ijk->ij", d1, r)
    bb = np.einsum("ijk,ijk->ij", d1, d2)
    den = aa * ee - bb * bb
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(den > 1e-12 * aa * ee, np.clip((bb * ff - cc * ee) / den, 0.0, 1.0), 0.0)
        t = (bb * s + ff) / np.maximum(ee, 1e-300)
        s = np.where(t < 0, np.clip(-cc / np.maximum(aa, 1e-300), 0.0, 1.0),
                     np.where(t > 1, np.clip((bb - cc) / np.maximum(aa, 1e-300), 0.0, 1.0), s))
    t = np.clip(t, 0.0, 1.0)
    dist = np.linalg.norm(p1 + d1 * s[..., None] - p2 - d2 * t[..., None], axis=2)
    return dist, s, t


def components(mask: np.ndarray) -> list:
    """8-connected components of the True cells of a 2D mask: [(rows, cols)]."""
    seen = np.zeros_like(mask)
    out = []
    for i, j in zip(*np.nonzero(mask)):
        if seen[i, j]:
            continue
        stack, cells = [(i, j)], []
        seen[i, j] = True
        while stack:
            x, y = stack.pop()
            cells.append((x, y))
            for dx in (-1, 0, 1):
                for dy in (-1, 0, 1):
                    u, v = x + dx, y + dy
                    if 0 <= u < mask.shape[0] and 0 <= v < mask.shape[1] and mask[u, v] and not seen[u, v]:
                        seen[u, v] = True
                        stack.append((u, v))
        rows, cols = zip(*cells)
        out.append((np.array(rows), np.array(cols)))
    return out


def nearest_on(points: FloatArray, poly: FloatArray, cum: FloatArray | None = None) -> tuple[FloatArray, FloatArray]:
    """Distance of each point (k, 3) to a polyline and the arc length of its footpoint: (k,), (k,).
    cum: cumulative_length(poly), when the caller has it already."""
    a, ab = poly[:-1], np.diff(poly, axis=0)
    ll = np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300)
    w = np.clip(np.einsum("kij,ij->ki", points[:, None, :] - a[None], ab) / ll, 0.0, 1.0)
    d = np.linalg.norm(a[None] + w[..., None] * ab[None] - points[:, None, :], axis=2)
    j = d.argmin(axis=1)
    cum = cumulative_length(poly) if cum is None else cum
    seg = np.sqrt(ll)
    k = np.arange(len(points))
    return d[k, j], cum[j] + w[k, j] * seg[j]


def ends_in(cum: FloatArray, segments: np.ndarray) -> tuple[bool, bool]:
    """(start, end): whether the stroke's first / last point lies in the run of these segments."""
    total = cum[-1]
    return bool(cum[segments.min()] <= 1e-9 * total), bool(cum[segments.max() + 1] >= total * (1 - 1e-9))


def apex_meeting(a: FloatArray, b: FloatArray, cum_a: FloatArray, cum_b: FloatArray, rows: np.ndarray,
                 cols: np.ndarray, delta: float) -> bool:
    """Whether a run along each other (the component rows x cols of segment_distances(a, b) <= delta)
    is two strokes meeting at an apex: the run holds one end of each, those ends lie within delta
    of each other, and from there the strokes part steadily (APEX_PARTING): their separation,
    sampled along a, has grown halfway along the run by at least APEX_PARTING of its growth over
    the run. The rulings of a cone, drawn to its tip, meet so; a stroke drawn over another's end
    stays close along the run and is trimmed there instead (core.stroke_graph)."""
    a_start, a_end = ends_in(cum_a, rows)
    b_start, b_end = ends_in(cum_b, cols)
    if a_start == a_end or b_start == b_end:
        return False
    samples = np.linspace(cum_a[rows.min()], cum_a[rows.max() + 1], 33)
    if a_end:
        samples = samples[::-1]
    pts = point_at_length(a, samples, cum_a)
    if np.linalg.norm(pts[0] - (b[0] if b_start else b[-1])) > delta:
        return False
    sep, _ = nearest_on(pts, b, cum_b)
    apex, mid, far = sep[0], sep[len(sep) // 2], max(sep[-1], sep[0])
    return bool(mid - apex >= APEX_PARTING * (far - apex))


def seam_twins(comps: list, dist: FloatArray, closed_a: bool, closed_b: bool, runs: Sequence[bool]) -> list:
    """Indices of the components of segment_distances(a, b) <= delta (comps, from `components`)
    but those that continue a closer one across the seam of a closed stroke: with a's (closed_a)
    or b's (closed_b) first and last segments taken as neighbours, a component next to one whose
    closest distance is smaller is the same place seen twice and is left out. Runs (runs[k] true:
    a component that follows both strokes further than a crossing does) are all kept. (A profile
    smaller than delta, crossed next to its seam, gave a second node candidate at the seam, its
    gap 0.5 delta, which merged its crossings.)"""
    if not (closed_a or closed_b) or len(comps) < 2:
        return list(range(len(comps)))
    m, k = dist.shape
    closest = [float(dist[rows, cols].min()) for rows, cols in comps]
    cells = [set(zip(rows.tolist(), cols.tolist())) for rows, cols in comps]
    crossing = [not run for run in runs]

    def neighbours(x: int, y: int) -> bool:
        for r, c in cells[x]:
            for dr in (-1, 0, 1):
                for dc in (-1, 0, 1):
                    u, v = r + dr, c + dc
                    u = u % m if closed_a else u
                    v = v % k if closed_b else v
                    if (u, v) in cells[y]:
                        return True
        return False

    drop = set()
    for x in range(len(comps)):
        for y in range(len(comps)):
            if x == y or not (crossing[x] and crossing[y]) or (closest[x], x) >= (closest[y], y):
                continue
            if neighbours(x, y):
                drop.add(y)
    return [n for n in range(len(comps)) if n not in drop]


class Links:
    """Groups of items 0..n-1 joined two at a time (union-find with path halving)."""

    def __init__(self, n: int) -> None:
        self.parent = list(range(n))

    def find(self, x: int) -> int:
        parent = self.parent
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    def join(self, a: int, b: int) -> None:
        self.parent[self.find(a)] = self.find(b)

    def groups(self) -> list:
        """[[items of one group, ascending]], in order of their first item."""
        out: dict = {}
        for k in range(len(self.parent)):
            out.setdefault(self.find(k), []).append(k)
        return list(out.values())


class NodeCandidates:
    """Node candidates: each a point and the (stroke, arc length) attachments it stands for."""

    def __init__(self) -> None:
        self.points: list = []
        self.attach: list = []

    def add(self, point, attachments) -> None:
        self.points.append(np.asarray(point, dtype=float))
        self.attach.append(list(attachments))


def _gaps(cands: NodeCandidates, strokes: Sequence[FloatArray]) -> list:
    """Per candidate, the largest distance between the stroke points it joins (its attachments'
    points, found with one point_at_length call per stroke)."""
    where: dict = {}
    for c, att in enumerate(cands.attach):
        for k, (i, s) in enumerate(att):
            where.setdefault(i, []).append((c, k, s))
    points: dict = {}
    for i, items in where.items():
        at = point_at_length(strokes[i], np.array([s for _, _, s in items]))
        for (c, k, _), p in zip(items, at.reshape(-1, 3)):
            points[c, k] = p
    out = []
    for c, att in enumerate(cands.attach):
        q = np.array([points[c, k] for k in range(len(att))])
        out.append(float(np.linalg.norm(q[:, None] - q[None], axis=2).max()))
    return out


def merge_candidates(cands: NodeCandidates, strokes: Sequence[FloatArray], delta: float) -> list:
    """Which candidates are one node: a label per candidate (single linkage of the links below).

    Two candidates closer than delta are linked, as CASSIE's near-crossings within delta are,
    except two that share a stroke and also join other, different strokes (A on strokes {i, j},
    B on {i, k}, or B on i alone): linking them would make one node of two places of stroke i, so
    they are linked only when no farther apart than JUNCTION_SPREAD times the imprecision there:
    the largest gap of A and B (the distance between the stroke points a candidate joins) and,
    when A and B both join other strokes, of any candidate of j and k within delta of A or B (the
    third pair of a junction of three strokes drawn loosely), or when A, B and that third
    candidate, pairwise within delta, all lie in the middles of their strokes (MIDDLE_REACH). A closed profile crossed exactly by
    eight curves 0.9 delta apart keeps eight nodes; three strokes drawn through one place, each
    missing the others by up to g, make one."""
    n = len(cands.points)
    if not n:
        return []
    pts = np.array(cands.points)
    d = np.linalg.norm(pts[:, None] - pts[None], axis=2)
    sets = [frozenset(i for i, _ in att) for att in cands.attach]
    gap = _gaps(cands, strokes)
    on_stroke: dict = {}
    for c, strokes_c in enumerate(sets):
        for i in strokes_c:
            on_stroke.setdefault(i, []).append(c)

    # how far each candidate lies from the nearest end of the strokes it joins (arc length)
    ends: dict = {}
    inner = []
    for att in cands.attach:
        for i, _ in att:
            if i not in ends:
                ends[i] = float(cumulative_length(strokes[i])[-1])
        inner.append(min(min(s, ends[i] - s) for i, s in att))
    links = Links(n)
    for a, b in zip(*np.nonzero(np.triu(d <= delta, 1))):
        root_a, root_b = links.find(a), links.find(b)
        if root_a == root_b:
            continue
        shared = sets[a] & sets[b]
        others_a, others_b = sets[a] - shared, sets[b] - shared
        if shared and (others_a or others_b):
            spread = max(gap[a], gap[b], SPREAD_FLOOR * delta)
            crossing = False
            if others_a and others_b:
                for c in {c for j in others_a for c in on_stroke[j]}:
                    if sets[c] & others_b and (d[c, a] <= delta or d[c, b] <= delta):
                        spread = max(spread, gap[c])
                        crossing |= d[c, a] <= delta and d[c, b] <= delta and all(
                            inner[x] > MIDDLE_REACH * delta for x in (a, b, c))
            if d[a, b] > JUNCTION_SPREAD * spread and not crossing:
                continue
        links.join(root_a, root_b)
    return [links.find(k) for k in range(n)]
