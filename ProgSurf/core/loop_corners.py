"""Where a loop of a stroke network gets its corners, when its Coons patch would fold (issue 18).

A loop of curves is filled with a 4-sided (or 3-sided) Coons patch (boundary.boundary_from_sides):
its sides are the network's edges, merged to four by the 2006 paper's rule (adjacent sides whose
chords turn least), so its corners are nodes of the network. On rough VR sketches the patch that
rule gives often turns over on itself with no interior stroke at all (CASSIE 10-2-1: 39 of its
45 surfaces folded, most of them a single face): a corner put where the loop runs straight on and
none where it turns makes the blended sides cross. Which four points of a loop are its corners is
a choice the strokes do not make (Mullineux fills n-sided nets by choosing how to divide them); a
corner anywhere on the loop keeps the loop's curves as they are, so two surfaces still share each
curve exactly.

:func:`choose_sides` keeps the paper's corners unless their base patch folds (its normal turns by
more than FOLD_DEG inside it, from its mean normal or within TUCK_REACH of the loop's diagonal:
the built face's checks, cad.analysis). Then every choice of four corners, or three with each of
them as the apex, among the loop's nodes and the middles of its sides is tried on the Coons patch
itself (every choice screened on a coarse grid, the best few measured on the checks' own), and
the one that turns least is taken when it turns at least GAIN_DEG less.
"""
from __future__ import annotations

import itertools
from typing import Optional, Sequence

import numpy as np

from .boundary import best_fit_plane, merge_to_four, triangle_apex, turn_to_apex
from .coons import coons_blend, df1, f1, f2
from .folds import (FACE_SAMPLES, FACE_TURN_DEG, FOLD_DENSE, TUCK_REACH, _face_samples, _turns_from_mean_deg,
                    inset_grid, tangent_corner, tucks_deg)
from .strokes import cumulative_length, point_at_length
from .types import FloatArray

FOLD_DEG = FACE_TURN_DEG
"""A base patch whose normal turns more than this inside it folds (the core's face check)."""

GAIN_DEG = 10.0
"""Other corners are taken only when their patch turns at least this much less."""

TRIANGLE_COST_DEG = 5.0
"""A 3-corner choice counts this much worse than a 4-corner one that turns as much: a collapsed
side is a point with no normal, kept for where four corners cannot do."""

COARSE_SAMPLES = 4
"""Samples per side of the fold grids on which every choice is screened ..."""

SHORTLIST = 8
"""... and how many of the best screened are measured on the fold checks' own samples."""

CREASE_SAMPLES = 33
"""Samples per side of the grid on which a patch's crease is read (patch_creases_deg)."""

CREASE_INSET = 0.1
"""... in from the sides by this share: by a corner, where two sides meet at a point or a triangle's
sides close on its apex, the normal turns round quickly however smooth the patch (helibody's
noisy triangles: 120-164 deg between samples at 6 % from a corner, faces built fine)."""

CREASE_DEG = 90.0
"""Other corners whose patch turns more than this between neighbouring samples (a fold line) are
not taken where the paper corners' patch does not: a patch that bends far over but smoothly
(a nacelle's lip, its sides U-shaped round it) reads as folding on the turn checks, and corners that
turn less on them twisted it into a band folded along a line (TiGL full_nacelle)."""

MAX_TRIES = 400
"""At most this many corner choices per loop: with more places than that allows, only the
loop's nodes are corner places (the sides' middles are left out)."""


def _arc_params(points: FloatArray) -> Optional[FloatArray]:
    """Arc-length parameters 0..1 of a polyline's points (boundary.BoundaryLoop's mapping), two
    points at one place a hair apart; None for a polyline of no length."""
    step = np.linalg.norm(np.diff(points, axis=0), axis=1)
    total = float(step.sum())
    if not total > 0:
        return None
    prm = np.concatenate([[0.0], np.cumsum(np.maximum(step, 1e-9 * total / len(step)))])
    return prm / prm[-1]


def patch_turn_deg(sides: Sequence[FloatArray], reach: float, samples: int = FACE_SAMPLES) -> float:
    """How far the Coons patch of a loop's 3 or 4 sides (loop order, each starting where the one
    before ends; with 3, the corner after sides[1] is the apex) turns inside it: the larger of the
    largest angle of its normal from their mean and the largest between two normals closer than
    `reach` (folds.turn_from_mean_deg, folds.tuck_deg), on the fold checks' samples (`samples`
    per side of their grids)."""
    return patch_turns_deg([sides], reach, samples)[0]


def patch_turns_deg(choices: Sequence[Sequence[FloatArray]], reach: float,
                    samples: int = FACE_SAMPLES, dense: bool = False) -> list[float]:
    """patch_turn_deg of several choices of sides at once (choose_sides screens hundreds). A side
    array met again (the same object, at the same place in a choice) is evaluated once. The
    arithmetic is per patch, so one choice gives what it gives alone. dense: the turn from the
    mean normal is read on the FOLD_DENSE grid too (folds.inset_grid: the built face's check reads it there)."""
    if not choices:
        return []
    points, normals, ok = _patch_frames(choices, *_face_samples(samples))
    turns = _turns_from_mean_deg(list(zip(normals, ok)))
    if dense:
        _, fine, good = _patch_frames(choices, *inset_grid(FOLD_DENSE))
        turns = [max(a, b) for a, b in zip(turns, _turns_from_mean_deg(list(zip(fine, good))))]
    return [max(a, b) for a, b in zip(turns, tucks_deg(normals, ok, points, reach))]


def patch_creases_deg(choices: Sequence[Sequence[FloatArray]], samples: int = CREASE_SAMPLES) -> list[float]:
    """Per choice of sides (as patch_turns_deg takes them), the largest angle (deg) between the
    normals of neighbouring samples of its Coons patch on a samples x samples grid CREASE_INSET in
    from its sides: a smooth patch, however far it bends over, turns a little from one sample to the
    next; one folded along a line turns over between the two samples either side of it."""
    if not choices:
        return []
    g = np.linspace(CREASE_INSET, 1.0 - CREASE_INSET, samples)
    s, r = (a.ravel() for a in np.meshgrid(g, g, indexing="ij"))
    _, normals, ok = _patch_frames(choices, s, r)
    grid = normals.reshape(len(choices), samples, samples, 3)
    good = ok.reshape(len(choices), samples, samples)
    out = []
    for n, k in zip(grid, good):
        cos = [np.where(k[1:] & k[:-1], (n[1:] * n[:-1]).sum(axis=-1), 1.0),
               np.where(k[:, 1:] & k[:, :-1], (n[:, 1:] * n[:, :-1]).sum(axis=-1), 1.0)]
        out.append(float(np.degrees(np.arccos(min(max(min(c.min() for c in cos), -1.0), 1.0)))))
    return out


def _patch_frames(choices: Sequence[Sequence[FloatArray]], s: FloatArray, r: FloatArray) -> tuple:
    """The Coons patches of several choices of sides at local (s, r) (k,): their points and unit
    normals (m, k, 3) and (m, k) where the normal is defined."""
    # each side at the samples' parameters and a step either side (their tangents), in one go
    h = 1e-6
    at_u = np.concatenate([s, np.minimum(s + h, 1.0), np.maximum(s - h, 0.0)])
    at_v = np.concatenate([r, np.minimum(r + h, 1.0), np.maximum(r - h, 0.0)])
    seen: dict = {}

    def value(side: FloatArray, place: int) -> FloatArray:
        key = (id(side), place)
        if key not in seen:
            pts = side if place < 2 else side[::-1]
            t = at_u if place % 2 == 0 else at_v
            prm = _arc_params(pts)
            seen[key] = (side, np.repeat(pts[:1], len(t), axis=0) if prm is None else
                         np.column_stack([np.interp(t, prm, pts[:, k]) for k in range(3)]))
        return seen[key][1]            # (the side is held with its value: its id stays its own)

    values, corners = [[], [], [], []], []
    for sides in choices:
        pts = [np.asarray(x, dtype=float) for x in sides]
        if len(pts) == 3:
            tip = pts[1][-1]
            pts = [pts[0], pts[1], np.stack([tip, tip]), pts[2]]
        for place in range(4):
            values[place].append(value(pts[place], place))
        corners.append([pts[0][0], pts[0][-1], pts[1][-1], pts[3][0]])
    n = len(s)
    (b0, b1, b2), (r0, r1, r2), (t0, t1, t2), (l0, l1, l2) = (
        [x[:, :n], x[:, n:2 * n], x[:, 2 * n:]] for x in (np.stack(v) for v in values))
    du = (at_u[n:2 * n] - at_u[2 * n:])[:, None]
    dv = (at_v[n:2 * n] - at_v[2 * n:])[:, None]
    corner = np.asarray(corners, dtype=float)[:, :, None, :]          # (m, 4, 1, 3)
    p00, p10, p11, p01 = (corner[:, i] for i in range(4))
    points = coons_blend(s, r, (b0, r0, t0, l0), np.moveaxis(corner, 1, 0))
    # its partial derivatives, Eq. 1 differentiated (the sides' by their central differences)
    fu1, fu2, fv1, fv2 = f1(s)[:, None], f2(s)[:, None], f1(r)[:, None], f2(r)[:, None]
    du1, dv1 = df1(s)[:, None], df1(r)[:, None]
    pu = (du1 * (l0 - r0) + fv1 * (b1 - b2) / du + fv2 * (t1 - t2) / du
          - du1 * ((fv1 * p00 + fv2 * p01) - (fv1 * p10 + fv2 * p11)))
    pv = (fu1 * (l1 - l2) / dv + fu2 * (r1 - r2) / dv + dv1 * (b0 - t0)
          - fu1 * dv1 * (p00 - p01) - fu2 * dv1 * (p10 - p11))
    cross = np.cross(pu, pv)
    size = np.linalg.norm(cross, axis=-1)
    ok = size > 1e-12 * np.maximum(size.max(axis=1, initial=0.0), 1e-300)[:, None]
    normals = cross / np.where(ok, size, 1.0)[..., None]
    sine = size / np.maximum(np.linalg.norm(pu, axis=-1) * np.linalg.norm(pv, axis=-1), 1e-300)
    ok &= ~tangent_corner(s[None, :], r[None, :], sine)
    return points, normals, ok


def _places(sides: Sequence[FloatArray], middles: Sequence[bool]) -> tuple[FloatArray, list]:
    """The loop as one closed polyline (points, without repeating its start) and the indices in it
    of the corner places: every side's start, and where `middles` says so the point halfway along it."""
    pts, places = [], []
    for s, middle in zip(sides, middles):
        s = np.asarray(s, dtype=float)
        places.append(len(pts))
        if middle and len(s) >= 2:
            cum = cumulative_length(s)
            half = 0.5 * cum[-1]
            k = int(np.searchsorted(cum, half))
            if 0 < k < len(s) - 1:
                places.append(len(pts) + k)
            elif len(s) == 2 and cum[-1] > 0:    # a straight side: put a point in its middle
                pts.append(s[0])
                places.append(len(pts))
                pts.append(point_at_length(s, half))
                continue
        pts.extend(s[:-1])
    return np.asarray(pts), places


def _cut(loop: FloatArray, at: Sequence[int], made: Optional[dict] = None) -> list:
    """The sides between the corners at loop indices `at` (in loop order, cyclically); `made`
    keeps each side made, by its ends, to hand the same array out again."""
    n = len(loop)
    made = {} if made is None else made
    out = []
    for a, b in zip(at, list(at[1:]) + [at[0]]):
        if (a, b) not in made:
            made[a, b] = loop[np.arange(a, (b if b > a else b + n) + 1) % n]
        out.append(made[a, b])
    return out


def default_sides(sides: Sequence[FloatArray], inside_ends: Optional[FloatArray] = None) -> tuple[list, int]:
    """The 3 or 4 sides boundary.boundary_from_sides makes of a loop's sides (the paper's merge;
    a triangle turned so that its apex, triangle_apex, is the corner after sides[1]), and that apex
    (1 for a triangle, -1 for four sides)."""
    pts = [np.asarray(s, dtype=float) for s in sides]
    if len(pts) > 4:
        four = merge_to_four(pts, best_fit_plane(np.concatenate(pts)))
        return [four[0], four[1], four[2], four[3]], -1
    if len(pts) == 3:
        return turn_to_apex(pts, triangle_apex(pts, inside_ends)), 1
    return pts, -1


def choose_sides(sides: Sequence[FloatArray], inside_ends: Optional[FloatArray] = None,
                 own: Optional[Sequence[bool]] = None) -> Optional[tuple[list, int, float, float]]:
    """Other corners for a loop whose paper corners give a folding base patch (module docstring).

    sides     : the loop's sides (n >= 3), in loop order, each starting where the one before ends
    inside_ends: the ends of the strokes inside the loop (the triangle's apex, triangle_apex)
    own       : per side, whether no other surface bounds itself by it: only there may a corner be
                put in its middle (a surface whose vertex lies inside its neighbour's edge is not
                sewn to it); None = every side
    Returns None to keep the paper's corners, else (the 3 or 4 new sides in loop order, the apex
    index (1) for 3 sides or -1, the paper corners' turn, the new corners' turn; deg)."""
    if len(sides) < 3:
        return None
    every = np.concatenate([np.asarray(x, dtype=float) for x in sides])
    # the tuck reach of the built surface's check: a share of the diagonal of its own faces
    reach = TUCK_REACH * float(np.linalg.norm(every.max(axis=0) - every.min(axis=0)))
    first, _ = default_sides(sides, inside_ends)
    base = patch_turns_deg([first], reach, dense=True)[0]
    if base <= FOLD_DEG:
        return None
    own = [True] * len(sides) if own is None else list(own)
    loop, places = _places(sides, own)
    if _tries(len(places)) > MAX_TRIES:
        loop, places = _places(sides, [False] * len(sides))
        if _tries(len(places)) > MAX_TRIES:
            return None
    # every choice on a coarse grid of samples, then the SHORTLIST best on the checks' own
    tries = [(at, -1) for at in itertools.combinations(places, 4)]
    # three corners, each the apex in turn (the corner after side 1)
    tries += [(at[k + 1:] + at[:k + 1], 1) for at in itertools.combinations(places, 3) for k in range(3)]
    cost = [TRIANGLE_COST_DEG if apex == 1 else 0.0 for _, apex in tries]
    cuts: dict = {}                   # one array per side: patch_turns_deg evaluates each once
    coarse = [t + c for t, c in zip(patch_turns_deg([_cut(loop, at, cuts) for at, _ in tries], reach,
                                                    COARSE_SAMPLES), cost)]
    best = (base - GAIN_DEG, None, -1)
    short = sorted(range(len(tries)), key=lambda i: (coarse[i], i))[:SHORTLIST]
    shortlisted = [_cut(loop, tries[k][0], cuts) for k in short]
    fine = patch_turns_deg(shortlisted, reach, dense=True)
    # no choice that folds along a line where the paper corners' patch only bends
    crease, *creases = patch_creases_deg([first] + shortlisted)
    for k, measured, folded in zip(short, fine, creases):
        at, apex = tries[k]
        turn = measured + cost[k]
        if crease <= CREASE_DEG < folded:
            continue
        if turn < best[0] - 1e-9:
            best = (turn, at, apex)
    turn, at, apex = best
    if at is None:
        return None
    return _cut(loop, at), apex, base, turn - (TRIANGLE_COST_DEG if apex == 1 else 0.0)


def _tries(places: int) -> int:
    from math import comb
    return comb(places, 4) + 3 * comb(places, 3)
