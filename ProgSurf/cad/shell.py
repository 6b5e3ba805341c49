"""The watertight shell: shared B-spline edge curves, one exact Coons B-spline face per region.

Qin & Wright section 3.3: the sub-patches of the pre-image network become B-spline faces fitted with
OCC. Each network curve is fitted ONCE through its nodes (cad.fit) and cut into its edges; each
region side is the join of its edge curves; each face is the exact Coons B-spline surface of its four
sides (faces.coons_surface). Neighbouring faces therefore have the same boundary geometry (to ~1e-12
mm, round-off of the pole arithmetic). Each face is bounded by its surface's iso-curves, and the faces
are joined into one shell by OCC sewing (at FreeCAD's fixed 1e-6 mm), which only merges edges that
already coincide and cuts an edge at a neighbour's vertex; it cannot close a real gap.

Incremental (build_shell(previous=)): after one more stroke, curves whose edges are unchanged are
reused; of a curve the stroke split or pulled, only the changed edges are fitted again, joined C2
to the kept pieces; faces whose sides are unchanged are reused; new faces are sewn with the kept
faces around them and put into the last shell in place of the faces they replace (sew_into), so
the sewing follows the change, not the size of the shell. The result meets the same tolerances as
a build from nothing, but is not pole for pole the same: it depends on the order of the edits.
"""
from __future__ import annotations

import hashlib
import time
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ..core.errors import FitError, InvalidOptionError
from ..core.types import FloatArray, Tolerances
from ._occ import Part, Vector
from .curves import constant_curve, fit_points, fit_polyline, join_side, unit_segment
from .faces import coons_surface
from .surface_data import SurfaceData

CONTINUITIES = ("G0", "G1")
"""G0: the paper's Coons sub-patches as they are; G1: tangent-continuous seams (issue 9, cad.g1)."""
EDGE_FIT_FRACTION = 0.5
"""Edges are fitted within this fraction of tol.fit_mm (at polyline vertices and chord midpoints): a
Coons face (Eq. 1, corners exact) moves by at most |dC| + |dD| <= twice its largest side deviation."""


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


def side_parameter(side_points: FloatArray, side_params: FloatArray, point: FloatArray) -> float:
    """Parameter of the side polyline vertex nearest to `point` (a junction node)."""
    i = int(np.argmin(np.linalg.norm(side_points - point, axis=1)))
    return float(side_params[i])


def _node_points(edges: dict) -> dict:
    """node id -> one 3D point, the mean of the polyline ends meeting there."""
    if not edges:
        return {}
    ids = np.array([n for e in edges.values() for n in (e.node0, e.node1)])
    pts = np.array([p for e in edges.values() for p in (e.polyline.points[0], e.polyline.points[-1])],
                   dtype=float)
    nodes, where = np.unique(ids, return_inverse=True)
    sums = np.zeros((len(nodes), 3))
    np.add.at(sums, where, pts)
    means = sums / np.bincount(where)[:, None]
    return dict(zip(nodes.tolist(), means))


def _curve_chain(edges: list) -> list | None:
    """Order the edges of one network curve end to end: [(EdgeView, reversed)], or None if they do
    not form one open chain."""
    ends: dict = {}
    for e in edges:
        ends.setdefault(e.node0, []).append(e)
        ends.setdefault(e.node1, []).append(e)
    starts = [n for n, es in ends.items() if len(es) == 1]
    if len(starts) != 2 or any(len(es) > 2 for es in ends.values()):
        return None
    chain, node, used = [], min(starts), set()
    while len(chain) < len(edges):
        e = next((x for x in ends[node] if x.id not in used), None)
        if e is None:
            return None
        used.add(e.id)
        rev = e.node1 == node
        chain.append((e, rev))
        node = e.node0 if rev else e.node1
    return chain


KINK_DEGREES = 3.0
"""A network curve turning by more than this at a node is fitted with a C0 knot there."""


def _chain_points(e, rev: bool) -> FloatArray:
    return (e.polyline.reversed() if rev else e.polyline).points


def _kink(a, ra: bool, b, rb: bool) -> bool:
    """True where the network curve turns by more than KINK_DEGREES from edge a into edge b."""
    pa, pb = _chain_points(a, ra), _chain_points(b, rb)
    din, dout = pa[-1] - pa[-2], pb[1] - pb[0]
    cos = float(din @ dout) / max(float(np.linalg.norm(din) * np.linalg.norm(dout)), 1e-300)
    return cos < np.cos(np.radians(KINK_DEGREES))


def _uv_length(e) -> float:
    return max(float(np.linalg.norm(np.asarray(e.uv1) - np.asarray(e.uv0))), 1e-12)


def _fit_curve(chain: list, nodes: dict, tol_mm: float, curve_id: int, derivs: dict | None = None,
               seed=()) -> dict:
    """Fit one network curve (a chain of edges) once, through all its nodes; cut it into the edges.
    The curve parameter is the cumulative pre-image (uv) length, which is how the network
    parametrises region sides, so the pieces re-join smoothly on a side.
    derivs: end derivatives the fit must have (see cad.fit.fit_cubic), for a part of a curve;
    seed: interior knots (curve parameter) to start the refinement from."""
    lengths = np.array([_uv_length(e) for e, _ in chain])
    cum = np.concatenate([[0.0], np.cumsum(lengths)]) / lengths.sum()
    params, points, fixed = [], [], {}
    for k, (e, rev) in enumerate(chain):
        poly = e.polyline.reversed() if rev else e.polyline
        t = cum[k] + poly.params * (cum[k + 1] - cum[k])
        params.append(t if k == 0 else t[1:])
        points.append(poly.points if k == 0 else poly.points[1:])
        fixed[float(cum[k])] = nodes[e.node1 if rev else e.node0]
        fixed[float(cum[k + 1])] = nodes[e.node0 if rev else e.node1]
    fixed[0.0], fixed[1.0] = fixed.pop(float(cum[0])), fixed.pop(float(cum[-1]))
    breaks = [float(cum[k]) for k in range(1, len(chain)) if _kink(*chain[k - 1], *chain[k])]
    curve = fit_points(np.concatenate(params), np.vstack(points), tol_mm, fixed, name=f"curve {curve_id}",
                       breaks=breaks, derivs=derivs, seed=seed)
    out = {}
    for k, (e, rev) in enumerate(chain):
        piece = unit_segment(curve, float(cum[k]), float(cum[k + 1]))
        if rev:
            piece.reverse()
            piece = unit_segment(piece, piece.FirstParameter, piece.LastParameter)
        out[e.id] = piece
    return out


def _end_derivatives(piece, rev: bool, at_chain_end: bool, scale: float) -> tuple:
    """First and second derivative of a fitted edge piece at one end of its traversal along the
    chain, with respect to a parameter `scale` times faster than the piece's own."""
    u = 0.0 if rev == at_chain_end else 1.0
    d1 = np.array(tuple(piece.getD1(u)[1])) * (-1.0 if rev else 1.0)
    d2 = np.array(tuple(piece.getD2(u)[2]))
    return d1 * scale, d2 * scale ** 2


def _seed_knots(before: dict, start: int, end: int) -> list:
    """Interior knots of the earlier fitted edge that ran from node `start` to node `end` (the
    edge a stroke has split or pulled), in the direction start -> end; [] if there is none."""
    for key, piece in before.items():
        if {key[1], key[2]} == {start, end}:
            knots = [float(k) for k in piece.getKnots()][1:-1]
            return knots if key[1] == start else [1.0 - k for k in knots]
    return []


def _chain_seed(chain: list, before: dict | None) -> list:
    """Seed knots for fitting a chain (a whole curve, or a run of its changed edges): those of the
    earlier edge that ran between the same end nodes (one a stroke has split or pulled); []
    when there is none."""
    if not before:
        return []
    start = chain[0][0].node1 if chain[0][1] else chain[0][0].node0
    end = chain[-1][0].node0 if chain[-1][1] else chain[-1][0].node1
    return _seed_knots(before, start, end)


def _refit_changed(chain: list, nodes: dict, tol_mm: float, curve_id: int, kept: dict,
                   before: dict | None = None) -> dict:
    """A network curve of which only some edges changed (a later stroke split or pulled them):
    keep the fitted pieces of the unchanged edges (`kept`: edge id -> piece) and fit each run of
    changed edges alone, joining its unchanged neighbours C2 (C0 at a kink), so that only the
    faces along the changed edges need to be built again. Within tol_mm like a whole fit, but the
    result depends on the order of the edits, not only on the network. before: the curve's earlier
    {edge key: piece}; the knots of the edge a run replaced seed its fit."""
    out = {e.id: kept[e.id] for e, _ in chain if e.id in kept}
    n, k = len(chain), 0
    while k < n:
        if chain[k][0].id in kept:
            k += 1
            continue
        j = k
        while j + 1 < n and chain[j + 1][0].id not in kept:
            j += 1
        run = chain[k:j + 1]
        run_length = sum(_uv_length(e) for e, _ in run)
        derivs = {}
        if k > 0 and not _kink(*chain[k - 1], *chain[k]):
            e, rev = chain[k - 1]
            derivs[0.0] = _end_derivatives(kept[e.id], rev, True, run_length / _uv_length(e))
        if j < n - 1 and not _kink(*chain[j], *chain[j + 1]):
            e, rev = chain[j + 1]
            derivs[1.0] = _end_derivatives(kept[e.id], rev, False, run_length / _uv_length(e))
        out.update(_fit_curve(run, nodes, tol_mm, curve_id, derivs, _chain_seed(run, before)))
        k = j + 1
    return out


def _digest(*arrays) -> bytes:
    """A content key: the exact bytes of the arrays (float64)."""
    h = hashlib.blake2b(digest_size=16)
    for a in arrays:
        h.update(np.ascontiguousarray(a, dtype=float).tobytes())
        h.update(b"|")
    return h.digest()


def _edge_key(e, nodes: dict, digests: dict | None = None) -> tuple:
    """What the fitted piece of one edge depends on: its id, ends, polyline, pre-image ends and
    the node points it must pass through. digests: {id(polyline): (polyline, digest, last key)}
    kept between builds, so that an unchanged (immutable, shared) polyline is not hashed again,
    nor the key of an unchanged edge view between unchanged node points made again."""
    poly = e.polyline
    entry = digests.get(id(poly)) if digests is not None else None
    ends = (tuple(nodes[e.node0].tolist()), tuple(nodes[e.node1].tolist()))
    if entry is None or entry[0] is not poly:
        entry = (poly, _digest(poly.points, poly.params), None)
    elif entry[2] is not None and entry[2][0] is e and entry[2][1] == ends:
        return entry[2][2]          # the same (immutable) edge view between the same node points
    key = (e.id, e.node0, e.node1, entry[1], _digest(e.uv0, e.uv1, nodes[e.node0], nodes[e.node1]))
    if digests is not None:
        digests[id(poly)] = (poly, entry[1], (e, ends, key))
    return key


DIGESTS = ("digests",)
"""Cache key of {id(polyline): (polyline, content digest, (edge view, its node points, its edge
key) or None)} (see _edge_key)."""


def fit_edges(network, tol: Tolerances, cache: dict | None = None, stats: dict | None = None,
              keep: dict | None = None) -> dict:
    """edge_id -> cubic Part.BSplineCurve on [0,1] (edge param 0 at node0). Each network curve (an
    outer side or an accepted stroke) is fitted once through all its nodes, then cut at them; a curve
    whose edges do not form one chain is fitted edge by edge.

    cache : {("curve", curve id, tolerance): {edge key: piece}} from an earlier build: a curve whose
            edges and nodes are all unchanged is taken from it; of a curve that a later stroke
            split or pulled, only the changed edges are fitted again (_refit_changed).
    stats : receives "curves": (reused, fitted or partly refitted).
    keep  : receives the entries of this build (reused and new), for the next one."""
    edges = network.edges()
    nodes = _node_points(edges)
    by_curve: dict = {}
    for e in edges.values():
        by_curve.setdefault(e.curve_id, []).append(e)
    tol_mm = tol.fit_mm * EDGE_FIT_FRACTION
    cache = {} if cache is None else cache
    keep = {} if keep is None else keep
    curves = {}
    reused = fitted = 0
    digests = dict(cache.get(DIGESTS, {}))
    for cid, group in by_curve.items():
        ckey = ("curve", cid, tol_mm)
        keys = {e.id: _edge_key(e, nodes, digests) for e in group}
        before = cache.get(ckey, {})
        kept = {eid: before[k] for eid, k in keys.items() if k in before}
        if len(kept) == len(group):
            piece = kept
            reused += 1
        else:
            chain = _curve_chain(group)
            if chain is not None and kept:
                piece = _refit_changed(chain, nodes, tol_mm, cid, kept, before)
            elif chain is not None:      # a new curve, or one whose every edge changed
                piece = _fit_curve(chain, nodes, tol_mm, cid, seed=_chain_seed(chain, before))
            else:
                piece = {e.id: kept.get(e.id) or fit_polyline(e.polyline, tol_mm, start=nodes[e.node0],
                                                               end=nodes[e.node1], name=f"edge {e.id} (curve {cid})")
                         for e in group}
            fitted += 1
        keep[ckey] = {keys[eid]: c for eid, c in piece.items()}
        curves.update(piece)
    live = {id(e.polyline) for e in edges.values()}
    keep[DIGESTS] = {k: v for k, v in digests.items() if k in live}
    if stats is not None:
        stats["curves"] = (reused, fitted)
    return curves


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
    (`sew`) cuts that edge at the neighbour's vertex, so the faces still meet vertex to vertex.
    (Faces bounded by pre-split iso-edges came out "self-intersecting" from OCC and needed a
    ShapeFix pass that cost ten times the rest of the face.)"""
    face = surface.toShape()
    if not face.isValid():
        face.fix(1e-9, 1e-9, 1e-7)
        if not face.isValid():
            raise FitError(f"OCC made an invalid {what}; report this sketch")
    return face


HISTORY = ("history",)
"""Cache key of the build before the previous one (its cache, one generation deep): an undo, or
any edit that returns to the strokes of two builds ago, finds its curves and faces there and gets
the very same shell back, not a refit of it."""


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
    infos = []
    reused = built = 0
    for region in network.regions():
        used = tuple(curves[eid] for side in region.sides for eid, _ in side.edges)
        # the same region view (the network keeps it while the region is unchanged) on the same
        # curve objects makes the same face: no need to cut the sides again
        fast = old.get(("region", region.id))
        if (fast is not None and fast[0] is region and len(fast[1]) == len(used)
                and all(a is b for a, b in zip(fast[1], used))):
            info, key = fast[2], fast[3]
            reused += 1
            cache[key] = info
            cache[("region", region.id)] = fast
            infos.append(info)
            continue
        pieces = tuple(_side_pieces(side, curves) for side in region.sides)
        corners = np.asarray(region.corners_xyz, dtype=float)
        # the face depends on its side pieces and on the very curve objects they cut
        key = ("face", region.id, pieces, tuple(id(curves[p.edge_id]) for side in pieces for p in side),
               _digest(corners), bool(region.triangle))
        info = old.get(key)
        if info is None:
            bottom, right, top, left = (_side_curve(pieces[k], curves, corners[c])
                                        for k, c in ((0, 0), (1, 1), (2, 3), (3, 0)))
            surface = coons_surface(bottom, right, top, left)
            face = make_face(surface, f"face for region {region.id}")
            info = FaceInfo(region.id, surface, face, pieces, bool(region.triangle))
            built += 1
        else:
            reused += 1
        cache[key] = info
        cache[("region", region.id)] = (region, used, info, key)
        infos.append(info)
    t2 = time.perf_counter()
    counts = {"curves": stats["curves"], "faces": (reused, built)}
    timings = {"fit_edges": t1 - t0, "faces": t2 - t1}
    g0_faces, sharp = (), frozenset()
    if continuity == "G1":
        g0_faces = tuple(infos)
        infos, sharp = _g1_faces(network, g0_faces, old, cache)
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
            cache[SEWN_SHELL] = (shape, sewn, {k: _vertex_keys(f) for k, f in sewn.items()})
    timings["sew"] = time.perf_counter() - t3
    counts["sewn"] = (sum(1 for f in faces if id(f) in old.get(SEWN, {})), len(faces))
    counts["local_sew"] = local is not None
    return ShellResult(shape, tuple(infos), curves, timings, continuity, sharp, g0_faces, cache, counts)


def _g1_faces(network, g0_infos: tuple, cache: dict, keep: dict) -> tuple[list, frozenset]:
    """G1 mode of build_shell: flux-corrected faces on the G0 faces' boundaries (cad.g1), and the
    ids of the seams kept sharp. G1 faces are taken from `cache` where their inputs are unchanged;
    this build's are put in `keep`."""
    from .g1 import smooth_faces

    smooth, sharp = smooth_faces(g0_infos, network, cache=cache, keep=keep)
    infos = []
    for info, g in zip(g0_infos, smooth):
        key = ("g1face", id(g))          # the G1Face is kept in the entry, so its id stays its own
        entry = cache.get(key)
        if entry is None or entry[0] is not g:
            face = make_face(g.surface, f"G1 face for region {info.region_id} (use continuity G0)")
            entry = (g, FaceInfo(info.region_id, g.surface, face, info.sides, info.triangle))
        keep[key] = entry
        infos.append(entry[1])
    return infos, sharp


SEWN = ("sewn",)
"""Cache key of {id(face given to sew): its face in the sewn shell}."""
SEWN_SHELL = ("sewn shell",)
"""Cache key of the last sewn shell: (shape, {id(face given): its sewn face}, {id(face given):
the rounded points of its sewn face's vertices}), what a local sew (sew_into) edits."""
_PROBE = (0.4142135623730951, 0.7320508075688772)


def probe_point(face) -> tuple:
    """A point of the face's surface at fixed parameters: sewing keeps each face's surface, so it
    tells the sewn faces apart and finds the face each one was sewn from."""
    return tuple(face.valueAt(*_PROBE))


def _probe_key(face) -> tuple:
    return tuple(round(float(x), 7) for x in probe_point(face))


def _vertex_keys(face) -> frozenset:
    return frozenset(tuple(round(float(c), 6) for c in (v.X, v.Y, v.Z)) for v in face.Vertexes)


def _match(given: list, shape) -> dict | None:
    """{id(face given to the sewing): its face in the sewn shape}, or None if they cannot all be
    told apart by a point of their surface."""
    where: dict = {}
    for f in given:
        where.setdefault(_probe_key(f), []).append(id(f))
    out = {}
    for f in shape.Faces:
        ids = where.get(_probe_key(f), [])
        if len(ids) != 1:
            return None
        out[ids[0]] = f
    return out if len(out) == len(given) else None


def sew(faces: list, previous: dict | None = None) -> tuple:
    """Join faces whose edges coincide into one shell (BRepBuilderAPI_Sewing, via Part).

    previous : {id(face): its face in an earlier sewn shell} for faces that were sewn before: the
               sewn face, whose edges are already shared with its old neighbours, is given to the
               sewing instead, so only the edges around new faces are sewn again.
    Returns (the sewn Part.Shell, or a Compound if OCC could not make one shell; {id(face): its
    face in it} for the next call, empty if the faces could not be told apart)."""
    previous = previous or {}
    given = [previous.get(id(f), f) for f in faces]
    sewn = Part.Compound(given)
    sewn.sewShape()
    shells = sewn.Shells
    shape = shells[0] if len(shells) == 1 else sewn
    # the sewing keeps each face's surface: tell the sewn faces apart by a point of their surface
    out = _match(faces, shape)
    return shape, out or {}


def sew_into(faces: list, last: tuple | None) -> tuple | None:
    """Sew new faces into the last sewn shell locally, so that the cost follows the faces a stroke
    changed, not the size of the shell (issue 8).

    last : the SEWN_SHELL entry of the previous build. The faces of the last shell that are gone
    (replaced by new ones) are taken out; the new faces are sewn together with the kept faces that
    touched the gone ones (their neighbours, sharing an edge or a vertex), and those neighbours are
    replaced in the shell by their re-sewn selves. Every other face, and the edges and vertices it
    shares, stays as it was. Returns (shell, SEWN_SHELL entry), or None where only a full sewing
    will do (no last shell, nothing taken out, or the result is not one shell of all the faces)."""
    if not last:
        return None
    shape, sewn_of, verts = last
    ids = {id(f) for f in faces}
    new = [f for f in faces if id(f) not in sewn_of]
    gone = [k for k in sewn_of if k not in ids]
    if not gone:
        return (shape, last) if not new else None
    if shape.ShapeType != "Shell":
        return None
    touched = frozenset().union(*(verts[k] for k in gone))
    near = [f for f in faces if id(f) in sewn_of and not touched.isdisjoint(verts[id(f)])]
    given = [sewn_of[id(f)] for f in near] + new
    local = Part.Compound(given)
    local.sewShape()
    found = _match(given, local)
    if found is None:
        return None
    pairs = [(sewn_of[id(f)], found[id(sewn_of[id(f)])]) for f in near]
    pairs.append((sewn_of[gone[0]], Part.Compound([found[id(f)] for f in new])))
    pairs += [(sewn_of[k], Part.Compound([])) for k in gone[1:]]      # an empty compound removes
    out = shape.replaceShape(pairs)
    if out.ShapeType != "Shell" or len(out.Faces) != len(faces):
        return None
    now = {id(f): sewn_of[id(f)] for f in faces if id(f) in sewn_of}
    now.update({id(f): found[id(sewn_of[id(f)])] for f in near})
    now.update({id(f): found[id(f)] for f in new})
    nverts = {k: verts[k] for k in now if k in verts}
    nverts.update({id(f): _vertex_keys(now[id(f)]) for f in near + new})
    return out, (out, now, nverts)
