"""One recompute of the progressive surface: strokes -> pipeline -> cad shell -> analysis.

Glue between ProgSurf.core.pipeline (Qin & Wright section 3, the patch network) and ProgSurf.cad
(B-spline faces, analysis, export). The Surface feature calls :func:`build_surface`; the Analyse
and Export commands call :func:`face_values` and :func:`export_shape`.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Sequence

import numpy as np

import FreeCAD  # noqa: F401  (FreeCAD before Part)
import Part

from ProgSurf.cad import analysis as cad_analysis
from ProgSurf.cad import export as cad_export
from ProgSurf.cad import shell as cad_shell
from ProgSurf.core import pipeline
from ProgSurf.core.errors import FitError, ProgSurfError
from ProgSurf.core.types import Tolerances

DEVIATION_SAMPLES = 41
"""Points per accepted stroke at which its distance from the surface is measured."""


@dataclass(frozen=True)
class Analysis:
    """Quality numbers of one build.

    seam_gap_mm        : largest gap between neighbouring faces along their shared edges
    seam_angle_deg     : largest angle between their normals (G1 defect of the G0 network)
    stroke_deviation_mm: per input stroke, its largest distance from the surface; -1 if rejected
    fit_deviation_mm   : largest distance of a face from its Coons sub-patch
    seams              : the cad layer's SeamStat per shared network edge
    region_of_face     : region id of each face of the Shape, in Shape.Faces order
    faces              : the cad layer's FaceInfo per region (surfaces, for projections)
    """

    seam_gap_mm: float
    seam_angle_deg: float
    stroke_deviation_mm: tuple
    fit_deviation_mm: float
    seams: tuple
    region_of_face: tuple
    faces: tuple = ()


@dataclass(frozen=True)
class Outcome:
    """What one recompute produced: the pipeline's BuildResult, the Shape and its analysis."""

    result: object
    shape: Part.Shape
    analysis: Analysis
    status_lines: list
    shell: object = None
    """the cad ShellResult; pass it as `previous` to the next build_surface to reuse what is unchanged"""


def status_line(record) -> str:
    """"index role status reason" for the StrokeStatus property."""
    return f"{record.index} {record.role} {record.status} {record.reason or ''}".rstrip()


def _sample(points: np.ndarray, count: int) -> np.ndarray:
    idx = np.unique(np.linspace(0, len(points) - 1, min(count, len(points))).round().astype(int))
    return points[idx]


def nearest_on_faces(infos: Sequence, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distance of each point (m, 3) to the shell and the index in ``infos`` of the nearest face
    (cad.analysis.surface_distances face by face: grid guess + clamped Gauss-Newton, Eq. 2)."""
    table = np.array([cad_analysis.surface_distances([(i.derived, (0.0, 1.0, 0.0, 1.0))], points)
                      for i in infos]).reshape(len(infos), -1)
    return table.min(axis=0), table.argmin(axis=0)


def _region_of_faces(shape: Part.Shape, infos: Sequence) -> tuple:
    """Match the (sewn) Shape's faces to the cad FaceInfos: sewing keeps each face's surface, so
    a point of it tells them apart (the nearest, for a shape whose surfaces were rebuilt)."""
    points = np.array([cad_shell.probe_point(i.face) for i in infos]).reshape(-1, 3)
    out = []
    for face in shape.Faces:
        p = np.array(cad_shell.probe_point(face))
        out.append(int(infos[int(np.argmin(np.linalg.norm(points - p, axis=1)))].region_id))
    return tuple(out)


def analyse(shape: Part.Shape, shell, result, n_strokes: int) -> Analysis:
    """Seam gap and angle (cad.analysis.seam_stats), fit and stroke deviations."""
    seams = tuple(cad_analysis.seam_stats(shell))
    fit = cad_analysis.fit_deviation(shell, result.network, n=9)
    deviation = [-1.0] * n_strokes
    kept = [rec for rec in result.records
            if rec.status == "accepted" and rec.points is not None and len(rec.points)]
    if kept:      # every stroke's samples in one call: one projection pass per face
        samples = [_sample(np.asarray(rec.points), DEVIATION_SAMPLES) for rec in kept]
        d = cad_analysis.point_distances(shell, np.vstack(samples))
        for rec, part in zip(kept, np.split(d, np.cumsum([len(x) for x in samples])[:-1])):
            deviation[rec.index] = float(part.max())
    return Analysis(
        seam_gap_mm=max((s.gap_max_mm for s in seams), default=0.0),
        seam_angle_deg=max((s.angle_max_deg for s in seams), default=0.0),
        stroke_deviation_mm=tuple(deviation),
        fit_deviation_mm=max(fit.values(), default=0.0),
        seams=seams,
        region_of_face=_region_of_faces(shape, shell.faces),
        faces=tuple(shell.faces))


def build_surface(strokes: Sequence[np.ndarray], boundary, tol: Tolerances, skin: bool = False,
                  continuity: str = "G0", previous=None, candidates=None, previous_result=None) -> Outcome:
    """Run the pipeline and the cad adapter on stroke point lists (each (n, 3)).

    previous: the `shell` of an earlier Outcome: curves and faces whose inputs are unchanged are
    reused (cad.build_shell), so a recompute after one stroke changed refits only what it touched.
    previous_result: the `result` of an earlier Outcome: when the strokes only grew by interior
    strokes, only the new ones are added to (a copy of) its network (pipeline.build).

    boundary: None (classify automatically), or the count of leading boundary strokes.
    candidates: with boundary None, the indices of the strokes the classification chooses from
    (the others are interior strokes); None = all.
    Raises ProgSurfError (bad input, boundary not closed, fit failure) or Part.OCCError.
    """
    if continuity not in cad_shell.CONTINUITIES:
        raise ProgSurfError(f"Continuity {continuity!r} is not one of {', '.join(cad_shell.CONTINUITIES)}")
    result = pipeline.build([np.asarray(s, dtype=float) for s in strokes], boundary=boundary,
                            tol=tol, candidates=candidates, previous=previous_result)
    shell = cad_shell.build_shell(result.network, tol, continuity=continuity, previous=previous)
    shape = shell.shape
    if shape.isNull() or not shape.Faces:
        raise FitError("the cad adapter returned no face; check the boundary strokes")
    analysis = analyse(shape, shell, result, len(strokes))
    if skin:   # the exchange surface (section 3.3): one face skinned across every patch
        shape = cad_export.skin_surface(result.network, tol.fit_mm)[0].toShape()
    return Outcome(result=result, shape=shape, analysis=analysis,
                   status_lines=[status_line(r) for r in sorted(result.records,
                                                                 key=lambda r: r.index)],
                   shell=shell)


def face_values(surface, mode: str) -> Optional[list]:
    """Per-face values of the surface's last build for colouring, in Shape.Faces order.

    mode "Stroke deviation": largest distance of an accepted interior stroke point whose nearest
    face it is (0 if none); "Seam defect": largest normal angle along the face's seams (degrees).
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
    for rec in result.records:   # boundary strokes are trimmed at the corners: not deviations
        if rec.role != "interior" or rec.status != "accepted" or rec.points is None:
            continue
        dist, which = nearest_on_faces(infos, _sample(np.asarray(rec.points), DEVIATION_SAMPLES))
        for d, k in zip(dist, which):
            rid = infos[k].region_id
            by_region[rid] = max(by_region.get(rid, 0.0), float(d))
    return [by_region.get(rid, 0.0) for rid in analysis.region_of_face]


def export_shape(shape: Part.Shape, path: str) -> None:
    """Write STEP (.step/.stp, AP214) or IGES (.iges/.igs) by extension (cad.export)."""
    if shape.isNull():
        raise ProgSurfError("the surface has no shape yet; recompute it before exporting")
    cad_export.export_shape(shape, path)
