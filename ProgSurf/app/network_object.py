"""The SurfaceNetwork feature: one parametric object for the whole stroke network (issue 18).

``Strokes`` links the user's Stroke features. ``execute`` gathers their points and runs
``ProgSurf.app.objects.build_object_and_measure``, the orchestration of ``build --surfaces all``:
the stroke network, its loops of curves, one progressive surface per loop, sewn into one shell per
connected part. Its Shape is that shell (or a compound of shells); moving a stroke recomputes it.

Every stroke is accounted for (Result properties, in ``Strokes`` order): the surfaces it bounds, those
it is an interior stroke of, or why it is unused; per surface, the strokes of its sides and its
interior strokes; per face of the Shape, the surface it belongs to. ``stroke_accounts`` and
``surface_strokes`` read them back as Python values.

A failed build (a ProgSurfError or an OCC failure) is reported on the Report view and in
``LastError``; the previous Shape and Result properties are kept, and the strokes are never written.
"""
from __future__ import annotations

from dataclasses import dataclass

import FreeCAD
import Part

from ProgSurf.core.errors import ProgSurfError
from ProgSurf.core.objects import side_strokes
from ProgSurf.core.types import Tolerances

from . import stroke_object
from .params import default_tolerances
from .proxy import PROP_OUTPUT, FeatureProxy, add_property
from .surface_object import CONTINUITY

TYPE = "ProgSurf::Network"

RESULTS = (
    ("App::PropertyInteger", "SurfaceCount", "Number of surfaces built (one per loop of curves)"),
    ("App::PropertyInteger", "ShellCount", "Number of sewn shells (one per connected part)"),
    ("App::PropertyInteger", "ClosedShells", "How many of the shells are closed (bound a solid)"),
    ("App::PropertyStringList", "StrokeAccounting",
     "One line per stroke (Strokes order): label: boundary of / interior to surface(s), or unused: why"),
    ("App::PropertyStringList", "StrokeReasons",
     "Per stroke (Strokes order): why it is unused, or a note (merged, hook removed); empty if none"),
    ("App::PropertyStringList", "SurfaceBoundaries",
     "Per surface: the indices (into Strokes) of the strokes its sides lie on, space separated"),
    ("App::PropertyStringList", "SurfaceInteriors",
     "Per surface: the indices (into Strokes) of its accepted interior strokes, space separated"),
    ("App::PropertyIntegerList", "FaceSurfaces", "Per face of the Shape: the surface it belongs to"),
    ("App::PropertyStringList", "FailedLoops",
     "Loops of curves that made no surface: their strokes' indices and why"),
    ("App::PropertyStringList", "DividedLoops",
     "Loops whose one patch folded, divided by a curve across them into two surfaces: their strokes' "
     "indices, the two surfaces, how far the patch turned and its parts"),
    ("App::PropertyStringList", "OpenedCorners",
     "Corners whose two sides left them the wrong way round their loop, just by their node, opened "
     "(the sides' ends eased): the two strokes' indices and the surface(s) at that corner"),
    ("App::PropertyFloat", "SeamGap", "Largest gap between two faces of a shell (mm)"),
    ("App::PropertyFloat", "FitDeviation", "Largest distance of a surface from its Coons sub-patches (mm)"),
    ("App::PropertyString", "LastError", "Why the last recompute failed (empty when it worked)"),
    ("App::PropertyString", "Quality", "The last build's quality checks: 'quality: ok' or a warning"),
    ("App::PropertyStringList", "SurfaceQuality",
     "Per surface: what its quality checks found (folds inside it, creases with other surfaces); empty if none"),
    ("App::PropertyIntegerList", "SurfaceRefilled",
     "Per surface: how many of its faces were refilled over the plane of their loop, because their Coons "
     "patch turned over (their sides kept)"),
)


class NetworkProxy(FeatureProxy):
    """Proxy of a Part::FeaturePython surface network. Saved state: a tiny JSON-safe dict.

    The last ObjectOutcome is kept on the proxy (transient) for ``network_report``, and so is a
    core.objects.BuildCache of the last builds: a recompute after one stroke moved rebuilds only the
    surfaces whose strokes changed (the outcome's ``build.rebuilt``)."""

    PROXY_TYPE = TYPE

    def __init__(self, obj) -> None:
        self.outcome = None
        self.cache = None
        super().__init__(obj)

    def setup(self, obj) -> None:
        """Create missing properties (new objects and documents saved by older versions)."""
        super().setup(obj)
        add_property(obj, "App::PropertyLinkList", "Strokes", "Strokes",
                     "The strokes of the network: every loop of curves they make becomes a surface")
        defaults = default_tolerances()
        for name, doc, value in (
                ("FilterThreshold", "Stroke filter distance in mm (0 = automatic)", defaults.filter_mm),
                ("SnapTolerance", "Distance within which strokes meet, in mm (0 = automatic)",
                 defaults.snap_mm),
                ("FitTolerance", "How far a B-spline face may lie from its Coons sub-patch in mm "
                 "(0 = automatic)", defaults.fit_mm)):
            if name not in obj.PropertiesList:
                obj.addProperty("App::PropertyFloat", name, "Tolerances", doc)
                setattr(obj, name, value)
        if "Continuity" not in obj.PropertiesList:
            obj.addProperty("App::PropertyEnumeration", "Continuity", "Surface",
                            "Continuity across the seams: G0 Coons sub-patches, G1 tangent-continuous "
                            "seams inside each surface and across the curves two surfaces share smoothly")
            obj.Continuity = CONTINUITY
        for kind, name, doc in RESULTS:
            add_property(obj, kind, name, "Result", doc, PROP_OUTPUT, read_only=True)

    def tolerances(self, obj) -> Tolerances:
        """The object's tolerances as the core's one Tolerances value (0 -> automatic; execute
        resolves automatic ones rounded to core.objects.STEADY_DIGITS significant digits)."""
        return Tolerances(filter_mm=obj.FilterThreshold or None, snap_mm=obj.SnapTolerance or None,
                          fit_mm=obj.FitTolerance or None)

    def execute(self, obj) -> None:
        from ProgSurf.app.objects import build_object_and_measure  # heavy: loaded on first recompute
        from ProgSurf.core.objects import BuildCache, steady_tolerances

        strokes = list(obj.Strokes)
        active = FreeCAD.ActiveDocument
        try:
            bad = [s.Label for s in strokes if not stroke_object.is_stroke(s)]
            if bad:
                raise ProgSurfError(f"{bad[0]!r} is not a ProgSurf stroke; link strokes only "
                                    "(make strokes first: Strokes from selection)")
            if not strokes:
                raise ProgSurfError("no strokes linked; a network needs strokes that meet around "
                                    "each surface")
            if getattr(self, "cache", None) is None:
                self.cache = BuildCache()
            points = [stroke_object.stroke_points(s) for s in strokes]
            # automatic tolerances rounded, so that an edit keeps the surfaces it does not touch
            outcome = build_object_and_measure(points, steady_tolerances(points, self.tolerances(obj)),
                                               continuity=obj.Continuity, cache=self.cache)
        except (ProgSurfError, Part.OCCError) as exc:
            obj.LastError = failure_message(obj, exc)
            FreeCAD.Console.PrintError(f"ProgSurf: {obj.LastError}\n")
            return
        finally:
            # the sewing runs in a temporary document (cad.object_shell.sew_at); closing it leaves
            # no active document: give the user's back
            if active is not None and FreeCAD.ActiveDocument is not active:
                FreeCAD.setActiveDocument(active.Name)
        self.outcome = outcome
        write_results(obj, outcome)
        FreeCAD.Console.PrintMessage(f"ProgSurf: {obj.Label}: {summary(obj)}; {len(outcome.build.rebuilt)} "
                                     f"of {len(outcome.build.surfaces)} surface(s) built, the others kept\n")
        for line in obj.StrokeAccounting:
            if ": unused: " in line:
                FreeCAD.Console.PrintWarning(f"ProgSurf: {obj.Label}: {line}\n")
        if outcome.problems:
            FreeCAD.Console.PrintWarning(f"ProgSurf: {obj.Label}: {obj.Quality}\n")

    def onDocumentRestored(self, obj) -> None:
        self.outcome = None
        self.cache = None
        super().onDocumentRestored(obj)

    def __setstate__(self, state) -> None:
        self.outcome = None
        self.cache = None


def write_results(obj, outcome) -> None:
    """The Result properties and the Shape from a successful build (module docstring)."""
    build, graph = outcome.build, outcome.build.graph
    strokes = list(obj.Strokes)

    def indices(edge_ids) -> str:
        return " ".join(str(i) for i in sorted(set(side_strokes(graph, edge_ids))))

    def users(k: int, field: str) -> str:
        return " ".join(str(r.index) for r in build.roles if k in getattr(r, field))

    obj.Shape = outcome.shape
    obj.SurfaceCount = len(build.surfaces)
    obj.ShellCount = len(outcome.shells)
    obj.ClosedShells = sum(bool(s["closed"]) for s in outcome.shells)
    obj.StrokeAccounting = [f"{strokes[r.index].Label}: {r.describe()}" for r in build.roles]
    obj.StrokeReasons = [r.reason for r in build.roles]
    # from the strokes' roles, so that both views agree (a rejected interior piece is in neither)
    obj.SurfaceBoundaries = [users(k, "boundary_of") for k in range(len(build.surfaces))]
    obj.SurfaceInteriors = [users(k, "interior_to") for k in range(len(build.surfaces))]
    obj.FaceSurfaces = list(outcome.model.face_owner)
    obj.FailedLoops = [f"{indices(c.edge_ids)}: {reason}" for c, reason in build.failed]
    obj.DividedLoops = [f"{' '.join(str(i) for i in sorted(set(loop)))}: divided by a curve across it into surfaces "
                        f"{' '.join(str(k) for k in build.surfaces_along(curve))} (one patch "
                        f"turned {whole:.0f} deg inside it, its parts {worse:.0f} deg at most)"
                        for curve, loop, whole, worse in build.divisions]
    obj.OpenedCorners = [f"{indices(pair)}: corner of surface(s) {' '.join(map(str, build.surfaces_at(pair)))} "
                         f"opened (its sides left it the wrong way round the loop, just by their node)"
                         for pair in build.opened]
    obj.SeamGap = max((s["seam_gap_max_mm"] for s in outcome.shells), default=0.0)
    obj.FitDeviation = max(outcome.fit_deviation_mm, default=0.0)
    obj.Quality = outcome.verdict()
    obj.SurfaceQuality = outcome.surface_problems()
    obj.SurfaceRefilled = outcome.refilled_faces
    obj.LastError = ""


def failure_message(obj, error: Exception) -> str:
    """``LastError`` of a failed build: why, and what the object shows now."""
    if not obj.Shape.isNull():
        return f"{obj.Label}: {error}; the previous shape is kept and the strokes are unchanged"
    return (f"{obj.Label}: no surface could be built: {error}; the strokes are unchanged "
            "(move strokes so that they meet around each surface, or change the tolerances)")


def summary(obj) -> str:
    """One line: surfaces, faces, shells, strokes used."""
    used = sum(1 for r in stroke_accounts(obj) if r.used)
    return (f"{obj.SurfaceCount} surface(s), {len(obj.FaceSurfaces)} face(s) in {obj.ShellCount} "
            f"shell(s) ({obj.ClosedShells} closed); strokes: {used} of {len(obj.StrokeReasons)} used")


def is_network(obj) -> bool:
    """True for a ProgSurf surface network feature."""
    return bool(obj is not None and getattr(obj, "Type", "") == TYPE)


@dataclass(frozen=True)
class StrokeAccount:
    """What the last successful build did with one stroke.

    stroke      : the Stroke feature            index : its place in ``Strokes``
    boundary_of : surface indices it bounds     interior_to : surface indices it is interior to
    reason      : why it is unused, or a note ("" if none)
    """

    stroke: object
    index: int
    boundary_of: tuple
    interior_to: tuple
    reason: str

    @property
    def used(self) -> bool:
        return bool(self.boundary_of or self.interior_to)


def _index_lists(lines) -> list:
    return [tuple(int(i) for i in line.split()) for line in lines]


def surface_strokes(obj, surface: int) -> tuple:
    """(boundary strokes, interior strokes) of surface number ``surface``, as Stroke features."""
    strokes = list(obj.Strokes)
    sides = _index_lists(obj.SurfaceBoundaries)[surface]
    inner = _index_lists(obj.SurfaceInteriors)[surface]
    return [strokes[i] for i in sides], [strokes[i] for i in inner]


def stroke_accounts(obj) -> list:
    """StrokeAccount per stroke of the last successful build, in ``Strokes`` order. After a failed
    recompute that changed the stroke list, the last build's accounting no longer matches it: the
    result is then empty."""
    strokes = list(obj.Strokes)
    if len(obj.StrokeReasons) != len(strokes):
        return []
    bounds = _index_lists(obj.SurfaceBoundaries)
    inner = _index_lists(obj.SurfaceInteriors)
    return [StrokeAccount(s, i, tuple(k for k, b in enumerate(bounds) if i in b),
                          tuple(k for k, b in enumerate(inner) if i in b), obj.StrokeReasons[i])
            for i, s in enumerate(strokes)]


def network_report(obj) -> dict:
    """The whole-object build report (app.objects.object_report) of the last build in this session;
    {} when there is none (a reopened document has one after its first recompute)."""
    outcome = getattr(obj.Proxy, "outcome", None)
    if outcome is None:
        return {}
    from ProgSurf.app.objects import object_report

    return object_report(outcome, inputs=[s.Label for s in obj.Strokes])
