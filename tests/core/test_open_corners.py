"""core.open_corners: a loop's corner whose two sides leave it the wrong way round the loop, just by
the node, is opened so that its Coons patch does not turn over there (issue 18)."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ProgSurf.core.folds import TUCK_REACH
from ProgSurf.core.loop_corners import FOLD_DEG, patch_turns_deg
from ProgSurf.core.open_corners import CORNER_READ, OPEN_SHARES, open_corners
from ProgSurf.core.stroke_cycles import Cycle, CycleChoice

DATA = Path(__file__).resolve().parents[2].parent / "shared" / "data"
LAMP = DATA / "cassie" / "10-2-1.xyz"
STROKES = {0: 0, 1: 1, 2: 2, 3: 3}             # each side of the test loop its own stroke


def _crossed_corner(dip: float):
    """A 4-sided loop, 100 x 40 mm: the bottom runs straight along x from the origin, the left
    side comes back to the origin along y = -dip x + c x^2 (through (60, 40)): it leaves the origin
    `dip` below the bottom's line and crosses it 13 mm on (for dip 0.2), so its first millimetres
    lie on the wrong side of the bottom, as two VR strokes meeting nearly tangent do."""
    x = np.linspace(0.0, 100.0, 41)
    bottom = np.c_[x, 0 * x, 0 * x]
    right = np.c_[np.full(21, 100.0), np.linspace(0.0, 40.0, 21), np.zeros(21)]
    top = np.c_[np.linspace(100.0, 60.0, 17), np.full(17, 40.0), np.zeros(17)]
    c = (40.0 + dip * 60.0) / 3600.0
    u = np.linspace(60.0, 0.0, 61)
    left = np.c_[u, -dip * u + c * u ** 2, 0 * u]
    polylines = {0: bottom, 1: right, 2: top, 3: left}
    cycle = Cycle(((0, False), (1, False), (2, False), (3, False)), 1.0)
    return CycleChoice((cycle,), (), frozenset(), {}, ()), polylines


def _turn(sides) -> float:
    """How far the loop's Coons patch turns inside it (the built face's checks, loop_corners)."""
    every = np.concatenate(sides)
    reach = TUCK_REACH * float(np.linalg.norm(every.max(axis=0) - every.min(axis=0)))
    return float(patch_turns_deg([sides], reach, dense=True)[0])


def test_a_corner_whose_sides_cross_by_the_node_is_opened_and_its_patch_no_longer_turns_over():
    choice, polylines = _crossed_corner(0.2)
    sides = choice.cycles[0].polylines_from(polylines)
    before = _turn(sides)
    assert before > FOLD_DEG
    opened_lines, opened = open_corners(choice, polylines, STROKES, {})
    assert opened == [(3, 0)]
    after = _turn(choice.cycles[0].polylines_from(opened_lines))
    assert after < FOLD_DEG, (before, after)
    for e in polylines:
        # every edge keeps its ends exactly (its nodes, shared with the other surfaces there) ...
        np.testing.assert_array_equal(opened_lines[e][[0, -1]], polylines[e][[0, -1]])
    # ... the two sides at the other corners are untouched ...
    for e in (1, 2):
        np.testing.assert_array_equal(opened_lines[e], polylines[e])
    # ... and the two opened move by under 2 mm (the left side dipped 0.7 mm below the bottom's
    # line), over no more than the first OPEN_SHARES[-1] of them
    for e, length in ((0, 100.0), (3, 80.0)):
        moved = np.array([np.min(np.linalg.norm(polylines[e] - p, axis=1)) for p in opened_lines[e]])
        assert moved.max() < 2.0
        end = polylines[e][0] if e == 0 else polylines[e][-1]
        far = np.linalg.norm(opened_lines[e] - end, axis=1) > OPEN_SHARES[-1] * length
        assert moved[far].max() < 1e-9
    left = opened_lines[3][::-1]
    reach = np.searchsorted(np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(left, axis=0), axis=1))],
                            CORNER_READ * 80.0)
    assert left[reach, 1] > 0.0                   # the left side leaves above the bottom now


def test_a_loop_whose_corners_leave_the_right_way_is_left_as_it_is():
    choice, polylines = _crossed_corner(-0.2)     # the left side leaves the origin above the bottom
    out, opened = open_corners(choice, polylines, STROKES, {})
    assert opened == []
    for e in polylines:
        np.testing.assert_array_equal(out[e], polylines[e])


def test_a_stroke_running_on_through_the_corner_keeps_its_direction_there():
    """Where the bottom is a piece of a stroke that runs on through the corner's node (node_tangents
    gave it a direction there), or the bottom and the left side are two pieces of one stroke, the
    corner is not opened: the stroke's direction there is kept."""
    choice, polylines = _crossed_corner(0.2)
    out, opened = open_corners(choice, polylines, STROKES, {(0, 0): np.array([1.0, 0.0, 0.0])})
    assert opened == []
    out, opened = open_corners(choice, polylines, {0: 0, 1: 1, 2: 2, 3: 0}, {})
    assert opened == []


@pytest.mark.skipif(not LAMP.is_file(), reason=f"shared sketch {LAMP} not found (../shared/data, absent from a user's clone)")
def test_the_lamps_two_crossed_corners_are_opened_and_their_surfaces_no_longer_fold():
    """CASSIE 10-2-1 (a lamp drawn in VR): strokes 67 and 69, and 66 and 68, leave their nodes the
    wrong way round the loops they bound (they cross again just by the node). Before, both of
    those surfaces were reported folding; opened, neither does, and the report and the summary
    name the corners."""
    from ProgSurf.app.objects import build_object_and_measure, object_report, object_summary
    from ProgSurf.io import read_strokes

    out = build_object_and_measure(read_strokes(LAMP))
    report = object_report(out, outputs={"step": "x.step"})
    corners = {frozenset(c["strokes"]): c["surfaces"] for c in report["opened_corners"]}
    for pair in ({67, 69}, {66, 68}):
        assert len(corners[frozenset(pair)]) == 1
        (k,) = corners[frozenset(pair)]
        assert not report["surfaces"][k]["folds"]
    assert "opened: they left it the wrong way round the loop" in object_summary(report)
    assert all(shell["valid"] for shell in out.shells)


def test_a_corner_is_not_opened_where_that_would_turn_a_neighbours_corner_over():
    """The crossed corner's left side also bounds a second loop, on its other side, whose other side
    leaves the same node along the bottom's line, between the left side's direction there (5 deg
    below it) and its direction once eased (above it): opened, that loop's corner would leave the
    wrong way. It is left as it is; alone, it is opened."""
    choice, polylines = _crossed_corner(0.2)
    alone, opened = open_corners(choice, polylines, STROKES, {})
    assert opened == [(3, 0)]
    x = np.linspace(0.0, 10.0, 11)
    polylines[6] = np.vstack([np.linspace([60.0, 40.0, 0.0], [10.0, 0.0, 0.0], 26)[:-1], np.c_[x[::-1], 0 * x, 0 * x]])
    neighbour = Cycle(((3, True), (6, False)), 1.0)
    both = CycleChoice(choice.cycles + (neighbour,), (), frozenset(), {}, ())
    out, opened = open_corners(both, polylines, {**STROKES, 6: 6}, {})
    assert opened == []
    for e in polylines:
        np.testing.assert_array_equal(out[e], polylines[e])
