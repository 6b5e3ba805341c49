"""Incremental shell update (cad.build_shell(..., previous=)): after one more stroke only the curves
and faces it touched are fitted and built again, and the result is the same shell as a full build."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ProgSurf import cad
from ProgSurf.core.pipeline import build
from ProgSurf.core.progressive import add_stroke
from ProgSurf.io import read_strokes

ROOT = Path(__file__).resolve().parents[2]


def poles(info) -> np.ndarray:
    return np.array([[tuple(p) for p in row] for row in info.surface.getPoles()])


class Step:
    def __init__(self, network, tol):
        self.network, self.tol = network, tol


@pytest.fixture(scope="module")
def steps():
    """clean4, then clean4 with one more short stroke drawn on its surface near a corner: a user
    adding a stroke to a surface that already has several patches."""
    result = build(read_strokes(ROOT / "examples" / "clean4.xyz"))
    after = result.network.clone()
    uv = np.linspace([0.06, 0.08], [0.2, 0.16], 25)
    stroke = np.asarray(after.evaluate_uv(uv)) + [0.0, 0.0, 0.3]
    record = add_stroke(after, stroke, 99, result.tol, result.tol.snap_mm)
    assert record.status == "accepted", record.reason
    return Step(result.network, result.tol), Step(after, result.tol)


def test_unchanged_curves_and_faces_are_reused_and_the_shell_is_the_same(steps):
    before, after = steps
    first = cad.build_shell(before.network, before.tol)
    assert first.reused == {"curves": (0, len({e.curve_id for e in before.network.edges().values()})),
                            "faces": (0, len(first.faces))}
    full = cad.build_shell(after.network, after.tol)
    incr = cad.build_shell(after.network, after.tol, previous=first)
    reused_curves, fitted = incr.reused["curves"]
    reused_faces, built = incr.reused["faces"]
    assert reused_curves > 0 and fitted > 0           # the new stroke and what it crossed
    assert reused_faces > 0 and built > 0
    assert reused_faces + built == len(full.faces)
    # the same faces, pole for pole, as building from nothing
    assert [f.region_id for f in incr.faces] == [f.region_id for f in full.faces]
    for a, b in zip(incr.faces, full.faces):
        assert np.array_equal(poles(a), poles(b))
    assert incr.shape.isValid() and incr.shape.ShapeType == "Shell"
    assert incr.shape.Area == pytest.approx(full.shape.Area, rel=1e-12)


def test_a_rebuild_of_the_same_network_reuses_everything(steps):
    _, after = steps
    first = cad.build_shell(after.network, after.tol)
    again = cad.build_shell(after.network, after.tol, previous=first)
    assert again.reused["curves"][1] == 0 and again.reused["faces"][1] == 0
    assert again.shape.Area == pytest.approx(first.shape.Area, rel=1e-12)


def test_a_changed_tolerance_fits_everything_again(steps):
    _, after = steps
    first = cad.build_shell(after.network, after.tol)
    from dataclasses import replace

    other = cad.build_shell(after.network, replace(after.tol, fit_mm=after.tol.fit_mm * 2), previous=first)
    assert other.reused["curves"][0] == 0 and other.reused["faces"][0] == 0


def test_g1_faces_far_from_the_new_stroke_are_reused_and_the_same():
    """A 30-region network grown with random strokes over a saddle (the benchmark's), then one more
    stroke: the G1 faces it does not reach (through a changed face, curve or node) are reused."""
    from benchmarks.latency import grow
    from benchmarks.surfaces import BENCH_TOL, SURFACES, random_stroke

    nets, _ = grow([30])
    net, tol = nets[30], BENCH_TOL
    rng = np.random.default_rng(3)
    later = net.clone()
    while add_stroke(later, random_stroke(SURFACES["saddle"], rng), 999, tol, tol.snap_mm).status != "accepted":
        later = net.clone()
    before, after = Step(net, tol), Step(later, tol)
    first = cad.build_shell(before.network, before.tol, continuity="G1")
    full = cad.build_shell(after.network, after.tol, continuity="G1")
    incr = cad.build_shell(after.network, after.tol, continuity="G1", previous=first)
    g1_reused = sum(1 for k in incr.cache if k[0] == "g1" and k in first.cache)
    assert 0 < g1_reused < len(incr.faces)
    assert len([k for k in incr.cache if k[0] == "g1"]) == len(incr.faces)   # nothing stale is kept
    for a, b in zip(incr.faces, full.faces):
        assert np.array_equal(poles(a), poles(b))
    assert incr.shape.isValid() and incr.shape.Area == pytest.approx(full.shape.Area, rel=1e-12)
