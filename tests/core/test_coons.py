"""Properties of the bicubically blended Coons patch (Qin & Wright Eq. 1)."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from ProgSurf.core.coons import coons_patch, f1, f2
from ProgSurf.core.errors import ProgSurfError
from ProgSurf.core.types import Polyline


def wavy_sides(seed: int, n: int = 17):
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.0, n)
    c = rng.normal(size=(4, 3)) * 10 + np.array([[0, 0, 0], [100, 0, 0], [100, 80, 0], [0, 80, 0]])
    bump = lambda: rng.normal(scale=5.0, size=3)[None, :] * np.sin(np.pi * t)[:, None]
    bottom = c[0] + np.outer(t, c[1] - c[0]) + bump()
    right = c[1] + np.outer(t, c[2] - c[1]) + bump()
    top = c[3] + np.outer(t, c[2] - c[3]) + bump()
    left = c[0] + np.outer(t, c[3] - c[0]) + bump()
    return bottom, right, top, left


def test_blending_functions_are_cubic_hermite():
    t = np.linspace(0, 1, 11)
    assert np.allclose(f1(t) + f2(t), 1.0)
    assert f1(0) == 1 and f1(1) == 0 and f2(0) == 0 and f2(1) == 1


@given(st.integers(0, 10_000))
@settings(max_examples=25, deadline=None)
def test_patch_reproduces_its_four_boundary_polylines(seed):
    bottom, right, top, left = wavy_sides(seed)
    p = coons_patch(bottom, right, top, left)
    t = np.linspace(0.0, 1.0, len(bottom))
    assert np.allclose(p.evaluate(t, 0.0), bottom, atol=1e-9)
    assert np.allclose(p.evaluate(t, 1.0), top, atol=1e-9)
    assert np.allclose(p.evaluate(0.0, t), left, atol=1e-9)
    assert np.allclose(p.evaluate(1.0, t), right, atol=1e-9)


def _bilinear(c):
    return lambda u, v: ((1 - u) * (1 - v))[..., None] * c[0] + (u * (1 - v))[..., None] * c[1] \
        + (u * v)[..., None] * c[2] + ((1 - u) * v)[..., None] * c[3]


def _patch_from_edges(bil):
    t = np.linspace(0, 1, 2)
    return coons_patch(bil(t, 0 * t), bil(1 + 0 * t, t), bil(t, 1 + 0 * t), bil(0 * t, t))


def test_untwisted_bilinear_surface_is_reproduced_exactly():
    # Any affine image of the square (zero twist c0 - c1 + c2 - c3) comes back exactly.
    c0, du, dv = np.array([3.0, -2, 7]), np.array([100.0, 5, 10]), np.array([-8.0, 70, -5])
    bil = _bilinear(np.array([c0, c0 + du, c0 + du + dv, c0 + dv]))
    uu, vv = np.meshgrid(np.linspace(0, 1, 13), np.linspace(0, 1, 9))
    assert np.allclose(_patch_from_edges(bil).evaluate(uu, vv), bil(uu, vv), atol=1e-9)


def test_twisted_bilinear_surface_differs_by_the_hermite_twist_term():
    # With cubic blends the boolean sum P = I - (I - P_u)(I - P_v) misses a twisted bilinear
    # surface by exactly -g(u) g(v) (c0 - c1 + c2 - c3), g(t) = f2(t) - t: a closed-form oracle.
    c = np.array([[0, 0, 0], [100, 5, 10], [90, 70, -5], [-5, 80, 20]], dtype=float)
    bil = _bilinear(c)
    uu, vv = np.meshgrid(np.linspace(0, 1, 13), np.linspace(0, 1, 9))
    g = lambda t: f2(t) - t
    expected = bil(uu, vv) - (g(uu) * g(vv))[..., None] * (c[0] - c[1] + c[2] - c[3])
    got = _patch_from_edges(bil).evaluate(uu, vv)
    assert np.allclose(got, expected, atol=1e-9)
    assert np.abs(got - bil(uu, vv)).max() > 0.1     # so the oracle is not vacuous


def test_derivatives_and_normals_match_finite_differences():
    p = coons_patch(*wavy_sides(3, 65))
    u, v, h = np.array([0.31, 0.5, 0.77]), np.array([0.42, 0.13, 0.88]), 1e-5
    pu, pv = p.derivatives(u, v)
    fu = (p.evaluate(u + h, v) - p.evaluate(u - h, v)) / (2 * h)
    fv = (p.evaluate(u, v + h) - p.evaluate(u, v - h)) / (2 * h)
    assert np.allclose(pu, fu, rtol=1e-3, atol=1e-3)
    assert np.allclose(pv, fv, rtol=1e-3, atol=1e-3)
    n = p.normals(u, v)
    assert np.allclose(np.linalg.norm(n, axis=1), 1.0)
    assert np.allclose(np.einsum("ij,ij->i", n, pu), 0.0, atol=1e-9)


def test_three_sided_patch_collapses_the_top_to_a_point():
    bottom, right, _, left = wavy_sides(5)
    apex = right[-1]
    left = left - np.linspace(0, 1, len(left))[:, None] * (left[-1] - apex)
    p = coons_patch(bottom, right, np.repeat(apex[None], 5, axis=0), left)
    assert np.allclose(p.evaluate(np.linspace(0, 1, 9), 1.0), apex)


def test_sides_that_do_not_meet_are_refused_with_a_reason():
    bottom, right, top, left = wavy_sides(1)
    with pytest.raises(ProgSurfError, match="corner"):
        coons_patch(bottom, right, top + 5.0, left)


def test_polyline_sides_use_their_own_parameters():
    pts = np.array([[0, 0, 0], [10, 0, 0], [100, 0, 0.0]])
    side = Polyline(pts, np.array([0.0, 0.5, 1.0]))
    assert np.allclose(side.evaluate(0.25), [5, 0, 0])
    assert np.allclose(side.reversed().evaluate(0.25), [55, 0, 0])
