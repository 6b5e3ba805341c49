"""The ProgSurf preferences page worked as a user works it, in the real FreeCAD GUI under Xvfb.

Edit > Preferences is opened on the ProgSurf page (FreeCADGui.showPreferences, a modal dialog);
a timer armed beforehand finds the dialog, grabs it to a PNG, types a new fit tolerance into the
page's FitTolerance spin box and presses OK. The value must then be in the parameter group, and
a surface made afterwards (make_surface on examples/clean4.xyz) must carry it.

The harness gives FreeCAD a private, temporary HOME and ends it with os._exit (user.cfg is not
even written back), so the changed parameter cannot reach the developer's own settings; the
script still restores it, so that nothing it runs afterwards sees the test value.

Set PROGSURF_GUI_SHOTS=<folder> to keep the screenshot (docs/gui_preferences.png was taken so).
"""
import os
from pathlib import Path

from harness import ROOT, require_gui, run_in_freecad_gui

SHOTS = os.environ.get("PROGSURF_GUI_SHOTS") or None
NEW_FIT_MM = 0.02

PREFERENCES = r'''
import sys
sys.path.insert(0, {root!r})
Gui.activateWorkbench("ProgSurfWorkbench")        # registers the preferences page
process_events(0.5)
from ProgSurf.app import params
import ProgSurf.app.make as ps

grp = App.ParamGet(params.PARAM_PATH)
report("fit_before", grp.GetFloat("FitTolerance", -1.0))
check(params.default_tolerances().fit_mm == params.DEFAULTS["FitTolerance"],
      "a fresh HOME starts from the default fit tolerance")
seen = {{}}


def fill_in(tries=[0]):
    """Runs inside the modal dialog's event loop: what a user does on the ProgSurf page."""
    dialog = QtGui.QApplication.activeModalWidget()
    if dialog is None:
        tries[0] += 1
        if tries[0] < 50:
            QtCore.QTimer.singleShot(200, fill_in)
        return
    try:
        seen["title"] = dialog.windowTitle()
        page = dialog.findChild(QtGui.QWidget, "ProgSurfPreferences")
        seen["page_visible"] = page is not None and page.isVisible()
        spin = dialog.findChild(QtGui.QDoubleSpinBox, "FitTolerance")
        seen["spin"] = spin is not None
        seen["fields"] = sorted(w.objectName() for w in dialog.findChildren(QtGui.QAbstractSpinBox)
                                if w.objectName() in ("FilterThreshold", "SnapTolerance",
                                                      "FitTolerance", "StrokeSamples")
                                and w.isVisible())
        if spin is not None:
            seen["spin_before"] = spin.value()
            spin.setValue({fit!r})
        QtGui.QApplication.processEvents()
        path = os.path.join(OUT, "gui_preferences.png")
        dialog.grab().save(path)
        seen["png"] = path
        buttons = dialog.findChild(QtGui.QDialogButtonBox)
        ok = buttons.button(QtGui.QDialogButtonBox.Ok) if buttons is not None else None
        seen["ok_button"] = ok is not None
        if ok is not None:
            ok.click()
        else:
            dialog.accept()
    except Exception as exc:              # leave the modal loop whatever happened
        seen["error"] = repr(exc)
        dialog.reject()


QtCore.QTimer.singleShot(500, fill_in)
Gui.showPreferences("ProgSurf")           # modal: returns after fill_in pressed OK
process_events(0.3)
report("seen", {{k: v for k, v in seen.items() if k != "png"}})
check("error" not in seen, f"driving the dialog failed: {{seen.get('error')}}")
check(seen.get("page_visible"), "the ProgSurf page is the one shown")
check(seen.get("fields") == ["FilterThreshold", "FitTolerance", "SnapTolerance", "StrokeSamples"],
      f"the page shows its four fields: {{seen.get('fields')}}")
check(abs(seen.get("spin_before", -1.0) - params.DEFAULTS["FitTolerance"]) < 1e-9,
      f"the page loaded the default fit tolerance: {{seen.get('spin_before')}}")
check(seen.get("ok_button"), "the dialog has an OK button")
check(QtGui.QApplication.activeModalWidget() is None, "the dialog closed")

stats = image_stats(seen.get("png", ""))
report("png_stats", stats)
check(stats["width"] > 300 and stats["height"] > 200, f"dialog grab size {{stats}}")
check(stats["stddev"] > 5 and stats["colours"] > 16 and stats["foreground"] > 0.02,
      f"the grabbed dialog is blank: {{stats}}")

fit_after = grp.GetFloat("FitTolerance", -1.0)
report("fit_after", fit_after)
check(abs(fit_after - {fit!r}) < 1e-9, f"OK saved the fit tolerance: {{fit_after}}")
check(abs(params.default_tolerances().fit_mm - {fit!r}) < 1e-9, "default_tolerances reads it")

doc = App.newDocument("Prefs")
strokes = ps.make_strokes_from_file({root!r} + "/examples/clean4.xyz", doc=doc)
surface = ps.make_surface(all_strokes=strokes)
report("surface", [surface.FitTolerance, surface.PatchCount, surface.LastError])
check(abs(surface.FitTolerance - {fit!r}) < 1e-9, "a new surface takes the preference")
check(surface.PatchCount >= 1 and surface.LastError == "", "the new surface built")

grp.RemFloat("FitTolerance")              # restore: the entry did not exist in a fresh HOME
check(params.default_tolerances().fit_mm == params.DEFAULTS["FitTolerance"], "restored")
App.closeDocument(doc.Name)
'''


def test_preferences_page_sets_the_fit_tolerance_of_new_surfaces():
    require_gui()
    out = Path(SHOTS) / "preferences" if SHOTS else None
    run = run_in_freecad_gui(PREFERENCES.format(root=str(ROOT), fit=NEW_FIT_MM), timeout=240,
                             out_dir=out)
    assert run.ok, run.explain()
    assert run.values["fit_before"] == -1.0, "a fresh HOME has no ProgSurf parameters"
    assert abs(run.values["fit_after"] - NEW_FIT_MM) < 1e-9
    assert abs(run.values["surface"][0] - NEW_FIT_MM) < 1e-9
    assert (run.out_dir / "gui_preferences.png").is_file()
