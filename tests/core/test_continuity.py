"""Properties of the G1 core (ProgSurf.core.continuity): Gregory-Coons patch, flux correction,
common normals, twist rule and the sharp-feature rule (issue 9; Egorov, curve mesh surfaces)."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from ProgSurf.core import continuity as g1
from ProgSurf.core.errors import ProgSurfError
from ProgSurf.core.types import Polyline


def surface(s, r):
    """A closed-form smooth surface used as the truth."""
    s, r = np.broadcast_arrays(np.asarray(s, float), np.asarray(r, float))
    return np.stack([100 * s + 5 * r * s, 80 * r + 3 * s * s, 10 * np.sin(2 * s) * np.cos(1.5 * r)], axis=-1)


def dsurf(s, r, h=1e-6):
    ps = (surface(s + h, r) - surface(s - h, r)) / (2 * h)
    pr = (surface(s, r + h) - surface(s, r - h)) / (2 * h)
    return ps, pr


def patch_of(bumps=(np.zeros(3), np.zeros(3), np.zeros(3), np.zeros(3))):
    """Gregory patch of `surface`'s boundaries and fluxes, each flux plus t(1-t)^2 * bump: the
    bumps vanish at the corners but change the twists, so they are incompatible in general."""
    bump = lambda t, b: (np.asarray(t, float) * (1 - np.asarray(t, float)) ** 2)[..., None] * b
    return g1.GregoryCoonsPatch(
        bottom=lambda t: surface(t, 0.0), right=lambda t: surface(1.0, t),
        top=lambda t: surface(t, 1.0), left=lambda t: surface(0.0, t),
        d_bottom=lambda t: dsurf(t, 0.0)[1] + bump(t, bumps[0]),
        d_right=lambda t: dsurf(1.0, t)[0] + bump(t, bumps[1]),
        d_top=lambda t: dsurf(t, 1.0)[1] + bump(t, bumps[2]),
        d_left=lambda t: dsurf(0.0, t)[0] + bump(t, bumps[3]))


def test_hermite_basis_interpolates_values_and_derivatives():
    t = np.array([0.0, 1.0])
    h = g1.hermite_basis(t)
    assert np.allclose(h[0], [1, 0, 0, 0]) and np.allclose(h[1], [0, 0, 0, 1])
    eps = 1e-7
    d0 = (g1.hermite_basis(eps) - g1.hermite_basis(0.0)) / eps
    d1 = (g1.hermite_basis(1.0) - g1.hermite_basis(1.0 - eps)) / eps
    assert np.allclose(d0, [0, 1, 0, 0], atol=1e-5) and np.allclose(d1, [0, 0, 1, 0], atol=1e-5)


@given(st.integers(0, 10_000))
@settings(max_examples=15, deadline=None)
def test_gregory_patch_interpolates_boundaries_and_incompatible_fluxes(seed):
    rng = np.random.default_rng(seed)
    bumps = tuple(rng.normal(scale=20.0, size=3) for _ in range(4))
    p = patch_of(bumps)
    t = np.linspace(0.0, 1.0, 13)
    assert np.allclose(p.evaluate(t, 0.0), surface(t, 0.0), atol=1e-9)
    assert np.allclose(p.evaluate(t, 1.0), surface(t, 1.0), atol=1e-9)
    assert np.allclose(p.evaluate(0.0, t), surface(0.0, t), atol=1e-9)
    assert np.allclose(p.evaluate(1.0, t), surface(1.0, t), atol=1e-9)
    ps, pr = p.derivatives(t, np.zeros_like(t))
    assert np.allclose(pr, p.d_bottom(t), atol=1e-3)
    ps, pr = p.derivatives(np.zeros_like(t), t)
    assert np.allclose(ps, p.d_left(t), atol=1e-3)
    ps, pr = p.derivatives(np.ones_like(t), t)
    assert np.allclose(ps, p.d_right(t), atol=1e-3)


def test_gregory_patch_reproduces_a_bicubic_polynomial_surface():
    rng = np.random.default_rng(3)
    coef = rng.normal(size=(4, 4, 3))
    def f(s, r):
        s, r = np.broadcast_arrays(np.asarray(s, float), np.asarray(r, float))
        return np.einsum("...i,...j,ijk->...k", np.stack([s ** k for k in range(4)], -1),
                         np.stack([r ** k for k in range(4)], -1), coef)

    h = 1e-6
    fs = lambda s, r: (f(np.asarray(s) + h, r) - f(np.asarray(s) - h, r)) / (2 * h)
    fr = lambda s, r: (f(s, np.asarray(r) + h) - f(s, np.asarray(r) - h)) / (2 * h)
    p = g1.GregoryCoonsPatch(lambda t: f(t, 0.0), lambda t: f(1.0, t), lambda t: f(t, 1.0), lambda t: f(0.0, t),
                             lambda t: fr(t, 0.0), lambda t: fs(1.0, t), lambda t: fr(t, 1.0),
                             lambda t: fs(0.0, t))
    g = np.linspace(0.0, 1.0, 9)
    ss, rr = np.meshgrid(g, g, indexing="ij")
    # exact up to the finite-difference twists (compatible here, so the Gregory term is constant)
    assert np.abs(p.evaluate(ss, rr) - f(ss, rr)).max() < 1e-4


@given(st.integers(0, 10_000))
@settings(max_examples=30, deadline=None)
def test_corrected_fluxes_of_both_sides_share_one_tangent_plane(seed):
    rng = np.random.default_rng(seed)
    m = 7
    tangent = rng.normal(size=(m, 3))
    na, nb = rng.normal(size=(m, 3)), rng.normal(size=(m, 3))
    na -= np.sum(na * g1.unit(tangent), -1, keepdims=True) * g1.unit(tangent)
    nb -= np.sum(nb * g1.unit(tangent), -1, keepdims=True) * g1.unit(tangent)
    n = g1.common_normals(na, nb, tangent, np.linspace(0, 1, m))
    assert np.allclose(np.linalg.norm(n, axis=1), 1.0)
    assert np.allclose(np.sum(n * tangent, axis=1), 0.0, atol=1e-9)
    da, db = rng.normal(size=(m, 3)), rng.normal(size=(m, 3))
    fa, fb = da + g1.flux_correction(da, n), db + g1.flux_correction(db, n)
    normal_a, normal_b = np.cross(tangent, fa), np.cross(tangent, fb)
    ok = (np.linalg.norm(normal_a, axis=1) > 1e-6) & (np.linalg.norm(normal_b, axis=1) > 1e-6)
    assert np.all(g1.normal_angle_deg(normal_a[ok], normal_b[ok]) < 1e-5)


def test_common_normal_meets_the_node_normals_at_the_ends():
    m = 11
    t = np.linspace(0, 1, m)
    tangent = np.tile([1.0, 0.0, 0.0], (m, 1))
    na = np.tile(g1.unit([0.0, 0.2, 1.0]), (m, 1))
    nb = np.tile(g1.unit([0.0, -0.2, 1.0]), (m, 1))
    node0, node1 = g1.unit([0.0, 0.5, 1.0]), -g1.unit([0.0, -0.3, 1.0])
    n = g1.common_normals(na, nb, tangent, t, node0, node1)
    assert np.allclose(n[0], node0) and np.allclose(n[-1], -node1)
    mid = np.array([0.0, 0.0, 1.0]) + 0.5 * (node0 - [0, 0, 1]) + 0.5 * (-node1 - [0, 0, 1])
    assert np.allclose(n[m // 2], g1.unit(mid), atol=1e-12)     # the difference ramps linearly


def test_compatible_twist_rule():
    a, b = np.array([1.0, 0, 0]), np.array([0, 3.0, 0])
    assert np.allclose(g1.compatible_twist(a, b, False, False), [0.5, 1.5, 0])
    assert np.allclose(g1.compatible_twist(a, b, True, False), b)
    assert np.allclose(g1.compatible_twist(a, b, False, True), a)
    assert np.allclose(g1.compatible_twist(a, b, True, True), 0)


def test_kink_rule_finds_a_corner_and_ignores_a_smooth_arc():
    phi = np.linspace(0, np.pi / 2, 200)
    arc = Polyline(np.c_[50 * np.cos(phi), 50 * np.sin(phi), 0 * phi], np.linspace(0, 1, 200))
    assert not g1.is_kinked(arc)
    t = np.linspace(0, 1, 101)
    kink = np.where(t[:, None] < 0.5, np.c_[t, 0 * t, 0 * t],
                    np.c_[0.5 + (t - 0.5) * np.cos(1.0), (t - 0.5) * np.sin(1.0), 0 * t]) * 100
    assert g1.is_kinked(Polyline(kink, t))          # turns by 57 degrees at t = 0.5
    assert g1.turning_angles(kink)[50] == pytest.approx(np.degrees(1.0), abs=0.5)
    with pytest.raises(ProgSurfError, match="kink angle"):
        g1.is_kinked(arc, angle_deg=-1.0)


def test_node_normal_spread_measures_disagreeing_corners():
    n, spread = g1.node_normal([np.array([0, 0, 1.0]), np.array([0, 0, -1.0]), None])
    assert np.allclose(np.abs(n), [0, 0, 1]) and spread == pytest.approx(0.0, abs=1e-6)
    _, spread = g1.node_normal([np.array([0, 0, 1.0]), g1.unit([0, np.sin(0.1), np.cos(0.1)])])
    assert spread == pytest.approx(np.degrees(0.1), rel=1e-6)
    assert g1.node_normal([None]) == (None, 0.0)


@pytest.mark.parametrize("width", [1.0, 0.25, 1.0 / 32.0])
def test_band_blend_has_the_hermite_start_and_fades_out_inside_its_band(width):
    h = 1e-7 * width
    assert g1.band_blend(0.0, width) == 0.0
    assert (g1.band_blend(h, width) - g1.band_blend(0.0, width)) / h == pytest.approx(1.0, rel=1e-5)
    beyond = np.linspace(width, 1.0, 50)
    assert np.all(g1.band_blend(beyond, width) == 0.0)
    # value, slope and curvature vanish at the band's edge: the correction fades out without a step
    edge = g1.band_blend(width - np.array([0.0, 1e-3, 2e-3]) * width, width)
    assert abs(edge[1]) <= 1e-8 * width and abs(edge[0] - 2 * edge[1] + edge[2]) <= 1e-8 * width
    t = np.linspace(0.0, width, 10001)
    assert g1.band_blend(t, width).max() == pytest.approx(g1.BAND_PEAK * width, rel=1e-6)
    with pytest.raises(ProgSurfError, match="band width"):
        g1.band_blend(t, 0.0)
