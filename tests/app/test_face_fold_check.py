"""The built faces' fold check (cad.analysis.face_folds) finds a tuck narrower than its coarse
grid's step: a face that turns over in a band 1-2 % of it wide, between the lines of the 9 x 9
grid, as a sketchgen family's 5-sided sketch had (201000 sk_cyl_penta_8: "quality: ok", 112 deg
over against the truth)."""
from __future__ import annotations

import numpy as np
import pytest

import FreeCAD
import Part

from ProgSurf.cad.analysis import FOLD_FACE_DEG, face_folds
from ProgSurf.cad.patch_faces import FaceInfo

POLES = 401


def _sheet(tuck: float, width: float = 0.005) -> Part.BSplineSurface:
    """A bicubic sheet 100 mm square, arched 30 mm across u, whose x runs back by `tuck` of its
    width over a band `width` of u wide at u = 0.795 (between the 9 x 9 grid's lines at 0.735 and
    0.8525): there it turns over on itself."""
    u = np.linspace(0.0, 1.0, POLES)
    v = np.linspace(0.0, 1.0, 12)
    x = u - tuck * 0.5 * (1.0 + np.tanh((u - 0.795) / width))
    z = 0.3 * np.sin(np.pi * u)
    poles = [[FreeCAD.Vector(100.0 * xi, 100.0 * vj, 100.0 * zi) for vj in v] for xi, zi in zip(x, z)]
    s = Part.BSplineSurface()
    s.buildFromPolesMultsKnots(poles, [4] + [1] * (POLES - 4) + [4], [4] + [1] * 8 + [4],
                               list(np.linspace(0.0, 1.0, POLES - 2)), list(np.linspace(0.0, 1.0, 10)),
                               False, False, 3, 3)
    return s


def _folds(surface) -> list:
    return face_folds([FaceInfo(0, surface, None, ((), (), (), ()), False)])


@pytest.mark.parametrize("tuck", [0.02, 0.03])
def test_a_narrow_tuck_between_the_coarse_grid_lines_is_a_fold(tuck):
    found = _folds(_sheet(tuck))
    assert [f.kind for f in found] == ["face"]
    assert found[0].angle_deg > FOLD_FACE_DEG


def test_the_same_sheet_without_its_tuck_is_no_fold():
    assert _folds(_sheet(0.0)) == []
