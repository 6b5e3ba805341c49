"""CASSIE .curves files (io.curves.read_curves, through read_strokes): metres to mm, strokes in
file order, and every malformed file refused with a StrokeFileError naming its line."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ProgSurf.core.errors import StrokeFileError
from ProgSurf.io import SUPPORTED_EXTENSIONS, read_strokes
from ProgSurf.io.curves import write_curves

SHARED = Path(__file__).resolve().parents[2].parent / "shared" / "data" / "cassie"

TWO = """v 3
-0.121317677 0.8807437 0.759578
-0.118458338 0.8773268 0.7765151
-0.1 0.87 0.79
v 2
0.5 0.25 -0.125
0.5 0.5 -0.125
"""


def test_a_curves_file_reads_as_strokes_in_millimetres(tmp_path):
    path = tmp_path / "lamp.curves"
    path.write_text(TWO)
    strokes = read_strokes(path)
    assert ".curves" in SUPPORTED_EXTENSIONS
    assert [len(s) for s in strokes] == [3, 2]
    np.testing.assert_allclose(strokes[0][1], [-118.458338, 877.3268, 776.5151])
    np.testing.assert_allclose(strokes[1], [[500, 250, -125], [500, 500, -125]])


@pytest.mark.parametrize("text, where", [
    ("0 0 0\nv 1\n0 0 0\n", "line 1"),                # a point before any 'v N'
    ("v 2\n0 0 0\n", "line 1"),                       # fewer points than announced
    ("v 1\n0 0 0\n1 1 1\n", "line 1"),                # more
    ("v x\n0 0 0\n", "line 1"),                       # a bad count
    ("v 1\n0 0\n", "line 2"),                         # two numbers
    ("v 1\n0 nan 0\n", "line 2"),                     # not finite
    ("v 1\n0 0 a\n", "line 2"),
    ("", "no points"),
    ("v 0\n", "no points"),
    ("v 1\n0 0 \x00\n", "binary file, not a .curves file"),
])
def test_a_malformed_curves_file_is_refused_naming_its_line(tmp_path, text, where):
    path = tmp_path / "bad.curves"
    path.write_text(text)
    with pytest.raises(StrokeFileError, match=where):
        read_strokes(path)


def test_written_strokes_read_back_as_written(tmp_path):
    strokes = [np.array([[0.0, 1.5, -2.25], [1234.5678, 1e-3, 987654.321]]), np.array([[5.0, 6.0, 7.0]])]
    path = tmp_path / "w.curves"
    write_curves(path, strokes)
    assert path.read_text().splitlines()[:2] == ["v 2", "0.0 0.0015 -0.00225"]
    for a, b in zip(read_strokes(path), strokes):
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12)


def test_options_are_for_c3d_files_only(tmp_path):
    path = tmp_path / "a.curves"
    path.write_text(TWO)
    with pytest.raises(StrokeFileError, match="c3d"):
        read_strokes(path, labels=["pen"])


@pytest.mark.skipif(not SHARED.is_dir(), reason="../shared/data/cassie is absent (a user's clone)")
@pytest.mark.parametrize("name", ["04-1-1", "teapot"])
def test_the_shared_cassie_originals_read_as_their_mm_copies(name):
    """../shared holds each CASSIE sketch as .curves (metres) and as .xyz converted to mm."""
    ours = read_strokes(SHARED / f"{name}.curves")
    theirs = read_strokes(SHARED / f"{name}.xyz")
    assert len(ours) == len(theirs)
    for a, b in zip(ours, theirs):
        np.testing.assert_allclose(a, b, atol=1e-3)
