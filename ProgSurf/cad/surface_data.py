"""What ProgSurf derives from one face's surface, kept with the face (FaceInfo.derived).

build_shell reuses a FaceInfo while the inputs of its face are unchanged, so what is derived from
its surface is made once, when first asked for, and found again by the next recompute: the numpy
evaluator of the surface (G1 sampling, projections), the surface with the knots G1 needs, the sample
grid of the distance search and the seams measured against its neighbours. It goes when the face
goes. ProgSurf never modifies a face's surface after building it (G1 refines a copy); what is kept
here relies on that.
"""
from __future__ import annotations

import weakref
from functools import cached_property
from typing import Callable

import numpy as np

from ..core.bspline_surface import SurfaceDerivatives
from ..core.types import FloatArray
from .faces import is_plain_bspline, surface_derivatives


class SurfaceData:
    """Data derived from one surface (a Part.BSplineSurface, or any Part surface for the grid).

    surface     : the surface it is derived from
    plain       : True if numpy can evaluate it (cad.faces.is_plain_bspline)
    derivatives : its numpy evaluator (core.bspline_surface.SurfaceDerivatives), plain surfaces only
    refined     : the surface with the knots G1 needs (cad.g1.refined_surface), for a G0 face
    """

    def __init__(self, surface):
        self.surface = surface
        self._grid: tuple | None = None          # ((bounds, n), (uv, points))
        self._seams: dict = {}                   # see seam()

    @cached_property
    def plain(self) -> bool:
        return is_plain_bspline(self.surface)

    @cached_property
    def derivatives(self) -> SurfaceDerivatives:
        return surface_derivatives(self.surface)

    @cached_property
    def refined(self):
        from .g1 import refined_surface

        return refined_surface(self.surface)

    def grid(self, bounds: tuple, n: int) -> tuple[FloatArray, FloatArray]:
        """(uv (n*n, 2), points (n*n, 3)): the surface sampled on an n x n grid of parameters over
        bounds (u0, u1, v0, v1), where the distance search starts (cad.analysis.surface_distances).
        The last grid is kept: a recompute after one stroke measures the strokes again on mostly
        the same faces."""
        if self._grid is not None and self._grid[0] == (tuple(bounds), n):
            return self._grid[1]
        u0, u1, v0, v1 = bounds
        uu, vv = np.meshgrid(np.linspace(u0, u1, n), np.linspace(v0, v1, n), indexing="ij")
        uv = np.stack([uu.ravel(), vv.ravel()], axis=1)
        if self.plain:      # all samples in one numpy evaluation
            grid = (uv, self.derivatives.evaluate(uv[:, 0], uv[:, 1])[0])
        else:
            grid = (uv, np.array([tuple(self.surface.value(float(u), float(v))) for u, v in uv]))
        self._grid = ((tuple(bounds), n), grid)
        return grid

    def seam(self, key: tuple, other: "SurfaceData", other_key: tuple, measure: Callable[[], object]):
        """measure() of a seam between this surface and `other` (cad.analysis): key says where on
        this face (side, piece, samples), other_key where on the other. Kept while the other face
        is the same (the same SurfaceData, so the same FaceInfo) at the same place: a recompute
        after one stroke measures mostly the same seams. One entry per key: a new neighbour there
        replaces the old one. The neighbour is held by a weak reference, so that a face does not
        keep the faces it was once measured against alive."""
        entry = self._seams.get(key)
        if entry is None or entry[0]() is not other or entry[1] != other_key:
            entry = self._seams[key] = (weakref.ref(other), other_key, measure())
        return entry[2]
