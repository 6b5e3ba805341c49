"""Task panel of the progressive surface: pick or confirm the boundary strokes, set the
tolerances and the continuity, and watch a live preview, with what happened to each interior
stroke. Creating or editing is one undo transaction: OK commits it, Cancel aborts it (a new
surface disappears again).

``CURRENT`` holds the open panel, so tests can drive it (``CURRENT.accept()``).
"""
from __future__ import annotations

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

from ProgSurf.app import make
from ProgSurf.app.stroke_object import is_stroke
from ProgSurf.app.surface_object import has_shape, stroke_states
from ProgSurf.core.errors import ProgSurfError

from .common import ask_yes_no, icon, tell

CURRENT = None
KEEP_UNBUILT = "keep_unbuilt_surface"
"""The question (a key of common.ANSWERS) asked on OK when a new surface could not be built."""


def create_surface(preselected: list) -> "SurfacePanel | None":
    """Create command: a new surface (automatic boundary) in an open transaction + its panel."""
    doc = FreeCAD.ActiveDocument
    strokes = preselected if len(preselected) >= 3 else [o for o in doc.Objects if is_stroke(o)]
    doc.openTransaction("Create progressive surface")
    try:
        surface = make.make_surface(all_strokes=strokes)
    except ProgSurfError as exc:
        doc.abortTransaction()
        tell("Create progressive surface", str(exc))
        return None
    return _show(SurfacePanel(surface, created=True))


def edit_surface(surface) -> "SurfacePanel":
    """Double-click / Edit: the panel on an existing surface, in its own transaction."""
    surface.Document.openTransaction("Edit progressive surface")
    return _show(SurfacePanel(surface, created=False))


def _show(panel: "SurfacePanel") -> "SurfacePanel":
    global CURRENT
    CURRENT = panel
    FreeCADGui.Control.showDialog(panel)
    return panel


def continuity_box(surface) -> "QtGui.QComboBox | None":
    """A G0/G1 choice set to the surface's Continuity, or None for a surface without one."""
    if "Continuity" not in surface.PropertiesList:
        return None
    box = QtGui.QComboBox()
    box.addItems(list(surface.getEnumerationsOfProperty("Continuity")))
    box.setCurrentIndex(box.findText(surface.Continuity))
    box.setToolTip("G0: the paper's Coons sub-patches; G1: tangent-continuous seams "
                   "(kinked strokes and outer corners stay sharp)")
    return box


class SurfacePanel:
    """The task panel: stroke list (checked = boundary), automatic classification, tolerances,
    continuity, and the read-only interior strokes with their status."""

    def __init__(self, surface, created: bool) -> None:
        self.surface, self.created = surface, created
        self.doc = surface.Document
        # the build the surface continues from: Cancel gives it back, so that the old shape
        # returns exactly (a refit after the preview's edits could differ within the fit tolerance)
        self.memory = surface.Proxy.memory() if hasattr(surface.Proxy, "memory") else None
        self.form = QtGui.QWidget()
        self.form.setWindowTitle("Progressive surface")
        self.form.setWindowIcon(QtGui.QIcon(icon("ProgSurf_CreateSurface")))
        layout = QtGui.QVBoxLayout(self.form)

        self.auto = QtGui.QCheckBox("Classify the checked strokes automatically")
        self.auto.setToolTip("Qin & Wright section 2: the furthest curves from the centroid "
                             "form the boundary; the others become interior strokes")
        self.auto.setChecked(surface.AutoBoundary)
        layout.addWidget(self.auto)
        layout.addWidget(QtGui.QLabel("Boundary strokes (checked):"))
        self.list = QtGui.QListWidget()
        used = set(surface.Boundary)
        self.strokes = [o for o in self.doc.Objects if is_stroke(o) and o not in surface.Interior]
        for stroke in self.strokes:
            item = QtGui.QListWidgetItem(QtGui.QIcon(icon("ProgSurf_Stroke")), stroke.Label)
            item.setFlags(item.flags() | QtCore.Qt.ItemIsUserCheckable)
            item.setCheckState(QtCore.Qt.Checked if stroke in used else QtCore.Qt.Unchecked)
            self.list.addItem(item)
        layout.addWidget(self.list)
        layout.addWidget(QtGui.QLabel("Interior strokes, in drawing order:"))
        self.interior = QtGui.QListWidget()
        self.interior.setSelectionMode(QtGui.QAbstractItemView.NoSelection)
        self.interior.setToolTip("What the last recompute did with each interior stroke; later "
                                 "strokes win (read-only; add strokes with Add interior)")
        layout.addWidget(self.interior)

        form = QtGui.QFormLayout()
        self.spins = {}
        for name, label, decimals in (("FilterThreshold", "Filter threshold (0 = auto)", 4),
                                      ("SnapTolerance", "Snap tolerance (0 = auto)", 4),
                                      ("FitTolerance", "Fit tolerance", 5)):
            spin = QtGui.QDoubleSpinBox()
            spin.setDecimals(decimals)
            spin.setRange(0.0, 1e5)
            spin.setSuffix(" mm")
            spin.setValue(getattr(surface, name))
            form.addRow(label, spin)
            self.spins[name] = spin
        self.continuity = continuity_box(surface)
        if self.continuity is not None:
            form.addRow("Continuity across seams", self.continuity)
        self.skin = QtGui.QCheckBox("Exchange surface (skin, paper 3.3)")
        self.skin.setChecked(surface.Skin)
        form.addRow(self.skin)
        layout.addLayout(form)
        self.preview = QtGui.QCheckBox("Live preview")
        self.preview.setChecked(True)
        layout.addWidget(self.preview)
        self.status = QtGui.QLabel()
        self.status.setWordWrap(True)
        layout.addWidget(self.status)

        self.auto.toggled.connect(self.changed)
        self.list.itemChanged.connect(self.changed)
        self.skin.toggled.connect(self.changed)
        self.preview.toggled.connect(self.changed)
        for spin in self.spins.values():
            spin.valueChanged.connect(self.changed)
        if self.continuity is not None:
            self.continuity.currentIndexChanged.connect(self.changed)
        self.show_status()

    # -- values -> object ------------------------------------------------------------------
    def boundary(self) -> list:
        return [s for i, s in enumerate(self.strokes)
                if self.list.item(i).checkState() == QtCore.Qt.Checked]

    def apply(self) -> None:
        """Write the panel's values into the surface's properties."""
        s = self.surface
        boundary = self.boundary()
        if s.AutoBoundary != self.auto.isChecked():
            s.AutoBoundary = self.auto.isChecked()
        if list(s.Boundary) != boundary:
            s.Boundary = boundary
        for name, spin in self.spins.items():
            if abs(getattr(s, name) - spin.value()) > 1e-12:
                setattr(s, name, spin.value())
        if s.Skin != self.skin.isChecked():
            s.Skin = self.skin.isChecked()
        if self.continuity is not None and s.Continuity != self.continuity.currentText():
            s.Continuity = self.continuity.currentText()

    def changed(self, *_args) -> None:
        if self.preview.isChecked():
            self.apply()
            self.doc.recompute()
            self.show_status()

    # -- object -> display ------------------------------------------------------------------
    def show_status(self) -> None:
        """Show the surface's last recompute: patches, G1 defect, boundary rejections, the quality
        warning (folds, fit) and the error."""
        s = self.surface
        states = stroke_states(s)
        if has_shape(s):
            lines = [f"{s.PatchCount} patch(es); largest seam angle (G1 defect) "
                     f"{s.SeamAngleMax:.3g} deg"]
        else:
            lines = ["<b>No surface yet</b>: it could not be built from these strokes. Check "
                     "other boundary strokes or change the tolerances; OK without a surface "
                     "asks whether to keep the empty object."]
        lines += [f"boundary stroke {st.stroke.Label} rejected: {st.reason}"
                  for st in states if st.role == "boundary" and st.status == "rejected"]
        quality = getattr(s, "Quality", "")
        if quality and not quality.startswith("quality: ok"):
            lines.append(f"<font color='darkorange'>{quality}</font>")
        if s.LastError:
            lines.append(f"<font color='red'>{s.LastError}</font>")
        self.status.setText("<br>".join(lines))
        self.show_interior(states)

    def show_interior(self, states: list) -> None:
        """Fill the read-only interior list: one row per interior stroke with its status."""
        self.interior.clear()
        rows = [(st.stroke.Label, st.status, st.reason) for st in states if st.role == "interior"]
        if not states and self.surface.LastError:
            rows = [(st.Label, "not built", "the last recompute failed")
                    for st in self.surface.Interior]
        for label, status, reason in rows:
            # an accepted stroke's note (ends, pulled curves) is long: tooltip only
            shown = reason and status != "accepted"
            text = f"{label}: {status}" + (f" ({reason})" if shown else "")
            item = QtGui.QListWidgetItem(QtGui.QIcon(icon("ProgSurf_Stroke")), text)
            item.setFlags(QtCore.Qt.ItemIsEnabled)
            item.setToolTip(reason or status)
            if status != "accepted":
                item.setForeground(QtGui.QBrush(QtGui.QColor("red")))
            self.interior.addItem(item)
        if not rows:
            failed = "no status: the last recompute failed (see below)"
            item = QtGui.QListWidgetItem(failed if self.surface.LastError
                                         else "none (use Add interior)")
            item.setFlags(QtCore.Qt.NoItemFlags)
            self.interior.addItem(item)
        count = min(self.interior.count(), 6)
        self.interior.setFixedHeight(count * self.interior.sizeHintForRow(0)
                                     + 2 * self.interior.frameWidth())

    # -- task dialog protocol --------------------------------------------------------------
    def getStandardButtons(self) -> int:
        return int(QtGui.QDialogButtonBox.Ok | QtGui.QDialogButtonBox.Cancel)

    def accept(self) -> bool:
        global CURRENT
        if len(self.boundary()) < 3:
            self.status.setText("<font color='red'>check at least 3 boundary strokes</font>")
            return False
        self.apply()
        self.doc.recompute()
        if self.created and not has_shape(self.surface) and not self.keep_unbuilt():
            self.doc.abortTransaction()        # the new surface goes; the strokes never changed
            self._close()
            CURRENT = None
            return True
        self.doc.commitTransaction()
        self._close()
        CURRENT = None
        return True

    def keep_unbuilt(self) -> bool:
        """OK on a new surface that never built: keep the empty object? Default no."""
        reason = self.surface.LastError or "its build failed"
        keep = ask_yes_no(KEEP_UNBUILT, "Create progressive surface",
                          f"{reason}\n\nKeep the empty surface object anyway? "
                          "No removes it; the strokes stay as they are.", default=False)
        if not keep:
            FreeCAD.Console.PrintWarning(f"ProgSurf: no surface was created: {reason}\n")
        return keep

    def reject(self) -> bool:
        global CURRENT
        self.doc.abortTransaction()
        if self.memory is not None:
            self.surface.Proxy.restore_memory(self.memory)
        self.doc.recompute()
        self._close()
        CURRENT = None
        return True

    def _close(self) -> None:
        FreeCADGui.Control.closeDialog()
        if FreeCADGui.ActiveDocument and FreeCADGui.ActiveDocument.getInEdit():
            FreeCADGui.ActiveDocument.resetEdit()
