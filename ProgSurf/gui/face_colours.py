"""Faces coloured by an analysis value: the surface's ``ColourBy`` view property.

The view provider of the surface recolours its faces whenever its Shape or ``ColourBy`` changes;
the Analyse view switches ``ColourBy`` to "Stroke deviation". With ``ColourBy`` "None" the faces
have the surface's ShapeColor, except those a quality check fails on (a fold, or a face over its
fit allowance: the report's quality section, the task panel's warning), which are WARNING_COLOUR.
"""
from __future__ import annotations

COLOUR_BY = ["None", "Stroke deviation", "Seam defect"]

WARNING_COLOUR = (1.0, 0.55, 0.0)
"""Orange, as the task panel's quality warning: a face a quality check fails on."""


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
    if values is not None:
        vobj.DiffuseColor = colour_map(values)
        return
    normal = tuple(vobj.ShapeColor)[:3]
    failing = None
    if mode == "None" and faces and getattr(getattr(obj, "Proxy", None), "analysis", None) is not None:
        from ProgSurf.app import build  # loaded already: it made the analysis

        failing = build.failing_faces(obj)
    if not failing or not any(failing):
        vobj.DiffuseColor = [normal] * max(faces, 1)
        return
    vobj.DiffuseColor = [WARNING_COLOUR if bad else normal for bad in failing]


DIMMED = (0.82, 0.82, 0.82)
"""Light grey: the faces of the surfaces not highlighted in the network panel."""


def surface_palette(count: int) -> list:
    """``count`` RGB colours (0..1) far apart in hue, one per surface of a network: the hue steps by
    the golden ratio, so that neighbouring surface numbers never look alike."""
    import colorsys

    return [colorsys.hsv_to_rgb((0.08 + 0.618034 * k) % 1.0, 0.55, 0.95) for k in range(count)]


def network_face_colours(face_surfaces: list, surface_count: int, highlight=None) -> list:
    """Per face of a network's shape, its surface's colour (``surface_palette``); with
    ``highlight`` (a collection of surface indices) the faces of every other surface are DIMMED."""
    palette = surface_palette(max(surface_count, max(face_surfaces, default=-1) + 1))
    return [palette[k] if highlight is None or k in highlight else DIMMED for k in face_surfaces]
