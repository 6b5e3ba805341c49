"""The pre-image plane network of Qin & Wright section 3: regions, shared edges, sub-patches."""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from .coons import CoonsPatch
from .footpoint import Facets, Footpoint, footpoint, prepare, real_footpoint
from .preimage import bilinear, cross2, inverse_bilinear, polygon_area, turning_corners
from .types import FloatArray, Polyline


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


# --------------------------------------------------------------------------------------------
# Internal state. Everything is immutable and replaced on change, so a snapshot of the network
# (for the "a failed stroke leaves the network exactly as it was" guarantee) is a shallow copy.
# --------------------------------------------------------------------------------------------

OUTER_CURVES = (0, 1, 2, 3)
"""Curve ids of the outer sides: bottom p(u,0), right p(1,v), top p(u,1), left p(0,v)."""


@dataclass(frozen=True)
class _Node:
    uv: FloatArray
    xyz: FloatArray


@dataclass(frozen=True)
class _Edge:
    n0: int
    n1: int
    curve_id: int
    polyline: Polyline


@dataclass(frozen=True)
class _Region:
    cycle: tuple      # node ids, counter-clockwise in the pre-image plane
    corners: tuple    # 3 or 4 node ids of the cycle, in cycle order


def _ramp(poly: Polyline, delta0: FloatArray, delta1: FloatArray) -> Polyline:
    """Add the linear distribution of delta0 at params 0 and delta1 at 1 (Qin & Wright step 4:
    "the positional difference vector will be distributed gradually")."""
    t = poly.params[:, None]
    return Polyline(poly.points + (1.0 - t) * delta0 + t * delta1, poly.params)


def _split_polyline(poly: Polyline, t: float, point: FloatArray) -> tuple[Polyline, Polyline]:
    """Split at parameter t, inserting ``point`` there; each half re-parameterised to 0..1."""
    prm, pts = poly.params, poly.points
    lo = prm < t - 1e-12
    hi = prm > t + 1e-12
    a_pts = np.vstack([pts[lo], point])
    a_prm = np.append(prm[lo], t) / t
    b_pts = np.vstack([point, pts[hi]])
    b_prm = (np.insert(prm[hi], 0, t) - t) / (1.0 - t)
    return Polyline(a_pts, a_prm), Polyline(b_pts, b_prm)


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


NEAR_REGIONS = 4
"""Footpoints are first searched in this many regions nearest (by bounding box) to the point."""


@lru_cache(maxsize=8)
def _grid_triangles(n: int) -> tuple:
    """The two triangles of each cell of an (n+1) x (n+1) grid, as index pairs of their corners."""
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    i, j = i.ravel(), j.ravel()
    return (((i, j), (i + 1, j), (i, j + 1)), ((i + 1, j + 1), (i, j + 1), (i + 1, j)))


class _FacetPart:
    """One region's piece of the footpoint facets: (xyz (F,3,3), uv (F,3,2), solver, owner (F,),
    bounding box (2,3)) by index, as a tuple would be. The box comes from the evaluated grid at
    once; the triangles and their Eq. 2 inverses only when first asked for (a footpoint search
    reads the boxes of every region but the facets of the few near the point)."""

    __slots__ = ("rid", "grid_xyz", "grid_uv", "box", "_full")

    def __init__(self, rid: int, grid_xyz: FloatArray, grid_uv: FloatArray):
        self.rid, self.grid_xyz, self.grid_uv = rid, grid_xyz, grid_uv
        flat = grid_xyz.reshape(-1, 3)
        self.box = np.stack([flat.min(axis=0), flat.max(axis=0)])
        self._full = None

    def __getitem__(self, k: int):
        if k == 4:
            return self.box
        if self._full is None:
            tris = _grid_triangles(self.grid_xyz.shape[0] - 1)
            p, q = self.grid_xyz, self.grid_uv
            fx = np.concatenate([np.stack([p[a, b] for a, b in t], axis=1) for t in tris])
            fu = np.concatenate([np.stack([q[a, b] for a, b in t], axis=1) for t in tris])
            self._full = (fx, fu, prepare(fx), np.full(len(fx), self.rid))
        return self._full[k]


def _join_parts(parts: list) -> Facets:
    """Facets of per-region pieces (network._facet_parts), joined in the given order."""
    return Facets(np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts]),
                  np.concatenate([p[3] for p in parts]),
                  tuple(np.concatenate([p[2][k] for p in parts]) for k in range(3)))


class PatchNetwork:
    """The progressive patch network of Qin & Wright section 3: the pre-image plane (the unit
    square) divided into convex 3/4-sided regions, each carrying a bicubically blended Coons
    sub-patch (Eq. 1) of its four sides. Sides are chains of edges; an edge is a piece of one
    curve (an outer side or an accepted stroke) and its 3D polyline is shared, as one object,
    by the regions on both sides of it, so the network has no gaps by construction.
    """

    def __init__(self, bottom: FloatArray, right: FloatArray, top: FloatArray, left: FloatArray,
                 mesh_density: int = 8) -> None:
        """The base surface from a closed 4-sided boundary (bottom c0->c1, right c1->c2,
        top c3->c2, left c0->c3), mapped to the unit square by point index (paper 2.1).
        A side given as a Polyline keeps its own parameters instead."""
        given = (bottom, right, top, left)
        sides = [s.points if isinstance(s, Polyline) else np.asarray(s, dtype=float).reshape(-1, 3) for s in given]
        params = [s.params if isinstance(s, Polyline) else None for s in given]
        self.mesh_density = int(mesh_density)
        self._nodes: dict[int, _Node] = {}
        self._edges: dict[int, _Edge] = {}
        self._regions: dict[int, _Region] = {}
        self._next = {"node": 0, "edge": 0, "region": 0, "curve": 4}
        self._curves: dict[int, dict] = {k: {"kind": "outer", "stroke": None} for k in OUTER_CURVES}
        self._edge_index: dict[tuple, tuple] = {}
        self._patches: dict[int, tuple] = {}      # region id -> (CoonsPatch, RegionView)
        self._facets: dict[int, tuple] = {}       # region id -> (xyz, uv)
        self._log: list = []                      # ("created"|"removed", region id) since last clear
        uv = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
        xyz = np.array([sides[0][0], sides[0][-1], sides[2][-1], sides[2][0]])
        c = [self._add_node(uv[k], xyz[k]) for k in range(4)]
        ends = [(c[0], c[1]), (c[1], c[2]), (c[3], c[2]), (c[0], c[3])]
        for curve_id, (side, (a, b)) in enumerate(zip(sides, ends)):
            prm = np.linspace(0.0, 1.0, len(side)) if len(side) > 1 else np.array([0.0, 1.0])
            if params[curve_id] is not None and len(side) > 1:
                prm = params[curve_id]
            pts = side if len(side) > 1 else np.vstack([side, side])
            poly = _ramp(Polyline(pts, prm), self._nodes[a].xyz - pts[0], self._nodes[b].xyz - pts[-1])
            self._add_edge(a, b, curve_id, poly)
        self._add_region((c[0], c[1], c[2], c[3]))

    # ---------------------------------------------------------------- state, snapshots
    _STATE = ("_nodes", "_edges", "_regions", "_next", "_curves", "_edge_index", "_patches", "_facets")

    def snapshot(self) -> tuple:
        """An opaque copy of the state; :meth:`restore` brings it back exactly."""
        return tuple(dict(getattr(self, name)) for name in self._STATE)

    def restore(self, snap: tuple) -> None:
        for name, value in zip(self._STATE, snap):
            setattr(self, name, dict(value))
        self._log = []
        self._changed()

    def _changed(self) -> None:
        """Record that nodes, edges or regions changed (edges() keeps its views until then)."""
        self.__dict__["_version"] = self.__dict__.get("_version", 0) + 1

    _VIEW_CACHES = ("_views", "_polys", "_region_views", "_located", "_joined", "_boxes_cache", "_segments")
    """Derived data kept between calls; every entry is checked against the records it was made
    from (by identity) before use, so a clone may start from its original's."""

    def derived(self, name: str, live) -> dict:
        """The derived-data dict `name` (one of _VIEW_CACHES, keyed by region or edge id). Once it
        holds more than twice the live ids, the entries of removed ones are dropped."""
        cache = self.__dict__.setdefault(name, {})
        if len(cache) > 2 * len(live) + 64:
            cache = self.__dict__[name] = {k: cache[k] for k in live if k in cache}
        return cache

    def clone(self) -> "PatchNetwork":
        """An independent copy that shares the immutable pieces (and the derived views)."""
        other = object.__new__(PatchNetwork)
        other.mesh_density = self.mesh_density
        other.restore(self.snapshot())
        for name in self._VIEW_CACHES:
            value = self.__dict__.get(name)
            if value is not None:
                other.__dict__[name] = dict(value) if isinstance(value, dict) else value
        return other

    def new_curve_id(self, kind: str, stroke: int | None = None) -> int:
        cid = self._next["curve"]
        self._next["curve"] += 1
        self._curves[cid] = {"kind": kind, "stroke": stroke}
        return cid

    def curve_info(self, curve_id: int) -> dict:
        """{"kind": "outer"|"stroke"|"split", "stroke": input stroke index or None}."""
        return dict(self._curves[curve_id])

    def _new_id(self, kind: str) -> int:
        i = self._next[kind]
        self._next[kind] = i + 1
        return i

    def _add_node(self, uv: FloatArray, xyz: FloatArray) -> int:
        nid = self._new_id("node")
        self._nodes[nid] = _Node(np.array(uv, dtype=float), np.array(xyz, dtype=float))
        self._changed()
        return nid

    def _add_edge(self, a: int, b: int, curve_id: int, poly: Polyline) -> int:
        eid = self._new_id("edge")
        self._edges[eid] = _Edge(a, b, curve_id, poly)
        self._changed()
        self._edge_index[(a, b)] = (eid, False)
        self._edge_index[(b, a)] = (eid, True)
        return eid

    def _remove_edge(self, eid: int) -> _Edge:
        e = self._edges.pop(eid)
        self._changed()
        self._edge_index.pop((e.n0, e.n1), None)
        self._edge_index.pop((e.n1, e.n0), None)
        return e

    def _add_region(self, cycle: tuple) -> int:
        rid = self._new_id("region")
        poly = np.array([self._nodes[n].uv for n in cycle])
        idx = [i for i in turning_corners(poly)]
        self._regions[rid] = _Region(tuple(cycle), tuple(cycle[i] for i in idx))
        self._changed()
        self._log.append(("created", rid))
        return rid

    def _remove_region(self, rid: int) -> _Region:
        self._log.append(("removed", rid))
        self._dirty([rid])
        self._changed()
        return self._regions.pop(rid)

    def _dirty(self, rids) -> None:
        for rid in rids:
            self._patches.pop(rid, None)
            self._facets.pop(rid, None)

    def regions_with_edge(self, a: int, b: int) -> list[int]:
        """Ids of the regions whose cycle runs along the edge a-b (either direction)."""
        out = []
        for rid, reg in self._regions.items():
            cyc = reg.cycle
            if a not in cyc or b not in cyc:
                continue
            n = len(cyc)
            for k in range(n):
                if {cyc[k], cyc[(k + 1) % n]} == {a, b}:
                    out.append(rid)
                    break
        return out

    # ---------------------------------------------------------------- queries
    @property
    def region_ids(self) -> list[int]:
        return list(self._regions)

    def __len__(self) -> int:
        return len(self._regions)

    def node_uv(self, nid: int) -> FloatArray:
        return self._nodes[nid].uv

    def node_xyz(self, nid: int) -> FloatArray:
        return self._nodes[nid].xyz

    def edge_between(self, a: int, b: int) -> tuple[int, bool]:
        """(edge id, reversed) of the edge joining nodes a and b."""
        return self._edge_index[(a, b)]

    def region_polygon(self, rid: int) -> FloatArray:
        """(n, 2) the region's cycle in the pre-image plane, counter-clockwise."""
        return np.array([self._nodes[n].uv for n in self._regions[rid].cycle])

    def region_corners(self, rid: int) -> tuple[tuple, bool]:
        """Corner node ids c0, c1, c2, c3 (c3 == c2 for a triangle) in Coons order, and triangle."""
        reg = self._regions[rid]
        k = reg.corners
        if len(k) == 4:
            uv = np.array([self._nodes[n].uv for n in k])
            start = int(np.argmin(uv[:, 0] + uv[:, 1] + 1e-9 * np.arange(4)))
            k = k[start:] + k[:start]
            return (k[0], k[1], k[2], k[3]), False
        # Triangle: the bottom is its longest side in the pre-image, the apex collapses (Fig. 4).
        uv = np.array([self._nodes[n].uv for n in k])
        lengths = [np.linalg.norm(uv[(i + 1) % 3] - uv[i]) for i in range(3)]
        i = int(np.argmax(lengths))
        return (k[i], k[(i + 1) % 3], k[(i + 2) % 3], k[(i + 2) % 3]), True

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
        views = self.derived("_region_views", self._regions)
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
        version = self.__dict__.get("_version", 0)
        last = self.__dict__.get("_edges_view")
        if last is not None and last[0] == version:
            return dict(last[1])                  # a copy: callers may not change the cached one
        views = self.derived("_views", self._edges)
        nodes = self._nodes
        out = {}
        for eid, e in self._edges.items():
            n0, n1 = nodes[e.n0], nodes[e.n1]
            c = views.get(eid)
            if c is None or c[0] is not e or c[1] is not n0 or c[2] is not n1:
                c = (e, n0, n1, EdgeView(eid, e.curve_id, e.n0, e.n1, n0.uv, n1.uv, e.polyline))
                views[eid] = c
            out[eid] = c[3]
        self.__dict__["_edges_view"] = (version, out)
        return dict(out)

    def curve_edges(self, curve_id: int) -> list[int]:
        return [eid for eid, e in self._edges.items() if e.curve_id == curve_id]

    def edge_regions(self) -> dict[int, list[int]]:
        """Edge id -> the ids of the (one or two) regions whose cycle uses it."""
        out: dict[int, list[int]] = {eid: [] for eid in self._edges}
        for rid, reg in self._regions.items():
            cyc = reg.cycle
            for k in range(len(cyc)):
                eid, _ = self.edge_between(cyc[k], cyc[(k + 1) % len(cyc)])
                out[eid].append(rid)
        return out

    # ---------------------------------------------------------------- evaluation
    def patch(self, rid: int) -> CoonsPatch:
        """The Coons sub-patch (Eq. 1) of region rid in its local (s, r)."""
        if rid not in self._patches:
            view = self.region(rid)
            b, r, t, l = (s.polyline for s in view.sides)
            self._patches[rid] = (CoonsPatch(b.evaluate, r.evaluate, t.evaluate, l.evaluate), view)
        return self._patches[rid][0]

    def evaluate_region(self, rid: int, s, r) -> FloatArray:
        """3D points of region rid's Coons sub-patch at local (s, r) in [0,1]^2; (..., 3)."""
        return self.patch(rid).evaluate(s, r)

    def local_to_uv(self, rid: int, s, r) -> FloatArray:
        (c0, c1, c2, c3), _ = self.region_corners(rid)
        corners = np.array([self._nodes[n].uv for n in (c0, c1, c2, c3)])
        return bilinear(corners, s, r)

    def uv_to_local(self, rid: int, uv: FloatArray) -> tuple[FloatArray, FloatArray]:
        ids, tri = self.region_corners(rid)
        corners = np.array([self._nodes[n].uv for n in ids])
        return inverse_bilinear(corners, np.atleast_2d(uv), tri)

    def _locator(self) -> tuple:
        """All region edges as half-planes, (start (E,2), direction (E,2), 1/length (E,)), with
        the region id and offset of each region's run: rebuilt only when a region changed."""
        cached = getattr(self, "_located", None)
        key = tuple(self._regions.items())
        if cached is not None and cached[0] == key:
            return cached[1]
        starts, dirs, owners, offsets = [], [], [], []
        count = 0
        polys = self.derived("_polys", self._regions)
        for rid, reg in self._regions.items():
            c = polys.get(rid)
            if c is None or c[0] is not reg:      # region records are replaced when they change
                poly = self.region_polygon(rid)
                c = (reg, poly, np.concatenate([poly[1:], poly[:1]]) - poly)
                polys[rid] = c
            starts.append(c[1])
            dirs.append(c[2])
            owners.append(rid)
            offsets.append(count)
            count += len(c[1])
        a = np.concatenate(starts)
        d = np.concatenate(dirs)
        inv = 1.0 / np.maximum(np.linalg.norm(d, axis=1), 1e-300)
        value = (a, d, inv, np.array(owners), np.array(offsets))
        self._located = (key, value)
        return value

    def locate(self, uv: FloatArray) -> int:
        """Id of the region whose polygon contains the pre-image point uv (2,) (the nearest one
        for a point just outside every polygon)."""
        return int(self.locate_many(np.reshape(uv, (1, 2)))[0])

    def locate_many(self, uv: FloatArray) -> np.ndarray:
        """locate() for points uv (k, 2) at once: region ids (k,)."""
        uv = np.clip(np.asarray(uv, dtype=float).reshape(-1, 2), 0.0, 1.0)
        a, d, inv, owners, offsets = self._locator()
        side = cross2(d[None, :, :], uv[:, None, :] - a[None, :, :]) * inv[None, :]
        depth = np.minimum.reduceat(side, offsets, axis=1)
        inside = depth >= 0
        pick = np.where(inside.any(axis=1), np.argmax(inside, axis=1), np.argmax(depth, axis=1))
        return owners[pick]

    def evaluate_uv(self, uv: FloatArray) -> FloatArray:
        """3D points of the surface at pre-image points uv (k, 2) (or (2,)); (k, 3) or (3,)."""
        uv = np.asarray(uv, dtype=float)
        single = uv.ndim == 1
        uv2 = np.atleast_2d(uv)
        rids = self.locate_many(uv2)
        out = np.empty((len(uv2), 3))
        for rid in np.unique(rids):
            mask = rids == rid
            s, r = self.uv_to_local(int(rid), uv2[mask])
            out[mask] = self.evaluate_region(int(rid), s, r)
        return out[0] if single else out

    def region_grid(self, rid: int, n: int | None = None) -> tuple[FloatArray, FloatArray]:
        """A re-parameterised mesh of the sub-patch: local (s, r) samples that include the side
        parameters of both opposite sides (so opposite sides have equal point counts, paper
        step 4 "re-parameterisation"), thinned to at most 4*n values; returns (s, r) 1-D arrays."""
        n = n or self.mesh_density
        view = self.region(rid)

        def merged(a: Polyline, b: Polyline) -> FloatArray:
            vals = np.unique(np.concatenate([a.params, b.params, np.linspace(0, 1, n + 1)]))
            if len(vals) > 4 * n:
                vals = np.unique(np.concatenate([vals[:: int(np.ceil(len(vals) / (4 * n)))], [1.0]]))
            return vals

        return (merged(view.sides[0].polyline, view.sides[2].polyline),
                merged(view.sides[1].polyline, view.sides[3].polyline))

    def _facet_parts(self) -> list:
        """Per-region facet pieces in region order, (xyz, uv, solver, owner, bounding box); cached
        per region and rebuilt only for regions a stroke changed."""
        missing = [rid for rid in self._regions if rid not in self._facets]
        if missing:
            n = self.mesh_density
            g = np.linspace(0.0, 1.0, n + 1)
            ss, rr = np.meshgrid(g, g, indexing="ij")
            for rid in missing:
                self._facets[rid] = _FacetPart(rid, self.evaluate_region(rid, ss, rr),
                                               self.local_to_uv(rid, ss, rr))
        return [self._facets[rid] for rid in self._regions]

    def facets(self) -> Facets:
        """The triangulated surface used for footpoints (Eq. 2): every region's piece, joined
        (the join is kept until a region changes)."""
        key = tuple(self._regions)
        parts = self._facet_parts()
        joined = self.__dict__.get("_joined")
        if joined is not None and joined[0] == key and all(a is b for a, b in zip(parts, joined[1])):
            return joined[2]
        facets = _join_parts(parts)
        self.__dict__["_joined"] = (key, parts, facets)
        return facets

    def footpoint(self, q: FloatArray, slack: float = 0.0) -> Footpoint:
        """Footpoint of q on the current surface (Eq. 2). The nearest real footpoint is searched
        only among regions whose bounding box can hold one nearer than the best of the nearest
        few regions (same result as searching every facet, in the same order); only when those
        have none is every facet searched."""
        q = np.asarray(q, dtype=float)
        parts = self._facet_parts()
        boxes = self._boxes(parts)
        gap = np.linalg.norm(np.maximum(0.0, np.maximum(boxes[:, 0] - q, q - boxes[:, 1])), axis=1)
        near = np.sort(np.argsort(gap, kind="stable")[:NEAR_REGIONS])
        found = real_footpoint(q, _join_parts([parts[i] for i in near]), slack)
        if found is not None:
            reach = np.flatnonzero(gap <= abs(found.distance) + slack + 1e-9)
            if not set(reach.tolist()) <= set(near.tolist()):
                found = real_footpoint(q, _join_parts([parts[i] for i in reach]), slack)
            return found
        return footpoint(q, self.facets(), slack)

    def _boxes(self, parts: list) -> FloatArray:
        """(R, 2, 3) bounding boxes (min, max) of the regions' facets, kept while the parts are."""
        cached = self.__dict__.get("_boxes_cache")
        if cached is not None and len(cached[0]) == len(parts) and all(a is b for a, b in zip(cached[0], parts)):
            return cached[1]
        boxes = np.stack([p[4] for p in parts])
        self.__dict__["_boxes_cache"] = (parts, boxes)
        return boxes

    # ---------------------------------------------------------------- invariants
    def check(self, tol: float = 1e-9) -> list[str]:
        """Problems with the network's invariants (empty when valid): regions tile the unit
        square without overlap, every region is convex and 3- or 4-sided, every edge has one
        region (outer) or two (interior), edge polylines end exactly at their nodes."""
        problems = []
        area = 0.0
        for rid, reg in self._regions.items():
            poly = self.region_polygon(rid)
            a = polygon_area(poly)
            area += a
            if a <= 0:
                problems.append(f"region {rid} is not counter-clockwise (area {a:.3g})")
            if len(reg.corners) not in (3, 4):
                problems.append(f"region {rid} has {len(reg.corners)} sides")
            edge = np.roll(poly, -1, axis=0) - poly
            if np.any(cross2(edge, np.roll(edge, -1, axis=0)) < -1e-12):
                problems.append(f"region {rid} is not convex")
        if abs(area - 1.0) > 1e-9:
            problems.append(f"regions cover an area of {area:.12f}, not 1")
        for eid, rids in self.edge_regions().items():
            e = self._edges[eid]
            want = 1 if e.curve_id in OUTER_CURVES else 2
            if len(rids) != want:
                problems.append(f"edge {eid} (curve {e.curve_id}) borders {len(rids)} regions, not {want}")
            for node, end in ((e.n0, e.polyline.points[0]), (e.n1, e.polyline.points[-1])):
                if np.linalg.norm(self._nodes[node].xyz - end) > tol:
                    problems.append(f"edge {eid} does not end at node {node}")
        return problems

    # ---------------------------------------------------------------- edits (used by progressive.py)
    def is_outer_node(self, nid: int) -> bool:
        uv = self._nodes[nid].uv
        return bool(np.any(np.minimum(uv, 1.0 - uv) <= 1e-12))

    def incident_edges(self, nid: int) -> list[int]:
        return [eid for eid, e in self._edges.items() if nid in (e.n0, e.n1)]

    def split_edge(self, eid: int, t: float, xyz: FloatArray, pull: bool) -> int:
        """Insert a node on edge eid at parameter t with 3D position xyz; returns its id.

        pull=True first pulls the edge to xyz with the paper's linear distribution of
        delta = xyz - P_k over each side of the split (step 4, "boundary update")."""
        e = self._edges[eid]
        poly = e.polyline
        here = poly.evaluate(t)
        if pull:
            delta = np.asarray(xyz, dtype=float) - here
            tau = poly.params
            hat = np.where(tau <= t, tau / max(t, 1e-300), (1.0 - tau) / max(1.0 - t, 1e-300))
            poly = Polyline(poly.points + hat[:, None] * delta, poly.params)
        else:
            xyz = here
        uv = self._nodes[e.n0].uv + t * (self._nodes[e.n1].uv - self._nodes[e.n0].uv)
        m = self._add_node(uv, xyz)
        first, second = _split_polyline(poly, t, np.asarray(xyz, dtype=float))
        rids = self.regions_with_edge(e.n0, e.n1)
        self._remove_edge(eid)
        self._add_edge(e.n0, m, e.curve_id, first)
        self._add_edge(m, e.n1, e.curve_id, second)
        for rid in rids:
            reg = self._regions[rid]
            cyc = list(reg.cycle)
            n = len(cyc)
            for k in range(n):
                if {cyc[k], cyc[(k + 1) % n]} == {e.n0, e.n1}:
                    cyc.insert(k + 1, m)
                    break
            self._regions[rid] = _Region(tuple(cyc), reg.corners)
            self._changed()
        self._dirty(rids)
        return m

    def move_node(self, nid: int, xyz: FloatArray) -> None:
        """Move a node to xyz and distribute the offset linearly along every incident edge."""
        node = self._nodes[nid]
        delta = np.asarray(xyz, dtype=float) - node.xyz
        self._nodes[nid] = _Node(node.uv, np.asarray(xyz, dtype=float))
        self._changed()
        for eid in self.incident_edges(nid):
            e = self._edges[eid]
            d0 = delta if e.n0 == nid else np.zeros(3)
            d1 = delta if e.n1 == nid else np.zeros(3)
            self._edges[eid] = _Edge(e.n0, e.n1, e.curve_id, _ramp(e.polyline, d0, d1))
            self._changed()
            self._dirty(self.regions_with_edge(e.n0, e.n1))

    def add_chord(self, rid: int, a: int, b: int, curve_id: int, poly: Polyline) -> tuple[int, int]:
        """Split region rid along a new edge a->b (both nodes on its cycle): Fig. 6 (a)-(d).
        Returns the ids of the two new regions (their corners are found from the geometry)."""
        cyc = list(self._regions[rid].cycle)
        ia, ib = cyc.index(a), cyc.index(b)
        n = len(cyc)
        first = [cyc[(ia + k) % n] for k in range((ib - ia) % n + 1)]
        second = [cyc[(ib + k) % n] for k in range((ia - ib) % n + 1)]
        self._add_edge(a, b, curve_id, poly)
        self._remove_region(rid)
        return self._add_region(tuple(first)), self._add_region(tuple(second))

    def region_corner_ids(self, rid: int) -> tuple:
        return self._regions[rid].corners

    def region_cycle(self, rid: int) -> tuple:
        return self._regions[rid].cycle

    def take_log(self) -> list:
        log, self._log = self._log, []
        return log
