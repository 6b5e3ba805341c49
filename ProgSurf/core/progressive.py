"""Progressive update of the patch network by one interior stroke: Qin & Wright section 3
(2006 text, steps (1)-(9), Fig. 5-8; motion-sketch text, Eq. 2 and Fig. 5 cases a-d).

One call of :func:`add_stroke` either accepts the stroke and changes the network, or rejects it
with a reason and leaves the network exactly as it was. This module holds that call and its
record: a closed stroke made two open ones, each open stroke's ends placed (steps (2), (6); in
:mod:`.stroke_ends`), its pre-image split into straight pieces (step (6), last paragraph), and the
pieces inserted one after the other (steps (3)-(5), (7)-(8); in :mod:`.stroke_insertion`, with
the crossings planned in :mod:`.node_planning`).
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Optional

import numpy as np

from .errors import (ProgSurfError, StrokeFoldsError, StrokeOutsideSurfaceError, StrokeRejectedError,
                     StrokeRunsAlongCurveError)
from .fold_repair import repair_folds
from .network import PatchNetwork
from . import off_surface
from .off_surface import as_drawn, drawn_off, end_misses, may_be_off, normals_at, onto_crossings
from .stroke_ends import StrokeEnd, end_of, placed_end, trim_ends
from .stroke_insertion import insert_piece
from .types import FloatArray, Tolerances

MAX_DEPTH = 5
"""Recursion depth of the pre-image straightness test (up to 32 straight pieces)."""


@dataclass(frozen=True)
class StrokeRecord:
    """What happened to one stroke.

    index   : the stroke's position in the input
    role    : "boundary" or "interior"
    status  : "accepted" or "rejected"
    reason  : why it was rejected, or a short note of what was done
    pre_image : (k, 2) the pre-image polyline in the unit square (with extensions), or None
    curve_ids : network curves made from this stroke (one per straight piece)
    regions_created, regions_removed : region ids
    pulled_curves : ids of earlier curves pulled to this stroke (later strokes win)
    ends    : how each end was placed: "snapped" (on/crossing a boundary) or "footpoint"
    end_offsets_mm : |Q - F| at each end placed by a footpoint (0 for snapped ends)
    points  : (n, 3) the stroke as it was used (filtered, faired, trimmed), or None
    fair_deviation_mm : largest distance of the filtered stroke from its faired curve
    merged_curves : ids of earlier curves an end of this stroke retraced and was merged into (it
              stops at the node where it leaves them: node_planning._plan_nodes(merge_ends=))
    """

    index: int
    role: str
    status: str
    reason: str = ""
    pre_image: Optional[FloatArray] = None
    curve_ids: tuple = ()
    regions_created: tuple = ()
    regions_removed: tuple = ()
    pulled_curves: tuple = ()
    ends: tuple = ()
    end_offsets_mm: tuple = ()
    points: Optional[FloatArray] = None
    fair_deviation_mm: float = 0.0
    merged_curves: tuple = ()


FOLD_REASON = "it would fold the surface"
"""How the record of a stroke rejected for folding the surface begins (StrokeFoldsError)."""

STRAIGHT_NOTE = ("taken as one straight piece of the pre-image (its bent pieces, each extended across "
                 "its region, folded the surface)")


@dataclass
class _Work:
    """What add_stroke has done so far, for its record: per straight piece its pre-image ends (2, 2),
    curve id, end kinds and end offsets; the ids of the earlier curves pulled to the stroke, and
    its misses of the earlier stroke curves it crossed (stroke_insertion._place_nodes); its ends
    merged into a curve they retrace: (curve id, fraction of the piece's pre-image, which end)."""

    pre_image: list = field(default_factory=list)
    curve_ids: list = field(default_factory=list)
    pulled: set = field(default_factory=set)
    ends: list = field(default_factory=list)
    offsets: list = field(default_factory=list)
    misses: list = field(default_factory=list)
    merged: list = field(default_factory=list)
    bent: bool = False          # its pre-image was split into straight pieces
    folded: bool = False        # it was rejected for folding the surface (StrokeFoldsError)


def add_stroke(net: PatchNetwork, stroke: FloatArray, index: int, tol: Tolerances, snap: float,
               falloff: str = "linear") -> StrokeRecord:
    """Add one interior stroke (steps (1)-(9)); never raises for a bad stroke: the record says why.

    stroke : (n, 3) filtered points of the stroke, in drawing order
    snap   : snap distance in mm (step 2)
    falloff: "linear" (the paper's even distribution) or "smooth" (cubic) for the end offsets
    """
    snap_state = net.snapshot()
    before = net.clone()        # the surface before the stroke, read (never changed) by both tries
    pts = np.array(stroke, dtype=float)
    rec, work = _add_once(net, before, pts, index, tol, snap, falloff, snap_state)
    misses = work.misses
    if work.bent and work.folded:
        # its pre-image bends: the paper inserts each straight piece in turn, each extended to the
        # boundary of its region across the surface (an extension no stroke drew); where those
        # folded it, the stroke is tried once more as one straight piece from its first end to
        # its last (the surface it makes is still the stroke's, in 3D: only its layout in the
        # pre-image differs)
        again, again_work = _add_once(net, before, pts, index, tol, snap, falloff, snap_state, straight=True)
        if again.status == "accepted":
            rec, misses = replace(again, reason=again.reason + "; " + STRAIGHT_NOTE), again_work.misses
    misses = as_drawn(pts, misses, snap) if len(pts) >= 2 else []
    if not may_be_off(misses, snap):
        return rec
    # drawn off the surface? (core.off_surface): the misses along the surface's normals before it
    normals = normals_at(before, [q - m for q, m in misses])
    off = drawn_off(misses, normals, snap)
    if off is not None:
        # moved onto the strokes it crosses and added again; when that fails, the stroke as
        # drawn keeps what it did
        first = net.snapshot()
        net.restore(snap_state)
        again, _ = _add_once(net, before, onto_crossings(pts, misses, normals), index, tol, snap, falloff,
                             snap_state)
        if again.status == "accepted":
            return replace(again, reason=again.reason + "; " + off_surface.note(len(misses), off))
        net.restore(first)
    return rec


def _add_once(net: PatchNetwork, old: PatchNetwork, pts: FloatArray, index: int, tol: Tolerances, snap: float,
              falloff: str, snap_state: tuple, straight: bool = False) -> tuple[StrokeRecord, _Work]:
    """add_stroke as the paper has it (later strokes win): the record, and what was done (_Work: the
    stroke's misses of the earlier stroke curves it crossed, those found before a rejection when it
    is rejected; whether its pre-image bent; whether it was rejected for folding the surface).
    old: a clone of net as it is now (snap_state), read only. straight: insert each open piece as
    one straight piece."""
    net.take_log()
    work = _Work()
    try:
        if len(pts) < 2:
            raise StrokeRejectedError(f"it has {len(pts)} point(s) after filtering; a stroke needs at least 2")
        pieces = [pts]
        if len(pts) >= 4 and np.linalg.norm(pts[0] - pts[-1]) < snap:
            far = int(np.argmax(np.linalg.norm(pts - pts[0], axis=1)))
            pieces = [pts[: far + 1], pts[far:]]          # a closed stroke: two open pieces
        used = []
        for piece in pieces:
            used.append(_add_open(net, old, piece, index, tol, snap, falloff, work, straight))
        log = net.take_log()
        touched = {r for kind, r in log if kind in ("created", "changed") and r in net.region_ids}
        left = repair_folds(net, old, touched, sag_mm=tol.made_sag_mm)
        replanned = net.take_log()
        log += replanned
        if left:
            worst = max(left, key=lambda f: f.angle_deg)
            raise StrokeFoldsError(f"{FOLD_REASON}: {worst.describe()}; redraw it closer "
                                   "to the surface, or further from the curves it nearly touches")
    except ProgSurfError as err:
        net.restore(snap_state)
        work.folded = isinstance(err, StrokeFoldsError)
        return StrokeRecord(index, "interior", "rejected", str(err), points=pts), work
    created = tuple(r for kind, r in log if kind == "created" and r in net.region_ids)
    removed = tuple(r for kind, r in log if kind == "removed" and r in old.region_ids)
    note = f"{len(work.curve_ids)} straight piece(s); ends: {', '.join(work.ends)}"
    if work.pulled:
        note += f"; pulled curve(s) {sorted(work.pulled)} to it"
    for curve, share, which in work.merged:
        info = net.curve_info(curve)
        drawn = (f"stroke {info['stroke']}" if info["kind"] == "stroke" and info["stroke"] is not None
                 else "the boundary" if info["kind"] == "outer" else f"curve {curve}")
        verb = "starts" if which == "first" else "ends"
        note += (f"; its {which} {100.0 * share:.0f} % retraces {drawn} (curve {curve}): merged into it, it "
                 f"{verb} where it leaves that curve")
    splits = sum(kind == "created" for kind, _ in replanned) // 2
    if splits:
        note += f"; {splits} region(s) split along the old surface where it would have creased"
    return StrokeRecord(index, "interior", "accepted", note, np.vstack(work.pre_image),
                        tuple(work.curve_ids), created, removed, tuple(sorted(work.pulled)),
                        tuple(work.ends), tuple(work.offsets), np.vstack(used),
                        merged_curves=tuple(sorted({c for c, _, _ in work.merged}))), work


def _straight_pieces(net: PatchNetwork, pts: FloatArray, uv0: FloatArray, uv1: FloatArray,
                     i0: int, i1: int, tol: float, snap: float, depth: int = 0) -> list[int]:
    """Step (6), last paragraph: split at the middle point recursively until each piece's
    pre-image is straight within tol. Returns interior break indices."""
    if i1 - i0 < 2 or depth >= MAX_DEPTH:
        return []
    m = (i0 + i1) // 2
    # (where the surface lies on itself, the sheet nearest the straight pre-image: footpoint near_uv)
    f = net.footpoint(pts[m], slack=snap, near_uv=uv0 + (m - i0) / (i1 - i0) * (uv1 - uv0))
    if not f.inside:
        raise StrokeOutsideSurfaceError(
            f"its point {m} ({pts[m][0]:.1f}, {pts[m][1]:.1f}, {pts[m][2]:.1f}) projects outside the surface")
    d = uv1 - uv0
    length = np.linalg.norm(d)
    off = abs(float(d[0] * (f.uv[1] - uv0[1]) - d[1] * (f.uv[0] - uv0[0]))) / max(length, 1e-300)
    if off <= tol:
        return []
    return (_straight_pieces(net, pts, uv0, f.uv, i0, m, tol, snap, depth + 1) + [m]
            + _straight_pieces(net, pts, f.uv, uv1, m, i1, tol, snap, depth + 1))


def _add_open(net: PatchNetwork, old: PatchNetwork, pts: FloatArray, index: int, tol: Tolerances,
              snap: float, falloff: str, work: _Work, straight: bool = False) -> FloatArray:
    """One open stroke: snap/trim its ends, find its straight pieces, insert them in turn (all of it
    as one straight piece with `straight`)."""
    if len(pts) < 2 or not np.ptp(pts, axis=0).max() > 0:
        # (a "closed" stroke of one repeated point splits into a piece of one point)
        raise StrokeRejectedError("it has no length: all its points are one point")
    drawn = pts
    pts, first, last = trim_ends(net, pts, snap)
    start, end = end_of(net, first, pts[0], "first", snap), end_of(net, last, pts[-1], "last", snap)
    work.misses.extend(end_misses(net, drawn, (first, last)))
    breaks = [] if straight else _straight_pieces(net, pts, start.uv, end.uv, 0, len(pts) - 1, tol.param, snap)
    work.bent |= bool(breaks)
    if breaks:
        # A gently bent pre-image can leave a later piece running along the extension of an
        # earlier one; then the whole stroke is taken as one straight piece instead.
        state = net.snapshot()
        marks = (len(work.ends), len(work.offsets), len(work.curve_ids), len(work.pre_image), set(work.pulled),
                 len(work.misses), len(work.merged))
        try:
            _insert_pieces(net, old, pts, start, end, [0] + breaks + [len(pts) - 1], index, tol, snap,
                           falloff, work)
            return pts
        except StrokeRunsAlongCurveError:
            net.restore(state)
            del work.ends[marks[0]:], work.offsets[marks[1]:], work.curve_ids[marks[2]:], work.pre_image[marks[3]:]
            del work.misses[marks[5]:], work.merged[marks[6]:]
            work.pulled = marks[4]
    _insert_pieces(net, old, pts, start, end, [0, len(pts) - 1], index, tol, snap, falloff, work)
    return pts


def _insert_pieces(net: PatchNetwork, old: PatchNetwork, pts: FloatArray, start: StrokeEnd, end: StrokeEnd,
                   bounds: list, index: int, tol: Tolerances, snap: float, falloff: str, work: _Work) -> None:
    """Insert the straight pieces pts[bounds[k]:bounds[k+1]+1] one after the other."""
    for k in range(len(bounds) - 1):
        piece = pts[bounds[k]: bounds[k + 1] + 1]
        if k == 0 and len(bounds) == 2:
            s, e = start, end
        else:
            # The network has changed since the ends were found: place them again on it. A break
            # point lies on the previous piece, so it snaps there without trimming.
            s = start if k == 0 else placed_end(net, piece, snap, "first")
            e = placed_end(net, piece[::-1], snap, "last")
        work.ends.extend(["snapped" if x.snapped else "footpoint" for x in (s, e)])
        work.offsets.extend([x.offset for x in (s, e)])
        cid = net.new_curve_id("stroke", index)
        work.curve_ids.append(cid)
        # only the stroke's own ends may stop at the node of a curve they retrace: its pieces meet
        # at their break points
        pre_image, pulled, misses, merged = insert_piece(net, old, piece, s, e, cid, tol, snap, falloff,
                                                         merge_ends=(k == 0, k == len(bounds) - 2))
        work.merged.extend(merged)
        work.pre_image.append(pre_image)
        work.pulled.update(pulled)
        work.misses.extend(misses)
