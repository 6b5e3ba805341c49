"""G1 faces: each exact G0 Coons B-spline face plus a Hermite flux correction, exact in B-spline form.

ProgSurf.core.continuity gives the rule (Egorov's flux functions with the normal component removed,
Gregory-like corner twists); this module applies it to the OCC faces of build_shell:

    S1(s,r) = S0(s,r) + g_b(r) db(s) + g_t(r) dt(s) + g_l(s) dl(r) + g_r(s) dr(r)
              - sum over corners g_i(s) g_j(r) tau_ij          (i in {l, r}, j in {b, t})

g_b..g_r are the Hermite blends of the derivative (h1, h2: value 0, slope 1 at their side, value and
slope 0 at the other) narrowed to a band beside their side (core.continuity.band_blend): the widest
band that keeps S1 within OFFSET_FRACTION of the diagonal of S0, so that G1 is never further from any
target than G0 by more than that (issue 16).

S0 is the G0 face (knots refined so that the corrections have room), db..dr are B-spline fits of the
flux corrections -(D . n) n along each side, constrained to vanish at the corners and to have the
corner's twist tau_ij as end derivative; so the correction is zero on the boundary (the boundary poles
are S0's: the shell stays exactly as watertight as G0) and its cross-boundary derivative is exactly
db..dr: the two faces of a seam share the tangent plane of the common normal n(t). Where two seams
meet at a corner their twists are averaged (compatible_twist); within the first knot span of such a
corner the fluxes give way, which is where the remaining G1 defect sits.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..core import continuity as g1
from ..core.bspline import basis_matrix, span_samples
from ..core.bspline_surface import unit_normals
from ..core.network import OUTER_CURVES
from ..core.strokes import sketch_diagonal
from ..core.types import FloatArray
from ._occ import Part
from .curves import to_array
from .faces import full_knots, unit_normal

MIN_SPANS = 16
"""Each direction of a G1 face gets at least this many knot spans (uniform knots are inserted)."""
END_KNOTS = (0.02, 0.98)
"""Extra knots near the corners: the twist compromise stays within the first span."""
ACROSS_END_KNOTS = (0.005, 0.01, 0.04, 0.96, 0.99, 0.995)
"""More knots near the corners of a face with a side along another surface of a whole object
(cad.object_g1): such a seam keeps the mean of the two faces' normals at its ends (neither surface
knows the other's node normals), so the twists its corners need disagree more than inside one
surface, and with END_KNOTS alone the compromise spread over the first 10-20 % of the side (1-3 deg
at 5 % on 16 of the noisy TiGL helicopter's 210 smooth shared sides). Inside one surface they made
the seams worse (sketchgen family 145000 in G1: 34 of 90 sketches' largest seam angle up by more
than 0.5 deg), so they are added to these faces only."""
FLUX_SAMPLES_PER_SPAN = 3
SMOOTHING = 1e-7
H = 1e-4
OFFSET_FRACTION = 0.001
"""G1 never makes a surface worse (issue 16): a G1 face lies within this fraction of the network's
diagonal of its G0 face everywhere, so its distance from any target, the truth included, grows by no
more than that over G0 (triangle inequality). Each seam's correction is confined to a band beside
the seam narrow enough to stay within it (BAND_WIDTHS)."""
BAND_WIDTHS = (1.0, 0.5, 0.25, 0.125, 0.0625, 0.03125)
"""Widths (fraction of the face's parameter range across the side) of the band over which a side's
flux correction fades out: the widest whose correction stays within its share of OFFSET_FRACTION.
A seam whose correction would need a narrower band than the last (a crease that cannot be rounded
within the bound) is left G0."""
SIDE_SHARE = 0.5
"""Share of OFFSET_FRACTION each side's band may use: two bands overlap at a corner."""
DISAGREE_DEG = 90.0
"""Where the two G0 faces of a seam disagree by more than this (a fold), G1 leaves the seam as it
is: aligning the normals by flipping one would turn the fold into a tangent fold."""
PEAK_SAMPLES = 33
"""Points per seam at which the size of its flux correction is measured (_Seams.flux_peaks)."""
SHARP_TAPER = 0.1
"""Part of a seam (edge parameter) next to a sharp node over which the G1 correction fades in."""


@dataclass(frozen=True)
class G1Face:
    """The G1 surface of one region and what was done to it.

    surface   : Part.BSplineSurface, boundary identical to the G0 face's
    free_sides: (4,) True where the side has no seam (outer boundary or degenerate): its flux may change
    offset_mm : largest |S1 - S0| (how far smoothing moved the face): the poles' bound where it is
                within OFFSET_FRACTION, else measured on a grid dense in the bands
    band_widths: (4,) width of the band beside each side over which its correction fades out
    kept_g0   : ids of its seams left G0: creases G1 cannot round within OFFSET_FRACTION
    scaled    : True if even the narrowest bands moved it too far and the correction was scaled
                down to OFFSET_FRACTION (its seams then keep part of their G0 defect)
    turned_over: True if the corrected face turned over (a fold) and the face was left G0
    """

    region_id: int
    surface: object
    free_sides: tuple
    offset_mm: float
    band_widths: tuple = (1.0, 1.0, 1.0, 1.0)
    kept_g0: tuple = ()
    scaled: bool = False
    turned_over: bool = False


def _refine(surface):
    s = surface.copy()
    for direction in ("U", "V"):
        knots = [float(k) for k in getattr(s, f"get{direction}Knots")()]
        cands = list(np.linspace(0.0, 1.0, MIN_SPANS + 1)[1:-1]) + list(END_KNOTS)
        for k in cands:
            gap = min(abs(k - q) for q in knots)
            lim = 0.25 / MIN_SPANS if k not in END_KNOTS else 0.5 * min(k, 1.0 - k)
            if gap > lim:
                getattr(s, f"insert{direction}Knot")(float(k), 1, 1e-12)
                knots.append(float(k))
    return s


@dataclass(frozen=True)
class _Refined:
    """A G0 surface with the knots G1 needs inserted (_refine): its poles, full knot vectors, and
    (u mults, v mults, u knots, v knots) for buildFromPolesMultsKnots."""

    poles: FloatArray
    ku: FloatArray
    kv: FloatArray
    mults_knots: tuple


def refined_surface(surface) -> _Refined:
    """_Refined of a G0 surface. Kept with the G0 face (its SurfaceData.refined, cad.surface_data):
    the G1 faces around a changed one are rebuilt on unchanged G0 faces."""
    r = _refine(surface)
    poles = to_array(r.getPoles())
    poles.setflags(write=False)
    return _Refined(poles, full_knots(r, "U"), full_knots(r, "V"),
                    (r.getUMultiplicities(), r.getVMultiplicities(), r.getUKnots(), r.getVKnots()))


def _inside_spans(knots: FloatArray) -> FloatArray:
    """FLUX_SAMPLES_PER_SPAN parameters evenly inside each nonzero span of a knot vector."""
    return span_samples(np.unique(knots), FLUX_SAMPLES_PER_SPAN)


@lru_cache(maxsize=4096)
def _band_coeffs(knots: tuple, width: float, end: int) -> FloatArray:
    """Coefficients (n,) of core.continuity.band_blend of `width` beside end 0 (or its mirror
    -g(1 - t) beside end 1) in the clamped cubic B-spline basis `knots` (a tuple, read-only result).

    Exact where G1 needs it: value 0 and derivative 1 at its end, value and derivative 0 at the
    other end, coefficients 0 beyond the band (the correction stays inside it); least squares to
    the blend in between."""
    k = np.asarray(knots, dtype=float)
    if end == 1:
        return -_band_coeffs(tuple((1.0 - k[::-1]).tolist()), width, 0)[::-1]
    n = len(k) - 4
    c = np.zeros(n)
    c[1] = (k[4] - k[0]) / 3.0
    free = [i for i in range(2, n - 2) if k[i] < width - 1e-12]
    if free:
        # samples inside every knot span too: a fit's knots can crowd (20 spans of 1e-5 at one
        # parameter), and a basis function that no sample reaches is free to take any value (a
        # coefficient of 1400 made a face of 20 km from a 600 mm dome)
        t = np.unique(np.concatenate([np.linspace(0.0, 1.0, 257), np.linspace(0.0, min(1.0, 1.5 * width), 257),
                                      _inside_spans(k)]))
        a = basis_matrix(k, t)
        rhs = g1.band_blend(t, width) - a[:, 1] * c[1]
        c[free] = np.linalg.lstsq(a[:, free], rhs, rcond=None)[0]
    c.setflags(write=False)
    return c


def _band_knots(width: float, end: int) -> list:
    """Knots a band of `width` beside `end` needs (four spans across it; wider bands have them in
    the MIN_SPANS uniform knots already)."""
    if width * MIN_SPANS >= 4.0:
        return []
    ks = [width * j / 4.0 for j in range(1, 5)]
    return ks if end == 0 else [1.0 - x for x in ks]


def _with_knots(refined: _Refined, extra_u: list, extra_v: list) -> _Refined:
    """`refined` with the knots extra_u, extra_v inserted (exact: the surface is unchanged)."""
    def new(knots, extra):
        return sorted({round(x, 12) for x in extra if min(abs(x - q) for q in knots) > 1e-9})

    extra_u, extra_v = new(refined.mults_knots[2], extra_u), new(refined.mults_knots[3], extra_v)
    if not extra_u and not extra_v:
        return refined
    s = Part.BSplineSurface()
    s.buildFromPolesMultsKnots(np.asarray(refined.poles, dtype=float).tolist(), *refined.mults_knots,
                               False, False, 3, 3)
    for x in extra_u:
        s.insertUKnot(float(x), 1, 1e-12)
    for x in extra_v:
        s.insertVKnot(float(x), 1, 1e-12)
    return _Refined(to_array(s.getPoles()), full_knots(s, "U"), full_knots(s, "V"),
                    (s.getUMultiplicities(), s.getVMultiplicities(), s.getUKnots(), s.getVKnots()))


def _fit_flux(knots: FloatArray, w: FloatArray, target: FloatArray, weight: FloatArray,
              tau0: FloatArray, tau1: FloatArray) -> FloatArray:
    """B-spline coefficients (n, 3) of a flux correction: zero at both ends, end derivatives tau0,
    tau1, least squares to target (m, 3) with weights (m,) elsewhere (+ a little smoothing)."""
    n = len(knots) - 4
    c = np.zeros((n, 3))
    c[1] = tau0 * (knots[4] - knots[0]) / 3.0
    c[n - 2] = -tau1 * (knots[n + 3] - knots[n - 1]) / 3.0
    if n <= 4:
        return c
    a = basis_matrix(knots, w)
    rhs = target - a[:, [1, n - 2]] @ c[[1, n - 2]]
    free = a[:, 2:n - 2] * np.sqrt(weight)[:, None]
    rhs = rhs * np.sqrt(weight)[:, None]
    d = np.diff(np.eye(n), n=2, axis=0)
    lam = SMOOTHING * max(float(np.sum(weight)), 1.0)
    dfree = d[:, 2:n - 2]
    drhs = -d[:, [1, n - 2]] @ c[[1, n - 2]]
    # normal equations (positive definite: the smoothing term alone is, on the free poles)
    lhs = free.T @ free + lam * dfree.T @ dfree
    full = free.T @ rhs + lam * dfree.T @ drhs
    try:
        c[2:n - 2] = np.linalg.solve(lhs, full)
    except np.linalg.LinAlgError:
        c[2:n - 2] = np.linalg.lstsq(np.vstack([free, np.sqrt(lam) * dfree]),
                                     np.vstack([rhs, np.sqrt(lam) * drhs]), rcond=None)[0]
    return c


class _Seams:
    """Which face sides are G1 seams and the common normal along each."""

    def __init__(self, infos, network, sharp: frozenset, limit: float = np.inf, across: dict | None = None):
        self.infos = {f.region_id: f for f in infos}
        self.limit = limit
        self._peaks: dict = {}    # edge id -> {region id: largest flux correction}, see flux_peaks()
        self.edges = network.edges()
        self.uses: dict = {}
        for f in infos:
            for k, pieces in enumerate(f.sides):
                for p in pieces:
                    self.uses.setdefault(p.edge_id, []).append((f, k, p))
        self.sharp = frozenset(e for e in sharp if len(self.uses.get(e, ())) == 2)
        self.seam = {e for e, u in self.uses.items() if len(u) == 2 and e not in sharp}
        # boundary edges that another surface of the object continues smoothly (cad.object_g1):
        # seams whose second face is that surface's
        self.across = {e: a for e, a in (across or {}).items()
                       if len(self.uses.get(e, ())) == 1 and e not in sharp and a.smooth_here}
        self.seam |= set(self.across)
        corner_normals: dict = {}
        for f in infos:
            ids, _ = network.region_corners(f.region_id)
            for nid, (s, r) in zip(ids, ((0, 0), (1, 0), (1, 1), (0, 1))):
                corner_normals.setdefault(nid, []).append(unit_normal(f.surface, float(s), float(r)))
        self.node = {nid: g1.node_normal(ns) for nid, ns in corner_normals.items()}
        self._ends: dict = {}     # edge id -> the seam's (end 0, end 1) face pairs, see normals()

    def _node_target(self, nid: int) -> FloatArray | None:
        """The node normal the seam's normal is pulled to at that end; None at a sharp node (the
        corners disagree there, so the seam keeps the mean of its faces' normals)."""
        normal, spread = self.node.get(nid, (None, 0.0))
        return normal if spread <= g1.SHARP_NODE_DEG else None

    def taper(self, edge_id: int, t: FloatArray) -> FloatArray:
        """(m,) at edge parameters t (m,): 1, going smoothly to 0 within SHARP_TAPER of a sharp
        node: there the faces keep their G0 crease and the correction fades in (a jump would make
        the flux fit ring)."""
        e = self.edges[edge_id]
        t = np.asarray(t, dtype=float)
        out = np.ones(len(t))
        for nid, dist in ((e.node0, t), (e.node1, 1.0 - t)):
            if self.node.get(nid, (None, 0.0))[1] > g1.SHARP_NODE_DEG:
                x = np.clip(dist / SHARP_TAPER, 0.0, 1.0)
                out = out * (x * x * (3.0 - 2.0 * x))
        return out

    def flux_peaks(self, edge_id: int) -> dict:
        """{region id: the largest flux correction |D . n| (mm per unit parameter) either face of
        the seam gets along it}, at PEAK_SAMPLES points, with the taper and the disagreeing parts
        left out as _side_target leaves them. The same for both faces: a seam is left G0 (kept_g0)
        on both or on neither."""
        if edge_id not in self._peaks:
            ts = np.linspace(0.0, 1.0, PEAK_SAMPLES)
            normals, ok = self.normals(edge_id, ts)
            na, nb, _, _ = self._pairs(edge_id, ts)
            agree = np.einsum("ij,ij->i", na, nb) >= np.cos(np.radians(DISAGREE_DEG))
            scale = self.taper(edge_id, ts) * agree * ok
            out = {}
            for f, k, p in self.uses[edge_id]:
                w = p.a + ((1.0 - ts) if p.reversed else ts) * (p.b - p.a)
                ds, dr = f.derived.derivatives.derivatives(*_side_points(k, w))
                cross = dr if k in (0, 2) else ds
                size = np.abs(np.einsum("ij,ij->i", cross, normals)) * scale
                out[f.region_id] = max(out.get(f.region_id, 0.0), float(size.max()))
            self._peaks[edge_id] = out
        return self._peaks[edge_id]

    def kept_g0(self, edge_id: int) -> bool:
        """True where the seam's correction would move a face by more than its share of the bound
        even in the narrowest band (BAND_WIDTHS): a crease G1 cannot round within OFFSET_FRACTION,
        left as G0 makes it."""
        budget = SIDE_SHARE * self.limit / (g1.BAND_PEAK * BAND_WIDTHS[-1])
        return max(self.flux_peaks(edge_id).values(), default=0.0) > budget

    def _pairs(self, edge_id: int, ts: FloatArray, known: tuple | None = None):
        """The two G0 faces' unit normals and the seam tangent at edge parameters ts (m,):
        (na, nb, tangent), each (m, 3), and (m,) True where at least one normal is defined (where
        only one is, it stands for both). known: (FaceInfo, S_s, S_r) of one of the two faces at
        these points, already evaluated by the caller."""
        ts = np.asarray(ts, dtype=float)
        if edge_id in self.across:
            return self._pairs_across(edge_id, ts, known)
        (fa, ka, pa), (fb, kb, pb) = self.uses[edge_id]
        found = []
        for f, k, p in ((fa, ka, pa), (fb, kb, pb)):
            if known is not None and f is known[0]:
                found.append(known[1:])
                continue
            w = p.a + ((1.0 - ts) if p.reversed else ts) * (p.b - p.a)
            found.append(f.derived.derivatives.derivatives(*_side_points(k, w)))
        (ds, dr), (db_s, db_r) = found
        na, oka = unit_normals(ds, dr)
        nb, okb = unit_normals(db_s, db_r)
        na = np.where(oka[:, None], na, nb)
        nb = np.where(okb[:, None], nb, na)
        return na, nb, ds if ka in (0, 2) else dr, oka | okb

    def _pairs_across(self, edge_id: int, ts: FloatArray, known: tuple | None):
        """_pairs of a seam across surfaces: this face's normal, the other surface's at the same
        points (turned to agree with it: the surfaces are oriented each on its own), the tangent."""
        f, k, p = self.uses[edge_id][0]
        w = p.a + ((1.0 - ts) if p.reversed else ts) * (p.b - p.a)
        points, ds, dr = f.derived.derivatives.evaluate(*_side_points(k, w))
        if known is not None and f is known[0]:
            ds, dr = known[1:]
        na, oka = unit_normals(ds, dr)
        nb, okb = self.across[edge_id].normals(points)
        nb = nb * np.where(np.einsum("ij,ij->i", na, nb) < 0.0, -1.0, 1.0)[:, None]
        na = np.where(oka[:, None], na, nb)
        nb = np.where(okb[:, None], nb, na)
        return na, nb, ds if k in (0, 2) else dr, oka | okb

    def normals(self, edge_id: int, ts: FloatArray, known: tuple | None = None) -> tuple[FloatArray, FloatArray]:
        """Common normals of the seam at edge parameters ts (m,): (m, 3), and (m,) True where
        defined. The mean of the faces' normals, plus the differences to the node normals at the
        seam's ends distributed linearly along it (core.continuity.common_normals; the ends are
        evaluated once per seam, and every sample is blended with the same ends)."""
        e = self.edges[edge_id]
        # (a seam across surfaces keeps the mean of its faces' normals at its ends too: the other
        # surface does the same there, and neither knows the other's node normals)
        n0, n1 = ((None, None) if edge_id in self.across
                  else (self._node_target(e.node0), self._node_target(e.node1)))
        ts = np.asarray(ts, dtype=float)
        na, nb, tan, ok = self._pairs(edge_id, ts, known)
        if edge_id in self.across and self.across[edge_id].follow:
            na = nb     # the other surface's faces there stay as they are: their normal is the aim
        out = np.zeros((len(ts), 3))
        if not ok.any():
            return out, ok
        if edge_id not in self._ends:
            ea, eb, et, eok = self._pairs(edge_id, np.array([0.0, 1.0]))
            self._ends[edge_id] = [(ea[i], eb[i], et[i]) if eok[i] and node is not None else None
                                   for i, node in enumerate((n0, n1))]
        e0, e1 = self._ends[edge_id]
        na, nb, tan, t_ok = na[ok], nb[ok], tan[ok], ts[ok]
        if (n0 is not None and e0 is None) or (n1 is not None and e1 is None):
            # an end without normals (a degenerate corner) is blended from each sample's own row
            rows = []
            for i in range(len(t_ok)):
                h = (na[i], nb[i], tan[i])
                r3 = [e0 or h, h, e1 or h]
                a3, b3, c3 = (np.array([r[q] for r in r3]) for q in range(3))
                rows.append(g1.common_normals(a3, b3, c3, np.array([0.0, t_ok[i], 1.0]), n0, n1)[1])
            out[ok] = np.array(rows)
            return out, ok
        first, last = (na[0], nb[0], tan[0]), (na[-1], nb[-1], tan[-1])
        e0, e1 = e0 or first, e1 or last
        t_rows = np.concatenate([[0.0], t_ok, [1.0]])
        stack = [np.vstack([e0[q], (na, nb, tan)[q], e1[q]]) for q in range(3)]
        out[ok] = g1.common_normals(*stack, t_rows, n0, n1)[1:-1]
        return out, ok


def _side_points(k: int, w: FloatArray) -> tuple[FloatArray, FloatArray]:
    """(s, r) arrays of side k (bottom, right, top, left) of the unit square at side parameters w."""
    w = np.asarray(w, dtype=float)
    if k == 0:
        return w, np.zeros_like(w)
    if k == 1:
        return np.ones_like(w), w
    if k == 2:
        return w, np.ones_like(w)
    return np.zeros_like(w), w


def _side_target(info, k: int, w: FloatArray, seams: _Seams) -> tuple[FloatArray, FloatArray]:
    """Flux correction samples (m, 3) along side k of a face at side parameters w, and weights."""
    target = np.zeros((len(w), 3))
    weight = np.zeros(len(w))
    pieces = info.sides[k]
    if not any(p.edge_id in seams.seam for p in pieces):
        return target, weight
    # the first piece whose [a, b] holds each sample (-1: none)
    inside = ((np.array([p.a for p in pieces])[None, :] - 1e-12 <= w[:, None])
              & (w[:, None] <= np.array([p.b for p in pieces])[None, :] + 1e-12))
    owner = np.where(inside.any(axis=1), np.argmax(inside, axis=1), -1)
    # this face's derivatives along the whole side, once: the seam normals and the flux use them
    ds_all, dr_all = info.derived.derivatives.derivatives(*_side_points(k, w))
    for j, piece in enumerate(pieces):
        if piece.edge_id not in seams.seam:
            continue
        idx = np.flatnonzero(owner == j)
        if not len(idx):
            continue
        if seams.kept_g0(piece.edge_id):       # its G0 flux stays
            weight[idx] = 1.0
            continue
        t = (w[idx] - piece.a) / (piece.b - piece.a)
        t = np.clip(1.0 - t if piece.reversed else t, 0.0, 1.0)
        normals, ok = seams.normals(piece.edge_id, t, (info, ds_all[idx], dr_all[idx]))
        if not ok.any():
            continue
        idx, t, normals = idx[ok], t[ok], normals[ok]
        cross = (dr_all if k in (0, 2) else ds_all)[idx]     # the derivative across side k
        taper = seams.taper(piece.edge_id, t)
        na, nb, _, _ = seams._pairs(piece.edge_id, t, (info, ds_all[idx], dr_all[idx]))
        agree = np.einsum("ij,ij->i", na, nb) >= np.cos(np.radians(DISAGREE_DEG))
        target[idx] = g1.flux_correction(cross, normals) * (taper * agree)[:, None]
        weight[idx] = 1.0
    return target, weight


def _band_width(peak: float, limit: float) -> float:
    """The widest of BAND_WIDTHS whose band moves the face by at most SIDE_SHARE * limit for a flux
    correction of size `peak` (the narrowest if none does)."""
    for width in BAND_WIDTHS:
        if peak * g1.BAND_PEAK * width <= SIDE_SHARE * limit:
            return width
    return BAND_WIDTHS[-1]


def _narrower(width: float) -> float:
    i = BAND_WIDTHS.index(width)
    return BAND_WIDTHS[min(i + 1, len(BAND_WIDTHS) - 1)]


def _correction(info, seams: _Seams, widths: tuple, free: tuple, fixed: tuple):
    """(refined surface with the bands' knots, pole offsets delta (nu, nv, 3), each side's largest
    move (4,)) of the G1 correction with bands of `widths` beside sides (bottom, right, top, left)."""
    ends = list(ACROSS_END_KNOTS) if any(p.edge_id in seams.across for side in info.sides for p in side) else []
    refined = _with_knots(info.derived.refined, _band_knots(widths[3], 0) + _band_knots(widths[1], 1) + ends,
                          _band_knots(widths[0], 0) + _band_knots(widths[2], 1) + ends)
    ku, kv = refined.ku, refined.kv
    side_knots = (ku, kv, ku, kv)
    data = []
    for k in range(4):
        kn = side_knots[k]
        n = len(kn) - 4
        # samples inside every knot span too: near a node the side's knots crowd (spans of 0.003),
        # and a span without data let the flux fit ring (6 degrees at 0.5% of a seam)
        w = np.unique(np.concatenate([np.linspace(0, 1, max(FLUX_SAMPLES_PER_SPAN * n, 64)), _inside_spans(kn),
                                      [0.0, H, 1.0 - H, 1.0]]))
        if free[k] or fixed[k]:
            data.append((w, np.zeros((len(w), 3)), np.zeros(len(w)), np.zeros(3), np.zeros(3)))
            continue
        target, weight = _side_target(info, k, w, seams)
        # A corner whose curves are not tangent-plane compatible (a kinked node) keeps its G0 value:
        # the fit is pinned to zero there and gives way within the first knot span only.
        d0 = (target[1] - target[0]) / H
        d1 = (target[-1] - target[-2]) / H
        data.append((w, target, weight, d0, d1))
    # corner twists: (side a, end of a, side b, end of b) per corner (0,0), (1,0), (0,1), (1,1)
    tau = {}
    for key, (ka, ea, kb, eb) in {(1, 1): (0, 3, 3, 3), (2, 1): (0, 4, 1, 3), (1, 2): (3, 4, 2, 3),
                                  (2, 2): (1, 4, 2, 4)}.items():
        if fixed[ka] or fixed[kb]:    # a sharp seam keeps its G0 flux: no twist change at its ends
            tau[key] = np.zeros(3)
        else:
            tau[key] = g1.compatible_twist(data[ka][ea], data[kb][eb], free[ka], free[kb])
    ends = {0: ((1, 1), (2, 1)), 1: ((2, 1), (2, 2)), 2: ((1, 2), (2, 2)), 3: ((1, 1), (1, 2))}
    coeffs = []
    for k in range(4):
        w, target, weight, _, _ = data[k]
        t0, t1 = tau[ends[k][0]], tau[ends[k][1]]
        if free[k]:
            target = g1.h1(w)[:, None] * t0 + g1.h2(w)[:, None] * t1
            weight = np.ones(len(w))
        coeffs.append(_fit_flux(side_knots[k], w, target, np.maximum(weight, 1e-6), t0, t1))
    # the blends across the sides: band_blend of each side's width (h1, h2 of the Hermite form)
    tku, tkv = tuple(ku.tolist()), tuple(kv.tolist())
    bb, bt = _band_coeffs(tkv, widths[0], 0), _band_coeffs(tkv, widths[2], 1)
    bl, br = _band_coeffs(tku, widths[3], 0), _band_coeffs(tku, widths[1], 1)
    cb, cr, ct, cl = coeffs
    delta = (cb[:, None, :] * bb[None, :, None] + ct[:, None, :] * bt[None, :, None]
             + bl[:, None, None] * cl[None, :, :] + br[:, None, None] * cr[None, :, :])
    for (i, j), t in tau.items():
        bu = bl if i == 1 else br
        bv = bb if j == 1 else bt
        delta -= bu[:, None, None] * bv[None, :, None] * t
    sizes = tuple(float(np.linalg.norm(c, axis=-1).max()) * g1.BAND_PEAK * wd for c, wd in zip(coeffs, widths))
    return refined, delta, sizes


def _moved(refined: _Refined, delta: FloatArray, widths: tuple) -> float:
    """Largest |S1 - S0| (mm): the poles' bound, and where that exceeds nothing, exact on a grid
    dense inside every band and with samples inside every knot span (spans of 1e-5 that a uniform
    grid steps over can hold the largest move)."""
    g = [np.linspace(0.0, 1.0, 65)]
    for wd in widths:
        g += [wd * np.linspace(0.0, 1.0, 17), 1.0 - wd * np.linspace(0.0, 1.0, 17)]
    gu, gv = (np.unique(np.concatenate(g + [_inside_spans(k)])) for k in (refined.ku, refined.kv))
    # (one product at a time: einsum of the three at once loops over every index together, 0.1 s a face)
    moved = np.einsum("ujk,vj->uvk", np.tensordot(basis_matrix(refined.ku, gu), delta, axes=(1, 0)),
                      basis_matrix(refined.kv, gv))
    return float(np.linalg.norm(moved, axis=-1).max())


def smooth_face(info, network, seams: _Seams, limit: float = np.inf) -> G1Face:
    """The G1 surface of one G0 FaceInfo (see the module docstring), within `limit` (mm) of it.

    Each side's correction fades out over the widest band (BAND_WIDTHS) that keeps the face within
    the limit; a seam that would need a narrower band is left G0 (_Seams.kept_g0). If the face still
    moves too far in the narrowest bands, its correction is scaled down to the limit (G1 is then not
    reached there: `scaled`); if the corrected face turns over (cad.analysis.face_turn_deg beyond
    FOLD_FACE_DEG, more than the G0 face), the face stays G0 (`turned_over`)."""
    from dataclasses import replace

    from .analysis import FOLD_FACE_DEG, face_turn_deg

    seam_pieces = [[p for p in pieces if p.edge_id in seams.seam] for pieces in info.sides]
    kept = tuple(sorted({p.edge_id for ps in seam_pieces for p in ps if seams.kept_g0(p.edge_id)}))
    free = tuple(not any(p.edge_id in seams.seam for p in pieces) and not any(p.edge_id in seams.sharp
                                                                            for p in pieces)
                 for pieces in info.sides)
    fixed = tuple(any(p.edge_id in seams.sharp for p in pieces) or bool(ps) and all(p.edge_id in kept for p in ps)
                  for pieces, ps in zip(info.sides, seam_pieces))
    widths = tuple(_band_width(max((seams.flux_peaks(p.edge_id).get(info.region_id, 0.0)
                                    for p in ps if p.edge_id not in kept), default=0.0), limit)
                   for ps in seam_pieces)
    scaled = False
    while True:
        refined, delta, sizes = _correction(info, seams, widths, free, fixed)
        size = float(np.linalg.norm(delta, axis=-1).max())
        if size <= limit or (size := _moved(refined, delta, widths)) <= limit:
            break
        over = [sz > SIDE_SHARE * limit for sz in sizes]
        narrower = tuple(_narrower(wd) if (o or not any(over)) else wd for wd, o in zip(widths, over))
        if narrower == widths:    # bounded: G1 may leave a defect here, never a large move
            delta = delta * (limit / size)
            scaled = True
            break
        widths = narrower
    out = Part.BSplineSurface()
    out.buildFromPolesMultsKnots(np.asarray(refined.poles + delta, dtype=float).tolist(), *refined.mults_knots,
                                 False, False, 3, 3)
    turn = face_turn_deg(replace(info, surface=out, face=None))
    turned_over = turn > FOLD_FACE_DEG and turn > face_turn_deg(info)
    if turned_over:        # the G0 face, as it is
        delta = np.zeros_like(delta)
        out = Part.BSplineSurface()
        out.buildFromPolesMultsKnots(np.asarray(refined.poles, dtype=float).tolist(), *refined.mults_knots,
                                     False, False, 3, 3)
    offset = 0.0 if turned_over else min(size, limit)    # |S1 - S0|: the poles' bound, or the grid's
    return G1Face(info.region_id, out, free, offset, widths, kept, scaled, turned_over)


def _face_key(info, network, seams: _Seams) -> tuple:
    """Everything smooth_face(info) reads: the face and, for each of its edges, the face across it
    and whether it is a seam or sharp, as object identities (G0 FaceInfos are reused by build_shell
    only when their content is unchanged); the normals of the nodes on its sides, by value."""
    ids, _ = network.region_corners(info.region_id)
    nodes = set(ids)
    edges = []
    for pieces in info.sides:
        for p in pieces:
            e = seams.edges[p.edge_id]
            nodes.update((e.node0, e.node1))
            other = tuple(sorted(id(f) for f, _, _ in seams.uses.get(p.edge_id, ())))
            if p.edge_id in seams.across:
                other += seams.across[p.edge_id].key
            edges.append((p.edge_id, e.node0, e.node1, other, p.edge_id in seams.seam, p.edge_id in seams.sharp))
    return (id(info), tuple(sorted(edges)), tuple(sorted((n, _node_value(seams, n)) for n in nodes)))


def _node_value(seams: _Seams, nid: int) -> tuple:
    """What a G1 face reads of a node: its normal and the spread of its corner normals, rounded
    to 1e-12 (a face rebuilt at the node with the same corner tangents gives them again up to
    round-off, so the faces around it need not be rebuilt)."""
    normal, spread = seams.node.get(nid, (None, 0.0))
    return (None if normal is None else tuple(round(float(x), 12) for x in normal), round(float(spread), 9))


def smooth_faces(infos, network, angle_deg: float = g1.KINK_ANGLE_DEG,
                 lookup=None, keep: dict | None = None, across: dict | None = None,
                 limit: float | None = None) -> tuple[tuple, frozenset]:
    """G1Face per G0 FaceInfo (same order), and the ids of the seams kept sharp (kinked strokes).

    lookup : key -> the G1Face an earlier call made for that key, or None; a face whose inputs (its
             G0 face and neighbours, the same objects; the normals of its nodes, the same values)
             are unchanged is taken from it.
    keep   : receives this call's {key: G1Face} (reused and new), for the next call.
    across : {boundary edge id: cad.object_g1.Across}: where another surface of a whole object lies
             across a boundary edge; the edges it continues smoothly are seams like the inner ones.
    limit  : how far (mm) a G1 face may lie from its G0 face; default offset_limit_mm(network)."""
    sharp = g1.sharp_edges(network, angle_deg)
    limit = offset_limit_mm(network) if limit is None else limit
    seams = _Seams(infos, network, sharp, limit, across)
    out = []
    for info in infos:
        key = ("g1", _face_key(info, network, seams))
        face = lookup(key) if lookup is not None else None
        if face is None:
            face = smooth_face(info, network, seams, limit)
        if keep is not None:
            keep[key] = face
        out.append(face)
    return tuple(out), sharp


def offset_limit_mm(network) -> float:
    """How far a G1 face may lie from its G0 face: OFFSET_FRACTION of the diagonal of the network's
    outer boundary (inf without one)."""
    outer = [e.polyline.points for e in network.edges().values() if e.curve_id in OUTER_CURVES]
    return OFFSET_FRACTION * sketch_diagonal(np.vstack(outer)) if outer else np.inf


def bound_summary(shell, network) -> dict:
    """What a G1 ShellResult's bound did (for the build report): the bound, the largest move of a
    face from its G0 face, the seams left G0 (creases that no band within the bound rounds), the
    faces left G0 because their correction turned them over, the faces whose correction was
    scaled down to the bound (their seams keep part of the G0 defect), and the faces put back to
    G0 because the G1 faces together folded where G0 did not (shell.keep_no_new_fold)."""
    faces = sorted((g for g, _ in shell.cache.g1_shapes.values()), key=lambda g: g.region_id)
    return {"offset_bound_mm": offset_limit_mm(network),
            "offset_max_mm": max((g.offset_mm for g in faces), default=0.0),
            "seams_left_g0": sorted({e for g in faces for e in g.kept_g0}),
            "faces_left_g0_turned_over": [g.region_id for g in faces if g.turned_over],
            "faces_scaled_to_bound": [g.region_id for g in faces if g.scaled],
            "faces_left_g0_new_fold": list(getattr(shell, "g1_reverted", ()))}
