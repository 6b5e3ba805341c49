"""The progressive Surface feature (Qin & Wright, section 3: base Coons patch + interior strokes).

Inputs are links to Stroke features: ``Boundary`` (the boundary strokes, or with
``AutoBoundary`` every stroke to classify, paper section 2 "identify boundary curves") and
``Interior`` (the interior strokes in drawing order: later strokes win, step 4-10).
``execute`` gathers the strokes' points and runs ``ProgSurf.app.build.build_and_measure``, the
orchestration the command line runs too: the patch network (``ProgSurf.core.pipeline``), a shell of
B-spline faces (``ProgSurf.cad``) and its quality numbers, which fill the Result properties.

A rejected stroke never breaks the surface: it is marked on the stroke and in ``StrokeStatus``
and reported as a warning. If the build fails (a ProgSurfError or an OCC failure), the error is
reported on the Report view and in ``LastError`` and the previous valid Shape is kept; a
surface whose first build fails has no shape and says so (``failure_message``).
"""
from __future__ import annotations

from dataclasses import dataclass

import FreeCAD
import Part

from ProgSurf.core.errors import ProgSurfError
from ProgSurf.core.off_surface import moved_note
from ProgSurf.core.types import Tolerances

from . import stroke_object
from .params import default_tolerances
from .proxy import PROP_OUTPUT, FeatureProxy, add_property

TYPE = "ProgSurf::Surface"
CONTINUITY = ["G0", "G1"]
"""G0: the paper's Coons sub-patches; G1: tangent-continuous seams (issue 9, ProgSurf.cad.g1)."""

RESULTS = (
    ("App::PropertyInteger", "PatchCount", "Number of sub-patches (faces) of the surface"),
    ("App::PropertyStringList", "StrokeStatus", "One line per stroke: index role status reason"),
    ("App::PropertyFloat", "SeamGap", "Largest gap between neighbouring faces along seams (mm)"),
    ("App::PropertyFloat", "SeamAngleMax",
     "Largest angle between normals of neighbouring faces along seams (deg, G1 defect)"),
    ("App::PropertyFloatList", "StrokeDeviation",
     "Largest distance of each stroke from the surface (mm), in stroke order; -1 if rejected"),
    ("App::PropertyFloat", "StrokeDeviationMax", "Largest deviation of an accepted stroke (mm)"),
    ("App::PropertyFloat", "FitDeviation", "Largest distance of a face from its Coons sub-patch"),
    ("App::PropertyString", "LastError", "Why the last recompute failed (empty when it worked)"),
    ("App::PropertyString", "Quality",
     "The last build's quality checks (folds, fit tolerance): 'quality: ok' or a warning saying why"),
)


class SurfaceProxy(FeatureProxy):
    """Proxy of a Part::FeaturePython progressive surface. Saved state: a tiny JSON-safe dict.

    The last BuildResult and analysis are kept on the proxy for the Analyse view only
    (transient: a reopened document rebuilds them on recompute).
    """

    PROXY_TYPE = TYPE

    def __init__(self, obj) -> None:
        self.forget_build()
        super().__init__(obj)

    def forget_build(self) -> None:
        """Drop the transient last build (a reopened document rebuilds it on recompute)."""
        self.result = None
        self.analysis = None
        self.shell = None

    def setup(self, obj) -> None:
        """Create missing properties (new objects and documents saved by older versions)."""
        super().setup(obj)
        add_property(obj, "App::PropertyLinkList", "Boundary", "Strokes",
                     "Boundary strokes; with AutoBoundary: all strokes to classify")
        add_property(obj, "App::PropertyBool", "AutoBoundary", "Strokes",
                     "Classify the Boundary list automatically into boundary and interior strokes")
        add_property(obj, "App::PropertyLinkList", "Interior", "Strokes",
                     "Interior strokes in drawing order (later strokes win)")
        defaults = default_tolerances()
        for name, doc, value in (
                ("FilterThreshold", "Stroke filter distance in mm (0 = automatic)",
                 defaults.filter_mm),
                ("SnapTolerance", "Snap distance of stroke ends to boundaries in mm (0 = auto)",
                 defaults.snap_mm),
                ("FitTolerance", "How far a B-spline face may lie from its Coons sub-patch in mm (0 = auto)",
                 defaults.fit_mm)):
            if name not in obj.PropertiesList:
                obj.addProperty("App::PropertyFloat", name, "Tolerances", doc)
                setattr(obj, name, value)
        add_property(obj, "App::PropertyBool", "Skin", "Surface", "Exchange surface: one "
                     "B-spline skinned through u-sections (paper section 3.3)")
        if "Continuity" not in obj.PropertiesList:
            obj.addProperty("App::PropertyEnumeration", "Continuity", "Surface",
                            "Continuity across seams: G0 Coons sub-patches, G1 tangent-continuous seams "
                            "(kinked strokes and outer corners stay sharp)")
            obj.Continuity = CONTINUITY
        elif list(obj.getEnumerationsOfProperty("Continuity")) != CONTINUITY:
            # a document saved when only G0 existed: offer the new modes, keep the chosen one
            current = obj.Continuity if obj.Continuity in CONTINUITY else CONTINUITY[0]
            obj.Continuity = CONTINUITY
            obj.Continuity = current
        for kind, name, doc in RESULTS:
            add_property(obj, kind, name, "Result", doc, PROP_OUTPUT, read_only=True)

    # -- recompute -------------------------------------------------------------------------
    def strokes(self, obj) -> list:
        """All input strokes in pipeline order: Boundary list, then Interior list."""
        return input_strokes(obj)

    def tolerances(self, obj) -> Tolerances:
        """The object's tolerances as the core's one Tolerances value (0 -> automatic)."""
        return Tolerances(filter_mm=obj.FilterThreshold or None,
                          snap_mm=obj.SnapTolerance or None,
                          fit_mm=obj.FitTolerance or None)

    def execute(self, obj) -> None:
        from ProgSurf.app import build  # heavy: pipeline + cad, loaded on first recompute

        strokes = self.strokes(obj)
        boundary = None if obj.AutoBoundary else len(obj.Boundary)
        # automatic classification chooses among the Boundary list only: strokes the designer
        # added as interior strokes stay interior (an off-surface one is rejected, not taken
        # for a boundary)
        candidates = list(range(len(obj.Boundary))) if obj.AutoBoundary and obj.Interior else None
        try:
            outcome = build.build_and_measure(
                [stroke_object.stroke_points(s) for s in strokes], boundary,
                self.tolerances(obj), skin=obj.Skin, continuity=obj.Continuity,
                previous=getattr(self, "shell", None), candidates=candidates,
                previous_result=getattr(self, "result", None))
        except (ProgSurfError, Part.OCCError) as exc:
            obj.LastError = failure_message(obj, exc)
            FreeCAD.Console.PrintError(f"ProgSurf: {obj.LastError}\n")
            return
        self.result, self.analysis = outcome.result, outcome.analysis
        self.shell = outcome.shell          # reused by the next recompute (not saved)
        for line, stroke in zip(outcome.status_lines, strokes):
            if " rejected" in line:
                FreeCAD.Console.PrintWarning(f"ProgSurf: {obj.Label}: stroke {stroke.Label} "
                                             f"rejected: {line.split(' ', 3)[-1]}\n")
        for record in outcome.result.records:
            stroke_object.set_result(strokes[record.index], record.role, record.status,
                                     record.reason or "")
            moved = moved_note(record.reason or "") if record.status == "accepted" else None
            if moved:
                FreeCAD.Console.PrintMessage(f"ProgSurf: {obj.Label}: stroke {strokes[record.index].Label} "
                                             f"accepted; {moved}\n")
        release_unused_strokes(obj.Document)
        obj.Shape = outcome.shape
        obj.PatchCount = len(outcome.result.network.regions())
        obj.StrokeStatus = outcome.status_lines
        obj.SeamGap = outcome.analysis.seam_gap_mm
        obj.SeamAngleMax = outcome.analysis.seam_angle_deg
        obj.StrokeDeviation = list(outcome.analysis.stroke_deviation_mm)
        obj.StrokeDeviationMax = max([d for d in obj.StrokeDeviation if d >= 0] or [0.0])
        obj.FitDeviation = outcome.analysis.fit_deviation_mm
        obj.Quality = outcome.analysis.verdict()
        if outcome.analysis.problems:
            FreeCAD.Console.PrintWarning(f"ProgSurf: {obj.Label}: {obj.Quality}\n")
        obj.LastError = ""

    def memory(self) -> tuple:
        """The last build kept in memory (result, analysis, shell): what the next recompute
        continues from. The task panel takes it when it opens and gives it back on Cancel."""
        return self.result, self.analysis, self.shell

    def restore_memory(self, memory: tuple) -> None:
        """Continue from an earlier build again (see memory): a recompute with that build's
        inputs then reuses all of it, so its shape comes back exactly, not refitted."""
        self.result, self.analysis, self.shell = memory

    def onDocumentRestored(self, obj) -> None:
        self.forget_build()
        super().onDocumentRestored(obj)

    def __setstate__(self, state) -> None:
        self.forget_build()


def has_shape(obj) -> bool:
    """True once a build of the surface succeeded (in this session or before it was saved)."""
    return not obj.Shape.isNull()


def failure_message(obj, error: Exception) -> str:
    """``LastError`` of a failed build: why, and what the surface shows now (the previous shape,
    or nothing when it never built). The strokes are never changed by a failed build."""
    if has_shape(obj):
        return f"{obj.Label}: {error}; the previous shape is kept"
    return (f"{obj.Label}: no surface could be built: {error}; the strokes are unchanged "
            "(change the boundary strokes or the tolerances)")


def is_surface(obj) -> bool:
    """True for a ProgSurf progressive surface feature."""
    return bool(obj is not None and getattr(obj, "Type", "") == TYPE)


def input_strokes(obj) -> list:
    """A surface's input strokes in pipeline order: Boundary list, then Interior list."""
    return list(obj.Boundary) + list(obj.Interior)


@dataclass(frozen=True)
class StrokeState:
    """What the last recompute did with one input stroke: one parsed ``StrokeStatus`` line.

    stroke : the Stroke feature (Boundary list, then Interior list, as the pipeline saw them)
    role   : "boundary" or "interior" (with AutoBoundary: as classified, paper section 2)
    status : "accepted" or "rejected"
    reason : why it was rejected, or a short note of what was done ("" if none)
    """

    stroke: object
    role: str
    status: str
    reason: str


def stroke_states(obj) -> list[StrokeState]:
    """The surface's ``StrokeStatus`` lines paired with its input strokes, in input order.

    Interior strokes come in drawing order (the order the pipeline adds them, step 4-10).
    After a failed recompute (``LastError`` set) the lines still describe the last successful
    build, whose stroke list may differ from the current one: the result is then empty.
    """
    if obj.LastError:
        return []
    strokes = input_strokes(obj)
    states = []
    for line in obj.StrokeStatus:
        index, role, status, *reason = line.split(" ", 3)
        if int(index) < len(strokes):
            states.append(StrokeState(strokes[int(index)], role, status,
                                      reason[0] if reason else ""))
    return states


def release_unused_strokes(doc) -> None:
    """Clear Role/Status of strokes that no surface uses any more (removed, or undone)."""
    for stroke in doc.Objects:
        if not stroke_object.is_stroke(stroke) or not stroke.Status:
            continue
        users = [o for o in stroke.InList if is_surface(o)
                 and (stroke in o.Boundary or stroke in o.Interior)]
        if not users:
            stroke_object.clear_result(stroke)
