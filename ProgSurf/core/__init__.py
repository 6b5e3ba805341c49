"""Numeric core of ProgSurf: numpy only, no FreeCAD, Part or Qt import."""
