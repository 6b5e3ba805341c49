"""The order and direction of boundary strokes around the loop, before they are closed
(core.closing): the cycle through all strokes whose end-to-start gaps add up least, exact for a few
strokes and greedy for many, with closed rings oriented alike (Qin & Wright, motion-sketch paper
section 2: boundary strokes drawn in any order and direction)."""
from __future__ import annotations

from typing import Sequence

import numpy as np

from .strokes import chord_length
from .types import FloatArray

EXACT_ORDER_MAX = 9
"""Up to this many boundary strokes the loop order is the exact cheapest cycle; above, nearest-end
chaining improved by 2-opt."""

CLOSED_FRACTION = 0.05
"""A stroke whose ends are closer than this fraction of its length is closed (a ring): joining it
either way round costs the same, so its direction is chosen by the opposite side (`_orient_rings`)."""


def _oriented_ends(strokes3d: Sequence[FloatArray]) -> FloatArray:
    """(k, 2, 2, 3): [stroke, reversed?, entry/exit, xyz]."""
    e = np.array([[s[0], s[-1]] for s in strokes3d])
    return np.stack([e, e[:, ::-1]], axis=1)


def _cycle_cost(order: Sequence[int], flags: Sequence[bool], ends: FloatArray, penalty: float) -> float:
    k = len(order)
    gaps = sum(float(np.linalg.norm(ends[order[n], int(flags[n]), 1] - ends[order[(n + 1) % k], int(flags[(n + 1) % k]), 0]))
               for n in range(k))
    return gaps + penalty * sum(bool(f) for f in flags)


def _exact_cycle(ends: FloatArray, penalty: float) -> tuple[list[int], list[bool]]:
    """Cheapest cycle through all strokes, stroke 0 first and as drawn (Held-Karp over oriented
    strokes); the cost is the sum of 3D gaps from each exit to the next entry plus `penalty` per
    reversed stroke (so ties keep the drawing direction)."""
    k = ends.shape[0]
    gap = np.linalg.norm(ends[:, :, None, None, 1, :] - ends[None, None, :, :, 0, :], axis=-1)
    # gap[a, fa, b, fb]: from the exit of a (flag fa) to the entry of b (flag fb)
    best: dict = {(1 << 0, 0, 0): (0.0, None)}
    for mask in range(1, 1 << k):
        if not mask & 1:
            continue
        for last in range(k):
            for fl in (0, 1):
                entry = best.get((mask, last, fl))
                if entry is None:
                    continue
                for nxt in range(1, k):
                    if mask >> nxt & 1:
                        continue
                    for fn in (0, 1):
                        cost = entry[0] + gap[last, fl, nxt, fn] + penalty * fn
                        key = (mask | 1 << nxt, nxt, fn)
                        if key not in best or cost < best[key][0]:
                            best[key] = (cost, (last, fl))
    full = (1 << k) - 1
    last, fl = min(((j, f) for j in range(1, k) for f in (0, 1) if (full, j, f) in best),
                   key=lambda jf: best[(full, jf[0], jf[1])][0] + gap[jf[0], jf[1], 0, 0])
    order, flags, mask = [], [], full
    while last is not None:
        order.append(last)
        flags.append(bool(fl))
        prev = best[(mask, last, fl)][1]
        mask &= ~(1 << last)
        last, fl = prev if prev is not None else (None, None)
    return order[::-1], flags[::-1]


def _greedy_cycle(ends: FloatArray, penalty: float) -> tuple[list[int], list[bool]]:
    """Nearest-end chaining from stroke 0 as drawn, then 2-opt: reverse any run of strokes (order
    and directions) that shortens the cycle, until none does."""
    k = ends.shape[0]
    order, flags, left = [0], [False], set(range(1, k))
    while left:
        here = ends[order[-1], int(flags[-1]), 1]
        j, f = min(((j, f) for j in sorted(left) for f in (0, 1)),
                   key=lambda jf: float(np.linalg.norm(ends[jf[0], jf[1], 0] - here)) + penalty * jf[1])
        order.append(j)
        flags.append(bool(f))
        left.discard(j)
    cost = _cycle_cost(order, flags, ends, penalty)
    improved = True
    while improved:
        improved = False
        for a in range(1, k):
            for b in range(a + 1, k + 1):
                o2 = order[:a] + order[a:b][::-1] + order[b:]
                f2 = flags[:a] + [not f for f in flags[a:b][::-1]] + flags[b:]
                c2 = _cycle_cost(o2, f2, ends, penalty)
                if c2 < cost - 1e-12 * cost:
                    order, flags, cost, improved = o2, f2, c2, True
    return order, flags


def _vector_area(p3: FloatArray) -> FloatArray:
    """3D vector area of a closed polyline (its direction says which way round it runs)."""
    return 0.5 * np.cross(p3, np.roll(p3, -1, axis=0)).sum(axis=0)


def _is_ring(p3: FloatArray) -> bool:
    return float(np.linalg.norm(p3[-1] - p3[0])) <= CLOSED_FRACTION * chord_length(p3)


def _orient_rings(strokes3d: Sequence[FloatArray], order: list[int], flags: list[bool],
                  ends: FloatArray, penalty: float) -> list[bool]:
    """In a loop of four, two opposite rings (closed strokes, e.g. the first and last profile of a
    fuselage) are run in opposite directions along the loop, so that as bottom and top of the Coons
    patch (top reversed) they turn the same way and the surface does not twist. Which of the two
    turns round is the one whose turning leaves the smaller gaps at the ring's ends (the cycle
    cost): turning the later one in the order, as before, made a loop that followed which ring
    came first in the input and which way it was drawn, and the same nacelle with its boundary
    strokes shuffled or reversed closed each ring at its other end, 100 mm away (issue 17,
    TiGL full_nacelle). Gaps equal within `penalty` turn the later one."""
    flags = list(flags)
    if len(order) != 4:
        return flags
    for a in (0, 1):
        sa, sb = strokes3d[order[a]], strokes3d[order[a + 2]]
        if _is_ring(sa) and _is_ring(sb):
            va = _vector_area(sa) * (-1 if flags[a] else 1)
            vb = _vector_area(sb) * (-1 if flags[a + 2] else 1)
            if float(va @ vb) > 0:
                later, first = list(flags), list(flags)
                later[a + 2], first[a] = not flags[a + 2], not flags[a]
                turn_first = _cycle_cost(order, first, ends, 0.0) < _cycle_cost(order, later, ends, 0.0) - penalty
                flags = first if turn_first else later
    return flags


def order_strokes(strokes3d: Sequence[FloatArray], diagonal: float) -> tuple[list[int], list[bool]]:
    """Loop order and reversal flags by end proximity in 3D: the cycle through all strokes whose
    gaps (each stroke's end to the next one's start) add up least.  Unlike an order by angle around
    the centroid this closes loops of any shape (L-shapes, U-shapes, tubes seen edge-on)."""
    k = len(strokes3d)
    if k == 1:
        return [0], [False]
    ends = _oriented_ends(strokes3d)
    penalty = 1e-9 * diagonal
    order, flags = (_exact_cycle if k <= EXACT_ORDER_MAX else _greedy_cycle)(ends, penalty)
    return order, _orient_rings(strokes3d, order, flags, ends, penalty)


