"""Issue 16 (1): no fold from an accepted stroke, in the built faces too.

The core checks each stroke against its Coons sub-patches (core.folds); the B-spline faces follow
those only within the fit, so a crease can still show in them. app.build then leaves out the last
stroke that made a failing face, builds again without it and keeps the build with the fewest
problems (app.build._withhold_folding).

data/cyl_penta_crease.xyz is a sketch drawn by ../shared/tools/sketchgen (family seed base 9000,
sk_cyl_penta_6: a cylinder panel with a bump, 5 sides, one open corner, 8 interior strokes): with
every stroke the core accepts, two built faces meet at a 64 deg crease the sketch does not have.
"""
from __future__ import annotations

import unittest
from pathlib import Path

import numpy as np

from ProgSurf.app import build
from ProgSurf.cad import shell as cad_shell
from ProgSurf.core import pipeline
from ProgSurf.core.types import Tolerances
from ProgSurf.io import read_strokes

SKETCH = Path(__file__).resolve().parent / "data" / "cyl_penta_crease.xyz"


class WithholdTest(unittest.TestCase):
    def test_a_stroke_whose_built_faces_crease_is_left_out_with_its_reason(self):
        strokes = read_strokes(str(SKETCH))
        core = pipeline.build_network(strokes)
        plain = build.measure(cad_shell.build_shell(core.network, core.tol), core, len(strokes))
        creases = [f for f in plain.folds if f.kind == "seam"]
        assert creases and max(f.angle_deg for f in creases) > 60.0, plain.problems

        out = build.build_and_measure(strokes, None, Tolerances())
        assert out.analysis.problems == (), out.analysis.problems
        assert out.analysis.verdict().startswith("quality: ok")
        left = [r for r in out.result.records if r.reason.startswith("with it")]
        assert left, [r.reason for r in out.result.records]
        for rec in left:
            assert rec.status == "rejected" and rec.role == "interior"
            assert core.records[rec.index].status == "accepted"
            assert "crease" in rec.reason or "turn over" in rec.reason or "fit tolerance" in rec.reason
            assert "region" not in rec.reason      # regions of a build that was not kept mean nothing
        # the surface is the one built without those strokes, whose records say so
        again = pipeline.build_network(strokes, withheld={r.index: r.reason for r in left})
        uv = np.random.default_rng(0).uniform(0.0, 1.0, (200, 2))
        assert np.array_equal(again.network.evaluate_uv(uv), out.result.network.evaluate_uv(uv))
        assert [r.status for r in again.records] == [r.status for r in out.result.records]

    def test_g1_leaves_out_the_strokes_g0_does(self):
        """G1 rounds the crease off, but the stroke that made it is left out all the same: G0 and
        G1 are compared on the same strokes (issue 16 (5)); kept, it raised the deviation from the
        truth from 0.19 to 0.53 % of the diagonal (RMS) on this sketch."""
        strokes = read_strokes(str(SKETCH))
        g0 = build.build_and_measure(strokes, None, Tolerances())
        g1 = build.build_and_measure(strokes, None, Tolerances(), continuity="G1")
        assert g1.shell.continuity == "G1" and g1.analysis.problems == ()
        assert [(r.status, r.reason) for r in g1.result.records] == [(r.status, r.reason) for r in g0.result.records]

    def test_a_sound_build_leaves_no_stroke_out(self):
        strokes = read_strokes(str(Path(__file__).resolve().parents[2] / "examples" / "rough4.xyz"))
        out = build.build_and_measure(strokes, None, Tolerances())
        assert out.analysis.problems == ()
        assert not [r for r in out.result.records if r.reason.startswith("with it")]
        core = pipeline.build_network(strokes)
        assert [r.status for r in core.records] == [r.status for r in out.result.records]
