"""Stroke fairing: a light cubic B-spline through the rough points of a stroke, within a tolerance.

Hand strokes carry tracker jitter. The paper filters points by a 3D distance threshold and leaves
smoothing to the CAD system; we also replace each stroke by the least-squares cubic B-spline with
the fewest uniform control points that stays within ``tol`` of every point (ends interpolated,
sharp corners kept), sampled densely enough that the polyline between samples stays within
``sag`` of the spline. Curves then become light B-spline edges downstream, instead of splines
that follow every wobble, and the Kamiya & Aoyama fairness criterion (a curvature-centre locus
without spurious oscillation) is met by construction of a low-order fit.
"""
from __future__ import annotations

import numpy as np

from .bspline import basis_matrix, uniform_knots
from .curve_fit import sample_to_sag
from .strokes import cumulative_length
from .types import FloatArray

MAX_SAMPLES = 400
"""At most about this many samples per faired stroke (the sag target gives way beyond it)."""

NOISE_SIGMAS = 4.0
"""A stroke's fairing tolerance is at least this many times its estimated point jitter, so that the
fair curve does not chase the noise (within the cap below)."""

NOISE_CAP = 0.5
"""...but never more than this fraction of the snap distance: a faired stroke still counts as on
the surface."""

CORNER_DEGREES = 50.0
"""A stroke turning by more than this at one point (over its neighbours) has an intended corner."""


def pchip(x: FloatArray, y: FloatArray, xq: FloatArray) -> FloatArray:
    """Monotone piecewise-cubic Hermite interpolation (Fritsch & Carlson) of increasing data:
    a C1 parameter map, so curve parameters have no speed jumps that B-spline fits would chase."""
    h = np.diff(x)
    delta = np.diff(y) / h
    d = np.zeros_like(y)
    for k in range(1, len(y) - 1):
        if delta[k - 1] * delta[k] > 0:
            w1, w2 = 2 * h[k] + h[k - 1], h[k] + 2 * h[k - 1]
            d[k] = (w1 + w2) / (w1 / delta[k - 1] + w2 / delta[k])
    d[0], d[-1] = delta[0], delta[-1]
    k = np.clip(np.searchsorted(x, xq, side="right") - 1, 0, len(h) - 1)
    s = (xq - x[k]) / h[k]
    h00, h10 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s
    h01, h11 = -2 * s**3 + 3 * s**2, s**3 - s**2
    return h00 * y[k] + h10 * h[k] * d[k] + h01 * y[k + 1] + h11 * h[k] * d[k + 1]


def _basis(t: FloatArray, m: int) -> FloatArray:
    """(len(t), m) cubic B-spline basis on a clamped uniform knot vector with m control points."""
    return basis_matrix(uniform_knots(m), np.clip(np.asarray(t, dtype=float), 0.0, 1.0))


def jitter(points: FloatArray) -> float:
    """Robust estimate of the point jitter (sigma, mm) of a stroke: each interior point's offset from
    the midpoint of its neighbours has per-axis variance 1.5 sigma^2 under isotropic noise, and its
    squared length a median of about 2.366 x that (chi-square with 3 degrees of freedom). A smooth
    stroke drawn with points a filter distance apart gives almost zero (its curvature term is tiny)."""
    pts = np.asarray(points, dtype=float)
    if len(pts) < 5:
        return 0.0
    e = pts[1:-1] - 0.5 * (pts[:-2] + pts[2:])
    return float(np.sqrt(np.median(np.einsum("ij,ij->i", e, e)) / (1.5 * 2.366)))


def stroke_tolerance(points: FloatArray, fair_mm: float, snap_mm: float) -> float:
    """The fairing tolerance for one stroke: fair_mm, raised to NOISE_SIGMAS x its jitter (capped
    at NOISE_CAP x snap_mm). fair_mm <= 0 turns fairing off."""
    if not fair_mm or fair_mm <= 0:
        return 0.0
    return float(max(fair_mm, min(NOISE_SIGMAS * jitter(points), NOISE_CAP * snap_mm)))


def _chord_params(points: FloatArray) -> FloatArray:
    run = cumulative_length(points)
    return run / run[-1] if run[-1] > 0 else np.linspace(0.0, 1.0, len(points))


def fit_cubic(points: FloatArray, tol: float) -> tuple[FloatArray | None, int]:
    """Least-squares cubic B-spline with end points interpolated and the fewest control points
    (from 4 up) within tol of every point, and between consecutive points within tol plus a quarter
    of their chord of its midpoint (a fit that meets the points but loops between them, as an
    interpolating spline through uneven points can, is refused).
    Returns (control points (m, 3), m), or (None, 0) when no such fit exists."""
    pts = np.asarray(points, dtype=float)
    n = len(pts)
    t = _chord_params(pts)
    if n < 4:                                 # too few points for a cubic: the straight chord
        return np.linspace(pts[0], pts[-1], 4), 4
    mid_t = 0.5 * (t[1:] + t[:-1])
    mid_p = 0.5 * (pts[1:] + pts[:-1])
    slack = tol + 0.25 * np.linalg.norm(np.diff(pts, axis=0), axis=1)
    for m in range(4, n + 1):
        b = _basis(t, m)
        ctrl = np.zeros((m, 3))
        ctrl[0], ctrl[-1] = pts[0], pts[-1]
        rhs = pts - np.outer(b[:, 0], pts[0]) - np.outer(b[:, -1], pts[-1])
        inner, *_ = np.linalg.lstsq(b[:, 1:-1], rhs, rcond=None)
        ctrl[1:-1] = inner
        err = float(np.linalg.norm(b @ ctrl - pts, axis=1).max())
        if err <= tol:
            if np.all(np.linalg.norm(_basis(mid_t, m) @ ctrl - mid_p, axis=1) <= slack):
                return ctrl, m
            return None, 0
    return None, 0


def evaluate_cubic(ctrl: FloatArray, t: FloatArray) -> FloatArray:
    return _basis(t, len(ctrl)) @ ctrl


def _max_curvature(dense: FloatArray) -> float:
    """Largest discrete curvature (turning angle over segment length) of a dense polyline."""
    d = np.diff(dense, axis=0)
    length = np.linalg.norm(d, axis=1)
    ok = length > 1e-14 * max(float(length.sum()), 1e-300)     # round-off segments (1e-12 mm at 100 mm)
    d, length = d[ok], length[ok]
    if len(d) < 2:
        return 0.0
    cos = np.clip(np.einsum("ij,ij->i", d[:-1], d[1:]) / (length[:-1] * length[1:]), -1.0, 1.0)
    return float((np.arccos(cos) / (0.5 * (length[:-1] + length[1:]))).max())


def stroke_corners(points: FloatArray, tol: float = 0.0) -> list[int]:
    """Indices of sharp turns (intended corners) in a stroke: the direction turns by more than
    CORNER_DEGREES between chords reaching at least 4 x tol (and one point) to either side, so that
    jitter within the fairing tolerance is not taken for a corner, once the stroke's bending on
    either side is taken off (_concentrated_turn): one index per corner."""
    n = len(points)
    if n < 5:
        return []
    run = cumulative_length(points)
    reach = 4.0 * tol
    idx = np.arange(1, n - 1)
    back = np.minimum(np.searchsorted(run, run[idx] - reach, side="right") - 1, idx - 1)
    ahead = np.maximum(np.searchsorted(run, run[idx] + reach, side="left"), idx + 1)
    ok = (back >= 0) & (ahead <= n - 1)
    idx, back, ahead = idx[ok], back[ok], ahead[ok]
    turn = _concentrated_turn(points, run, idx, back, ahead)
    sharp = turn > np.radians(CORNER_DEGREES)
    out: list[int] = []
    k = 0
    while k < len(idx):                       # one corner per run of sharp indices: its sharpest
        if not sharp[k]:
            k += 1
            continue
        j = k
        while j + 1 < len(idx) and sharp[j + 1]:
            j += 1
        best = k + int(np.argmax(turn[k:j + 1]))
        i = int(idx[best])
        if 2 <= i <= n - 3 and (not out or i - out[-1] >= 3):
            out.append(i)
        k = j + 1
    return out


def _turn(points: FloatArray, idx, back, ahead) -> FloatArray:
    """Angle (rad) between the chords back -> idx and idx -> ahead."""
    a = points[idx] - points[back]
    b = points[ahead] - points[idx]
    cos = np.einsum("ij,ij->i", a, b) / np.maximum(np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1), 1e-300)
    return np.arccos(np.clip(cos, -1.0, 1.0))


def _concentrated_turn(points: FloatArray, run: FloatArray, idx, back, ahead) -> FloatArray:
    """How far the stroke turns AT each index idx (rad): the turn t between the chords to back and
    to ahead, less the turn that its bending spread along the stroke gives those chords.

    A smooth bend of curvature k turns chords of arc a and b by about k (a + b) / 2; a corner turns
    them by its angle c whatever their length. So with the back chord made twice as long, t2 =
    c + 1.5 k a against t = c + k a (a = b), and 3 t - 2 t2 = c: the bend is taken off and the corner
    stays. Without this, a noisy ring of radius R faired within a tolerance near R / 6 (4 x its jitter,
    itself near R / 23: sigma 0.2 % of the sketch on a fuselage's frame, TiGL fuselage2, helibody) read its own roundness over the
    4 x tol chords, 40 deg, plus jitter, as corners of 50-60 deg, kept them, and its surfaces
    creased across from them (folds of 96-112 deg). The estimate is read with the back chord
    doubled and with the ahead chord doubled, and the larger is kept: a corner followed closely by
    another (a U drawn with two corners) reads its own angle from the side that is clear of the
    other.

    Near a stroke's end only one doubled chord fits, and the short side's own bending cannot be
    read: only the side that was doubled is taken off there, once (2 t - t2). Taken off twice, as
    if the short side bent the same, a 60 deg corner drawn 6 points before the end of an arc that
    turns the same way read under 50 and was lost (found by a review: 51 of 300 such corners, with
    jitter of an eighth of the tolerance; 3 now). Where the stroke is too short on both sides for a
    doubled chord, the plain turn is kept."""
    n = len(points)
    plain = _turn(points, idx, back, ahead)
    span_b = run[idx] - run[back]
    span_a = run[ahead] - run[idx]
    back2 = np.searchsorted(run, run[idx] - 2.0 * span_b, side="right") - 1
    ahead2 = np.searchsorted(run, run[idx] + 2.0 * span_a, side="left")
    fits_b = back2 >= 0
    fits_a = ahead2 <= n - 1
    bend_b = _turn(points, idx, np.maximum(back2, 0), ahead) - plain      # the back side's bending
    bend_a = _turn(points, idx, back, np.minimum(ahead2, n - 1)) - plain
    both = np.maximum(np.where(fits_b, plain - 2.0 * bend_b, -np.inf), np.where(fits_a, plain - 2.0 * bend_a, -np.inf))
    one = np.where(fits_b, plain - bend_b, plain - bend_a)
    est = np.where(fits_b & fits_a, both, np.where(fits_b | fits_a, one, plain))
    return np.minimum(est, plain)


def fair_stroke(points: FloatArray, tol: float, sag: float, keep_index: bool = False,
                original_at: list | None = None) -> tuple[FloatArray, FloatArray]:
    """Fair a stroke (see module docstring).

    points     : (n, 3) filtered stroke points
    tol        : largest distance of the fair curve from any input point (mm); <= 0 disables
    sag        : largest distance of the returned polyline from the fair curve between samples
    keep_index : when True the input points' index parameters i/(n-1) are kept (the paper's
                 mapping of equalised boundary points onto the unit square): samples are
                 inserted between consecutive points and given interpolated index parameters.
    original_at: if a list is given, it receives the output index of every input point.
    Returns (points (N, 3), params (N,) in [0, 1]): chord-length params, or index params.
    """
    pts = np.asarray(points, dtype=float)
    n = len(pts)
    if tol <= 0 or n < 4 or np.ptp(pts, axis=0).max() == 0:
        if original_at is not None:
            original_at.extend(range(n))
        prm = np.linspace(0.0, 1.0, n) if keep_index else _chord_params(pts)
        return pts.copy(), prm
    cuts = [0] + stroke_corners(pts, tol) + [n - 1]
    out_pts, out_prm = [pts[:1]], [np.zeros(1)]
    original = [0]                      # where each input point lands in the output
    for a, b in zip(cuts[:-1], cuts[1:]):
        seg = pts[a:b + 1]
        ctrl, _ = fit_cubic(seg, tol)
        if ctrl is None:                      # no fair cubic: this piece keeps its points
            out_pts.append(seg[1:])
            original.extend([original[-1] + k for k in range(1, len(seg))])
            continue
        t = _chord_params(seg)
        # Samples between consecutive points: enough that the chord sag stays under `sag`.
        curv = _max_curvature(evaluate_cubic(ctrl, np.linspace(0.0, 1.0, 201)))
        step = np.sqrt(8 * sag / curv) if curv > 0 else np.inf
        u = [t[:1]]
        for i in range(len(seg) - 1):
            span = np.linalg.norm(seg[i + 1] - seg[i])
            k = int(min(max(1, np.ceil(span / step)), max(1, MAX_SAMPLES // n)))
            w = t[i] + np.arange(1, k + 1) / k * (t[i + 1] - t[i])
            w[-1] = t[i + 1]
            u.append(w)
        # ... and where MAX_SAMPLES held the uniform density back, more samples at the bends only
        u, piece = sample_to_sag(lambda x: evaluate_cubic(ctrl, x), np.concatenate(u), sag)
        out_pts.append(piece[1:])
        at = np.searchsorted(u, t[1:])          # the input points' parameters are all still in u
        original.extend((original[-1] + at).tolist())
    res = np.vstack(out_pts)
    res[0], res[-1] = pts[0], pts[-1]
    chord = _chord_params(res)
    if original_at is not None:
        original_at.extend(original)
    if keep_index:
        # The index parameter i/(n-1) of every input point, joined C1 between them (a piecewise
        # linear map would jump in speed at every point and make the B-spline edges heavy).
        return res, np.clip(pchip(chord[original], np.linspace(0.0, 1.0, n), chord), 0.0, 1.0)
    return res, chord
