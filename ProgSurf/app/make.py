"""The make_* scripting API of ProgSurf (headless; the GUI commands call exactly these).

    import ProgSurf.app.make as ps
    strokes = ps.make_strokes_from_file("examples/clean4.xyz")
    surface = ps.make_surface(boundary=strokes[:4], interior=strokes[4:])
    ps.add_interior(surface, [ps.make_stroke_from_sketch(sketch)])
    network = ps.make_surface_network(strokes)      # every surface the strokes' loops bound

When the GUI is up, new objects get their view providers through VIEW_PROVIDER_HOOK.
Every function recomputes the document unless ``recompute=False``; none opens an undo
transaction (the caller does: one command = one transaction).
"""
from __future__ import annotations

import os
from typing import Callable, Iterable, Optional, Sequence

import FreeCAD

from ProgSurf import optional
from ProgSurf.core.errors import InvalidStrokeError, MissingPackageError, ProgSurfError

from . import extract
from .network_object import NetworkProxy, is_network
from .params import default_tolerances
from .stroke_object import StrokeProxy, is_stroke
from .surface_object import SurfaceProxy, is_surface


def _doc(doc=None):
    if isinstance(doc, str):
        doc = FreeCAD.getDocument(doc)
    return doc or FreeCAD.ActiveDocument or FreeCAD.newDocument()


VIEW_PROVIDER_HOOK: Optional[Callable] = None
"""Set by ProgSurf.gui when the GUI is up: ``hook(view_object, "stroke" | "surface" | "network")`` gives a
new object its view provider. The document layer never imports the GUI layer itself."""


def _attach_view(obj, kind: str) -> None:
    if VIEW_PROVIDER_HOOK is not None and getattr(obj, "ViewObject", None) is not None:
        VIEW_PROVIDER_HOOK(obj.ViewObject, kind)


def _new_stroke(doc, name: str):
    obj = doc.addObject("Part::FeaturePython", name)
    StrokeProxy(obj)
    _attach_view(obj, "stroke")
    return obj


def _finish(doc, recompute: bool) -> None:
    if recompute:
        doc.recompute()


def make_stroke_from_points(points, name: str = "Stroke", doc=None, recompute: bool = True):
    """A stroke that owns its points: ``points`` (n, 3) array-like in mm, n >= 2."""
    vectors = extract.array_to_vectors(points)
    if len(vectors) < 2:
        raise InvalidStrokeError(f"stroke {name!r} has {len(vectors)} point(s); "
                                 "a stroke needs at least 2")
    doc = _doc(doc)
    obj = _new_stroke(doc, name)
    obj.Points = vectors
    _finish(doc, recompute)
    return obj


def make_strokes_from_file(path: str, doc=None, recompute: bool = True, **options) -> list:
    """Import every stroke of a .xyz/.txt/.csv/.asc/.c3d file, in file order, into a group.

    ``options`` go to the C3D reader (see ProgSurf.io.read_strokes). Raises StrokeFileError, or
    MissingPackageError saying how to install the package 'c3d' into FreeCAD's Python.
    """
    from ProgSurf.io import read_strokes  # numpy reader, imported when a file is read

    try:
        arrays = read_strokes(path, **options)
    except MissingPackageError as exc:
        raise optional.for_freecad(exc, FreeCAD.getUserAppDataDir()) from None
    doc = _doc(doc)
    stem = os.path.splitext(os.path.basename(path))[0]
    group = doc.addObject("App::DocumentObjectGroup", f"Strokes_{stem}".replace("-", "_"))
    group.Label = f"Strokes {stem}"
    strokes = []
    for array in arrays:
        obj = make_stroke_from_points(array, name="Stroke", doc=doc, recompute=False)
        group.addObject(obj)
        strokes.append(obj)
    _finish(doc, recompute)
    return strokes


def make_stroke_from_sketch(sketch, chain: int = 0, recompute: bool = True):
    """A stroke that follows connected chain number ``chain`` of a Sketcher sketch."""
    return _linked_stroke(sketch, (), chain, recompute)


def make_strokes_from_sketch(sketch, recompute: bool = True) -> list:
    """One linked stroke per connected chain of the sketch's (non-construction) geometry."""
    count = len(extract.order_chains(extract.sketch_geometry_edges(sketch)))
    if count == 0:
        raise InvalidStrokeError(f"sketch {sketch.Label!r} has no curve geometry; "
                                 "draw lines, arcs or B-splines in it")
    strokes = [_linked_stroke(sketch, (), i, False) for i in range(count)]
    _finish(sketch.Document, recompute)
    return strokes


def make_stroke_from_edges(obj, subnames: Sequence[str] = (), recompute: bool = True):
    """A stroke that follows the edges ``subnames`` of ``obj`` (all edges if empty).

    The edges must form one connected chain; use make_strokes_from_edges otherwise.
    """
    chains = extract.edge_chains(obj, subnames, 2)
    if len(chains) != 1:
        raise InvalidStrokeError(f"{obj.Label!r} {list(subnames)} form {len(chains)} separate "
                                 "chains; select connected edges or use make_strokes_from_edges")
    return _linked_stroke(obj, subnames, 0, recompute)


def make_strokes_from_edges(obj, subnames: Sequence[str] = (), recompute: bool = True) -> list:
    """One linked stroke per connected chain of the edges ``subnames`` of ``obj``."""
    count = len(extract.edge_chains(obj, subnames, 2))
    strokes = [_linked_stroke(obj, subnames, i, False) for i in range(count)]
    _finish(obj.Document, recompute)
    return strokes


def _linked_stroke(source, subnames: Sequence[str], chain: int, recompute: bool):
    doc = source.Document
    obj = _new_stroke(doc, "Stroke")
    obj.Source = (source, list(subnames)) if subnames else source
    obj.ChainIndex = chain
    obj.Samples = default_tolerances().samples
    obj.Label = f"Stroke {source.Label}" + (f" {chain}" if chain else "")
    _finish(doc, recompute)
    return obj


def make_strokes_from_selection(selection: Iterable, recompute: bool = True) -> list:
    """Strokes from (object, subnames) pairs, as Gui.Selection.getSelectionEx gives them.

    A sketch selected whole gives one stroke per chain; edges give one stroke per chain; a
    selected ProgSurf stroke or surface is skipped.
    """
    strokes, doc = [], None
    for obj, subnames in selection:
        if is_stroke(obj) or is_surface(obj) or is_network(obj):
            continue
        edges = [s for s in subnames if s.startswith("Edge")]
        if obj.isDerivedFrom("Sketcher::SketchObject") and not edges:
            strokes += make_strokes_from_sketch(obj, recompute=False)
        else:
            strokes += make_strokes_from_edges(obj, edges, recompute=False)
        doc = obj.Document
    if not strokes:
        raise InvalidStrokeError("the selection holds no sketch, wire or edge; "
                                 "select sketches, Draft wires/B-splines or edges")
    _finish(doc, recompute)
    return strokes


def _check_strokes(strokes: Iterable, what: str) -> list:
    out = list(strokes or ())
    for s in out:
        if not is_stroke(s):
            raise InvalidStrokeError(f"{what}: {getattr(s, 'Label', s)!r} is not a ProgSurf "
                                     "stroke; make strokes first (Strokes from selection)")
    return out


def make_surface(boundary: Optional[Sequence] = None, interior: Sequence = (),
                 all_strokes: Optional[Sequence] = None, name: str = "Surface",
                 filter_mm: Optional[float] = None, snap_mm: Optional[float] = None,
                 fit_mm: Optional[float] = None, skin: bool = False, recompute: bool = True):
    """A progressive surface from boundary strokes (or all strokes, classified) and interior ones.

    Give ``boundary`` (its strokes in any order) or ``all_strokes`` (classified automatically,
    Qin & Wright section 2). ``interior`` strokes are applied in the given order. Tolerances
    default to the preferences (ProgSurf.app.params); 0 or None = automatic for filter/snap.
    """
    if (boundary is None) == (all_strokes is None):
        raise ProgSurfError("give either boundary strokes or all_strokes, not both or neither")
    first = _check_strokes(boundary if all_strokes is None else all_strokes, "boundary")
    inner = _check_strokes(interior, "interior")
    if not first:
        raise ProgSurfError("no boundary strokes given; a surface needs 3 or more")
    doc = first[0].Document
    obj = doc.addObject("Part::FeaturePython", name)
    SurfaceProxy(obj)
    defaults = default_tolerances()
    obj.AutoBoundary = all_strokes is not None
    obj.Boundary = first
    obj.Interior = inner
    obj.FilterThreshold = float(defaults.filter_mm if filter_mm is None else filter_mm)
    obj.SnapTolerance = float(defaults.snap_mm if snap_mm is None else snap_mm)
    obj.FitTolerance = float(defaults.fit_mm if fit_mm is None else fit_mm)
    obj.Skin = bool(skin)
    _attach_view(obj, "surface")
    _finish(doc, recompute)
    return obj


def add_interior(surface, strokes: Sequence, recompute: bool = True):
    """Append interior strokes to a surface, in the given (drawing/selection) order."""
    if not is_surface(surface):
        raise ProgSurfError(f"{getattr(surface, 'Label', surface)!r} is not a ProgSurf surface")
    new = [s for s in _check_strokes(strokes, "interior")
           if s not in surface.Interior and s not in surface.Boundary]
    if not new:
        raise ProgSurfError("no new stroke to add: the selected strokes are already in "
                            f"{surface.Label!r}")
    surface.Interior = list(surface.Interior) + new
    _finish(surface.Document, recompute)
    return surface


def make_surface_network(strokes: Optional[Sequence] = None, doc=None, name: str = "SurfaceNetwork",
                         filter_mm: Optional[float] = None, snap_mm: Optional[float] = None,
                         fit_mm: Optional[float] = None, recompute: bool = True):
    """One parametric object for the whole stroke network (issue 18): every loop of curves the
    ``strokes`` make becomes a surface, sewn into one shell per connected part.

    ``strokes`` default to every stroke of the document. Tolerances default to the preferences
    (ProgSurf.app.params); 0 or None = automatic. See ProgSurf.app.network_object.
    """
    given = None if strokes is None else list(strokes)
    doc = given[0].Document if given else _doc(doc)
    chosen = _check_strokes([o for o in doc.Objects if is_stroke(o)] if given is None else given, "network")
    if not chosen:
        raise ProgSurfError(f"document {doc.Label!r} has no strokes to make a network of; "
                            "import strokes or make them from sketches first")
    obj = doc.addObject("Part::FeaturePython", name)
    NetworkProxy(obj)
    defaults = default_tolerances()
    obj.Strokes = chosen
    obj.FilterThreshold = float(defaults.filter_mm if filter_mm is None else filter_mm)
    obj.SnapTolerance = float(defaults.snap_mm if snap_mm is None else snap_mm)
    obj.FitTolerance = float(defaults.fit_mm if fit_mm is None else fit_mm)
    _attach_view(obj, "network")
    _finish(doc, recompute)
    return obj
