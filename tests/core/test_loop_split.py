"""core.loop_split: the curve across a loop and the choice of a division (issue 18)."""
from __future__ import annotations

import numpy as np

from ProgSurf.core.loop_split import best_division, chord, halves, loop_turn_deg


def _loop(points) -> list:
    pts = [np.asarray(p, dtype=float) for p in points]
    return [np.linspace(pts[k], pts[(k + 1) % len(pts)], 20) for k in range(len(pts))]


def test_the_curve_across_ends_at_the_nodes_and_lies_in_a_flat_loops_plane():
    sides = _loop([(0, 0, 0), (100, 0, 0), (100, 30, 0), (30, 30, 0), (30, 100, 0), (0, 100, 0)])
    across = chord(sides, 0, 3)
    assert np.array_equal(across[0], sides[0][0]) and np.array_equal(across[-1], sides[3][0])
    assert np.abs(across[:, 2]).max() < 1e-9


def test_the_curve_across_leaves_each_node_in_the_plane_of_the_sides_meeting_there():
    """On a loop that is not flat (a hexagon on a saddle, z = xy/100), the curve across leaves node
    i and arrives at node j along the plane the two sides meeting there span: the plane the surface
    passes through the node in. (On a flat loop's rim that plane is the loop's, as a Coons patch of
    that loop is flat.)"""
    ang = np.linspace(0, 2 * np.pi, 7)[:-1]
    nodes = [np.array([80 * np.cos(a), 60 * np.sin(a), 0.0]) for a in ang]
    for p in nodes:
        p[2] = p[0] * p[1] / 100.0
    sides = []
    for k in range(6):
        t = np.linspace(0, 1, 30)[:, None]
        xy = nodes[k][:2] + t * (nodes[(k + 1) % 6][:2] - nodes[k][:2])
        sides.append(np.c_[xy, xy[:, 0] * xy[:, 1] / 100.0])
    across = chord(sides, 1, 4)
    for k, d in ((1, across[1] - across[0]), (4, across[-2] - across[-1])):
        before, after = sides[k - 1][-2] - sides[k - 1][-1], sides[k][1] - sides[k][0]
        normal = np.cross(before, after)
        normal /= np.linalg.norm(normal)
        assert abs(float(d @ normal)) / np.linalg.norm(d) < 0.05, k


def test_a_loop_that_does_not_fold_is_not_divided_and_the_halves_close():
    sides = _loop([(0, 0, 0), (60, 0, 5), (100, 20, 0), (90, 80, 5), (40, 100, 0), (0, 60, 5)])
    assert loop_turn_deg(sides) < 85
    assert best_division(sides) is None
    across = chord(sides, 1, 4)
    a, b = halves(sides, 1, 4, across)
    for part in (a, b):
        for one, two in zip(part, part[1:] + part[:1]):
            assert np.array_equal(one[-1], two[0])          # each side starts where the last ended
