"""Issue 16 on 3-sided patches: strokes drawn to the apex, where the patch collapses (Fig. 4).

An octant of a sphere is the 3-sided surface a designer draws most: three quarter circles, and
meridians from the pole. Every meridian runs into the pole, so the pole is where the patch
collapses, and each meridian meets the collapsed side where its own direction takes it. A
meridian used to snap to whichever boundary side passed nearest the pole, run diagonally across
the pre-image to a corner of it, and fold the surface (sketchgen octants: most meridians were
rejected as folds)."""
from __future__ import annotations

import numpy as np

from ProgSurf.core.boundary import triangle_apex
from ProgSurf.core.folds import find_folds
from ProgSurf.core.pipeline import build_network

R = 300.0


def _sphere(theta, phi):
    """Points of the sphere of radius R at polar angles theta and azimuths phi (arrays)."""
    return R * np.column_stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)])


def _octant(azimuths, overshoot_deg=2.0, drift=4.0, wobble=0.0, seed=0):
    """The octant's three sides and one meridian per azimuth (deg), each drawn from the equator to
    the pole and a little past it, drifting sideways, with an optional hand wobble (mm)."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.0, 60)
    q = np.pi / 2
    sides = [_sphere(np.full_like(t, q), q * t),                  # equator, x to y
             _sphere(q * (1 - t), np.full_like(t, q)),            # y meridian, up to the pole
             _sphere(q * t, np.zeros_like(t))]                    # x meridian, pole down to x
    strokes = []
    for az in azimuths:
        a = np.radians(az)
        th = np.linspace(q, 0.0, 50)
        p = _sphere(th, np.full_like(th, a))
        # on past the pole along its tangent, and drifting sideways by up to `drift` mm towards
        # the nearer meridian side, as a hand does (it passes the pole a few mm off)
        past = R * np.radians(overshoot_deg) * np.linspace(0.0, 1.0, 6)[1:, None] * -np.array([np.cos(a), np.sin(a), 0.0])
        p = np.vstack([p, p[-1] + past])
        side = np.array([np.sin(a), -np.cos(a), 0.0]) * (1.0 if az < 45.0 else -1.0)
        p = p + drift * np.linspace(0.0, 1.0, len(p))[:, None] ** 2 * side
        strokes.append(p + wobble * rng.normal(size=p.shape))
    return sides + strokes


def test_meridians_drawn_to_the_pole_meet_the_collapsed_side_and_do_not_fold():
    res = build_network(_octant([25.0, 50.0, 70.0], wobble=0.3), boundary=3)
    interior = res.records[3:]
    assert [r.status for r in interior] == ["accepted"] * 3, [r.reason for r in interior]
    net = res.network
    assert find_folds(net) == []
    # each meridian's pre-image ends on the collapsed side (the pole), away from its corners
    pole = np.array([0.0, 0.0, R])
    for rec in interior:
        ends = rec.pre_image[[0, -1]]
        at_pole = np.linalg.norm(net.evaluate_uv(ends) - pole, axis=1)
        k = int(np.argmin(at_pole))
        assert at_pole[k] < 1e-6 * R
        on_side = np.isclose(ends[k], 0.0, atol=1e-9) | np.isclose(ends[k], 1.0, atol=1e-9)
        assert on_side.sum() == 1, f"stroke {rec.index} runs to a corner of the pre-image, {ends[k]}"
        assert 0.05 < ends[k][~on_side][0] < 0.95
    # the surface is the sphere, within 1 % of its radius
    g = np.linspace(0.0, 1.0, 15)
    u, v = np.meshgrid(g, g)
    pts = net.evaluate_uv(np.column_stack([u.ravel(), v.ravel()]))
    assert np.abs(np.linalg.norm(pts, axis=1) - R).max() < 0.01 * R


def test_a_corner_that_strokes_run_into_is_the_apex():
    """All three corners of an octant are right angles: the corner the meridians run into is
    where it collapses, whatever order its sides were drawn in."""
    strokes = _octant([30.0, 60.0])
    pole = np.array([0.0, 0.0, R])
    for turn in range(3):
        sides = [strokes[(turn + k) % 3] for k in range(3)]
        ends = np.array([[s[-1], s[-3]] for s in strokes[3:]] + [[s[0], s[2]] for s in strokes[3:]])
        apex = triangle_apex(sides, ends)
        assert np.linalg.norm(sides[apex][-1] - pole) < 1e-9 * R
