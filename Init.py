# ProgSurf: FreeCAD start-up registration, run by FreeCAD and FreeCADCmd (no GUI).
#
# Registration only: the import filter for stroke files. In a developer checkout set up by
# install.sh (and only there) also the checkout's .venv and tests/ on sys.path and the
# document-level unit tests (`freecadcmd -t TestProgSurfApp`); an addon installed by FreeCAD's
# Addon Manager gets none of that.
#
# FreeCAD 0.20 exec()s this file inside a function without __file__, so everything lives in
# one function that finds the addon's folder on sys.path (FreeCAD has put it there).


def _progsurf_register():
    import importlib.util
    import os
    import sys

    import FreeCAD

    def is_addon(folder):
        return all(os.path.isfile(os.path.join(folder, *part)) for part in
                   (("InitGui.py",), ("package.xml",), ("ProgSurf", "__init__.py")))

    roots = [p for p in sys.path if p and os.path.isdir(p) and is_addon(p)]
    if not roots:
        FreeCAD.Console.PrintWarning(
            "ProgSurf: cannot find its own folder (InitGui.py, package.xml and ProgSurf/ side by "
            "side) on sys.path; reinstall it with the Addon Manager, or run install.sh\n")
        return
    root = os.path.normpath(roots[0])

    FreeCAD.addImportType("ProgSurf strokes (*.xyz *.asc *.c3d *.curves)", "ProgSurf.app.importer")

    # Loaded by its path: importing the ProgSurf package here would fix, at start-up, which
    # checkout every later `import ProgSurf` gets.
    spec = importlib.util.spec_from_file_location(
        "progsurf_venv_site", os.path.join(root, "ProgSurf", "venv_site.py"))
    venv_site = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(venv_site)
    if venv_site.add_developer_paths(root) and "TestProgSurfApp" not in FreeCAD.__unit_test__:
        FreeCAD.__unit_test__ += ["TestProgSurfApp"]


_progsurf_register()
