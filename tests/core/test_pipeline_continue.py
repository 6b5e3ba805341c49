"""pipeline.build_network(previous=): when a sketch only grew by interior strokes, the earlier network is
continued with the new strokes (what the document does when a designer adds a stroke), and the
surface is exactly the one built from nothing; any other change builds from nothing. (With the
boundary strokes named, as the document names them, automatic tolerances come from them alone, so
an added interior stroke does not change them.)"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ProgSurf.core.pipeline import build_network
from ProgSurf.io import read_strokes

ROOT = Path(__file__).resolve().parents[2]


def _same_network(a, b) -> None:
    ea, eb = a.edges(), b.edges()
    assert sorted(ea) == sorted(eb)
    for k in ea:
        assert (ea[k].node0, ea[k].node1, ea[k].curve_id) == (eb[k].node0, eb[k].node1, eb[k].curve_id)
        assert np.array_equal(ea[k].polyline.points, eb[k].polyline.points)
        assert np.array_equal(ea[k].polyline.params, eb[k].polyline.params)
    assert a.region_ids == b.region_ids


@pytest.fixture(scope="module")
def strokes():
    return read_strokes(ROOT / "examples" / "clean4.xyz")


def test_adding_interior_strokes_continues_the_earlier_network(strokes):
    full = build_network(strokes, boundary=4)
    n = len(full.interior)
    assert n >= 2
    head = len(strokes) - 1                       # all but the last interior stroke
    assert full.interior[-1] == head
    earlier = build_network(strokes[:head], boundary=4)
    later = build_network(strokes, boundary=4, previous=earlier)
    assert later.timings_s["reused strokes"] == head
    assert "reused strokes" not in full.timings_s
    _same_network(later.network, full.network)
    assert [(r.index, r.role, r.status) for r in later.records] == [(r.index, r.role, r.status) for r in full.records]
    # the earlier result is not changed by being continued
    _same_network(earlier.network, build_network(strokes[:head], boundary=4).network)


def test_a_changed_earlier_stroke_builds_from_nothing(strokes):
    earlier = build_network(strokes[:-1], boundary=4)
    moved = [np.array(s, dtype=float) for s in strokes]
    moved[-2] = moved[-2] + [0.0, 0.0, 0.5]
    later = build_network(moved, boundary=4, previous=earlier)
    assert "reused strokes" not in later.timings_s
    _same_network(later.network, build_network(moved, boundary=4).network)


def test_named_candidates_continue_too_and_automatic_classification_rebuilds(strokes):
    earlier = build_network(strokes[:-1], candidates=[0, 1, 2, 3])
    assert build_network(strokes, candidates=[0, 1, 2, 3], previous=earlier).timings_s["reused strokes"] == len(strokes) - 1
    # without named boundary strokes the automatic tolerances follow every stroke: a new one
    # changes them, and the surface is built from nothing
    earlier = build_network(strokes[:-1])
    assert "reused strokes" not in build_network(strokes, previous=earlier).timings_s


def test_other_tolerances_build_from_nothing(strokes):
    from dataclasses import replace

    earlier = build_network(strokes[:-1], boundary=4)
    later = build_network(strokes, boundary=4, tol=replace(earlier.tol, fit_mm=earlier.tol.fit_mm * 2), previous=earlier)
    assert "reused strokes" not in later.timings_s


def test_the_boundary_loop_is_kept_when_its_named_strokes_are_unchanged(strokes):
    earlier = build_network(strokes[:-1], boundary=4)
    later = build_network(strokes, boundary=4, previous=earlier)
    assert later.boundary is earlier.boundary          # not closed and faired again
    moved = [np.array(s, dtype=float) for s in strokes]
    moved[0] = moved[0] + [0.0, 0.0, 0.5]               # a boundary stroke moved: closed again
    again = build_network(moved, boundary=4, previous=earlier)
    assert again.boundary is not earlier.boundary and "reused strokes" not in again.timings_s
    _same_network(again.network, build_network(moved, boundary=4).network)


def test_a_withheld_stroke_is_rejected_with_its_reason_and_left_out():
    """build_network(withheld={i: why}): stroke i is recorded as rejected with that reason and the
    surface is the one built without it (app.build leaves out strokes whose built faces fold)."""
    strokes = read_strokes(str(Path(__file__).resolve().parents[2] / "examples" / "rough4.xyz"))
    # the boundary named: the loop and the tolerances come from its strokes alone, so a build
    # without stroke k is exactly what leaving it out must give
    full = build_network(strokes, boundary=4)
    assert [r.role for r in full.records[:4]] == ["boundary"] * 4
    inner = [r.index for r in full.records if r.role == "interior" and r.status == "accepted"]
    assert len(inner) >= 2
    for k in (inner[0], inner[-1]):
        out = build_network(strokes, boundary=4, withheld={k: "left out: a test"})
        assert out.records[k].status == "rejected" and out.records[k].reason == "left out: a test"
        without = build_network([s for i, s in enumerate(strokes) if i != k], boundary=4)
        uv = np.random.default_rng(1).uniform(0.0, 1.0, (100, 2))
        assert np.array_equal(out.network.evaluate_uv(uv), without.network.evaluate_uv(uv))
        assert [r.status for i, r in enumerate(out.records) if i != k] == [r.status for r in without.records]
