"""Curves drawn twice between the same two nodes (core.twice_drawn): merged when their faired
curves lie within SIDE_GAP x delta of each other both ways, so that the lens between them is no
surface and the surfaces on either side share one curve; a wider lens stays a surface."""
from __future__ import annotations

import numpy as np

from ProgSurf.core.objects import build_object
from ProgSurf.core.pipeline import SNAP_FRACTION
from ProgSurf.core.stroke_cycles import find_cycles
from ProgSurf.core.stroke_graph import build_stroke_graph
from ProgSurf.core.twice_drawn import twice_drawn

W, H = 200.0, 120.0


def _bump(x, y):
    return 20.0 * np.sin(np.pi * x / W) * np.sin(np.pi * y / H)


def _line(p, q, n=40):
    t = np.linspace(0.0, 1.0, n)[:, None]
    xy = np.asarray(p, float) + t * (np.asarray(q, float) - np.asarray(p, float))
    return np.column_stack([xy, _bump(xy[:, 0], xy[:, 1])])


def _pass(side: float, half_width: float, n: int = 60):
    """A stroke across the middle from the left side to the right one, bowed half_width to `side`
    (+1 or -1) in y and back: two of them make a lens 2 x half_width wide at its middle."""
    x = np.linspace(0.0, W, n)
    y = H / 2 + side * half_width * np.sin(np.pi * x / W)
    return np.column_stack([x, y, _bump(x, y)])


def sketch(half_width: float) -> list:
    """A bumped rectangle (four strokes overshooting their corners) cut in two by a curve drawn
    twice, the passes bowed apart into a lens."""
    return [_line((-6, 0), (W + 6, 0)), _line((W, -6), (W, H + 6)), _line((W + 6, H), (-6, H)),
            _line((0, H + 6), (0, -6)), _pass(+1, half_width), _pass(-1, half_width)[::-1]]


def _network(half_width: float):
    strokes = sketch(half_width)
    delta = SNAP_FRACTION * float(np.linalg.norm(np.ptp(np.vstack(strokes), axis=0)))
    graph = build_stroke_graph(strokes, delta)
    return graph, find_cycles(graph)


def _lens(graph, choice):
    lens = [c for c in choice.cycles if len(c.sides) == 2]
    assert len(lens) == 1, [len(c.sides) for c in choice.cycles]
    return lens[0]


def test_a_lens_whose_faired_sides_coincide_is_merged_and_its_neighbours_share_the_curve():
    """The passes 1.5 delta apart at the middle are two graph edges (within delta along less than
    OVERSKETCH_COVER of them) and the cycles hold the lens between them; given faired sides that
    coincide (both on the middle line, sampled differently), the lens is
    dropped with its reason and both neighbours take the earlier stroke's edge, in their own
    direction round them."""
    graph, choice = _network(0.75 * SNAP_FRACTION * np.hypot(W + 12, H + 12))
    lens = _lens(graph, choice)
    (a, _), (b, _) = lens.sides
    assert len(choice.cycles) == 3
    polylines = {e.id: e.points for e in graph.edges}
    for e, n in ((a, 23), (b, 57)):
        p0, p1 = graph.edges[e].points[0], graph.edges[e].points[-1]
        x = np.linspace(p0[0], p1[0], n)
        polylines[e] = np.column_stack([x, np.full(n, H / 2), _bump(x, np.full(n, H / 2))])
        polylines[e][0], polylines[e][-1] = p0, p1
    merged_choice, merged = twice_drawn(graph, choice, polylines)
    kept, gone = sorted((a, b), key=lambda e: graph.edges[e].stroke)
    assert merged == {gone: kept}
    assert len(merged_choice.cycles) == 2
    assert all(kept in c.edge_ids and gone not in c.edge_ids for c in merged_choice.cycles)
    assert any(c == lens and "drawn twice" in why for c, why in merged_choice.dropped)
    for c in merged_choice.cycles:            # each side still runs from where the one before ends
        ends = [graph.edges[e].node1 if rev else graph.edges[e].node0 for e, rev in c.sides]
        starts = [graph.edges[e].node0 if rev else graph.edges[e].node1 for e, rev in c.sides]
        assert starts == ends[1:] + ends[:1]


def test_a_lens_wider_than_delta_once_faired_is_a_surface_of_its_own():
    """The same passes with their own (faired) points: 1.5 delta apart, not one curve; nothing is
    merged, and the built object has the lens as a third surface."""
    graph, choice = _network(0.75 * SNAP_FRACTION * np.hypot(W + 12, H + 12))
    same, merged = twice_drawn(graph, choice, {e.id: e.points for e in graph.edges})
    assert merged == {} and same is choice
    out = build_object(sketch(0.75 * SNAP_FRACTION * np.hypot(W + 12, H + 12)))
    assert len(out.surfaces) == 3
    assert not any("drawn twice" in r.reason for r in out.roles)


def test_passes_within_delta_are_one_curve_already_in_the_graph():
    """Passes 0.4 delta apart are merged by the graph (stroke_graph._merge_parallel), and the built
    object is two surfaces on one shared curve; the later stroke is accounted for as merged."""
    out = build_object(sketch(0.2 * SNAP_FRACTION * np.hypot(W + 12, H + 12)))
    assert len(out.surfaces) == 2
    shared = set(out.surfaces[0].sides) & set(out.surfaces[1].sides)
    assert len(shared) == 1
    assert "merged" in out.roles[5].reason


def test_faired_sides_further_apart_than_the_side_by_side_gap_are_two_curves():
    """Faired sides 0.8 delta apart at the middle (within delta, beyond SIDE_GAP x delta: curves of
    one family drawn close together, as core.stroke_graph._side_by_side keeps them apart) are
    not merged: the lens stays a loop of its own."""
    half = 0.75 * SNAP_FRACTION * np.hypot(W + 12, H + 12)
    graph, choice = _network(half)
    (a, _), (b, _) = _lens(graph, choice).sides
    polylines = {e.id: e.points for e in graph.edges}
    for e in (a, b):
        p = graph.edges[e].points
        mid = np.column_stack([p[:, 0], H / 2 + 0.4 / 0.75 * (p[:, 1] - H / 2), p[:, 2]])
        polylines[e] = mid
        assert 0.79 * graph.delta < 2 * np.abs(mid[:, 1] - H / 2).max() < 0.81 * graph.delta
    same, merged = twice_drawn(graph, choice, polylines)
    assert merged == {} and same is choice
