"""The quality checks of one build (app.build.Analysis), read by the verdict, the report, the
document and the face colours: which faces fail, and the problems computed once."""
from __future__ import annotations

from ProgSurf.app.build import Analysis, quality_section
from ProgSurf.core.folds import Fold


def analysis(**kw) -> Analysis:
    base = dict(seam_gap_mm=0.0, seam_angle_deg=0.0, stroke_deviation_mm=(), fit_deviation_mm=0.0,
                seams=(), region_of_face=(1, 2, 3, 4, 5), fit_tolerance_mm=0.01)
    return Analysis(**dict(base, **kw))


def test_failing_regions_are_the_faces_the_problems_name():
    """A creased seam fails both its faces, a turned-over face itself, a face over its fit
    allowance itself; a face within its (larger) allowance passes."""
    a = analysis(folds=(Fold("seam", 70.0, (2, 3), edge=9), Fold("face", 120.0, (5,))),
                 fit_deviation_by_region={1: 0.015, 4: 0.02, 5: 0.001},
                 fit_allowance_by_region={1: 0.02, 4: 0.012})
    assert a.failing_regions == {2, 3, 4, 5}
    assert set(a.fit_over) == {4}
    assert len(a.problems) == 3 and "region 4" in a.problems[-1]
    q = quality_section(a)
    named = {r for f in q["folds"] for r in f["regions"]} | {int(k) for k in q["faces_over_fit_tolerance"]}
    assert named == a.failing_regions and not q["ok"]


def test_a_sound_build_has_no_failing_face():
    a = analysis(fit_deviation_by_region={1: 0.009, 2: 0.0})
    assert a.failing_regions == frozenset() and a.problems == () and a.verdict().startswith("quality: ok")


def test_problems_are_computed_once():
    """The verdict, the report and the document each read them: one list, not remade per read
    (and not to be changed by a reader)."""
    a = analysis(folds=(Fold("face", 100.0, (1,)),))
    assert a.problems is a.problems and a.fit_over is a.fit_over
    assert isinstance(a.problems, tuple)
