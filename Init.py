# ProgSurf: FreeCAD start-up registration, run by FreeCAD and FreeCADCmd (no GUI).
#
# Registration only: the import filter for stroke files, the document-level unit tests
# (`freecadcmd -t TestProgSurfApp`), and the paths they need. Nothing else runs here.
#
# FreeCAD 0.20 exec()s this file inside a function without __file__, so everything lives in
# one function that finds the checkout on sys.path (FreeCAD has put the Mod folder there).


def _progsurf_register():
    import importlib.util
    import os
    import sys

    import FreeCAD

    def is_checkout(folder):
        return (os.path.isfile(os.path.join(folder, "InitGui.py"))
                and os.path.isfile(os.path.join(folder, "ProgSurf", "__init__.py"))
                and os.path.isfile(os.path.join(folder, "tests", "TestProgSurfApp.py")))

    roots = [p for p in sys.path if p and os.path.isdir(p) and is_checkout(p)]
    if not roots:
        FreeCAD.Console.PrintWarning("ProgSurf: cannot find its own folder on sys.path; "
                                     "run install.sh from the checkout\n")
        return
    root = os.path.normpath(roots[0])

    # PyPI-only packages (c3d) live in the checkout's venv, built on this same Python. The helper
    # is loaded by its path: importing the ProgSurf package here would fix, at start-up, which
    # checkout every later `import ProgSurf` gets.
    spec = importlib.util.spec_from_file_location(
        "progsurf_venv_site", os.path.join(root, "ProgSurf", "venv_site.py"))
    venv_site = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(venv_site)
    venv_site.add_venv_site_packages(root)

    # Appended, not inserted: tests/ must never shadow a real module.
    tests = os.path.join(root, "tests")
    if tests not in sys.path:
        sys.path.append(tests)

    FreeCAD.addImportType("ProgSurf strokes (*.xyz *.asc *.c3d)", "ProgSurf.app.importer")
    if "TestProgSurfApp" not in FreeCAD.__unit_test__:
        FreeCAD.__unit_test__ += ["TestProgSurfApp"]


_progsurf_register()
