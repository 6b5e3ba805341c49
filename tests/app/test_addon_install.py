"""ProgSurf installed the FreeCAD way: what FreeCAD's Addon Manager does, without install.sh.

The Addon Manager clones the repository into the user's Mod folder: no .venv, no link, no
install.sh. So this test copies the files git tracks into the Mod folder of a fresh HOME and
runs freecadcmd there, which must: load the addon from the copy, with nothing of this checkout
(its .venv, its tests/) on sys.path; build a surface from a point list in a document; and,
without the optional package 'c3d', refuse a .c3d file with a message that says how to
install it into FreeCAD's Python. FreeCAD 0.20's own Addon Manager code (Addon.py, shipped
with FreeCAD) reads the copy's package.xml: every package it then requires must be importable,
or it would stop the install with a critical dialog.

unittest classes, so that both pytest and `freecadcmd -t TestProgSurfApp` run them.
"""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

if "/usr/lib/freecad-python3/lib" not in sys.path:
    sys.path.append("/usr/lib/freecad-python3/lib")
import FreeCAD  # noqa: E402,F401  (FreeCAD before ProgSurf.app)

from ProgSurf.optional import FREECAD_PACKAGES_FOLDER, OPTIONAL_PACKAGES  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
ADDON_MANAGER = Path("/usr/share/freecad/Mod/AddonManager")
TIMEOUT_S = 300

SCRIPT = r'''
import json, os, sys, traceback
import FreeCAD
out = {"errors": []}
try:
    mod = os.path.join(FreeCAD.getUserAppDataDir(), "Mod", "ProgSurf")
    out["sys_path"] = list(sys.path)
    out["unit_test"] = list(FreeCAD.__unit_test__)
    out["import_type"] = FreeCAD.getImportType("c3d")
    import ProgSurf
    out["progsurf_file"] = ProgSurf.__file__
    import ProgSurf.app.make as ps
    doc = FreeCAD.newDocument("AddonInstall")
    strokes = ps.make_strokes_from_file(os.path.join(mod, "examples", "clean4.xyz"), doc=doc)
    surface = ps.make_surface(all_strokes=strokes)
    doc.recompute()
    out["surface"] = {"patches": surface.PatchCount, "faces": len(surface.Shape.Faces),
                      "valid": surface.Shape.isValid(), "error": surface.LastError,
                      "strokes": len(strokes)}
    out["c3d_installed"] = __import__("importlib").util.find_spec("c3d") is not None
    from ProgSurf.core.errors import MissingPackageError
    try:
        ps.make_strokes_from_file(os.path.join(mod, "examples", "sketch_mocap.c3d"), doc=doc)
        out["c3d_message"] = None
    except MissingPackageError as exc:
        out["c3d_message"] = str(exc)
        out["c3d_objects_after"] = len(doc.Objects)
    out["objects_before_c3d"] = len(strokes) + 2
    sys.path.append(os.path.join(FreeCAD.getResourceDir(), "Mod", "AddonManager"))
    import Addon
    repo = Addon.Addon("ProgSurf", "https://example.org/ProgSurf", Addon.Addon.Status.NOT_INSTALLED,
                       "main")
    repo.load_metadata_file(os.path.join(mod, "package.xml"))
    deps = Addon.Addon.Dependencies()
    repo.walk_dependency_tree({}, deps)
    out["am_required"] = sorted(deps.python_required)
    missing = []
    for name in deps.python_required:
        try:
            __import__(name)
        except ImportError:
            missing.append(name)
    out["am_required_missing"] = missing
except Exception:
    out["errors"].append(traceback.format_exc())
with open(os.environ["PROGSURF_RESULT"], "w") as f:
    json.dump(out, f)
'''


def tracked_files() -> list[str]:
    """The files git tracks in the checkout: what the Addon Manager's clone holds."""
    run = subprocess.run(["git", "-C", str(ROOT), "ls-files", "-z"], capture_output=True)
    if run.returncode != 0:
        return []
    return [name for name in run.stdout.decode().split("\0") if name]


def optional_pylibs(metadata_txt: Path) -> set[str]:
    """The ``optionalpylibs=`` packages of a metadata.txt, read the way FreeCAD's Addon Manager
    reads it (0.20: addonmanager_workers.UpdateMetadataCacheWorker.process_metadata_txt)."""
    names = set()
    for line in metadata_txt.read_text(encoding="utf-8").splitlines():
        if line.startswith("optionalpylibs="):
            names.update(n.strip() for n in line.split("=", 1)[1].split(",") if n.strip())
    return names


class TestAddonManagerInstall(unittest.TestCase):
    """A copy of the tracked files in a fresh Mod folder, loaded by freecadcmd, no venv."""

    @classmethod
    def setUpClass(cls):
        files = tracked_files()
        if not files:
            raise unittest.SkipTest("not a git checkout (git ls-files gave nothing): "
                                    "cannot tell which files an Addon Manager clone holds")
        if shutil.which("freecadcmd") is None:
            raise unittest.SkipTest("freecadcmd is not installed")
        cls.work = Path(tempfile.mkdtemp(prefix="progsurf-addon-"))
        home = cls.work / "home"
        mod = home / ".local" / "share" / "FreeCAD" / "Mod" / "ProgSurf"
        for name in files:
            source = ROOT / name
            if source.is_file():
                (mod / name).parent.mkdir(parents=True, exist_ok=True)
                shutil.copy2(source, mod / name)
        cls.mod, cls.home = mod, home
        script = cls.work / "am_install.py"
        script.write_text(SCRIPT, encoding="utf-8")
        result = cls.work / "result.json"
        env = {k: v for k, v in os.environ.items()
               if k not in ("PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV")}
        env.update(HOME=str(home), PROGSURF_RESULT=str(result), LANG="C.UTF-8")
        run = subprocess.run(["freecadcmd", str(script)], cwd=cls.work, env=env,
                             stdin=subprocess.DEVNULL, capture_output=True, text=True,
                             errors="replace", timeout=TIMEOUT_S)
        cls.output = run.stdout + run.stderr
        cls.result = json.loads(result.read_text()) if result.is_file() else None

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.work, ignore_errors=True)

    def setUp(self):
        self.assertIsNotNone(self.result, f"freecadcmd wrote no result:\n{self.output[-3000:]}")
        self.assertEqual(self.result["errors"], [])

    def test_copy_has_no_venv_and_is_what_freecad_loads(self):
        self.assertFalse((self.mod / ".venv").exists())
        self.assertEqual(Path(self.result["progsurf_file"]).resolve().parent.parent,
                         self.mod.resolve())
        self.assertIn("ProgSurf.app.importer", self.result["import_type"])

    def test_nothing_of_a_checkout_on_sys_path(self):
        leaked = [p for p in self.result["sys_path"]
                  if str(ROOT) in p or ".venv" in p or Path(p).name == "tests"]
        self.assertEqual(leaked, [])
        self.assertNotIn("TestProgSurfApp", self.result["unit_test"])

    def test_point_list_surface_builds(self):
        surface = self.result["surface"]
        self.assertEqual(surface["error"], "")
        self.assertTrue(surface["valid"])
        self.assertGreaterEqual(surface["patches"], 1)
        self.assertEqual(surface["faces"], surface["patches"])
        self.assertEqual(surface["strokes"], 7)   # clean4.xyz: 4 boundary + 3 interior strokes

    def test_c3d_without_the_package_says_how_to_install_it(self):
        if self.result["c3d_installed"]:
            self.skipTest("FreeCAD's Python has the package 'c3d' outside any venv here: "
                          "the missing-package message cannot be provoked")
        message = self.result["c3d_message"]
        self.assertIsNotNone(message, "a .c3d file was read without the package 'c3d'")
        target = self.home / ".local" / "share" / "FreeCAD" / FREECAD_PACKAGES_FOLDER
        self.assertIn("reading C3D files needs", message)
        self.assertRegex(message, r"\S*python3\.\d+ -m pip install .*--target "
                                  + re.escape(f'"{target}" c3d'))
        self.assertIn("restart FreeCAD", message)
        self.assertEqual(self.result["c3d_objects_after"], self.result["objects_before_c3d"],
                         "a refused .c3d file adds nothing to the document")

    def test_addon_manager_020_requires_only_installed_packages(self):
        if not (ADDON_MANAGER / "Addon.py").is_file():
            self.skipTest(f"FreeCAD's Addon Manager is not at {ADDON_MANAGER}")
        self.assertEqual(self.result["am_required"], ["numpy"])
        self.assertEqual(self.result["am_required_missing"], [])


class TestC3DPackageMissing(unittest.TestCase):
    """In this process: with 'c3d' unimportable, File > Open of a .c3d file says how to install
    it into FreeCAD's Python and leaves no empty document behind."""

    def setUp(self):
        self.saved = sys.modules.get("c3d", False)
        sys.modules["c3d"] = None              # `import c3d` now raises ImportError

    def tearDown(self):
        if self.saved is False:
            del sys.modules["c3d"]
        else:
            sys.modules["c3d"] = self.saved

    def test_open_c3d_says_how_to_install_and_leaves_no_document(self):
        from ProgSurf.app import importer
        from ProgSurf.core.errors import MissingPackageError

        before = set(FreeCAD.listDocuments())
        with self.assertRaises(MissingPackageError) as caught:
            importer.open(str(ROOT / "examples" / "sketch_mocap.c3d"))
        target = os.path.join(FreeCAD.getUserAppDataDir(), FREECAD_PACKAGES_FOLDER)
        self.assertIn(f'--target "{target}" c3d', str(caught.exception))
        self.assertEqual(set(FreeCAD.listDocuments()), before)


class TestOptionalPackagesDeclared(unittest.TestCase):
    """metadata.txt declares exactly the optional packages ProgSurf imports lazily."""

    def test_metadata_txt_lists_the_optional_packages(self):
        self.assertEqual(optional_pylibs(ROOT / "metadata.txt"), set(OPTIONAL_PACKAGES))

    def test_optional_packages_are_not_required_in_package_xml(self):
        meta = FreeCAD.Metadata(str(ROOT / "package.xml"))
        required = {dep["package"] for dep in meta.Depend}
        self.assertEqual(required & set(OPTIONAL_PACKAGES), set())

    def test_optional_packages_are_imported_lazily(self):
        """Importing the whole of ProgSurf's non-GUI layers imports no optional package."""
        code = ("import sys; sys.path.append('/usr/lib/freecad-python3/lib'); import FreeCAD\n"
                "import ProgSurf.app.make, ProgSurf.app.build, ProgSurf.io, ProgSurf.io.c3d, "
                "ProgSurf.cad.render, ProgSurf.cli\n"
                f"print(sorted(set({sorted(OPTIONAL_PACKAGES)!r}) & set(sys.modules)))")
        run = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                             text=True, env=dict(os.environ, PYTHONPATH=str(ROOT)))
        self.assertEqual(run.returncode, 0, run.stderr)
        self.assertEqual(run.stdout.strip(), "[]")


if __name__ == "__main__":
    unittest.main()
