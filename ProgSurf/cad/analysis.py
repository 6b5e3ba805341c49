"""Quality of the CAD result: seam gaps, G1 defect along seams, fit and stroke deviations.

Qin & Wright section 4 judge the surface by eye; the issue asks for numbers: the largest seam gap
(watertightness), the angle between the normals of neighbouring faces along each seam (the G1 defect
of the G0 Coons network, degrees), how far each face lies from its Coons sub-patch (Eq. 1 on the
network polylines) and how far each accepted stroke lies from the surface.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core.memo import per_object
from ..core.types import FloatArray
from ._occ import Part, Vector
from .faces import derivatives_of, is_plain_bspline, unit_normal

SIDE_UV = (lambda w: (w, 0.0), lambda w: (1.0, w), lambda w: (w, 1.0), lambda w: (0.0, w))
"""(s, r) of side parameter w on sides bottom, right, top, left of a face's parameter square."""


@dataclass(frozen=True)
class SeamStat:
    """One interior network edge: the faces of regions (region_a, region_b) meet along it.

    gap_max_mm      : largest |S_a - S_b| at matching points of the shared edge
    angle_max_deg, angle_median_deg : angle between the unit normals of the two faces (G1 defect)
    """

    edge_id: int
    region_a: int
    region_b: int
    gap_max_mm: float
    angle_max_deg: float
    angle_median_deg: float


def _edge_uses(result) -> dict:
    """edge_id -> [(FaceInfo, side index, SidePiece)] over all faces."""
    uses: dict = {}
    for info in result.faces:
        for k, pieces in enumerate(info.sides):
            for p in pieces:
                uses.setdefault(p.edge_id, []).append((info, k, p))
    return uses


def _side_point(info, side: int, piece, t: float) -> tuple[float, float]:
    w = piece.a + ((1.0 - t) if piece.reversed else t) * (piece.b - piece.a)
    return SIDE_UV[side](w)


def _seam_samples(a: tuple, b: tuple, t: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Gap (mm) and normal angle (deg; NaN where a face's normal is undefined) at the seam's edge
    parameters t, between the faces a and b, each given as (FaceInfo, side index, SidePiece)."""
    (fa, ka, pa), (fb, kb, pb) = a, b
    gaps, angles = np.empty(len(t)), np.full(len(t), np.nan)
    for i, x in enumerate(t):
        sa, ra = _side_point(fa, ka, pa, x)
        sb, rb = _side_point(fb, kb, pb, x)
        qa = np.array(tuple(fa.surface.value(sa, ra)))
        qb = np.array(tuple(fb.surface.value(sb, rb)))
        gaps[i] = float(np.linalg.norm(qa - qb))
        na, nb = unit_normal(fa.surface, sa, ra), unit_normal(fb.surface, sb, rb)
        if na is not None and nb is not None:
            angles[i] = float(np.degrees(np.arccos(np.clip(na @ nb, -1.0, 1.0))))
    return gaps, angles


def seam_stats(result, samples: int = 64) -> list[SeamStat]:
    """Gap and normal angle along every edge shared by two faces, sampled at `samples` points."""
    out = []
    t = np.linspace(0.0, 1.0, samples)
    for eid, uses in sorted(_edge_uses(result).items()):
        if len(uses) != 2:
            continue
        (fa, ka, pa), (fb, kb, pb) = uses

        def measure(a=uses[0], b=uses[1]) -> tuple:
            gaps, angles = _seam_samples(a, b, t)
            angles = angles[~np.isnan(angles)]
            return (float(gaps.max()), float(angles.max()) if len(angles) else 0.0,
                    float(np.median(angles)) if len(angles) else 0.0)

        stats = per_object(_SEAMS, (fa.surface, fb.surface), measure, (ka, kb, pa, pb, samples),
                           4 * GRID_CACHE_FACES)
        out.append(SeamStat(eid, fa.region_id, fb.region_id, *stats))
    return out


_SEAMS: dict = {}
"""Seam measurements kept between calls (core.memo.per_object), per pair of surface objects and the
pieces of their sides along the seam: a recompute after one stroke measures mostly the same seams."""


def fit_deviation(result, network, n: int = 21) -> dict:
    """region_id -> largest |face(s,r) - Coons sub-patch(s,r)| on an n x n grid of [0,1]^2."""
    g = np.linspace(0.0, 1.0, n)
    ss, rr = np.meshgrid(g, g, indexing="ij")
    out = {}
    for info in result.faces:
        ref = np.asarray(network.evaluate_region(info.region_id, ss, rr), dtype=float)
        got = np.array([[tuple(info.surface.value(float(a), float(b))) for a, b in zip(ra, rb)]
                        for ra, rb in zip(ss, rr)])
        out[info.region_id] = float(np.linalg.norm(got - ref, axis=-1).max())
    return out


_GRIDS: dict = {}
GRID_CACHE_FACES = 512
"""Sample grids kept between calls, per surface object (a recompute after one stroke measures
the strokes again on mostly the same faces): {id(surface): (surface, bounds, n, grid)}. An entry
holds its surface, so the id stays its own while cached; the oldest go first beyond this size."""


def _grid(surface, bounds, n: int) -> tuple[FloatArray, FloatArray]:
    entry = _GRIDS.get(id(surface))
    if entry is not None and entry[0] is surface and entry[1] == tuple(bounds) and entry[2] == n:
        return entry[3]
    u0, u1, v0, v1 = bounds
    uu, vv = np.meshgrid(np.linspace(u0, u1, n), np.linspace(v0, v1, n), indexing="ij")
    uv = np.stack([uu.ravel(), vv.ravel()], axis=1)
    if is_plain_bspline(surface):      # all samples in one numpy evaluation (cad.faces)
        grid = (uv, derivatives_of(surface).evaluate(uv[:, 0], uv[:, 1])[0])
    else:
        grid = (uv, np.array([tuple(surface.value(float(u), float(v))) for u, v in uv]))
    _GRIDS[id(surface)] = (surface, tuple(bounds), n, grid)
    while len(_GRIDS) > GRID_CACHE_FACES:
        del _GRIDS[next(iter(_GRIDS))]
    return grid


def _project(surface, bounds, p: FloatArray, uv: FloatArray, iterations: int = 12) -> float:
    """Distance from p to the surface patch over `bounds`: Gauss-Newton from uv, clamped to bounds
    (the 2x2 normal equations of the step, in plain floats)."""
    u0, u1, v0, v1 = bounds
    px, py, pz = (float(x) for x in p)
    u, v = float(uv[0]), float(uv[1])
    best = math.inf
    for _ in range(iterations):
        qx, qy, qz = surface.value(u, v)
        rx, ry, rz = px - qx, py - qy, pz - qz
        best = min(best, math.sqrt(rx * rx + ry * ry + rz * rz))
        ax, ay, az = surface.getDN(u, v, 1, 0)
        bx, by, bz = surface.getDN(u, v, 0, 1)
        aa, ab, bb = ax * ax + ay * ay + az * az, ax * bx + ay * by + az * bz, bx * bx + by * by + bz * bz
        ar, br = ax * rx + ay * ry + az * rz, bx * rx + by * ry + bz * rz
        det = aa * bb - ab * ab
        if det <= 1e-300 * max(aa * bb, 1e-300):
            break
        du, dv = (bb * ar - ab * br) / det, (aa * br - ab * ar) / det
        nu, nv = min(max(u + du, u0), u1), min(max(v + dv, v0), v1)
        if abs(nu - u) + abs(nv - v) < 1e-13:
            break
        u, v = nu, nv
    qx, qy, qz = surface.value(u, v)
    return min(best, math.sqrt((px - qx) ** 2 + (py - qy) ** 2 + (pz - qz) ** 2))


GRID_BLOCK = 250_000
"""Points x grid samples whose squared distances surface_distances holds at once (2 MB)."""


def surface_distances(patches, points: FloatArray, grid: int = 41, candidates: int = 3) -> FloatArray:
    """(m,) distance from each point (m, 3) to the union of surface patches [(surface, (u0,u1,v0,v1))]:
    nearest samples of a grid on each patch, then a clamped Gauss-Newton projection on the
    `candidates` nearest patches (OCC's Extrema is ~50 ms a point on a heavy B-spline face)."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    grids = [_grid(surf, bounds, grid) for surf, bounds in patches]
    if not grids:
        return np.full(len(pts), np.inf)
    sizes = [len(xyz) for _, xyz in grids]
    starts = np.concatenate([[0], np.cumsum(sizes)])
    allxyz = np.concatenate([xyz for _, xyz in grids])
    centre = allxyz.mean(axis=0)
    grid_c = allxyz - centre
    grid_sq = np.einsum("ij,ij->i", grid_c, grid_c)
    # the `candidates` nearest faces of each point, and the nearest grid sample on each (the start
    # of its projection), found a block of points at a time
    chunk = max(1, GRID_BLOCK // len(allxyz))
    near = np.empty((len(pts), min(candidates, len(grids))), dtype=int)
    start = np.empty(near.shape, dtype=int)
    for lo in range(0, len(pts), chunk):
        block = pts[lo:lo + chunk] - centre
        # squared distances to every grid sample at once (|p|^2 + |g|^2 - 2 p.g about the grid's
        # centre): they only choose where each projection starts; the projection measures
        d2 = np.einsum("ij,ij->i", block, block)[:, None] + grid_sq[None, :] - 2.0 * block @ grid_c.T
        per_face = np.minimum.reduceat(d2, starts[:-1], axis=1)
        near[lo:lo + len(block)] = np.argsort(per_face, axis=1, kind="stable")[:, :near.shape[1]]
        for c in range(near.shape[1]):
            ks = near[lo:lo + len(block), c]
            for k in np.unique(ks):
                rows = np.flatnonzero(ks == k)
                start[lo + rows, c] = np.argmin(d2[rows, starts[k]:starts[k + 1]], axis=1)
    # then every face's projections at once
    out = np.full(len(pts), np.inf)
    for k in np.unique(near):
        rows, cols = np.nonzero(near == k)
        uv, _ = grids[k]
        surface, bounds = patches[k]
        begin = uv[start[rows, cols]]
        if is_plain_bspline(surface):
            d = _project_many(surface, bounds, pts[rows], begin)
        else:
            d = np.array([_project(surface, bounds, pts[i], b) for i, b in zip(rows, begin)])
        np.minimum.at(out, rows, d)
    return out


def _project_many(surface, bounds, p: FloatArray, uv: FloatArray, iterations: int = 12) -> FloatArray:
    """_project for many points (m, 3) on one non-rational B-spline patch at once, from starts uv
    (m, 2): the same clamped Gauss-Newton steps, evaluated in numpy (cad.faces.SurfaceDerivatives)."""
    u0, u1, v0, v1 = bounds
    ev = derivatives_of(surface)
    u, v = uv[:, 0].astype(float).copy(), uv[:, 1].astype(float).copy()
    best = np.full(len(p), np.inf)
    live = np.ones(len(p), dtype=bool)
    for _ in range(iterations):
        idx = np.flatnonzero(live)
        if not len(idx):
            break
        q, a, b = ev.evaluate(u[idx], v[idx])
        r = p[idx] - q
        best[idx] = np.minimum(best[idx], np.linalg.norm(r, axis=1))
        aa, ab, bb = (a * a).sum(1), (a * b).sum(1), (b * b).sum(1)
        ar, br = (a * r).sum(1), (b * r).sum(1)
        det = aa * bb - ab * ab
        ok = det > 1e-300 * np.maximum(aa * bb, 1e-300)
        safe = np.where(ok, det, 1.0)
        nu = np.clip(u[idx] + (bb * ar - ab * br) / safe, u0, u1)
        nv = np.clip(v[idx] + (aa * br - ab * ar) / safe, v0, v1)
        moving = ok & (np.abs(nu - u[idx]) + np.abs(nv - v[idx]) >= 1e-13)
        u[idx] = np.where(moving, nu, u[idx])
        v[idx] = np.where(moving, nv, v[idx])
        live[idx] = moving
    q = ev.evaluate(u, v)[0]
    return np.minimum(best, np.linalg.norm(p - q, axis=1))


def point_distances(result, points: FloatArray) -> FloatArray:
    """(m,) distance from each point to the faces of a ShellResult (each face spans [0,1]^2)."""
    return surface_distances([(f.surface, (0.0, 1.0, 0.0, 1.0)) for f in result.faces], points)


def shape_point_distances(shape, points: FloatArray) -> FloatArray:
    """(m,) distance from each point to the faces of any shape whose faces span their whole
    surfaces (as ours do, also after STEP/IGES read-back)."""
    return surface_distances([(f.Surface, tuple(f.ParameterRange)) for f in shape.Faces], points)


def shell_seam_gaps(shape, samples: int = 32) -> dict:
    """Watertightness of any shell (e.g. one read back from STEP/IGES): for every edge shared by two
    faces, the largest distance between the two faces' surfaces evaluated through the edge's two
    pcurves (what OCC itself uses), and the count of free (one-face) edges.
    Returns {'shared_edges', 'free_edges', 'seam_gap_max_mm'}."""
    shared = free = 0
    gap = 0.0
    for edge in shape.Edges:
        nfaces = len(shape.ancestorsOfType(edge, Part.Face))
        if nfaces == 1:
            free += 1
        if nfaces != 2:
            continue
        shared += 1
        reps = [edge.curveOnSurface(i) for i in range(2)]
        if any(rep is None for rep in reps):
            continue
        t = np.linspace(edge.FirstParameter, edge.LastParameter, samples)
        pts = []
        for c2d, surface, placement, _, _ in reps:
            uv = [c2d.value(float(x)) for x in t]
            pts.append(np.array([tuple(placement.multVec(surface.value(p.x, p.y))) for p in uv]))
        gap = max(gap, float(np.linalg.norm(pts[0] - pts[1], axis=1).max()))
    return {"shared_edges": shared, "free_edges": free, "seam_gap_max_mm": gap}


SHARP_NODE_ZONE = 0.1
"""Part of a seam (edge parameter, at each end) next to a sharp node that the G1 target leaves out
(cad.g1.SHARP_TAPER: the correction fades in over it, the G0 crease of the node is kept)."""


@dataclass(frozen=True)
class G1SeamStat:
    """One interior seam measured for the G1 targets (issue 9).

    angle_max_deg, angle_median_deg : over all samples (as SeamStat)
    sharp           : the seam lies on a kinked stroke (core.continuity.sharp_edges): a kept feature
    smooth_max_deg  : largest angle away from sharp nodes (SHARP_NODE_ZONE at such ends); the
                      number the 1 degree target applies to (0 for a sharp seam)
    node_spread_deg : (2,) corner-normal spread at its two nodes (> SHARP_NODE_DEG: sharp node)
    """

    edge_id: int
    region_a: int
    region_b: int
    gap_max_mm: float
    angle_max_deg: float
    angle_median_deg: float
    sharp: bool
    smooth_max_deg: float
    node_spread_deg: tuple


def _corner_normal(surface, corner: int) -> FloatArray | None:
    s, r = ((0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0))[corner]
    return unit_normal(surface, s, r)


def node_spreads(result, network) -> dict:
    """node id -> largest angle (deg) between the corner normals of the faces cornered there."""
    from ..core.continuity import node_normal

    normals: dict = {}
    for info in result.faces:
        ids, _ = network.region_corners(info.region_id)
        for k, nid in enumerate(ids):
            normals.setdefault(nid, []).append(_corner_normal(info.surface, k))
    return {nid: node_normal(ns)[1] for nid, ns in normals.items()}


def g1_seam_stats(result, network, samples: int = 128) -> list[G1SeamStat]:
    """Seam gap and normal angle of every interior seam, with the intended sharp features marked
    by rule: seams on kinked strokes (result.sharp_edges, or core.continuity.sharp_edges) and the
    ends of seams at sharp nodes (corner normals spread by more than SHARP_NODE_DEG)."""
    from ..core.continuity import SHARP_NODE_DEG, sharp_edges

    sharp = result.sharp_edges if result.continuity == "G1" else sharp_edges(network)
    spreads = node_spreads(result, network)
    edges = network.edges()
    t = np.linspace(0.0, 1.0, samples)
    out = []
    for eid, uses in sorted(_edge_uses(result).items()):
        if len(uses) != 2:
            continue
        fa, fb = uses[0][0], uses[1][0]
        e = edges[eid]
        spread = (spreads.get(e.node0, 0.0), spreads.get(e.node1, 0.0))
        keep = np.ones(samples, dtype=bool)
        if spread[0] > SHARP_NODE_DEG:
            keep &= t > SHARP_NODE_ZONE
        if spread[1] > SHARP_NODE_DEG:
            keep &= t < 1.0 - SHARP_NODE_ZONE
        gaps, angles = _seam_samples(uses[0], uses[1], t)
        defined = ~np.isnan(angles)
        kept = angles[defined & keep]
        angles = angles[defined]
        is_sharp = eid in sharp
        out.append(G1SeamStat(eid, fa.region_id, fb.region_id, float(gaps.max()),
                              float(angles.max()) if len(angles) else 0.0,
                              float(np.median(angles)) if len(angles) else 0.0, is_sharp,
                              0.0 if is_sharp or not len(kept) else float(kept.max()), spread))
    return out


def g0_view(result):
    """The G0 faces a G1 ShellResult was made from, as a ShellResult (shape None), for measuring
    G0 beside G1 on the same strokes; a G0 result is returned as it is."""
    from dataclasses import replace

    if result.continuity != "G1":
        return result
    return replace(result, shape=None, faces=result.g0_faces, continuity="G0", g0_faces=())
