"""The Analyse view: faces coloured by stroke deviation (face_colours), a table of stroke
deviations and seam defects, and a picture of the pre-image plane (Qin & Wright section 3: the
unit square divided into 3- and 4-sided regions, with each interior stroke's pre-image line).

The picture is drawn by matplotlib's Agg canvas (no pyplot, no global backend change) into a
PNG shown in a non-modal dialog. ``CURRENT`` holds the open dialog (for tests).
"""
from __future__ import annotations

import io

import FreeCAD
import numpy as np
from PySide import QtCore, QtGui

from ProgSurf import optional
from ProgSurf.core.errors import MissingPackageError

from .common import tell

CURRENT = None
PICTURE_FEATURE = "the Analyse view's picture of the pre-image plane"
REGION_COLOURS = ("#fff2cc", "#dae8fc", "#d5e8d4", "#f8cecc", "#e1d5e7", "#ffe6cc")
STROKE_COLOURS = ("#1f77b4", "#2ca02c", "#d62728", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2",
                  "#17becf", "#bcbd22", "#7f7f7f")


def region_polygon(region, edges: dict) -> np.ndarray:
    """(k, 2) outline of a region in the pre-image plane, walking its sides' edges."""
    pts = []
    for k, side in enumerate(region.sides):
        chain = list(side.edges)
        if k >= 2:                     # top (c3 -> c2) and left (c0 -> c3) are walked backwards
            chain = [(e, not r) for e, r in reversed(chain)]
        for eid, rev in chain:
            e = edges[eid]
            pts.append(e.uv1 if rev else e.uv0)
    if len(pts) < 3:
        pts = list(region.corners_uv)
    return np.array(pts, dtype=float).reshape(-1, 2)


def render_preimage_png(result, labels: list, size_px: int = 560) -> bytes:
    """PNG of the pre-image plane of a BuildResult: regions, edges and strokes' pre-images.

    Raises MissingPackageError (saying how to install it into FreeCAD's Python) without
    matplotlib, an optional package."""
    optional.require("matplotlib", PICTURE_FEATURE, FreeCAD.getUserAppDataDir())
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.patches import Polygon

    fig = Figure(figsize=(size_px / 100, size_px / 100), dpi=100)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(111)
    edges = result.network.edges()
    for i, region in enumerate(result.network.regions()):
        poly = region_polygon(region, edges)
        ax.add_patch(Polygon(poly, closed=True, facecolor=REGION_COLOURS[i % len(REGION_COLOURS)],
                             edgecolor="none"))
        c = poly.mean(axis=0)
        ax.text(c[0], c[1], f"R{region.id}{' (3)' if region.triangle else ''}", ha="center",
                va="center", fontsize=8, color="0.35")
    for e in edges.values():
        ax.plot([e.uv0[0], e.uv1[0]], [e.uv0[1], e.uv1[1]], color="black", lw=1.0)
    for rec in result.records:
        if rec.role != "interior" or rec.pre_image is None:
            continue
        pre = np.asarray(rec.pre_image, dtype=float).reshape(-1, 2)
        colour = STROKE_COLOURS[rec.index % len(STROKE_COLOURS)]
        style = "-" if rec.status == "accepted" else ":"
        ax.plot(pre[:, 0], pre[:, 1], style, color=colour, lw=2.5,
                label=f"{labels[rec.index]} ({rec.status})")
    ax.set_xlim(-0.03, 1.03)
    ax.set_ylim(-0.03, 1.03)
    ax.set_aspect("equal")
    ax.set_xlabel("u")
    ax.set_ylabel("v")
    ax.set_title("Pre-image plane: regions and strokes' pre-images")
    if any(rec.role == "interior" for rec in result.records):
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=2, fontsize=8)
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    return buf.getvalue()


def ensure_build(surface) -> bool:
    """The surface's last build in memory (rebuilt once after a document was reopened)."""
    if getattr(surface.Proxy, "result", None) is None:
        surface.touch()
        surface.Document.recompute()
    return getattr(surface.Proxy, "result", None) is not None


def show(surface) -> "AnalysisDialog | None":
    """Analyse command: colour the faces and open the analysis dialog."""
    global CURRENT
    if not ensure_build(surface):
        tell("Analyse surface", f"{surface.Label} has no valid build to analyse: "
             f"{surface.LastError or 'recompute it first'}")
        return None
    surface.ViewObject.ColourBy = "Stroke deviation"
    if CURRENT is not None:
        CURRENT.close()
    CURRENT = AnalysisDialog(surface)
    CURRENT.show()
    return CURRENT


class AnalysisDialog(QtGui.QDialog):
    """Non-modal: the pre-image plane picture, the stroke table, the seam numbers."""

    def __init__(self, surface) -> None:
        import FreeCADGui

        super().__init__(FreeCADGui.getMainWindow())
        self.setWindowTitle(f"ProgSurf analysis: {surface.Label}")
        self.surface = surface
        strokes = surface.Proxy.strokes(surface)
        result = surface.Proxy.result
        layout = QtGui.QHBoxLayout(self)
        picture = QtGui.QLabel()
        try:
            png = render_preimage_png(result, [s.Label for s in strokes])
        except MissingPackageError as exc:
            # the tables below need no matplotlib: say why the picture is missing, show the rest
            tell("Analyse surface", str(exc))
            picture.setText(str(exc))
            picture.setWordWrap(True)
            picture.setTextInteractionFlags(QtCore.Qt.TextSelectableByMouse)  # copy the command
            picture.setFixedWidth(360)
        else:
            pixmap = QtGui.QPixmap()
            pixmap.loadFromData(png, "PNG")
            picture.setPixmap(pixmap)
        layout.addWidget(picture)

        right = QtGui.QVBoxLayout()
        summary = QtGui.QLabel(
            f"<b>{surface.PatchCount} patches</b><br>"
            f"Largest seam gap: {surface.SeamGap:.3g} mm<br>"
            f"Largest seam angle (G1 defect): {surface.SeamAngleMax:.3g} deg<br>"
            f"Largest stroke deviation: {surface.StrokeDeviationMax:.3g} mm<br>"
            f"Fit deviation: {surface.FitDeviation:.3g} mm<br>"
            "Faces coloured by stroke deviation (blue 0 -> red max); change with the "
            "surface's ColourBy view property.")
        summary.setWordWrap(True)
        right.addWidget(summary)
        self.table = QtGui.QTableWidget(len(strokes), 5)
        self.table.setHorizontalHeaderLabels(["Stroke", "Role", "Status", "Deviation (mm)",
                                              "Reason"])
        deviation = list(surface.StrokeDeviation)
        for rec in result.records:
            dev = deviation[rec.index] if rec.index < len(deviation) else -1.0
            cells = (strokes[rec.index].Label, rec.role, rec.status,
                     f"{dev:.4g}" if dev >= 0 else "-", rec.reason or "")
            for col, text in enumerate(cells):
                item = QtGui.QTableWidgetItem(text)
                item.setFlags(item.flags() & ~QtCore.Qt.ItemIsEditable)
                self.table.setItem(rec.index, col, item)
        self.table.resizeColumnsToContents()
        right.addWidget(self.table)
        seams = surface.Proxy.analysis.seams
        self.seams = QtGui.QTableWidget(len(seams), 4)
        self.seams.setHorizontalHeaderLabels(["Seam (edge)", "Regions", "Gap (mm)",
                                              "Angle max (deg)"])
        for row, s in enumerate(seams):
            for col, text in enumerate((str(s.edge_id), f"R{s.region_a} | R{s.region_b}",
                                        f"{s.gap_max_mm:.2g}", f"{s.angle_max_deg:.3g}")):
                self.seams.setItem(row, col, QtGui.QTableWidgetItem(text))
        self.seams.resizeColumnsToContents()
        right.addWidget(self.seams)
        layout.addLayout(right)
        self.resize(1200, 620)

