"""Point-list reader/writer and read_strokes dispatch: round trips, every separator, and bad files
raise only StrokeFileError (never another exception)."""
from __future__ import annotations

import glob
import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ProgSurf.core.errors import InvalidStrokeError, ProgSurfError, StrokeFileError
from ProgSurf.io import read_strokes
from ProgSurf.io.pointlist import read_point_list, write_point_list

ROOT = Path(__file__).resolve().parents[2]
SHARED = ROOT.parent / "shared" / "data"

coord = st.floats(min_value=-1e5, max_value=1e5, allow_nan=False, allow_infinity=False)
stroke_st = st.lists(st.tuples(coord, coord, coord), min_size=1, max_size=8).map(lambda p: np.array(p, float))
hyp = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])


@hyp
@given(strokes=st.lists(stroke_st, min_size=1, max_size=5))
def test_write_then_read_round_trips(tmp_path, strokes):
    path = tmp_path / "a.xyz"
    copies = [s.copy() for s in strokes]
    write_point_list(path, strokes)
    back = read_point_list(path)
    assert len(back) == len(strokes)
    for a, b in zip(strokes, back):
        assert b.shape == a.shape
        np.testing.assert_allclose(b, a, atol=1e-6, rtol=0)
    for a, c in zip(strokes, copies):
        np.testing.assert_array_equal(a, c)
    assert path.read_text().startswith("#")


@pytest.mark.parametrize("sep", [" ", "\t", ",", ";", " ; ", ", ", "  \t "])
def test_every_separator_reads_the_same(tmp_path, sep):
    text = "# two strokes\n\n" + "\n".join(sep.join(r) for r in [("1", "2", "3"), ("4", "5", "6")])
    text += "\n\n\n" + sep.join(("7", "8.5", "-9e-1")) + "\n" + sep.join(("0", "0", "1")) + "\n"
    (tmp_path / "s.txt").write_text(text)
    got = read_point_list(tmp_path / "s.txt")
    assert [g.tolist() for g in got] == [[[1, 2, 3], [4, 5, 6]], [[7, 8.5, -0.9], [0, 0, 1]]]


def test_fourth_column_names_strokes_and_header_is_skipped(tmp_path):
    text = "x,y,z,stroke\n0,0,0,5\n1,0,0,5\n0,1,0,2\n2,0,0,5\n\n0,2,0,2\n"
    (tmp_path / "s.csv").write_text(text)
    got = read_strokes(tmp_path / "s.csv")
    assert [g.tolist() for g in got] == [[[0, 0, 0], [1, 0, 0], [2, 0, 0]], [[0, 1, 0], [0, 2, 0]]]


def test_header_with_spaces_and_crlf(tmp_path):
    (tmp_path / "s.asc").write_bytes(b"X Y Z\r\n1 2 3\r\n4 5 6\r\n")
    assert read_strokes(tmp_path / "s.asc")[0].tolist() == [[1, 2, 3], [4, 5, 6]]


@pytest.mark.parametrize("text, pattern", [
    ("1 2 3\n4 abc 6\n", r"line 2 of bad\.xyz: expected 3 numbers, got 'abc'"),
    ("# c\n1 2\n", r"line 2 of bad\.xyz: expected 3 numbers .* got 2"),
    ("1 2 3 4 5\n", r"line 1 of bad\.xyz"),
    ("1 2 nan\n", r"line 1 of bad\.xyz: .*not finite"),
    ("1 2 3 1\n1 2 3\n", r"line 2 of bad\.xyz: has 3 columns but line 1 has 4"),
    ("1 2 3 1.5\n", r"line 1 of bad\.xyz: stroke column '1.5' is not an integer"),
    ("# only comments\n\n", r"bad\.xyz contains no points"),
    ("", r"bad\.xyz contains no points"),
    ("x y z\nx y z\n", r"line 2 of bad\.xyz"),
])
def test_malformed_lines_name_file_and_line(tmp_path, text, pattern):
    (tmp_path / "bad.xyz").write_text(text)
    with pytest.raises(StrokeFileError, match=pattern):
        read_point_list(tmp_path / "bad.xyz")


def test_missing_file_binary_file_and_unknown_extension(tmp_path):
    with pytest.raises(StrokeFileError, match="cannot read"):
        read_strokes(tmp_path / "nope.xyz")
    with pytest.raises(StrokeFileError, match="cannot read"):
        read_point_list(tmp_path)
    (tmp_path / "b.xyz").write_bytes(b"\x00\x01\x02")
    with pytest.raises(StrokeFileError, match="binary"):
        read_strokes(tmp_path / "b.xyz")
    (tmp_path / "a.stl").write_text("1 2 3\n")
    with pytest.raises(StrokeFileError, match=r"\.xyz, \.txt, \.csv, \.asc, \.c3d"):
        read_strokes(tmp_path / "a.stl")
    (tmp_path / "a.xyz").write_text("1 2 3\n")
    with pytest.raises(StrokeFileError, match="only for .c3d"):
        read_strokes(tmp_path / "a.xyz", rate=100)


def test_writer_refuses_what_it_cannot_write_back(tmp_path):
    with pytest.raises(InvalidStrokeError):
        write_point_list(tmp_path / "a.xyz", [])
    with pytest.raises(InvalidStrokeError, match="stroke 1"):
        write_point_list(tmp_path / "a.xyz", [np.zeros((2, 3)), np.array([[0, 0, np.nan]])])
    with pytest.raises(InvalidStrokeError, match="stroke 0"):
        write_point_list(tmp_path / "a.xyz", [np.zeros((2, 2))])


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.binary(max_size=200))
def test_random_bytes_raise_only_stroke_file_errors(tmp_path, data):
    path = tmp_path / "r.xyz"
    path.write_bytes(data)
    try:
        strokes = read_point_list(path)
    except StrokeFileError:
        return
    assert strokes and all(s.ndim == 2 and s.shape[1] == 3 and np.isfinite(s).all() for s in strokes)


line_st = st.one_of(
    st.text(alphabet="0123456789.-+eE ,;\t#abcxyzn", max_size=30),
    st.lists(coord.map(repr), min_size=1, max_size=5).map(" ".join),
    st.just(""),
)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(lines=st.lists(line_st, max_size=12))
def test_garbage_lines_raise_only_project_errors(tmp_path, lines):
    path = tmp_path / "g.txt"
    path.write_text("\n".join(lines))
    try:
        strokes = read_strokes(path)
    except ProgSurfError:
        return
    assert all(s.shape[1] == 3 and s.shape[0] >= 1 for s in strokes)


SHARED_FILES = sorted(glob.glob(str(SHARED / "cassie" / "*.xyz")) + glob.glob(str(SHARED / "tigl" / "*" / "*.xyz")))


@pytest.mark.skipif(not SHARED_FILES, reason=f"shared sketch data not found at {SHARED}")
@pytest.mark.parametrize("path", SHARED_FILES or [None], ids=lambda p: Path(p).name if p else "absent")
def test_shared_sketches_read_with_the_counts_their_headers_state(path):
    text = Path(path).read_text()
    strokes = read_strokes(path)
    m = re.search(r"strokes: (\d+)", text)
    assert m and len(strokes) == int(m.group(1))
    m = re.search(r"points: (\d+)", text)
    if m:
        assert sum(len(s) for s in strokes) == int(m.group(1))
    first = next(line for line in text.splitlines() if line and not line.startswith("#"))
    np.testing.assert_allclose(strokes[0][0], [float(v) for v in first.split()])
