"""The surface task panel driven in the real FreeCAD GUI under Xvfb (ProgSurf.gui.task_panel).

The create command is run on the strokes of examples/clean4.xyz and its panel is driven through
``task_panel.CURRENT``, widget by widget as a user would: unticking a boundary stroke must
recompute the live preview, ticking it again must bring the first surface back, and switching
Continuity to G1 must change the surface's G1 defect (SeamAngleMax). The read-only interior
list must show every interior stroke with its status. OK commits one undo step; Cancel on a
later edit must restore every old value without leaving an undo step.

Set PROGSURF_GUI_SHOTS=<folder> to keep the screenshot (docs/gui_task_panel.png was taken so).
"""
import os
from pathlib import Path

from harness import ROOT, require_gui, run_in_freecad_gui

SHOTS = os.environ.get("PROGSURF_GUI_SHOTS") or None

PANEL = r'''
import sys
sys.path.insert(0, {root!r})
Gui.activateWorkbench("ProgSurfWorkbench")
import ProgSurf.gui.common as common
import ProgSurf.gui.task_panel as task_panel
common.INTERACTIVE = False


def state(surface):
    """What the live preview shows of the surface (rounded: recomputes repeat to ~1e-9)."""
    return (surface.PatchCount, surface.LastError, round(surface.Shape.Area, 3),
            round(surface.SeamAngleMax, 3))


def rows(panel):
    lst = panel.interior
    return [lst.item(i).text() for i in range(lst.count())]


doc = App.newDocument("Panel")
doc.UndoMode = 1
Gui.activeDocument().activeView().viewIsometric()
common.ANSWERS["open"] = {root!r} + "/examples/clean4.xyz"
Gui.runCommand("ProgSurf_ImportStrokes")
process_events(0.5)
strokes = [o for o in doc.Objects if getattr(o, "Type", "") == "ProgSurf::Stroke"]
check(len(strokes) == 7, f"clean4 has 7 strokes, got {{len(strokes)}}")
undo_before = doc.UndoCount

Gui.Selection.clearSelection()
Gui.runCommand("ProgSurf_CreateSurface")
process_events(0.5)
panel = task_panel.CURRENT
check(panel is not None and Gui.Control.activeDialog(), "task panel open")
surface = panel.surface
first = state(surface)
report("first", first)
check(first[0] >= 1 and first[1] == "", "the preview built a surface")

# the read-only interior list: the 3 interior strokes of clean4, in drawing order, accepted
interior = [s for s in strokes if s.Role == "interior"]
first_rows = rows(panel)
report("interior_rows", first_rows)
check(len(interior) == 3, f"clean4 has 3 interior strokes: {{[s.Label for s in interior]}}")
check([r.split(":")[0] for r in first_rows] == [s.Label for s in interior],
      "the interior list names the interior strokes in drawing order")
check(all(r.endswith(": accepted") for r in first_rows), "every interior row says accepted")
tips = [panel.interior.item(i).toolTip() for i in range(panel.interior.count())]
check(tips == [s.Reason for s in interior], "each row's tooltip is the stroke's note")
editable = QtCore.Qt.ItemIsUserCheckable | QtCore.Qt.ItemIsEditable | QtCore.Qt.ItemIsSelectable
flags = [int(panel.interior.item(i).flags() & editable) for i in range(panel.interior.count())]
check(not any(flags), "the interior list is read-only")

# untick one boundary stroke: the live preview recomputes
combo = panel.continuity
check(combo is not None and [combo.itemText(i) for i in range(combo.count())] == ["G0", "G1"],
      "a G0/G1 continuity choice")
check(combo is not None and combo.currentText() == surface.Continuity == "G0", "starts at G0")
side = next(i for i, s in enumerate(panel.strokes) if s.Role == "boundary")
panel.list.item(side).setCheckState(QtCore.Qt.Unchecked)
process_events(0.5)
unticked = state(surface)
report("unticked", unticked)
report("unticked_rows", rows(panel))
check(panel.strokes[side] not in surface.Boundary, "the unticked stroke left Boundary")
check(unticked != first, f"the preview did not change: {{unticked}}")
if surface.LastError:
    check(surface.LastError.split(";")[0] in panel.status.text()
          and rows(panel) == ["no status: the last recompute failed (see below)"],
          "the panel shows why the preview failed")
panel.list.item(side).setCheckState(QtCore.Qt.Checked)
process_events(0.5)
report("reticked", state(surface))
check(state(surface) == first, f"ticked again, the first surface is back: {{state(surface)}}")

# G1: the G1 defect (largest angle between normals across seams) changes
g0_angle = surface.SeamAngleMax
combo.setCurrentIndex(combo.findText("G1"))
process_events(0.5)
g1 = state(surface)
report("g1", g1)
report("seam_angle_g0_g1", [g0_angle, surface.SeamAngleMax])
check(surface.Continuity == "G1" and g1[1] == "", "G1 surface built")
check(surface.SeamAngleMax < g0_angle - 0.1,
      f"G1 lowers the seam angle: {{g0_angle}} -> {{surface.SeamAngleMax}}")
check("%.3g" % surface.SeamAngleMax in panel.status.text(), "the panel shows the G1 defect")
panel.spins["FitTolerance"].setValue(0.02)
process_events(0.5)
Gui.Selection.clearSelection()
mw = Gui.getMainWindow()
combo_view = mw.findChild(QtGui.QDockWidget, "Combo View")
if combo_view is not None:                # wide enough to read the panel in the screenshot
    mw.resizeDocks([combo_view], [430], QtCore.Qt.Horizontal)
process_events(0.5)
Gui.SendMsgToActiveView("ViewFit")
window = grab_window("gui_task_panel")
stats = image_stats(window)
report("window_stats", stats)
check(stats["stddev"] > 5 and stats["colours"] > 16, f"main window grab is blank: {{stats}}")

check(panel.accept(), "panel accepted")
process_events(0.5)
check(task_panel.CURRENT is None and not Gui.Control.activeDialog(), "panel closed")
report("undo_names", doc.UndoNames)
check(doc.UndoCount == undo_before + 1 and doc.UndoNames[0] == "Create progressive surface",
      "creating is one undo step")
accepted = (surface.Continuity, surface.FitTolerance, [s.Name for s in surface.Boundary],
            state(surface))
report("accepted", accepted[:3])

# the designer fixes the classification and adds a stroke drawn beside the surface: it is
# rejected, and the edit panel says why, in red (with AutoBoundary every stroke, Interior ones
# too, would be classified, and a far stroke would join the boundary)
import ProgSurf.app.make as ps
doc.openTransaction("Outside stroke")
far = ps.make_stroke_from_points([[150, 100, 5], [170, 120, 5], [190, 140, 5]], name="Outside",
                                 doc=doc)
surface.AutoBoundary = False
surface.Boundary = [s for s in strokes if s.Role == "boundary"]
surface.Interior = interior
ps.add_interior(surface, [far])
doc.commitTransaction()
report("far", [far.Role, far.Status, far.Reason, surface.LastError])
undo_before = doc.UndoCount
check((far.Role, far.Status) == ("interior", "rejected") and far.Reason, "outside: rejected")
accepted = (surface.Continuity, surface.FitTolerance, [s.Name for s in surface.Boundary],
            state(surface))

# edit, change everything, Cancel: the old values and shape come back, no undo step is left
Gui.ActiveDocument.setEdit(surface.Name, 0)
process_events(0.5)
edit = task_panel.CURRENT
check(edit is not None and edit is not panel, "the edit panel opened")
report("edit_rows", rows(edit))
last = edit.interior.item(edit.interior.count() - 1)
check(edit.strokes == list(surface.Boundary), "the edit panel ticks the 4 boundary strokes")
check(rows(edit)[:3] == first_rows and last.text() == f"{{far.Label}}: rejected ({{far.Reason}})",
      "the edit panel lists the rejected stroke last, with its reason")
check(last.foreground().color() == QtGui.QColor("red"), "a rejected row is red")
check(edit.continuity.currentText() == "G1"
      and abs(edit.spins["FitTolerance"].value() - 0.02) < 1e-9, "the edit panel shows the values")
edit.continuity.setCurrentIndex(edit.continuity.findText("G0"))
edit.spins["FitTolerance"].setValue(0.05)
edit.list.item(edit.strokes.index(panel.strokes[side])).setCheckState(QtCore.Qt.Unchecked)
process_events(0.5)
report("edited", state(surface))
check(surface.Continuity == "G0" and surface.FitTolerance == 0.05 and state(surface) != accepted[3],
      "the edit previewed")
check(edit.reject(), "panel cancelled")
process_events(0.5)
restored = (surface.Continuity, surface.FitTolerance, [s.Name for s in surface.Boundary],
            state(surface))
report("restored", restored[:3])
check(restored == accepted, f"Cancel restores the old values: {{restored}} vs {{accepted}}")
check(doc.UndoCount == undo_before and doc.RedoCount == 0, "Cancel leaves no undo step")
check(task_panel.CURRENT is None and not Gui.Control.activeDialog()
      and not Gui.ActiveDocument.getInEdit(), "edit panel closed")
'''


def test_task_panel_preview_continuity_interior_status_and_cancel():
    require_gui()
    out = Path(SHOTS) / "task_panel" if SHOTS else None
    run = run_in_freecad_gui(PANEL.format(root=str(ROOT)), timeout=300, out_dir=out)
    assert run.ok, run.explain()
    g0, g1 = run.values["seam_angle_g0_g1"]
    assert g1 < g0
    assert len(run.values["interior_rows"]) == 3
    assert (run.out_dir / "gui_task_panel.png").is_file()
