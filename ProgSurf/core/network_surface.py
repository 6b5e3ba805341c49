"""Surface queries of the pre-image plane network (Qin & Wright section 3).

Holds what the network answers about its surface: the Coons sub-patch of a region (Eq. 1) and
its points at local (s, r) or at pre-image points (u, v), the region that contains a pre-image
point, the re-parameterised mesh of a sub-patch (step (4) "re-parameterisation"), and the
triangulated surface and footpoint search of step (6) (motion-sketch text, Eq. 2: the pre-image
(u_f, v_f) of a point Q off the surface). :class:`NetworkSurface` is the part of
:class:`~ProgSurf.core.network.PatchNetwork` that answers them.
"""
from __future__ import annotations

import numpy as np

from .coons import CoonsPatch, coons_blend, f1
from .footpoint import Facets, Footpoint, nearest_on_mesh, prepare, real_footpoint
from .network_views import pruned
from .preimage import bilinear, cross2, inverse_bilinear_sets
from .types import FloatArray, Polyline, evaluate_polyline_rows, evaluate_polylines

NEAR_REGIONS = 4
"""Footpoints are first searched in this many regions nearest (by bounding box) to the point."""


def _cell_fans(grid: FloatArray) -> FloatArray:
    """The facets of a region's grid (n+1, n+1, d): each cell split into four triangles about its
    centre (the mean of its corners), (4 n^2, 3, d). A split along one diagonal depended on which
    corner of the region comes first, which follows the direction the boundary strokes were drawn
    in: the footpoints of Eq. 2 on those facets, and the surface, moved with it (issue 17: up to
    2.7 times the fit tolerance on fig11_general). The four-way split is the same mesh whichever
    corner comes first."""
    c00, c10, c11, c01 = grid[:-1, :-1], grid[1:, :-1], grid[1:, 1:], grid[:-1, 1:]
    mid = 0.25 * ((c00 + c11) + (c10 + c01))
    fans = [np.stack([mid, a, b], axis=2).reshape(-1, 3, grid.shape[-1])
            for a, b in ((c00, c10), (c10, c11), (c11, c01), (c01, c00))]
    return np.concatenate(fans)


class _FacetPart:
    """One region's piece of the footpoint facets: (xyz (F,3,3), uv (F,3,2), solver, owner (F,),
    bounding box (2,3)) by index, as a tuple would be. The box comes from the evaluated grid at
    once; the triangles and their Eq. 2 inverses only when first asked for (a footpoint search
    reads the boxes of every region but the facets of the few near the point)."""

    __slots__ = ("rid", "grid_xyz", "grid_uv", "box", "_full")

    def __init__(self, rid: int, grid_xyz: FloatArray, grid_uv: FloatArray, box: FloatArray | None = None) -> None:
        self.rid, self.grid_xyz, self.grid_uv = rid, grid_xyz, grid_uv
        if box is None:
            flat = grid_xyz.reshape(-1, 3)
            box = np.stack([flat.min(axis=0), flat.max(axis=0)])
        self.box = box
        self._full = None

    def __getitem__(self, k: int):
        if k == 4:
            return self.box
        if self._full is None:
            fx, fu = _cell_fans(self.grid_xyz), _cell_fans(self.grid_uv)
            self._full = (fx, fu, prepare(fx), np.full(len(fx), self.rid))
        return self._full[k]


def _join_parts(parts: list) -> Facets:
    """Facets of per-region pieces (NetworkSurface._facet_parts), joined in the given order."""
    return Facets(np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts]),
                  np.concatenate([p[3] for p in parts]),
                  tuple(np.concatenate([p[2][k] for p in parts]) for k in range(3)))


class NetworkSurface:
    """The surface queries of :class:`~ProgSurf.core.network.PatchNetwork` (mixed into it): reads
    its records ``_nodes``, ``_regions``, its views (region, region_corners, region_polygon),
    fills its per-region ``_patches`` and ``_facets`` (dropped by the edits that change a region)
    and keeps the rest in its ``_view_cache``."""

    def patch(self, rid: int) -> CoonsPatch:
        """The Coons sub-patch (Eq. 1) of region rid in its local (s, r)."""
        if rid not in self._patches:
            view = self.region(rid)
            b, r, t, l = (s.polyline for s in view.sides)
            self._patches[rid] = (CoonsPatch(b.evaluate, r.evaluate, t.evaluate, l.evaluate), view)
        return self._patches[rid][0]

    def evaluate_region(self, rid: int, s: FloatArray | float, r: FloatArray | float) -> FloatArray:
        """3D points of region rid's Coons sub-patch at local (s, r) in [0,1]^2; (..., 3)."""
        return self.patch(rid).evaluate(s, r)

    def _sides_and_corners(self, rids) -> tuple[list, list]:
        """The four side polylines (bottom, right, top, left) and the corners (4, 3) of each region's
        sub-patch."""
        sides, corners = [], []
        for rid in rids:
            patch = self.patch(rid)
            sides.append(tuple(side.polyline for side in self._patches[rid][1].sides))
            corners.append(patch.corners())
        return sides, corners

    def evaluate_regions_indexed(self, sets: list[tuple[int, FloatArray, FloatArray, np.ndarray, np.ndarray]]) -> FloatArray:
        """:meth:`evaluate_regions` of several (region id, s values (a,), r values (b,), s index (k,),
        r index (k,)): the points (s values[s index], r values[r index]), the same values, each side
        evaluated once per distinct parameter (a central-difference grid repeats them)."""
        sides, corners = self._sides_and_corners([rid for rid, *_ in sets])
        jobs = [(poly[i], sv if i % 2 == 0 else rv) for i in range(4) for poly, (_, sv, rv, _, _) in zip(sides, sets)]
        pts = evaluate_polylines(jobs)
        la, lb = [len(sv) for _, sv, _, _, _ in sets], [len(rv) for _, _, rv, _, _ in sets]
        at_s = np.concatenate([[0], np.cumsum(la)[:-1]])
        at_r = np.concatenate([[0], np.cumsum(lb)[:-1]])
        gs = np.concatenate([a + si for a, (_, _, _, si, _) in zip(at_s, sets)])
        gr = np.concatenate([a + ri for a, (_, _, _, _, ri) in zip(at_r, sets)])
        na, nb = sum(la), sum(lb)
        u = np.concatenate([sv for _, sv, _, _, _ in sets])[gs]
        v = np.concatenate([rv for _, _, rv, _, _ in sets])[gr]
        bottom, right, top, left = pts[gs], pts[na + gr], pts[na + nb + gs], pts[2 * na + nb + gr]
        sizes = [len(si) for _, _, _, si, _ in sets]
        return coons_blend(u, v, (bottom, right, top, left), np.repeat(np.stack(corners, axis=1), sizes, axis=1))

    def region_differences(self, rids: list, which: np.ndarray, s: FloatArray, r: FloatArray,
                           s0: FloatArray, s1: FloatArray, r0: FloatArray, r1: FloatArray) -> tuple[FloatArray, FloatArray]:
        """The central differences (P(s1, r) - P(s0, r)) / (s1 - s0) and (P(s, r1) - P(s, r0)) /
        (r1 - r0), (k, 3) each, of the sub-patches P of regions rids[which] (k,) (the fold checks'
        normals; s0 < s1 about s and r0 < r1 about r, each a function of s or r alone, as
        clip01(s -+ step) is: samples of one region with one s share one evaluation of its s0, s1),
        written out from Eq. 1:

            dP/ds = q(s0, s1) [(p(0,r) - p(1,r)) - f1(r) (p00 - p10) - f2(r) (p01 - p11)]
                    + [f1(r) (p(s1,0) - p(s0,0)) + f2(r) (p(s1,1) - p(s0,1))] / (s1 - s0)

        with q(a, b) = (f1(b) - f1(a)) / (b - a) = 2 (a^2 + ab + b^2) - 3 (a + b) exactly, and
        likewise in r: the differences of the blends cost nothing and lose no digits, only the
        sides are differenced. Each region's bottom and top are evaluated once at each of its
        distinct s (and the s0, s1 of it), its right and left at each distinct r, found by one
        sort of (region, value) for all regions at once."""
        sides, corners = self._sides_and_corners(rids)
        which = np.asarray(which, dtype=np.intp)
        n, k = len(rids), len(which)
        rows, values, picks = [], [], []
        for t, lo, hi, pair in ((s, s0, s1, (0, 2)), (r, r0, r1, (1, 3))):
            order = np.lexsort((t, which))
            w, v = which[order], t[order]
            new = np.ones(k, dtype=bool)
            new[1:] = (w[1:] != w[:-1]) | (v[1:] != v[:-1])
            rank = np.empty(k, dtype=np.intp)
            rank[order] = np.cumsum(new) - 1                    # each sample's distinct value
            at = order[new]                                     # a sample holding each distinct value
            for i in pair:                                      # side i of region j is polyline i n + j
                rows.append(np.tile(i * n + which[at], 3))
                values.append(np.concatenate([lo[at], hi[at], t[at]]))
            picks.append((len(at), rank))
        pts = evaluate_polyline_rows([side[i] for i in range(4) for side in sides], np.concatenate(rows),
                                     np.concatenate(values))
        (ds, rank_s), (dr, rank_r) = picks
        got, start = [], 0
        for d, rank in ((ds, rank_s), (ds, rank_s), (dr, rank_r), (dr, rank_r)):   # bottom, top, right, left
            side = pts[start:start + 3 * d]
            got.append(((side[d:2 * d] - side[:d])[rank], side[2 * d:][rank]))
            start += 3 * d
        (d_bottom, bottom), (d_top, top), (d_right, right), (d_left, left) = got
        p00, p10, p11, p01 = np.moveaxis(np.stack(corners)[which], 1, 0)
        fs1, fr1 = f1(s)[:, None], f1(r)[:, None]
        fs2, fr2 = 1.0 - fs1, 1.0 - fr1
        qs = (2.0 * (s0 * s0 + s0 * s1 + s1 * s1) - 3.0 * (s0 + s1))[:, None]
        qr = (2.0 * (r0 * r0 + r0 * r1 + r1 * r1) - 3.0 * (r0 + r1))[:, None]
        du = qs * ((left - right) - fr1 * (p00 - p10) - fr2 * (p01 - p11)) \
            + (fr1 * d_bottom + fr2 * d_top) / (s1 - s0)[:, None]
        dv = qr * ((bottom - top) - fs1 * (p00 - p01) - fs2 * (p10 - p11)) \
            + (fs1 * d_left + fs2 * d_right) / (r1 - r0)[:, None]
        return du, dv

    def evaluate_regions(self, sets: list[tuple[int, FloatArray, FloatArray]]) -> FloatArray:
        """:meth:`evaluate_region` of several (region id, s (k,), r (k,)) at once, concatenated
        (sum k, 3): the same values, the sub-patches' sides and blends evaluated together."""
        sides, corners = self._sides_and_corners([rid for rid, _, _ in sets])
        u = np.concatenate([np.asarray(s, dtype=float).reshape(-1) for _, s, _ in sets])
        v = np.concatenate([np.asarray(r, dtype=float).reshape(-1) for _, _, r in sets])
        # bottom and top at s, right and left at r (Eq. 1), all sets' points of one side together
        jobs = [(poly[i], s if i % 2 == 0 else r) for i in range(4) for poly, (_, s, r) in zip(sides, sets)]
        pts = evaluate_polylines(jobs).reshape(4, len(u), 3)
        sizes = [np.size(s) for _, s, _ in sets]
        return coons_blend(u, v, tuple(pts), np.repeat(np.stack(corners, axis=1), sizes, axis=1))

    def local_to_uv(self, rid: int, s: FloatArray | float, r: FloatArray | float) -> FloatArray:
        """Pre-image points (..., 2) of region rid's local (s, r): the bilinear map of its corners."""
        (c0, c1, c2, c3), _ = self.region_corners(rid)
        corners = np.array([self._nodes[n].uv for n in (c0, c1, c2, c3)])
        return bilinear(corners, s, r)

    def uv_to_local(self, rid: int, uv: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Local (s, r) of pre-image points uv (k, 2) in region rid: the inverse of local_to_uv."""
        return self.uv_to_local_sets([(rid, uv)])[0]

    def uv_to_local_sets(self, sets: list[tuple[int, FloatArray]]) -> list[tuple[FloatArray, FloatArray]]:
        """:meth:`uv_to_local` of several (region id, uv (k, 2)) at once (preimage.inverse_bilinear_sets:
        the same values, the Newton iterations of all of them run together)."""
        corners: dict = {}
        for rid, _ in sets:
            if rid not in corners:
                ids, tri = self.region_corners(rid)
                corners[rid] = (np.array([self._nodes[n].uv for n in ids]), tri)
        return inverse_bilinear_sets([(corners[rid][0], np.atleast_2d(uv), corners[rid][1]) for rid, uv in sets])

    def _locator(self) -> tuple:
        """All region edges as half-planes, (start (E,2), direction (E,2), 1/length (E,)), with
        the region id and offset of each region's run: rebuilt only when a region changed."""
        cache = self._view_cache
        key = tuple(self._regions.items())
        if cache.locator is not None and cache.locator[0] == key:
            return cache.locator[1]
        starts, dirs, owners, offsets = [], [], [], []
        count = 0
        polys = cache.polygons = pruned(cache.polygons, self._regions)
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
        cache.locator = (key, value)
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
        out = self.evaluate_uv_sets([np.atleast_2d(uv)])[0]
        return out[0] if uv.ndim == 1 else out

    def evaluate_uv_sets(self, sets: list[FloatArray]) -> list[FloatArray]:
        """:meth:`evaluate_uv` of several point sets uv (k, 2) at once: [(k, 3)] per set, the
        same values as set by set (each set's points in one region are inverted as one set)."""
        sets = [np.asarray(uv, dtype=float).reshape(-1, 2) for uv in sets]
        rids = self.locate_many(np.concatenate(sets))
        held, at = [], 0
        for i, uv in enumerate(sets):
            mine = rids[at: at + len(uv)]
            held += [(i, int(rid), mine == rid) for rid in np.unique(mine)]
            at += len(uv)
        # every region's points together (uv_to_local_sets, evaluate_regions: the same values as
        # region by region)
        local = self.uv_to_local_sets([(rid, sets[i][mask]) for i, rid, mask in held])
        pts = self.evaluate_regions([(rid, s, r) for (_, rid, _), (s, r) in zip(held, local)]) if held else None
        out = [np.empty((len(uv), 3)) for uv in sets]
        at = 0
        for (i, _, mask), (s, _) in zip(held, local):
            out[i][mask] = pts[at: at + len(s)]
            at += len(s)
        return out

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
            # all missing grids in one evaluate_regions and one bilinear map (the same values as
            # evaluate_region and local_to_uv region by region: a stroke leaves several to make)
            n = self.mesh_density
            g = np.linspace(0.0, 1.0, n + 1)
            si, ri = (a.ravel() for a in np.meshgrid(np.arange(n + 1), np.arange(n + 1), indexing="ij"))
            ss, rr = g[si], g[ri]
            xyz = self.evaluate_regions_indexed([(rid, g, g, si, ri) for rid in missing]).reshape(len(missing), n + 1, n + 1, 3)
            corners = np.array([[self._nodes[k].uv for k in self.region_corners(rid)[0]] for rid in missing])
            uv = bilinear(corners.transpose(1, 0, 2)[:, :, None, :], ss, rr).reshape(len(missing), n + 1, n + 1, 2)
            flat = xyz.reshape(len(missing), -1, 3)
            boxes = np.stack([flat.min(axis=1), flat.max(axis=1)], axis=1)
            for rid, grid_xyz, grid_uv, box in zip(missing, xyz, uv, boxes):
                self._facets[rid] = _FacetPart(rid, grid_xyz, grid_uv, box)
        return [self._facets[rid] for rid in self._regions]

    def facets(self) -> Facets:
        """The triangulated surface used for footpoints (Eq. 2): every region's piece, joined
        (the join is kept until a region changes)."""
        key = tuple(self._regions)
        parts = self._facet_parts()
        joined = self._view_cache.joined
        if joined is not None and joined[0] == key and all(a is b for a, b in zip(parts, joined[1])):
            return joined[2]
        facets = _join_parts(parts)
        self._view_cache.joined = (key, parts, facets)
        return facets

    def footpoint(self, q: FloatArray, slack: float = 0.0, near_uv: FloatArray | None = None) -> Footpoint:
        """Footpoint of q on the current surface (Eq. 2). The nearest real footpoint is searched
        only among regions whose bounding box can hold one nearer than the best of the nearest
        few regions (same result as searching every facet, in the same order); only when those
        have none is every facet searched for one, and then for the nearest point of the mesh only
        the regions whose box is no further than the near regions' nearest point."""
        q = np.asarray(q, dtype=float)
        parts = self._facet_parts()
        boxes = self._boxes(parts)
        gap = np.linalg.norm(np.maximum(0.0, np.maximum(boxes[:, 0] - q, q - boxes[:, 1])), axis=1)
        near = np.sort(np.argsort(gap, kind="stable")[:NEAR_REGIONS])
        near_facets = _join_parts([parts[i] for i in near])
        found = real_footpoint(q, near_facets, slack, near_uv)
        if found is not None:
            # (a margin for the round-off of the boxes: 1e-9 mm at 100 mm, relative to the point)
            margin = 1e-11 * (float(np.abs(q).max()) + abs(found.distance) + slack)
            reach = np.flatnonzero(gap <= abs(found.distance) + slack + margin)
            if not set(reach.tolist()) <= set(near.tolist()):
                found = real_footpoint(q, _join_parts([parts[i] for i in reach]), slack, near_uv)
            return found
        found = real_footpoint(q, self.facets(), slack, near_uv)
        if found is not None:
            return found
        # the nearest point of the mesh: among the regions whose box is no further than the
        # nearest point of the near ones (the same point as over every facet, found first in the
        # same order: a facet at that least distance lies in a region whose box is no further)
        bound = nearest_on_mesh(q, near_facets).distance
        margin = 1e-11 * (float(np.abs(q).max()) + bound)
        reach = np.flatnonzero(gap <= bound + margin)
        return nearest_on_mesh(q, _join_parts([parts[i] for i in reach]))

    def _boxes(self, parts: list) -> FloatArray:
        """(R, 2, 3) bounding boxes (min, max) of the regions' facets, kept while the parts are."""
        cached = self._view_cache.boxes
        if cached is not None and len(cached[0]) == len(parts) and all(a is b for a, b in zip(cached[0], parts)):
            return cached[1]
        boxes = np.stack([p[4] for p in parts])
        self._view_cache.boxes = (parts, boxes)
        return boxes
