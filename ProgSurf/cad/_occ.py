"""Locate and import FreeCAD's Part module: the only place ProgSurf touches OCC.

FreeCAD's Debian package keeps its Python modules in /usr/lib/freecad-python3/lib; `FreeCAD` must be
imported before `Part` so that the application is initialised.
"""
from __future__ import annotations

import os
import sys

FREECAD_LIB_DIRS = ("/usr/lib/freecad-python3/lib", "/usr/lib/freecad/lib", "/usr/local/lib/freecad/lib")

if "FreeCAD" not in sys.modules:
    for _path in filter(os.path.isdir, FREECAD_LIB_DIRS):
        if _path not in sys.path:
            sys.path.append(_path)

import FreeCAD  # noqa: E402  (must precede Part)
import Part  # noqa: E402

Vector = FreeCAD.Vector

__all__ = ["FreeCAD", "Part", "Vector"]
