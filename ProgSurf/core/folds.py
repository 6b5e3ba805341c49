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
from typing import Iterable, Optional

import numpy as np

from .types import FloatArray

SEAM_FOLD_DEG = 55.0
FACE_TURN_DEG = 85.0
SEAM_SAMPLES = 9
FACE_SAMPLES = 9
_STEP = 1e-4


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


def region_normals(net, rid: int, s: FloatArray, r: FloatArray) -> tuple[FloatArray, np.ndarray]:
    """Unit normals (k, 3) of region rid's sub-patch at local (s, r) (k,), and which are defined."""
    s = np.asarray(s, dtype=float)
    r = np.asarray(r, dtype=float)
    s0, s1 = np.clip(s - _STEP, 0, 1), np.clip(s + _STEP, 0, 1)
    r0, r1 = np.clip(r - _STEP, 0, 1), np.clip(r + _STEP, 0, 1)
    ss = np.concatenate([s0, s1, s, s])
    rr = np.concatenate([r, r, r0, r1])
    p = net.evaluate_region(rid, ss, rr).reshape(4, len(s), 3)
    du = (p[1] - p[0]) / (s1 - s0)[:, None]
    dv = (p[3] - p[2]) / (r1 - r0)[:, None]
    n = np.cross(du, dv)
    lu, lv = np.linalg.norm(du, axis=1), np.linalg.norm(dv, axis=1)
    unit, ok = _unit(n)
    ok &= np.linalg.norm(n, axis=1) > 1e-6 * np.maximum(lu * lv, 1e-300)
    # on (or next to) a collapsed side one derivative is round-off: its direction means nothing
    size = max(float(np.max(lu, initial=0.0)), float(np.max(lv, initial=0.0)), 1e-300)
    ok &= (lu > 1e-6 * size) & (lv > 1e-6 * size)
    return unit, ok


def _angle(a: FloatArray, b: FloatArray) -> FloatArray:
    return np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", a, b), -1.0, 1.0)))


def turn_from_mean_deg(normals: FloatArray, ok: np.ndarray) -> float:
    """Largest angle (deg) between the defined unit normals (k, 3) (ok: (k,) which are) and their
    mean normal; 0 with fewer than 3, 180 when they cancel out."""
    if ok.sum() < 3:
        return 0.0
    mean, good = _unit(normals[ok].sum(axis=0))
    if not good:
        return 180.0
    return float(_angle(normals[ok], np.broadcast_to(mean, normals[ok].shape)).max())


def face_turn_deg(net, rid: int, n: int = FACE_SAMPLES) -> float:
    """Largest angle (deg) between a normal of region rid and the region's mean normal."""
    g = np.linspace(0.0, 1.0, n)
    s, r = (a.ravel() for a in np.meshgrid(g, g, indexing="ij"))
    normals, ok = region_normals(net, rid, s, r)
    return turn_from_mean_deg(normals, ok)


def seam_angle_deg(net, eid: int, regions: tuple, n: int = SEAM_SAMPLES) -> float:
    """Largest angle (deg) between the normals of the two regions along edge eid, 5 %..95 %."""
    e = net.edges()[eid]
    t = np.linspace(0.05, 0.95, n)
    uv = e.uv0 + np.outer(t, e.uv1 - e.uv0)
    normals, oks = [], []
    for rid in regions:
        s, r = net.uv_to_local(rid, uv)
        nrm, ok = region_normals(net, rid, np.clip(s, 0, 1), np.clip(r, 0, 1))
        normals.append(nrm)
        oks.append(ok)
    ok = oks[0] & oks[1]
    if not ok.any():
        return 0.0
    return float(_angle(normals[0][ok], normals[1][ok]).max())


def find_folds(net, regions: Optional[Iterable[int]] = None, sharp_curves: Iterable[int] = ()) -> list[Fold]:
    """Every fold of the network among ``regions`` (default: all) and the seams they share with
    any neighbour. ``sharp_curves``: curves drawn sharp, whose seams may crease."""
    live = set(net.region_ids)
    todo = live if regions is None else set(regions) & live
    sharp = set(sharp_curves)
    out: list[Fold] = []
    for rid in sorted(todo):
        turn = face_turn_deg(net, rid)
        if turn > FACE_TURN_DEG:
            out.append(Fold("face", turn, (rid,)))
    edges = net.edges()
    for eid, owners in net.edge_regions().items():
        if len(owners) != 2 or not (set(owners) & todo):
            continue
        cid = edges[eid].curve_id
        if cid in sharp:
            continue
        angle = seam_angle_deg(net, eid, tuple(owners))
        if angle > SEAM_FOLD_DEG:
            out.append(Fold("seam", angle, tuple(owners), eid, cid))
    return out


def surface_turn_deg(net, uv: FloatArray) -> float:
    """Largest angle (deg) between a normal of the network's surface at pre-image points uv (k, 2)
    and their mean normal: how much the surface itself turns over that part of the pre-image."""
    uv = np.clip(np.asarray(uv, dtype=float).reshape(-1, 2), 0.0, 1.0)
    h = np.where(uv + _STEP <= 1.0, _STEP, -_STEP)
    p = net.evaluate_uv(uv)
    du = (net.evaluate_uv(uv + np.column_stack([h[:, 0], 0 * h[:, 0]])) - p) / h[:, :1]
    dv = (net.evaluate_uv(uv + np.column_stack([0 * h[:, 1], h[:, 1]])) - p) / h[:, 1:]
    normals, ok = _unit(np.cross(du, dv))
    return turn_from_mean_deg(normals, ok)
