"""Stroke fairing (core.fairing) and the even equalisation of faired boundary sides (core.boundary)."""
from __future__ import annotations

import numpy as np
import pytest

from ProgSurf.core.boundary import equalise_uniform
from ProgSurf.core.fairing import (NOISE_CAP, NOISE_SIGMAS, fair_stroke, fit_cubic, jitter, stroke_corners,
                                   stroke_tolerance)
from ProgSurf.core.strokes import chord_length


def arc(n: int = 120, radius: float = 60.0, sweep: float = 1.2) -> np.ndarray:
    a = np.linspace(0.0, sweep, n)
    return np.c_[radius * np.cos(a), radius * np.sin(a), 5.0 * np.sin(2 * a)]


def distance_to_polyline(p: np.ndarray, poly: np.ndarray) -> np.ndarray:
    a, b = poly[:-1], poly[1:]
    ab = b - a
    w = np.clip(np.einsum("kij,ij->ki", p[:, None] - a[None], ab) / np.einsum("ij,ij->i", ab, ab), 0, 1)
    return np.linalg.norm(a[None] + w[..., None] * ab[None] - p[:, None], axis=2).min(axis=1)


@pytest.mark.parametrize("sigma", [0.05, 0.15, 0.4])
def test_jitter_estimate_recovers_the_noise_of_a_smooth_stroke(sigma):
    rng = np.random.default_rng(3)
    clean = arc()
    assert jitter(clean) < 0.01
    noisy = clean + rng.normal(0.0, sigma, clean.shape)
    assert jitter(noisy) == pytest.approx(sigma, rel=0.3)


def test_stroke_tolerance_rises_with_noise_and_is_capped_by_the_snap_distance():
    rng = np.random.default_rng(4)
    clean = arc()
    assert stroke_tolerance(clean, 0.1, 3.0) == 0.1
    noisy = clean + rng.normal(0.0, 0.2, clean.shape)
    assert stroke_tolerance(noisy, 0.1, 3.0) == pytest.approx(NOISE_SIGMAS * jitter(noisy))
    very = clean + rng.normal(0.0, 2.0, clean.shape)
    assert stroke_tolerance(very, 0.1, 3.0) == NOISE_CAP * 3.0
    assert stroke_tolerance(noisy, 0.0, 3.0) == 0.0          # fairing off


def test_a_noisy_stroke_faired_at_its_own_tolerance_is_light_and_close():
    rng = np.random.default_rng(5)
    clean = arc()
    noisy = clean + rng.normal(0.0, 0.15, clean.shape)
    tol = stroke_tolerance(noisy, 0.1, 3.0)
    ctrl, m = fit_cubic(noisy, tol)
    assert m <= 12, m                            # the arc needs few poles, the noise is not chased
    faired, params = fair_stroke(noisy, tol, 0.0025)
    assert distance_to_polyline(noisy, faired).max() <= tol + 1e-9
    assert distance_to_polyline(faired, clean).max() < 0.5 * tol  # closer to the truth than the noise
    assert np.all(np.diff(params) > 0) and params[0] == 0.0 and params[-1] == 1.0


def test_fairing_never_loops_between_uneven_points():
    """Regression: through clustered points the fewest-poles fit could interpolate and swing
    kilometres away between them (a 17-point edge 105 m long in a 100 mm sketch)."""
    rng = np.random.default_rng(0)
    for _ in range(300):
        n = int(rng.integers(5, 12))
        t = np.sort(np.r_[0.0, 1.0, rng.uniform(0, 1, n - 2) ** 3])
        pts = np.c_[100 * t, 20 * np.sin(3 * t), rng.normal(0, 0.3, n)]
        faired, _ = fair_stroke(pts, 0.15, 0.0025)
        assert chord_length(faired) <= 1.25 * chord_length(pts)
        assert distance_to_polyline(faired, pts).max() <= 0.5 * np.linalg.norm(np.diff(pts, axis=0), axis=1).max()


def test_corners_are_found_at_the_fairing_scale_and_kept():
    rng = np.random.default_rng(6)
    leg = np.linspace(0.0, 40.0, 41)[:, None]
    ell = np.vstack([leg * [1, 0, 0], [40, 0, 0] + leg[1:] * [0, 1, 0]])
    noisy = ell + rng.normal(0.0, 0.1, ell.shape)
    tol = stroke_tolerance(noisy, 0.1, 3.0)
    assert stroke_corners(noisy, tol) == [40]
    faired, _ = fair_stroke(noisy, tol, 0.0025)
    assert np.linalg.norm(faired - noisy[40], axis=1).min() < 1e-9   # the corner point is kept
    straight = np.c_[np.linspace(0, 80, 81), np.zeros(81), np.zeros(81)] + rng.normal(0.0, 0.1, (81, 3))
    assert stroke_corners(straight, stroke_tolerance(straight, 0.1, 3.0)) == []


def test_a_noisy_ring_faired_coarsely_has_no_corners_and_a_drawn_corner_keeps_its_own():
    """A round frame drawn sparsely with jitter gets a fairing tolerance near a sixth of its radius
    (4 x the jitter read on it: 85 mm on a 2000 mm frame here; 88 on fuselage2's), and chords of 4 x that turn 40 deg on the ring's roundness alone: the
    jitter made 50-60 deg of it at some points, read as corners (TiGL fuselage2 noisy: 5 and 7
    corners on two frames, their surfaces creased across). The ring's own bending is taken off; a
    square's corners, and a U's two corners closer than the chords, stay."""
    rng = np.random.default_rng(29)
    radius = 2000.0
    found = []
    for _ in range(20):
        k = int(rng.integers(40, 70))
        phi = np.sort(rng.uniform(0.0, 2 * np.pi, k))
        ring = np.c_[radius * np.cos(phi), radius * np.sin(phi), np.zeros(k)] + rng.normal(0.0, 40.0, (k, 3))
        found.append(len(stroke_corners(ring, 4.0 * 85.0)))
    assert sum(found) <= 2, found
    side = np.linspace(0.0, 1000.0, 26)[:-1, None]
    square = np.vstack([side * [1, 0, 0], [1000, 0, 0] + side * [0, 1, 0], [1000, 1000, 0] + side * [-1, 0, 0],
                        [0, 1000, 0] + side * [0, -1, 0], [[0, 0, 0]]]) + rng.normal(0.0, 5.0, (101, 3))
    assert stroke_corners(square, 20.0) == [25, 50, 75]
    leg = np.linspace(0.0, 400.0, 41)[:, None]
    u = np.vstack([leg[::-1] * [0, 1, 0], leg[1:9] * [1, 0, 0], [80, 0, 0] + leg[1:] * [0, 1, 0]])
    assert stroke_corners(u, 10.0) == [40, 48]        # 80 apart, chords of 40 and 80 either side
    # 50 apart: each corner's doubled chord on the side of the other crosses it, so each is read
    # from the side clear of it (the larger of the two readings)
    u = np.vstack([leg[::-1] * [0, 1, 0], leg[1:6] * [1, 0, 0], [50, 0, 0] + leg[1:] * [0, 1, 0]])
    assert stroke_corners(u, 10.0) == [40, 45]


def test_a_corner_just_before_a_strokes_end_after_a_bend_the_same_way_is_kept():
    """Six points from the end only the back chord can be doubled: the arc's bending behind the
    corner is taken off once, the short straight side's (none) is not guessed. Taken off twice (as
    if the short side bent the same), the 60 deg corner after an arc of radius 15 tolerances read
    under 50 deg: lost drawn clean, and 131 times in 300 with jitter of an eighth of the tolerance."""
    radius = 15.0
    th = np.arange(48) / radius
    arc = np.column_stack([radius * np.sin(th), radius * (1.0 - np.cos(th)), np.zeros_like(th)])
    out = th[-1] + np.radians(60.0)
    tail = arc[-1] + np.arange(1, 7)[:, None] * [np.cos(out), np.sin(out), 0.0]
    pts = np.vstack([arc, tail])
    assert stroke_corners(pts, 1.0) == [47]
    rng = np.random.default_rng(7)
    missed = sum(not any(abs(k - 47) <= 1 for k in stroke_corners(pts + rng.normal(0.0, 1.0 / 8, pts.shape), 1.0))
                 for _ in range(300))
    assert missed <= 30, missed


def test_equalise_uniform_gives_even_spacing_equal_counts_and_keeps_corners():
    a = arc(200)
    leg = np.linspace(0.0, 30.0, 16)[:, None]
    b = np.vstack([leg * [1, 0, 0], [30, 0, 0] + leg[1:] * [0, 1, 0]])     # a corner at index 15
    ea, eb = equalise_uniform(a, b)
    assert len(ea) == len(eb) == 200
    for side in (ea,):
        d = np.linalg.norm(np.diff(side, axis=0), axis=1)
        assert d.max() / d.min() < 1.01
    assert np.linalg.norm(eb - [30, 0, 0], axis=1).min() < 1e-12
    assert np.allclose(eb[[0, -1]], b[[0, -1]]) and np.allclose(ea[[0, -1]], a[[0, -1]])
    d = np.linalg.norm(np.diff(eb, axis=0), axis=1)
    assert d.max() / d.min() < 1.1             # even on both legs (each leg gets its share)


def test_a_side_keeping_every_vertex_is_resampled_piece_by_piece_to_the_bit():
    """equalise_uniform keeps every vertex of the side with fewer points (boundary_from_sides), so
    its pieces are single segments, hundreds per side: they are resampled in one go, and must give
    what resampling each piece on its own (strokes.resample_arclength) gives, to the bit, a piece
    of no length and a longer piece between kept corners among them."""
    from ProgSurf.core.boundary import _pieces_at_corners, _resample_keeping_corners
    from ProgSurf.core.strokes import resample_arclength

    rng = np.random.default_rng(3)
    t = np.cumsum(rng.uniform(0.3, 1.7, 60))                        # uneven steps along a helix
    side = np.column_stack([40.0 * np.cos(t / 20.0), 40.0 * np.sin(t / 20.0), 3.0 * t])
    side[20] = side[19]                                            # a piece of no length
    keep = [k for k in range(1, 59) if k not in (40, 41, 42)]      # 39..43: one piece of 4 segments
    for n in (61, 137, 400):
        got = _resample_keeping_corners(side, n, keep)
        cuts = sorted(set(_pieces_at_corners(side)) | set(keep))
        assert len(got) == n and set(cuts) >= {39, 43} and 40 not in cuts
        # where each kept vertex landed: between them, each piece resampled on its own
        at = [int(np.flatnonzero((got == side[c]).all(axis=1))[-1 if c == 20 else 0]) for c in cuts]
        for (a, b), (i, j) in zip(zip(cuts[:-1], cuts[1:]), zip(at[:-1], at[1:])):
            if a == 19:                                            # the piece of no length
                continue
            assert np.array_equal(got[i:j + 1], resample_arclength(side[a:b + 1], j - i + 1)), (n, a)


def _arc_position_alone(orig: np.ndarray, pts: np.ndarray) -> list:
    """Each point located on its own (arc_positions before it located them in blocks): the segment
    nearest it at or after the last point's."""
    step = np.linalg.norm(np.diff(orig, axis=0), axis=1)
    cum = np.concatenate([[0.0], np.cumsum(step)])
    a, d = orig[:-1], np.diff(orig, axis=0)
    dd = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
    out, k = [], 0
    for p in pts:
        t = np.clip(np.einsum("ij,ij->i", p - a[k:], d[k:]) / dd[k:], 0.0, 1.0)
        j = int(np.argmin(np.linalg.norm(a[k:] + t[:, None] * d[k:] - p, axis=1)))
        k += j
        out.append(cum[k] + t[j] * step[k])
    return out


def test_points_located_in_blocks_land_where_each_alone_lands_to_the_bit():
    """boundary.arc_positions locates a resampled side's points on the original a block at a time
    (ARC_BLOCK); each must get the parameter it gets located alone, to the bit, on a side that
    doubles back close to itself (the search only forward keeps the points in order) and with more
    points than a block."""
    from ProgSurf.core.boundary import ARC_BLOCK, arc_positions, equalise_uniform

    rng = np.random.default_rng(5)
    t = np.linspace(0.0, 1.0, 150)
    hairpin = np.column_stack([100.0 * np.sin(np.pi * t), 3.0 * np.cos(np.pi * t), 0.1 * t])
    hairpin += rng.normal(scale=0.05, size=hairpin.shape)
    for n in (40, 3 * ARC_BLOCK + 5):
        side, _ = equalise_uniform(hairpin, np.linspace([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], n))
        side = side + rng.normal(scale=1e-9, size=side.shape)      # a fit's points lie a hair off
        prm = arc_positions(hairpin, side)
        ref = np.asarray(_arc_position_alone(hairpin, side)) / float(np.linalg.norm(np.diff(hairpin, axis=0), axis=1).sum())
        ref[0], ref[-1] = 0.0, 1.0
        assert np.array_equal(prm, ref / ref[-1]), n
        assert np.all(np.diff(prm) > 0)                          # in order, across the hairpin's gap


def test_squared_distances_are_summed_as_numpy_sums_them():
    """cad.object_g1's nearest-sample search sums squared differences per coordinate; it must give
    ((q - p) ** 2).sum(axis=-1) to the bit (which sample is nearest decides where a neighbour
    surface is looked up)."""
    from ProgSurf.cad.object_g1 import _squared_distances

    rng = np.random.default_rng(11)
    for scale in (1e-3, 1.0, 1e3):
        q = rng.normal(size=(19, 3)) * scale
        p = rng.normal(size=(2000, 3)) * scale * rng.uniform(0.5, 2.0, size=(2000, 1))
        assert np.array_equal(_squared_distances(q, p), ((q[:, None, :] - p[None]) ** 2).sum(axis=2))
