"""The derived views of the pre-image plane network (Qin & Wright section 3, Fig. 4-5).

Holds what the network's records look like to their readers: one edge (:class:`EdgeView`), one
side of a region as a chain of edges (:class:`SideView`) and one 3- or 4-sided region with its
corners in Coons order (:class:`RegionView`, the four boundary curves of Eq. 1; a triangle is the
special case of Fig. 4 with a collapsed side), the 3D segments of every edge, and the one
:class:`ViewCache` a network keeps them in between calls. :class:`NetworkViews` is the part of
:class:`~ProgSurf.core.network.PatchNetwork` that makes them.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Iterable, Optional

import numpy as np

from .strokes import APEX_TIE_DEG, chord_length, corner_angle_deg
from .types import FloatArray, Polyline

OUTER_CURVES = (0, 1, 2, 3)
"""Curve ids of the outer sides: bottom p(u,0), right p(1,v), top p(u,1), left p(0,v)."""


@dataclass(frozen=True)
class EdgeView:
    """One edge of the network: a piece of a boundary curve between two nodes.

    id       : edge id (stable while the edge exists)
    curve_id : the curve it belongs to (0-3 the outer sides bottom/right/top/left, then strokes)
    node0, node1 : node ids at its ends
    uv0, uv1 : (2,) pre-image end points; the pre-image is the straight segment uv0-uv1
    polyline : 3D points (n,3), params (n,) 0..1 along uv0->uv1
    """

    id: int
    curve_id: int
    node0: int
    node1: int
    uv0: FloatArray
    uv1: FloatArray
    polyline: Polyline


@dataclass(frozen=True)
class SideView:
    """One side of a region: a chain of edges (edge_id, reversed) and its concatenated polyline.

    Degenerate (the collapsed side of a triangle): ``edges`` is empty and the polyline is
    two copies of one point.
    """

    edges: tuple
    polyline: Polyline

    @property
    def degenerate(self) -> bool:
        return len(self.edges) == 0


@dataclass(frozen=True)
class RegionView:
    """A 3- or 4-sided region of the pre-image plane and its Coons sub-patch.

    corners_uv : (4, 2) c0, c1, c2, c3 (a triangle has c3 == c2)
    corners_xyz: (4, 3)
    sides      : (bottom c0->c1, right c1->c2, top c3->c2, left c0->c3), SideView each
    triangle   : True for a 3-sided region (top side degenerate)
    """

    id: int
    corners_uv: FloatArray
    corners_xyz: FloatArray
    sides: tuple
    triangle: bool


EdgeSegments = tuple
"""All 3D segments of all edge polylines, one row per segment: A (S,3), B (S,3), edge id (S,),
t0, t1 (S,) the edge parameters at A and B, outer (S,) whether the edge is on the outer boundary."""


class ViewCache:
    """Derived data a network keeps between calls. Every entry is checked against the records it
    was made from (by identity) before it is used, so a clone may start from its original's.

    edges_now    : the edges() answer {edge id: EdgeView} until nodes, edges or regions change
    edge_views   : edge id -> (edge record, node0 record, node1 record, EdgeView)
    segments     : edge id -> (EdgeView, A, B, edge ids, t0, t1, outer), its rows of EdgeSegments
    region_views : region id -> (region record, its cycle's node records, edge records, RegionView)
    polygons     : region id -> (region record, polygon (n,2), edge directions (n,2))
    locator      : (regions key, half-planes of every region) for locate_many
    joined       : (region ids, facet parts, Facets) for facets()
    boxes        : (facet parts, (R, 2, 3) bounding boxes) for footpoint()
    apexes       : region id -> (region record, edge records along its cycle, apex index) of a
                   3-sided region (NetworkViews._triangle_apex)
    quad_corners : region id -> (region record, its corners' node records, corner ids in Coons
                   order) of a 4-sided region (NetworkViews.region_corners)
    """

    __slots__ = ("edges_now", "edge_views", "segments", "region_views", "polygons", "locator",
                 "joined", "boxes", "apexes", "quad_corners")

    def __init__(self) -> None:
        self.edges_now: Optional[dict] = None
        self.edge_views: dict = {}
        self.segments: dict = {}
        self.region_views: dict = {}
        self.polygons: dict = {}
        self.locator: Optional[tuple] = None
        self.joined: Optional[tuple] = None
        self.boxes: Optional[tuple] = None
        self.apexes: dict = {}
        self.quad_corners: dict = {}

    def copy(self) -> "ViewCache":
        """A cache for a clone: the per-id tables copied (each network adds its own entries), the
        rest shared (replaced, never changed in place); edges_now is not carried over."""
        other = ViewCache()
        other.edge_views, other.segments = dict(self.edge_views), dict(self.segments)
        other.region_views, other.polygons = dict(self.region_views), dict(self.polygons)
        other.apexes, other.quad_corners = dict(self.apexes), dict(self.quad_corners)
        other.locator, other.joined, other.boxes = self.locator, self.joined, self.boxes
        return other


def pruned(table: dict, live: Iterable) -> dict:
    """`table` (keyed by region or edge id); once it holds more than twice the live ids, a copy
    without the entries of removed ones."""
    if len(table) > 2 * len(live) + 64:
        return {k: table[k] for k in live if k in table}
    return table


def _join_sides(chain: list[tuple[Polyline, float, float]]) -> Polyline:
    """Concatenate polylines, each mapped to the side parameter interval [a, b]."""
    pts, prm = [], []
    for k, (poly, a, b) in enumerate(chain):
        p = poly.points
        q = a + poly.params * (b - a)
        if k > 0:
            p, q = p[1:], q[1:]
        pts.append(p)
        prm.append(q)
    points = np.vstack(pts)
    params = np.concatenate(prm)
    params[0], params[-1] = 0.0, 1.0
    return Polyline(points, np.maximum.accumulate(params))


POINT_SIDE = 1e-6
"""A region's side shorter than this fraction of its longest side is a point in 3D (NetworkViews.lens)."""


class NetworkViews:
    """The views of :class:`~ProgSurf.core.network.PatchNetwork` (mixed into it): reads its
    records ``_nodes``, ``_edges``, ``_regions``, ``_edge_index`` and keeps what it makes in its
    ``_view_cache``."""

    def region_polygon(self, rid: int) -> FloatArray:
        """(n, 2) the region's cycle in the pre-image plane, counter-clockwise."""
        return np.array([self._nodes[n].uv for n in self._regions[rid].cycle])

    def region_corners(self, rid: int) -> tuple[tuple, bool]:
        """Corner node ids c0, c1, c2, c3 (c3 == c2 for a triangle) in Coons order, and triangle."""
        reg = self._regions[rid]
        k = reg.corners
        if len(k) == 4:
            nodes = tuple(self._nodes[n] for n in k)
            cache = self._view_cache.quad_corners = pruned(self._view_cache.quad_corners, self._regions)
            hit = cache.get(rid)
            if hit is not None and hit[0] is reg and all(x is y for x, y in zip(hit[1], nodes)):
                return hit[2], False
            uv = np.array([n.uv for n in nodes])
            start = int(np.argmin(uv[:, 0] + uv[:, 1] + 1e-9 * np.arange(4)))
            k = k[start:] + k[:start]
            cache[rid] = (reg, nodes, (k[0], k[1], k[2], k[3]))
            return (k[0], k[1], k[2], k[3]), False
        # Triangle: the apex that collapses (Fig. 4) is its sharpest corner in 3D; the side
        # opposite it is the bottom.
        i = (self._triangle_apex(rid, k) + 1) % 3
        return (k[i], k[(i + 1) % 3], k[(i + 2) % 3], k[(i + 2) % 3]), True

    def _triangle_apex(self, rid: int, k: tuple) -> int:
        """Index (0-2) in k of the corner a 3-sided region collapses at: its sharpest corner in
        3D, where the two sides leave it at the smallest angle. A 3-sided Coons patch
        collapsed anywhere else squeezes a sharp corner between a regular bottom and side, and
        turns over there (a sliver). Near ties (within APEX_TIE_DEG) keep the pre-image rule:
        the apex opposite the longest pre-image side."""
        reg = self._regions[rid]
        cache = self._view_cache.apexes = pruned(self._view_cache.apexes, self._regions)
        index = self._edge_index
        cyc = reg.cycle
        edges = tuple(self._edges[index[(a, b)][0]] for a, b in zip(cyc, cyc[1:] + cyc[:1]))
        hit = cache.get(rid)
        if hit is not None and hit[0] is reg and len(hit[1]) == len(edges) and all(x is y for x, y in zip(hit[1], edges)):
            return hit[2]
        uv = np.array([self._nodes[n].uv for n in k])
        lengths = [np.linalg.norm(uv[(i + 1) % 3] - uv[i]) for i in range(3)]
        default = (int(np.argmax(lengths)) + 2) % 3
        angles = [corner_angle_deg(self._side_points(rid, k[i], k[(i + 1) % 3]),
                                    self._side_points(rid, k[i], k[(i + 2) % 3])) for i in range(3)]
        best = int(np.argmin(angles))
        apex = best if angles[best] < angles[default] - APEX_TIE_DEG else default
        cache[rid] = (reg, edges, apex)
        return apex

    def lens(self, rid: int) -> Optional[tuple[int, int, int]]:
        """(a, b, q) when region rid is a lens: 3-sided, its side from corner a to corner b (in
        cycle order) a point in 3D (shorter than POINT_SIDE of its longest side), q its third
        corner. Two curves that end at a 3-sided sketch's apex (its collapsed boundary side) and
        cross at q bound it. Collapsed at any corner, its Coons patch has a collapsed side
        opposite too, hence no cross derivative along either curve; with either tip as a
        regular corner, it squeezes the sharp tip between two sides and turns over (see
        core.fold_repair.split_lens). None otherwise."""
        k = self._regions[rid].corners
        if len(k) != 3:
            return None
        length = [chord_length(self._side_points(rid, k[i], k[(i + 1) % 3])) for i in range(3)]
        point = [j for j in range(3) if length[j] <= POINT_SIDE * max(length)]
        if len(point) != 1:
            return None
        j = point[0]
        return k[j], k[(j + 1) % 3], k[(j + 2) % 3]

    def _walk(self, rid: int, a: int, b: int) -> list[int]:
        """Nodes of the region's cycle from corner a to corner b (either direction, along the
        side that joins them without passing another corner)."""
        cyc = list(self._regions[rid].cycle)
        corners = set(self._regions[rid].corners)
        n = len(cyc)
        for step in (1, -1):
            i = cyc.index(a)
            path = [a]
            while True:
                i = (i + step) % n
                path.append(cyc[i])
                if cyc[i] == b:
                    return path
                if cyc[i] in corners:
                    break
        raise RuntimeError(f"nodes {a} and {b} are not adjacent corners of region {rid}")

    def _side_points(self, rid: int, a: int, b: int) -> FloatArray:
        """(n, 3) the points of _side(rid, a, b).polyline (a != b), without its parameters."""
        path = self._walk(rid, a, b)
        pts = []
        for k in range(len(path) - 1):
            eid, rev = self.edge_between(path[k], path[k + 1])
            p = self._edges[eid].polyline.points
            p = p[::-1] if rev else p
            pts.append(p[1:] if k > 0 else p)
        return np.concatenate(pts)

    def _side(self, rid: int, a: int, b: int) -> SideView:
        if a == b:
            p = self._nodes[a].xyz
            return SideView((), Polyline(np.vstack([p, p]), np.array([0.0, 1.0])))
        path = self._walk(rid, a, b)
        ua, ub = self._nodes[a].uv, self._nodes[b].uv
        d = ub - ua
        dd = float(d @ d)
        pos = [float((self._nodes[n].uv - ua) @ d / dd) for n in path]
        pos[0], pos[-1] = 0.0, 1.0
        edges, chain = [], []
        for k in range(len(path) - 1):
            eid, rev = self.edge_between(path[k], path[k + 1])
            poly = self._edges[eid].polyline
            chain.append((poly.reversed() if rev else poly, pos[k], pos[k + 1]))
            edges.append((eid, rev))
        return SideView(tuple(edges), _join_sides(chain))

    def region(self, rid: int) -> RegionView:
        """The view of one region (see :class:`RegionView`), kept while its record, the nodes
        of its cycle and the edges along it are the same objects."""
        reg = self._regions[rid]
        cyc = reg.cycle
        nodes = tuple(self._nodes[n] for n in cyc)
        index = self._edge_index
        edges = tuple(self._edges[index[(a, b)][0]] for a, b in zip(cyc, cyc[1:] + cyc[:1]))
        cache = self._view_cache
        views = cache.region_views = pruned(cache.region_views, self._regions)
        c = views.get(rid)
        if (c is not None and c[0] is reg and len(c[1]) == len(nodes)
                and all(x is y for x, y in zip(c[1], nodes)) and all(x is y for x, y in zip(c[2], edges))):
            return c[3]
        view = self._region_view(rid)
        views[rid] = (reg, nodes, edges, view)
        return view

    def _region_view(self, rid: int) -> RegionView:
        (c0, c1, c2, c3), tri = self.region_corners(rid)
        sides = (self._side(rid, c0, c1), self._side(rid, c1, c2),
                 self._side(rid, c3, c2), self._side(rid, c0, c3))
        ids = (c0, c1, c2, c3)
        return RegionView(rid, np.array([self._nodes[n].uv for n in ids]),
                          np.array([self._nodes[n].xyz for n in ids]), sides, tri)

    def regions(self) -> list[RegionView]:
        return [self.region(rid) for rid in self._regions]

    def edges(self) -> dict[int, EdgeView]:
        """Edge id -> EdgeView. Views are kept per edge while its (immutable) record and end nodes
        are the same objects: a stroke touches a few edges, so most views are reused."""
        cache = self._view_cache
        if cache.edges_now is not None:
            return dict(cache.edges_now)          # a copy: callers may not change the cached one
        views = cache.edge_views = pruned(cache.edge_views, self._edges)
        nodes = self._nodes
        out = {}
        for eid, e in self._edges.items():
            n0, n1 = nodes[e.n0], nodes[e.n1]
            c = views.get(eid)
            if c is None or c[0] is not e or c[1] is not n0 or c[2] is not n1:
                c = (e, n0, n1, EdgeView(eid, e.curve_id, e.n0, e.n1, n0.uv, n1.uv, e.polyline))
                views[eid] = c
            out[eid] = c[3]
        cache.edges_now = out
        return dict(out)

    def edge_segments(self) -> EdgeSegments:
        """All 3D segments of all edge polylines (see :data:`EdgeSegments`), for the snap test of
        step (2). Each edge's rows are kept while its view is the same object (a stroke changes a
        few edges; the rest are only joined)."""
        edges = self.edges()
        cache = self._view_cache
        rows = cache.segments = pruned(cache.segments, edges)
        parts = []
        for k, e in edges.items():
            c = rows.get(k)
            if c is None or c[0] is not e:
                p, q = e.polyline.points, e.polyline.params
                n = len(p) - 1
                c = (e, p[:-1], p[1:], np.full(n, k), q[:-1], q[1:], np.full(n, e.curve_id in OUTER_CURVES))
                rows[k] = c
            parts.append(c)
        return tuple(np.concatenate([c[i] for c in parts]) for i in range(1, 7))

    def curve_edges(self, curve_id: int) -> list[int]:
        """Ids of the edges that are pieces of curve curve_id."""
        return [eid for eid, e in self._edges.items() if e.curve_id == curve_id]

    def edge_regions(self) -> dict[int, list[int]]:
        """Edge id -> the ids of the (one or two) regions whose cycle uses it."""
        out: dict[int, list[int]] = {eid: [] for eid in self._edges}
        index = self._edge_index
        for rid, reg in self._regions.items():
            cyc = reg.cycle
            for a, b in zip(cyc, cyc[1:] + cyc[:1]):
                out[index[(a, b)][0]].append(rid)
        return out
