"""Closing rough boundary strokes into one loop (Qin & Wright, motion-sketch paper section 2, Fig. 2b;
2006 paper section 2.1 "a simple pre-processing can be conducted to make them intersect each other").

All 2D work happens in the projection plane; 3D positions follow the same segment parameters, and a
corner is the 3D midpoint of the two strokes' points above the 2D meeting point.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np
import numpy.typing as npt

from .errors import InvalidOptionError, InvalidStrokeError, OpenBoundaryError
from .stroke_order import order_strokes
from .strokes import chord_length, cumulative_length, point_at_length, ramp
from .types import FloatArray, Tolerances

END_TANGENT_FRACTION = 0.1
"""The end direction of a stroke is taken over this fraction of its length (robust to hand jitter)."""

DIRECT_JOIN_RATIO = 3.0
"""When reaching the tangent-line intersection would extend/trim the ends by more than this times the
gap between them (nearly collinear ends), the ends are joined directly at their 3D midpoint instead."""

CORNER_WINDOW = 0.03
"""Turning angles for corner splitting are measured over +-3 % of the loop length."""


def project(points: npt.ArrayLike, origin: FloatArray, axes: FloatArray) -> FloatArray:
    """In-plane coordinates (..., 2) of (..., 3) points."""
    return (np.asarray(points, dtype=float) - origin) @ np.asarray(axes).T


def _cross(a: FloatArray, b: FloatArray) -> FloatArray:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


PARALLEL_SINE = 1e-10
"""Two segments whose directions' sine is below this are parallel (segment_intersections)."""


def segment_intersections(a: FloatArray, b: FloatArray) -> tuple[FloatArray, ...]:
    """All crossings of the segments of 2D polylines a (n, 2) and b (m, 2).

    Returns (i, j, t, s): segment a[i]a[i+1] at fraction t meets b[j]b[j+1] at fraction s
    (closed intervals; parallel segments are ignored, and so are segments within PARALLEL_SINE of
    parallel: on a side drawn as an exact straight line, as a program draws it, the projection's
    round-off alone gave two non-adjacent segments of one line a "crossing" at an arbitrary t, s)."""
    if a.shape[0] < 2 or b.shape[0] < 2:
        return (np.zeros(0, int), np.zeros(0, int), np.zeros(0), np.zeros(0))
    p, r = a[:-1], np.diff(a, axis=0)
    q, e = b[:-1], np.diff(b, axis=0)
    w = q[None, :, :] - p[:, None, :]
    with np.errstate(divide="ignore", invalid="ignore"):
        den = _cross(r[:, None, :], e[None, :, :])
        lengths = np.linalg.norm(r, axis=1)[:, None] * np.linalg.norm(e, axis=1)[None, :]
        den = np.where(np.abs(den) <= PARALLEL_SINE * lengths, 0.0, den)
        t = _cross(w, e[None, :, :]) / den
        s = _cross(w, r[:, None, :]) / den
    ok = np.isfinite(t) & np.isfinite(s) & (t >= 0) & (t <= 1) & (s >= 0) & (s <= 1)
    i, j = np.nonzero(ok)
    return i, j, t[i, j], s[i, j]


@dataclass(frozen=True)
class ClosedSide:
    """One side of the closed loop.

    points         : (n, 3) float, from the corner before to the corner after
    source         : input stroke indices whose points it holds
    key            : (lowest input index, part number along that stroke): orders sides intrinsically
    reversed_input : True when it runs against the drawing direction of stroke key[0]
    """

    points: FloatArray
    source: tuple[int, ...]
    key: tuple[int, int]
    reversed_input: bool

    def reversed(self) -> "ClosedSide":
        return ClosedSide(self.points[::-1].copy(), self.source, self.key, not self.reversed_input)


def _end_direction(p3: FloatArray, at_end: bool) -> FloatArray:
    """3D direction pointing out of the stroke at its end (at_end) or start."""
    length = chord_length(p3)
    h = END_TANGENT_FRACTION * length
    if at_end:
        return p3[-1] - point_at_length(p3, length - h)
    return p3[0] - point_at_length(p3, h)


@dataclass(frozen=True)
class _Corner:
    point: FloatArray  # (3,)
    keep_until: int  # the previous stroke keeps vertices [.. keep_until)
    keep_from: int  # the next stroke keeps vertices [keep_from ..)
    note: str
    own_a: FloatArray | None = None  # the previous stroke's own point at the corner (before the midpoint)
    own_b: FloatArray | None = None  # the next stroke's own point at the corner


def _close_corner(a3: FloatArray, b3: FloatArray, origin: FloatArray, axes: FloatArray,
                  limit: float, names: tuple[int, int], same: bool = False) -> _Corner:
    """Where stroke a (ending) meets stroke b (starting): the crossing or the meeting point of the two
    end tangents nearest the ends, or the midpoint of the ends when the tangents are nearly parallel."""
    a2, b2 = project(a3, origin, axes), project(b3, origin, axes)
    ca, cb = cumulative_length(a2), cumulative_length(b2)
    ia0 = int(np.searchsorted(ca, 0.5 * ca[-1], side="right")) - 1
    ib1 = int(np.searchsorted(cb, 0.5 * cb[-1], side="left")) + 1
    ia0, ib1 = max(0, min(ia0, len(a2) - 2)), max(2, min(ib1, len(b2)))
    da3, db3 = _end_direction(a3, True), _end_direction(b3, False)
    da2, db2 = da3 @ axes.T, db3 @ axes.T
    na, nb = float(np.linalg.norm(da2)), float(np.linalg.norm(db2))
    reach = 2.0 * limit
    ext_a = a3[-1] + (da3 / na * reach if na > 1e-12 * limit else 0.0 * da3)
    ext_b = b3[0] + (db3 / nb * reach if nb > 1e-12 * limit else 0.0 * db3)
    tail3 = np.vstack([a3[ia0:], ext_a])
    head3 = np.vstack([ext_b, b3[:ib1]])
    tail2, head2 = project(tail3, origin, axes), project(head3, origin, axes)
    i, j, t, s = segment_intersections(tail2, head2)
    if same:  # closing a single stroke on itself: ignore the shared middle of its two halves
        far = (i == len(tail2) - 2) | (j == 0) | (np.abs(ia0 + i - (j - 1)) > 1)
        i, j, t, s = i[far], j[far], t[far], s[far]
    gap_ends = float(np.linalg.norm(a2[-1] - b2[0]))
    end_gap3 = float(np.linalg.norm(a3[-1] - b3[0]))
    la, lb = ca[-1], cb[-1]
    if i.size:
        seg_a = np.linalg.norm(np.diff(tail2, axis=0), axis=1)
        seg_b = np.linalg.norm(np.diff(head2, axis=0), axis=1)
        pos_a = (ca[ia0] + np.concatenate([[0.0], np.cumsum(seg_a)])[i] + t * seg_a[i]) - la
        pos_b = (np.concatenate([[0.0], np.cumsum(seg_b)])[j] + s * seg_b[j]) - seg_b[0]
        cost = np.abs(pos_a) + np.abs(pos_b)
        k = int(np.argmin(cost))
        extension = max(pos_a[k], 0.0) + max(-pos_b[k], 0.0)
        crossing = pos_a[k] <= 0 and pos_b[k] >= 0
        ik, jk = int(i[k]), int(j[k])
        pa = tail3[ik] + t[k] * (tail3[ik + 1] - tail3[ik])
        pb = head3[jk] + s[k] * (head3[jk + 1] - head3[jk])
        # a crossing in projection only is not a corner when the strokes are far apart in depth there
        # (a ring seen edge-on): then the ends are joined in 3D below
        apart = float(np.linalg.norm(pa - pb)) > max(2.0 * end_gap3, 1e-3 * limit)
        if not apart and (crossing or cost[k] <= DIRECT_JOIN_RATIO * gap_ends + 1e-12 * limit):
            if extension > limit:
                raise _gap_error(names, extension, limit)
            keep_until = len(a3) if ik == len(tail3) - 2 else ia0 + ik + 1
            keep_from = 0 if jk == 0 else jk
            what = ("cut at their crossing" if crossing else
                    f"extended in the projection plane by {extension:.3g} mm to meet")
            trimmed = max(-pos_a[k], 0.0) + max(pos_b[k], 0.0)
            tiny = 1e-9 * limit
            what = "cut at their crossing" if extension <= tiny else what
            trimmed = 0.0 if trimmed <= tiny else trimmed
            note = f"corner of strokes {names[0]}->{names[1]}: {what}" + (
                f", {trimmed:.3g} mm of overshoot trimmed" if trimmed > 0 else "")
            return _Corner(0.5 * (pa + pb), keep_until, keep_from, note, pa, pb)
    if end_gap3 > limit:
        raise _gap_error(names, end_gap3, limit)
    note = f"corner of strokes {names[0]}->{names[1]}: ends {end_gap3:.3g} mm apart joined at their 3D midpoint"
    return _Corner(0.5 * (a3[-1] + b3[0]), len(a3), 0, note, a3[-1], b3[0])


def _gap_error(names: tuple[int, int], width: float, limit: float) -> OpenBoundaryError:
    return OpenBoundaryError(
        f"the gap between the end of stroke {names[0]} and the start of stroke {names[1]} is {width:.4g} mm "
        f"wide, more than the limit of {limit:.4g} mm (Tolerances.gap_factor x sketch diagonal); draw the "
        "strokes closer together or raise gap_factor")


SEAM_FRACTION = 0.02
"""Two opposite sides closer than this fraction of their length everywhere are one seam of a tube."""


CORNER_SPLIT_DEG = 40.0
"""A three-sided loop is split where one side turns by at least this much (and at least half as
much as the loop turns at its weakest corner), far from its ends: a fourth corner drawn in one stroke."""


def _turning(loop2d: FloatArray) -> FloatArray:
    """Turning angle (rad) at each vertex of a closed 2D polyline, over a window of the loop length."""
    seg = np.linalg.norm(np.diff(np.vstack([loop2d, loop2d[:1]]), axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    total = s[-1]
    s = s[:-1]
    h = CORNER_WINDOW * total
    ext = np.vstack([loop2d, loop2d, loop2d[:1]])  # twice around, to look across the seam
    ext_s = np.concatenate([s, s + total, [2.0 * total]])
    before = np.stack([np.interp(s - h + total, ext_s, ext[:, c]) for c in range(2)], axis=1)
    after = np.stack([np.interp(s + h, ext_s, ext[:, c]) for c in range(2)], axis=1)
    v1, v2 = loop2d - before, after - loop2d
    return np.abs(np.arctan2(_cross(v1, v2), np.sum(v1 * v2, axis=1)))


def _split_at_corners(points3d: FloatArray, owner: np.ndarray, origin: FloatArray, axes: FloatArray,
                      flipped: dict[int, bool]) -> tuple[list[ClosedSide], str]:
    """Split a closed loop drawn as one or two strokes at its 3 or 4 sharpest corners (largest turning
    angles in projection, at least a tenth of the loop apart)."""
    loop3d = points3d[:-1]  # the last point repeats the first
    own = owner[:-1]
    uv = project(loop3d, origin, axes)
    turn = _turning(uv)
    cum = cumulative_length(np.vstack([uv, uv[:1]]))[:-1]
    total = cumulative_length(np.vstack([uv, uv[:1]]))[-1]
    picked: list[int] = []
    for idx in np.argsort(-turn, kind="stable"):
        d = np.abs(cum[idx] - cum[picked])
        if np.all(np.minimum(d, total - d) >= 0.1 * total):  # (True for the first pick)
            picked.append(int(idx))
        if len(picked) == 4:
            break
    if len(picked) < 3:
        raise OpenBoundaryError(
            f"the boundary drawn as {len(set(own.tolist()))} stroke(s) has fewer than 3 corners; "
            "draw at least 3 boundary sides")
    if len(picked) == 4 and turn[picked[3]] < 0.5 * turn[picked[2]]:
        picked = picked[:3]
    corners = sorted(picked)
    sides = []
    for n, c in enumerate(corners):
        nxt = corners[(n + 1) % len(corners)]
        idx = np.arange(c, nxt + 1) if nxt > c else np.concatenate([np.arange(c, len(loop3d)), np.arange(0, nxt + 1)])
        src = tuple(sorted(set(own[idx].tolist())))
        sides.append(ClosedSide(loop3d[idx], src, (min(src), n), flipped[min(src)]))
    angles = ", ".join(f"{np.degrees(turn[c]):.0f}" for c in corners)
    return sides, f"boundary of {len(set(own.tolist()))} stroke(s) split at {len(corners)} corners (turning {angles} deg)"


def _check_simple(sides: Sequence[ClosedSide], origin: FloatArray, axes: FloatArray) -> None:
    """OpenBoundaryError when the closed loop crosses or touches itself in projection."""
    loop = np.concatenate([s.points[:-1] for s in sides])
    owner = np.concatenate([np.full(len(s.points) - 1, min(s.source)) for s in sides])
    uv = project(loop, origin, axes)
    step = np.linalg.norm(np.diff(np.vstack([uv, uv[:1]]), axis=0), axis=1)
    keep = step > 1e-12 * np.abs(uv).max()  # no zero-length segments
    loop, owner, uv = loop[keep], owner[keep], uv[keep]
    uv = np.vstack([uv, uv[:1]])
    n = uv.shape[0] - 1
    for start in range(0, n, 256):
        i, j, _, _ = segment_intersections(uv[start:min(start + 257, n + 1)], uv)
        i = i + start
        gap = np.abs(i - j)
        bad = (gap > 1) & (gap < n - 1)
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            p = loop[i[k]]
            raise OpenBoundaryError(
                f"the closed boundary crosses itself in projection near ({p[0]:.4g}, {p[1]:.4g}, {p[2]:.4g}) "
                f"(strokes {owner[i[k]]} and {owner[j[k] % n]}); check that the boundary strokes go once "
                "around the surface, or name the boundary strokes explicitly")


def _ramp_to_corners(inner: FloatArray, before: _Corner, after: _Corner) -> FloatArray:
    """Stroke points between two corners, moved so that they run smoothly into both corner points.
    The corner is the 3D midpoint of the two strokes' points there, so each stroke is off it by half
    their distance in depth: strokes.ramp spreads that over the stroke's last stretch."""
    if len(inner) < 2:
        return inner
    run = cumulative_length(inner)
    total = float(run[-1])
    if total <= 0:
        return inner
    out = np.array(inner, dtype=float)
    for corner, own, dist in ((before, before.own_b, run), (after, after.own_a, total - run)):
        if own is None:
            continue
        offset = ramp(dist, np.asarray(corner.point, dtype=float) - np.asarray(own, dtype=float), total)
        if offset is not None:
            out += offset
    return out


def close_loop(strokes: Sequence[FloatArray], names: Sequence[int], plane, tol: Tolerances,
               diagonal: float) -> tuple[list[ClosedSide], list[str]]:
    """Order, orient, cut and extend boundary strokes into a closed loop of sides.

    strokes : (n_i, 3) validated boundary strokes; names: their input indices (for messages/source)
    Returns the sides (>= 3) in loop order, each ending exactly where the next starts, and notes.
    """
    if not (np.isfinite(tol.gap_factor) and tol.gap_factor > 0):
        raise InvalidOptionError(f"Tolerances.gap_factor={tol.gap_factor!r}; give a positive fraction such as 0.25")
    if not strokes:
        raise OpenBoundaryError("no boundary strokes; a boundary needs at least 3 sides")
    origin, axes = plane.origin, plane.axes
    limit = tol.gap_factor * diagonal
    for s, name in zip(strokes, names):
        if not chord_length(project(s, origin, axes)) > 1e-9 * max(diagonal, 1e-300):
            raise InvalidStrokeError(
                f"boundary stroke {name} has no length in the projection plane; draw it along the boundary")
    order, flags = order_strokes(strokes, diagonal)
    loop = [strokes[i][::-1] if f else strokes[i] for i, f in zip(order, flags)]
    ids = [names[i] for i in order]
    k = len(loop)
    try:
        corners = [_close_corner(loop[n], loop[(n + 1) % k], origin, axes, limit, (ids[n], ids[(n + 1) % k]),
                                 same=k == 1) for n in range(k)]
    except OpenBoundaryError as exc:
        raise OpenBoundaryError(f"boundary strokes {ids} (in loop order): {exc}") from None
    notes = [c.note for c in corners]
    sides = []
    for n in range(k):
        before, after = corners[n - 1], corners[n]
        inner = _ramp_to_corners(loop[n][before.keep_from:after.keep_until], before, after)
        pts = np.vstack([before.point, inner, after.point])
        keep = np.concatenate([[True], np.linalg.norm(np.diff(pts, axis=0), axis=1) > 1e-12 * diagonal])
        keep[-1] = True
        pts = pts[keep]
        if np.linalg.norm(pts[-2] - pts[-1]) <= 1e-12 * diagonal and len(pts) > 2:
            pts = np.delete(pts, -2, axis=0)
        sides.append((pts, ids[n], flags[n]))
    if k <= 2:
        pts = np.concatenate([sides[0][0]] + [s[0][1:] for s in sides[1:]])
        owner = np.concatenate([np.full(len(sides[0][0]), sides[0][1])] +
                               [np.full(len(s[0]) - 1, s[1]) for s in sides[1:]])
        if np.linalg.norm(pts[0] - pts[-1]) > 0:
            pts, owner = np.vstack([pts, pts[:1]]), np.append(owner, owner[0])
        closed, note = _split_at_corners(pts, owner, origin, axes, dict(zip(ids, flags)))
        notes.append(note)
    else:
        closed = [ClosedSide(p, (name,), (name, 0), f) for p, name, f in sides]
    if len(closed) == 3:
        closed, note = _split_strong_corner(closed, origin, axes)
        notes += [note] if note else []
    seam = _seam(closed)
    if seam:
        notes.append(seam)
    else:
        try:
            _check_simple(closed, origin, axes)
        except OpenBoundaryError as exc:
            raise OpenBoundaryError(f"boundary strokes {ids} (in loop order): {exc}") from None
    return closed, notes


def _split_strong_corner(sides: list[ClosedSide], origin: FloatArray,
                         axes: FloatArray) -> tuple[list[ClosedSide], str]:
    """Three sides, but one stroke turns a corner in its middle (an L drawn in one go): split it
    there, giving four sides.  The corner is the sharpest turn (in projection, over +-3 % of the
    loop) at least a tenth of the loop away from the three corners, if it turns by at least
    CORNER_SPLIT_DEG and at least half as much as the weakest of the three corners."""
    pts = np.concatenate([sd.points[:-1] for sd in sides])
    side_of = np.concatenate([np.full(len(sd.points) - 1, n) for n, sd in enumerate(sides)])
    at = np.concatenate([[0], np.cumsum([len(sd.points) - 1 for sd in sides])])
    uv = project(pts, origin, axes)
    turn = _turning(uv)
    cum = cumulative_length(np.vstack([uv, uv[:1]]))
    total, cum = cum[-1], cum[:-1]
    d = np.abs(cum[:, None] - cum[at[:3]][None, :])
    far = np.min(np.minimum(d, total - d), axis=1) >= 0.1 * total
    if total <= 0 or not far.any():
        return sides, ""
    cand = np.flatnonzero(far)
    best = int(cand[np.argmax(turn[cand])])
    weakest = float(turn[at[:3]].min())
    if turn[best] < max(np.radians(CORNER_SPLIT_DEG), 0.5 * weakest):
        return sides, ""
    n = int(side_of[best])
    cut = best - int(at[n])
    sd = sides[n]
    first, second = sd.points[:cut + 1], sd.points[cut:]
    key0, key1 = sd.key, (sd.key[0], sd.key[1] + 1)
    if sd.reversed_input:  # parts are numbered along the stroke as drawn
        key0, key1 = key1, key0
    parts = [ClosedSide(first, sd.source, key0, sd.reversed_input),
             ClosedSide(second, sd.source, key1, sd.reversed_input)]
    out = sides[:n] + parts + sides[n + 1:]
    return out, (f"stroke {sd.source[0]} split where it turns {np.degrees(turn[best]):.0f} deg "
                 f"(at {pts[best].round(3).tolist()}): a fourth corner")


def _seam(sides: Sequence[ClosedSide]) -> str:
    """A note when two opposite sides of a four-sided loop coincide in 3D (the seam of a tube, e.g.
    the first and last guide of a fuselage); such a loop is closed in 3D but folds in any projection,
    so it is not checked for crossings there.  Empty when there is no seam."""
    if len(sides) != 4:
        return ""
    for a in (0, 1):
        pa, pb = sides[a].points, sides[a + 2].points[::-1]
        la, lb = chord_length(pa), chord_length(pb)
        if la <= 0 or lb <= 0 or abs(la - lb) > 0.1 * max(la, lb):  # noise lengthens strokes
            continue
        t = np.linspace(0.0, 1.0, 64)
        qa, qb = point_at_length(pa, t * la), point_at_length(pb, t * lb)
        if float(np.linalg.norm(qa - qb, axis=1).max()) <= SEAM_FRACTION * max(la, lb):
            return (f"sides of strokes {list(sides[a].source)} and {list(sides[a + 2].source)} coincide: "
                    "the boundary is cut open along a seam (a tube); its projection is not checked for crossings")
    return ""
