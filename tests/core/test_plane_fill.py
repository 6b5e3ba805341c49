"""The plane refill of a folding face (core.plane_fill): on a U-shaped loop, whose Coons patch
turns over at the two inner corners of the notch, the refilled face keeps its border poles and
turns nowhere over; a flat loop in any plane stays flat; a loop that crosses itself seen from its
plane is left alone."""
from __future__ import annotations

import numpy as np
import pytest

from ProgSurf.core.bspline import basis_matrix
from ProgSurf.core.bspline_surface import SurfaceDerivatives, unit_normals
from ProgSurf.core.coons import coons_patch
from ProgSurf.core.folds import FACE_INSET
from ProgSurf.core.plane_fill import (MAX_TILT_DEG, greville, is_simple, loop_plane, plane_map, plane_refill,
                                      refill_poles, simple_frame, untangled)

POLES = 24


def chain(*corners, n=40):
    pts = [np.linspace(a, b, n, endpoint=False) for a, b in zip(corners[:-1], corners[1:])]
    return np.vstack(pts + [np.asarray(corners[-1], float)[None]])


def u_loop(size=100.0):
    """A U of 3 x 2 units with a 1 x 1 notch, as four sides (bottom, right, top, left) whose top
    runs into the notch and out: the Coons patch of the plane turns over at the notch."""
    s = lambda *c: size * chain(*[np.asarray(p, float) for p in c])
    return (s((0, 0), (3, 0)), s((3, 0), (3, 2)), s((0, 2), (1, 2), (1, 1), (2, 1), (2, 2), (3, 2)),
            s((0, 0), (0, 2)))


def bspline_face(sides, lift=lambda p: np.zeros(len(p))):
    """A cubic B-spline face (poles (POLES, POLES, 3), full knots) through the Coons patch of the
    plane sides at its Greville points, lifted by z = lift(x, y) (sides in space: as they are)."""
    b, r, t, l = (s if s.shape[1] == 3 else np.column_stack([s, lift(s)]) for s in sides)
    patch = coons_patch(b, r, t, l)
    knots = np.concatenate([[0.0] * 3, np.linspace(0.0, 1.0, POLES - 2), [1.0] * 3])
    g = greville(knots, 3, POLES)
    at = patch.grid(g, g)
    basis = basis_matrix(knots, g, 3)
    poles = np.linalg.solve(basis, np.linalg.solve(basis, at.transpose(1, 0, 2).reshape(POLES, -1))
                            .reshape(POLES, POLES, 3).transpose(1, 0, 2).reshape(POLES, -1)).reshape(POLES, POLES, 3)
    return poles, knots


def border_of(poles, knots, m=120):
    t = np.linspace(0.0, 1.0, m, endpoint=False)
    one, nil = np.ones_like(t), np.zeros_like(t)
    uv = np.vstack([np.column_stack([t, nil]), np.column_stack([one, t]), np.column_stack([1 - t, one]),
                    np.column_stack([nil, 1 - t])])
    return SurfaceDerivatives(poles, knots, knots, 3, 3).evaluate(uv[:, 0], uv[:, 1])[0], uv


def normals(poles, knots, n=33):
    g = np.linspace(FACE_INSET, 1.0 - FACE_INSET, n)
    s, r = (a.ravel() for a in np.meshgrid(g, g, indexing="ij"))
    _, ds, dr = SurfaceDerivatives(poles, knots, knots, 3, 3).evaluate(s, r)
    return unit_normals(ds, dr)[0]


def refill(poles, knots, held=1):
    border, uv = border_of(poles, knots)
    found = plane_refill(poles, (knots, knots), (3, 3), border, uv, held=(held,))
    return found[0] if found else None


def test_a_u_shaped_loop_turns_over_as_a_coons_patch_and_not_refilled():
    poles, knots = bspline_face(u_loop())
    before = normals(poles, knots)
    assert (before[:, 2] < -0.5).any() and (before[:, 2] > 0.5).any()      # turned over somewhere
    new = refill(poles, knots)
    assert new is not None
    after = normals(new, knots)
    assert (after[:, 2] > 0.99).all()                   # a flat U, facing one way everywhere
    np.testing.assert_array_equal(new[[0, -1]], poles[[0, -1]])      # the border poles: the sides
    np.testing.assert_array_equal(new[:, [0, -1]], poles[:, [0, -1]])
    assert np.abs(new[..., 2]).max() < 1e-9             # the plane's face stays in it
    # with two rows held, the face's tangent plane along its sides is the Coons patch's too
    two = refill(poles, knots, held=2)
    np.testing.assert_array_equal(two[[0, 1, -2, -1]], poles[[0, 1, -2, -1]])
    np.testing.assert_array_equal(two[:, [0, 1, -2, -1]], poles[:, [0, 1, -2, -1]])
    assert np.abs(two[2:-2, 2:-2] - poles[2:-2, 2:-2]).max() > 1.0       # and the rest moved


@pytest.mark.parametrize("seed", range(3))
def test_a_tilted_plane_loop_gives_a_face_in_that_plane(seed):
    """A rigid motion of the U lifted onto the plane z = 0.2 x - 0.1 y: the refilled face lies in
    that plane (mean value weights reproduce linear heights) and faces one way."""
    rng = np.random.default_rng(seed)
    poles, knots = bspline_face(u_loop(), lift=lambda p: 0.2 * p[:, 0] - 0.1 * p[:, 1])
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    rot = q * np.sign(np.linalg.det(q))
    shift = rng.normal(size=3) * 500.0
    moved = poles @ rot.T + shift
    new = refill(moved, knots)
    assert new is not None
    plane_n = rot @ (np.array([-0.2, 0.1, 1.0]) / np.linalg.norm([-0.2, 0.1, 1.0]))
    assert np.abs((new - shift) @ plane_n).max() < 1e-6 * 300.0
    after = normals(new, knots)
    assert (np.abs(after @ plane_n) > 0.99).all() and len(set(np.sign(after @ plane_n))) == 1


def test_a_loop_crossing_itself_in_its_plane_is_left_alone():
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    bow_tie = np.array([[0, 0], [1, 1], [1, 0], [0, 1]], float)
    assert is_simple(square) and not is_simple(bow_tie)
    # a figure of eight: its top side swings across its bottom side, in the plane
    sides = [100.0 * chain((0, 0), (3, 0)), 100.0 * chain((3, 0), (3, 1)),
             100.0 * chain((0, 1), (1, 1), (2, -1), (3, 1)), 100.0 * chain((0, 0), (0, 1))]
    poles, knots = bspline_face(sides)
    assert refill(poles, knots) is None


def folded_u(angle):
    """The U's sides with the outer half of its right arm (x > 250) folded up about the line
    x = 250 by `angle` degrees, over the rest of the U."""
    t = np.radians(angle)

    def fold(p):
        r = np.clip(p[:, 0] - 250.0, 0.0, None)
        return np.column_stack([np.minimum(p[:, 0], 250.0) + r * np.cos(t), p[:, 1], r * np.sin(t)])
    return [fold(s) for s in u_loop()]


@pytest.mark.parametrize("angle", [110.0, 135.0])
def test_a_loop_crossing_itself_along_its_normal_is_refilled_seen_from_the_side(angle):
    """Folded over, the U's loop crosses itself seen along its vector area's normal n; seen along a
    direction d tilted from n it does not: the refilled face faces d everywhere (its Coons patch
    turned over), and keeps its tangent plane along its sides (2 rows held; not with 1)."""
    poles, knots = bspline_face(folded_u(angle))
    border, _ = border_of(poles, knots)
    c, e1, e2, n = loop_plane(border)
    assert not is_simple(np.column_stack([(border - c) @ e1, (border - c) @ e2]))
    d = simple_frame(border, c, n)[2]
    assert 0.0 < np.degrees(np.arccos(d @ n)) <= MAX_TILT_DEG
    assert (normals(poles, knots) @ d).min() < -0.5                    # the Coons patch turns over
    new = refill(poles, knots, held=2)
    assert new is not None
    assert (normals(new, knots) @ d).min() > 0.0                       # the refill does not
    np.testing.assert_array_equal(new[[0, 1, -2, -1]], poles[[0, 1, -2, -1]])
    np.testing.assert_array_equal(new[:, [0, 1, -2, -1]], poles[:, [0, 1, -2, -1]])
    assert refill(poles, knots, held=1) is None


def test_a_loose_refill_keeps_the_border_alone_where_the_tangent_plane_would_turn_it_over():
    """Folded 150 deg, the U seen from its tilted direction d: the refill that keeps the face's
    tangent plane along its sides still turns over (the folded arm's sides lean past d), the one
    that keeps its border alone does not. A reshaped map gives that one only when asked (loose:
    the caller then checks it against the neighbouring surfaces, cad.object_shell.loosened)."""
    poles, knots = bspline_face(folded_u(150.0))
    border, uv = border_of(poles, knots)
    mapped = plane_map(border, uv)
    assert mapped.reshaped
    d = mapped.axes[2]
    assert sorted(refill_poles(mapped, poles, (knots, knots), (3, 3), held=(2, 1))) == [2]
    grids = refill_poles(mapped, poles, (knots, knots), (3, 3), held=(2, 1), loose=True)
    assert sorted(grids) == [1, 2]
    assert (normals(grids[2], knots) @ d).min() < -0.2
    assert (normals(grids[1], knots) @ d).min() > 0.0
    np.testing.assert_array_equal(grids[1][[0, -1]], poles[[0, -1]])
    np.testing.assert_array_equal(grids[1][:, [0, -1]], poles[:, [0, -1]])


def test_is_simple_reads_every_pair_of_segments():
    """The all-pairs test agrees with a plain loop over the pairs on random polygons."""
    rng = np.random.default_rng(5)

    def crossing(p, q, r, s):
        c = lambda a, b, x: (b[0] - a[0]) * (x[1] - a[1]) - (b[1] - a[1]) * (x[0] - a[0])
        return c(p, q, r) * c(p, q, s) < 0 and c(r, s, p) * c(r, s, q) < 0

    simple = 0
    for _ in range(300):
        poly = rng.normal(size=(int(rng.integers(4, 12)), 2))
        m = len(poly)
        plain = not any(crossing(poly[i], poly[(i + 1) % m], poly[j], poly[(j + 1) % m])
                        for i in range(m) for j in range(i + 2, m) if not (i == 0 and j == m - 1))
        assert is_simple(poly) == plain
        simple += plain
    assert 0 < simple < 300


def test_untangled_cuts_off_a_small_loop_at_its_crossing():
    """A square whose bottom runs past its corner and whose right side starts back under it: the
    small loop they make (1.70 long: from the crossing along the bottom, back, and up the right
    side to it) is cut off at the crossing, the values there interpolated along the bottom; where
    that is more than `most` of the length, or the polygon runs clockwise, it is refused."""
    xy = np.array([[0, 0], [10.4, 0], [9.9, -0.5], [10, 10], [0, 10]], float)
    values = np.arange(5.0)[:, None]
    assert not is_simple(xy)
    cut, at = untangled(xy, values, 0.05)
    assert is_simple(cut) and len(cut) == 4
    x = 9.9 + 0.1 * 0.5 / 10.5                    # where the right side crosses the bottom
    np.testing.assert_allclose(cut[1], [x, 0.0], atol=1e-12)
    np.testing.assert_allclose(at[:, 0], [0.0, x / 10.4, 3.0, 4.0], atol=1e-12)
    assert untangled(xy, values, 0.035) is None    # 1.70 of 41.6
    eight = np.array([[0, 0], [10, 10], [10, 0], [0, 10]], float)
    assert untangled(eight, np.zeros((4, 1)), 0.4) is None      # two lobes, each half of it
    square = np.array([[0, 0], [10, 0], [10, 10], [0, 10]], float)
    assert untangled(square, np.zeros((4, 1)), 0.1) is not None
    assert untangled(square[::-1], np.zeros((4, 1)), 0.1) is None     # clockwise


def _square(n=40, size=100.0):
    t = np.linspace(0.0, 1.0, n, endpoint=False)[:, None]
    corners = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float) * size
    return np.vstack([a + t * (b - a) for a, b in zip(corners, np.roll(corners, -1, axis=0))])


@pytest.mark.parametrize("corner", [0, 40])
def test_untangled_reads_a_small_loop_the_same_at_any_corner(corner):
    """The same small loop (1 + sqrt 2 + 1 long) drawn at the corner where the polygon starts (its
    crossing between its last segments and its first) and at another: cut off within 1 % of the
    length, refused within 0.7 %, either way."""
    xy = _square()
    m = len(xy)
    if corner == 0:     # the left side runs down past (0, 0), the bottom starts back left of it
        xy[m - 1], xy[0] = (0.0, -1.0), (-1.0, 0.0)
    else:               # the bottom runs on past (100, 0), the right side starts back under it
        xy[40], xy[41] = (101.0, 0.0), (100.0, -1.0)
    values = np.arange(float(m))[:, None]
    assert not is_simple(xy)
    found = untangled(xy, values, 0.01)
    assert found is not None and is_simple(found[0]) and len(found[0]) == m - 1
    assert untangled(xy, values, 0.007) is None


def test_a_loop_with_a_small_loop_by_a_corner_is_refilled_without_it():
    """The U's border, its bottom drawn 2 mm past a corner and back under it: crossing itself seen
    from every side, the loop is refilled over its plane without that small loop (2 rows held
    only): the face turns over nowhere, its border poles where they were."""
    poles, knots = bspline_face(u_loop())
    border, uv = border_of(poles, knots)
    np.testing.assert_allclose(border[118:122, :2], [[295, 0], [297.5, 0], [300, 0], [300, 200 / 120]], atol=1e-9)
    border[119], border[120] = (302.0, 0.0, 0.0), (299.0, -2.0, 0.0)
    c, _, _, n = loop_plane(border)
    assert simple_frame(border, c, n) is None
    new = plane_refill(poles, (knots, knots), (3, 3), border, uv, held=(1, 2))
    assert len(new) == 1
    assert (normals(new[0], knots)[:, 2] > 0.99).all()
    np.testing.assert_array_equal(new[0][[0, 1, -2, -1]], poles[[0, 1, -2, -1]])
    np.testing.assert_array_equal(new[0][:, [0, 1, -2, -1]], poles[:, [0, 1, -2, -1]])
