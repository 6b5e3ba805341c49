"""The pre-image plane network of Qin & Wright section 3: its records and their edits.

Holds :class:`PatchNetwork`, the progressive patch network: the nodes, edges and regions that
divide the pre-image plane (the unit square) into 3- and 4-sided regions, the edits of the
progressive update (step (4): split an edge at a crossing, pull a node to the stroke and spread
the offset linearly along its edges ("the positional difference vector will be distributed
gradually"), split a region along a chord, Fig. 5/6 cases (a)-(d)), the snapshot that lets a
rejected stroke leave the network as it was, and the check of its invariants. The views of the
records (regions, sides, edges) are in :mod:`.network_views`, the surface queries (Coons
sub-patches of Eq. 1, locate, footpoints of Eq. 2) in :mod:`.network_surface`; both are mixed
into :class:`PatchNetwork` and importable from here.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .network_surface import NEAR_REGIONS, NetworkSurface
from .network_views import OUTER_CURVES, EdgeSegments, EdgeView, NetworkViews, RegionView, SideView, ViewCache
from .preimage import cross2, polygon_area, turning_corners
from .types import FloatArray, Polyline

__all__ = ["EdgeSegments", "EdgeView", "NEAR_REGIONS", "OUTER_CURVES", "PatchNetwork", "RegionView", "SideView"]


# --------------------------------------------------------------------------------------------
# Internal state. Everything is immutable and replaced on change, so a snapshot of the network
# (for the "a failed stroke leaves the network exactly as it was" guarantee) is a shallow copy.
# --------------------------------------------------------------------------------------------

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


DEGENERATE_ATOL = 1e-12
"""Relative round-off (of the coordinates' size) under which a point is the point a collapsed side
is made of (PatchNetwork.split_edge, stroke_ends._collapsed_near)."""


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


class PatchNetwork(NetworkViews, NetworkSurface):
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
        self._view_cache = ViewCache()
        self._nodes: dict[int, _Node] = {}
        self._edges: dict[int, _Edge] = {}
        self._regions: dict[int, _Region] = {}
        self._next = {"node": 0, "edge": 0, "region": 0, "curve": 4}
        self._curves: dict[int, dict] = {k: {"kind": "outer", "stroke": None} for k in OUTER_CURVES}
        self._edge_index: dict[tuple, tuple] = {}
        self._patches: dict[int, tuple] = {}      # region id -> (CoonsPatch, RegionView)
        self._facets: dict[int, tuple] = {}       # region id -> (xyz, uv)
        self._log: list = []                      # ("created"|"removed"|"changed", region id) since last clear
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
        """Bring back the state of a :meth:`snapshot`."""
        for name, value in zip(self._STATE, snap):
            setattr(self, name, dict(value))
        self._log = []
        self._changed()

    def _changed(self) -> None:
        """Record that nodes, edges or regions changed (edges() keeps its answer until then)."""
        self._view_cache.edges_now = None

    def clone(self) -> "PatchNetwork":
        """An independent copy that shares the immutable pieces (and the derived views)."""
        other = object.__new__(type(self))
        other.mesh_density = self.mesh_density
        other._view_cache = self._view_cache.copy()
        other.restore(self.snapshot())
        return other

    def new_curve_id(self, kind: str, stroke: int | None = None) -> int:
        """A new curve id of this kind ("stroke" or "split"), made from input stroke `stroke`."""
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
            self._log.append(("changed", rid))
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

    # ---------------------------------------------------------------- records
    @property
    def region_ids(self) -> list[int]:
        return list(self._regions)

    @property
    def node_ids(self) -> list[int]:
        return list(self._nodes)

    def __len__(self) -> int:
        return len(self._regions)

    def node_uv(self, nid: int) -> FloatArray:
        return self._nodes[nid].uv

    def node_xyz(self, nid: int) -> FloatArray:
        return self._nodes[nid].xyz

    def edge_between(self, a: int, b: int) -> tuple[int, bool]:
        """(edge id, reversed) of the edge joining nodes a and b."""
        return self._edge_index[(a, b)]

    def has_edge(self, a: int, b: int) -> bool:
        """Whether an edge joins nodes a and b."""
        return (a, b) in self._edge_index

    def region_corner_ids(self, rid: int) -> tuple:
        """The 3 or 4 corner node ids of region rid, in cycle order."""
        return self._regions[rid].corners

    def region_cycle(self, rid: int) -> tuple:
        """The node ids around region rid, counter-clockwise in the pre-image plane."""
        return self._regions[rid].cycle

    def take_log(self) -> list:
        """("created" | "removed", region id) of every region change since the last call."""
        log, self._log = self._log, []
        return log

    def is_outer_node(self, nid: int) -> bool:
        """Whether node nid lies on the outer boundary of the unit square."""
        uv = self._nodes[nid].uv
        return bool(np.any(np.minimum(uv, 1.0 - uv) <= 1e-12))

    def incident_edges(self, nid: int) -> list[int]:
        """Ids of the edges that end at node nid."""
        return [eid for eid, e in self._edges.items() if nid in (e.n0, e.n1)]

    # ---------------------------------------------------------------- edits (used by progressive)
    def split_edge(self, eid: int, t: float, xyz: FloatArray, pull: bool) -> int:
        """Insert a node on edge eid at parameter t with 3D position xyz; returns its id.

        pull=True first pulls the edge to xyz with the paper's linear distribution of
        delta = xyz - P_k over each side of the split (step 4, "boundary update")."""
        e = self._edges[eid]
        poly = e.polyline
        here = poly.evaluate(t)
        if not np.ptp(poly.points, axis=0).max() > 0.0:
            # a piece of a 3-sided patch's collapsed side stays one point, bit for bit: its pieces
            # are found by it (stroke_ends._collapsed_near), and interpolating between equal points
            # is not exact (the split's round-off, 6e-14 mm, made a meridian's later neighbour miss
            # the collapsed side on one BLAS kernel and not on another)
            here = poly.points[0].copy()
            pull = pull and not np.allclose(xyz, here, rtol=0.0, atol=DEGENERATE_ATOL * (1.0 + np.abs(here).max()))
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
