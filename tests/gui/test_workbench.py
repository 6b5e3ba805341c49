"""The ProgSurf workbench in the real FreeCAD GUI, under Xvfb."""
from harness import require_gui, run_in_freecad_gui

WORKBENCH_SCRIPT = r'''
from PySide import QtGui
mw = Gui.getMainWindow()
check("ProgSurfWorkbench" in Gui.listWorkbenches(), "ProgSurfWorkbench is not in the list")
wb = Gui.getWorkbench("ProgSurfWorkbench")
check(wb.MenuText == "ProgSurf", f"MenuText is {wb.MenuText!r}")
check(os.path.isfile(wb.Icon), f"workbench icon {wb.Icon!r} is not a file")

Gui.activateWorkbench("ProgSurfWorkbench")
process_events(0.5)
check(Gui.activeWorkbench().name() == "ProgSurfWorkbench",
      f"active workbench is {Gui.activeWorkbench().name()}")

commands = sorted(c for c in Gui.listCommands() if c.startswith("ProgSurf_"))
report("commands", commands)
for name in commands:
    pixmap = Gui.Command.get(name).getInfo()["pixmap"]
    check(os.path.isfile(pixmap), f"{name} has no icon file: {pixmap!r}")
toolbars = {tb.objectName(): tb for tb in mw.findChildren(QtGui.QToolBar)}
check("ProgSurf" in toolbars, f"no ProgSurf toolbar among {sorted(toolbars)}")
toolbar = toolbars.get("ProgSurf")
tool_actions = [a for a in toolbar.actions() if not a.isSeparator()] if toolbar else []
check(len(tool_actions) == len(commands),
      f"ProgSurf toolbar has {len(tool_actions)} buttons for {len(commands)} commands {commands}")
menu_actions = {a.text().replace("&", ""): a for a in mw.menuBar().actions()}
report("menus", sorted(menu_actions))
# FreeCAD shows no empty menu: while ProgSurf.gui registers no command there is none to find.
if commands:
    check("ProgSurf" in menu_actions, f"no ProgSurf menu in the menu bar {sorted(menu_actions)}")
    menu = menu_actions["ProgSurf"].menu() if "ProgSurf" in menu_actions else None
    items = [a for a in menu.actions() if not a.isSeparator()] if menu else []
    check(len(items) >= len(commands),
          f"ProgSurf menu has {len(items)} entries for {len(commands)} commands {commands}")

doc = App.newDocument("GuiSmoke")
box = doc.addObject("Part::Box", "Box")
box.Length, box.Width, box.Height = 10, 6, 4
doc.recompute()
Gui.SendMsgToActiveView("ViewFit")
Gui.ActiveDocument.ActiveView.viewIsometric()
Gui.SendMsgToActiveView("ViewFit")
check(box.isValid() and abs(box.Shape.Volume - 240.0) < 1e-9, "the box did not build")

view = image_stats(screenshot("view", 640, 480))
report("view", view)
check(view["width"] == 640 and view["height"] == 480, f"screenshot size {view}")
check(view["stddev"] > 5 and view["foreground"] > 0.05, f"3D view screenshot is blank: {view}")

window = image_stats(grab_window("window"))
report("window", window)
check(window["stddev"] > 5 and window["colours"] > 16, f"main window grab is blank: {window}")
'''


def test_workbench_activates_with_toolbar_menu_and_view():
    require_gui()
    run = run_in_freecad_gui(WORKBENCH_SCRIPT, timeout=240)
    assert run.ok, run.explain()
    assert run.checks >= 9, f"only {run.checks} checks ran: {run.values}"
    if run.values["commands"]:
        assert "ProgSurf" in run.values["menus"], run.values


def test_harness_fails_on_exception_inside_recompute():
    """The harness must catch a FeaturePython whose execute() raises: the run is not ok."""
    require_gui()
    run = run_in_freecad_gui(r'''
class Raises:
    def __init__(self, obj):
        obj.Proxy = self
    def execute(self, obj):
        raise RuntimeError("deliberate failure inside recompute")
    def __getstate__(self):
        return None
    def __setstate__(self, state):
        return None

doc = App.newDocument("Broken")
obj = doc.addObject("Part::FeaturePython", "Broken")
Raises(obj)
doc.recompute()
''', timeout=240)
    assert not run.ok
    text = "\n".join(run.failures)
    assert "Broken" in text and ("invalid" in text or "Traceback" in text), text


def test_harness_fails_on_failed_check_and_on_raise():
    require_gui()
    run = run_in_freecad_gui('check(1 + 1 == 3, "arithmetic")\nraise ValueError("boom")\n',
                             timeout=240)
    assert not run.ok
    assert any("check failed: arithmetic" in f for f in run.failures), run.failures
    assert any("boom" in f for f in run.failures), run.failures
