"""Every ProgSurf command run through FreeCADGui.runCommand in the real GUI under Xvfb.

After each step a screenshot is taken; it must not be blank, and it must differ from the one
before where the step changed the scene. Dialogs are driven through ProgSurf.gui.common's
ANSWERS/INTERACTIVE hooks and the task panel's CURRENT handle, never by clicking.

Set PROGSURF_GUI_SHOTS=<folder> to keep the screenshots (docs/gui_*.png were taken that way).
"""
import os
from pathlib import Path

from harness import ROOT, require_gui, run_in_freecad_gui

SHOTS = os.environ.get("PROGSURF_GUI_SHOTS") or None

COMMON = r'''
import sys
sys.path.insert(0, {root!r})
sys.path.insert(0, {root!r} + "/tests/app")
import Part
Gui.activateWorkbench("ProgSurfWorkbench")
import ProgSurf.gui.common as common
import ProgSurf.gui.task_panel as task_panel
import ProgSurf.gui.analysis_view as analysis_view
common.INTERACTIVE = False
COMMANDS = ["ProgSurf_ImportStrokes", "ProgSurf_StrokesFromSelection", "ProgSurf_CreateSurface",
            "ProgSurf_AddInterior", "ProgSurf_Export", "ProgSurf_Analyse"]


def changed_fraction(a, b, threshold=24):
    """Fraction of sampled pixels whose colour differs by more than ``threshold`` in a channel."""
    ia, ib = QtGui.QImage(a), QtGui.QImage(b)
    if ia.size() != ib.size():
        return 1.0
    step, diff, n = 3, 0, 0
    for y in range(0, ia.height(), step):
        for x in range(0, ia.width(), step):
            n += 1
            pa, pb = ia.pixel(x, y), ib.pixel(x, y)
            diff += any(abs(((pa >> k) & 255) - ((pb >> k) & 255)) > threshold for k in (0, 8, 16))
    return diff / n


def shot(name, previous=None, must_change=True):
    Gui.Selection.clearSelection()        # selected objects are drawn in the highlight colour
    Gui.SendMsgToActiveView("ViewFit")
    path = screenshot(name)
    stats = image_stats(path)
    check(stats["stddev"] > 3 and stats.get("foreground", 1) > 0.005, f"{{name}}: blank view {{stats}}")
    if previous is not None:
        frac = changed_fraction(previous, path)
        report(name + "_changed", frac)
        if must_change:
            check(frac > 0.002, f"{{name}}: the view did not change ({{frac:.4f}})")
    return path


def active(name):
    return Gui.Command.get(name).isActive() if hasattr(Gui, "Command") else True
'''

BUNDLED = COMMON + r'''
check(all(c in Gui.listCommands() for c in COMMANDS), "commands registered")
wb = Gui.activeWorkbench()
report("toolbars", wb.listToolbars())
report("menus", wb.listMenus())
check("ProgSurf" in wb.listToolbars() and "ProgSurf" in wb.listMenus(), "toolbar and menu")
grab_window("gui_workbench")
doc = App.newDocument("Bundled")
Gui.activeDocument().activeView().viewIsometric()
common.ANSWERS["open"] = {root!r} + "/examples/{example}"
Gui.runCommand("ProgSurf_ImportStrokes")
process_events(0.5)
strokes = [o for o in doc.Objects if getattr(o, "Type", "") == "ProgSurf::Stroke"]
report("strokes", len(strokes))
check(len(strokes) >= 4, "strokes imported")
p1 = shot("01_imported")

Gui.Selection.clearSelection()
Gui.runCommand("ProgSurf_CreateSurface")
process_events(0.5)
panel = task_panel.CURRENT
check(panel is not None, "task panel open")
panel.spins["FitTolerance"].setValue({fit})
process_events(0.5)
surface = panel.surface
report("preview_patches", surface.PatchCount)
p2 = shot("02_preview", p1)
check(panel.accept(), "panel accepted")
process_events(0.5)
check(task_panel.CURRENT is None and not Gui.Control.activeDialog(), "panel closed")
report("patches", surface.PatchCount)
report("status", list(surface.StrokeStatus))
report("error", surface.LastError)
check(surface.PatchCount >= 1 and surface.LastError == "", "surface built")
colours = sorted({{tuple(round(c, 2) for c in s.ViewObject.LineColor[:3]) for s in strokes}})
report("stroke_colours", colours)
check(len(colours) >= 2, "boundary and interior strokes coloured apart")
p3 = shot("03_surface", p2, must_change=False)

Gui.Selection.clearSelection()
Gui.Selection.addSelection(surface)
Gui.runCommand("ProgSurf_Analyse")
process_events(1.0)
dialog = analysis_view.CURRENT
check(dialog is not None and dialog.isVisible(), "analysis dialog shown")
check(surface.ViewObject.ColourBy == "Stroke deviation", "faces coloured")
from ProgSurf.app import build
values = build.face_values(surface, "Stroke deviation")
report("face_values", values)
report("diffuse", [list(c) for c in surface.ViewObject.DiffuseColor])
check(len(surface.ViewObject.DiffuseColor) == surface.PatchCount, "one colour per face")
check(len({{tuple(c) for c in surface.ViewObject.DiffuseColor}}) > 1, "faces coloured apart")
p4 = shot("04_analysis", p3)
if dialog is not None:
    dialog.grab().save(os.path.join(OUT, "gui_analysis_dialog.png"))
    grab_window("gui_analysis_window")
    dialog.close()

step = os.path.join(OUT, "surface.step")
common.ANSWERS["save"] = step
Gui.runCommand("ProgSurf_Export")
back = Part.read(step)
report("step_faces", len(back.Faces))
check(len(back.Faces) == surface.PatchCount, "STEP read back has every face")
check(abs(back.Area - surface.Shape.Area) < 1e-6 * surface.Shape.Area, "STEP area")
import Import
iges = os.path.join(OUT, "surface_by_file_export.igs")
Import.export([surface], iges)            # FreeCAD's own File > Export on the Shape
back = Part.read(iges)
check(len(back.Faces) == surface.PatchCount, "File > Export IGES has every face")

# motion capture: strokes from a .c3d file, or a message that says how to install the reader
import importlib.util
mocap = App.newDocument("Mocap")
common.ANSWERS["open"] = {root!r} + "/examples/sketch_mocap.c3d"
Gui.runCommand("ProgSurf_ImportStrokes")
process_events(0.5)
n = len([o for o in mocap.Objects if getattr(o, "Type", "") == "ProgSurf::Stroke"])
report("c3d_strokes", n)
if importlib.util.find_spec("c3d") is not None:
    check(n >= 4, "C3D strokes imported")
else:
    check(n == 0 and "install" in common.MESSAGES[-1][1], "C3D install hint")
'''

SKETCHES = COMMON + r'''
import test_document as T
import ProgSurf.app.make as ps
doc = App.newDocument("Sketches")
doc.UndoMode = 1
boundary, s1, s2 = T.fig11_sketches(doc)
for sk in (boundary, s1, s2):
    sk.ViewObject.Visibility = False
Gui.activeDocument().activeView().viewIsometric()
Gui.Selection.clearSelection()
check(not Gui.Command.get("ProgSurf_StrokesFromSelection").isActive()
      if hasattr(Gui, "Command") else True, "inactive without selection")
for sk in (boundary, s1, s2):
    Gui.Selection.addSelection(sk)
Gui.runCommand("ProgSurf_StrokesFromSelection")
process_events(0.5)
strokes = [o for o in doc.Objects if getattr(o, "Type", "") == "ProgSurf::Stroke"]
report("strokes", [s.Label for s in strokes])
check(len(strokes) == 6, "4 boundary chains + 2 sections")
p1 = shot("01_strokes")
bnd = [s for s in strokes if s.Source[0] == boundary]
sec1 = [s for s in strokes if s.Source[0] == s1][0]
sec2 = [s for s in strokes if s.Source[0] == s2][0]

Gui.Selection.clearSelection()
for s in bnd:
    Gui.Selection.addSelection(s)
Gui.runCommand("ProgSurf_CreateSurface")
process_events(0.5)
panel = task_panel.CURRENT
panel.auto.setChecked(False)              # the 4 selected strokes are the boundary
panel.spins["FilterThreshold"].setValue(T.FILTER_MM)
panel.spins["SnapTolerance"].setValue(T.SNAP_MM)
check(panel.accept(), "panel accepted")
surface = panel.surface
surface.ViewObject.Transparency = 20
report("base_patches", surface.PatchCount)
check(surface.PatchCount == 1, "base Coons patch")
p2 = shot("02_base_surface", p1)

Gui.Selection.clearSelection()
Gui.Selection.addSelection(sec1)
Gui.runCommand("ProgSurf_AddInterior")
process_events(0.5)
report("one_patches", surface.PatchCount)
check(surface.PatchCount == 2, "one section: 2 patches")
p3 = shot("gui_sketch_before_interior", p2)
area_one = surface.Shape.Area

Gui.Selection.clearSelection()
Gui.Selection.addSelection(sec2)
Gui.runCommand("ProgSurf_AddInterior")
process_events(0.5)
report("two_patches", surface.PatchCount)
check(surface.PatchCount == 4, "Fig. 11: 4 patches")
check(sec1.Status == "accepted" and sec2.Role == "interior", "roles written on strokes")
p4 = shot("gui_sketch_after_interior", p3)
Gui.Selection.addSelection(surface)
grab_window("gui_workbench_document")
Gui.Selection.clearSelection()

Gui.runCommand("Std_Undo")
doc.recompute()
process_events(0.5)
report("undo_patches", surface.PatchCount)
report("undo_sec2", [sec2.Role, sec2.Status, list(sec2.ViewObject.LineColor)])
check(surface.PatchCount == 2 and list(surface.Interior) == [sec1], "undo: one undo step")
p5 = shot("06_undone", p4)
report("undo_vs_before", changed_fraction(p5, p3))
check(abs(surface.Shape.Area - area_one) < 1e-6 * area_one, "undo restores the earlier shape")
check(list(sec2.ViewObject.LineColor)[:3] == list(sec2.ViewObject.PointColor)[:3]
      and sec2.Status == "", "the undone stroke is grey again")
Gui.runCommand("Std_Redo")
doc.recompute()
process_events(0.5)
check(surface.PatchCount == 4, "redo")

s2.Placement = App.Placement(App.Vector(0, 150, 0), T.XZ_PLANE)   # move the sketch
doc.recompute()
process_events(0.5)
check(surface.LastError == "" and abs(sec2.Points[0].y - 150) < 1e-9, "surface follows sketch")
p6 = shot("07_moved_sketch", p4)

Gui.Selection.clearSelection()
Gui.Selection.addSelection(surface)
Gui.runCommand("ProgSurf_Analyse")
process_events(1.0)
p7 = shot("gui_analysis", p6)
if analysis_view.CURRENT is not None:
    analysis_view.CURRENT.grab().save(os.path.join(OUT, "gui_analysis_dialog.png"))
    analysis_view.CURRENT.close()
'''


def run(script: str, name: str):
    out = Path(SHOTS) / name if SHOTS else None
    return run_in_freecad_gui(script, timeout=300, out_dir=out)


def test_bundled_example_import_create_analyse_export():
    require_gui()
    example = "clean4.xyz"
    if not (ROOT / "examples" / example).is_file():
        import pytest
        pytest.skip(f"examples/{example} is not generated yet")
    result = run(BUNDLED.format(root=str(ROOT), example=example, fit=0.02), "bundled")
    assert result.ok, result.explain()
    assert result.values["strokes"] >= 4
    assert result.values["patches"] == result.values["step_faces"]
    assert result.values["04_analysis_changed"] > 0.002


def test_sketch_example_strokes_from_selection_add_interior_undo():
    require_gui()
    result = run(SKETCHES.format(root=str(ROOT)), "sketches")
    assert result.ok, result.explain()
    assert [result.values[k] for k in ("base_patches", "one_patches", "two_patches",
                                      "undo_patches")] == [1, 2, 4, 2]
