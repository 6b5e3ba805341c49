"""The cycles of a stroke network that bound surfaces, a manifold choice (issue 18, part 2).

Each node gets a normal from the directions of its edges (the plane they span, or for an apex
or corner whose edges leave it to one side, like a cone's tip or a cube's corner, the plane
through their tips), oriented consistently along the graph. Ordering its edges by angle about
that normal gives a rotation system; its faces (walk an edge, turn to the next edge around the
node, repeat) use every edge at most once in each direction, so each curve bounds at most two
surfaces: the manifold choice that Zhuang, Zou, Carr and Ju (2013) make with a local "mapping" at
each node and that CASSIE makes by walking the graph with node normals.

Not every face bounds a surface: per connected part, a face that runs the other way round the
node normals than the most faces do is the outer face of an open sheet (a grid's border), and a
face the node normals lie along (ALIGN_MIN) is a rim such as a tube's end; both are left out.
Dangling edges (pruned first) bound nothing; they are candidates for interior strokes. Nor do
bridges, edges whose two sides are one face (a face walks them both ways): the face is the loops
left when they are cut out of its walk (a shield's plate round a stud that a stroke joins to its
rim, which was left out whole before); a bridge is no interior stroke of it (core.objects).
"""
from __future__ import annotations

import heapq
from collections import Counter
from dataclasses import dataclass

import numpy as np

from .stroke_graph import StrokeGraph
from .strokes import cumulative_length, point_at_length
from .types import FloatArray

ALIGN_MIN = 0.3
"""A face bounds a surface when the mean of its nodes' normals, dotted with the unit vector area
of its loop (in the part's orientation), is at least this."""

ISOTROPIC = 0.4
"""Edge directions whose smallest scatter eigenvalue is at least this fraction of the largest
span no plane (a cube's corner): the node's normal is then their mean."""

APEX_COS = 0.5
"""A node whose edges all leave it within 60 degrees of their mean direction (cos >= this) is an
apex or a corner: the tip of a cone whose rulings meet there, a cube's corner. Its normal is the
normal of the plane through the tips of the edge directions (for a cone, its axis; for a cube's
corner, the mean), about which the edges turn in order; the plane through the directions
themselves, right for a node inside a sheet, would lie along the cone's axis and order its
rulings at random. The TiGL fuselage's tail apex closes with 0.5; with 0.8 it does not, with 0.2
10-2-1's network changes."""

STRAIGHT_DEG = 30.0
"""A node of two edges whose directions are within this of one line counts in a face's alignment
only when the face has no other node (_straight_nodes)."""

WEAK_TURN_COS = 0.0
"""A node's normal oriented from its neighbour's across an edge whose direction turns by more than
the angle of this cosine between its two ends is checked again (_flip_weak)."""

TURN_DISC = 0.75
"""A face whose turning number (_turning) is at least this bounds a disc (_flip_weak's count)."""

TURN_DISC_TOL = 0.15
"""A face whose loop's vector area says nothing of its side (alignment under ALIGN_MIN) bounds a
surface when its turning number is within this of 1: at each corner it turns as a disc with
nearly straight sides does (a strip round a lip, whose nodes' normals point every way)."""

TANGENT_REACH = 3.0
"""An edge's direction at a node is taken to its point this many delta along it (at most 30 % of it,
but at least TANGENT_LEAST delta)."""

TANGENT_LEAST = 0.5
"""... at least this many delta along it (or all of it): a short edge's first 30 % lies within the
strokes' noise of its node (the noisy TiGL helicopter's boom rings, cut by 16 guides into pieces
of 30 mm, turned 45 deg out of their plane that way, with delta 42 mm)."""


@dataclass(frozen=True)
class Cycle:
    """A cycle of the stroke network that bounds one surface.

    sides : ((edge id, reversed), ...) in loop order: each side runs from the node where the
            previous one ends
    align : how well the loop's vector area agrees with its nodes' normals (1: fully)
    """

    sides: tuple
    align: float

    @property
    def edge_ids(self) -> frozenset:
        return frozenset(e for e, _ in self.sides)

    def polylines(self, graph: StrokeGraph) -> list:
        """The sides' points in loop order: [(n_k, 3)], each ending where the next starts."""
        return [graph.edges[e].points[::-1] if rev else graph.edges[e].points for e, rev in self.sides]

    def polylines_from(self, points: dict) -> list:
        """The sides in loop order from {edge id: (n, 3) points} (another cut of the same edges,
        such as the faired one): [(n_k, 3)]."""
        return [points[e][::-1] if rev else points[e] for e, rev in self.sides]

    def loop_points(self, graph: StrokeGraph) -> FloatArray:
        return np.vstack([p[:-1] for p in self.polylines(graph)])


@dataclass(frozen=True)
class CycleChoice:
    """The surfaces' cycles of a stroke network, and what was left out.

    cycles   : the chosen Cycles             dropped : [(Cycle, reason)] faces not taken
    dangling : edge ids that bound nothing (pruned tree branches and bridges)
    normals  : {node id: (3,) unit normal} (nodes of degree 2 or more)
    parts    : [set of edge ids] per connected part of the non-dangling graph
    bridges  : the dangling edge ids that are bridges (both ends on loops, the same face either side)
    """

    cycles: tuple
    dropped: tuple
    dangling: frozenset
    normals: dict
    parts: tuple
    bridges: frozenset = frozenset()


def _prune(graph: StrokeGraph) -> set:
    """Edges left after removing, again and again, every edge at a node of degree 1."""
    live = {e.id for e in graph.edges}
    deg: dict = {}
    for e in graph.edges:
        deg[e.node0] = deg.get(e.node0, 0) + 1
        deg[e.node1] = deg.get(e.node1, 0) + 1
    changed = True
    while changed:
        changed = False
        for e in graph.edges:
            if e.id in live and (deg[e.node0] == 1 or deg[e.node1] == 1):
                live.discard(e.id)
                deg[e.node0] -= 1
                deg[e.node1] -= 1
                changed = True
    return live


def _tangent(points: FloatArray, reach: float, least: float = 0.0) -> FloatArray:
    """Unit direction from points[0] to the point `reach` along the polyline: at most 30 % of it,
    but at least `least` (or all of it)."""
    cum = cumulative_length(points)
    p = point_at_length(points, min(reach, max(0.3 * cum[-1], min(least, cum[-1]))))
    d = p - points[0]
    n = np.linalg.norm(d)
    return d / n if n > 0 else np.zeros(3)


def _half_edges(graph: StrokeGraph, live: set) -> dict:
    """node -> [(edge id, reversed, unit tangent leaving the node)]."""
    reach = TANGENT_REACH * graph.delta
    least = TANGENT_LEAST * graph.delta
    out: dict = {}
    for e in graph.edges:
        if e.id not in live:
            continue
        out.setdefault(e.node0, []).append((e.id, False, _tangent(e.points, reach, least)))
        out.setdefault(e.node1, []).append((e.id, True, _tangent(e.points[::-1], reach, least)))
    return out


def _raw_normal(tangents: FloatArray) -> FloatArray | None:
    """The normal of the plane the edge directions span (None for two collinear ones); at an apex
    (APEX_COS), the direction about which they turn."""
    if len(tangents) == 2:
        n = np.cross(tangents[0], tangents[1])
        norm = np.linalg.norm(n)
        return n / norm if norm > 1e-6 else None
    mean = tangents.mean(axis=0)
    size = np.linalg.norm(mean)
    if size > 1e-9 and np.min(tangents @ (mean / size)) >= APEX_COS:
        # the directions' tips lie round their mean: the normal of the plane through the tips
        w, v = np.linalg.eigh((tangents - mean).T @ (tangents - mean))
        if w[1] > 1e-6 * w[-1]:
            return v[:, 0] if v[:, 0] @ mean >= 0 else -v[:, 0]
    w, v = np.linalg.eigh(tangents.T @ tangents)
    if w[0] >= ISOTROPIC * w[-1]:
        m = tangents.sum(axis=0)
        norm = np.linalg.norm(m)
        if norm > 1e-6:
            return m / norm
    return v[:, 0]


def _parts(graph: StrokeGraph, live: set) -> list:
    """Connected parts of the live edges: [set of edge ids]."""
    adj: dict = {}
    for e in graph.edges:
        if e.id in live:
            adj.setdefault(e.node0, []).append(e.id)
            adj.setdefault(e.node1, []).append(e.id)
    seen: set = set()
    parts = []
    for start in sorted(live):
        if start in seen:
            continue
        part, stack = set(), [start]
        while stack:
            k = stack.pop()
            if k in part:
                continue
            part.add(k)
            e = graph.edges[k]
            stack.extend(x for n in (e.node0, e.node1) for x in adj[n] if x not in part)
        seen |= part
        parts.append(part)
    return parts


def _oriented_normals(graph: StrokeGraph, half: dict) -> dict:
    """Node normals, flipped along the graph to agree with their neighbour's across each edge,
    compared with their components along the edge's chord removed. The most certain agreements
    go first (a maximum spanning tree of |agreement|, as Hoppe et al. 1992 orient point normals):
    a node whose edges give a poor plane (its normal near the others' tangent plane, as where a
    stroke lifted off the sheet is snapped onto a crossing by short edges) is reached last, so a
    wrong sign there does not spread to the nodes beyond it."""
    raw = {n: _raw_normal(np.array([t for _, _, t in hs])) for n, hs in half.items()}
    normals: dict = {}

    def agreement(u: int, v: int, nv: FloatArray) -> float:
        c = graph.nodes[v].point - graph.nodes[u].point
        cn = np.linalg.norm(c)
        c = c / cn if cn > 0 else c
        pu, pv = normals[u] - (normals[u] @ c) * c, nv - (nv @ c) * c
        return float(pu @ pv)

    for seed in sorted(half, key=lambda n: -len(half[n])):
        if seed in normals or raw[seed] is None:
            continue
        normals[seed] = raw[seed]
        heap: list = []

        def push(u: int) -> None:
            for eid, _, _ in half[u]:
                v = graph.edges[eid].other(u)
                if v in normals:
                    continue
                # two collinear edges (no normal of its own): the neighbour's, across the edge
                nv = raw[v] if raw[v] is not None else normals[u]
                sure = 2.0 if raw[v] is None else abs(agreement(u, v, nv))
                heapq.heappush(heap, (-sure, v, u))

        push(seed)
        while heap:
            _, v, u = heapq.heappop(heap)
            if v in normals:
                continue
            nv = raw[v] if raw[v] is not None else normals[u]
            normals[v] = -nv if agreement(u, v, nv) < 0 else nv
            push(v)
    return normals


def _turning(graph: StrokeGraph, face: list, normals: dict, leaving: dict) -> float:
    """A face's turning number about its nodes' normals: the sum over its corners of pi less the
    angle between the edge it leaves by and the one it came in by (counter-clockwise about the
    node's normal), over 2 pi. A face that bounds a disc turns once (1: four corners of 90 deg);
    a ring's cap whose nodes all lie on its ring, or a strip round a hole, does not (0)."""
    total = 0.0
    for k in range(len(face)):
        e_in, r_in = face[k - 1]
        e_out, r_out = face[k]
        edge = graph.edges[e_out]
        n = edge.node1 if r_out else edge.node0
        nrm = normals.get(n)
        if nrm is None:
            continue
        a = leaving[(n, e_out, r_out)]
        b = leaving[(n, e_in, not r_in)]
        a, b = a - (a @ nrm) * nrm, b - (b @ nrm) * nrm
        total += np.pi - np.arctan2(float(np.cross(a, b) @ nrm), float(a @ b)) % (2 * np.pi)
    return total / (2 * np.pi)


def _discs(graph: StrokeGraph, half: dict, normals: dict, leaving: dict) -> int:
    """How many faces of the rotation system that the normals give turn once (TURN_DISC)."""
    count = 0
    for face in _faces(graph, _rotation(half, normals)):
        ids = [e for e, _ in face]
        if len(set(ids)) == len(ids) and _turning(graph, face, normals, leaving) >= TURN_DISC:
            count += 1
    return count


def _flip_weak(graph: StrokeGraph, half: dict, normals: dict, leaving: dict) -> dict:
    """The normals, with each group of nodes joined to the others only by edges that turn by more
    than a right angle between their ends (WEAK_TURN_COS) flipped as a whole where that makes more
    faces of the rotation system discs (_turning). _oriented_normals compares the normals at an
    edge's two ends; round a lip, where the sheet turns 150 deg along its guides from a nacelle's
    inner ring to its outer one, that says the opposite of the truth, and the inner ring's nodes
    were flipped: the strip round the lip made two loops of eight curves each (two rings and four
    guides), neither a surface, and the inner ring was taken as a stroke inside the surfaces
    behind the outer one, which it pulled 200 mm inwards. leaving: (node, edge id, reversed) ->
    the edge's unit direction leaving that node (_half_edges)."""
    # the groups: the connected parts (_parts) of the edges turning less; a node on none is alone
    steady = {eid for (u, eid, rev), t in leaving.items()
              if float(t @ -leaving[(graph.edges[eid].other(u), eid, not rev)]) >= WEAK_TURN_COS}
    part_of = {n: k for k, part in enumerate(_parts(graph, steady))
               for eid in part for n in (graph.edges[eid].node0, graph.edges[eid].node1)}
    groups: dict = {}
    for n in normals:
        groups.setdefault(part_of.get(n, ("alone", n)), []).append(n)
    if len(groups) < 2:
        return normals
    best = _discs(graph, half, normals, leaving)
    for members in sorted(groups.values(), key=len)[:-1]:
        trial = dict(normals)
        for n in members:
            trial[n] = -trial[n]
        score = _discs(graph, half, trial, leaving)
        if score > best:
            normals, best = trial, score
    return normals


def _rotation(half: dict, normals: dict) -> dict:
    """node -> its half-edges [(edge id, reversed)] in counter-clockwise order about its normal."""
    out = {}
    for n, hs in half.items():
        nrm = normals.get(n)
        if nrm is None or len(hs) <= 2:
            out[n] = [(e, r) for e, r, _ in hs]
            continue
        proj = [t - (t @ nrm) * nrm for _, _, t in hs]
        x = proj[0] / max(np.linalg.norm(proj[0]), 1e-300)
        y = np.cross(nrm, x)
        ang = [np.arctan2(p @ y, p @ x) for p in proj]
        order = np.argsort(ang, kind="stable")
        out[n] = [(hs[k][0], hs[k][1]) for k in order]
    return out


def _faces(graph: StrokeGraph, rotation: dict) -> list:
    """The faces of the rotation system: [[(edge id, reversed), ...]]."""
    def head(h):
        e = graph.edges[h[0]]
        return e.node0 if h[1] else e.node1

    seen: set = set()
    faces = []
    for n in sorted(rotation):
        for h in rotation[n]:
            if h in seen:
                continue
            face = []
            cur = h
            while cur not in seen:
                seen.add(cur)
                face.append(cur)
                w = head(cur)
                around = rotation[w]
                back = (cur[0], not cur[1])
                k = around.index(back)
                cur = around[k - 1]
            faces.append(face)
    return faces


def _pinched(graph: StrokeGraph, face: list) -> list:
    """A face split where it passes through one node twice: [face, ...]. The walk round a face of
    the rotation system comes back to a node it passed (two loops that touch at a node, a loop
    drawn as a figure eight, laps of a stroke drawn round and round) when the node's edges are
    ordered so that the face leaves by another one; such a loop crosses itself in its own
    surface: every one the 12 real sketches had (8 of 565) turned its Coons patch over. Each closed
    stretch between two visits is a loop of its own."""
    def start(h):
        e = graph.edges[h[0]]
        return e.node1 if h[1] else e.node0

    out, stack = [], [list(face)]
    while stack:
        f = stack.pop()
        seen: dict = {}
        for k, h in enumerate(f):
            n = start(h)
            if n in seen:
                j = seen[n]
                stack += [f[j:k], f[:j] + f[k:]]
                break
            seen[n] = k
        else:
            out.append(f)
    return out


def _cut_bridges(face: list) -> tuple[list, set]:
    """(the closed walks left of a face once both walks along each edge it walks both ways, a
    bridge, are taken out: [[(edge id, reversed), ...]]; those edges). A face A, e, B, e', C (e'
    the way back along e) is the closed walk C + A round e's first node and the closed walk B
    round its other one: a sheet's face with a group of curves inside it that one curve joins to
    its border (a shield's stud drawn on its plate) is its border and that group's outline. A
    face with no bridge is ([face], {}). (Every edge the face walks twice is returned, also one
    whose two walks a cut at another edge parts: walks e, g, e', g' cut at e leave g in each.)"""
    twice = {e for e, n in Counter(e for e, _ in face).items() if n > 1}
    out, stack = [], [list(face)]
    while stack:
        f = stack.pop()
        first: dict = {}
        for k, (e, _) in enumerate(f):
            if e in first:                # walked back along e: A = f[:i], B = f[i + 1:k], C = f[k + 1:]
                i = first[e]
                stack += [f[k + 1:] + f[:i], f[i + 1:k]]
                break
            first[e] = k
        else:
            if f:
                out.append(f)
    return out, twice


def vector_area(points: FloatArray) -> FloatArray:
    """3D vector area (3,) of the closed polygon `points` (n, 3), about its mean: its direction
    says which way round it runs."""
    c = points.mean(axis=0)
    q = points - c
    return 0.5 * np.cross(q, np.roll(q, -1, axis=0)).sum(axis=0)


def _alignment(graph: StrokeGraph, face: list, normals: dict, straight: frozenset = frozenset()) -> float:
    """How well a face's vector area agrees with its nodes' normals: the mean of their dot products
    with its unit vector area (0 when it has no area or no node normal). Nodes in `straight` (two
    edges running on nearly in line: _straight_nodes) count only when the face has no other."""
    pts = np.vstack([(graph.edges[e].points[::-1] if r else graph.edges[e].points)[:-1] for e, r in face])
    area = vector_area(pts)
    norm = np.linalg.norm(area)
    nodes = [graph.edges[e].node1 if r else graph.edges[e].node0 for e, r in face]
    if any(n not in straight for n in nodes):
        nodes = [n for n in nodes if n not in straight]
    ns = [normals[n] for n in nodes if n in normals]
    return float(np.mean([n @ area / norm for n in ns])) if ns and norm > 0 else 0.0


def _straight_nodes(half: dict) -> frozenset:
    """Nodes of two edges that run on within STRAIGHT_DEG of one line (a stroke drawn in two parts,
    two strokes meeting end to end): the plane of their two directions, their normal, says
    little of the surface there, and one such normal turned the wrong way left a face of a body
    out (alignment 0.30 with it, 0.74 without)."""
    limit = -np.cos(np.radians(STRAIGHT_DEG))
    return frozenset(n for n, hs in half.items() if len(hs) == 2 and float(hs[0][2] @ hs[1][2]) <= limit)


def find_cycles(graph: StrokeGraph) -> CycleChoice:
    """The cycles of the stroke network that bound surfaces (module docstring)."""
    live = _prune(graph)
    half = _half_edges(graph, live)
    leaving = {(n, e, r): t for n, hs in half.items() for e, r, t in hs}
    normals = _flip_weak(graph, half, _oriented_normals(graph, half), leaving)
    straight = _straight_nodes(half)
    faces = _faces(graph, _rotation(half, normals))
    parts = _parts(graph, live)
    part_of = {k: p for p, edges in enumerate(parts) for k in edges}
    bridges: set = set()
    cut: set = set()                      # the loops of faces cut at a bridge
    scored: dict = {}
    for face in faces:
        # a face that walks an edge both ways: that edge is a bridge and bounds nothing, but the
        # face round it does, without it (_cut_bridges)
        walks, twice = _cut_bridges(face)
        bridges |= twice
        for walk in walks:
            cycle = Cycle(tuple(walk), _alignment(graph, walk, normals, straight))
            if twice:
                cut.add(cycle.sides)
            scored.setdefault(part_of[walk[0][0]], []).append(cycle)
    chosen, dropped = [], []
    for p in sorted(scored):
        cycles = scored[p]
        if len(cycles) == 2 and cycles[0].edge_ids == cycles[1].edge_ids:
            # one loop and nothing else: the same cycle both ways round; keep one
            keep = max(cycles, key=lambda c: c.align)
            chosen.append(Cycle(keep.sides, abs(keep.align)))
            continue
        votes = sum(np.sign(c.align) for c in cycles if abs(c.align) >= ALIGN_MIN)
        sign = 1.0 if votes >= 0 else -1.0
        for c in cycles:
            a = sign * c.align
            if a >= ALIGN_MIN:
                for loop in _pinched(graph, list(c.sides)):
                    if len(loop) == len(c.sides):
                        chosen.append(Cycle(c.sides, a))
                        continue
                    b = sign * _alignment(graph, loop, normals, straight)
                    if b >= ALIGN_MIN or (len(loop) == 1 and b > 0):
                        # a closed stroke met at one node only (a wheel drawn touching a body) has
                        # one node normal to judge it by, which says little of its plane: the
                        # way round that agrees with it is taken
                        chosen.append(Cycle(tuple(loop), b))
                    else:
                        dropped.append((Cycle(tuple(loop), b), "a loop of a face that passes through one of "
                                        f"its nodes twice; it spans no surface (alignment {b:.2f})"))
            elif a <= -ALIGN_MIN:
                dropped.append((c, "outer face of an open sheet: it runs the other way round the node normals"
                                if c.sides not in cut else
                                "outer face of an open sheet or of curves that one curve (a bridge) joins to "
                                "the rest: it runs the other way round the node normals"))
            elif abs(sign * _turning(graph, list(c.sides), normals, leaving) - 1.0) <= TURN_DISC_TOL:
                # a strip that turns round a lip: its nodes' normals point every way round its
                # vector area, yet at each corner it turns as a disc does
                chosen.append(Cycle(c.sides, a))
            else:
                dropped.append((c, f"spans no surface: its nodes' normals lie along it (alignment {a:.2f})"))
    dangling = frozenset({e.id for e in graph.edges} - live) | frozenset(bridges)
    return CycleChoice(tuple(chosen), tuple(dropped), dangling, normals, tuple(frozenset(p) for p in parts),
                       frozenset(bridges))
