"""A stroke drawn off the surface (core.off_surface): moved onto the strokes it crosses when it
misses them all alike, within the snap distance; otherwise the paper's rule (later strokes win)."""
import numpy as np

from ProgSurf.core.off_surface import drawn_off, onto_crossings
from ProgSurf.core.progressive import add_stroke
from ProgSurf.core.types import Tolerances

from test_progressive import check_invariants, flat_network, line

TOL = Tolerances()
SNAP = 10.0


def two_sections():
    """A flat 100 x 100 square crossed by two strokes x = 30 and x = 70 drawn on it."""
    net = flat_network()
    for k, x in enumerate((30, 70)):
        assert add_stroke(net, line((x, 0, 0), (x, 100, 0)), 4 + k, TOL, snap=SNAP).status == "accepted"
    return net


def across(z):
    """A stroke across both sections, y = 50 from x = -2 to 102 (over the boundary), at height z(x)."""
    pts = line((-2, 50, 0), (102, 50, 0), 53)
    pts[:, 2] = z(pts[:, 0])
    return pts


def highest(net):
    return max(float(np.abs(e.polyline.points[:, 2]).max()) for e in net.edges().values())


def test_stroke_drawn_six_mm_over_the_surface_is_moved_onto_the_strokes_it_crosses():
    net = two_sections()
    rec = add_stroke(net, across(lambda x: 6.0 + 0 * x), 6, TOL, snap=SNAP)
    assert rec.status == "accepted"
    assert "drawn off the surface" in rec.reason and "4 drawn curves" in rec.reason, rec.reason
    check_invariants(net, rec, SNAP)
    # nothing was pulled up: every curve, the new one included, stays on the plane
    assert highest(net) < 1e-6
    assert abs(net.evaluate_uv(np.array([0.5, 0.5]))[2]) < 1e-6
    # the stroke as used (in the record) is the drawn one moved down
    assert np.abs(rec.points[:, 2]).max() < 1e-6


def test_stroke_that_rises_between_the_curves_keeps_its_shape_above_them():
    """Only the misses where it meets drawn curves are removed: a stroke 6 mm up at the boundary
    and the sections and 10 mm up between them still raises the surface there by about 4 mm."""
    net = two_sections()
    bump = lambda x: 6.0 + 4.0 * np.clip(1.0 - np.abs(x - 50.0) / 15.0, 0.0, 1.0)
    rec = add_stroke(net, across(bump), 6, TOL, snap=SNAP)
    assert rec.status == "accepted" and "drawn off the surface" in rec.reason
    # (a miss is measured across the stroke's chord over a snap distance, here rising a little)
    assert abs(net.evaluate_uv(np.array([0.3, 0.5]))[2]) < 0.1
    assert abs(net.evaluate_uv(np.array([0.5, 0.5]))[2] - 4.0) < 0.3


def test_stroke_further_off_than_the_snap_distance_reshapes_the_surface_as_drawn():
    """A deliberate reshape: 15 mm (1.5 snap distances) up along its whole length."""
    net = two_sections()
    rec = add_stroke(net, across(lambda x: 15.0 + 0 * x), 6, TOL, snap=SNAP)
    assert rec.status == "accepted" and "drawn off" not in rec.reason
    assert abs(net.evaluate_uv(np.array([0.3, 0.5]))[2] - 15.0) < 0.5


def test_stroke_within_drawing_noise_pulls_the_curves_it_crosses():
    """3 mm (0.3 snap distances) is drawing noise here: later strokes win, as in the paper."""
    net = two_sections()
    rec = add_stroke(net, across(lambda x: 3.0 + 0 * x), 6, TOL, snap=SNAP)
    assert rec.status == "accepted" and "drawn off" not in rec.reason
    assert 2.0 < net.evaluate_uv(np.array([0.3, 0.5]))[2] < 3.5


def test_stroke_that_meets_the_boundary_and_rises_in_the_middle_is_a_reshape():
    net = two_sections()
    rec = add_stroke(net, across(lambda x: 8.0 * np.sin(np.pi * np.clip(x, 0, 100) / 100)), 6, TOL, snap=SNAP)
    assert rec.status == "accepted" and "drawn off" not in rec.reason
    assert net.evaluate_uv(np.array([0.5, 0.5]))[2] > 7.0


def test_drawn_off_needs_two_misses_alike_along_the_normal():
    p = np.zeros(3)
    up = np.array([0.0, 0.0, 6.0])
    z = np.array([[0.0, 0.0, 1.0]] * 2)
    assert drawn_off([(p, up)], z[:1], SNAP) is None                          # one is not enough
    assert drawn_off([(p, up), (p, up * 1.2)], z, SNAP) == 6.6
    assert drawn_off([(p, up), (p, -up)], z, SNAP) is None                    # opposite sides
    assert drawn_off([(p, up), (p, np.array([6.0, 0.0, 0.0]))], z, SNAP) is None   # along the surface
    assert drawn_off([(p, up * 0.7), (p, up * 2.3)], z, SNAP) is None         # uneven: 4.2 and 13.8 mm
    assert drawn_off([(p, up * 0.4), (p, up * 0.4)], z, SNAP) is None         # 2.4 mm: noise
    assert drawn_off([(p, up * 2.0), (p, up * 2.0)], z, SNAP) is None         # 12 mm: beyond the snap
    # a curved surface turns its normal, and misses held off it turn alike
    tilted = np.array([[0.0, 0.6, 0.8], [0.0, -0.6, 0.8]])
    assert drawn_off([(p, 6.0 * tilted[0]), (p, 6.0 * tilted[1])], tilted, SNAP) == 6.0


def test_onto_crossings_removes_each_miss_where_it_was_and_spreads_it_between():
    pts = line((0, 0, 5), (100, 0, 5), 101)
    misses = [(np.array([20.0, 0, 5]), np.array([0, 0, 5.0])), (np.array([80.0, 0, 5]), np.array([0, 0, 3.0]))]
    out = onto_crossings(pts, misses)
    z = dict(zip(pts[:, 0].round(6), out[:, 2]))
    assert abs(z[0.0] - 0.0) < 1e-9 and abs(z[20.0] - 0.0) < 1e-9     # held before the first
    assert abs(z[50.0] - 1.0) < 1e-9                                  # halfway between 0 and 2
    assert abs(z[80.0] - 2.0) < 1e-9 and abs(z[100.0] - 2.0) < 1e-9   # held after the last
    assert np.array_equal(out[:, :2], pts[:, :2])
