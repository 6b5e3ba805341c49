"""Zigzag strokes: stitching and scribbles drawn along a curve (issue 18, part 1).

A designer who sketches a shoe draws its stitching as a zigzag along a welt or a seam, touching the
curve it follows again and again. Such a stroke draws no curve of the object: the curve it follows
does. Kept in the stroke network, each of its touches is a node, and every tooth between two touches
is a sliver surface, a triangle or a lens a few delta wide, that stands off the object like a fin
(CASSIE 07-2-2, a shoe: 66 surfaces, 13 folding; without its two stitching strokes 45, 9 folding).

`zigzags` finds them: a stroke is a zigzag along another when

- it lies within ZIGZAG_NEAR x delta of the other at OVERSKETCH_COVER of its points and chord
  midpoints (it follows it, as an over-sketch does, only more loosely),
- it touches the other (within ZIGZAG_TOUCH x delta) and leaves it (beyond ZIGZAG_AWAY x delta)
  ZIGZAG_CYCLES times or more, and
- it is ZIGZAG_RATIO times or more as long as the run of the other it follows (its footpoints'
  travel along the other): a zigzag's teeth make it long for the way it goes; a curve that it
  touches and leaves again is as long as that way, or shorter; and that run is ZIGZAG_RUN x delta
  long or more.

A stroke found so is left out of the network, with a note saying which stroke it follows. The
thresholds are in delta, the sketch's touching distance, so they hold at any size. On 88 CASSIE
sketches (the 6 in ../shared and 82 others of its public data) they pick 13 strokes in 7 sketches,
each looked at: the stitching of six shoes, and in a seventh two stitching strokes and a scribbled
ball. Below the ratio stay crossed lacing (0.47, 1.33), a piece of that scribble (1.29), a stitching
stroke measured along a curve that passes it twice (0.39), two stitching strokes measured along each
other (0.94, 0.98) and one curve of 02-0-2 (1.07).
"""
from __future__ import annotations

import numpy as np

from .stroke_joins import Boxes
from .stroke_nodes import nearest_on
from .strokes import cumulative_length
from .types import FloatArray

ZIGZAG_NEAR = 3.0
"""A zigzag lies within this many delta of the curve it follows (along OVERSKETCH_COVER of it)."""

ZIGZAG_TOUCH = 0.5
"""... touches it (comes within this many delta of it) ..."""

ZIGZAG_AWAY = 1.0
"""... and leaves it (goes further than this many delta from it; stitching between two curves 1.8
delta apart, touching each in turn, leaves either by 1.1 to 2.4 delta) ..."""

ZIGZAG_RUN = 6.0
"""... along a run of the other at least this many delta long (its footpoints' extent): a small ring
drawn round a curve, an eyelet that a lace crosses, follows no more of it than its diameter."""

ZIGZAG_CYCLES = 3
"""... this many times or more (touch, leave and touch again: one cycle) ..."""

ZIGZAG_RATIO = 1.4
"""... and is this many times as long as the run of the curve it follows, or more (the CASSIE shoes'
stitching 1.48 to 2.64; the one curve that passes the other tests, 1.07). A triangle wave is
sqrt(1 + (2 h / p)^2) times as long as its way: 1.4 is teeth about half as high as their pitch."""


def _cycles(d: FloatArray, delta: float) -> int:
    """Touch-leave-touch cycles of a distance profile (mm) along a stroke."""
    touched = left = False
    cycles = 0
    for x in d:
        if x <= ZIGZAG_TOUCH * delta:
            if left:
                cycles += 1
            touched, left = True, False
        elif x >= ZIGZAG_AWAY * delta and touched:
            left = True
    return cycles


def zigzag_along(stroke: FloatArray, other: FloatArray, delta: float, cover: float) -> float:
    """How many times as long `stroke` is as the run of `other` it follows, when it is a zigzag along
    it (module docstring; cover: the share of its length that must lie within ZIGZAG_NEAR x delta of
    it), else 0. Measured at its points and chord midpoints (cover: the share of them)."""
    if len(stroke) < 2 or len(other) < 2:
        return 0.0
    probe = np.empty((2 * len(stroke) - 1, 3))
    probe[0::2], probe[1::2] = stroke, 0.5 * (stroke[1:] + stroke[:-1])
    d, at = nearest_on(probe, other)
    near = d <= ZIGZAG_NEAR * delta
    if np.mean(near) < cover or _cycles(d, delta) < ZIGZAG_CYCLES:
        return 0.0
    if float(np.ptp(at[near])) < ZIGZAG_RUN * delta:
        return 0.0
    step = np.linalg.norm(np.diff(probe, axis=0), axis=1)
    both = near[1:] & near[:-1]
    # a footpoint that jumps (across a tooth of the other, were it the zigzag) counts a few steps
    travel = np.minimum(np.abs(np.diff(at)), 4.0 * step)
    way = float(np.sum(travel[both]))
    length = float(np.sum(step[both]))
    return length / way if way > 0.0 else float("inf")


def zigzags(strokes: list, live: list, delta: float, cover: float) -> dict:
    """{stroke: the stroke it zigzags along} among the `live` strokes (indices into strokes), the
    most zigzagging first: a stroke that another zigzags along is never left out as one itself."""
    boxes = Boxes(strokes)
    reach = ZIGZAG_NEAR * delta
    # a shorter stroke cannot make the cycles: each goes out and back between the two distances
    least = 2 * ZIGZAG_CYCLES * (ZIGZAG_AWAY - ZIGZAG_TOUCH) * delta
    found = []
    alive = np.zeros(len(strokes), dtype=bool)
    alive[list(live)] = True
    for j in live:
        pj = strokes[j]
        if len(pj) < 2 or float(cumulative_length(pj)[-1]) < least:
            continue
        near = alive & boxes.close_to(boxes.lo[j], boxes.hi[j], reach)
        near[j] = False
        for i in np.flatnonzero(near):
            i = int(i)
            inbox = np.all((pj >= boxes.lo[i] - reach) & (pj <= boxes.hi[i] + reach), axis=1)
            if np.mean(inbox) < cover:
                continue
            ratio = zigzag_along(pj, strokes[i], delta, cover)
            if ratio >= ZIGZAG_RATIO:
                found.append((ratio, j, i))
    out: dict = {}
    for _, j, i in sorted(found, reverse=True):
        if j not in out and i not in out and j not in out.values():
            out[j] = i
    return out
