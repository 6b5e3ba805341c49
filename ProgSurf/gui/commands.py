"""The workbench's commands. Each one that changes the document builds its make_* call inside
ONE named undo transaction (as Draft's draftguitools do).

Messages and file dialogs go through ProgSurf.gui.common (``tell``, ``ask_path``), whose
``ANSWERS`` / ``MESSAGES`` / ``INTERACTIVE`` hooks let a test drive them without interaction.
"""
from __future__ import annotations

import FreeCAD
import FreeCADGui

from ProgSurf.app import make
from ProgSurf.app.network_object import is_network
from ProgSurf.app.stroke_object import is_stroke
from ProgSurf.app.surface_object import is_surface
from ProgSurf.core.errors import ProgSurfError

from .common import ask_path, icon, tell

STROKE_FILTER = "Stroke files (*.xyz *.txt *.csv *.asc *.c3d *.curves);;All files (*)"
EXPORT_FILTER = "STEP (*.step *.stp);;IGES (*.iges *.igs)"


def selected() -> list:
    """(object, subnames) pairs of the selection, in selection order."""
    return [(s.Object, tuple(s.SubElementNames)) for s in FreeCADGui.Selection.getSelectionEx()]


def selected_strokes() -> list:
    return [o for o, _ in selected() if is_stroke(o)]


def target_surface(doc=None):
    """The selected surface, else the only (or last) surface of the document, else None."""
    for obj, _ in selected():
        if is_surface(obj):
            return obj
    doc = doc or FreeCAD.ActiveDocument
    surfaces = [o for o in doc.Objects if is_surface(o)] if doc else []
    return surfaces[-1] if surfaces else None


def run_in_transaction(doc, name: str, func, *args, **kwargs):
    """Run one make_* call as one undo step; on a ProgSurfError abort and tell the user."""
    doc.openTransaction(name)
    try:
        value = func(*args, **kwargs)
    except ProgSurfError as exc:
        doc.abortTransaction()
        tell(name, str(exc))
        return None
    doc.commitTransaction()
    doc.recompute()
    return value


def import_strokes(path: str, doc=None) -> list:
    """What Import strokes does with a chosen path (also called by tests)."""
    doc = doc or FreeCAD.ActiveDocument or FreeCAD.newDocument()
    # a .c3d file without the optional package 'c3d': make_* raises a MissingPackageError that
    # says how to install it into FreeCAD's Python, and run_in_transaction tells the user
    strokes = run_in_transaction(doc, "Import strokes", make.make_strokes_from_file, path, doc)
    if strokes and FreeCADGui.ActiveDocument:
        FreeCADGui.SendMsgToActiveView("ViewFit")
    return strokes or []


class _Command:
    name = ""
    menu = ""
    tip = ""
    icon_name = ""

    def GetResources(self) -> dict:
        return {"Pixmap": icon(self.icon_name), "MenuText": self.menu, "ToolTip": self.tip}


class ImportStrokes(_Command):
    name, icon_name = "ProgSurf_ImportStrokes", "ProgSurf_ImportStrokes"
    menu = "Import strokes..."
    tip = "Import 3D sketch strokes from a point-list (.xyz .asc .csv .txt) or C3D file"

    def IsActive(self) -> bool:
        return True

    def Activated(self) -> None:
        path = ask_path("open", "Import strokes", STROKE_FILTER)
        if path:
            import_strokes(path)


class StrokesFromSelection(_Command):
    name, icon_name = "ProgSurf_StrokesFromSelection", "ProgSurf_StrokesFromSelection"
    menu = "Strokes from selection"
    tip = ("Make strokes that follow the selected sketches (one per connected chain), "
           "wires, Draft B-splines or edges")

    def IsActive(self) -> bool:
        return any(not is_stroke(o) and not is_surface(o) and not is_network(o) for o, _ in selected())

    def Activated(self) -> None:
        doc = selected()[0][0].Document
        run_in_transaction(doc, "Strokes from selection", make.make_strokes_from_selection,
                           selected())


class CreateSurface(_Command):
    name, icon_name = "ProgSurf_CreateSurface", "ProgSurf_CreateSurface"
    menu = "Create progressive surface..."
    tip = ("Build a surface from boundary strokes and interior strokes (task panel: pick or "
           "confirm the boundary, tolerances, live preview)")

    def IsActive(self) -> bool:
        doc = FreeCAD.ActiveDocument
        return bool(doc) and sum(1 for o in doc.Objects if is_stroke(o)) >= 3 \
            and not FreeCADGui.Control.activeDialog()

    def Activated(self) -> None:
        from . import task_panel

        task_panel.create_surface(selected_strokes())


class CreateSurfaceNetwork(_Command):
    name, icon_name = "ProgSurf_SurfaceNetwork", "ProgSurf_SurfaceNetwork"
    menu = "Surface network (every loop of strokes)"
    tip = ("One parametric object for the whole stroke network: every loop of the selected strokes "
           "(or of all strokes) becomes a surface, sewn into shells; its panel shows which strokes "
           "bound which surface and why a stroke is unused")

    def IsActive(self) -> bool:
        doc = FreeCAD.ActiveDocument
        return bool(doc) and any(is_stroke(o) for o in doc.Objects) and not FreeCADGui.Control.activeDialog()

    def Activated(self) -> None:
        create_network(FreeCAD.ActiveDocument, selected_strokes())


def create_network(doc, strokes: list):
    """What the Surface network command does (also called by tests): a network of ``strokes`` (all
    strokes of ``doc`` when none) in one undo step, then its panel; a network that could not be
    built at all is not kept, and the user is told why."""
    from . import network_panel

    name = "Create surface network"
    doc.openTransaction(name)
    try:
        net = make.make_surface_network(strokes or None, doc=doc)
    except ProgSurfError as exc:
        doc.abortTransaction()
        tell(name, str(exc))
        return None
    if net.Shape.isNull():
        reason = net.LastError
        doc.abortTransaction()              # the strokes never changed
        doc.recompute()
        tell(name, reason)
        return None
    doc.commitTransaction()
    network_panel.show(net)
    return net


class AddInterior(_Command):
    name, icon_name = "ProgSurf_AddInterior", "ProgSurf_AddInterior"
    menu = "Add interior stroke(s)"
    tip = "Add the selected strokes to the surface as interior strokes, in selection order"

    def IsActive(self) -> bool:
        return bool(selected_strokes()) and target_surface() is not None

    def Activated(self) -> None:
        surface = target_surface()
        run_in_transaction(surface.Document, "Add interior stroke(s)", make.add_interior,
                           surface, selected_strokes())


class Export(_Command):
    name, icon_name = "ProgSurf_Export", "ProgSurf_Export"
    menu = "Export STEP/IGES..."
    tip = "Export the progressive surface (or the selected surface network) as a STEP (AP214) or IGES file"

    def IsActive(self) -> bool:
        return export_target() is not None

    def Activated(self) -> None:
        path = ask_path("save", "Export surface", EXPORT_FILTER)
        if path:
            export_surface(export_target(), path)


def export_target():
    """The selected surface network, else target_surface()."""
    for obj, _ in selected():
        if is_network(obj) and not obj.Shape.isNull():
            return obj
    return target_surface()


def export_surface(surface, path: str) -> bool:
    """What Export does with a chosen path: STEP or IGES by extension (also called by tests)."""
    from ProgSurf.app import build

    try:
        build.export_shape(surface.Shape, path)
    except (ProgSurfError, OSError) as exc:
        tell("Export surface", str(exc))
        return False
    tell("Export surface", f"{surface.Label} written to {path}", error=False)
    return True


class Analyse(_Command):
    name, icon_name = "ProgSurf_Analyse", "ProgSurf_Analyse"
    menu = "Analyse surface"
    tip = ("Colour the faces by stroke deviation, list stroke deviations and seam defects, "
           "and show the pre-image plane with the strokes' pre-images")

    def IsActive(self) -> bool:
        return target_surface() is not None

    def Activated(self) -> None:
        from . import analysis_view

        analysis_view.show(target_surface())


COMMANDS = (ImportStrokes, StrokesFromSelection, CreateSurface, CreateSurfaceNetwork, AddInterior, Export,
            Analyse)


def register() -> list[str]:
    """Add every command to FreeCADGui; return their names in toolbar order."""
    for cls in COMMANDS:
        FreeCADGui.addCommand(cls.name, cls())
    return [cls.name for cls in COMMANDS]
