"""The watertight shell: shared B-spline edge curves, one exact Coons B-spline face per region.

Qin & Wright section 3.3: the sub-patches of the pre-image network become B-spline faces fitted with
OCC. build_shell runs the three steps: each network curve is fitted ONCE through its nodes and cut
into its edges (cad.edges); each region side is the join of its edge curves and each face the exact
Coons B-spline surface of its four sides, or in G1 mode its flux-corrected replacement (cad.patch_faces);
the faces are joined into one shell by OCC sewing (cad.sewing), which only merges edges that already
coincide and cuts an edge at a neighbour's vertex; it cannot close a real gap.

Incremental (build_shell(previous=)): after one more stroke, curves whose edges are unchanged are
reused; of a curve the stroke split or pulled, only the changed edges are fitted again, joined C2
to the kept pieces; faces whose sides are unchanged are reused; new faces are sewn with the kept
faces around them and put into the last shell in place of the faces they replace (sew_into), so
the sewing follows the change, not the size of the shell. What is reused travels in the result as
one ShellCache. The result meets the same tolerances as a build from nothing, but is not pole for
pole the same: it depends on the order of the edits.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from types import MappingProxyType
from typing import Mapping

import numpy as np

from ..core.errors import InvalidOptionError
from ..core.network import OUTER_CURVES
from ..core.strokes import sketch_diagonal
from ..core.types import FIT_FRACTION, Tolerances
from .edges import fit_edges
from .patch_faces import REFILL_ROWS, coons_faces, g1_faces
from .sewing import SewnShell, sew, sew_into, sew_tolerance, vertex_keys

CONTINUITIES = ("G0", "G1")
"""G0: the paper's Coons sub-patches as they are; G1: tangent-continuous seams (issue 9, cad.g1)."""


@dataclass
class ShellCache:
    """What one build_shell made that a later build (previous=) may reuse, keyed by the exact content
    or the very objects it was made from. Each field holds this build's entries only (those it
    reused and those it made); the entries of the build before are kept one generation deep in
    `older`. Read through `lookup`, which looks in both generations."""

    curves: dict = field(default_factory=dict)
    """(curve id, edge fit tolerance in mm) -> {edge key: fitted piece, a Part.BSplineCurve on
    [0, 1]} (cad.edges.fit_edges). The edge key is everything the piece depends on (ids, ends,
    digests of its polyline, pre-image ends and node points). Kept: every curve of this build's
    network, reused or fitted."""
    digests: dict = field(default_factory=dict)
    """id(polyline) -> (polyline, its content digest, (edge view, its node points, its edge key) or
    None), so that an unchanged polyline is not hashed again (cad.edges). Kept: the polylines of
    this build's network only."""
    regions: dict = field(default_factory=dict)
    """region id -> (region view, the curve objects on its sides, its FaceInfo, its `faces` key): the
    same region view on the same curve objects gives the same face without cutting its sides.
    Kept: every region of this build's network."""
    faces: dict = field(default_factory=dict)
    """(region id, side pieces, ids of the curve objects they cut, corner digest, triangle, (refill
    rows, loose)) -> the region's G0 FaceInfo (cad.patch_faces.coons_faces; the last entry says how
    a folding face may be refilled). Kept: the faces of this build's regions."""
    g1_faces: dict = field(default_factory=dict)
    """G1 mode: ("g1", what the face reads) -> G1Face, the flux-corrected surface (cad.g1.smooth_faces).
    Kept: the G1 faces of this build; empty in G0 mode."""
    g1_shapes: dict = field(default_factory=dict)
    """G1 mode: id(G1Face) -> (that G1Face, its FaceInfo with the OCC face); the entry keeps the
    G1Face alive, so its id stays its own. Kept: as g1_faces."""
    sewn: dict = field(default_factory=dict)
    """id(face given to the sewing) -> its face in the sewn shell: kept faces are given to the next
    sewing pre-sewn (cad.sewing.sew). Kept: the faces of this build's shell. It is also the
    sewn-face map of `sewn_shell`, held once, here (sewn_shell holds the shell and its vertices)."""
    sewn_shell: SewnShell | None = None
    """The sewn shell of this build and its faces' vertex points, what the next build sews its new
    faces into (cad.sewing.sew_into); None where the sewing did not give one shell of faces that
    could be told apart. Kept: this build's shell only; `older`'s is never read (only the last
    shell is edited)."""
    older: ShellCache | None = None
    """The cache of the build before (its own `older` dropped): an undo, or any edit that returns to
    the strokes of two builds ago, finds its curves and faces there and gets the very same shell
    back, not a refit of it. Kept: one generation (the next build drops this one's `older`)."""

    def lookup(self, kind: str, key):
        """The entry `key` of the field named `kind` (curves, digests, regions, faces, g1_faces,
        g1_shapes, sewn): this generation's, else the older one's; None if neither has it. A curve's
        pieces are those of both generations, the newer winning where both have an edge key."""
        here = getattr(self, kind).get(key)
        if self.older is None:
            return here
        there = getattr(self.older, kind).get(key)
        if isinstance(here, dict) and isinstance(there, dict):
            return {**there, **here}
        return there if here is None else here


@dataclass(frozen=True)
class ShellResult:
    """The CAD result of a patch network.

    shape       : the sewn Part.Shell (or a Compound if OCC could not make one shell; see `valid`)
    faces       : FaceInfo per region, in network.regions() order
    edge_curves : edge_id -> Part.BSplineCurve on [0, 1], fitted once
    timings_s   : {'fit_edges': .., 'faces': .., 'sew': ..} (+ 'g1' in G1 mode)
    continuity  : "G0" (exact Coons faces) or "G1" (cad.g1: flux-corrected faces, same boundaries)
    sharp_edges : ids of interior edges kept sharp in G1 mode (kinked strokes); empty in G0
    g0_faces    : in G1 mode, the G0 FaceInfos the G1 faces were made from (same order); else ()
    g0_folds    : in G1 mode, the folds of those G0 faces (analysis.face_folds, sharp_edges
                  excepted), found once for keep_no_new_fold and app.build; else ()
    tight       : curve id -> factor on its fit tolerance that this build fitted it with (build_shell)
    given       : the curves made elsewhere it was built on (build_shell(given=)): a build again on
                  the very same curve objects reuses its curves and faces (cad.object_shell.loosened)
    cache       : what a later build_shell(..., previous=this) may reuse (ShellCache): fitted
                  curves and faces keyed by the exact content (polylines, nodes, tolerance) they
                  were made from, the sewn shell, and the same of the build before
    reused      : {"curves": (reused, fitted), "faces": (reused, built), "sewn": (faces given
                  pre-sewn, faces), "local_sew": True if sewn into the previous shell locally
                  (sew_into), False if the whole shell was sewn} of this build
    """

    shape: object
    faces: tuple
    edge_curves: dict
    timings_s: dict = field(default_factory=dict)
    continuity: str = "G0"
    sharp_edges: frozenset = frozenset()
    g0_faces: tuple = ()
    cache: ShellCache = field(default_factory=ShellCache, repr=False, compare=False)
    reused: dict = field(default_factory=dict, compare=False)
    g1_reverted: tuple = ()
    g0_folds: tuple = ()
    tight: Mapping = field(default_factory=lambda: MappingProxyType({}))
    given: tuple | None = field(default=None, repr=False, compare=False)


G1_REVERT_ROUNDS = 4
"""keep_no_new_fold: rounds of putting faces back to G0 before every face is."""


def keep_no_new_fold(g0_faces: tuple, g1_faces: list, sharp: frozenset,
                     g0_folds: tuple | None = None) -> tuple[list, tuple]:
    """G1 never makes it worse (issue 16): the faces of every fold (analysis.folds: a seam whose
    faces meet at more than 60 deg, a face that turns over) that the G1 faces have and the G0
    faces do not are put back to their G0 faces, which have the same boundaries, until no new fold
    is left (after G1_REVERT_ROUNDS rounds, every face is). cad.g1 leaves a seam G0 where its
    faces disagree and a face whose own correction turns it over, but two corrections that each
    stay within the bound can still meet at a crease near a corner (sk_octant_8: G1 made seams of
    149-172 deg around a 3-sided face that G0 had smooth). g0_folds: face_folds(g0_faces, sharp),
    when the caller has them. Returns (faces, region ids put back)."""
    from .analysis import face_folds

    def keys(faces) -> set:
        return {(f.kind, f.regions) for f in face_folds(faces, sharp)}

    before = ({(f.kind, f.regions) for f in g0_folds} if g0_folds is not None else keys(g0_faces))
    faces = list(g1_faces)
    back: set = set()
    for _ in range(G1_REVERT_ROUNDS):
        new = keys(faces) - before
        if not new:
            return faces, tuple(sorted(back))
        back |= {r for _, regions in new for r in regions}
        faces = [g0 if g0.region_id in back else g1 for g0, g1 in zip(g0_faces, g1_faces)]
    if keys(faces) - before:
        back |= {f.region_id for f in g0_faces}
        faces = list(g0_faces)
    return faces, tuple(sorted(back))


def network_diagonal(network) -> float:
    """The diagonal (core.strokes.sketch_diagonal) of the network's outer boundary curves."""
    edges = network.edges().values()
    return sketch_diagonal(np.vstack([e.polyline.points for e in edges if e.curve_id in OUTER_CURVES]))


def build_shell(network, tol: Tolerances = Tolerances(), continuity: str = "G0",
                previous: "ShellResult | None" = None, given: tuple | None = None,
                across: dict | None = None, g1_limit_mm: float | None = None,
                tight: dict | None = None, refill_rows: tuple | None = None,
                loose: frozenset = frozenset()) -> ShellResult:
    """Fit the shared edges, build one exact Coons B-spline face per region, sew them into a shell.

    continuity "G1": each face is then replaced by its flux-corrected G1 surface (cad.g1), with the
    same boundary curves, before sewing. Raises InvalidOptionError for another continuity, FitError
    when an edge cannot be fitted within tol.fit_mm or OCC cannot make a face.

    previous : an earlier ShellResult of this network (or of one built from the same strokes):
               curves and faces whose inputs did not change are reused, so that after one more
               stroke only what it touched is fitted and built again, and sewn into its shell.
    given    : curves and node points made elsewhere for some edges (cad.edges.fit_edges(given=)).
    across   : G1 mode: {boundary edge id: cad.object_g1.Across}, where another surface of a whole
               object continues this one (cad.g1.smooth_faces).
    g1_limit_mm : G1 mode: how far a G1 face may lie from its G0 face (default: cad.g1.offset_limit_mm
               of the network; a whole object's surfaces take it of the whole sketch).
    tight    : curve id -> factor on its fit tolerance (cad.edges.fit_edges(tight=)); default: the
               previous build's, so that an edit does not loosen what an earlier build tightened.
    refill_rows : the rows of poles a folding face's plane refill may keep (cad.patch_faces.REFILL_ROWS;
               default that of `continuity`): a G0 build that G1 builds on takes G1's.
    loose    : ids of the regions whose folding face's refill may keep its border alone even where
               its loop was seen from a tilted direction or untangled (cad.patch_faces.refilled_face):
               cad.object_shell checks such a refill against the other surfaces.
    """
    if continuity not in CONTINUITIES:
        raise InvalidOptionError(f"continuity {continuity!r} is not one of {', '.join(CONTINUITIES)}")
    if tol.fit_mm is None:      # not resolved by the pipeline: relative to the network's size
        tol = replace(tol, fit_mm=FIT_FRACTION * network_diagonal(network))
    t0 = time.perf_counter()
    last = previous.cache if previous is not None else ShellCache()
    cache = ShellCache(older=replace(last, older=None) if previous is not None else None)
    stats: dict = {}
    if tight is None:
        tight = dict(previous.tight) if previous is not None else {}
    curves = fit_edges(network, tol, last, stats, keep=cache, given=given, tight=tight)
    t1 = time.perf_counter()
    infos, counts_faces = coons_faces(network, curves, last, cache,
                                      REFILL_ROWS[continuity] if refill_rows is None else refill_rows, loose)
    t2 = time.perf_counter()
    counts = {"curves": stats["curves"], "faces": counts_faces}
    timings = {"fit_edges": t1 - t0, "faces": t2 - t1}
    g0_faces, sharp, reverted, g0_folds = (), frozenset(), (), ()
    if continuity == "G1":
        from .analysis import face_folds

        g0_faces = tuple(infos)
        infos, sharp = g1_faces(network, g0_faces, last, cache, across, g1_limit_mm)
        g0_folds = tuple(face_folds(g0_faces, sharp))
        infos, reverted = keep_no_new_fold(g0_faces, infos, sharp, g0_folds)
        timings["g1"] = time.perf_counter() - t2
    t3 = time.perf_counter()
    faces = [i.face for i in infos]
    presewn = {id(f): s for f in faces if (s := last.lookup("sewn", id(f))) is not None}
    sew_tol = sew_tolerance(tol.fit_mm)
    local = sew_into(faces, last.sewn_shell, last.sewn, sew_tol)
    if local is not None:
        cache.sewn_shell, cache.sewn = local
        shape = cache.sewn_shell.shape
    else:
        shape, cache.sewn = sew(faces, presewn, sew_tol)
        if cache.sewn and shape.ShapeType == "Shell":
            cache.sewn_shell = SewnShell(shape, {k: vertex_keys(f, sew_tol) for k, f in cache.sewn.items()},
                                         sew_tol)
    timings["sew"] = time.perf_counter() - t3
    counts["sewn"] = (sum(1 for f in faces if id(f) in presewn), len(faces))
    counts["local_sew"] = local is not None
    return ShellResult(shape, tuple(infos), curves, timings, continuity, sharp, g0_faces, cache, counts, reverted,
                       g0_folds, MappingProxyType(dict(tight)), given)
