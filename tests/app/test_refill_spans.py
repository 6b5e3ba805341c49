"""A folding face's plane refill tries finer knots in turn (cad.patch_faces.REFILL_SPANS): a U whose
notch is a narrow slot (0.2 of its 3 units wide, 1.7 deep) keeps turning over next to its sides
when refilled with 16 knot spans each way and its tangent plane along its sides held (G1's refill,
core.plane_fill.HELD[:1]); with 64 it does not, and its sides are the same curves."""
from __future__ import annotations

import numpy as np

import FreeCAD
import Part

from ProgSurf.cad.analysis import FOLD_FACE_DEG, lone_face_fold_deg
from ProgSurf.cad.patch_faces import FaceInfo, make_face, refilled_face
from ProgSurf.core.bspline import basis_matrix
from ProgSurf.core.coons import coons_patch
from ProgSurf.core.plane_fill import greville

POLES = 19          # 16 knot spans of a cubic


def _chain(*corners, n=40):
    pts = [np.linspace(a, b, n, endpoint=False) for a, b in zip(corners[:-1], corners[1:])]
    return 100.0 * np.vstack(pts + [np.asarray(corners[-1], float)[None]])


def _slot_face() -> FaceInfo:
    """The cubic B-spline face (POLES x POLES) through the plane Coons patch of the slotted U at its
    Greville points."""
    sides = [_chain((0, 0), (3, 0)), _chain((3, 0), (3, 2)),
             _chain((0, 2), (1.4, 2), (1.4, 0.3), (1.6, 0.3), (1.6, 2), (3, 2)), _chain((0, 0), (0, 2))]
    patch = coons_patch(*(np.column_stack([s, np.zeros(len(s))]) for s in sides))
    knots = np.concatenate([[0.0] * 3, np.linspace(0.0, 1.0, POLES - 2), [1.0] * 3])
    g = greville(knots, 3, POLES)
    basis = basis_matrix(knots, g, 3)
    at = patch.grid(g, g)                                            # (POLES, POLES, 3)
    poles = np.linalg.solve(basis, np.linalg.solve(basis, at.transpose(1, 0, 2).reshape(POLES, -1))
                            .reshape(POLES, POLES, 3).transpose(1, 0, 2).reshape(POLES, -1)).reshape(POLES, POLES, 3)
    surface = Part.BSplineSurface()
    mults = [4] + [1] * (POLES - 4) + [4]
    inner = list(np.linspace(0.0, 1.0, POLES - 2))
    surface.buildFromPolesMultsKnots([[FreeCAD.Vector(*p) for p in row] for row in poles], mults, mults,
                                     inner, inner, False, False, 3, 3)
    return FaceInfo(0, surface, make_face(surface, "slot face"), ((), (), (), ()), False)


def _border(surface, m=50):
    t = np.linspace(0.0, 1.0, m)
    return np.array([tuple(surface.value(float(a), float(b))) for a, b in
                     [(x, 0.0) for x in t] + [(1.0, x) for x in t] + [(x, 1.0) for x in t] + [(0.0, x) for x in t]])


def test_a_slot_refilled_with_16_spans_folds_with_64_it_does_not():
    info = _slot_face()
    assert lone_face_fold_deg(info) > FOLD_FACE_DEG
    assert refilled_face(info, rows=(2,), spans=(16,)) is None
    out = refilled_face(info, rows=(2,))                # REFILL_SPANS: 16, 32, then 64
    assert out is not None and out.refilled
    assert lone_face_fold_deg(out) <= FOLD_FACE_DEG
    assert (out.surface.NbUPoles, out.surface.NbVPoles) == (67, 67)
    np.testing.assert_allclose(_border(out.surface), _border(info.surface), atol=1e-9)
