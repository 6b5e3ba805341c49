"""FreeCAD import module for stroke files (.xyz .txt .csv .asc .c3d .curves).

Init.py registers it: ``FreeCAD.addImportType("ProgSurf strokes (*.xyz *.asc *.c3d *.curves)",
"ProgSurf.app.importer")``, so File > Open / File > Import and ``FreeCAD.openDocument`` /
``FreeCAD.getDocument(name)``-based ``insert`` reach it, headless too.
"""
from __future__ import annotations

import os

import FreeCAD

from ProgSurf.core.errors import ProgSurfError

from . import make


def open(filename: str):  # noqa: A001 - FreeCAD's import-module protocol names it open
    """Create a new document named after the file and import its strokes into it."""
    name = os.path.splitext(os.path.basename(filename))[0]
    doc = FreeCAD.newDocument(name.replace("-", "_").replace(" ", "_") or "Strokes")
    doc.Label = name
    try:
        make.make_strokes_from_file(filename, doc=doc)
    except ProgSurfError:
        FreeCAD.closeDocument(doc.Name)    # a file that cannot be read leaves no empty document
        raise
    return doc


def insert(filename: str, docname: str):
    """Import the strokes of ``filename`` into the document ``docname`` (created if missing)."""
    try:
        doc = FreeCAD.getDocument(docname)
    except NameError:
        doc = FreeCAD.newDocument(docname)
    FreeCAD.setActiveDocument(doc.Name)
    return make.make_strokes_from_file(filename, doc=doc)
