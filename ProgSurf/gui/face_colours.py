"""Faces coloured by an analysis value: the surface's ``ColourBy`` view property.

The view provider of the surface recolours its faces whenever its Shape or ``ColourBy`` changes;
the Analyse view switches ``ColourBy`` to "Stroke deviation".
"""
from __future__ import annotations

COLOUR_BY = ["None", "Stroke deviation", "Seam defect"]


def colour_map(values: list) -> list:
    """Blue (0) -> green -> red (largest value) as RGB tuples in 0..1."""
    top = max(values, default=0.0)
    out = []
    for v in values:
        t = 0.0 if top <= 0 else min(max(v / top, 0.0), 1.0)
        out.append((t, 1.0 - abs(2 * t - 1.0), 1.0 - t) if t > 0 else (0.2, 0.3, 0.9))
    return out


def colour_faces(vobj) -> None:
    """Apply the ViewObject's ColourBy mode to the faces (DiffuseColor, one colour per face)."""
    obj = vobj.Object
    faces = len(obj.Shape.Faces) if not obj.Shape.isNull() else 0
    mode = getattr(vobj, "ColourBy", "None")
    values = None
    if mode != "None" and faces:
        from ProgSurf.app import build  # heavy (pipeline + cad): loaded when a value is asked for

        values = build.face_values(obj, mode)
    if values is None:
        vobj.DiffuseColor = [tuple(vobj.ShapeColor)[:3]] * max(faces, 1)
        return
    vobj.DiffuseColor = colour_map(values)
