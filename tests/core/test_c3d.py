"""C3D reader: strokes from marker trajectories, pen-up where the marker is covered (issue 7).

Every file is written here with the `c3d` library's Writer (tests/core/c3d_fixtures.py), so each
sample is known and the stroke splits can be checked exactly.
Run: /work/main/.venv/bin/python -m pytest tests/core/test_c3d.py
"""
from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("c3d", reason="the c3d package is not installed: .venv/bin/pip install c3d")

sys.path.insert(0, str(Path(__file__).resolve().parent))
from c3d_fixtures import quantise, runs_to_trajectory, write_c3d  # noqa: E402

from hypothesis import HealthCheck, example, given, settings, strategies as st  # noqa: E402
from hypothesis.extra import numpy as hnp  # noqa: E402

from ProgSurf.core.errors import InvalidOptionError, MissingPackageError, StrokeFileError  # noqa: E402
from ProgSurf.core.strokes import auto_filter_threshold  # noqa: E402
from ProgSurf.io.c3d import (  # noqa: E402
    list_markers, read_c3d, read_c3d_strokes, smooth_stroke,
)

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "sketch_mocap.c3d"
RAW = dict(min_duration_s=0.0, min_length_mm=0.0, filter_mm=0)  # keep every valid sample


def helix(t: np.ndarray) -> np.ndarray:
    """A known trajectory in mm at frame indices t (never passes through the origin)."""
    t = np.asarray(t, float)
    return np.column_stack([50 + 40 * np.cos(t / 25), 30 + 40 * np.sin(t / 25), 10 + 0.2 * t])


# --------------------------------------------------------------------------- stroke splits


def test_gaps_split_strokes_at_exact_frames(tmp_path):
    n = 400
    pts = helix(np.arange(n))
    valid = np.ones(n, bool)
    valid[100:120] = False      # occluded: residual -1
    pts[200:203] = np.nan       # NaN gap with a valid residual
    pts[300:305] = 0.0          # zero-filled gap
    valid[350] = False          # one-frame dropout
    valid[352] = False          # leaves a 1-sample run at index 351
    path = write_c3d(tmp_path / "gaps.c3d", pts[:, None], ["Pen"], valid=valid[:, None])

    r = read_c3d(path, **RAW)
    runs = [(0, 99), (120, 199), (203, 299), (305, 349), (353, 399)]
    assert r.frames == tuple((a + 1, b + 1) for a, b in runs)  # file frames start at 1
    assert r.markers == ("Pen",) * 5
    for stroke, (a, b) in zip(r.strokes, runs):
        np.testing.assert_allclose(stroke, helix(np.arange(a, b + 1)), atol=1e-4)
    assert [(d.frames, "1 sample" in d.reason) for d in r.dropped] == [((352, 352), True)]
    assert r.frame_rate == 100.0 and r.units == "mm" and r.labels == ("Pen",)


def test_frames_are_file_frame_numbers(tmp_path):
    pts, valid = runs_to_trajectory(60, [(5, 24), (40, 59)], helix)
    path = write_c3d(tmp_path / "start.c3d", pts[:, None], ["Pen"], valid=valid[:, None],
                     first_frame=1000)
    assert read_c3d(path, **RAW).frames == ((1005, 1024), (1040, 1059))


def test_short_runs_dropped_by_duration_and_length(tmp_path):
    line = lambda t: np.column_stack([np.asarray(t, float), np.zeros(len(t)), np.full(len(t), 7.0)])
    slow = lambda t: np.column_stack([0.1 * np.asarray(t, float), np.ones(len(t)), np.ones(len(t))])
    n = 200
    pts = np.zeros((n, 3))
    valid = np.zeros(n, bool)
    for (a, b), f in [((0, 8), line), ((20, 29), line), ((50, 89), slow), ((100, 199), line)]:
        pts[a : b + 1], valid[a : b + 1] = f(np.arange(a, b + 1)), True
    path = write_c3d(tmp_path / "short.c3d", pts[:, None], ["Pen"], valid=valid[:, None])

    r = read_c3d(path, min_duration_s=0.1, min_length_mm=5.0, filter_mm=0)
    # 9 frames = 0.09 s: dropped; 10 frames = 0.1 s: kept; 40 frames of 0.1 mm steps = 3.9 mm: dropped
    assert r.frames == ((21, 30), (101, 200))
    reasons = {d.frames: d.reason for d in r.dropped}
    assert set(reasons) == {(1, 9), (51, 90)}
    assert "min_duration_s" in reasons[(1, 9)] and "min_length_mm" in reasons[(51, 90)]

    with pytest.raises(StrokeFileError, match="no stroke left"):
        read_c3d_strokes(path, min_duration_s=5.0)


# --------------------------------------------------------------------------- storage and units


@pytest.mark.parametrize("scale", [0.25, 0.5])
def test_integer_and_float_storage_read_the_same(tmp_path, scale):
    pts, valid = runs_to_trajectory(300, [(0, 140), (170, 299)], helix)
    pts = quantise(pts, scale)  # exact in 16-bit integers times scale
    f = write_c3d(tmp_path / "f.c3d", pts[:, None], ["Pen"], valid=valid[:, None], scale=-1.0)
    i = write_c3d(tmp_path / "i.c3d", pts[:, None], ["Pen"], valid=valid[:, None], scale=scale)
    assert i.stat().st_size < f.stat().st_size  # really stored as int16

    rf, ri = read_c3d(f, **RAW), read_c3d(i, **RAW)
    assert rf.frames == ri.frames == ((1, 141), (171, 300))
    for a, b, (lo, hi) in zip(rf.strokes, ri.strokes, [(0, 140), (170, 299)]):
        np.testing.assert_array_equal(a, b)
        np.testing.assert_allclose(b, pts[lo : hi + 1], atol=1e-9)


@pytest.mark.parametrize("units,factor", [("m", 1000.0), ("cm", 10.0), ("mm", 1.0),
                                          ("METERS", 1000.0), ("  ", 1.0)])
def test_units_convert_to_mm(tmp_path, units, factor):
    pts, valid = runs_to_trajectory(200, [(10, 90), (120, 199)], helix)
    path = write_c3d(tmp_path / "u.c3d", pts[:, None] / factor, ["Pen"], units=units,
                     valid=valid[:, None])
    r = read_c3d(path, **RAW)
    assert r.units == (units.strip() or "mm")
    for stroke, (a, b) in zip(r.strokes, [(10, 90), (120, 199)]):
        # float32 storage: relative precision 6e-8 of coordinates up to ~100 mm
        np.testing.assert_allclose(stroke, helix(np.arange(a, b + 1)), atol=2e-5)


def test_metre_and_millimetre_files_give_the_same_strokes(tmp_path):
    pts, valid = runs_to_trajectory(300, [(0, 99), (150, 299)], helix)
    mm = write_c3d(tmp_path / "mm.c3d", pts[:, None], ["Pen"], units="mm", valid=valid[:, None])
    m = write_c3d(tmp_path / "m.c3d", pts[:, None] / 1000, ["Pen"], units="m", valid=valid[:, None])
    a, b = read_c3d(mm, smooth=5), read_c3d(m, smooth=5)  # default filter and smoothing too
    assert a.frames == b.frames and len(a.strokes) == 2
    assert a.filter_mm == pytest.approx(b.filter_mm, rel=1e-6)
    for sa, sb in zip(a.strokes, b.strokes):
        assert sa.shape == sb.shape
        np.testing.assert_allclose(sa, sb, atol=1e-4)


def test_unknown_units_rejected(tmp_path):
    path = write_c3d(tmp_path / "in.c3d", helix(np.arange(50))[:, None], ["Pen"], units="in")
    with pytest.raises(StrokeFileError, match="POINT:UNITS is 'in'.*m, cm or mm"):
        read_c3d(path)


# --------------------------------------------------------------------------- markers


@pytest.fixture()
def three_markers(tmp_path):
    n = 300
    t = np.arange(n)
    lhand = np.column_stack([10 + 0.05 * t, np.full(n, 5.0), np.full(n, 5.0)])  # ~14 mm path
    rfin = helix(t)                                                               # ~500 mm path
    head = np.column_stack([np.full(n, 1.0), 0.5 * t + 1, np.full(n, 1700.0)])     # ~144 mm path
    valid = np.ones((n, 3), bool)
    valid[100:150, 1] = False
    valid[200:210, 2] = False
    valid[50:60, 0] = False
    pts = np.stack([lhand, rfin, head], axis=1)
    path = write_c3d(tmp_path / "three.c3d", pts, ["LHand", "RFIN", "Head"], valid=valid)
    return path, pts, valid


def test_default_marker_is_the_most_moving(three_markers):
    path, pts, valid = three_markers
    r = read_c3d(path, **RAW)
    expected = []
    for m in range(3):
        steps = np.linalg.norm(np.diff(pts[:, m], axis=0), axis=1)
        expected.append(steps[valid[1:, m] & valid[:-1, m]].sum())  # no bridging over gaps
    np.testing.assert_allclose(r.path_mm, expected, rtol=1e-5)
    assert int(np.argmax(expected)) == 1
    assert r.markers == ("RFIN", "RFIN") and r.frames == ((1, 100), (151, 300))
    np.testing.assert_allclose(r.strokes[1], pts[150:, 1], atol=1e-4)
    assert list_markers(path) == ["LHand", "RFIN", "Head"]


def test_markers_chosen_by_label_case_insensitive(three_markers):
    path, pts, _ = three_markers
    r = read_c3d(path, markers=["  head ", "LHAND"], **RAW)
    # ordered by first frame, then by the order the markers were asked for
    assert r.markers == ("Head", "LHand", "LHand", "Head")
    assert r.frames == ((1, 200), (1, 50), (61, 300), (211, 300))
    np.testing.assert_allclose(r.strokes[0], pts[:200, 2], atol=1e-4)
    np.testing.assert_allclose(r.strokes[2], pts[60:, 0], atol=1e-4)
    assert read_c3d(path, markers="rfin", **RAW).markers == ("RFIN", "RFIN")


def test_unknown_marker_lists_available_labels(three_markers):
    path, _, _ = three_markers
    with pytest.raises(StrokeFileError, match="no marker 'Nose'; available labels: LHand, RFIN, Head"):
        read_c3d_strokes(path, markers=["RFIN", "Nose"])
    with pytest.raises(InvalidOptionError, match="markers is an empty list"):
        read_c3d(path, markers=[])


# --------------------------------------------------------------------------- cleaning


def test_filter_uses_the_paper_distance_threshold(tmp_path):
    t = np.arange(500)
    speed = 0.2 + 1.6 * (np.sin(t / 40) ** 2)  # fixed rate, varying hand speed
    x = np.cumsum(speed)
    pts = np.column_stack([x, 10 * np.sin(x / 30), np.full(len(t), 3.0)])
    path = write_c3d(tmp_path / "f.c3d", pts[:, None], ["Pen"])

    raw = read_c3d(path, **RAW).strokes[0]
    r = read_c3d(path, min_duration_s=0, min_length_mm=0, filter_mm=4.0)
    s = r.strokes[0]
    assert r.filter_mm == 4.0
    np.testing.assert_array_equal(s[[0, -1]], raw[[0, -1]])  # ends kept
    gaps = np.linalg.norm(np.diff(s, axis=0), axis=1)
    assert gaps.min() >= 4.0 - 1e-9 and len(s) < len(raw) / 2

    auto = read_c3d(path, min_duration_s=0, min_length_mm=0)
    assert auto.filter_mm == pytest.approx(auto_filter_threshold([raw]))


def test_smoothing_keeps_stroke_ends_and_removes_jitter(tmp_path):
    rng = np.random.default_rng(3)
    clean = helix(np.arange(400))
    noisy = clean + rng.normal(0, 0.5, clean.shape)
    path = write_c3d(tmp_path / "n.c3d", noisy[:, None], ["Pen"])
    raw = read_c3d(path, **RAW).strokes[0]
    smoothed = read_c3d(path, min_duration_s=0, min_length_mm=0, filter_mm=0, smooth=9).strokes[0]
    np.testing.assert_array_equal(smoothed[[0, -1]], raw[[0, -1]])
    err_raw = np.linalg.norm(raw - clean, axis=1)[20:-20].mean()
    err_smooth = np.linalg.norm(smoothed - clean, axis=1)[20:-20].mean()
    assert err_smooth < 0.5 * err_raw


@settings(max_examples=60, deadline=None)
@given(pts=hnp.arrays(np.float64, st.tuples(st.integers(1, 40), st.just(3)),
                      elements=st.floats(-1e3, 1e3)),
       window=st.integers(0, 15))
def test_smooth_stroke_fixes_ends_and_reproduces_lines(pts, window):
    out = smooth_stroke(pts, window)
    assert out.shape == pts.shape
    np.testing.assert_array_equal(out[[0, -1]], pts[[0, -1]])
    # a symmetric moving average reproduces uniformly sampled straight lines
    line = pts[0] + np.linspace(0, 1, len(pts))[:, None] * (pts[-1] - pts[0])
    np.testing.assert_allclose(smooth_stroke(line, window), line, atol=1e-9)


@pytest.mark.parametrize("kw,match", [({"min_duration_s": -1}, "min_duration_s"),
                                      ({"min_length_mm": float("nan")}, "min_length_mm"),
                                      ({"filter_mm": -2.0}, "filter_mm"),
                                      ({"smooth": 2.5}, "smooth")])
def test_bad_options_rejected(tmp_path, kw, match):
    path = write_c3d(tmp_path / "o.c3d", helix(np.arange(50))[:, None], ["Pen"])
    with pytest.raises(InvalidOptionError, match=match):
        read_c3d(path, **kw)


# --------------------------------------------------------------------------- bad input


@pytest.fixture()
def good_file(tmp_path):
    pts, valid = runs_to_trajectory(400, [(0, 199), (250, 399)], helix)
    return write_c3d(tmp_path / "good.c3d", np.stack([pts, pts + 1], 1), ["A", "B"],
                     valid=np.stack([valid, valid], 1))


def test_not_a_c3d_file(tmp_path):
    text = tmp_path / "strokes.c3d"
    text.write_text("0 0 0\n1 1 1\n")
    with pytest.raises(StrokeFileError, match="is not a C3D file: byte 2 is 0x20"):
        read_c3d_strokes(text)
    empty = tmp_path / "empty.c3d"
    empty.write_bytes(b"")
    with pytest.raises(StrokeFileError, match="is not a C3D file"):
        read_c3d_strokes(empty)
    with pytest.raises(StrokeFileError, match="no such C3D file"):
        read_c3d_strokes(tmp_path / "missing.c3d")


@pytest.mark.parametrize("cut", [300, 600, 1300, 4000])
def test_truncated_file(good_file, tmp_path, cut):
    data = good_file.read_bytes()
    assert cut < len(data) - 512
    short = tmp_path / "short.c3d"
    short.write_bytes(data[:cut])
    with pytest.raises(StrokeFileError, match="truncated"):
        read_c3d_strokes(short)
    if cut < 1024:  # the parameter section itself is cut
        with pytest.raises(StrokeFileError, match="truncated"):
            list_markers(short)


@settings(max_examples=40, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(cut=st.integers(0, 8000), flip=st.integers(0, 2000), byte=st.integers(0, 255))
@example(cut=0, flip=16, byte=0)      # the header's data block 0: the reader sought before the start
def test_damaged_files_give_stroke_file_error_or_the_right_strokes(good_file, tmp_path, cut, flip,
                                                                    byte):
    """Cut or corrupt a good file anywhere: never a traceback, only StrokeFileError or a result."""
    data = bytearray(good_file.read_bytes())
    reference = read_c3d(good_file, **RAW)
    for variant in (bytes(data[: min(cut, len(data))]),
                    bytes(data[:flip]) + bytes([byte]) + bytes(data[flip + 1 :])):
        damaged = tmp_path / "damaged.c3d"
        damaged.write_bytes(variant)
        try:
            result = read_c3d(damaged, **RAW)
        except StrokeFileError as exc:
            assert str(exc)
            continue
        if variant == bytes(data[: len(variant)]):  # only padding was cut: same strokes
            assert result.frames == reference.frames


def test_file_with_no_points(tmp_path):
    path = write_c3d(tmp_path / "nopoints.c3d", np.zeros((20, 0, 3)), [])
    with pytest.raises(StrokeFileError, match=r"has no 3D points \(POINT:USED is 0\)"):
        read_c3d_strokes(path)
    hidden = write_c3d(tmp_path / "hidden.c3d", helix(np.arange(20))[:, None], ["Pen"],
                       valid=np.zeros((20, 1), bool))
    with pytest.raises(StrokeFileError, match="no valid marker sample"):
        read_c3d_strokes(hidden)


def test_missing_library_says_how_to_install(good_file, monkeypatch):
    monkeypatch.setitem(sys.modules, "c3d", None)  # makes `import c3d` raise ImportError
    with pytest.raises(MissingPackageError, match=r"reading C3D files needs .*pip install c3d"):
        read_c3d_strokes(good_file)


def test_dispatcher_reads_c3d(good_file):
    from ProgSurf.io import read_strokes

    strokes = read_strokes(good_file, markers=["b"], filter_mm=0)
    direct = read_c3d_strokes(good_file, markers=["B"], filter_mm=0)
    assert len(strokes) == 2
    for a, b in zip(strokes, direct):
        np.testing.assert_array_equal(a, b)


# --------------------------------------------------------------------------- size


def test_100k_frames_read_in_bounded_memory(tmp_path):
    """100,000 frames x 6 markers (9.6 MB file) read in a fresh interpreter whose peak resident
    memory stays bounded (~70 MB measured, of which ~35 MB is Python + numpy). No timing asserted."""
    n, m = 100_000, 6
    t = np.arange(n)
    pts = np.stack([helix(t + 1000 * k) * (1 + k) for k in range(m)], axis=1)
    valid = np.ones((n, m), bool)
    valid[::997] = False  # a pen-up about every 10 s
    path = write_c3d(tmp_path / "big.c3d", pts, [f"M{k}" for k in range(m)], valid=valid)
    child = (
        "import resource, sys\n"
        "from ProgSurf.io.c3d import read_c3d\n"
        "r = read_c3d(sys.argv[1], filter_mm=0)\n"
        "print(r.markers[0], len(r.strokes), sum(len(s) for s in r.strokes),\n"
        "      [int(l.split()[1]) for l in open('/proc/self/status') if l.startswith('VmHWM:')][0])\n"
    )
    import c3d  # the child must find the same library as this process (maybe via .venv)

    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT), str(Path(c3d.__file__).parents[1])]))
    out = subprocess.run([sys.executable, "-c", child, str(path)], cwd=ROOT, env=env,
                         capture_output=True, text=True, check=True).stdout.split()
    pen_ups = len(range(0, n, 997))
    assert out[:3] == ["M5", str(pen_ups), str(n - pen_ups)]  # M5 is scaled by 6: most-moving
    # VmHWM (KiB): this process's own peak; ru_maxrss would keep the parent's (pytest's) peak
    # across fork and exec, which made this test fail when the suite had grown to 250 MB
    peak_mb = int(out[3]) / 1024
    assert peak_mb < 250, f"peak resident memory {peak_mb:.0f} MB"


# --------------------------------------------------------------------------- bundled example


def _load_example_script():
    spec = importlib.util.spec_from_file_location("make_c3d_example",
                                                  ROOT / "examples" / "make_c3d_example.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_bundled_example_has_boundary_then_interior_strokes():
    script = _load_example_script()
    r = read_c3d(EXAMPLE)
    assert r.units == "m" and r.frame_rate == 100.0 and r.labels == ("PEN",)
    strokes = read_c3d_strokes(EXAMPLE)
    assert len(strokes) == 6 == len(r.strokes)
    assert [d.reason.startswith("lasts 0.05 s") for d in r.dropped] == [True]  # the flicker
    corners = np.array([[0, 0], [100, 0], [100, 80], [0, 80]], float)
    for k in range(4):  # bottom, right, top, left: each runs from one corner to the next
        s = strokes[k]
        assert np.linalg.norm(s[0, :2] - corners[k]) < 3.0
        assert np.linalg.norm(s[-1, :2] - corners[(k + 1) % 4]) < 3.0
    for s in strokes[4:]:  # interior: every point strictly inside the boundary
        assert (s[:, 0] > 1).all() and (s[:, 0] < 99).all()
        assert (s[:, 1] > 1).all() and (s[:, 1] < 79).all()
    for s in strokes:  # drawn over the closed-form surface, within tracker jitter
        dz = s[:, 2] - script.surface_z(s[:, 0], s[:, 1])
        assert np.abs(dz).max() < 1.5


def test_bundled_example_is_what_the_script_writes(tmp_path):
    script = _load_example_script()
    fresh = script.make_example(tmp_path / "again.c3d")
    assert fresh.read_bytes() == EXAMPLE.read_bytes()
