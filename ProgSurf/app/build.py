"""Build and measure the progressive surface: the one orchestration of the command line and the document.

    strokes -> core.pipeline.build_network   the patch network (Qin & Wright section 3)
            -> cad.build_shell               B-spline faces sewn into one shell
            -> cad.analysis                  seam gaps and angles, fit and stroke deviations
            [-> cad.export.skin_surface]     the exchange surface (section 3.3), when asked

:func:`build_and_measure` runs these steps for both callers: the Surface feature on recompute
(app.surface_object) and the command line (cli.run_build, which then exports the files, writes the
report made by :func:`build_report` and prints its summary). The Analyse and Export commands call
:func:`face_values` and :func:`export_shape`, the surface's view provider :func:`failing_faces`.

One sample rule for every caller:

- stroke deviation: every point of each accepted stroke (a largest distance is a maximum: samples
  could only miss it);
- fit deviation: an n x n grid of each face's parameter square, n = FIT_GRID;
- seams: cad.analysis.SEAM_SAMPLES points along every edge shared by two faces.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from functools import cached_property
from types import MappingProxyType
from typing import TYPE_CHECKING, Mapping, Optional, Sequence

import numpy as np

from ProgSurf.cad import analysis as cad_analysis
from ProgSurf.cad import export as cad_export
from ProgSurf.cad import sewing as cad_sewing
from ProgSurf.cad import shell as cad_shell
from ProgSurf.core import pipeline
from ProgSurf.core.errors import FitError, ProgSurfError
from ProgSurf.core.types import Tolerances

if TYPE_CHECKING:
    import Part

FIT_GRID = 21
"""Samples per side of the grid on which a face is compared with its Coons sub-patch."""

@dataclass(frozen=True)
class ReportMeasures:
    """What only the build report holds (measured when build_and_measure is asked for a report).

    g1_seams : cad.analysis.G1SeamStat per interior seam of the built surface
    g0_seams : the same on the G0 faces a G1 surface was made from; () for a G0 surface
    shell    : the sewn shape's own watertightness through its pcurves (cad.analysis.shell_seam_gaps:
               shared_edges, free_edges, seam_gap_max_mm), and valid, area_mm2
    """

    g1_seams: tuple
    g0_seams: tuple
    shell: dict


@dataclass(frozen=True)
class Analysis:
    """Quality numbers of one build.

    seam_gap_mm        : largest gap between neighbouring faces along their shared edges
    seam_angle_deg     : largest angle between their normals (G1 defect of the G0 network)
    stroke_deviation_mm: per input stroke, the largest distance of its points from the surface;
                         -1 if not measured (rejected, or without points)
    fit_deviation_mm   : largest distance of a face from its Coons sub-patch
    seams              : the cad layer's SeamStat per shared network edge
    region_of_face     : region id of each face of the Shape, in Shape.Faces order
    faces              : the cad layer's FaceInfo per region (surfaces, for projections)
    fit_deviation_by_region : region id -> largest distance of its face from its Coons sub-patch
    report             : ReportMeasures, or None when no report was asked for
    folds              : cad.analysis.Fold per fold of the built faces (seams creased, faces turned over)
    fit_tolerance_mm   : the fit tolerance the faces were built to
    fit_allowance_by_region : region id -> how far its face may lie from its Coons sub-patch: the
                         fit tolerance plus the chord sag of its sides' polylines, which the curve
                         fit is allowed (cad.analysis.fit_allowance); empty: the fit tolerance
    """

    seam_gap_mm: float
    seam_angle_deg: float
    stroke_deviation_mm: tuple
    fit_deviation_mm: float
    seams: tuple
    region_of_face: tuple
    faces: tuple = ()
    fit_deviation_by_region: Mapping = field(default_factory=dict)
    report: Optional[ReportMeasures] = None
    folds: tuple = ()
    fit_tolerance_mm: float = 0.0
    fit_allowance_by_region: Mapping = field(default_factory=dict)

    def fit_allowance(self, rid: int) -> float:
        """How far region rid's face may lie from its Coons sub-patch (fit_allowance_by_region)."""
        return self.fit_allowance_by_region.get(rid, self.fit_tolerance_mm)

    @cached_property
    def fit_over(self) -> Mapping:
        """region id -> fit deviation of the faces that lie further from their Coons sub-patch
        than the fit tolerance allows them (the fit tolerance plus their sides' chord sag).
        Computed once (read-only: the Analysis does not change)."""
        return MappingProxyType({rid: d for rid, d in self.fit_deviation_by_region.items()
                                 if d > self.fit_allowance(rid)})

    @cached_property
    def problems(self) -> tuple[str, ...]:
        """What fails the quality checks, one short phrase each; empty when the build is sound.
        Computed once (the verdict, the report and the document each read it)."""
        out = [f.describe() for f in self.folds]
        over = self.fit_over
        if over:
            rid = max(over, key=over.get)
            out.append(f"{len(over)} face(s) lie further from their Coons sub-patch than the fit tolerance "
                       f"{self.fit_tolerance_mm:.3g} mm and their sides' chord sag allow (region {rid}: "
                       f"{over[rid]:.3g} mm, allowed {self.fit_allowance(rid):.3g} mm)")
        return tuple(out)

    @cached_property
    def failing_regions(self) -> frozenset:
        """Region ids of the faces a quality check fails on: both faces of a creased seam, a face
        that turns over, a face over its fit allowance (the faces the problems name)."""
        return frozenset(r for f in self.folds for r in f.regions) | frozenset(self.fit_over)

    def verdict(self, extra: Sequence[str] = ()) -> str:
        """One line: "quality: ok" or "quality: WARNING ..." naming the first problems (and `extra`
        ones the caller measured, e.g. the skin's deviation)."""
        problems = list(self.problems) + list(extra)
        if not problems:
            return "quality: ok (no fold; every face within the fit tolerance)"
        more = f" (and {len(problems) - 2} more)" if len(problems) > 2 else ""
        return f"quality: WARNING {len(problems)} problem(s): " + "; ".join(problems[:2]) + more

    @property
    def stroke_deviation_by_index(self) -> dict:
        """stroke index -> largest distance of its points, for the measured strokes only."""
        return {i: d for i, d in enumerate(self.stroke_deviation_mm) if d >= 0.0}


@dataclass(frozen=True)
class Outcome:
    """What one build produced.

    result       : the pipeline's BuildResult (network, stroke records, resolved tolerances)
    shape        : the document's Shape: the sewn shell, or with skin the one skinned face
    analysis     : its Analysis (always measured on the shell of faces)
    status_lines : "index role status reason" per stroke, in input order
    shell        : the cad ShellResult; pass it as `previous` to the next build_and_measure to
                   reuse what is unchanged
    skin         : with skin, (the skinned Part.BSplineSurface, its largest distance from the
                   network in mm); else None
    timings_s    : seconds per step: the pipeline's stages, "fit" (the shell), "analysis" and,
                   with skin, "skin"
    """

    result: object
    shape: "Part.Shape"
    analysis: Analysis
    status_lines: list
    shell: object = None
    skin: Optional[tuple] = None
    timings_s: dict = field(default_factory=dict)


def status_line(record) -> str:
    """"index role status reason" for the StrokeStatus property."""
    return f"{record.index} {record.role} {record.status} {record.reason or ''}".rstrip()


def nearest_on_faces(infos: Sequence, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distance of each point (m, 3) to the shell and the index in ``infos`` of the nearest face
    (cad.analysis.surface_distances face by face: grid guess + clamped Gauss-Newton, Eq. 2)."""
    table = np.array([cad_analysis.surface_distances([(i.derived, (0.0, 1.0, 0.0, 1.0))], points)
                      for i in infos]).reshape(len(infos), -1)
    return table.min(axis=0), table.argmin(axis=0)


def _region_of_faces(shape: "Part.Shape", infos: Sequence) -> tuple:
    """Match the (sewn) Shape's faces to the cad FaceInfos: sewing keeps each face's surface, so
    a point of it tells them apart (the nearest, for a shape whose surfaces were rebuilt)."""
    points = np.array([cad_sewing.probe_point(i.face) for i in infos]).reshape(-1, 3)
    out = []
    for face in shape.Faces:
        p = np.array(cad_sewing.probe_point(face))
        out.append(int(infos[int(np.argmin(np.linalg.norm(points - p, axis=1)))].region_id))
    return tuple(out)


def _measured_strokes(result) -> list:
    """The stroke records whose deviation is measured: accepted, with points."""
    return [rec for rec in result.records
            if rec.status == "accepted" and rec.points is not None and len(rec.points)]


def _report_measures(shell, network) -> ReportMeasures:
    """G1 seam statistics (and G0 beside G1), and the sewn shape's own checks, for the report."""
    g1 = tuple(cad_analysis.g1_seam_stats(shell, network))
    g0 = (tuple(cad_analysis.g1_seam_stats(cad_analysis.g0_view(shell), network))
          if shell.continuity == "G1" else ())
    shape = shell.shape
    info = cad_analysis.shell_seam_gaps(shape)
    info.update({"valid": bool(shape.isValid()), "area_mm2": float(shape.Area)})
    return ReportMeasures(g1_seams=g1, g0_seams=g0, shell=info)


def measure(shell, result, n_strokes: int, report: bool = False) -> Analysis:
    """Seam gap and angle (cad.analysis.seam_stats), fit and stroke deviations of a ShellResult
    built from `result`'s network, by the module's sample rule; with report, ReportMeasures too."""
    # (at cad.analysis.SEAM_SAMPLES: the samples the fold check reads, kept with the faces)
    seams = tuple(cad_analysis.seam_stats(shell))
    # the fit is that of the exact Coons faces: in G1 mode of the G0 faces the G1 faces were made
    # from (G1 then moves a face by at most cad.g1.OFFSET_FRACTION of the diagonal, on purpose)
    fitted = cad_analysis.g0_view(shell)
    fit = cad_analysis.fit_deviation(fitted, result.network, n=FIT_GRID)
    deviation = [-1.0] * n_strokes
    kept = _measured_strokes(result)
    if kept:      # every stroke's points in one call: one projection pass per face
        d = cad_analysis.point_distances(shell, np.vstack([np.asarray(rec.points) for rec in kept]))
        for rec, part in zip(kept, np.split(d, np.cumsum([len(rec.points) for rec in kept])[:-1])):
            deviation[rec.index] = float(part.max())
    return Analysis(
        seam_gap_mm=max((s.gap_max_mm for s in seams), default=0.0),
        seam_angle_deg=max((s.angle_max_deg for s in seams), default=0.0),
        stroke_deviation_mm=tuple(deviation),
        fit_deviation_mm=max(fit.values(), default=0.0),
        seams=seams,
        region_of_face=_region_of_faces(shell.shape, shell.faces),
        faces=tuple(shell.faces),
        fit_deviation_by_region=fit,
        report=_report_measures(shell, result.network) if report else None,
        folds=tuple(cad_analysis.folds(shell)),
        fit_tolerance_mm=float(result.tol.fit_mm),
        fit_allowance_by_region=cad_analysis.fit_allowance(fitted, result.network, result.tol.fit_mm))


WITHHOLD_ROUNDS = 4
"""How many strokes a build may leave out, one at a time, because its built faces fold with them."""


def _shell_of(result, continuity: str, previous):
    shell = cad_shell.build_shell(result.network, result.tol, continuity=continuity, previous=previous)
    if shell.shape.isNull() or not shell.shape.Faces:
        raise FitError("the cad adapter returned no face; check the boundary strokes")
    return shell


def _failing(shell, analysis: Analysis) -> tuple[tuple, frozenset]:
    """(folds, failing regions) a stroke may be left out for: those of the built faces, and in G1
    mode those of the G0 faces the G1 faces were made from too, so that G0 and G1 leave out the
    same strokes (issue 16 (5) compares them on the same strokes; G1 rounding off a crease the G0
    faces have is not a reason to keep the stroke that made it)."""
    folds = tuple(analysis.folds) + tuple(shell.g0_folds)        # g0_folds: () in G0 mode
    return folds, frozenset(r for f in folds for r in f.regions) | frozenset(analysis.fit_over)


def _culprit(result, folds: tuple, failing: frozenset) -> Optional[tuple[int, str]]:
    """The last accepted interior stroke that made a failing face, and what fails there in words
    for its record (the region numbers of a build that is not kept would mean nothing to the user);
    None when no stroke made one (the base surface itself fails)."""
    made = {rid: rec.index for rec in result.records if rec.status == "accepted" and rec.role == "interior"
            for rid in rec.regions_created}
    mine = [made[rid] for rid in failing if rid in made]
    if not mine:
        return None
    index = max(mine)
    own = {rid for rid, i in made.items() if i == index} & failing
    for fold in sorted(folds, key=lambda f: -f.angle_deg):
        if set(fold.regions) & own:
            what = (f"the built surface would crease: two of its faces meet at {fold.angle_deg:.0f} deg"
                    if fold.kind == "seam" else
                    f"a built face would turn over: its normal turns {fold.angle_deg:.0f} deg inside it")
            return index, what
    return index, "a built face would lie further from its Coons patch than the fit tolerance allows"


def _withhold_folding(arrays, boundary, tol, candidates, continuity, result, shell, analysis):
    """Issue 16 (1): an accepted stroke must not fold the surface. The core checks each stroke
    against its Coons sub-patches; the B-spline faces follow those only within the fit, and a crease
    or a tuck can still show in them (sketchgen famK cyl_penta_6: a crease of 64 deg where the
    sub-patches meet at 49 deg). Then the last stroke that made a failing face (_failing) is left
    out and the network built again without it, and again, for up to WITHHOLD_ROUNDS strokes
    (leaving one out can let a stroke in that the core refused before). The first build that passes
    every check is kept: the surface is the one without those strokes, whose records say why. When
    none does, the build as it was is kept, with its warning: leaving strokes out is no cure when
    what fails is the base surface itself (CASSIE 07-2-2 as one surface: its loop's Coons patch
    turns over with no interior stroke at all)."""
    def scored(result, shell, analysis):
        folds, failing = _failing(shell, analysis)
        return result, shell, analysis, folds, failing, len(folds) + (1 if analysis.fit_over else 0)

    first = current = scored(result, shell, analysis)
    withheld: dict[int, str] = {}
    for _ in range(WITHHOLD_ROUNDS):
        result, shell, analysis, folds, failing, count = current
        found = _culprit(result, folds, failing) if count else None
        if found is None:
            break
        index, problem = found
        withheld = {**withheld, index: (f"with it {problem}; redraw it closer to the surface, or further from "
                                        "the curves it nearly touches")}
        again = pipeline.build_network(arrays, boundary=boundary, tol=tol, candidates=candidates, withheld=withheld)
        shell_again = _shell_of(again, continuity, shell)
        current = scored(again, shell_again, measure(shell_again, again, len(arrays)))
    return (current if current[-1] == 0 else first)[:3]


TIGHTEN_ROUNDS = 2
"""Rounds of tighten_fit: the first fits the curves around a face still over the fit tolerance
within their tolerance of the polyline's chords too (cad.edges.fit_edges(tight=): hug), the second
at half that tolerance."""


def tighten_fit(result, shell, analysis: Analysis, continuity: str, n_strokes: int) -> tuple:
    """(shell, analysis) with every face within the fit tolerance of its Coons sub-patch where
    TIGHTEN_ROUNDS allow: the curves around a face that lies further from its sub-patch than
    tol.fit_mm are fitted again, and the faces on them are rebuilt (the others are reused). Each
    curve is fitted within half the tolerance at its polyline's vertices, and a smooth curve may
    leave the chords between them by their sag: a face bounded by two sagging sides ended up past
    the tolerance (8 of 90 sketchgen sketches by 6-25 %, seed base 67000; 3 of 36 of our own)
    though every curve kept its own. Fitted within the tolerance of the chords too, they are all
    within it (a tighter tolerance at the vertices alone rang between them: 1.24 x). The round with
    the smallest largest deviation and no more folds is kept; its shell keeps the factors for the
    next build (cad.build_shell(tight=))."""
    edges = result.network.edges()
    best = (shell, analysis)
    for _ in range(TIGHTEN_ROUNDS):
        over = {rid for rid, d in analysis.fit_deviation_by_region.items() if d > analysis.fit_tolerance_mm}
        if not over:
            break
        curves = {edges[p.edge_id].curve_id for info in cad_analysis.g0_view(shell).faces
                  if info.region_id in over for pieces in info.sides for p in pieces}
        tight = dict(shell.tight)    # first round: the same tolerance, hugging; then half of it
        tight.update({cid: 0.5 * tight[cid] if cid in tight else 1.0 for cid in curves})
        shell = cad_shell.build_shell(result.network, result.tol, continuity=continuity, previous=shell,
                                      tight=tight)
        analysis = measure(shell, result, n_strokes)
        # (a tighter fit can ring between the vertices of a sagging polyline, and a curve that
        # hugs its polyline's corners could crease a face: the closest round without a fold more)
        if (analysis.fit_deviation_mm < best[1].fit_deviation_mm
                and len(analysis.folds) <= len(best[1].folds)):
            best = (shell, analysis)
    return best


def build_and_measure(strokes: Sequence[np.ndarray], boundary, tol: Tolerances, *, continuity: str = "G0",
                      skin: bool = False, previous=None, candidates=None, previous_result=None,
                      report: bool = False) -> Outcome:
    """Run the pipeline and the cad adapter on stroke point lists (each (n, 3)) and measure the result.

    boundary: None (classify automatically), or the count of leading boundary strokes.
    candidates: with boundary None, the indices of the strokes the classification chooses from
    (the others are interior strokes); None = all.
    previous: the `shell` of an earlier Outcome: curves and faces whose inputs are unchanged are
    reused (cad.build_shell), so a recompute after one stroke changed refits only what it touched.
    previous_result: the `result` of an earlier Outcome: when the strokes only grew by interior
    strokes, only the new ones are added to (a copy of) its network (pipeline.build_network).
    skin: also skin the exchange surface across every patch (the Outcome's shape is then that face).
    report: also measure what only the build report holds (ReportMeasures; about as long again).
    Raises ProgSurfError (bad input, boundary not closed, fit failure) or Part.OCCError.
    """
    if continuity not in cad_shell.CONTINUITIES:
        raise ProgSurfError(f"Continuity {continuity!r} is not one of {', '.join(cad_shell.CONTINUITIES)}")
    arrays = [np.asarray(s, dtype=float) for s in strokes]
    result = pipeline.build_network(arrays, boundary=boundary, tol=tol, candidates=candidates,
                                    previous=previous_result)
    timings = dict(result.timings_s)
    clock = time.perf_counter()
    shell = _shell_of(result, continuity, previous)
    timings["fit"] = time.perf_counter() - clock
    clock = time.perf_counter()
    analysis = measure(shell, result, len(strokes))
    timings["analysis"] = time.perf_counter() - clock
    clock = time.perf_counter()
    result, shell, analysis = _withhold_folding(arrays, boundary, tol, candidates, continuity, result, shell, analysis)
    timings["withhold"] = time.perf_counter() - clock
    clock = time.perf_counter()
    shell, analysis = tighten_fit(result, shell, analysis, continuity, len(strokes))
    timings["tighten"] = time.perf_counter() - clock
    if report:
        analysis = replace(analysis, report=_report_measures(shell, result.network))
    shape = shell.shape
    skinned = None
    if skin:   # the exchange surface (section 3.3): one face skinned across every patch
        clock = time.perf_counter()
        skinned = cad_export.skin_surface(result.network, result.tol.fit_mm)
        timings["skin"] = time.perf_counter() - clock
        shape = skinned[0].toShape()
    return Outcome(result=result, shape=shape, analysis=analysis,
                   status_lines=[status_line(r) for r in sorted(result.records,
                                                                 key=lambda r: r.index)],
                   shell=shell, skin=skinned, timings_s=timings)


def build_report(outcome: Outcome, *, inputs: Sequence[str], outputs: Mapping, timings_s: Mapping) -> dict:
    """The build report (io.report.make_report) of an Outcome measured with report=True.

    inputs: the stroke files; outputs: kind -> path of every file written; timings_s: the caller's
    seconds per step (the Outcome's own included)."""
    from ProgSurf.io.report import continuity_section, make_report

    if outcome.analysis.report is None:
        raise ProgSurfError("the build was measured without report=True; it has no report figures")
    shell, result, analysis, measures = outcome.shell, outcome.result, outcome.analysis, outcome.analysis.report
    extra = {}
    if outcome.skin is not None:
        surface, deviation = outcome.skin
        extra["skin"] = {"u_poles": surface.NbUPoles, "v_poles": surface.NbVPoles,
                         "deviation_max_mm": deviation}
    if shell.continuity == "G1":     # what G1 left G0 to stay within its bound of the G0 faces
        from ProgSurf.cad.g1 import bound_summary

        extra["g1_bound"] = bound_summary(shell, result.network)
    return make_report(
        faces=len(shell.shape.Faces), records=result.records,
        seams=[{"edge": s.edge_id, "regions": [s.region_a, s.region_b], "gap_max_mm": s.gap_max_mm,
                "angle_max_deg": s.angle_max_deg, "angle_median_deg": s.angle_median_deg}
               for s in analysis.seams],
        stroke_deviation_mm=analysis.stroke_deviation_by_index,
        fit_deviation_mm=analysis.fit_deviation_by_region,
        poles_per_face=[{"region": f.region_id, "u_poles": f.poles[0], "v_poles": f.poles[1],
                         "u_degree": f.poles[2], "v_degree": f.poles[3], "triangle": f.triangle}
                        for f in shell.faces],
        timings_s=timings_s, inputs=list(inputs), outputs=outputs,
        tolerances={"filter_mm": result.tol.filter_mm, "snap_mm": result.tol.snap_mm,
                    "fit_mm": result.tol.fit_mm},
        shell=measures.shell, extra=dict(extra, quality=quality_section(analysis, skin_problems(outcome)),
                                         **continuity_section(
            shell.continuity, measures.g1_seams, measures.g0_seams, shell.timings_s.get("g1"))))


def skin_problems(outcome: Outcome) -> list:
    """The skinned exchange surface further from the patches than the fit tolerance, as a problem
    phrase for the verdict (SKIN_LADDER keeps the finest skin when none is within it)."""
    if outcome.skin is None or outcome.skin[1] <= outcome.analysis.fit_tolerance_mm:
        return []
    return [f"the skinned exchange surface lies up to {outcome.skin[1]:.3g} mm from the patches "
            f"(fit tolerance {outcome.analysis.fit_tolerance_mm:.3g} mm)"]


def fold_record(fold) -> dict:
    """A fold (core.folds.Fold) as the reports list it."""
    return {"kind": fold.kind, "angle_deg": fold.angle_deg, "regions": list(fold.regions), "edge": fold.edge}


def quality_section(analysis: Analysis, extra: Sequence[str] = ()) -> dict:
    """The report's quality checks: folds, faces over the fit tolerance, `extra` problems the
    caller measured, and the verdict line."""
    return {"ok": not analysis.problems and not extra, "verdict": analysis.verdict(extra),
            "folds": [fold_record(f) for f in analysis.folds],
            "fit_tolerance_mm": analysis.fit_tolerance_mm,
            "fit_allowance_max_mm": max(analysis.fit_allowance_by_region.values(),
                                        default=analysis.fit_tolerance_mm),
            "faces_over_fit_tolerance": {str(k): v for k, v in analysis.fit_over.items()}}


def failing_faces(surface) -> Optional[list]:
    """Per face of the surface's last build, in Shape.Faces order: whether a quality check fails on
    it (Analysis.failing_regions: a fold, or over its fit allowance). None when the surface has no
    build in memory that matches its Shape."""
    analysis = getattr(surface.Proxy, "analysis", None)
    if analysis is None or len(analysis.region_of_face) != len(surface.Shape.Faces):
        return None
    failing = analysis.failing_regions
    return [rid in failing for rid in analysis.region_of_face]


def face_values(surface, mode: str) -> Optional[list]:
    """Per-face values of the surface's last build for colouring, in Shape.Faces order.

    mode "Stroke deviation": largest distance of an accepted interior stroke point whose nearest
    face it is (0 if none; every point, as the stroke deviation); "Seam defect": largest normal
    angle along the face's seams (degrees).
    None when the surface has no build in memory (recompute it first).
    """
    proxy = surface.Proxy
    result, analysis = getattr(proxy, "result", None), getattr(proxy, "analysis", None)
    shape = surface.Shape
    if result is None or analysis is None or len(analysis.region_of_face) != len(shape.Faces):
        return None
    if mode == "Seam defect":
        by_region: dict = {}
        for s in analysis.seams:
            for rid in (s.region_a, s.region_b):
                by_region[rid] = max(by_region.get(rid, 0.0), s.angle_max_deg)
        return [by_region.get(rid, 0.0) for rid in analysis.region_of_face]
    by_region: dict = {}
    infos = analysis.faces
    for rec in _measured_strokes(result):   # boundary strokes are trimmed at the corners: not deviations
        if rec.role != "interior":
            continue
        dist, which = nearest_on_faces(infos, np.asarray(rec.points))
        for d, k in zip(dist, which):
            rid = infos[k].region_id
            by_region[rid] = max(by_region.get(rid, 0.0), float(d))
    return [by_region.get(rid, 0.0) for rid in analysis.region_of_face]


def export_shape(shape: "Part.Shape", path: str) -> None:
    """Write STEP (.step/.stp, AP214) or IGES (.iges/.igs) by extension (cad.export)."""
    if shape.isNull():
        raise ProgSurfError("the surface has no shape yet; recompute it before exporting")
    cad_export.export_shape(shape, path)
