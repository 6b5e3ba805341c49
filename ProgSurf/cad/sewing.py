"""Sewing the faces of the shell into one Part.Shell, whole (sew) or locally after an edit (sew_into).

Qin & Wright section 3.3 ends with the sub-patch faces joined into one surface. Here OCC's sewing
(BRepBuilderAPI_Sewing, at SEW_FRACTION of the fit tolerance: 1.4e-6 mm on the bundled examples)
joins them: it only merges edges that already coincide (the faces share their boundary curves,
cad.edges) and cuts an edge at a neighbour's vertex; it cannot close a real gap.

Sewing keeps each face's surface, so a point of the surface at fixed parameters (probe_point) tells
the sewn faces apart and finds the face each was sewn from. That map lets a later build give kept
faces pre-sewn (sew), or take the faces a stroke replaced out of the last shell and sew only the new
faces and their neighbours into it (sew_into, issue 8).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ._occ import Part

_PROBE = (0.4142135623730951, 0.7320508075688772)

SEW_FRACTION = 1e-4
"""The sewing tolerance as a fraction of the fit tolerance (FreeCAD's default is a fixed 1e-6 mm,
which is 1e-3 of the fit tolerance of a sketch 0.1 mm across and 1e-11 of its coordinates at 1 m).
Shared edges coincide to round-off, so the sewing finds the same edges at any tolerance between
the two; vertex and probe keys are rounded at the same scale."""


def sew_tolerance(fit_mm: float) -> float:
    """The sewing tolerance for a fit tolerance (SEW_FRACTION of it; 1e-6 mm if it is not positive)."""
    return SEW_FRACTION * fit_mm if fit_mm and fit_mm > 0 else 1e-6


def _decimals(tolerance: float) -> int:
    """Decimals of the power of ten at or below `tolerance` (6 for 1e-6 to 9.9e-6)."""
    return -int(math.floor(math.log10(tolerance) + 1e-6))


@dataclass(frozen=True)
class SewnShell:
    """A sewn shell of all the faces given, which a later build may sew new faces into (sew_into).

    shape     : the Part.Shell
    vertices  : {id(face given to the sewing): the points (vertex_keys, rounded at the sewing
                tolerance) of its sewn face's vertices}, to find the neighbours of a face taken out
    tolerance : the sewing tolerance it was sewn at (sew_into sews at the same one only)
    The sewn face of each face given is the sewn-face map kept beside it (ShellCache.sewn)."""

    shape: object
    vertices: dict
    tolerance: float = 1e-6


def probe_point(face) -> tuple:
    """A point of the face's surface at fixed parameters: sewing keeps each face's surface, so it
    tells the sewn faces apart and finds the face each one was sewn from."""
    return tuple(face.valueAt(*_PROBE))


def _probe_key(face, tolerance: float = 1e-6) -> tuple:
    """probe_point rounded to a tenth of the sewing tolerance (1e-7 mm at 1e-6)."""
    digits = _decimals(tolerance) + 1
    return tuple(round(float(x), digits) for x in probe_point(face))


def vertex_keys(face, tolerance: float = 1e-6) -> frozenset:
    """The points of a face's vertices, rounded at the sewing tolerance (to 1e-6 mm at 1e-6 mm):
    faces sharing one share a key."""
    digits = _decimals(tolerance)
    return frozenset(tuple(round(float(c), digits) for c in (v.X, v.Y, v.Z)) for v in face.Vertexes)


def _match(given: list, shape, tolerance: float = 1e-6) -> dict | None:
    """{id(face given to the sewing): its face in the sewn shape}, or None if they cannot all be
    told apart by a point of their surface."""
    where: dict = {}
    for f in given:
        where.setdefault(_probe_key(f, tolerance), []).append(id(f))
    out = {}
    for f in shape.Faces:
        ids = where.get(_probe_key(f, tolerance), [])
        if len(ids) != 1:
            return None
        out[ids[0]] = f
    return out if len(out) == len(given) else None


def sew(faces: list, previous: dict | None = None, tolerance: float = 1e-6) -> tuple:
    """Join faces whose edges coincide into one shell (BRepBuilderAPI_Sewing, via Part, at
    `tolerance` mm: sew_tolerance of the fit tolerance).

    previous : {id(face): its face in an earlier sewn shell} for faces that were sewn before: the
               sewn face, whose edges are already shared with its old neighbours, is given to the
               sewing instead, so only the edges around new faces are sewn again.
    Returns (the sewn Part.Shell, or a Compound if OCC could not make one shell; {id(face): its
    face in it} for the next call, empty if the faces could not be told apart)."""
    previous = previous or {}
    given = [previous.get(id(f), f) for f in faces]
    sewn = Part.Compound(given)
    sewn.sewShape(tolerance)
    shells = sewn.Shells
    if not shells and len(sewn.Faces) == 1:     # one patch (boundary strokes only): a shell of one face
        shells = [Part.Shell(sewn.Faces)]
    shape = shells[0] if len(shells) == 1 else sewn
    # the sewing keeps each face's surface: tell the sewn faces apart by a point of their surface
    out = _match(faces, shape, tolerance)
    return shape, out or {}


def sew_into(faces: list, last: SewnShell | None, sewn_of: dict,
             tolerance: float = 1e-6) -> tuple[SewnShell, dict] | None:
    """Sew new faces into the last sewn shell locally, so that the cost follows the faces a stroke
    changed, not the size of the shell (issue 8).

    last    : the SewnShell of the previous build; sewn_of: its {id(face given): sewn face}.
    The faces of the last shell that are gone (replaced by new ones) are taken out; the new faces
    are sewn together with the kept faces that touched the gone ones (their neighbours, sharing an
    edge or a vertex), and those neighbours are replaced in the shell by their re-sewn selves.
    Every other face, and the edges and vertices it shares, stays as it was. Returns (SewnShell,
    {id(face): its sewn face}) of all the faces, or None where only a full sewing will do (no last
    shell, or one sewn at another tolerance, nothing taken out, or the result is not one shell of
    all the faces)."""
    if last is None or last.tolerance != tolerance:
        return None
    shape, verts = last.shape, last.vertices
    ids = {id(f) for f in faces}
    new = [f for f in faces if id(f) not in sewn_of]
    gone = [k for k in sewn_of if k not in ids]
    if not gone:
        return (last, sewn_of) if not new else None
    if shape.ShapeType != "Shell":
        return None
    touched = frozenset().union(*(verts[k] for k in gone))
    near = [f for f in faces if id(f) in sewn_of and not touched.isdisjoint(verts[id(f)])]
    given = [sewn_of[id(f)] for f in near] + new
    local = Part.Compound(given)
    local.sewShape(tolerance)
    found = _match(given, local, tolerance)
    if found is None:
        return None
    pairs = [(sewn_of[id(f)], found[id(sewn_of[id(f)])]) for f in near]
    pairs.append((sewn_of[gone[0]], Part.Compound([found[id(f)] for f in new])))
    pairs += [(sewn_of[k], Part.Compound([])) for k in gone[1:]]      # an empty compound removes
    out = shape.replaceShape(pairs)
    if out.ShapeType != "Shell" or len(out.Faces) != len(faces):
        return None
    now = {id(f): sewn_of[id(f)] for f in faces if id(f) in sewn_of}
    now.update({id(f): found[id(sewn_of[id(f)])] for f in near})
    now.update({id(f): found[id(f)] for f in new})
    nverts = {k: verts[k] for k in now if k in verts}
    nverts.update({id(f): vertex_keys(now[id(f)], tolerance) for f in near + new})
    return SewnShell(out, nverts, tolerance), now
