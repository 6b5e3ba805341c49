"""View providers of the Stroke, Surface and SurfaceNetwork features.

Stroke colour tells its outcome in the surface that uses it: boundary (blue), interior accepted
(green), rejected (red), unused (grey). The surface can colour its faces by an analysis value
(``ColourBy``, see face_colours), recomputed whenever its Shape changes. A surface network colours
each surface's faces apart (face_colours.surface_palette, the legend of its task panel), and dims all
but the surfaces its panel highlights.
"""
from __future__ import annotations

from .common import icon
from .face_colours import COLOUR_BY, colour_faces, network_face_colours

COLOURS = {
    ("boundary", "accepted"): (0.10, 0.30, 0.90),
    ("interior", "accepted"): (0.05, 0.65, 0.15),
    "rejected": (0.90, 0.10, 0.10),
    "unused": (0.45, 0.45, 0.45),
}


def stroke_colour(role: str, status: str) -> tuple:
    """RGB of a stroke from its Role and Status (set by the surface that uses it)."""
    if status == "rejected":
        return COLOURS["rejected"]
    return COLOURS.get((role, status), COLOURS["unused"])


def attach(vobj, kind: str) -> None:
    """Give a new object's ViewObject the ProgSurf view provider of ``kind``."""
    if kind == "stroke":
        ViewProviderStroke(vobj)
    elif kind == "surface":
        ViewProviderSurface(vobj)
    elif kind == "network":
        ViewProviderNetwork(vobj)
    else:
        raise ValueError(f"unknown view provider kind {kind!r}; use 'stroke', 'surface' or 'network'")


class _Base:
    icon_name = "ProgSurf"

    def __init__(self, vobj) -> None:
        vobj.Proxy = self
        self.Object = vobj.Object
        self.ViewObject = vobj

    def attach(self, vobj) -> None:
        self.ViewObject = vobj
        self.Object = vobj.Object

    def getIcon(self) -> str:
        return icon(self.icon_name)

    def __getstate__(self):
        return {"kind": self.icon_name}

    def __setstate__(self, state) -> None:
        return None

    def dumps(self):
        return self.__getstate__()

    def loads(self, state) -> None:
        return self.__setstate__(state)


class ViewProviderStroke(_Base):
    """A stroke: its polyline and its points, coloured by role and status."""

    icon_name = "ProgSurf_Stroke"

    def __init__(self, vobj) -> None:
        super().__init__(vobj)
        vobj.LineWidth = 3.0
        vobj.PointSize = 4.0
        self.colour(vobj)

    def updateData(self, obj, prop: str) -> None:
        if prop in ("Role", "Status", "Shape") and getattr(obj, "ViewObject", None):
            self.colour(obj.ViewObject)

    def colour(self, vobj) -> None:
        obj = vobj.Object
        rgb = stroke_colour(getattr(obj, "Role", ""), getattr(obj, "Status", ""))
        for prop in ("LineColor", "PointColor"):
            if tuple(round(c, 3) for c in getattr(vobj, prop)[:3]) != \
                    tuple(round(c, 3) for c in rgb):
                setattr(vobj, prop, rgb)

    def onChanged(self, vobj, prop: str) -> None:
        return None


class _Faces(_Base):
    """A feature whose view provider colours its faces itself and opens its panel on a double-click:
    subclasses define apply_colours(vobj) and open_panel(obj)."""

    recolour_on: tuple = ("Shape",)
    """The data properties whose change colours the faces again."""

    def updateData(self, obj, prop: str) -> None:
        if prop in self.recolour_on and getattr(obj, "ViewObject", None):
            self.apply_colours(obj.ViewObject)
            # FreeCAD's own view provider rebuilds the faces after this call and draws them in one
            # colour, whatever DiffuseColor holds: colour them again once the event loop is back
            from PySide import QtCore

            QtCore.QTimer.singleShot(0, lambda vobj=obj.ViewObject: self.recolour(vobj))

    def recolour(self, vobj) -> None:
        """apply_colours, unless the object was deleted since it was asked for."""
        try:
            vobj.Object
        except ReferenceError:
            return
        self.apply_colours(vobj)

    def setEdit(self, vobj, mode: int = 0) -> bool:
        if mode != 0:
            return False
        self.open_panel(vobj.Object)
        return True

    def unsetEdit(self, vobj, mode: int = 0) -> bool:
        import FreeCADGui

        FreeCADGui.Control.closeDialog()
        return True

    def doubleClicked(self, vobj) -> bool:
        import FreeCADGui

        FreeCADGui.ActiveDocument.setEdit(vobj.Object.Name, 0)
        return True


class ViewProviderSurface(_Faces):
    """A progressive surface; double-click opens its task panel."""

    icon_name = "ProgSurf_Surface"

    def __init__(self, vobj) -> None:
        super().__init__(vobj)
        self.setup(vobj)
        vobj.ShapeColor = (0.80, 0.80, 0.70)

    def setup(self, vobj) -> None:
        if "ColourBy" not in vobj.PropertiesList:
            vobj.addProperty("App::PropertyEnumeration", "ColourBy", "Analysis",
                             "Colour the faces by an analysis value (Analyse command)")
            vobj.ColourBy = COLOUR_BY

    def attach(self, vobj) -> None:
        super().attach(vobj)
        self.setup(vobj)

    def onChanged(self, vobj, prop: str) -> None:
        if prop == "ColourBy":
            self.apply_colours(vobj)

    def apply_colours(self, vobj) -> None:
        colour_faces(vobj)

    def open_panel(self, obj) -> None:
        from . import task_panel

        task_panel.edit_surface(obj)


class ViewProviderNetwork(_Faces):
    """A surface network: each surface's faces in its own colour; double-click opens the panel that
    lists the surfaces with their strokes and every stroke's accounting.

    ``highlight``: the surface indices the panel shows (None = all); transient, not saved."""

    icon_name = "ProgSurf_SurfaceNetwork"
    recolour_on = ("Shape", "FaceSurfaces")

    def __init__(self, vobj) -> None:
        self.highlight = None
        super().__init__(vobj)
        vobj.LineWidth = 1.0

    def attach(self, vobj) -> None:
        self.highlight = None
        super().attach(vobj)

    def onChanged(self, vobj, prop: str) -> None:
        return None

    def show_surfaces(self, vobj, surfaces=None) -> None:
        """Highlight the faces of ``surfaces`` (indices; None = every surface in its colour)."""
        self.highlight = None if surfaces is None else set(surfaces)
        self.apply_colours(vobj)

    def apply_colours(self, vobj) -> None:
        obj = vobj.Object
        owners = list(obj.FaceSurfaces)
        if obj.Shape.isNull() or len(owners) != len(obj.Shape.Faces):
            return                      # a failed first build: no faces, or faces of another build
        vobj.DiffuseColor = network_face_colours(owners, obj.SurfaceCount, getattr(self, "highlight", None))

    def open_panel(self, obj) -> None:
        from . import network_panel

        network_panel.show(obj)
