# ProgSurf: FreeCAD GUI start-up registration: the workbench and its icon.
#
# Registration only. Commands and preferences are registered by ProgSurf.gui when the workbench
# is first activated, so that starting FreeCAD stays fast and imports nothing of ProgSurf.
#
# FreeCAD 0.20 exec()s this file inside a function without __file__: the class is defined inside
# a function so that it can see the icon path computed here.


def _progsurf_add_workbench():
    import os
    import sys

    import FreeCADGui as Gui

    icon = ""
    for folder in sys.path:
        candidate = os.path.join(folder or ".", "resources", "icons", "ProgSurf.svg")
        if os.path.isfile(os.path.join(folder or ".", "InitGui.py")) and os.path.isfile(candidate):
            icon = os.path.abspath(candidate)
            break

    class ProgSurfWorkbench(Gui.Workbench):
        """Progressive surfaces from 3D sketch strokes (Qin & Wright)."""

        MenuText = "ProgSurf"
        ToolTip = ("Progressive freeform surfaces from rough 3D sketch strokes: "
                   "boundary, Coons patches, interior strokes, STEP/IGES export")
        Icon = icon

        def Initialize(self):
            """Called once, on first activation: register commands, toolbar, menu, preferences."""
            import ProgSurf.gui as g
            commands = g.register_commands()
            self.appendToolbar("ProgSurf", commands)
            self.appendMenu("ProgSurf", commands)
            g.register_preferences()

        def Activated(self):
            """Nothing to set up on each activation."""

        def Deactivated(self):
            """Nothing to tear down on each deactivation."""

        def GetClassName(self):
            return "Gui::PythonWorkbench"

    Gui.addWorkbench(ProgSurfWorkbench())


_progsurf_add_workbench()
