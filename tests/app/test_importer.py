"""Stroke files into a document (ProgSurf.app.importer): inserted through the module, and opened or
imported through FreeCAD's own registry (Init.py registers the import types).

unittest classes on test_document's DocTestCase (a fresh document per test, closed afterwards), so
that pytest and `freecadcmd -t TestProgSurfApp` both run them.
"""
import os
import sys
import unittest

if "/usr/lib/freecad-python3/lib" not in sys.path:
    sys.path.append("/usr/lib/freecad-python3/lib")
import FreeCAD  # noqa: E402  (FreeCAD before Part)

from test_document import DocTestCase  # noqa: E402  (first: it puts this checkout on sys.path)

import numpy as np  # noqa: E402

import ProgSurf.app.make as ps  # noqa: E402
from ProgSurf.io import read_strokes, write_point_list  # noqa: E402
from ProgSurf.io.curves import write_curves  # noqa: E402


class TestImport(DocTestCase):
    def write_file(self, ext=".xyz"):
        strokes = [np.array([[0, 0, 0], [50, 0, 1], [100, 0, 0]], float),
                   np.array([[100, 0, 0], [100, 50, 2], [100, 100, 0]], float),
                   np.array([[100, 100, 0], [50, 100, 1], [0, 100, 0]], float),
                   np.array([[0, 100, 0], [0, 50, 2], [0, 0, 0]], float)]
        path = os.path.join(self.tmp.name, "square" + ext)
        write_point_list(path, strokes)
        return path, read_strokes(path)

    def check_imported(self, objs, expected):
        self.assertEqual(len(objs), len(expected))
        for obj, arr in zip(objs, expected):
            self.assertRecomputed(obj)
            np.testing.assert_allclose([tuple(v) for v in obj.Points], arr, atol=1e-9)

    def test_insert_through_the_module(self):
        path, expected = self.write_file()
        import ProgSurf.app.importer as importer
        objs = importer.insert(path, self.doc.Name)
        self.check_imported(objs, expected)
        self.assertIn(objs[0], self.doc.Objects)

    def open_through_registry(self, path, module=""):
        """FreeCAD's File > Open path: loadFile(path, doc="", module) -> a new document."""
        before = set(FreeCAD.listDocuments())
        FreeCAD.loadFile(path, "", module)
        new = set(FreeCAD.listDocuments()) - before
        self.assertEqual(len(new), 1)
        return FreeCAD.getDocument(new.pop())

    def test_import_through_freecad_registry(self):
        if "ProgSurf.app.importer" not in FreeCAD.getImportType("xyz"):
            self.skipTest("Init.py has not registered the import type: run ./install.sh")
        for ext in ("asc", "c3d", "curves"):
            self.assertIn("ProgSurf.app.importer", FreeCAD.getImportType(ext))
        path, expected = self.write_file(".xyz")
        opened = self.open_through_registry(path)      # .xyz: the module is found by extension
        try:
            objs = [o for o in opened.Objects if hasattr(o, "Points")]
            self.check_imported(objs, expected)
            surface = ps.make_surface(boundary=objs)
            self.assertRecomputed(surface)
            self.assertEqual(surface.PatchCount, 1)
        finally:
            FreeCAD.closeDocument(opened.Name)
        # .asc is also claimed by FreeCAD's Points module: File > Open asks, scripts name us
        path, expected = self.write_file(".asc")
        opened = self.open_through_registry(path, "ProgSurf.app.importer")
        try:
            self.check_imported([o for o in opened.Objects if hasattr(o, "Points")], expected)
        finally:
            FreeCAD.closeDocument(opened.Name)
        # CASSIE's .curves (metres), found by its extension
        path = os.path.join(self.tmp.name, "vr.curves")
        write_curves(path, expected)
        opened = self.open_through_registry(path)
        try:
            self.check_imported([o for o in opened.Objects if hasattr(o, "Points")], expected)
        finally:
            FreeCAD.closeDocument(opened.Name)
        path, expected = self.write_file(".asc")
        # and insert into this document by name (File > Import)
        FreeCAD.loadFile(path, self.doc.Name, "ProgSurf.app.importer")
        self.check_imported([o for o in self.doc.Objects if hasattr(o, "Points")], expected)


if __name__ == "__main__":
    unittest.main()
