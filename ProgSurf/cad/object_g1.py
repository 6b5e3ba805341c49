"""G1 across the curves that two surfaces of a whole object share (issue 18: "G1 across a shared
curve where the sketch is smooth there, sharp where it was drawn sharp").

Each surface is built on its own (cad.shell.build_shell); in G1 mode its faces are tangent-continuous
across its inner seams (cad.g1). Where two surfaces share a curve, their boundary edges there are
pieces of one curve (cad.shared_edges), so a point of one surface's side is a point of the other's.
Each face along such a curve is told the other surface's normal there (Across), and its side becomes
a seam like an inner one: both faces' flux corrections aim at the same common normal (the mean of
the two G0 normals, the other one turned to agree with its own: each surface is oriented by its own
pre-image), so the two faces meet tangent-continuous, within the same bound on how far G1 may move a
face (cad.g1.OFFSET_FRACTION).

A curve along which the two surfaces meet at an angle was drawn sharp (a box's edge): where, at any
point along it away from its ends, the directions in which the two faces leave the curve are more
than SHARP_DEG from opposite, it is left as G0 makes it. So is a curve that more than two surfaces
share at one place (no one tangent plane there).
"""
from __future__ import annotations

import copy
from dataclasses import dataclass

import numpy as np

from ..core.bspline_surface import unit_normals
from ..core.continuity import KINK_ANGLE_DEG
from ..core.network import OUTER_CURVES
from ..core.types import FloatArray
from .g1 import _side_points

SHARP_DEG = KINK_ANGLE_DEG
"""Two surfaces leaving a shared curve more than this from opposite directions meet at a sharp
curve (the rule for a stroke drawn with a kink, core.continuity.KINK_ANGLE_DEG)."""
SIDE_SAMPLES = 129
"""Points per side piece at which the other surfaces are looked up (then refined between them)."""
CHECK = np.linspace(0.05, 0.95, 19)
"""Edge parameters at which a shared curve is tested for a sharp angle and measured (ends left out:
three or more surfaces meet there)."""


def _inward(k: int, ds: FloatArray, dr: FloatArray) -> FloatArray:
    """The derivative across side k (bottom, right, top, left) pointing into the face."""
    return (dr, -ds, -dr, ds)[k]


def _across_curve(inward: FloatArray, tangent: FloatArray) -> tuple[FloatArray, np.ndarray]:
    """Unit (m, 3) of `inward` with its part along `tangent` removed, and (m,) where defined."""
    t = tangent / np.maximum(np.linalg.norm(tangent, axis=1), 1e-300)[:, None]
    d = inward - np.einsum("ij,ij->i", inward, t)[:, None] * t
    size = np.linalg.norm(d, axis=1)
    ok = size > 1e-9 * np.maximum(np.linalg.norm(inward, axis=1), 1e-300)
    return d / np.where(ok, size, 1.0)[:, None], ok


def _squared_distances(q: FloatArray, points: FloatArray) -> FloatArray:
    """(m, n) squared distances between q (m, 3) and points (n, 3): ((q - p) ** 2).sum(axis=-1),
    the same arithmetic (each square rounded, added x + y, then z), without the slow reduction
    over a 3-wide axis of an (m, n, 3) temporary (across_maps finds thousands of nearest samples)."""
    out = np.subtract.outer(q[:, 0], points[:, 0])
    out *= out
    for k in (1, 2):
        d = np.subtract.outer(q[:, k], points[:, k])
        d *= d
        out += d
    return out


@dataclass(frozen=True)
class _Side:
    """One piece of a face's side on its surface's boundary, sampled for the lookup."""

    surface: int
    info: object
    k: int
    piece: object
    w: FloatArray
    points: FloatArray

    def evaluate(self, w: FloatArray) -> tuple:
        return self.info.derived.derivatives.evaluate(*_side_points(self.k, w))


def _sides(results: list, networks: list) -> list[_Side]:
    """Every boundary side piece of every G0 face of every surface (results: ShellResults,
    networks: their PatchNetworks), sampled."""
    out = []
    for n, (res, network) in enumerate(zip(results, networks)):
        edges = network.edges()
        for info in res.g0_faces or res.faces:
            for k, pieces in enumerate(info.sides):
                for p in pieces:
                    if edges[p.edge_id].curve_id in OUTER_CURVES:
                        w = np.linspace(p.a, p.b, SIDE_SAMPLES)
                        out.append(_Side(n, info, k, p, w, info.derived.derivatives.evaluate(*_side_points(k, w))[0]))
    return out


class Across:
    """The faces of the other surface along one boundary edge of a surface: its normal and the
    direction it leaves the curve in, at points of the curve."""

    def __init__(self, sides: list, reach: float):
        self.sides = sides
        self.reach = reach
        self.key = tuple(sorted(id(s.info) for s in sides))
        """What the G1 faces along the edge read of the other surface (cad.g1._face_key)."""
        self._points = np.concatenate([s.points for s in sides])
        self._owner = np.repeat(np.arange(len(sides)), [len(s.points) for s in sides])
        self._index = np.concatenate([np.arange(len(s.points)) for s in sides])
        self._count = np.array([len(s.points) for s in sides])
        self._w = np.concatenate([s.w for s in sides])
        self.partners: set = set()
        """(surface, boundary edge id) of the other surface's sides along this edge (across_maps)."""
        self.angles = np.full(len(CHECK), np.nan)
        """angle_deg at CHECK along the piece of this surface's side it was found for (across_maps)."""
        self.near_corner = np.zeros(len(CHECK), dtype=bool)
        """Where, at CHECK, the other surface's point lies within CORNER_SKIP of a corner of its
        face (across_maps): there it leaves the curve along its adjacent side, drawn there."""
        self.smooth_here = False
        """Whether the two surfaces continue each other along this edge, decided alike on both sides
        (across_maps; smooth() seen from this side alone)."""
        self.follow = False
        """The other surface's faces along this edge stay G0 (following): this side's G1 correction
        aims at their normal instead of the mean of the two (cad.g1._Seams.normals)."""

    def _locate(self, points: FloatArray) -> tuple[np.ndarray, FloatArray, np.ndarray]:
        """(side index (m,), its side parameter (m,), (m,) True where within reach) of points (m, 3):
        the nearest sample, then the nearest point of the chords to its neighbours on its side."""
        q = np.asarray(points, dtype=float).reshape(-1, 3)
        near = _squared_distances(q, self._points).argmin(axis=1)
        owner, i = self._owner[near], self._index[near]
        best = np.linalg.norm(self._points[near] - q, axis=1)
        w = self._w[near].copy()
        for step in (-1, 1):
            other = near + step
            ok = (i + step >= 0) & (i + step < self._count[owner])
            other = np.where(ok, other, near)
            a, ab = self._points[near], self._points[other] - self._points[near]
            x = np.clip(np.einsum("ij,ij->i", q - a, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300), 0.0, 1.0)
            d = np.linalg.norm(a + x[:, None] * ab - q, axis=1)
            better = ok & (d < best)
            best = np.where(better, d, best)
            w = np.where(better, self._w[near] + x * (self._w[other] - self._w[near]), w)
        return owner, w, best <= self.reach

    def _frames(self, points: FloatArray) -> tuple[FloatArray, FloatArray, np.ndarray]:
        """(normals, inward derivatives, defined), each (m, 3) / (m,)."""
        owner, w, ok = self._locate(points)
        m = len(w)
        normals, inward = np.zeros((m, 3)), np.zeros((m, 3))
        for o in np.unique(owner):
            rows = np.flatnonzero(owner == o)
            side = self.sides[o]
            _, ds, dr = side.evaluate(w[rows])
            n, n_ok = unit_normals(ds, dr)
            normals[rows], inward[rows] = n, _inward(side.k, ds, dr)
            ok[rows] &= n_ok
        return normals, inward, ok

    def normals(self, points: FloatArray) -> tuple[FloatArray, np.ndarray]:
        """The other surface's unit normals (m, 3) at points (m, 3) of the curve, (m,) where defined."""
        normals, _, ok = self._frames(points)
        return normals, ok

    def angle_deg(self, info, k: int, piece, at: FloatArray = CHECK) -> FloatArray:
        """At `at` (default CHECK) along the piece of side k of face info: how far (deg) the two
        surfaces leave the curve from opposite directions (0: one smooth surface; 90: a box's edge;
        180: they leave it alike, one folded onto the other); NaN where either is undefined."""
        w = piece.a + ((1.0 - at) if piece.reversed else at) * (piece.b - piece.a)
        points, ds, dr = info.derived.derivatives.evaluate(*_side_points(k, w))
        tangent = ds if k in (0, 2) else dr
        mine, ok_a = _across_curve(_inward(k, ds, dr), tangent)
        _, inward, ok = self._frames(points)
        other, ok_b = _across_curve(inward, tangent)
        cos = np.clip(-np.einsum("ij,ij->i", mine, other), -1.0, 1.0)
        return np.where(ok & ok_a & ok_b, np.degrees(np.arccos(cos)), np.nan)

    def smooth(self) -> bool:
        """True where the two surfaces continue each other all along the piece: its angles within
        SHARP_DEG everywhere. (The median alone let in curves along which the faces part by 60-90
        deg somewhere, a fin where another surface folds back; G1 then made fuselage1's worst angle
        across surfaces 90 deg where G0 had 51.)"""
        return bool(np.isfinite(self.angles).any() and np.nanmax(self.angles) <= SHARP_DEG)


def across_maps(results: list, networks: list, reach: float) -> list[dict]:
    """Per surface, {boundary edge id: Across} of its boundary edges along which, at every point
    (within reach mm: the sewing tolerance), exactly one other surface lies (the same or one after
    another), from the G0 faces. results: ShellResults, networks: their PatchNetworks."""
    sides = _sides(results, networks)
    out: list[dict] = [{} for _ in results]
    if not sides:
        return out
    lo = np.array([s.points.min(axis=0) - reach for s in sides])
    hi = np.array([s.points.max(axis=0) + reach for s in sides])
    surface = np.array([s.surface for s in sides])
    for j, mine in enumerate(sides):
        near = np.flatnonzero((surface != mine.surface) & np.all(lo <= hi[j], axis=1) & np.all(lo[j] <= hi, axis=1))
        p = mine.piece
        q = mine.evaluate(p.a + CHECK * (p.b - p.a))[0]
        # which other surfaces lie along it, point by point: one along all of it (in one or more
        # faces, of one or more surfaces one after another), never two at one point
        others = sorted({sides[i].surface for i in near})
        reached = np.array([Across([sides[i] for i in near if sides[i].surface == n], reach)._locate(q)[2]
                            for n in others]).reshape(len(others), len(q))
        if not len(others) or not np.all(reached.sum(axis=0) == 1):
            continue
        along = {n for n, hit in zip(others, reached) if hit.any()}
        found = out[mine.surface][p.edge_id] = Across([sides[i] for i in near if sides[i].surface in along], reach)
        owner, w, ok = found._locate(q)
        found.partners = {(found.sides[o].surface, found.sides[o].piece.edge_id) for o in owner[ok]}
        found.angles = found.angle_deg(mine.info, mine.k, p)
        found.near_corner = ok & (np.minimum(w, 1.0 - w) < CORNER_SKIP)
        found.smooth_here = found.smooth()
    # one decision for both sides of a shared piece: smooth where every side along it, seen from
    # its own face, finds the surfaces continuing each other (a side judged on a longer piece can
    # part where a shorter one across it does not; G1 on one side only would meet no aim)
    changed = True
    while changed:
        changed = False
        for n, found_n in enumerate(out):
            for a in found_n.values():
                if a.smooth_here and not all(out[m][e].smooth_here if e in out[m] else False for m, e in a.partners):
                    a.smooth_here, changed = False, True
    return out


def following(results: list, maps: list) -> list[dict]:
    """Per surface, the across map (across_maps) to build its G1 faces with again, or None: where the
    other surface's faces along a smooth shared curve were left G0 (their correction turned them over,
    cad.g1.smooth_face, or made a new fold, cad.shell.keep_no_new_fold), a side that aimed at the
    mean of the two normals met a face that did not move and kept half the G0 angle (the TiGL noisy
    helicopter: 14.7 of 29.4 deg). Those edges get a copy of their Across that follows the other
    surface's normal (the caller keeps the surface built with it where that leaves a smaller angle:
    a face that cannot turn the whole way within the bound is scaled down, cad.g1.smooth_face,
    and can end further from the other than half way). results: the G1 ShellResults, maps:
    across_maps of their G0 faces."""
    stayed = []
    for res in results:
        turned = {g.region_id for g, _ in res.cache.g1_shapes.values() if g.turned_over}
        stayed.append(turned | set(res.g1_reverted))
    out: list = []
    for found in maps:
        changed = {}
        for edge, a in found.items():
            if a.smooth_here and a.sides and all(s.info.region_id in stayed[s.surface] for s in a.sides):
                b = copy.copy(a)
                b.follow = True
                b.key = a.key + ("follow",)
                changed[edge] = b
        out.append({**found, **changed} if changed else None)
    return out


END_CHECK = np.array([0.02, 0.98])
"""Edge parameters next to a piece's ends. There each face leaves the shared curve along the side
that meets it there (a Coons patch's derivative across a side at a corner is the tangent of the
adjacent side): along the strokes drawn across the curve."""
CORNER_SKIP = 0.05
"""A point of a shared curve this close (in its side's parameter) to a corner of the other
surface's face is not checked for a crease: there that face leaves the curve along its adjacent
side, which a stroke drew (the rule of END_CHECK, seen from the other side). Measured exactly at
such a corner the angle was a matter of round-off (fuselage1 clean: 116 deg on one OpenBLAS kernel,
undefined on another, next to readings of 65 deg)."""
FOLD_RISE_DEG = 60.0
"""A shared piece along which the two surfaces part, somewhere between its ends, by more than this
beyond how they leave it at its ends folds one surface onto the other (a fin or a tuck nobody drew:
issue 16's fold, two faces whose normals differ by more than 60 deg away from the ends where no
sharp feature was drawn; what the strokes drew is how the surfaces leave the curve at its ends)."""


def across_folds(results: list, maps: list) -> list[dict]:
    """The folds across surfaces of G0 faces (results: ShellResults, maps: their across_maps): per
    shared piece (once, from the surface with the lower index), {"surfaces": (a, b), "edge": boundary
    edge id of a, "angle_deg": the largest angle between its ends (Across.angles), "ends_deg": the
    larger at its ends}, where the first exceeds the second by more than FOLD_RISE_DEG."""
    out = []
    for n, (res, found) in enumerate(zip(results, maps)):
        for info in res.g0_faces or res.faces:
            for k, pieces in enumerate(info.sides):
                for p in pieces:
                    a = found.get(p.edge_id)
                    if a is None or not a.partners or not np.isfinite(a.angles).any():
                        continue
                    other = min(m for m, _ in a.partners)
                    if other < n:
                        continue
                    ends = a.angle_deg(info, k, p, END_CHECK)
                    top = float(np.nanmax(ends)) if np.isfinite(ends).any() else 0.0
                    # away from both surfaces' corners: next to its own ends (CHECK) and to the
                    # other's face corners, each face leaves the curve along a side drawn there
                    inner = np.where(a.near_corner, np.nan, a.angles)
                    if not np.isfinite(inner).any():
                        continue
                    worst = float(np.nanmax(inner))
                    if worst > top + FOLD_RISE_DEG:
                        out.append({"surfaces": (n, other), "edge": p.edge_id, "angle_deg": worst, "ends_deg": top})
    return out


TANGENT_DEG = 1.0
"""A shared curve along which the two surfaces' normals stay within this is counted tangent-continuous."""


def _side_angles(results: list, maps: list, only=None):
    """(surface index, smooth: bool, the largest angle (deg) between the two surfaces' normals at
    CHECK, 0 on a sharp side) per side of a G0 face on a shared curve (across_angles), of every
    surface or of the surface indices in `only`."""
    finals = [{info.region_id: info for info in res.faces} for res in results]
    for n, (res, final, found) in enumerate(zip(results, finals, maps)):
        if only is not None and n not in only:
            continue
        for info in res.g0_faces or res.faces:
            for k, pieces in enumerate(info.sides):
                for p in pieces:
                    a = found.get(p.edge_id)
                    if a is None:
                        continue
                    if not a.smooth_here:
                        yield n, False, 0.0
                        continue
                    w = p.a + CHECK * (p.b - p.a)
                    points, ds, dr = final[info.region_id].derived.derivatives.evaluate(*_side_points(k, w))
                    na, ok_a = unit_normals(ds, dr)
                    # the other surface's built faces, at the places of its G0 faces' samples
                    other = Across([_Side(s.surface, finals[s.surface][s.info.region_id], s.k, s.piece, s.w, s.points)
                                    for s in a.sides], a.reach)
                    nb, ok_b = other.normals(points)
                    ok = ok_a & ok_b
                    angle = np.degrees(np.arccos(np.clip(np.abs(np.einsum("ij,ij->i", na, nb))[ok], 0.0, 1.0)))
                    yield n, True, float(angle.max()) if len(angle) else 0.0


def worst_side_deg(results: list, maps: list, surface: int) -> float:
    """The largest angle (deg) between one surface's normals and its neighbours' along the smooth
    curves it shares (_side_angles; 0 without)."""
    return max((top for _, smooth, top in _side_angles(results, maps, {surface}) if smooth), default=0.0)


def across_angles(results: list, maps: list) -> dict:
    """The angles (deg) between the two surfaces' normals along every side of a face on a shared
    curve that is smooth in G0 (CHECK points, the other's normal turned to agree): the largest, how
    many such sides stay within TANGENT_DEG, and how many sides of each kind (a shared piece counts
    once from each of its surfaces; the G1 defect across surfaces: 0 where tangent-continuous).
    results: the built ShellResults (their faces: G0 or G1), maps: across_maps of their G0 faces."""
    worst, smooth, sharp, tangent = 0.0, 0, 0, 0
    for _, is_smooth, top in _side_angles(results, maps):
        if not is_smooth:
            sharp += 1
            continue
        smooth += 1
        worst = max(worst, top)
        tangent += top <= TANGENT_DEG
    return {"smooth_sides": smooth, "sharp_sides": sharp, "tangent_sides": tangent, "angle_max_deg": worst}
