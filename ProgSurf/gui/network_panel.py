"""Task panel of a surface network: which strokes bound which surface (issue 18, item 4).

The surfaces are listed with the colour their faces have in the 3D view (the legend) and their
strokes; picking one selects its strokes and dims every other surface. The strokes are listed with
their accounting (boundary of / interior to which surfaces, or unused and why); picking one selects
it and shows the surfaces it bounds. The panel only looks: it changes nothing in the document.

``CURRENT`` holds the open panel, so tests can drive it (``CURRENT.pick_surface(0)``).
"""
from __future__ import annotations

import FreeCADGui
from PySide import QtCore, QtGui

from ProgSurf.app.network_object import stroke_accounts, summary, surface_strokes

from .common import icon
from .face_colours import surface_palette

CURRENT = None


def show(network) -> "NetworkPanel":
    """Open the panel on ``network`` (the view provider's setEdit, the create command)."""
    global CURRENT
    if FreeCADGui.Control.activeDialog():
        FreeCADGui.Control.closeDialog()
    CURRENT = NetworkPanel(network)
    FreeCADGui.Control.showDialog(CURRENT)
    return CURRENT


def swatch(rgb: tuple) -> "QtGui.QIcon":
    """A small square of colour ``rgb`` (0..1), the legend entry of a surface."""
    pixmap = QtGui.QPixmap(14, 14)
    pixmap.fill(QtGui.QColor.fromRgbF(*rgb))
    return QtGui.QIcon(pixmap)


class NetworkPanel:
    """Surfaces (legend, strokes) and strokes (accounting) of one SurfaceNetwork."""

    def __init__(self, network) -> None:
        self.network = network
        self.form = QtGui.QWidget()
        self.form.setWindowTitle("Surface network")
        self.form.setWindowIcon(QtGui.QIcon(icon("ProgSurf_SurfaceNetwork")))
        layout = QtGui.QVBoxLayout(self.form)
        self.status = QtGui.QLabel()
        self.status.setWordWrap(True)
        layout.addWidget(self.status)
        layout.addWidget(QtGui.QLabel("Surfaces (pick one to select its strokes):"))
        self.surfaces = QtGui.QListWidget()
        layout.addWidget(self.surfaces)
        layout.addWidget(QtGui.QLabel("Strokes (pick one to show the surfaces it bounds):"))
        self.strokes = QtGui.QListWidget()
        layout.addWidget(self.strokes)
        for view in (self.surfaces, self.strokes):   # long lines wrap in the narrow task view
            view.setWordWrap(True)
            view.setHorizontalScrollBarPolicy(QtCore.Qt.ScrollBarAlwaysOff)
        self.show_all = QtGui.QPushButton("Show every surface")
        layout.addWidget(self.show_all)
        self.fill()
        self.surfaces.currentRowChanged.connect(self.pick_surface)
        self.strokes.currentRowChanged.connect(self.pick_stroke)
        self.show_all.clicked.connect(self.reset)

    def fill(self) -> None:
        """The lists from the network's Result properties."""
        net = self.network
        lines = [summary(net)] if len(net.FaceSurfaces) else ["<b>No surface yet</b>"]
        if net.Quality and not net.Quality.startswith("quality: ok"):
            lines.append(f"<font color='darkorange'>{net.Quality}</font>")
        if net.LastError:
            lines.append(f"<font color='red'>{net.LastError}</font>")
        self.status.setText("<br>".join(lines))
        palette = surface_palette(net.SurfaceCount)
        accounts = stroke_accounts(net)
        for k in range(net.SurfaceCount if accounts else 0):
            sides, inner = surface_strokes(net, k)
            text = f"Surface {k}: " + ", ".join(s.Label for s in sides)
            if inner:
                text += "; interior: " + ", ".join(s.Label for s in inner)
            refilled = net.SurfaceRefilled[k] if k < len(getattr(net, "SurfaceRefilled", ())) else 0
            if refilled:
                text += (f"; its Coons patch turned over: {refilled} face(s) refilled over the plane of their "
                         "loop (sides kept)")
            problem = net.SurfaceQuality[k] if k < len(getattr(net, "SurfaceQuality", ())) else ""
            if problem:
                text += f" (warning: {problem})"
            item = QtGui.QListWidgetItem(swatch(palette[k]), text)
            item.setToolTip(text)
            if problem:
                item.setForeground(QtGui.QBrush(QtGui.QColor("darkorange")))
            self.surfaces.addItem(item)
        for account, line in zip(accounts, net.StrokeAccounting):
            item = QtGui.QListWidgetItem(QtGui.QIcon(icon("ProgSurf_Stroke")), line)
            item.setToolTip(line)
            if not account.used:
                item.setForeground(QtGui.QBrush(QtGui.QColor("red")))
            self.strokes.addItem(item)

    def _show(self, surfaces, strokes) -> None:
        vobj = self.network.ViewObject
        if vobj is not None and hasattr(vobj.Proxy, "show_surfaces"):
            vobj.Proxy.show_surfaces(vobj, surfaces)
        FreeCADGui.Selection.clearSelection()
        for stroke in strokes:
            FreeCADGui.Selection.addSelection(stroke)

    def pick_surface(self, k: int) -> None:
        """Select surface ``k``'s strokes (sides and interior) and dim the other surfaces."""
        if k < 0:
            return
        self.strokes.setCurrentRow(-1)          # one list at a time says what is shown
        sides, inner = surface_strokes(self.network, k)
        self._show([k], sides + inner)

    def pick_stroke(self, i: int) -> None:
        """Select stroke ``i`` and show only the surfaces it bounds or is interior to."""
        if i < 0:
            return
        self.surfaces.setCurrentRow(-1)
        account = stroke_accounts(self.network)[i]
        self._show(account.boundary_of + account.interior_to, [account.stroke])

    def reset(self) -> None:
        """Every surface in its colour again, nothing selected."""
        self.surfaces.setCurrentRow(-1)
        self.strokes.setCurrentRow(-1)
        self._show(None, [])

    # -- task dialog protocol --------------------------------------------------------------
    def getStandardButtons(self) -> int:
        return int(QtGui.QDialogButtonBox.Close)

    def reject(self) -> bool:
        global CURRENT
        self.reset()
        FreeCADGui.Control.closeDialog()
        if FreeCADGui.ActiveDocument and FreeCADGui.ActiveDocument.getInEdit():
            FreeCADGui.ActiveDocument.resetEdit()
        CURRENT = None
        return True

    def accept(self) -> bool:
        return self.reject()
