"""A loop of many sides whose Coons patch folds whatever its corners, split in two (issue 18).

The paper merges a boundary of any number of sides to four and fills it with one Coons patch;
loop_corners chooses other corners where that patch folds. A loop of five or more sides on a real
sketch often folds with every choice of corners (CASSIE vintage_car: loops of 6-12 sides turned
96-179 deg with the best corners): one patch cannot bend round so many sides. Mullineux fills an
n-sided net by dividing it; here a loop is divided by a curve across it, between two of its nodes,
and each part is filled as its own surface: the two share that curve exactly, as two surfaces share
a stroke.

The curve across (:func:`chord`) is the cubic Hermite arc between the two nodes that leaves each in
the tangent plane of the loop there (spanned by the two sides meeting at the node), towards the
other node: the surface the loop bounds passes through the node in that plane, so the curve lies
along it and the two parts meet without a crease where the loop's sides meet smoothly. Of the
ways to divide the loop (every pair of nodes with two sides or more on each part) each is screened
on the two parts' paper corners on a coarse grid, the best SHORTLIST measured with the corners
loop_corners would choose, and the division whose worse part turns least is taken when neither
part folds (turns at most loop_corners.FOLD_DEG) and it turns at least loop_corners.GAIN_DEG less
than the whole (a loop just over FOLD_DEG is not given a curve nobody drew for 3 deg): a division
whose parts fold too made faces that the shell could not be sewn from (CASSIE 04-1-1: a 9-sided
loop turned 178 deg, its parts 167, two shells invalid).
"""
from __future__ import annotations

import itertools
from typing import Optional, Sequence

import numpy as np

from .continuity import hermite_basis, unit
from .folds import TUCK_REACH
from .loop_corners import COARSE_SAMPLES, FOLD_DEG, GAIN_DEG, choose_sides, default_sides, patch_turns_deg
from .strokes import cumulative_length
from .types import FloatArray

MIN_SIDES = 5
"""Loops of at least this many sides whose patch folds are divided."""

SHORTLIST = 3
"""How many of the best screened divisions are measured with their parts' chosen corners."""

CHORD_POINTS = 33
"""Points of a curve across."""

TANGENT_SHARE = 0.1
"""A side's direction at a node is that of its chord to the point this share of its length along."""


def _leaving(side: FloatArray) -> FloatArray:
    """The direction a side leaves its first point in (over TANGENT_SHARE of its length)."""
    cum = cumulative_length(side)
    k = min(max(1, int(np.searchsorted(cum, TANGENT_SHARE * cum[-1]))), len(side) - 1)
    return unit(side[k] - side[0])


def _towards(sides: Sequence[FloatArray], k: int, target: FloatArray) -> FloatArray:
    """Unit direction from node k (the start of sides[k]) towards target, in the plane of the two
    sides meeting there (the direction to target itself where they are in line)."""
    here = sides[k][0]
    normal = np.cross(_leaving(sides[k - 1][::-1]), _leaving(sides[k]))
    d = np.asarray(target, dtype=float) - here
    if np.linalg.norm(normal) > 1e-6:
        normal = unit(normal)
        d = d - float(d @ normal) * normal
    return unit(d)


def chord(sides: Sequence[FloatArray], i: int, j: int, n: int = CHORD_POINTS) -> FloatArray:
    """(n, 3) the curve across a loop from node i to node j (module docstring); node k is where
    sides[k] starts."""
    p, q = np.asarray(sides[i][0], dtype=float), np.asarray(sides[j][0], dtype=float)
    length = float(np.linalg.norm(q - p))
    t0 = _towards(sides, i, q) * length
    t1 = -_towards(sides, j, p) * length
    out = hermite_basis(np.linspace(0.0, 1.0, n)) @ np.array([p, t0, t1, q])
    out[0], out[-1] = p, q                       # the nodes exactly
    return out


def _reach(sides: Sequence[FloatArray]) -> float:
    every = np.concatenate([np.asarray(x, dtype=float) for x in sides])
    return TUCK_REACH * float(np.linalg.norm(every.max(axis=0) - every.min(axis=0)))


_UNSET = object()


def loop_turn_deg(sides: Sequence[FloatArray], own: Optional[Sequence[bool]] = None, chosen=_UNSET) -> float:
    """How far the base patch of a loop of 3 or more sides turns inside it with the corners it
    gets: the paper's, or loop_corners.choose_sides's where those fold (`chosen`: what
    choose_sides(sides, None, own) gave, if the caller has it already)."""
    if chosen is _UNSET:
        chosen = choose_sides(sides, None, own)
    if chosen is not None:
        return float(chosen[3])
    first, _ = default_sides(sides, None)
    return float(patch_turns_deg([first], _reach(sides), dense=True)[0])


def halves(sides: Sequence[FloatArray], i: int, j: int, across: FloatArray) -> tuple[list, list]:
    """The two loops of a division between nodes i < j: sides i..j-1 then the curve back from j to
    i, and sides j..i-1 (round the loop) then the curve from i to j."""
    return list(sides[i:j]) + [across[::-1]], list(sides[j:]) + list(sides[:i]) + [across]


def best_division(sides: Sequence[FloatArray], own: Optional[Sequence[bool]] = None, chosen=_UNSET
                  ) -> Optional[tuple[int, int, FloatArray, float, float]]:
    """(i, j, the curve across from node i to node j, the whole loop's turn, the worse half's turn;
    deg) of the division of a loop that folds (module docstring), or None: the loop has fewer than
    MIN_SIDES sides, does not fold, or every division has a part that folds or gains less than
    GAIN_DEG. own: per side, whether no other
    surface bounds itself by it (loop_corners: only there may a corner be put in a side's middle);
    chosen: the whole loop's choose_sides(sides, None, own), if the caller has it (it builds the
    loop undivided with those corners)."""
    n = len(sides)
    if n < MIN_SIDES:
        return None
    own = [True] * n if own is None else list(own)
    whole = loop_turn_deg(sides, own, chosen)
    if whole <= FOLD_DEG:
        return None
    # (each part keeps two sides or more: with the curve across, three)
    pairs = [(i, j) for i, j in itertools.combinations(range(n), 2) if j - i >= 2 and n - (j - i) >= 2]
    acrosses = {pair: chord(sides, *pair) for pair in pairs}
    parts = {pair: halves(sides, *pair, acrosses[pair]) for pair in pairs}
    firsts = [default_sides(part, None)[0] for pair in pairs for part in parts[pair]]
    reaches = [_reach(part) for pair in pairs for part in parts[pair]]
    # one reach per batch: each part's own is what its check reads, so screen part by part size
    coarse = [float(patch_turns_deg([first], reach, COARSE_SAMPLES)[0]) for first, reach in zip(firsts, reaches)]
    worse = [max(coarse[2 * k], coarse[2 * k + 1]) for k in range(len(pairs))]
    limit = min(FOLD_DEG, whole - GAIN_DEG)
    best = None
    for k in sorted(range(len(pairs)), key=lambda k: (worse[k], k))[:SHORTLIST]:
        i, j = pairs[k]
        a, b = parts[pairs[k]]
        own_a = own[i:j] + [False]
        own_b = own[j:] + own[:i] + [False]
        # the part that screened worse first: a division is taken only if both parts turn at most
        # `limit` and less than the best so far, so once one does not the other is not measured
        first, second = ((a, own_a), (b, own_b)) if coarse[2 * k] >= coarse[2 * k + 1] else ((b, own_b), (a, own_a))
        bound = limit if best is None else min(limit, best[4] - 1e-9)
        turn = loop_turn_deg(*first)
        if turn > bound:
            continue
        turn = max(turn, loop_turn_deg(*second))
        if turn <= bound:
            best = (i, j, acrosses[pairs[k]], whole, turn)
    return best
