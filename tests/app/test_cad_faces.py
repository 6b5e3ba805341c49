"""ProgSurf.cad curves/faces: the exact B-spline Coons surface and the constrained edge fit."""
from __future__ import annotations

import numpy as np
import pytest

from ProgSurf.cad import curves, faces
from ProgSurf.core.curve_fit import basis_matrix, chord_sag, fit_cubic
from ProgSurf.core.bspline import SpanBasis, basis_matrices
from ProgSurf.core.coons import coons_patch
from ProgSurf.core.errors import FitError
from ProgSurf.core.types import Polyline

T = np.linspace(0.0, 1.0, 61)


def _poly(f) -> Polyline:
    return Polyline(np.array([f(x) for x in T]), T)


def _as_callable(curve):
    return lambda x: curves.curve_points(curve, np.asarray(x)).reshape(np.shape(x) + (3,))


SIDES = {  # bottom c0->c1, right c1->c2, top c3->c2, left c0->c3 of a saddle-like patch
    "bottom": lambda x: [100 * x, 10 * np.sin(np.pi * x), 0.0],
    "right": lambda x: [100.0, 80 * x, 5 * np.sin(2 * np.pi * x)],
    "top": lambda x: [100 * x, 80.0, 20 * np.sin(np.pi * x)],
    "left": lambda x: [0.0, 80 * x, 0.0],
}


def test_coons_surface_is_the_coons_patch_of_its_sides():
    """The B-spline surface equals Eq. (1) evaluated on the same four B-spline sides (to round-off)."""
    sides = [curves.fit_polyline(_poly(SIDES[k]), 0.002) for k in ("bottom", "right", "top", "left")]
    surface = faces.coons_surface(*sides)
    patch = coons_patch(*[_as_callable(c) for c in sides])
    g = np.linspace(0.0, 1.0, 17)
    got = np.array([[tuple(surface.value(a, b)) for b in g] for a in g])
    assert np.abs(got - patch.grid(g, g)).max() < 1e-9
    assert surface.UDegree == 3 and surface.VDegree == 3


def test_coons_surface_of_two_point_sides_matches_the_core_patch():
    """Straight 2-point sides (degree 1 elevated to 3; GeomFill would refuse < 4 poles) against
    the numpy core's Eq. (1) on the same 2-point polylines (an independent evaluator)."""
    c = np.array([[0, 0, 0], [10, 0, 2], [12, 9, 5], [-1, 8, 1]], dtype=float)
    b, r, t, l = (curves.line_curve(p, q) for p, q in ((c[0], c[1]), (c[1], c[2]), (c[3], c[2]), (c[0], c[3])))
    surface = faces.coons_surface(b, r, t, l)
    patch = coons_patch(c[[0, 1]], c[[1, 2]], c[[3, 2]], c[[0, 3]])
    for s, v in [(0.3, 0.7), (0.5, 0.5), (0.9, 0.1), (0.0, 0.4), (1.0, 1.0)]:
        assert np.allclose(tuple(surface.value(s, v)), patch.evaluate(s, v), atol=1e-12)


def test_degenerate_side_gives_a_valid_face():
    """A 3-sided patch: the top side collapsed to the apex point."""
    apex = np.array([50.0, 80.0, 10.0])
    b = curves.fit_polyline(_poly(SIDES["bottom"]), 0.002)
    r = curves.line_curve([100.0, 0.0, 0.0], apex)
    l = curves.line_curve([0.0, 0.0, 0.0], apex)
    surface = faces.coons_surface(b, r, curves.constant_curve(apex), l)
    assert np.allclose(tuple(surface.value(0.3, 1.0)), apex, atol=1e-12)
    assert surface.toShape().isValid()


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_fit_passes_exactly_through_nodes_and_within_tol_of_the_polyline(seed):
    rng = np.random.default_rng(seed)
    t = np.sort(np.concatenate([[0.0, 1.0], rng.random(80)]))
    pts = np.stack([100 * t, 10 * np.sin(3 * np.pi * t), 3 * np.cos(2 * np.pi * t)], axis=1)
    fixed_t = np.array([0.0, t[20], t[55], 1.0])
    fixed_p = pts[[0, 20, 55, -1]] + 0.001
    knots, poles = fit_cubic(t, pts, fixed_t, fixed_p, tol=0.003)
    assert np.abs(basis_matrix(knots, fixed_t) @ poles - fixed_p).max() < 1e-9
    dense = np.linspace(0, 1, 2001)
    poly = np.stack([np.interp(dense, t, pts[:, k]) for k in range(3)], axis=1)
    # between the vertices too (checked at midpoints and inside spans): within the tolerance plus
    # the chord's own sag, the most a smooth curve through the vertices may differ from the chord
    sag = chord_sag(pts)[np.clip(np.searchsorted(t, dense) - 1, 0, len(t) - 2)]
    assert np.all(np.linalg.norm(basis_matrix(knots, dense) @ poles - poly, axis=1) < 0.0045 + sag)
    assert np.linalg.norm(basis_matrix(knots, t) @ poles - pts, axis=1).max() <= 0.003
    assert np.allclose(basis_matrix(knots, dense).sum(axis=1), 1.0)


def test_fit_that_cannot_reach_the_tolerance_raises_fit_error():
    t = np.array([0.0, 0.5, 0.5 + 1e-12, 1.0])  # a jump: no continuous curve can follow it
    pts = np.array([[0, 0, 0], [1, 0, 0], [1, 5, 0], [2, 5, 0]], dtype=float)
    with pytest.raises(FitError, match="fit-tol"):
        fit_cubic(t, pts, np.array([0.0, 1.0]), pts[[0, -1]], tol=1e-4, max_rounds=8)


def test_a_fit_below_the_points_round_off_stops_at_the_knot_cap_and_gives_its_closest_curve():
    """best_effort: a tolerance no curve can meet (1e-13 of a 100 mm curve: below its round-off)
    returns the fit on the last knots, bounded by MAX_KNOTS_PER_VERTEX, through the end nodes."""
    from ProgSurf.core.curve_fit import MAX_CORNER_KNOTS, MAX_KNOTS_PER_VERTEX

    t = np.linspace(0.0, 1.0, 30)
    pts = np.stack([100 * t, 10 * np.sin(3 * np.pi * t), np.zeros_like(t)], axis=1)
    with pytest.raises(FitError):
        fit_cubic(t, pts, np.array([0.0, 1.0]), pts[[0, -1]], tol=1e-11)
    knots, poles = fit_cubic(t, pts, np.array([0.0, 1.0]), pts[[0, -1]], tol=1e-11, best_effort=True)
    assert len(knots) - 8 <= MAX_KNOTS_PER_VERTEX * len(t) + MAX_CORNER_KNOTS
    ends = basis_matrix(knots, np.array([0.0, 1.0])) @ poles
    assert np.abs(ends - pts[[0, -1]]).max() < 1e-9
    assert np.linalg.norm(basis_matrix(knots, t) @ poles - pts, axis=1).max() < 1e-6 * 100   # 1e-6 of its size


def test_join_side_is_smooth_where_pieces_of_one_curve_meet():
    whole = curves.fit_polyline(_poly(SIDES["bottom"]), 0.002)
    a = curves.unit_segment(whole, 0.0, 0.4)
    b = curves.unit_segment(whole, 0.4, 1.0)
    side = curves.join_side([a, b], [False, False], [0.0, 0.4, 1.0])
    x = np.linspace(0, 1, 50)
    assert np.abs(curves.curve_points(side, x) - curves.curve_points(whole, x)).max() < 1e-9
    assert side.Continuity != "C0"


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_basis_matrix_evaluates_like_occ(seed):
    """core.bspline.basis_matrix (the local Cox-de Boor basis) against OCC's own evaluation of the
    same B-spline, with repeated knots, at the ends and at knots."""
    rng = np.random.default_rng(seed)
    inner = np.sort(rng.random(12))
    inner = np.sort(np.concatenate([inner, inner[[3, 3, 7]]]))     # a C0 and a C1 knot
    knots = np.concatenate([np.zeros(4), inner, np.ones(4)])
    poles = rng.normal(size=(len(knots) - 4, 3))
    occ = curves.bspline(knots, poles)
    t = np.concatenate([[0.0, 1.0], inner, rng.random(50)])
    assert np.abs(basis_matrix(knots, t) @ poles - curves.curve_points(occ, t)).max() <= 1e-12


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_span_basis_and_derivative_basis_agree_with_cox_de_boor(seed):
    """core.bspline.SpanBasis (per-span polynomials, found once per knot vector) gives the same
    basis and derivative basis as the recursion, with repeated knots, at the ends and at knots."""
    rng = np.random.default_rng(seed)
    inner = np.sort(rng.random(15))
    inner = np.sort(np.concatenate([inner, inner[[2, 2, 9]], [0.001, 0.0015]]))
    knots = np.concatenate([np.zeros(4), inner, np.ones(4)])
    t = np.concatenate([[0.0, 1.0], inner, rng.random(80)])
    want, want_low = basis_matrices(knots, t)
    got, got_low = SpanBasis(knots)(t)
    assert np.abs(got - want).max() <= 1e-11 and np.abs(got_low - want_low).max() <= 1e-11
    assert np.abs(want_low - basis_matrix(knots[1:-1], t, 2)).max() <= 1e-14


def test_surface_derivatives_evaluate_like_occ():
    """core.bspline_surface.SurfaceDerivatives of a Part surface (cad.faces.surface_derivatives: all
    points at once, from the derivative poles) against OCC's getDN on a Coons face with C0 junction
    knots, on its sides, corners and inside; normals undefined at the apex of a 3-sided face, as
    unit_normal says."""
    rng = np.random.default_rng(4)
    sides = [curves.fit_points(np.linspace(0, 1, 12), np.column_stack([np.linspace(0, 30, 12), 3 * np.sin(np.linspace(0, 3, 12)) + k, np.full(12, 2.0 * k)]), 0.01) for k in range(2)]
    left = curves.line_curve(np.array(tuple(sides[0].StartPoint)), np.array(tuple(sides[1].StartPoint)))
    right = curves.join_side([curves.line_curve(np.array(tuple(sides[0].EndPoint)), np.array([31.0, 0.5, 1.5])),
                              curves.line_curve(np.array([31.0, 0.5, 1.5]), np.array(tuple(sides[1].EndPoint)))],
                             [False, False], [0.0, 0.4, 1.0])
    for surface in (faces.coons_surface(sides[0], right, sides[1], left),
                    faces.coons_surface(sides[0], right, curves.constant_curve(np.array(tuple(sides[1].StartPoint))), left)):
        d = faces.surface_derivatives(surface)
        s = np.concatenate([[0.0, 1.0, 0.0, 1.0, 0.3], rng.random(60)])
        r = np.concatenate([[0.0, 0.0, 1.0, 1.0, 0.4], rng.random(60)])
        ds, dr = d.derivatives(s, r)
        occ_s = np.array([tuple(surface.getDN(float(a), float(b), 1, 0)) for a, b in zip(s, r)])
        occ_r = np.array([tuple(surface.getDN(float(a), float(b), 0, 1)) for a, b in zip(s, r)])
        assert np.abs(ds - occ_s).max() <= 1e-9 * np.abs(occ_s).max()
        assert np.abs(dr - occ_r).max() <= 1e-9 * np.abs(occ_r).max()
        w = np.linspace(0, 1, 20)
        for ss, rr in ((w, 0 * w), (w, 1 + 0 * w), (w, 0.61 + 0 * w), (0 * w, w), (1 + 0 * w, w), (0.37 + 0 * w, w)):
            q, a, b = d.evaluate(ss, rr)        # an iso-line: the constant parameter's basis once
            oq = np.array([tuple(surface.value(float(x), float(y))) for x, y in zip(ss, rr)])
            oa = np.array([tuple(surface.getDN(float(x), float(y), 1, 0)) for x, y in zip(ss, rr)])
            ob = np.array([tuple(surface.getDN(float(x), float(y), 0, 1)) for x, y in zip(ss, rr)])
            assert np.abs(q - oq).max() <= 1e-9 * np.abs(oq).max()
            assert np.abs(a - oa).max() <= 1e-9 * max(np.abs(oa).max(), 1.0)
            assert np.abs(b - ob).max() <= 1e-9 * max(np.abs(ob).max(), 1.0)
        n, ok = d.normals(s, r)
        for i in range(len(s)):
            if min(np.abs(occ_s[i]).max(), np.abs(occ_r[i]).max()) <= 1e-12 * np.abs(occ_s).max():
                # OCC's derivative along a collapsed side is round-off (2e-15), and unit_normal
                # makes a direction of it; the numpy one is exactly 0 there: no normal
                assert not ok[i]
                continue
            u = faces.unit_normal(surface, float(s[i]), float(r[i]))
            assert (u is None) == (not ok[i])
            if u is not None:
                assert np.abs(u - n[i]).max() <= 1e-9
    assert not ok[2] and not ok[3]      # the collapsed top of the 3-sided face


def test_fit_with_end_derivatives_meets_them_exactly():
    """core.curve_fit.fit_cubic(derivs=): the first and second derivatives asked for at both ends (how a
    refitted part of a network curve joins its kept neighbours C2), within tolerance in between."""
    t = np.linspace(0.0, 1.0, 30)
    pts = np.column_stack([40 * t, 10 * np.sin(3 * t), 5 * t ** 2])
    want = {0.0: (np.array([40.0, 31.0, 1.0]), np.array([0.0, -20.0, 12.0])),
            1.0: (np.array([38.0, -29.0, 11.0]), np.array([5.0, -90.0, 9.0]))}
    knots, poles = fit_cubic(t, pts, np.array([0.0, 1.0]), pts[[0, -1]], 0.01, derivs=want)
    c = curves.bspline(knots, poles)
    for end, (d1, d2) in want.items():
        assert np.allclose(tuple(c.getD1(end)[1]), d1, atol=1e-8)
        assert np.allclose(tuple(c.getD2(end)[2]), d2, atol=1e-7)
    assert np.abs(basis_matrix(knots, t) @ poles - pts).max() <= 0.01


class _OccEvaluated:
    """A face's surface seen only through OCC's value and getDN: cad.analysis.surface_distances
    then projects onto it point by point through OCC, not with its numpy evaluation of plain
    B-splines."""

    def __init__(self, surface):
        self.surface = surface

    def value(self, u, v):
        return self.surface.value(u, v)

    def getDN(self, u, v, nu, nv):  # noqa: N802 (OCC's name)
        return self.surface.getDN(u, v, nu, nv)


def test_distances_by_numpy_projection_equal_occ_evaluation():
    """cad.analysis projects onto ProgSurf's bicubic faces in numpy, all points of a face at once;
    the same clamped Gauss-Newton steps evaluated by OCC give the same distances, on the face and
    off it, and no distance is shorter than OCC's own Extrema finds (distToShape)."""
    from pathlib import Path

    import Part
    from FreeCAD import Vector

    from ProgSurf import cad
    from ProgSurf.cad import analysis
    from ProgSurf.core.pipeline import build_network
    from ProgSurf.io import read_strokes

    r = build_network(read_strokes(Path(__file__).resolve().parents[2] / "examples" / "clean4.xyz"))
    shell = cad.build_shell(r.network, r.tol)
    pts = np.vstack([rec.points for rec in r.records if rec.points is not None])
    pts = np.vstack([pts, pts[::3] + np.random.default_rng(0).normal(scale=2.0, size=pts[::3].shape)])
    bounds = (0.0, 1.0, 0.0, 1.0)
    for f in shell.faces:
        fast = analysis.surface_distances([(f.surface, bounds)], pts)
        slow = analysis.surface_distances([(_OccEvaluated(f.surface), bounds)], pts)
        assert np.abs(fast - slow).max() <= 1e-9
        extrema = np.array([f.face.distToShape(Part.Vertex(Vector(*map(float, p))))[0] for p in pts[::7]])
        assert (fast[::7] >= extrema - 1e-9).all()
    d = analysis.point_distances(shell, pts)
    # the drawn strokes lie within their fairing (0.31 mm on clean4) of the surface; jittered points not
    assert d[:len(pts) - len(pts[::3])].max() <= 0.5 and d.max() > 1.0
