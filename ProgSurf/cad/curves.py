"""Shared edge curves: network polylines -> cubic OCC B-spline curves, fitted once.

Qin & Wright, section 3.3: "the resulting sub-patches become B-spline faces fitted with OCC". Every
edge of the pre-image network (EdgeView) becomes one cubic B-spline on [0, 1] whose parameter is the
polyline's pre-image parameter, so that C(t) ~ polyline(t). A side of a region is a chain of such edges;
:func:`join_side` concatenates them into one B-spline (C0 knots of full multiplicity at the junctions),
reparametrised so the side parameter equals the side polyline's parameter.

This module and its siblings in ProgSurf.cad are the only code converting numpy <-> FreeCAD.Vector.
"""
from __future__ import annotations

from typing import Iterable, Sequence

import numpy as np

from ..core.bspline import span_samples
from ..core.curve_fit import DEGREE, fit_cubic
from ..core.errors import FitError
from ..core.types import FloatArray, Polyline
from ._occ import Part, Vector



def to_vectors(points: FloatArray) -> list:
    """(n, 3) float -> list of FreeCAD.Vector."""
    return [Vector(*p) for p in np.asarray(points, dtype=float).reshape(-1, 3).tolist()]


def to_array(vectors: Iterable) -> FloatArray:
    """FreeCAD.Vector, or (nested) sequences of them -> float array (..., 3)."""
    if hasattr(vectors, "x"):
        return np.array([vectors.x, vectors.y, vectors.z], dtype=float)
    items = list(vectors)
    if items and hasattr(items[0], "x"):     # the common flat case, without recursion
        return np.array([(v.x, v.y, v.z) for v in items], dtype=float).reshape(-1, 3)
    return np.array([to_array(y) for y in items], dtype=float)


def curve_points(curve, t: FloatArray) -> FloatArray:
    """Evaluate a Part curve at parameters t (m,) -> (m, 3)."""
    return np.array([tuple(curve.value(float(x))) for x in np.ravel(t)], dtype=float)


def line_curve(p0: FloatArray, p1: FloatArray):
    """A straight segment p0 -> p1 on [0, 1] as a cubic B-spline (degree 1 elevated to 3)."""
    c = Part.BSplineCurve()
    c.buildFromPolesMultsKnots(to_vectors(np.array([p0, p1])), [2, 2], [0.0, 1.0], False, 1)
    c.increaseDegree(DEGREE)
    return c


def constant_curve(point: FloatArray):
    """A degenerate side (the collapsed top of a 3-sided region): a cubic Bezier with 4 equal poles."""
    c = Part.BSplineCurve()
    c.buildFromPolesMultsKnots(to_vectors(np.repeat(np.reshape(point, (1, 3)), 4, axis=0)),
                               [4, 4], [0.0, 1.0], False, DEGREE)
    return c


def bspline(knots: FloatArray, poles: FloatArray, degree: int = DEGREE):
    """A Part.BSplineCurve from a full clamped knot vector and poles (n, 3)."""
    values, mults = np.unique(np.round(np.asarray(knots, dtype=float), 14), return_counts=True)
    c = Part.BSplineCurve()
    c.buildFromPolesMultsKnots(to_vectors(poles), [int(m) for m in mults], [float(v) for v in values],
                               False, degree)
    return c


def collapsed(points: FloatArray) -> bool:
    """True when the points are one point up to round-off: their spread is within 1e-12 of their
    largest coordinate, whatever the scale (the collapsed top of a 3-sided region; its nodes are
    means of polyline ends, a few ulps off the points, and a few ulps of a 1 m sketch are 1e-11 mm)."""
    pts = np.asarray(points, dtype=float)
    return float(np.ptp(pts, axis=0).max()) <= 1e-12 * float(np.abs(pts).max())


def fit_points(params: FloatArray, points: FloatArray, tol_mm: float, fixed: dict | None = None,
               name: str = "curve", breaks=(), derivs: dict | None = None, seed=(), best_effort: bool = False,
               hug: bool = False):
    """Fit one cubic B-spline C(t), t in [0,1], to points with their own parameters, within tol_mm
    at every point and passing EXACTLY through `fixed` {t: (3,) point} (the network nodes, ends
    included), and with the end derivatives `derivs` if given (core.curve_fit.fit_cubic). Two points
    (or all coincident) give a straight segment, unless end derivatives are asked for.
    Raises FitError when no cubic B-spline within tol_mm is found, unless best_effort (then the
    closest fit the bounded refinement found: fit_cubic). hug: within tol_mm of the chords too
    (fit_cubic)."""
    prm = np.asarray(params, dtype=float)
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    fixed = dict(fixed or {})
    fixed.setdefault(0.0, pts[0])
    fixed.setdefault(1.0, pts[-1])
    if len(pts) < 2:
        raise FitError(f"{name} has {len(pts)} point; a curve needs at least 2")
    ft = np.array(sorted(fixed))
    fp = np.array([fixed[k] for k in ft], dtype=float)
    if collapsed(np.vstack([pts, fp])) or (len(pts) == 2 and len(ft) == 2 and not derivs):
        return line_curve(fp[0], fp[-1])   # a straight edge, or a collapsed one (a triangle's apex side)
    knots, poles = fit_cubic(prm, pts, ft, fp, tol_mm, name=name, breaks=breaks, derivs=derivs, seed=seed,
                             best_effort=best_effort, hug=hug)
    return bspline(knots, poles)


def fit_polyline(polyline: Polyline, tol_mm: float, start: FloatArray | None = None,
                 end: FloatArray | None = None, name: str = "edge", best_effort: bool = False,
                 hug: bool = False):
    """fit_points for one polyline, with optional exact end points."""
    fixed = {}
    if start is not None:
        fixed[0.0] = np.asarray(start, dtype=float)
    if end is not None:
        fixed[1.0] = np.asarray(end, dtype=float)
    return fit_points(polyline.params, polyline.points, tol_mm, fixed, name, best_effort=best_effort, hug=hug)


def unit_segment(curve, a: float, b: float):
    """The piece of `curve` over [a, b], as a new B-spline re-parametrised to [0, 1]."""
    c = curve.copy()
    if a > 0.0 or b < 1.0:
        c.segment(a, b)
    ks, ms = _knots_mults(c)
    k0, k1 = ks[0], ks[-1]
    out = Part.BSplineCurve()
    out.buildFromPolesMultsKnots(c.getPoles(), ms, [(k - k0) / (k1 - k0) for k in ks], False, c.Degree)
    return out


def curve_deviation(curve, polyline: Polyline) -> float:
    """Largest distance |C(t_i) - p_i| at the polyline's vertices (what the fit controls; between
    vertices the smooth curve may differ from the chords by the polyline's own sag)."""
    prm = np.asarray(polyline.params, dtype=float)
    return float(np.linalg.norm(curve_points(curve, prm) - polyline.points, axis=1).max())


def _knots_mults(curve) -> tuple[list, list]:
    return [float(k) for k in curve.getKnots()], [int(m) for m in curve.getMultiplicities()]


def join_side(curves: Sequence, reversed_flags: Sequence[bool], breaks: Sequence[float]):
    """Join the edge curves of one region side into one cubic B-spline on [0, 1].

    curves        : Part.BSplineCurve on [0,1] each (cubic), in traversal order
    reversed_flags: True where the edge runs against the side
    breaks        : (k+1,) side parameters of the junctions, 0 = breaks[0] < ... < breaks[k] = 1;
                    edge i covers [breaks[i], breaks[i+1]] of the side polyline's parameter.
    The junction poles are taken from the first curve; the curves must meet there (shared nodes).
    """
    poles: list = []
    knots: list = []
    mults: list = []
    for i, (curve, rev) in enumerate(zip(curves, reversed_flags)):
        c = curve.copy()
        if c.Degree < DEGREE:
            c.increaseDegree(DEGREE)
        if rev:
            c.reverse()
        ks, ms = _knots_mults(c)
        k0, k1 = ks[0], ks[-1]
        a, b = float(breaks[i]), float(breaks[i + 1])
        mapped = [a + (k - k0) * (b - a) / (k1 - k0) for k in ks]
        p = list(c.getPoles())
        if i == 0:
            poles.extend(p)
            knots.extend(mapped)
            mults.extend(ms)
        else:
            poles.extend(p[1:])
            mults[-1] = DEGREE  # C0 junction: interior knot of multiplicity = degree
            knots.extend(mapped[1:])
            mults.extend(ms[1:])
    knots[0], knots[-1] = 0.0, 1.0
    side = Part.BSplineCurve()
    side.buildFromPolesMultsKnots(poles, mults, knots, False, DEGREE)
    if len(breaks) > 2:
        size = float(np.ptp(to_array(poles), axis=0).max())
        _smooth_junctions(side, [float(b) for b in breaks[1:-1]], JUNCTION_FRACTION * size)
    return side


JUNCTION_FRACTION = 1e-11
"""A junction knot of a joined side is lowered where the curve moves by at most this fraction of
the side's size (1e-9 mm on a 100 mm side): round-off, at any scale."""


JUNCTION_SAMPLES = 16
"""Samples per knot span at which a joined side is compared before and after a junction knot is
lowered (_smooth_junctions)."""


def _smooth_junctions(curve, junctions: Sequence[float], tol: float = 1e-9) -> None:
    """Lower the C0 junction knots of a joined side as far as the geometry allows (to within tol mm):
    pieces of one smoothly fitted curve re-join C2, which BRepCheck/BOP checks require (no C0 faces).

    OCC's removeKnot checks its tolerance at the poles it eliminates, not on the curve: it removed
    the corner knot of two straight strokes meeting square (a plate's corner, 4 poles each), and the
    side cut the corner by 70 mm. Each lowering is therefore checked on the curve itself (every knot
    span sampled, both before and after) and undone where the curve moved by more than tol."""
    for u in junctions:
        for m in range(0, DEGREE):
            ks = [float(k) for k in curve.getKnots()]
            idx = next((i for i, k in enumerate(ks) if abs(k - u) <= 1e-12), None)
            if idx is None:
                break
            before = curve.copy()
            if curve.removeKnot(idx + 1, m, tol):
                # (removing a knot changes the curve DEGREE + 1 spans either side of it at most)
                near = (ks[max(idx - DEGREE - 1, 0)], ks[min(idx + DEGREE + 1, len(ks) - 1)])
                if _moved(before, curve, near) <= tol:
                    break
                _restore(curve, before)


def _moved(before, after, near: tuple[float, float]) -> float:
    """Largest distance (mm) between two B-spline curves at the same parameters in [near[0],
    near[1]], sampled inside every knot span of either there."""
    breaks = np.unique(np.concatenate([np.asarray(c.getKnots(), dtype=float) for c in (before, after)]
                                      + [np.asarray(near, dtype=float)]))
    t = span_samples(breaks[(breaks >= near[0]) & (breaks <= near[1])], JUNCTION_SAMPLES)
    return float(max(before.value(float(x)).distanceToPoint(after.value(float(x))) for x in t))


def _restore(curve, source) -> None:
    """Make `curve` (a Part.BSplineCurve) the same as `source` again, in place."""
    ks, ms = _knots_mults(source)
    curve.buildFromPolesMultsKnots(source.getPoles(), ms, ks, source.isPeriodic(), source.Degree)


def make_compatible(curves: Sequence) -> list:
    """Copies of the curves with one common degree and knot vector (degree elevation, then knot
    insertion up to the largest multiplicity of each knot); geometry unchanged.
    All curves must share the parameter range [0, 1]."""
    out = [c.copy() for c in curves]
    degree = max(c.Degree for c in out)
    for c in out:
        if c.Degree < degree:
            c.increaseDegree(degree)
    have = [dict(zip(*_knots_mults(c))) for c in out]
    merged: dict = {}     # knot -> largest multiplicity in any curve
    for knots in have:
        for k, m in knots.items():
            merged[k] = max(merged.get(k, 0), m)
    values = sorted(merged)
    groups: list = []     # runs of knots within 1e-10 of the run's first
    for k in values:
        if groups and k - groups[-1][0] <= 1e-10:
            groups[-1].append(k)
        else:
            groups.append([k])
    need = [max(merged[k] for k in g) for g in groups]
    for c, knots in zip(out, have):
        todo = []
        for g, m in zip(groups, need):
            if not 0.0 < g[0] < 1.0:
                continue
            got = knots.get(g[0], 0) if len(g) == 1 else max((knots[k] for k in g if k in knots), default=0)
            if m > got:
                todo.append((g[0], m - got))
        if todo:
            c.insertKnots([k for k, _ in todo], [m for _, m in todo], 1e-10, True)
    return out
