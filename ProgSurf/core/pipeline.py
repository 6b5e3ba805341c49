"""The whole progressive method on a list of strokes (Qin & Wright, Fig. 5): boundary, base
surface, then every interior stroke in drawing order."""
from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from typing import Callable, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

from .boundary import BoundaryLoop, apex_holds, boundary_indices, make_boundary, stroke_end_pairs
from .fairing import fair_stroke, stroke_tolerance
from .network import PatchNetwork
from .progressive import StrokeRecord, add_stroke
from .strokes import (auto_filter_threshold, filter_stroke, round_points, segment_projections, sketch_diagonal,
                      validate_stroke)
from .types import FIT_FRACTION, Polyline, Tolerances

SNAP_FRACTION = 0.02
"""Automatic snap distance: this fraction of the sketch's bounding-box diagonal (the paper ties
its thresholds to the surface size)."""

FAIR_FRACTION = 0.05
"""Automatic fairing tolerance: this fraction of the snap distance, well above tracker jitter
and well under the distance at which a stroke end counts as touching a boundary."""

TIE_FRACTION = 1e-6
"""Two stroke ends whose distances from the boundary's centre differ by less than this fraction of
the fit tolerance are a tie (see `processing_order`): far above round-off, so that a rotated or
moved sketch orders every stroke as the original does."""

Progress = Callable[[int, int, str], None]
"""progress(done, total, message): called after each stage and each interior stroke."""


@dataclass
class BuildResult:
    """The outcome of :func:`build_network`.

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
    interior: list = field(default_factory=list)
    falloff: str = "linear"
    pool: tuple = ()

    @property
    def accepted(self) -> list:
        return [r for r in self.records if r.status == "accepted"]

    @property
    def rejected(self) -> list:
        return [r for r in self.records if r.status == "rejected"]


def resolve_tolerances(strokes: Sequence[np.ndarray], tol: Tolerances) -> Tolerances:
    """Fill in automatic filter, snap, fairing and fit distances from the sketch's size."""
    filt = tol.filter_mm if tol.filter_mm is not None else auto_filter_threshold(strokes)
    snap = tol.snap_mm if tol.snap_mm is not None else SNAP_FRACTION * sketch_diagonal(np.concatenate(strokes))
    fair = tol.fair_mm if tol.fair_mm is not None else FAIR_FRACTION * snap
    fit = tol.fit_mm if tol.fit_mm is not None else FIT_FRACTION * sketch_diagonal(np.concatenate(strokes))
    return replace(tol, filter_mm=float(filt), snap_mm=float(snap), fair_mm=float(fair), fit_mm=float(fit))


def _fair_deviation(original: np.ndarray, faired: np.ndarray) -> float:
    """Largest distance from the original points to the faired polyline."""
    return float(segment_projections(original, faired)[1].min(axis=1).max())


def _kept_points(raw: np.ndarray, parts: list) -> np.ndarray:
    """The points of a boundary stroke that lie along the pieces kept in the loop: a point whose
    nearest point on every kept piece is one of its ends lies on trimmed over-sketch (or beyond a
    gap), not on the surface's edge, and is left out."""
    if not parts:
        return raw
    keep = np.zeros(len(raw), dtype=bool)
    for piece in parts:
        w, d = segment_projections(raw, piece)
        j = d.argmin(axis=1)
        wj = w[np.arange(len(raw)), j]
        at_end = ((j == 0) & (wj <= 0.0)) | ((j == len(piece) - 2) & (wj >= 1.0))
        keep |= ~at_end
    return raw[keep] if keep.any() else raw


def processing_order(stroke: np.ndarray, centre: np.ndarray, tie_mm: float) -> bool:
    """Whether an interior stroke is added reversed: the progressive update walks a stroke from its
    first point (the over-sketch trimmed at the first end first, straight pieces inserted in turn,
    the first extended across the second's start), so a stroke drawn the other way made another
    surface (issue 17: on `three_sided`, whose one interior stroke is two straight pieces, the
    other half was extended). Every interior stroke is
    therefore added starting from its end farther from `centre` (the centre of the boundary
    strokes' points), whichever way it was drawn; a rigid motion or a scaling of the sketch keeps
    that choice. Ends equally far within tie_mm keep the drawing order.

    stroke : (n, 3) the stroke as drawn;  centre : (3,)"""
    d0, d1 = np.linalg.norm(stroke[0] - centre), np.linalg.norm(stroke[-1] - centre)
    return bool(d1 - d0 > tie_mm)


def _as_drawn(rec: StrokeRecord) -> StrokeRecord:
    """The record of a stroke added reversed, turned back to its drawing order."""
    return replace(rec, points=None if rec.points is None else rec.points[::-1].copy(),
                   pre_image=None if rec.pre_image is None else rec.pre_image[::-1].copy(),
                   ends=tuple(reversed(rec.ends)), end_offsets_mm=tuple(reversed(rec.end_offsets_mm)))


def _ends_of_interior(previous: BuildResult, arrays: list):
    """The ends (boundary.stroke_end_pairs) of every stroke that is not one of `previous`'s boundary
    strokes."""
    chosen = set(range(len(previous.strokes))) - set(previous.interior)
    return stroke_end_pairs(arrays, [i for i in range(len(arrays)) if i not in chosen])


def _continues(previous: Optional[BuildResult], arrays: list, loop: BoundaryLoop, interior: list,
               tol: Tolerances, falloff: str) -> bool:
    """True when `previous` was built from the first strokes of `arrays`, unchanged, with the same
    tolerances, falloff and boundary loop, and every later stroke is interior: the surface is then
    `previous`'s network with the later strokes added (the progressive method itself)."""
    if previous is None or len(previous.strokes) > len(arrays) or previous.tol != tol or previous.falloff != falloff:
        return False
    n = len(previous.strokes)
    if previous.interior != [i for i in interior if i < n] or any(i not in interior for i in range(n, len(arrays))):
        return False
    if not all(a.shape == b.shape and np.array_equal(a, b) for a, b in zip(previous.strokes, arrays)):
        return False
    old = previous.boundary
    return old.source == loop.source and all(np.array_equal(a, b) for a, b in zip(old.sides, loop.sides))


def build_network(strokes: Sequence[npt.ArrayLike], boundary: Union[None, int, Sequence[int]] = None,
                  tol: Tolerances = Tolerances(), progress: Optional[Progress] = None,
                  falloff: str = "linear", candidates: Optional[Sequence[int]] = None,
                  previous: Optional[BuildResult] = None, loop: Optional[BoundaryLoop] = None,
                  withheld: Optional[Mapping[int, str]] = None) -> BuildResult:
    """Build the progressive surface's patch network.

    strokes  : (n_i, 3) point arrays in mm, in drawing order
    boundary : None = classify by rays from the centroid; N = the first N strokes; list = indices
    candidates : with boundary None, the strokes the classification may choose from (the others are
                 interior strokes in any case); None = all
    previous : the result of an earlier build. When the strokes only grew by interior strokes (the
               earlier ones, the tolerances and the boundary unchanged), the new strokes are added to
               a copy of its network instead of adding every stroke again: the same surface, in
               the time of the new strokes (timings_s["reused strokes"] counts the others).
    loop     : the BoundaryLoop of the strokes `boundary` names, made by the caller from a loop that
               is closed already (boundary.boundary_from_sides: a cycle of the stroke network)
    withheld : interior stroke index -> why it is left out: recorded as rejected with that reason and
               not added (a caller's later check found that the surface folds with it)
    Raises a ProgSurfError when no surface can be made (bad strokes, a boundary that cannot be
    closed); an interior stroke that cannot be added is recorded as rejected, never raised.
    """
    timings: dict = {}
    clock = time.perf_counter()
    arrays = [validate_stroke(s, i) for i, s in enumerate(strokes)]
    # automatic tolerances follow the size of the sketch, or of the boundary strokes (or boundary
    # candidates) when they are named: an interior stroke added later must not change them
    named = candidates if candidates is not None else boundary_indices(boundary, len(arrays)) if arrays else None
    sized = [arrays[i] for i in named if 0 <= i < len(arrays)] if named is not None else arrays
    tol = resolve_tolerances(sized or arrays, tol) if arrays else tol
    timings["validate"] = time.perf_counter() - clock

    clock = time.perf_counter()
    # the strokes the boundary is made from, when named: ("named" or "candidates", indices)
    pool = ("named" if candidates is None else "candidates", tuple(sorted(named))) if named is not None else ()
    if (previous is not None and pool and previous.pool == pool and previous.tol == tol
            and all(i < len(previous.strokes) and i < len(arrays) and np.array_equal(previous.strokes[i], arrays[i])
                    for i in pool[1])
            and apex_holds(previous.boundary, _ends_of_interior(previous, arrays))):
        # the same named strokes and tolerances make the same loop: keep it (fairing and closing
        # the boundary is most of the work when one interior stroke is added)
        chosen = set(range(len(previous.strokes))) - set(previous.interior)
        loop, interior = previous.boundary, sorted(set(range(len(arrays))) - chosen)
    elif loop is not None:
        interior = sorted(set(range(len(arrays))) - set(named or ()))
    else:
        loop, interior = make_boundary(arrays, boundary, tol, candidates)
    timings["boundary"] = time.perf_counter() - clock
    total = len(interior) + 2
    if progress:
        progress(1, total, "boundary closed")

    clock = time.perf_counter()
    sag = tol.sag_mm
    records: dict[int, StrokeRecord] = {}
    todo = list(interior)
    withheld = dict(withheld or {})
    if not withheld and _continues(previous, arrays, loop, interior, tol, falloff):
        net = previous.network.clone()
        done = len(previous.strokes)
        records.update({i: previous.records[i] for i in range(done)})
        todo = [i for i in interior if i >= done]
        timings["reused strokes"] = done
    else:
        # The sides keep the paper's mapping of equalised points to the unit square (by index), or
        # a whole object's loop its arc length (BoundaryLoop.params); interior strokes are
        # faired below.
        net = PatchNetwork(*[side if prm is None else Polyline(side, prm)
                             for side, prm in zip(loop.sides, loop.side_params())])
    timings["base"] = time.perf_counter() - clock
    if progress:
        progress(2, total, "base surface")

    used = {i for side in loop.source for i in side}
    centre = np.concatenate([arrays[i] for i in sorted(used)] or arrays).mean(axis=0)
    for i in range(len(arrays)):
        if i not in interior and i not in records:
            note = "boundary side" if i in used else "boundary stroke not used in the closed loop"
            records[i] = StrokeRecord(i, "boundary", "accepted" if i in used else "rejected", note,
                                      points=_kept_points(arrays[i], loop.used.get(i, [])))
    start_all = time.perf_counter()
    for k, i in enumerate(todo, start=len(interior) - len(todo)):
        clock = time.perf_counter()
        if i in withheld:
            records[i] = StrokeRecord(i, "interior", "rejected", withheld[i], points=arrays[i])
            continue
        # rounded (1e-9 mm on the examples) so that a save/reopen round trip fairs the same
        reverse = processing_order(arrays[i], centre, TIE_FRACTION * tol.fit_mm)
        drawn = arrays[i][::-1] if reverse else arrays[i]
        pts = round_points(filter_stroke(drawn, tol.filter_mm), tol.fit_mm)
        stol = replace(tol, fair_mm=stroke_tolerance(pts, tol.fair_mm, tol.snap_mm))
        faired, _ = fair_stroke(pts, stol.fair_mm, sag)
        rec = add_stroke(net, faired, i, stol, tol.snap_mm, falloff)
        rec = _as_drawn(rec) if reverse else rec
        records[i] = replace(rec, fair_deviation_mm=_fair_deviation(pts, faired) if len(pts) > 1 else 0.0)
        timings[f"stroke {i}"] = time.perf_counter() - clock
        if progress:
            r = records[i]
            progress(3 + k, total, f"stroke {i}: {r.status}" + ("" if r.status == "accepted" else f" ({r.reason})"))
    timings["interior"] = time.perf_counter() - start_all
    return BuildResult(net, [records[i] for i in range(len(arrays))], timings, loop, tol, arrays,
                       list(interior), falloff, pool)
