"""core.node_tangents: one direction for a stroke where it runs through a node of the network, so
that the curves of its pieces join tangent-continuously there (and none where it was drawn with a
corner); the curves fitted with them (cad.shared_edges.graph_curves) do join so."""
from __future__ import annotations

import numpy as np
import pytest

from ProgSurf.core.node_tangents import KINK_DEG, node_tangents
from ProgSurf.core.objects import _faired_strokes, _stroke_arcs, build_object, edge_polylines, stroke_network
from test_stroke_graph import cylinder, grid, line


def _tangents(strokes):
    """(StrokeGraph, node_tangents) of a sketch, as core.objects.build_object finds them."""
    g, _, tol = stroke_network(strokes)
    faired, origins = _faired_strokes(list(g.strokes), tol)
    arcs = _stroke_arcs(g, faired, origins)
    return g, node_tangents(g, faired, arcs, edge_polylines(g, faired, origins, arcs))


def _angle(a, b) -> float:
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.degrees(np.arccos(np.clip(a @ b / np.linalg.norm(a) / np.linalg.norm(b), -1.0, 1.0))))


def test_a_stroke_through_a_crossing_has_one_direction_there_and_none_at_a_corner():
    """A line along x crossed by a line along y: both run through their crossing, each gets its
    own direction there (the same for its two pieces: +x, +y). A V whose corner (90 deg) lies on
    a third line gets none at its corner; the third line, which runs through smoothly, does."""
    strokes = [line([0, 50, 0], [100, 50, 0], 40), line([50, 0, 0], [50, 100, 0], 40),
               np.vstack([line([150, 0, 0], [200, 50, 0], 30), line([200, 50, 0], [250, 0, 0], 30)[1:]]),
               line([150, 50, 0], [250, 50, 0], 40)]
    g, tangents = _tangents(strokes)
    for stroke, axis in ((0, [1, 0, 0]), (1, [0, 1, 0])):
        edges = sorted(g.edges_of_stroke(stroke), key=lambda e: e.s0)
        inner = [(e, f) for e, f in zip(edges[:-1], edges[1:]) if e.node1 == f.node0]
        assert inner
        for e, f in inner:
            assert _angle(tangents[(e.id, 1)], axis) < 1.0 and _angle(tangents[(f.id, 0)], axis) < 1.0
            assert np.array_equal(tangents[(e.id, 1)], tangents[(f.id, 0)])
    v_edges = sorted(g.edges_of_stroke(2), key=lambda e: e.s0)
    corner = [(e, f) for e, f in zip(v_edges[:-1], v_edges[1:]) if e.node1 == f.node0]
    assert corner and all((e.id, 1) not in tangents and (f.id, 0) not in tangents for e, f in corner)
    third = sorted(g.edges_of_stroke(3), key=lambda e: e.s0)
    assert any((e.id, 1) in tangents for e in third[:-1])
    assert KINK_DEG < 90.0


def test_a_ring_runs_through_its_seam():
    """A cylinder's rims are closed strokes: each runs on from its last piece into its first
    through the node where it starts and ends, and gets a direction there as at its crossings;
    the rulings end on the rims and get none."""
    b = build_object(cylinder(radius=50.0, height=120.0))
    for e in b.graph.edges:
        ring = e.stroke in (0, 1)
        assert ((e.id, 0) in b.tangents) == ring and ((e.id, 1) in b.tangents) == ring


def test_the_direction_depends_on_the_stroke_near_its_node_only():
    """A stroke added across one piece of a grid line (the tolerances kept, as an edited sketch
    keeps them) leaves the direction at the line's other nodes as it was, to the bit (the surfaces
    that do not touch the new stroke keep their curves)."""
    strokes = grid(lambda x, y: 20 * np.sin(x / 60.0), n=3, size=200.0, samples=60)
    before = build_object(strokes)
    after = build_object(strokes + [line([50, -20, 0], [50, 80, 0], 40)], before.tol)
    kept = 0
    for (eid, end), t in before.tangents.items():
        e = before.graph.edges[eid]
        node = before.graph.nodes[e.node1 if end else e.node0].point
        if abs(node[0] - 50.0) < 1.0:      # (the new stroke's own nodes)
            continue
        same = [t2 for (eid2, end2), t2 in after.tangents.items()
                if after.graph.edges[eid2].stroke == e.stroke
                and np.linalg.norm(after.graph.nodes[after.graph.edges[eid2].node1 if end2
                                                      else after.graph.edges[eid2].node0].point - node) < 1e-9]
        assert same and all(np.array_equal(t, t2) for t2 in same)
        kept += 1
    assert kept >= 4


def test_graph_curves_of_a_noisy_stroke_join_tangent_continuously():
    """The pieces of a noisy grid's strokes, fitted one by one (cad.shared_edges.graph_curves),
    kink by degrees at their nodes; with the nodes' directions they leave each node along the same
    line (within 1e-6 deg)."""
    pytest.importorskip("FreeCAD")
    from ProgSurf.cad.shared_edges import graph_curves

    rng = np.random.default_rng(1)
    strokes = [s + rng.normal(scale=2.5, size=s.shape)
               for s in grid(lambda x, y: 90 * np.sin(x / 70) * np.cos(y / 120), n=4, size=300.0, samples=60)]
    b = build_object(strokes)
    free = graph_curves(b.polylines, b.tol.fit_mm)
    held = graph_curves(b.polylines, b.tol.fit_mm, b.tangents)
    pairs = {}
    for (eid, end), t in b.tangents.items():
        pairs.setdefault(tuple(t), []).append((eid, end))

    def direction(curves, eid, end):
        return np.array(tuple(curves[eid].curve.tangent(float(end))[0]))

    kinks_free, kinks_held = [], []
    for ends in pairs.values():
        if len(ends) != 2:
            continue
        (e, _), (f, _) = sorted(ends, key=lambda x: -x[1])     # e arrives (end 1), f leaves (end 0)
        kinks_free.append(_angle(direction(free, e, 1), direction(free, f, 0)))
        kinks_held.append(_angle(direction(held, e, 1), direction(held, f, 0)))
    assert len(kinks_held) >= 12
    assert max(kinks_free) > 0.5
    assert max(kinks_held) < 1e-6
