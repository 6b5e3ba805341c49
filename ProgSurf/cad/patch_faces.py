"""The faces of the shell: one exact Coons B-spline face per region, and its G1 replacement.

Qin & Wright section 3.3, second half: each sub-patch of the pre-image network becomes a B-spline
face. Each region side is the join of its shared edge curves (cad.edges), cut where the side's
junction nodes lie (SidePiece), and the face is the exact Coons B-spline surface of its four sides
(faces.coons_surface, Eq. 1), bounded by the surface's iso-curves (make_face). Neighbouring faces
therefore have the same boundary geometry (to ~1e-12 mm, round-off of the pole arithmetic).
In G1 mode each face is then replaced by its flux-corrected surface on the same boundaries (cad.g1,
issue 9).

Incremental: a face whose side pieces, curve objects, corners and shape are unchanged is taken
from the earlier builds' ShellCache (faces, regions; g1_faces, g1_shapes in G1 mode).
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from ..core.errors import FitError
from ..core.plane_fill import HELD, PlaneMap, plane_map, refill_poles
from ..core.types import FloatArray
from ._occ import Part
from .curves import constant_curve, join_side, to_array
from .edges import content_digest
from .faces import coons_surface, full_knots
from .surface_data import SurfaceData

if TYPE_CHECKING:
    from .shell import ShellCache


@dataclass(frozen=True)
class SidePiece:
    """One network edge on one side of a face: it covers side parameters [a, b] of that side."""

    edge_id: int
    reversed: bool
    a: float
    b: float


@dataclass(frozen=True)
class FaceInfo:
    """One face of the shell and where its network edges lie in its (s, r) parameter square.

    sides : (bottom, right, top, left), each a tuple of SidePiece (empty for a degenerate side)
    """

    region_id: int
    surface: object
    face: object
    sides: tuple
    triangle: bool
    refilled: bool = False      # inner poles moved in its loop's plane (refilled_face)
    # where it folds and no refill unfolded it: its loop's map, which a loose refill reuses
    plane: PlaneMap | None = field(default=None, compare=False, repr=False)

    @property
    def poles(self) -> tuple[int, int, int, int]:
        """(nu, nv, udegree, vdegree) of the B-spline surface."""
        s = self.surface
        return s.NbUPoles, s.NbVPoles, s.UDegree, s.VDegree

    @cached_property
    def derived(self) -> SurfaceData:
        """What is derived from the surface (cad.surface_data), kept with the face: build_shell
        reuses a FaceInfo while its face's inputs are unchanged."""
        return SurfaceData(self.surface)


def side_parameter(side_points: FloatArray, side_params: FloatArray, point: FloatArray) -> float:
    """Parameter of the side polyline vertex nearest to `point` (a junction node)."""
    i = int(np.argmin(np.linalg.norm(side_points - point, axis=1)))
    return float(side_params[i])


def _side_pieces(side, curves: dict) -> tuple:
    pts, prm = side.polyline.points, side.polyline.params
    breaks = [0.0]
    for k, (eid, rev) in enumerate(side.edges):
        if k == len(side.edges) - 1:
            breaks.append(1.0)
            break
        c = curves[eid]
        end = np.array(tuple(c.StartPoint if rev else c.EndPoint))
        breaks.append(side_parameter(pts, prm, end))
    if any(b1 <= b0 for b0, b1 in zip(breaks, breaks[1:])):
        raise FitError(f"side junction parameters {breaks} are not increasing; the network side "
                       "polyline does not pass through its edges' nodes")
    return tuple(SidePiece(int(eid), bool(rev), breaks[k], breaks[k + 1])
                 for k, (eid, rev) in enumerate(side.edges))


def _side_curve(pieces: tuple, curves: dict, corner: FloatArray):
    if not pieces:
        return constant_curve(corner)
    return join_side([curves[p.edge_id] for p in pieces], [p.reversed for p in pieces],
                     [pieces[0].a] + [p.b for p in pieces])


def make_face(surface, what: str = "face"):
    """The face of the whole surface, bounded by its four iso-curves (a degenerate side gives
    OCC's degenerated edge). Where a neighbour shares only part of a longer side, the sewing
    (cad.sewing.sew) cuts that edge at the neighbour's vertex, so the faces still meet vertex to
    vertex. (Faces bounded by pre-split iso-edges came out "self-intersecting" from OCC and needed
    a ShapeFix pass that cost ten times the rest of the face.)"""
    face = surface.toShape()
    if not face.isValid():
        size = face.BoundBox.DiagonalLength      # (1e-9, 1e-9, 1e-7) mm on a 100 mm face
        face.fix(1e-11 * size, 1e-11 * size, 1e-9 * size)
        if not face.isValid():
            raise FitError(f"OCC made an invalid {what}; report this sketch")
    return face


REFILL_SIDE_SAMPLES = 120
"""Points per side at which a folding face's border is read for its plane refill."""

REFILL_SPANS = (16, 32, 64)
"""A folding face is refilled with at least this many knot spans each way (knots inserted evenly
where it has fewer: the same surface, more poles to move), tried in turn until a refill does not
fold. With the rows held at its sides, a refill with too few poles kept turning over next to them:
of the refills that still folded with 16 spans on the 82 unseen CASSIE sketches, 154 of 173 did
so within a tenth of the face from a side; with 32, then 64 spans too, 29 more surfaces unfolded
(230 -> 201, each row count tried with all three before the next one; the loop's plane map made
once for all; creases between surfaces 53 -> 52; build time +8 %)."""


REFILL_ROWS = {"G0": HELD, "G1": HELD[:1]}
"""The rows of poles at each side a plane refill keeps, tried in turn (core.plane_fill.HELD), by
continuity: in G1 only the refill that keeps the face's tangent plane along its sides, which the G1
step then turns to its neighbours' (with the sides alone kept, a noisy grid over a wave unfolded one
more surface but 2 of its 15 smooth shared sides stayed 1.5 deg off tangent, all within 0.1 before)."""


def loop_map(info: FaceInfo) -> PlaneMap | None:
    """The map of the face's loop (its border read at REFILL_SIDE_SAMPLES points a side) onto its
    parameter square, which its plane refill inverts (core.plane_fill.plane_map)."""
    t = np.linspace(0.0, 1.0, REFILL_SIDE_SAMPLES, endpoint=False)
    one, nil = np.ones_like(t), np.zeros_like(t)
    uv = np.vstack([np.column_stack([t, nil]), np.column_stack([one, t]),
                    np.column_stack([1.0 - t, one]), np.column_stack([nil, 1.0 - t])])
    border = np.array([tuple(info.surface.value(float(a), float(b))) for a, b in uv])
    return plane_map(border, uv)


def refilled_face(info: FaceInfo, rows: tuple = REFILL_ROWS["G0"], spans: tuple = REFILL_SPANS,
                  loose: bool = False, mapped: PlaneMap | None = None) -> FaceInfo | None:
    """The face with its inner poles refilled in its loop's plane (core.plane_fill), where its
    Coons patch folds (analysis.lone_face_fold_deg beyond FOLD_FACE_DEG) and the refill does not
    (keeping each of `rows` rows of poles at each side in turn, each with at least `spans` knot
    spans each way in turn: the first refill that unfolds it); else None. Its sides, and so every
    edge it shares, are the same curves. loose: a loop seen from a tilted direction or untangled may
    be refilled within its border alone too (core.plane_fill.refill_poles). mapped: the loop's map
    (loop_map) where the caller has found that the face folds and made it."""
    from .analysis import FOLD_FACE_DEG, lone_face_fold_deg

    if mapped is None:
        if info.triangle or lone_face_fold_deg(info) <= FOLD_FACE_DEG:
            return None
        mapped = loop_map(info)         # the loop's map: the same for every knot vector below
        if mapped is None:
            return None
    # each knot vector's refills (one per row count), made once: None where it adds no knot to
    # the one before (the same poles, the same refills)
    levels: dict = {}
    for held in rows:
        for level, least in enumerate(spans):
            if level not in levels:
                surface, inserted = _with_spans(info.surface, least)
                levels[level] = None if level and not inserted else (surface, refill_poles(
                    mapped, to_array(surface.getPoles()), (full_knots(surface, "U"), full_knots(surface, "V")),
                    (surface.UDegree, surface.VDegree), held=rows, loose=loose))
            if levels[level] is None or held not in levels[level][1]:
                continue
            surface, grids = levels[level]
            refill = Part.BSplineSurface()
            refill.buildFromPolesMultsKnots(grids[held].tolist(), surface.getUMultiplicities(),
                                            surface.getVMultiplicities(), surface.getUKnots(),
                                            surface.getVKnots(), False, False, surface.UDegree, surface.VDegree)
            out = FaceInfo(info.region_id, refill, make_face(refill, f"refilled face for region {info.region_id}"),
                           info.sides, info.triangle, True)
            if lone_face_fold_deg(out) <= FOLD_FACE_DEG:
                return out
    return None


def _with_spans(surface, least: int) -> tuple:
    """(a copy of the B-spline surface with knots inserted evenly each way where it has fewer than
    `least` spans: the same surface, more poles to move; whether any were inserted)."""
    surface = surface.copy()
    inserted = False
    for direction in ("U", "V"):        # a straight side's direction has one span: room to move
        knots = getattr(surface, f"get{direction}Knots")()
        if len(knots) - 1 < least:
            inner = np.linspace(0.0, 1.0, least + 1)[1:-1]
            new_knots = [float(k) for k in inner if np.min(np.abs(np.asarray(knots) - k)) > 1e-6]
            getattr(surface, f"insert{direction}Knots")(new_knots, [1] * len(new_knots), 1e-9, False)
            inserted = True
    return surface, inserted


def coons_faces(network, curves: dict, cache: "ShellCache", keep: "ShellCache",
                refill_rows: tuple = REFILL_ROWS["G0"], loose: frozenset = frozenset()) -> tuple[list, tuple]:
    """The G0 face of each region (network.regions() order): the exact Coons B-spline surface of
    its four sides, each side the join of its edge curves (curves: edge id -> piece, fit_edges).

    cache : the earlier builds' ShellCache: a face whose inputs are unchanged is taken from it
            (`regions` for the same region view on the same curve objects, else `faces` by content).
    keep  : receives this build's `faces` and `regions` (reused and new).
    refill_rows : the rows of poles a folding face's plane refill may keep (refilled_face)
    loose : ids of the regions whose refill may be loose (refilled_face)
    Returns ([FaceInfo], (reused, built))."""
    infos = []
    reused = built = 0
    for region in network.regions():
        used = tuple(curves[eid] for side in region.sides for eid, _ in side.edges)
        # the same region view (the network keeps it while the region is unchanged) on the same
        # curve objects makes the same face: no need to cut the sides again
        fast = cache.lookup("regions", region.id)
        refill_key = (refill_rows, region.id in loose)      # (the last entry of its `faces` key)
        if (fast is not None and fast[0] is region and len(fast[1]) == len(used) and fast[3][-1] == refill_key
                and all(a is b for a, b in zip(fast[1], used))):
            info, key = fast[2], fast[3]
            reused += 1
            keep.faces[key] = info
            keep.regions[region.id] = fast
            infos.append(info)
            continue
        pieces = tuple(_side_pieces(side, curves) for side in region.sides)
        corners = np.asarray(region.corners_xyz, dtype=float)
        # the face depends on its side pieces and on the very curve objects they cut
        key = (region.id, pieces, tuple(id(curves[p.edge_id]) for side in pieces for p in side),
               content_digest(corners), bool(region.triangle), refill_key)
        info = cache.lookup("faces", key)
        if info is None:
            # a loose face starts from the face built without that (kept by the build it tries again)
            plain = cache.lookup("faces", key[:-1] + ((refill_rows, False),)) if region.id in loose else None
            if plain is None:
                bottom, right, top, left = (_side_curve(pieces[k], curves, corners[c])
                                            for k, c in ((0, 0), (1, 1), (2, 3), (3, 0)))
                surface = coons_surface(bottom, right, top, left)
                face = make_face(surface, f"face for region {region.id}")
                plain = _refilled(FaceInfo(region.id, surface, face, pieces, bool(region.triangle)), refill_rows)
            info = _loose_refill(plain, refill_rows) if region.id in loose else plain
            built += 1
        else:
            reused += 1
        keep.faces[key] = info
        keep.regions[region.id] = (region, used, info, key)
        infos.append(info)
    return infos, (reused, built)


def _refilled(info: FaceInfo, rows: tuple) -> FaceInfo:
    """The Coons face `info` as coons_faces keeps it: refilled where it folds and a refill does not
    (refilled_face, keeping `rows` rows of poles), else with its loop's map (FaceInfo.plane) where
    it folds."""
    from .analysis import FOLD_FACE_DEG, lone_face_fold_deg

    if info.triangle or lone_face_fold_deg(info) <= FOLD_FACE_DEG:
        return info
    mapped = loop_map(info)
    if mapped is None:
        return info
    return refilled_face(info, rows, mapped=mapped) or replace(info, plane=mapped)


def _loose_refill(plain: FaceInfo, rows: tuple) -> FaceInfo:
    """The face `plain` (as _refilled made it) refilled within its border alone where it still folds
    and its loop was seen from a tilted direction or untangled (refilled_face loose), where that
    unfolds it; else `plain` itself."""
    if plain.plane is None or not plain.plane.reshaped:
        return plain
    return refilled_face(plain, tuple(r for r in rows if r < 2), loose=True, mapped=plain.plane) or plain


def g1_faces(network, g0_infos: tuple, cache: "ShellCache", keep: "ShellCache",
             across: dict | None = None, limit: float | None = None) -> tuple[list, frozenset]:
    """G1 mode of build_shell: flux-corrected faces on the G0 faces' boundaries (cad.g1), and the
    ids of the seams kept sharp. G1 surfaces (`g1_faces`) and their faces (`g1_shapes`) are taken
    from `cache` where their inputs are unchanged; this build's are put in `keep`. across: the
    boundary edges other surfaces continue, limit: the G1 faces' bound (cad.g1.smooth_faces)."""
    from .g1 import smooth_faces

    smooth, sharp = smooth_faces(g0_infos, network, lookup=lambda key: cache.lookup("g1_faces", key),
                                 keep=keep.g1_faces, across=across, limit=limit)
    infos = []
    for info, g in zip(g0_infos, smooth):
        key = id(g)          # the G1Face is kept in the entry, so its id stays its own
        entry = cache.lookup("g1_shapes", key)
        if entry is None or entry[0] is not g:
            face = make_face(g.surface, f"G1 face for region {info.region_id} (use continuity G0)")
            entry = (g, FaceInfo(info.region_id, g.surface, face, info.sides, info.triangle, info.refilled))
        keep.g1_shapes[key] = entry
        infos.append(entry[1])
    return infos, sharp
