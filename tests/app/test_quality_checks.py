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


def test_the_fold_check_reads_the_seams_the_report_reads():
    """Each seam's angle in the fold check is the report's angle_max_deg of that seam (the same
    samples, away from its ends): with 9 samples the check missed a tuck 3 % of a seam wide beside
    a 3-sided face's apex, which the report read at 84 deg and the verdict called ok. Measured on
    the project's own sketches of a 3-sided patch and of a pentagon."""
    import numpy as np

    from benchmarks.sketches import make_config
    from ProgSurf.app.build import build_and_measure
    from ProgSurf.cad import analysis as cad_analysis
    from ProgSurf.core.types import Tolerances

    compared = 0
    for config, seed in (("octant", 3), ("cyl_penta", 1)):
        sketch = make_config(config, seed)
        out = build_and_measure(sketch.strokes, None, Tolerances())
        report = {s.edge_id: s.angle_max_deg for s in out.analysis.seams}
        checked = cad_analysis._inner_seam_angles(out.shell.faces)
        assert {eid for eid, _, _ in checked} <= set(report)
        for eid, _, angle in checked:
            assert angle == report[eid]
            compared += 1
        worst = max((a for _, _, a in checked), default=0.0)
        assert (worst > cad_analysis.FOLD_SEAM_DEG) == any(f.kind == "seam" for f in out.analysis.folds)
        assert np.isclose(out.analysis.seam_angle_deg, max(report.values(), default=0.0))
    assert compared > 10


def test_a_face_over_the_fit_tolerance_has_its_curves_fitted_tighter(monkeypatch):
    """Two of the project's own sketches (a cylinder panel, an octant) each have a face 9-12 %
    further from its Coons sub-patch than the fit tolerance, their curves fitted at half of it
    (cad.edges.EDGE_FIT_FRACTION) as usual; app.build.tighten_fit fits that face's curves within it
    of their polylines' chords too, and every face is then within the tolerance itself, not only
    within its allowance."""
    from benchmarks.sketches import make_config
    from ProgSurf.app import build
    from ProgSurf.core.types import Tolerances

    for config, seed in (("cyl_bump", 5000), ("octant", 8001)):
        strokes = make_config(config, seed).strokes
        loose = build.build_and_measure(strokes, None, Tolerances())
        with monkeypatch.context() as m:
            m.setattr(build, "TIGHTEN_ROUNDS", 0)
            plain = build.build_and_measure(strokes, None, Tolerances())
        fit = plain.analysis.fit_tolerance_mm
        assert plain.analysis.fit_deviation_mm > fit and not plain.shell.tight
        assert loose.analysis.fit_deviation_mm <= fit, (config, loose.analysis.fit_deviation_mm / fit)
        assert loose.shell.tight and set(loose.shell.tight.values()) <= {1.0, 0.5}
        # the tightened faces are the same surface: the strokes' deviation hardly moves
        assert abs(max(loose.analysis.stroke_deviation_mm) - max(plain.analysis.stroke_deviation_mm)) < 2 * fit
