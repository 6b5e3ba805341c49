"""Chord sag (core.curve_fit.chord_sag), the allowance the curve fit gives a smooth curve between
the vertices of a polyline, and the sampling that keeps it small where the network makes its
polylines (sample_to_sag: the fairing, the splits along the old surface)."""
from pathlib import Path

import numpy as np

from ProgSurf.core.curve_fit import chord_sag, sample_to_sag
from ProgSurf.core.fairing import fair_stroke
from ProgSurf.core.pipeline import build_network
from ProgSurf.io import read_strokes

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def arc(theta: np.ndarray, radius: float = 10.0) -> np.ndarray:
    return np.column_stack([radius * np.cos(theta), radius * np.sin(theta), 0 * theta])


def test_chord_sag_of_a_sampled_circle_is_its_true_sag():
    theta = np.linspace(0.0, np.pi / 2, 9)
    pts = arc(theta)
    length = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    assert np.allclose(chord_sag(pts), length ** 2 / (8 * 10.0), rtol=1e-9)


def test_a_corner_gives_the_chords_beside_it_no_sag():
    """Two straight runs of 9 mm chords meeting at 42 deg (a boundary side merged of two strokes):
    no smooth curve samples the corner, so the fit gets no allowance to cut it."""
    turn = np.radians(42.0)
    a = np.column_stack([np.arange(-5, 1) * 9.0, np.zeros(6), np.zeros(6)])
    b = np.column_stack([np.arange(1, 6) * 9.0 * np.cos(turn), np.arange(1, 6) * 9.0 * np.sin(turn), np.zeros(5)])
    sag = chord_sag(np.vstack([a, b]))
    assert sag.max() < 1e-12


def test_sample_to_sag_halves_the_chords_that_sag_more_and_keeps_the_given_parameters():
    w0 = np.linspace(0.0, 1.0, 5)
    w, pts = sample_to_sag(lambda w: arc(w * np.pi / 2), w0, 1e-3)
    assert set(w0) <= set(w) and np.all(np.diff(w) > 0)
    assert np.allclose(pts, arc(w * np.pi / 2))
    assert chord_sag(pts).max() <= 1e-3
    # the true sag of each chord of the circle, too
    length = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    assert (length ** 2 / 80.0).max() <= 1e-3 * 1.01
    same_w, same = sample_to_sag(lambda w: arc(w * np.pi / 2), w0, None)
    assert np.array_equal(same_w, w0) and np.allclose(same, arc(w0 * np.pi / 2))


def test_a_long_stroke_is_faired_to_the_sag_at_its_bends_too():
    """MAX_SAMPLES holds the uniform density of a long stroke back; the bends get more samples."""
    t = np.linspace(0.0, 1.0, 300)
    pts = np.column_stack([400 * t, 15 * np.tanh((t - 0.5) * 40), 0 * t])     # one tight bend
    faired, prm = fair_stroke(pts, 0.05, 0.003)
    assert chord_sag(faired).max() <= 0.003
    assert np.all(np.diff(prm) > 0)


def test_three_sided_split_along_the_old_surface_sags_under_a_quarter_of_the_fit_tolerance():
    """The fold repair splits three_sided's creased region along the surface before the stroke;
    32 chords sagged 1.5 times the fit tolerance and the report's fit check failed."""
    res = build_network(read_strokes(EXAMPLES / "three_sided.xyz"))
    net = res.network
    splits = [e for e in net.edges().values() if net.curve_info(e.curve_id)["kind"] == "split"]
    assert splits
    for e in splits:
        assert chord_sag(e.polyline.points).max() <= res.tol.sag_mm
