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

from ..core.bspline_surface import project_points, unit_normals
from ..core.folds import FOLD_DENSE, TUCK_REACH, Fold, inset_grid, tuck_deg, turn_from_mean_deg
from ..core.curve_fit import chord_sag
from ..core.types import FloatArray
from ._occ import Part, Vector
from .faces import unit_normal
from .surface_data import SurfaceData

SIDE_UV = (lambda w: (w, 0.0), lambda w: (1.0, w), lambda w: (w, 1.0), lambda w: (0.0, w))
"""(s, r) of side parameter w on sides bottom, right, top, left of a face's parameter square."""


@dataclass(frozen=True)
class SeamStat:
    """One interior network edge: the faces of regions (region_a, region_b) meet along it.

    gap_max_mm      : largest |S_a - S_b| at matching points of the shared edge
    angle_max_deg, angle_median_deg : angle between the unit normals of the two faces (G1 defect)
                      between SEAM_END and 1 - SEAM_END of the seam, where both are defined

    G1SeamStat adds what the G1 targets need (sharp features).
    """

    edge_id: int
    region_a: int
    region_b: int
    gap_max_mm: float
    angle_max_deg: float
    angle_median_deg: float


def _edge_uses(result) -> dict:
    """edge_id -> [(FaceInfo, side index, SidePiece)] over all faces."""
    return _uses_of(result.faces)


def _uses_of(faces) -> dict:
    """_edge_uses of FaceInfos."""
    uses: dict = {}
    for info in faces:
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
        inner = 0.0 < x < 1.0
        na, nb = side_normal(fa.surface, sa, ra, inner), side_normal(fb.surface, sb, rb, inner)
        if na is not None and nb is not None:
            angles[i] = float(np.degrees(np.arccos(np.clip(na @ nb, -1.0, 1.0))))
    return gaps, angles


LIMIT_STEPS = (1e-3, 1e-2)
"""Steps (of the face's parameter range) into a face at which side_normal reads the limit of its
normal where the normal on the side itself is undefined."""


def side_normal(surface, s: float, r: float, limit: bool = True) -> FloatArray | None:
    """unit_normal at the side point (s, r) of a face on [0, 1]^2; where it is undefined there and
    `limit`, its limit from inside the face: the normal a small step (LIMIT_STEPS) in from the
    side, as OCC's BRepLProp reads it from higher derivatives. A Coons patch whose two sides
    adjacent to a side are both points (a lens of two curves) has no cross derivative along it:
    its normal is undefined along the whole side, and a seam there read no angle at all while
    the limit was 50-80 deg off the neighbour's (sketchgen 153000 sk_octant_8: a fin in the STEP
    file that the report and the fold check both missed). At a corner the step is taken along
    both parameters. None where the normal a step in is undefined too, or for a point inside the
    face (no side to step in from)."""
    n = unit_normal(surface, s, r)
    if n is not None or not limit:
        return n
    for h in LIMIT_STEPS:
        ds = h if s <= 0.0 else -h if s >= 1.0 else 0.0
        dr = h if r <= 0.0 else -h if r >= 1.0 else 0.0
        if ds == 0.0 and dr == 0.0:
            return None
        n = unit_normal(surface, s + ds, r + dr)
        if n is not None:
            return n
    return None


def _measured(a: tuple, b: tuple, samples: int) -> tuple[FloatArray, FloatArray]:
    """_seam_samples at `samples` evenly spaced edge parameters (read-only arrays), kept with face
    a (its SurfaceData.seam) while face b and the pieces of both sides along the seam are the same:
    a recompute after one stroke measures mostly the same seams."""
    (fa, ka, pa), (fb, kb, pb) = a, b

    def measure() -> tuple[FloatArray, FloatArray]:
        gaps, angles = _seam_samples(a, b, np.linspace(0.0, 1.0, samples))
        gaps.setflags(write=False)
        angles.setflags(write=False)
        return gaps, angles

    return fa.derived.seam((ka, pa, samples), fb.derived, (kb, pb), measure)


SEAM_SAMPLES = 101
"""Points along every seam (evenly, ends included: every 1 % of it) at which its gap and normal
angle are measured: the report's seam figures and the fold check (_inner_seam_angles) read the
same samples."""

SEAM_END = 0.04
"""The seam angles leave out this fraction of a seam at each end (issue 16: a fold is two normals
that differ "along their shared edge, away from its ends"; sketchgen's run_family reads 5 % to 95 %
of the edge's own parameter, which is not quite the face's, hence a little more here: a tuck at
95 % of a seam next to an apex read 92 deg there and was missed at 94 %). At a 3-sided face's
collapsed corner the derivative along the collapsed side is 1e-17 to 1e-12 of the other, so its
normal there points wherever the round-off does: sampled at the ends, seams that end at an apex
read 170-180 deg on sketches with no fold at all."""


def _away_from_ends(angles: FloatArray) -> FloatArray:
    """The defined angles (not NaN) of a seam's evenly spaced samples between SEAM_END and
    1 - SEAM_END of it."""
    t = np.linspace(0.0, 1.0, len(angles))
    angles = angles[(t >= SEAM_END - 1e-12) & (t <= 1.0 - SEAM_END + 1e-12)]
    return angles[~np.isnan(angles)]


def _summary(gaps: FloatArray, angles: FloatArray, ends: bool = False) -> tuple[float, float, float]:
    """(gap_max_mm, angle_max_deg, angle_median_deg) of a seam's samples, evenly spaced over the
    whole seam: the gap over all of them, the angles between SEAM_END and 1 - SEAM_END (with ends,
    over all of them), those where a normal is undefined (NaN) left out; both angles are 0 where
    none is defined."""
    angles = angles[~np.isnan(angles)] if ends else _away_from_ends(angles)
    return (float(gaps.max()), float(angles.max()) if len(angles) else 0.0,
            float(np.median(angles)) if len(angles) else 0.0)


def seam_stats(result, samples: int = SEAM_SAMPLES) -> list[SeamStat]:
    """Gap and normal angle along every edge shared by two faces, sampled at `samples` points (the
    angle away from the seam's ends: _summary)."""
    out = []
    for eid, uses in sorted(_edge_uses(result).items()):
        if len(uses) != 2:
            continue
        stats = _summary(*_measured(uses[0], uses[1], samples))
        out.append(SeamStat(eid, uses[0][0].region_id, uses[1][0].region_id, *stats))
    return out


def fit_deviation(result, network, n: int = 21) -> dict:
    """region_id -> largest |face(s,r) - Coons sub-patch(s,r)| on an n x n grid of [0,1]^2 (on
    its sides only for a face refilled in its plane, cad.patch_faces.refilled_face)."""
    g = np.linspace(0.0, 1.0, n)
    ss, rr = np.meshgrid(g, g, indexing="ij")
    border = (ss == 0.0) | (ss == 1.0) | (rr == 0.0) | (rr == 1.0)
    out = {}
    for info in result.faces:
        # a refilled face's inside is not its Coons patch, by design: its sides are
        s, r = (ss[border], rr[border]) if getattr(info, "refilled", False) else (ss.ravel(), rr.ravel())
        ref = np.asarray(network.evaluate_region(info.region_id, s, r), dtype=float)
        got = np.array([tuple(info.surface.value(float(a), float(b))) for a, b in zip(s, r)])
        out[info.region_id] = float(np.linalg.norm(got - ref, axis=-1).max())
    return out


def fit_allowance(result, network, fit_mm: float) -> dict:
    """region_id -> how far the face may lie from its Coons sub-patch (fit_deviation): fit_mm plus
    the largest chord sag (core.curve_fit.chord_sag) of the polylines of its bottom and top sides
    and of its left and right sides.

    That is what the curve fit promises: each shared curve lies within half the fit tolerance
    (cad.edges.EDGE_FIT_FRACTION) of its polyline at the vertices, and within that plus the
    chord's sag between them (a smooth curve cannot, and need not, hug the corners of a coarse
    polyline); the face and the sub-patch are the Coons patches (Eq. 1) of those curves and of
    those polylines, so they differ by at most the largest difference along the bottom or top
    plus the largest along the left or right. The network keeps the sag of the polylines it makes
    (faired strokes, splits) under a quarter of the fit tolerance (Tolerances.sag_mm): the
    allowance is 1.2 to 1.6 times the fit tolerance on the bundled examples, up to 3.3 times where a
    boundary side merged of two strokes keeps a corner. A face beyond it is a fit that broke its
    promise."""
    edges = network.edges()
    sag: dict = {}

    def side_sag(pieces) -> float:
        for p in pieces:
            if p.edge_id not in sag:
                pts = edges[p.edge_id].polyline.points
                sag[p.edge_id] = float(chord_sag(pts).max()) if len(pts) > 2 else 0.0
        return max((sag[p.edge_id] for p in pieces), default=0.0)

    out = {}
    for info in result.faces:
        bottom, right, top, left = (side_sag(pieces) for pieces in info.sides)
        out[info.region_id] = float(fit_mm) + max(bottom, top) + max(left, right)
    return out


def _project(surface, bounds, p: FloatArray, uv: FloatArray, iterations: int = 12) -> float:
    """Distance from p to the surface patch over `bounds`: Gauss-Newton from uv, clamped to bounds
    (the 2x2 normal equations of the step, in plain floats): core.bspline_surface.project_points
    for a surface numpy cannot evaluate (one OCC call per evaluation)."""
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
    `candidates` nearest patches (OCC's Extrema is ~50 ms a point on a heavy B-spline face).
    A patch's surface may be given as its SurfaceData (a FaceInfo's `derived`): its grid and numpy
    evaluator are then kept for the next call."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    patches = [(s if isinstance(s, SurfaceData) else SurfaceData(s), bounds) for s, bounds in patches]
    grids = [data.grid(bounds, grid) for data, bounds in patches]
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
        data, bounds = patches[k]
        begin = uv[start[rows, cols]]
        if data.plain:        # all of this face's projections in numpy
            d = project_points(data.derivatives, bounds, pts[rows], begin)
        else:
            d = np.array([_project(data.surface, bounds, pts[i], b) for i, b in zip(rows, begin)])
        np.minimum.at(out, rows, d)
    return out


def point_distances(result, points: FloatArray) -> FloatArray:
    """(m,) distance from each point to the faces of a ShellResult (each face spans [0,1]^2)."""
    return surface_distances([(f.derived, (0.0, 1.0, 0.0, 1.0)) for f in result.faces], points)


def shape_point_distances(shape, points: FloatArray) -> FloatArray:
    """(m,) distance from each point to the faces of any shape whose faces span their whole
    surfaces (as ours do, also after STEP/IGES read-back)."""
    return surface_distances([(f.Surface, tuple(f.ParameterRange)) for f in shape.Faces], points)


def shell_seam_gaps(shape, samples: int = 32) -> dict:
    """Watertightness of any shell (e.g. one read back from STEP/IGES): for every edge shared by two
    faces, the largest distance between the two faces' surfaces evaluated through the edge's two
    pcurves (what OCC itself uses), and the count of free (one-face) edges; a degenerated edge
    (the collapsed side of a 3-sided face: a point, no boundary) is neither.
    Returns {'shared_edges', 'free_edges', 'seam_gap_max_mm'}."""
    shared = free = 0
    gap = 0.0
    for edge in shape.Edges:
        if edge.Degenerated:
            continue
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
class G1SeamStat(SeamStat):
    """One interior seam measured for the G1 targets (issue 9): a SeamStat (gap and angles over all
    samples) and

    sharp           : the seam lies on a kinked stroke (core.continuity.sharp_edges): a kept feature
    smooth_max_deg  : largest angle away from sharp nodes (SHARP_NODE_ZONE at such ends); the
                      number the 1 degree target applies to (0 for a sharp seam)
    node_spread_deg : (2,) corner-normal spread at its two nodes (> SHARP_NODE_DEG: sharp node)
    """

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
        gaps, angles = _measured(uses[0], uses[1], samples)
        kept = angles[~np.isnan(angles) & keep]
        is_sharp = eid in sharp
        out.append(G1SeamStat(eid, fa.region_id, fb.region_id, *_summary(gaps, angles, ends=True), is_sharp,
                              0.0 if is_sharp or not len(kept) else float(kept.max()), spread))
    return out


def g0_view(result):
    """The G0 faces a G1 ShellResult was made from, as a ShellResult (shape None), for measuring
    G0 beside G1 on the same strokes; a G0 result is returned as it is."""
    from dataclasses import replace

    if result.continuity != "G1":
        return result
    return replace(result, shape=None, faces=result.g0_faces, continuity="G0", g0_faces=(), g0_folds=())


FOLD_SEAM_DEG = 60.0
"""A seam whose two faces' normals differ by more than this away from its ends is a fold."""

FOLD_FACE_DEG = 90.0
"""A face whose normal turns by more than this inside it is a fold: a normal this far from the
face's mean normal (it turns over on itself), or two normals this far apart less than
core.folds.TUCK_REACH of the diagonal from each other (a tuck)."""

FOLD_SAMPLES = 9
"""Points per side of a face's grid (3 % in from its sides) at which face folds are looked for: the
sides of a face are left out, where a 3-sided face's collapsed corner has no defined normal (seams:
SEAM_SAMPLES between SEAM_END and 1 - SEAM_END)."""


def _fold_grid(n: int = FOLD_SAMPLES) -> tuple[FloatArray, FloatArray]:
    return inset_grid(n)


def _face_points_and_normals(info, s: FloatArray, r: FloatArray) -> tuple[FloatArray, FloatArray, np.ndarray]:
    """(points, unit normals, defined) of a face at (s, r): _face_normals with the points of the
    same evaluation."""
    data = info.derived
    if data.plain:
        points, ds, dr = data.derivatives.evaluate(s, r)
        return (points, *unit_normals(ds, dr))
    points = np.array([tuple(info.surface.value(float(a), float(b))) for a, b in zip(s, r)])
    return (points, *_face_normals(info, s, r))


def _face_normals(info, s: FloatArray, r: FloatArray) -> tuple[FloatArray, np.ndarray]:
    data = info.derived
    if data.plain:
        ds, dr = data.derivatives.derivatives(s, r)
    else:
        ds = np.array([tuple(info.surface.getDN(float(a), float(b), 1, 0)) for a, b in zip(s, r)])
        dr = np.array([tuple(info.surface.getDN(float(a), float(b), 0, 1)) for a, b in zip(s, r)])
    return unit_normals(ds, dr)


def folds(result) -> list[Fold]:
    """Every fold of a ShellResult: face_folds of its faces, its sharp_edges excepted."""
    return folds_and_seam_max_deg(result)[0]


def folds_and_seam_max_deg(result) -> tuple[list[Fold], float]:
    """(folds(result), the largest angle (deg) between two faces' normals along any of its seams
    between SEAM_END and 1 - SEAM_END of the seam, sharp edges drawn on purpose included; 0 with no
    seam where the normals are defined), the seams sampled once for both."""
    seams = _inner_seam_angles(result.faces)
    sharp = set(getattr(result, "sharp_edges", ()) or ())
    found = _folds(result.faces, [seam for seam in seams if seam[0] not in sharp])
    return found, max((a for _, _, a in seams), default=0.0)


def face_folds(faces, sharp_edges=()) -> list[Fold]:
    """Every fold among FaceInfos: seams whose faces' normals differ by more than FOLD_SEAM_DEG
    between SEAM_END and 1 - SEAM_END of the seam (seams kept sharp on purpose, sharp_edges,
    excepted), and
    faces whose normal turns by more than FOLD_FACE_DEG inside them (from their mean normal, or
    between two normals closer than TUCK_REACH of the diagonal of all the faces)."""
    return _folds(faces, _inner_seam_angles(faces, sharp_edges))


def _folds(faces, seams: list) -> list[Fold]:
    """face_folds of FaceInfos whose seams' angles (_inner_seam_angles) are measured already."""
    out = [Fold("seam", angle, regions, edge=eid) for eid, regions, angle in seams if angle > FOLD_SEAM_DEG]
    s, r = _fold_grid()
    samples = [_face_points_and_normals(info, s, r) for info in faces]
    if samples:
        every = np.vstack([at for at, _, _ in samples])
        reach = TUCK_REACH * float(np.linalg.norm(every.max(axis=0) - every.min(axis=0)))
    for info, (at, normals, ok) in zip(faces, samples):
        turn = max(face_turn_deg(info, FOLD_DENSE), tuck_deg(normals, ok, at, reach))
        if turn > FOLD_FACE_DEG:
            out.append(Fold("face", turn, (info.region_id,)))
    return out


def _inner_seam_angles(faces, sharp_edges=()) -> list:
    """[(edge id, (region ids), largest angle between the two faces' normals between SEAM_END and
    1 - SEAM_END of the seam, deg)] of every seam among FaceInfos (not those in sharp_edges) where
    one is defined: the SEAM_SAMPLES samples the report's seam angles read (_measured, kept with
    the face), so the fold check and the report agree. With 9 samples (FOLD_SAMPLES) the check
    missed a tuck 3 % of a seam wide next to a 3-sided face's apex that the report read at 84 deg
    (sketchgen 67000 sk_octant_4)."""
    sharp = set(sharp_edges)
    out = []
    for eid, uses in sorted(_uses_of(faces).items()):
        if len(uses) != 2 or eid in sharp:
            continue
        angles = _away_from_ends(_measured(uses[0], uses[1], SEAM_SAMPLES)[1])
        if len(angles):
            out.append((eid, (uses[0][0].region_id, uses[1][0].region_id), float(angles.max())))
    return out


def lone_face_fold_deg(info) -> float:
    """How far a face folds as _folds reads it when it is the only face of its surface: its turn
    from its mean normal on the FOLD_DENSE grid, or its tuck on the FOLD_SAMPLES grid within
    TUCK_REACH of its own samples' diagonal (fold beyond FOLD_FACE_DEG)."""
    at, normals, ok = _face_points_and_normals(info, *_fold_grid())
    reach = TUCK_REACH * float(np.linalg.norm(at.max(axis=0) - at.min(axis=0)))
    return max(face_turn_deg(info, FOLD_DENSE), tuck_deg(normals, ok, at, reach))


def face_turn_deg(info, n: int = FOLD_SAMPLES) -> float:
    """Largest angle (deg) between a normal of a face (a FaceInfo: its surface and derived data)
    and its mean normal, on an n x n grid 3 % in from its sides: a face fold beyond FOLD_FACE_DEG
    (folds() reads it on the FOLD_DENSE grid; cad.g1 checks its corrected faces with it on the
    FOLD_SAMPLES grid, whose turn it compares with the G0 face's: a G1 face that turns over where
    only the dense grid sees it is reported by folds() and its stroke left out, app.build)."""
    normals, ok = _face_normals(info, *_fold_grid(n))
    return turn_from_mean_deg(normals, ok)
