"""The whole progressive method on a list of strokes (Qin & Wright, Fig. 5): boundary, base
surface, then every interior stroke in drawing order."""
from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from typing import Callable, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

from .boundary import BoundaryLoop, make_boundary
from .network import PatchNetwork
from .progressive import StrokeRecord, add_stroke
from .strokes import auto_filter_threshold, filter_stroke, sketch_diagonal, validate_stroke
from .types import Tolerances

SNAP_FRACTION = 0.02
"""Automatic snap distance: this fraction of the sketch's bounding-box diagonal (the paper ties
its thresholds to the surface size)."""

Progress = Callable[[int, int, str], None]
"""progress(done, total, message): called after each stage and each interior stroke."""


@dataclass
class BuildResult:
    """The outcome of :func:`build`.

    network   : the patch network (the surface)
    records   : one StrokeRecord per input stroke, in input order
    timings_s : seconds per stage: "validate", "boundary", "base", "interior" and "stroke i"
    boundary  : the closed 4-sided boundary
    tol       : the tolerances used, with automatic values resolved
    """

    network: PatchNetwork
    records: list
    timings_s: dict
    boundary: BoundaryLoop
    tol: Tolerances
    strokes: list = field(default_factory=list)

    @property
    def accepted(self) -> list:
        return [r for r in self.records if r.status == "accepted"]

    @property
    def rejected(self) -> list:
        return [r for r in self.records if r.status == "rejected"]


def resolve_tolerances(strokes: Sequence[np.ndarray], tol: Tolerances) -> Tolerances:
    """Fill in automatic filter and snap distances from the sketch's size."""
    filt = tol.filter_mm if tol.filter_mm is not None else auto_filter_threshold(strokes)
    snap = tol.snap_mm if tol.snap_mm is not None else SNAP_FRACTION * sketch_diagonal(np.concatenate(strokes))
    return replace(tol, filter_mm=float(filt), snap_mm=float(snap))


def build(strokes: Sequence[npt.ArrayLike], boundary: Union[None, int, Sequence[int]] = None,
          tol: Tolerances = Tolerances(), progress: Optional[Progress] = None,
          falloff: str = "linear") -> BuildResult:
    """Build the progressive surface.

    strokes  : (n_i, 3) point arrays in mm, in drawing order
    boundary : None = classify by rays from the centroid; N = the first N strokes; list = indices
    Raises a ProgSurfError when no surface can be made (bad strokes, a boundary that cannot be
    closed); an interior stroke that cannot be added is recorded as rejected, never raised.
    """
    timings: dict = {}
    clock = time.perf_counter()
    arrays = [validate_stroke(s, i) for i, s in enumerate(strokes)]
    tol = resolve_tolerances(arrays, tol) if arrays else tol
    timings["validate"] = time.perf_counter() - clock

    clock = time.perf_counter()
    loop, interior = make_boundary(arrays, boundary, tol)
    timings["boundary"] = time.perf_counter() - clock
    total = len(interior) + 2
    if progress:
        progress(1, total, "boundary closed")

    clock = time.perf_counter()
    net = PatchNetwork(loop.bottom, loop.right, loop.top, loop.left)
    timings["base"] = time.perf_counter() - clock
    if progress:
        progress(2, total, "base surface")

    records: dict[int, StrokeRecord] = {}
    used = {i for side in loop.source for i in side}
    for i in range(len(arrays)):
        if i not in interior:
            note = "boundary side" if i in used else "boundary stroke not used in the closed loop"
            records[i] = StrokeRecord(i, "boundary", "accepted" if i in used else "rejected", note,
                                      points=arrays[i])
    start_all = time.perf_counter()
    for k, i in enumerate(interior):
        clock = time.perf_counter()
        pts = filter_stroke(arrays[i], tol.filter_mm)
        records[i] = add_stroke(net, pts, i, tol, tol.snap_mm, falloff)
        timings[f"stroke {i}"] = time.perf_counter() - clock
        if progress:
            r = records[i]
            progress(3 + k, total, f"stroke {i}: {r.status}" + ("" if r.status == "accepted" else f" ({r.reason})"))
    timings["interior"] = time.perf_counter() - start_all
    return BuildResult(net, [records[i] for i in range(len(arrays))], timings, loop, tol, arrays)
