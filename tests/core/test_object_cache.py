"""Incremental whole-object builds (issue 18, item 6): with a core.objects.BuildCache, an edited
sketch rebuilds only the surfaces whose inputs changed, and the result is the one a build from
scratch gives (core surfaces, their faces, the report). A box's edges make six surfaces; a stroke
drawn over its top face is an interior stroke of that one surface only."""
from __future__ import annotations

import numpy as np
import pytest

from ProgSurf.app.objects import build_object_and_measure, object_report
from ProgSurf.core.objects import BuildCache, build_object, steady_tolerances
from ProgSurf.core.types import Tolerances
from test_stroke_graph import cube_edges

BOX = np.array([10.0, 8.0, 6.0])
SIZE = BOX[2]


def box_edges():
    """The twelve edges of the box [0, 10] x [0, 8] x [0, 6] (sides all different: its principal
    axes, and so the automatic tolerances, are well defined)."""
    return [e * BOX / 10.0 for e in cube_edges()]


def over_top(bulge=1.0, n=25):
    """A stroke above the box's top face (z = SIZE), inside it, bulging up in its middle."""
    t = np.linspace(0.0, 1.0, n)
    return np.stack([2 + 6 * t, 2 + 4 * t, SIZE + bulge * np.sin(np.pi * t)], axis=1)


def network_content(result) -> tuple:
    """Everything of a surface's patch network, as plain values: nodes (uv, xyz), edges (ends,
    curve, polyline points), regions (corner cycles)."""
    net = result.network
    nodes = tuple((n, net.node_uv(n).tobytes(), net.node_xyz(n).tobytes()) for n in sorted(net.node_ids))
    edges = tuple((k, e.node0, e.node1, e.curve_id, e.polyline.points.tobytes())
                  for k, e in sorted(net.edges().items()))
    regions = tuple((r, net.region_cycle(r)) for r in sorted(net.region_ids))
    return nodes, edges, regions


def same_build(a, b) -> None:
    """Two ObjectBuilds are the same build: surfaces (cycles, sides, interior, networks, records),
    failures and stroke roles."""
    assert len(a.surfaces) == len(b.surfaces)
    for s, t in zip(a.surfaces, b.surfaces):
        assert (s.key, s.sides, s.interior, s.part, s.cycle.sides) == (t.key, t.sides, t.interior, t.part, t.cycle.sides)
        assert network_content(s.result) == network_content(t.result)
        assert [(r.status, r.reason) for r in s.result.records] == [(r.status, r.reason) for r in t.result.records]
    assert [(c.sides, why) for c, why in a.failed] == [(c.sides, why) for c, why in b.failed]
    assert a.roles == b.roles


@pytest.fixture(scope="module")
def tol():
    return steady_tolerances(box_edges(), Tolerances())


def top_surface(build) -> int:
    """The surface on the top face (z = SIZE): the one whose sides' points all lie at that height."""
    tops = [k for k, s in enumerate(build.surfaces)
            if all(np.allclose(build.graph.edges[e].points[:, 2], SIZE) for e in s.sides)]
    assert len(tops) == 1
    return tops[0]


def test_a_stroke_inside_one_surface_rebuilds_that_surface_only(tol):
    cache = BuildCache()
    first = build_object(box_edges(), tol, cache=cache)
    assert first.rebuilt == tuple(range(6))            # an empty cache: everything is built
    grown = build_object(box_edges() + [over_top()], tol, cache=cache)
    top = top_surface(grown)
    assert grown.roles[-1].interior_to == (top,)
    assert grown.rebuilt == (top,)
    for k, surf in enumerate(grown.surfaces):
        if k != top:
            assert surf.reused and surf.result is first.surfaces[k].result
    # the rebuilt surface follows the new stroke: its network is no longer the empty face's
    assert network_content(grown.surfaces[top].result) != network_content(first.surfaces[top].result)
    same_build(grown, build_object(box_edges() + [over_top()], tol))


def test_removing_the_stroke_again_takes_the_surface_back_from_the_build_before(tol):
    cache = BuildCache()
    first = build_object(box_edges(), tol, cache=cache)
    build_object(box_edges() + [over_top()], tol, cache=cache)
    back = build_object(box_edges(), tol, cache=cache)       # an undo
    assert back.rebuilt == ()
    assert all(s.result is f.result for s, f in zip(back.surfaces, first.surfaces))


def test_bowing_a_stroke_rebuilds_the_surfaces_it_bounds(tol):
    cache = BuildCache()
    first = build_object(box_edges(), tol, cache=cache)
    strokes = box_edges()
    k = 0
    t = np.linspace(0.0, 1.0, len(strokes[k]))
    # its ends stay at the box's corners: the other strokes' pieces keep their points
    strokes[k] = strokes[k] + np.outer(0.5 * np.sin(np.pi * t), [-1.0, -1.0, 0.0])
    bowed = build_object(strokes, tol, cache=cache)
    assert len(first.roles[k].boundary_of) == 2
    assert set(bowed.roles[k].boundary_of) <= set(bowed.rebuilt)
    # the faces away from the bowed stroke (not at its end corners, whose node points the stroke
    # graph may move slightly) are kept
    ends = {n for e in bowed.graph.edges_of_stroke(k) for n in (e.node0, e.node1)}
    touching = {j for j, s in enumerate(bowed.surfaces)
                if any({bowed.graph.edges[e].node0, bowed.graph.edges[e].node1} & ends for e in s.sides)}
    assert set(bowed.rebuilt) <= touching and len(touching) < 6
    same_build(bowed, build_object(strokes, tol))


def test_a_changed_option_rebuilds_every_surface(tol):
    cache = BuildCache()
    build_object(box_edges(), tol, cache=cache)
    assert build_object(box_edges(), tol, cache=cache).rebuilt == ()
    finer = Tolerances(filter_mm=tol.filter_mm, snap_mm=tol.snap_mm, fit_mm=0.5 * tol.fit_mm)
    assert build_object(box_edges(), finer, cache=cache).rebuilt == tuple(range(6))


def test_the_cache_keys_on_the_points_not_on_the_objects(tol):
    """Equal strokes in new arrays find their surfaces in the cache. A point moved by one unit in
    the last place is rounded to the fit grid (core.strokes.round_points) before anything is built
    from it: the surfaces' inputs are the same, and so are their keys. A point moved by five times
    the fit tolerance changes the surfaces the stroke bounds, and only those."""
    cache = BuildCache()
    build_object(box_edges(), tol, cache=cache)
    assert build_object([s.copy() for s in box_edges()], tol, cache=cache).rebuilt == ()
    strokes = box_edges()
    strokes[3][10] = np.nextafter(strokes[3][10], np.inf)
    assert build_object(strokes, tol, cache=cache).rebuilt == ()
    along = strokes[3][-1] - strokes[3][0]
    across = np.cross(along, [1.0, 1.0, 1.0])
    strokes[3][10] += 5 * tol.fit_mm * across / np.linalg.norm(across)
    nudged = build_object(strokes, tol, cache=cache)
    assert len(nudged.roles[3].boundary_of) == 2
    assert set(nudged.rebuilt) == set(nudged.roles[3].boundary_of)
    same_build(nudged, build_object(strokes, tol))


def test_steady_tolerances_round_the_automatic_values_and_keep_given_ones():
    auto = Tolerances()
    steady = steady_tolerances(box_edges(), auto)
    for name in ("filter_mm", "snap_mm", "fit_mm"):
        value = getattr(steady, name)
        assert float(f"{value:.2e}") == value
    bigger = [s * (1 + 1e-5) for s in box_edges()]     # the sketch's size changed in the 5th digit
    assert steady_tolerances(bigger, auto) == steady
    given = Tolerances(filter_mm=0.123456, snap_mm=0.654321, fit_mm=0.00123456)
    assert steady_tolerances(box_edges(), given) == given


def test_app_build_reuses_the_faces_and_reports_as_a_build_from_scratch(tol):
    """app.objects with a cache: the untouched surfaces keep their very ShellResults (the OCC faces
    are not made again), and the report and shape equal those of a build without a cache."""
    import Part  # noqa: F401  (after FreeCAD, by the conftest)

    cache = BuildCache()
    first = build_object_and_measure(box_edges(), tol, cache=cache)
    grown = build_object_and_measure(box_edges() + [over_top()], tol, cache=cache)
    top = top_surface(grown.build)
    assert grown.build.rebuilt == (top,)
    for k in range(6):
        assert (grown.model.surfaces[k] is first.model.surfaces[k]) == (k != top)
    scratch = build_object_and_measure(box_edges() + [over_top()], tol)
    a, b = object_report(grown), object_report(scratch)
    a.pop("timings_s"), b.pop("timings_s")
    assert a == b
    assert grown.shape.Area == pytest.approx(scratch.shape.Area, rel=1e-12)
    assert grown.shape.isValid() and grown.model.shells[0].isClosed()
    # the new stroke shaped the top: the grown box's area exceeds the plain one's
    assert grown.shape.Area > first.shape.Area + 1.0
