"""The shared edge curves of the shell: each network curve fitted once and cut into its edges.

Qin & Wright section 3.3, first half: the boundary curves of the sub-patches become B-spline
curves. Each network curve (an outer side or an accepted stroke) is fitted ONCE through all its
nodes (core.curve_fit, within EDGE_FIT_FRACTION of the fit tolerance) and cut at them into its edges, so
that two faces meeting at an edge bound themselves by the very same curve (cad.patch_faces).

Incremental (fit_edges(cache=)): a curve whose edges and nodes are all unchanged is taken from the
cache; of a curve a later stroke split or pulled, only the runs of changed edges are fitted again,
joined C2 (C0 at a kink) to the kept pieces, their refinement seeded with the knots of the edge
they replace. Each piece is keyed by the exact content it was fitted from (_edge_key).

A curve the bounded knot refinement cannot bring within the tolerance (a tolerance below the
points' round-off, a jump in a polyline) is kept as its closest fit (fit_cubic(best_effort=True)):
the faces on it are then measured further from their Coons sub-patches than allowed, which the
build's quality verdict reports, instead of the whole build failing on valid strokes.
"""
from __future__ import annotations

import hashlib
from typing import TYPE_CHECKING, Mapping

import numpy as np

from ..core.types import FloatArray, Tolerances
from .curves import fit_points, fit_polyline, unit_segment

if TYPE_CHECKING:
    from .shell import ShellCache

EDGE_FIT_FRACTION = 0.5
"""Edges are fitted within this fraction of tol.fit_mm (at polyline vertices and chord midpoints): a
Coons face (Eq. 1, corners exact) moves by at most |dC| + |dD| <= twice its largest side deviation."""
KINK_DEGREES = 3.0
"""A network curve turning by more than this at a node is fitted with a C0 knot there."""


def node_points(edges: dict) -> dict:
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


def curve_chain(edges: list) -> list | None:
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


def _chain_points(e, rev: bool) -> FloatArray:
    return (e.polyline.reversed() if rev else e.polyline).points


def kinked(a, ra: bool, b, rb: bool) -> bool:
    """True where the network curve turns by more than KINK_DEGREES from edge a into edge b (each
    with whether the chain runs along it reversed, as curve_chain gives them)."""
    pa, pb = _chain_points(a, ra), _chain_points(b, rb)
    din, dout = pa[-1] - pa[-2], pb[1] - pb[0]
    cos = float(din @ dout) / max(float(np.linalg.norm(din) * np.linalg.norm(dout)), 1e-300)
    return cos < np.cos(np.radians(KINK_DEGREES))


def uv_length(e) -> float:
    """Length of an edge's pre-image chord in the (u, v) square (at least 1e-12): the weight of the
    edge in its curve's parameter."""
    return max(float(np.linalg.norm(np.asarray(e.uv1) - np.asarray(e.uv0))), 1e-12)


def fit_curve(chain: list, nodes: dict, tol_mm: float, curve_id: int, derivs: dict | None = None,
              seed=(), hug: bool = False) -> dict:
    """Fit one network curve (a chain of edges) once, through all its nodes; cut it into the edges.
    The curve parameter is the cumulative pre-image (uv) length, which is how the network
    parametrises region sides, so the pieces re-join smoothly on a side.
    derivs: end derivatives the fit must have (see core.curve_fit.fit_cubic), for a part of a curve;
    seed: interior knots (curve parameter) to start the refinement from.
    hug: within tol_mm of the polyline's chords too (core.curve_fit.fit_cubic).
    Returns edge id -> Part.BSplineCurve on [0, 1] (edge param 0 at node0)."""
    lengths = np.array([uv_length(e) for e, _ in chain])
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
    breaks = [float(cum[k]) for k in range(1, len(chain)) if kinked(*chain[k - 1], *chain[k])]
    curve = fit_points(np.concatenate(params), np.vstack(points), tol_mm, fixed, name=f"curve {curve_id}",
                       breaks=breaks, derivs=derivs, seed=seed, best_effort=True, hug=hug)
    out = {}
    for k, (e, rev) in enumerate(chain):
        piece = unit_segment(curve, float(cum[k]), float(cum[k + 1]))
        if rev:
            piece.reverse()
            piece = unit_segment(piece, piece.FirstParameter, piece.LastParameter)
        out[e.id] = piece
    return out


def end_derivatives(piece, rev: bool, at_chain_end: bool, scale: float) -> tuple:
    """First and second derivative of a fitted edge piece at one end of its traversal along the
    chain, with respect to a parameter `scale` times faster than the piece's own.
    at_chain_end: the end where the traversal leaves the piece (True) or enters it (False)."""
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
                   before: dict | None = None, hug: bool = False) -> dict:
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
        run_length = sum(uv_length(e) for e, _ in run)
        derivs = {}
        if k > 0 and not kinked(*chain[k - 1], *chain[k]):
            e, rev = chain[k - 1]
            derivs[0.0] = end_derivatives(kept[e.id], rev, True, run_length / uv_length(e))
        if j < n - 1 and not kinked(*chain[j], *chain[j + 1]):
            e, rev = chain[j + 1]
            derivs[1.0] = end_derivatives(kept[e.id], rev, False, run_length / uv_length(e))
        out.update(fit_curve(run, nodes, tol_mm, curve_id, derivs, _chain_seed(run, before), hug))
        k = j + 1
    return out


def content_digest(*arrays) -> bytes:
    """A content key: the exact bytes of the arrays (float64)."""
    h = hashlib.blake2b(digest_size=16)
    for a in arrays:
        h.update(np.ascontiguousarray(a, dtype=float).tobytes())
        h.update(b"|")
    return h.digest()


def _edge_key(e, nodes: dict, digests: dict, lookup) -> tuple:
    """What the fitted piece of one edge depends on: its id, ends, polyline, pre-image ends and
    the node points it must pass through. digests: this build's ShellCache.digests, which receives
    the entry of e's polyline; lookup: ShellCache.lookup of the earlier builds, so that an
    unchanged (immutable, shared) polyline is not hashed again, nor the key of an unchanged edge
    view between unchanged node points made again."""
    poly = e.polyline
    entry = digests.get(id(poly)) or lookup("digests", id(poly))
    ends = (tuple(nodes[e.node0].tolist()), tuple(nodes[e.node1].tolist()))
    if entry is None or entry[0] is not poly:
        entry = (poly, content_digest(poly.points, poly.params), None)
    elif entry[2] is not None and entry[2][0] is e and entry[2][1] == ends:
        digests[id(poly)] = entry
        return entry[2][2]          # the same (immutable) edge view between the same node points
    key = (e.id, e.node0, e.node1, entry[1], content_digest(e.uv0, e.uv1, nodes[e.node0], nodes[e.node1]))
    digests[id(poly)] = (poly, entry[1], (e, ends, key))
    return key


def _nothing(kind: str, key) -> None:
    """The lookup of an empty cache."""
    return None


def fit_edges(network, tol: Tolerances, cache: "ShellCache | None" = None, stats: dict | None = None,
              keep: "ShellCache | None" = None, given: tuple | None = None,
              tight: Mapping | None = None) -> dict:
    """edge_id -> cubic Part.BSplineCurve on [0,1] (edge param 0 at node0). Each network curve (an
    outer side or an accepted stroke) is fitted once through all its nodes, then cut at them; a curve
    whose edges do not form one chain is fitted edge by edge.

    cache : the ShellCache of an earlier build (its `curves` and `digests`): a curve whose edges and
            nodes are all unchanged is taken from it; of a curve that a later stroke split or
            pulled, only the changed edges are fitted again (_refit_changed).
    stats : receives "curves": (reused, fitted or partly refitted).
    keep  : a ShellCache whose `curves` and `digests` receive this build's entries (reused and
            new), for the next one.
    given : (edge id -> curve, node id -> (3,) point): curves made elsewhere (cad.shared_edges: a
            whole object's boundary edges, pieces of the curves two surfaces share) and the points of
            their nodes; a network curve whose every edge is given takes them, the other curves are
            fitted through those node points.
    tight : curve id -> factor on its fit tolerance, for curves of a face that came out further
            from its sub-patch than the fit tolerance (app.build.tighten_fit): such a curve is also
            fitted within that tolerance of its polyline's chords (fit_curve(hug=True))."""
    edges = network.edges()
    nodes = node_points(edges)
    given_curves, given_nodes = given if given is not None else ({}, {})
    nodes.update(given_nodes)
    by_curve: dict = {}
    for e in edges.values():
        by_curve.setdefault(e.curve_id, []).append(e)
    base_mm = tol.fit_mm * EDGE_FIT_FRACTION
    tight = tight or {}
    lookup = _nothing if cache is None else cache.lookup
    curves, fitted_curves = {}, {}
    reused = fitted = 0
    digests: dict = {}          # every live polyline's entry (each edge's is made or renewed below)
    for cid, group in by_curve.items():
        tol_mm = base_mm * tight.get(cid, 1.0)
        hug = cid in tight
        ckey = (cid, tol_mm, hug)
        keys = {e.id: _edge_key(e, nodes, digests, lookup) for e in group}
        before = lookup("curves", ckey) or {}
        kept = {eid: before[k] for eid, k in keys.items() if k in before}
        if given_curves and all(e.id in given_curves for e in group):
            piece = {e.id: given_curves[e.id] for e in group}
            fitted += 1
        elif len(kept) == len(group):
            piece = kept
            reused += 1
        else:
            chain = curve_chain(group)
            if chain is not None and kept:
                piece = _refit_changed(chain, nodes, tol_mm, cid, kept, before, hug)
            elif chain is not None:      # a new curve, or one whose every edge changed
                piece = fit_curve(chain, nodes, tol_mm, cid, seed=_chain_seed(chain, before), hug=hug)
            else:
                piece = {e.id: kept.get(e.id) or fit_polyline(e.polyline, tol_mm, start=nodes[e.node0],
                                                               end=nodes[e.node1], name=f"edge {e.id} (curve {cid})",
                                                               best_effort=True, hug=hug)
                         for e in group}
            fitted += 1
        fitted_curves[ckey] = {keys[eid]: c for eid, c in piece.items()}
        curves.update(piece)
    if keep is not None:
        keep.curves.update(fitted_curves)
        keep.digests = digests
    if stats is not None:
        stats["curves"] = (reused, fitted)
    return curves
