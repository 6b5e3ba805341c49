"""Folds of a patch network: where its Coons sub-patches crease or turn over.

A fold is what a designer sees as a fin, a tuck or an inverted face that no stroke asked for:

- a seam fold: along an edge shared by two regions, away from its ends (5 %..95 %), the two
  sub-patches' normals differ by more than ``SEAM_FOLD_DEG``;
- a face fold: inside one region, a normal more than ``FACE_TURN_DEG`` from the region's mean
  normal (the face turns over on itself).

The built faces are checked at 60 and 90 deg (cad.analysis.folds); the network is held 5 deg
inside those, since the B-spline faces follow the polyline sub-patches only within the fit.

Normals come from central differences of the sub-patch (Eq. 1) in its local (s, r); a sample where
a derivative vanishes (the collapsed side of a 3-sided region) has no normal and is skipped.
Both sub-patches of a seam are parameterised from the same pre-image plane, so their normals are
oriented alike and an inverted neighbour reads near 180 deg.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Iterable, Optional, Sequence

import numpy as np

from .preimage import clip01
from .types import FloatArray, cross3

SEAM_FOLD_DEG = 55.0
FACE_TURN_DEG = 85.0
SEAM_SAMPLES = 9
FACE_SAMPLES = 9
FACE_INSET = 0.03
_STEP = 1e-4

TANGENT_CORNER_DEG = 5.0
"""A patch's corner where its two sides meet within this angle of tangency (a ring merged to four
sides: its corners lie on one smooth curve) has no normal of its own: its partial derivatives
there are parallel up to the polyline's kinks, and the sign of their cross product is chance. On
the TiGL-like nose cap (tests/core/test_loop_corners.py) the ring's 4 corners met 0.01-1.9 deg off
tangency and the one at 0.01 deg read its normal upside down, 180 deg from the rest, depending on
which sides were merged and on the machine's BLAS. Such a corner sample is left out of the fold
checks (tangent_corner); the samples around it still show a fold that the corner makes."""


def tangent_corner(s: FloatArray, r: FloatArray, sine: FloatArray) -> np.ndarray:
    """Which samples at local (s, r) are a corner of the patch (s and r each 0 or 1) whose partial
    derivatives make an angle whose sine is `sine` within TANGENT_CORNER_DEG of 0 or 180 deg."""
    s, r = np.asarray(s, dtype=float), np.asarray(r, dtype=float)
    at = ((s == 0.0) | (s == 1.0)) & ((r == 0.0) | (r == 1.0))
    return at & (np.abs(sine) < np.sin(np.radians(TANGENT_CORNER_DEG)))


@dataclass(frozen=True)
class Fold:
    """One fold: kind "seam" (edge id, the two regions, angle) or "face" (region, angle)."""

    kind: str
    angle_deg: float
    regions: tuple
    edge: int = -1
    curve_id: int = -1

    def describe(self) -> str:
        if self.kind == "seam":
            where = f"curve {self.curve_id}" if self.curve_id >= 0 else f"edge {self.edge}"
            return (f"a crease of {self.angle_deg:.0f} deg between regions {self.regions[0]} and "
                    f"{self.regions[1]} along {where}")
        return f"region {self.regions[0]} turns over ({self.angle_deg:.0f} deg inside it)"


def _unit(v: FloatArray) -> tuple[FloatArray, np.ndarray]:
    n = np.linalg.norm(v, axis=-1)
    ok = n > 1e-12 * max(float(np.max(n, initial=0.0)), 1e-300)
    return v / np.where(ok, n, 1.0)[..., None], ok


def normal_sets(net, jobs: Sequence[tuple[int, FloatArray, FloatArray]]) -> list[tuple[FloatArray, np.ndarray]]:
    """:func:`region_normals` of several (region id, s (k,), r (k,)) (k > 0) at once: the fold
    checks sample every region they look at inside and along each of its seams, and all of it is
    evaluated together (NetworkSurface.region_differences). Every value is the one region_normals
    gives for its set alone: the arithmetic is per sample, and what is relative (which normals are
    defined) is relative within each set. Returns [(unit normals (k, 3), defined (k,))] per job."""
    if not jobs:
        return []
    by_region: dict[int, list[int]] = {}
    for i, (rid, _, _) in enumerate(jobs):
        by_region.setdefault(rid, []).append(i)
    order = [i for held in by_region.values() for i in held]
    sizes_of = [len(job[1]) for job in jobs]
    sizes = [sizes_of[i] for i in order]
    starts = np.cumsum([0] + sizes[:-1])
    s = np.concatenate([np.asarray(jobs[i][1], dtype=float) for i in order])
    r = np.concatenate([np.asarray(jobs[i][2], dtype=float) for i in order])
    s0, s1 = clip01(s - _STEP), clip01(s + _STEP)
    r0, r1 = clip01(r - _STEP), clip01(r + _STEP)
    # every sample's differences in s and in r, all evaluated together, each region's sides once
    # per distinct parameter (NetworkSurface.region_differences)
    # (Forward differences were tried in b5697fd: near a collapsed apex they read a region of
    # three_sided 98 deg turned over where central ones read under 85.)
    which = np.repeat(np.arange(len(by_region)), [sum(sizes_of[i] for i in held) for held in by_region.values()])
    du, dv = net.region_differences(list(by_region), which, s, r, s0, s1, r0, r1)
    n = cross3(du, dv)
    lu, lv, ln = (np.linalg.norm(x, axis=1) for x in (du, dv, n))

    def per_set(values: FloatArray) -> FloatArray:
        return np.repeat(np.maximum.reduceat(values, starts), sizes)

    ok = ln > 1e-12 * np.maximum(per_set(ln), 1e-300)
    unit = n / np.where(ok, ln, 1.0)[:, None]
    ok &= ln > 1e-6 * np.maximum(lu * lv, 1e-300)
    # on (or next to) a collapsed side one derivative is round-off: its direction means nothing
    size = np.maximum(np.maximum(per_set(lu), per_set(lv)), 1e-300)
    ok &= (lu > 1e-6 * size) & (lv > 1e-6 * size)
    ok &= ~tangent_corner(s, r, ln / np.maximum(lu * lv, 1e-300))
    out: list = [None] * len(jobs)
    for i, a, k in zip(order, starts, sizes):
        out[i] = (unit[a:a + k], ok[a:a + k])
    return out


def region_normals(net, rid: int, s: FloatArray, r: FloatArray) -> tuple[FloatArray, np.ndarray]:
    """Unit normals (k, 3) of region rid's sub-patch at local (s, r) (k,), by central differences
    of step _STEP (one-sided at the sides), and which are defined."""
    return normal_sets(net, [(rid, s, r)])[0]


def _angle(a: FloatArray, b: FloatArray) -> FloatArray:
    return np.degrees(np.arccos(np.minimum(np.maximum(np.einsum("ij,ij->i", a, b), -1.0), 1.0)))


def turn_from_mean_deg(normals: FloatArray, ok: np.ndarray) -> float:
    """Largest angle (deg) between the defined unit normals (k, 3) (ok: (k,) which are) and their
    mean normal; 0 with fewer than 3, 180 when they cancel out."""
    return _turns_from_mean_deg([(normals, ok)])[0]


TUCK_REACH = 0.15
"""Two normals of one face more than 90 deg apart are a fold when they are closer than this share
of the sketch's diagonal (tuck_deg): a face that turns that far over more room follows the shape
drawn (a strip across a cylinder panel 0.75 of the diagonal wide spreads ~100 deg), and a smooth
surface turns that far within it only where its radius of curvature is under a tenth of the
diagonal."""


def tuck_deg(normals: FloatArray, ok: np.ndarray, points: FloatArray, reach: float) -> float:
    """Largest angle (deg) between two defined unit normals (k, 3) (ok: (k,) which are) at points
    (k, 3) less than `reach` apart: how far the surface turns within that distance. A tuck whose
    turned-over part is a small share of a face moves the mean normal little, so the turn from the
    mean reads about half of it (famK cyl_penta_8: a sliver 128 deg across, 69 deg from its mean,
    upside down against the truth)."""
    return tucks_deg(normals[None], ok[None], points[None], reach)[0]


def tucks_deg(normals: FloatArray, ok: np.ndarray, points: FloatArray, reach: float) -> list[float]:
    """tuck_deg of several sets at once: normals and points (m, k, 3), ok (m, k). The arithmetic
    is per pair of samples, so one set gives what it gives alone."""
    unit = np.asarray(normals, dtype=float)
    at = np.asarray(points, dtype=float)
    both = ok[:, :, None] & ok[:, None, :]
    near = np.linalg.norm(at[:, :, None, :] - at[:, None, :, :], axis=-1) < reach
    dot = (unit[:, :, None, 0] * unit[:, None, :, 0] + unit[:, :, None, 1] * unit[:, None, :, 1]
           + unit[:, :, None, 2] * unit[:, None, :, 2])
    cos = np.where(near & both, dot, 1.0).min(axis=(1, 2), initial=1.0)
    return [0.0 if n < 2 else float(np.degrees(np.arccos(min(max(float(c), -1.0), 1.0))))
            for n, c in zip(ok.sum(axis=1), cos)]


FOLD_DENSE = 33
"""Points per side of the grid (FACE_INSET in from its sides, inset_grid) on which a built face's
turn from its mean normal is read (cad.analysis.folds) and on which a loop's corners are judged
(loop_corners.patch_turns_deg(dense=True)). A tuck 3-5 % of a face wide that fell between the lines
of the 9 x 9 grid turned 112 deg over unreported (sketchgen family 201000 sk_cyl_penta_8: "quality:
ok", found by the comparison with the truth alone); on 33 x 33 it reads 112 deg, and no other face
of that family's 90 sketches or of family 193000's 90 turns more than 62 deg. (The tucks' pairwise
test, tuck_deg, stays on the 9 x 9 grid: it compares every pair of samples.) Judged on 9 x 9, CASSIE
10-2-1's loop of surface 12 turned 69 deg, on this grid 93, and its built face was reported folding
(92 deg) with the paper's corners kept; teapot's surface 43, 79 and 94."""


@lru_cache(maxsize=8)
def inset_grid(n: int) -> tuple[FloatArray, FloatArray]:
    """Local (s, r) (n*n,) each: an n x n grid FACE_INSET in from a face's sides, where the built
    face's fold check samples it (cad.analysis)."""
    g = np.linspace(FACE_INSET, 1.0 - FACE_INSET, n)
    s, r = (a.ravel() for a in np.meshgrid(g, g, indexing="ij"))
    s.setflags(write=False)           # made once (lru_cache), shared by every check
    r.setflags(write=False)
    return s, r


@lru_cache(maxsize=8)
def _face_samples(n: int = FACE_SAMPLES) -> tuple[FloatArray, FloatArray]:
    """Local (s, r) over a region, (2*n*n,) each: an n x n grid from side to side, and the n x n
    grid FACE_INSET in from the sides where the built face's check samples
    (cad.analysis.face_turn_deg): a tuck narrower than the first grid's step can turn over there
    (famG octant_8: 72 deg on the sides' grid, 156 deg on the inset one, a fold of the built face).
    Both are kept: with the inset grid alone (b5697fd) fuselage1 kept a stroke (13) that, with
    both, turns a region over 136 deg and is rejected, while the same sketch rotated rejected it
    (tests/core/test_invariance_real.py)."""
    out = []
    for lo in (0.0, FACE_INSET):
        g = np.linspace(lo, 1.0 - lo, n)
        out.append([a.ravel() for a in np.meshgrid(g, g, indexing="ij")])
    s, r = np.concatenate([out[0][0], out[1][0]]), np.concatenate([out[0][1], out[1][1]])
    s.setflags(write=False)           # made once (lru_cache), shared by every fold check
    r.setflags(write=False)
    return s, r


def face_turn_deg(net, rid: int, n: int = FACE_SAMPLES) -> float:
    """Largest angle (deg) between a normal of region rid and the region's mean normal."""
    normals, ok = region_normals(net, rid, *_face_samples(n))
    return turn_from_mean_deg(normals, ok)


def _seam_uv(edges: list, n: int) -> FloatArray:
    """Pre-image points (len(edges), n, 2) of edge views, 5 %..95 % along each."""
    t = np.linspace(0.05, 0.95, n)
    uv0 = np.array([e.uv0 for e in edges]).reshape(-1, 2)
    uv1 = np.array([e.uv1 for e in edges]).reshape(-1, 2)
    return uv0[:, None, :] + t[None, :, None] * (uv1 - uv0)[:, None, :]


def _seam_angle(sides: list[tuple[FloatArray, np.ndarray]]) -> float:
    """Largest angle (deg) between the two regions' normals at the samples both define."""
    return _seam_angles([sides])[0]


def seam_angle_deg(net, eid: int, regions: tuple, n: int = SEAM_SAMPLES) -> float:
    """Largest angle (deg) between the normals of the two regions along edge eid, 5 %..95 %."""
    edge = net.edges()[eid]
    uv = _seam_uv([edge], n)[0]
    local = seam_local(net, [(rid, edge, uv) for rid in regions])
    return _seam_angle([region_normals(net, rid, s, r) for rid, (s, r) in zip(regions, local)])


_SIDES = ((0, 1), (1, 2), (3, 2), (0, 3))
"""A region's sides as corner pairs (bottom c0->c1, right c1->c2, top c3->c2, left c0->c3): on each
the bilinear map of the corners (NetworkSurface.local_to_uv) is linear, (s, 0), (1, r), (s, 1), (0, r)."""


def seam_local(net, jobs: Sequence[tuple[int, object, FloatArray]]) -> list[tuple[FloatArray, FloatArray]]:
    """Local (s, r) in region rid of pre-image points uv (k, 2) on one of its edges, for each (rid,
    edge view, uv): net.uv_to_local's values without its Newton iterations. The edge lies on one
    side of the region (a straight line in the pre-image), where the bilinear map is linear: s or r
    is the point's share along that side, the other 0 or 1 (most of a stroke's fold checks went to
    inverting these seam samples)."""
    if not jobs:
        return []
    corners: dict = {}
    for rid, _, _ in jobs:
        if rid not in corners:
            ids, _ = net.region_corners(rid)
            corners[rid] = [net.node_uv(n) for n in ids]
    c = np.array([corners[rid] for rid, _, _ in jobs], dtype=float)                 # (J, 4, 2)
    ends = np.array([(e.uv0, e.uv1) for _, e, _ in jobs], dtype=float)            # (J, 2, 2)
    i, j = np.array(_SIDES).T
    a, d = c[:, i], c[:, j] - c[:, i]                                             # (J, 4, 2)
    length = np.hypot(d[..., 0], d[..., 1])
    rel = ends[:, None, :, :] - a[:, :, None, :]                                  # (J, 4, 2, 2)
    off = np.abs(d[:, :, None, 0] * rel[..., 1] - d[:, :, None, 1] * rel[..., 0]).max(axis=2)
    off = np.where(length > 0.0, off / np.where(length > 0.0, length, 1.0), np.inf)
    pick = off.argmin(axis=1)                                                     # (J,)
    rows = np.arange(len(jobs))
    a, d = a[rows, pick], d[rows, pick]                                           # (J, 2)
    uv = np.array([np.asarray(p, dtype=float).reshape(-1, 2) for _, _, p in jobs])  # (J, k, 2)
    f = clip01(np.einsum("jkc,jc->jk", uv - a[:, None, :], d) / np.einsum("jc,jc->j", d, d)[:, None])
    fixed = np.where((pick == 0) | (pick == 3), 0.0, 1.0)[:, None]                  # (J, 1)
    along_s = ((pick == 0) | (pick == 2))[:, None]
    s_out, r_out = np.where(along_s, f, fixed), np.where(along_s, fixed, f)
    return list(zip(s_out, r_out))


def find_folds(net, regions: Optional[Iterable[int]] = None, sharp_curves: Iterable[int] = ()) -> list[Fold]:
    """Every fold of the network among ``regions`` (default: all) and the seams they share with
    any neighbour. ``sharp_curves``: curves drawn sharp, whose seams may crease.

    The same checks as face_turn_deg and seam_angle_deg, with the same values, all evaluated
    together (normal_sets): one call per check was most of a stroke's time."""
    live = set(net.region_ids)
    todo = live if regions is None else set(regions) & live
    sharp = set(sharp_curves)
    edges = net.edges()
    seams = [(eid, tuple(owners)) for eid, owners in net.edge_regions().items()
             if len(owners) == 2 and set(owners) & todo and edges[eid].curve_id not in sharp]
    faces = sorted(todo)
    pairs = [(eid, rid) for eid, owners in seams for rid in owners]
    uv = dict(zip([eid for eid, _ in seams], _seam_uv([edges[eid] for eid, _ in seams], SEAM_SAMPLES)))
    local = seam_local(net, [(rid, edges[eid], uv[eid]) for eid, rid in pairs])
    grid = _face_samples()
    got = normal_sets(net, [(rid, *grid) for rid in faces]
                      + [(rid, s, r) for (_, rid), (s, r) in zip(pairs, local)])
    normals = dict(zip([(rid, "face") for rid in faces] + [(rid, eid) for eid, rid in pairs], got))
    out: list[Fold] = []
    for rid, turn in zip(faces, _turns_from_mean_deg([normals[rid, "face"] for rid in faces])):
        if turn > FACE_TURN_DEG:
            out.append(Fold("face", turn, (rid,)))
    angles = _seam_angles([[normals[rid, eid] for rid in owners] for eid, owners in seams])
    for (eid, owners), angle in zip(seams, angles):
        if angle > SEAM_FOLD_DEG:
            out.append(Fold("seam", angle, owners, eid, edges[eid].curve_id))
    return out


def _turns_from_mean_deg(sets: list[tuple[FloatArray, np.ndarray]]) -> list[float]:
    """turn_from_mean_deg of several (normals (k, 3), ok (k,)) of one size k, at once (the
    arithmetic is per set, row by row: one set gives what it gives alone)."""
    if not sets:
        return []
    unit = np.stack([n for n, _ in sets])
    ok = np.stack([k for _, k in sets])
    total = np.where(ok[..., None], unit, 0.0).sum(axis=1)          # (adding 0.0 changes no sum)
    size = np.linalg.norm(total, axis=-1)
    good = size > 1e-12 * np.maximum(size, 1e-300)
    mean = total / np.where(good, size, 1.0)[:, None]
    k = unit.shape[1]
    angle = _angle(unit.reshape(-1, 3), np.repeat(mean, k, axis=0)).reshape(-1, k)
    worst = np.where(ok, angle, -np.inf).max(axis=1)
    out = np.where(good, worst, 180.0)
    return [0.0 if n < 3 else float(t) for n, t in zip(ok.sum(axis=1), out)]


def _seam_angles(sides: list[list[tuple[FloatArray, np.ndarray]]]) -> list[float]:
    """_seam_angle of several seams whose sides have one number of samples, at once."""
    if not sides:
        return []
    n0, n1 = (np.stack([s[i][0] for s in sides]) for i in (0, 1))
    ok = np.stack([s[0][1] for s in sides]) & np.stack([s[1][1] for s in sides])
    k = n0.shape[1]
    angle = _angle(n0.reshape(-1, 3), n1.reshape(-1, 3)).reshape(-1, k)
    worst = np.where(ok, angle, -np.inf).max(axis=1)
    return [float(a) if any_ok else 0.0 for a, any_ok in zip(worst, ok.any(axis=1))]


def surface_normal_vectors(net, uv: FloatArray) -> FloatArray:
    """Normal vectors (k, 3), not unit, of the network's surface at pre-image points uv (k, 2): the
    cross product of its differences of _STEP in the pre-image (backward at the far sides)."""
    uv = np.clip(np.asarray(uv, dtype=float).reshape(-1, 2), 0.0, 1.0)
    h = np.where(uv + _STEP <= 1.0, _STEP, -_STEP)
    p, pu, pv = net.evaluate_uv_sets([uv, uv + np.column_stack([h[:, 0], 0 * h[:, 0]]),
                                      uv + np.column_stack([0 * h[:, 1], h[:, 1]])])
    du = (pu - p) / h[:, :1]
    dv = (pv - p) / h[:, 1:]
    return cross3(du, dv)


def surface_turn_deg(net, uv: FloatArray) -> float:
    """Largest angle (deg) between a normal of the network's surface at pre-image points uv (k, 2)
    and their mean normal: how much the surface itself turns over that part of the pre-image."""
    return turn_from_mean_deg(*_unit(surface_normal_vectors(net, uv)))
