"""Stroke validation and the paper's 3D distance filter (Qin & Wright, section 2)."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from ProgSurf.core.errors import (DegenerateSketchError, InvalidOptionError, InvalidStrokeError,
                                  ProgSurfError)
from ProgSurf.core.strokes import (auto_filter_threshold, chord_length, filter_stroke, resample_arclength,
                                   sketch_diagonal, validate_stroke)

finite = st.floats(-1e4, 1e4, allow_nan=False, allow_infinity=False)
stroke_st = st.integers(2, 40).flatmap(lambda n: arrays(float, (n, 3), elements=finite))
fast = settings(max_examples=80, deadline=None)


def test_validate_returns_a_float_copy():
    src = [[0, 0, 0], [1, 2, 3]]
    arr = np.array(src, dtype=int)
    out = validate_stroke(arr, 0)
    assert out.dtype == np.float64 and out.shape == (2, 3)
    out[0, 0] = 99
    assert arr[0, 0] == 0


@pytest.mark.parametrize("bad, pattern", [
    ([[0, 0, 0]], r"stroke 7 has 1 point; a stroke needs at least 2"),
    (np.zeros((0, 3)), r"stroke 7 has 0 points"),
    ([[0, 0], [1, 1]], r"stroke 7 has shape \(2, 2\)"),
    ([[0, 0, 0], [1, np.nan, 0]], r"stroke 7 .*NaN or infinite.*point 1"),
    ([[0, 0, np.inf], [1, 1, 0]], r"stroke 7 .*NaN or infinite.*point 0"),
    ([["a", "b", "c"], [1, 1, 1]], r"stroke 7 is not an array of numbers"),
    ([[0, 0, 0], [1, 1]], r"stroke 7"),
])
def test_validate_names_the_stroke_and_the_problem(bad, pattern):
    with pytest.raises(InvalidStrokeError, match=pattern):
        validate_stroke(bad, 7)


@fast
@given(stroke=stroke_st, frac=st.floats(0.0, 0.5))
def test_filter_keeps_ends_spacing_and_order(stroke, frac):
    before = stroke.copy()
    threshold = frac * (chord_length(stroke) + 1e-9)
    out = filter_stroke(stroke, threshold)
    np.testing.assert_array_equal(stroke, before)  # input untouched
    np.testing.assert_array_equal(out[0], stroke[0])
    np.testing.assert_array_equal(out[-1], stroke[-1])
    # every kept point is an input point, in input order, but for at most one point halfway
    # between the two middle points
    found = [np.flatnonzero((stroke == p).all(axis=1)) for p in out]
    assert sum(len(f) == 0 for f in found) <= (1 if len(stroke) % 2 == 0 else 0)
    idx = [int(f[0]) for f in found if len(f)]
    assert idx == sorted(idx) or len(set(map(tuple, stroke))) < len(stroke)
    # the filter runs from both ends to the middle: all kept spacings but the two beside the
    # middle are at least the threshold
    gaps = np.linalg.norm(np.diff(out, axis=0), axis=1)
    assert np.sum(gaps < threshold) <= 2
    assert len(out) <= len(stroke)
    # ... so a stroke drawn the other way keeps the same points (issue 17)
    np.testing.assert_array_equal(filter_stroke(stroke[::-1], threshold), out[::-1])


def test_filter_keeps_the_same_points_of_a_rough_stroke_drawn_either_way():
    """Uneven spacing (a hand slowing down) is where a filter run from one end only kept other
    points when the stroke was drawn the other way (issue 17)."""
    rng = np.random.default_rng(17)
    for n in (40, 41):
        x = np.cumsum(rng.exponential(1.0, n))
        stroke = np.column_stack([x, np.sin(x / 10), rng.normal(0, 0.05, n)])
        out = filter_stroke(stroke, 2.5)
        assert 3 < len(out) < n
        np.testing.assert_array_equal(filter_stroke(stroke[::-1], 2.5), out[::-1])


def test_filter_drops_dense_clusters_exactly_as_the_paper_says():
    pts = np.array([[0, 0, 0], [0.1, 0, 0], [0.2, 0, 0], [1.0, 0, 0], [1.05, 0, 0], [2.0, 0, 0], [2.1, 0, 0]])
    out = filter_stroke(pts, 0.5)
    # 2.0 gives way to the last point 2.1 (which is always kept)
    np.testing.assert_array_equal(out, pts[[0, 3, 6]])
    np.testing.assert_array_equal(filter_stroke(pts, 0.0), pts)


@pytest.mark.parametrize("bad", [-1.0, np.nan, np.inf])
def test_filter_rejects_bad_threshold(bad):
    with pytest.raises(InvalidOptionError, match="threshold"):
        filter_stroke(np.zeros((3, 3)), bad)


def test_auto_threshold_is_half_a_percent_of_the_diagonal_and_scales():
    rng = np.random.default_rng(1)
    strokes = [np.column_stack([np.linspace(0, 100, 50), np.full(50, y), rng.normal(0, 1, 50)]) for y in (0, 80)]
    diag = sketch_diagonal(np.concatenate(strokes))
    assert auto_filter_threshold(strokes) == pytest.approx(0.005 * diag)
    assert auto_filter_threshold([3.0 * s for s in strokes]) == pytest.approx(3.0 * auto_filter_threshold(strokes))
    # invariant under rotation (the diagonal is measured in the principal axes)
    c, s = np.cos(0.7), np.sin(0.7)
    rot = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    assert auto_filter_threshold([p @ rot.T for p in strokes]) == pytest.approx(auto_filter_threshold(strokes))


def test_auto_threshold_keeps_short_strokes_sampled():
    big = [np.array([[0, 0, 0], [1000, 0, 0]]), np.array([[0, 0, 0], [0, 1000, 0]])]
    short = [np.array([[0, 0, 0], [1.0, 0, 0]])] * 5
    assert auto_filter_threshold(big + short) <= 0.05 * 1.0 + 1e-12


def test_auto_threshold_refuses_a_point_sketch():
    with pytest.raises(DegenerateSketchError, match="coincide"):
        auto_filter_threshold([np.ones((3, 3))])
    with pytest.raises(DegenerateSketchError):
        auto_filter_threshold([])


@fast
@given(stroke=stroke_st, n=st.integers(2, 50))
def test_resample_keeps_ends_and_spacing(stroke, n):
    out = resample_arclength(stroke, n)
    assert out.shape == (n, 3)
    np.testing.assert_array_equal(out[[0, -1]], stroke[[0, -1]])
    total = chord_length(stroke)
    assert chord_length(out) <= total + 1e-9 * (1 + total)


def test_chord_length_is_the_sum_of_chords():
    assert chord_length([[0, 0, 0], [3, 4, 0], [3, 4, 12]]) == pytest.approx(17.0)
    assert chord_length([[1, 1, 1]]) == 0.0


@fast
@given(data=st.lists(st.lists(st.floats(allow_nan=True, allow_infinity=True), max_size=4), max_size=5))
def test_malformed_strokes_raise_only_project_errors(data):
    try:
        out = validate_stroke(data, 3)
    except ProgSurfError:
        return
    assert out.shape[1] == 3 and out.shape[0] >= 2 and np.isfinite(out).all()
