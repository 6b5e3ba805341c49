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
the sewing follows the change, not the size of the shell. The result meets the same tolerances as a build from nothing, but is not pole for
pole the same: it depends on the order of the edits.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

from ..core.errors import InvalidOptionError
from ..core.types import Tolerances
from .edges import fit_edges
from .patch_faces import coons_faces, g1_faces
from .sewing import sew, sew_into, vertex_keys

CONTINUITIES = ("G0", "G1")
"""G0: the paper's Coons sub-patches as they are; G1: tangent-continuous seams (issue 9, cad.g1)."""


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
    cache       : what a later build_shell(..., previous=this) may reuse: fitted curves and G0
                  faces keyed by the exact content (polylines, nodes, tolerance) they were made from
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
    cache: dict = field(default_factory=dict, repr=False, compare=False)
    reused: dict = field(default_factory=dict, compare=False)


HISTORY = ("history",)
"""Cache key of the build before the previous one (its cache, one generation deep): an undo, or
any edit that returns to the strokes of two builds ago, finds its curves and faces there and gets
the very same shell back, not a refit of it."""
SEWN = ("sewn",)
"""Cache key of {id(face given to sew): its face in the sewn shell}."""
SEWN_SHELL = ("sewn shell",)
"""Cache key of the last sewn shell: (shape, {id(face given): its sewn face}, {id(face given):
the rounded points of its sewn face's vertices}), what a local sew (sew_into) edits."""


def _with_history(cache: dict) -> dict:
    """One lookup dict of a cache and its HISTORY generation; where both hold a dict-valued entry
    (curve pieces, sewn faces, digests) the two are merged, the newer winning."""
    older = cache.get(HISTORY)
    if not older:
        return {k: v for k, v in cache.items() if k != HISTORY}
    out = dict(older)
    for k, v in cache.items():
        if k == HISTORY:
            continue
        if isinstance(v, dict) and isinstance(out.get(k), dict):
            out[k] = {**out[k], **v}
        else:
            out[k] = v
    return out


def build_shell(network, tol: Tolerances = Tolerances(), continuity: str = "G0",
                previous: "ShellResult | None" = None) -> ShellResult:
    """Fit the shared edges, build one exact Coons B-spline face per region, sew them into a shell.

    continuity "G1": each face is then replaced by its flux-corrected G1 surface (cad.g1), with the
    same boundary curves, before sewing. Raises InvalidOptionError for another continuity, FitError
    when an edge cannot be fitted within tol.fit_mm or OCC cannot make a face.

    previous : an earlier ShellResult of this network (or of one built from the same strokes):
               curves and G0 faces whose inputs did not change are reused, so that after one
               more stroke only what it touched is fitted and built again (the shell is re-sewn).
    """
    if continuity not in CONTINUITIES:
        raise InvalidOptionError(f"continuity {continuity!r} is not one of {', '.join(CONTINUITIES)}")
    t0 = time.perf_counter()
    last = previous.cache if previous is not None else {}
    old = _with_history(last)
    cache: dict = {HISTORY: {k: v for k, v in last.items() if k != HISTORY}}
    stats: dict = {}
    curves = fit_edges(network, tol, old, stats, keep=cache)
    t1 = time.perf_counter()
    infos, counts_faces = coons_faces(network, curves, old, cache)
    t2 = time.perf_counter()
    counts = {"curves": stats["curves"], "faces": counts_faces}
    timings = {"fit_edges": t1 - t0, "faces": t2 - t1}
    g0_faces, sharp = (), frozenset()
    if continuity == "G1":
        g0_faces = tuple(infos)
        infos, sharp = g1_faces(network, g0_faces, old, cache)
        timings["g1"] = time.perf_counter() - t2
    t3 = time.perf_counter()
    faces = [i.face for i in infos]
    local = sew_into(faces, last.get(SEWN_SHELL))
    if local is not None:
        shape, cache[SEWN_SHELL] = local
        cache[SEWN] = local[1][1]
    else:
        shape, sewn = sew(faces, old.get(SEWN))
        cache[SEWN] = sewn
        if sewn and shape.ShapeType == "Shell":
            cache[SEWN_SHELL] = (shape, sewn, {k: vertex_keys(f) for k, f in sewn.items()})
    timings["sew"] = time.perf_counter() - t3
    counts["sewn"] = (sum(1 for f in faces if id(f) in old.get(SEWN, {})), len(faces))
    counts["local_sew"] = local is not None
    return ShellResult(shape, tuple(infos), curves, timings, continuity, sharp, g0_faces, cache, counts)
