"""Foundation: the manifest, the registration in Init.py, the layer rules, a headless document
whose surface reports what the command line reports.

unittest classes, so that both pytest and `freecadcmd -t TestProgSurfApp` run them.
"""
import ast
import math
import os
import subprocess
import sys
import tempfile
import unittest
import xml.etree.ElementTree as ET
from pathlib import Path

if "/usr/lib/freecad-python3/lib" not in sys.path:
    sys.path.append("/usr/lib/freecad-python3/lib")
import FreeCAD  # noqa: E402  (FreeCAD before Part)
import Part  # noqa: E402,F401

ROOT = Path(__file__).resolve().parents[2]
ICON_DIR = ROOT / "resources" / "icons"
ICONS = ("ProgSurf", "ProgSurf_ImportStrokes", "ProgSurf_StrokesFromSelection",
         "ProgSurf_CreateSurface", "ProgSurf_AddInterior", "ProgSurf_Export",
         "ProgSurf_Analyse", "ProgSurf_Stroke", "ProgSurf_Surface", "ProgSurf_SurfaceNetwork")

# Layer rules of STYLE.md: which top-level modules each ProgSurf sub-package must not import.
FREECAD_MODULES = {"FreeCAD", "FreeCADGui", "Part", "Mesh", "MeshPart", "Draft", "Sketcher",
                   "Surface", "Import", "PySide", "PySide2", "PySide6", "pivy", "OCC"}
GUI_MODULES = {"FreeCADGui", "PySide", "PySide2", "PySide6", "pivy"}
LAYER_FORBIDDEN = {
    "core": FREECAD_MODULES | {"ProgSurf.cad", "ProgSurf.app", "ProgSurf.gui", "ProgSurf.io"},
    "io": FREECAD_MODULES | {"ProgSurf.cad", "ProgSurf.app", "ProgSurf.gui"},
    "cad": GUI_MODULES | {"ProgSurf.app", "ProgSurf.gui"},
    "app": GUI_MODULES | {"ProgSurf.gui"},
}


def imported_modules(source: str, module: str) -> set[str]:
    """Absolute names of every module `source` imports; `module` is its dotted name
    (e.g. "ProgSurf.core.coons"), used to resolve relative imports."""
    package = module.rsplit(".", 1)[0].split(".")
    names = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[:len(package) - node.level + 1]
                prefix = ".".join(base + ([node.module] if node.module else []))
            else:
                prefix = node.module or ""
            names.add(prefix)
            names.update(f"{prefix}.{alias.name}" for alias in node.names)
    return names


def layer_violations(source: str, module: str, forbidden: set[str]) -> list[str]:
    """The imports of `source` that fall under a forbidden module or package."""
    return sorted(name for name in imported_modules(source, module)
                  if any(name == bad or name.startswith(bad + ".") for bad in forbidden))


def read_manifest() -> "FreeCAD.Metadata":
    return FreeCAD.Metadata(str(ROOT / "package.xml"))


def installed_checkout() -> Path | None:
    """The checkout FreeCAD loads ProgSurf from, or None when install.sh has not linked one."""
    link = Path(FreeCAD.getUserAppDataDir()) / "Mod" / "ProgSurf"
    return link.resolve() if link.exists() else None


class TestManifest(unittest.TestCase):
    """package.xml is an Addon Manager manifest that FreeCAD 0.20 itself parses."""

    def test_fields(self):
        meta = read_manifest()
        self.assertEqual(meta.Name, "ProgSurf")
        self.assertEqual(meta.Version, "0.1.0")
        self.assertEqual(meta.FreeCADMin, "0.20.0")
        self.assertEqual([lic["name"] for lic in meta.License], ["LGPL-2.1-or-later"])
        self.assertTrue((ROOT / meta.License[0]["file"]).is_file())
        self.assertTrue(meta.Maintainer and "@" in meta.Maintainer[0]["email"])
        self.assertIn("repository", {url["type"] for url in meta.Urls})
        self.assertGreater(len(meta.Description), 40)
        self.assertIn("numpy", {dep["package"] for dep in meta.Depend})

    def test_workbench_entry(self):
        meta = read_manifest()
        workbenches = meta.Content.get("workbench", [])
        self.assertEqual(len(workbenches), 1)
        wb = workbenches[0]
        self.assertEqual(wb.Classname, "ProgSurfWorkbench")
        subdir = ROOT / wb.Subdirectory
        self.assertTrue((subdir / "Init.py").is_file() and (subdir / "InitGui.py").is_file())
        self.assertTrue((ROOT / wb.Icon).is_file())
        self.assertTrue(meta.supportsCurrentFreeCAD())
        self.assertTrue(wb.supportsCurrentFreeCAD())

    def test_version_matches_package(self):
        import ProgSurf
        self.assertEqual(read_manifest().Version, ProgSurf.__version__)

    def test_icons_are_48px_svg(self):
        self.assertTrue((ROOT / read_manifest().Icon).is_file())
        for name in ICONS:
            path = ICON_DIR / f"{name}.svg"
            with self.subTest(icon=name):
                svg = ET.parse(path).getroot()
                self.assertEqual(svg.tag, "{http://www.w3.org/2000/svg}svg")
                self.assertEqual(svg.get("viewBox").split(), ["0", "0", "48", "48"])
                self.assertGreaterEqual(len(list(svg.iter())), 4, "an icon draws something")


class TestRegistration(unittest.TestCase):
    """Init.py, run by FreeCAD at start-up, registers the importer and the unit tests."""

    def setUp(self):
        installed = installed_checkout()
        if installed is None:
            self.skipTest("ProgSurf is not linked into FreeCAD's Mod folder: run ./install.sh")
        if installed != ROOT:
            self.skipTest(f"FreeCAD loads ProgSurf from {installed}, not from this checkout "
                          f"{ROOT}: run ./install.sh here")

    def test_import_filter(self):
        for ext in ("xyz", "asc", "c3d"):
            with self.subTest(ext=ext):
                self.assertIn("ProgSurf.app.importer", FreeCAD.getImportType(ext))

    def test_unit_test_module(self):
        self.assertIn("TestProgSurfApp", FreeCAD.__unit_test__)
        import TestProgSurfApp
        self.assertEqual(Path(TestProgSurfApp.__file__).resolve().parent, ROOT / "tests")

    def test_venv_packages_visible(self):
        if not (ROOT / ".venv").is_dir():
            self.skipTest("no .venv in the checkout: run ./install.sh")
        import c3d
        self.assertTrue(hasattr(c3d, "Reader") and hasattr(c3d, "Writer"))


class TestLayers(unittest.TestCase):
    """STYLE.md's layers: core and io know nothing of FreeCAD; only gui knows FreeCADGui/PySide."""

    def test_checker_catches_violations(self):
        forbidden = LAYER_FORBIDDEN["core"]
        self.assertEqual(layer_violations("import FreeCAD", "ProgSurf.core.x", forbidden),
                         ["FreeCAD"])
        self.assertEqual(layer_violations("from ..gui import cmd", "ProgSurf.core.x", forbidden),
                         ["ProgSurf.gui", "ProgSurf.gui.cmd"])
        self.assertEqual(layer_violations("from PySide import QtGui", "ProgSurf.app.x",
                                          LAYER_FORBIDDEN["app"]), ["PySide", "PySide.QtGui"])
        self.assertEqual(layer_violations("import numpy as np\nfrom . import types",
                                          "ProgSurf.core.x", forbidden), [])

    def test_packages_respect_layers(self):
        checked = 0
        for layer, forbidden in LAYER_FORBIDDEN.items():
            for path in sorted((ROOT / "ProgSurf" / layer).rglob("*.py")):
                parts = path.relative_to(ROOT).with_suffix("").parts
                module = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
                if parts[-1] == "__init__":
                    module += ".__init__"
                with self.subTest(module=module):
                    self.assertEqual(layer_violations(path.read_text(encoding="utf-8"), module,
                                                      forbidden), [])
                checked += 1
        self.assertGreater(checked, 0, "no module of ProgSurf was found to check")


class TestHeadlessDocument(unittest.TestCase):
    """A ProgSurf surface recomputes in a document without the GUI, and its Result properties are
    the figures the command line reports for the same strokes: both run app.build's one
    build-and-measure (STYLE.md: one orchestration per job)."""

    def setUp(self):
        if FreeCAD.GuiUp:
            self.skipTest("the GUI is up: this test is about the headless document")
        self.doc = FreeCAD.newDocument("ProgSurfFoundation")
        self.tmp = tempfile.TemporaryDirectory()

    def tearDown(self):
        if self.doc.Name in FreeCAD.listDocuments():
            FreeCAD.closeDocument(self.doc.Name)
        self.tmp.cleanup()

    def test_surface_properties_are_the_command_line_figures(self):
        from ProgSurf.app import make
        from ProgSurf.io import read_strokes
        from ProgSurf.io.report import read_report

        example = ROOT / "examples" / "clean4.xyz"
        report_path = os.path.join(self.tmp.name, "clean4.json")
        env = dict(os.environ)
        env.pop("PYTHONPATH", None)
        proc = subprocess.run(["/usr/bin/python3", "-m", "ProgSurf", "build", str(example), "-o",
                               os.path.join(self.tmp.name, "clean4.step"), "--report", report_path, "-q"],
                              cwd=ROOT, capture_output=True, text=True, timeout=600, env=env)
        self.assertEqual(proc.returncode, 0, proc.stderr)
        report = read_report(report_path)

        strokes = [make.make_stroke_from_points(p, name=f"Stroke{i:03d}", doc=self.doc, recompute=False)
                   for i, p in enumerate(read_strokes(example))]
        surface = make.make_surface(all_strokes=strokes, recompute=False,
                                    **{k: report["tolerances"][k] for k in ("filter_mm", "snap_mm", "fit_mm")})
        self.doc.recompute()
        self.assertTrue(surface.isValid(), surface.State)
        self.assertEqual(surface.LastError, "")
        self.assertEqual(surface.PatchCount, report["faces"])
        self.assertEqual(len(surface.Shape.Faces), report["faces"])
        self.assertEqual([line.split(" ", 3)[:3] for line in surface.StrokeStatus],
                         [[str(s["index"]), s["role"], s["status"]] for s in report["strokes"]])
        # the document's points pass through FreeCAD Vectors and the report's tolerances through
        # JSON: the same figures to rounding (a sample rule of their own differs by 1e-4 and more)
        close = {"rel_tol": 1e-8, "abs_tol": 1e-12}
        self.assertTrue(math.isclose(surface.Shape.Area, report["shell"]["area_mm2"], **close))
        for name, key in (("SeamGap", "seam_gap_max_mm"), ("SeamAngleMax", "seam_angle_max_deg"),
                          ("FitDeviation", "fit_deviation_max_mm"),
                          ("StrokeDeviationMax", "stroke_deviation_max_mm")):
            with self.subTest(property=name):
                self.assertTrue(math.isclose(getattr(surface, name), report[key], **close),
                                (getattr(surface, name), report[key]))
        measured = {int(k): v for k, v in report["stroke_deviation_mm"].items()}
        self.assertEqual(len(surface.StrokeDeviation), len(strokes))
        for index, deviation in enumerate(surface.StrokeDeviation):
            with self.subTest(stroke=index):
                self.assertTrue(math.isclose(deviation, measured.get(index, -1.0), **close),
                                (deviation, measured.get(index)))
