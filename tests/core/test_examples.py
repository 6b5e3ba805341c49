"""The bundled example sketches: reproducible, self-describing, on their closed-form surfaces, and
each closes into the boundary its header announces."""
from __future__ import annotations

import importlib.util
import re
from pathlib import Path

import numpy as np
import pytest

from ProgSurf.core.boundary import make_boundary
from ProgSurf.io import read_strokes

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
FILES = {"clean4.xyz": (4, 3), "rough4.xyz": (4, 3), "fig10_five_sided.xyz": (5, 1), "three_sided.xyz": (3, 1)}


def _generator():
    spec = importlib.util.spec_from_file_location("make_examples", EXAMPLES / "make_examples.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_regenerating_the_examples_gives_identical_files(tmp_path):
    _generator().write_examples(str(tmp_path))
    for name in FILES:
        assert (tmp_path / name).read_bytes() == (EXAMPLES / name).read_bytes(), name


@pytest.mark.parametrize("name", FILES)
def test_header_says_what_it_is_and_how_many_boundary_strokes_come_first(name):
    text = (EXAMPLES / name).read_text()
    header = [line for line in text.splitlines() if line.startswith("#")]
    assert text.startswith("#")
    nb, ni = FILES[name]
    m = re.search(r"boundary strokes first: (\d+)", "\n".join(header))
    assert m and int(m.group(1)) == nb
    assert len(read_strokes(EXAMPLES / name)) == nb + ni


@pytest.mark.parametrize("name, surface", [("clean4.xyz", "saddle"), ("three_sided.xyz", "dome"),
                                           ("fig10_five_sided.xyz", "dome"), ("rough4.xyz", "saddle")])
def test_strokes_lie_on_their_surface(name, surface):
    f = getattr(_generator(), surface)
    noise = 0.0 if name == "clean4.xyz" else 2.5  # wobble + jitter of the rough sketches, mm
    for s in read_strokes(EXAMPLES / name):
        assert np.max(np.abs(s[:, 2] - f(s[:, 0], s[:, 1]))) <= noise + 1e-4


@pytest.mark.parametrize("name", FILES)
def test_each_example_closes_with_its_announced_boundary(name):
    strokes = read_strokes(EXAMPLES / name)
    nb, ni = FILES[name]
    loop, interior = make_boundary(strokes, nb)
    assert interior == list(range(nb, nb + ni))
    assert sorted(i for s in loop.source for i in s) == list(range(nb))
    assert loop.triangle == (nb == 3)
    np.testing.assert_array_equal(loop.bottom[-1], loop.right[0])
    np.testing.assert_array_equal(loop.top[0], loop.left[-1])


def test_rough4_really_is_rough():
    strokes = read_strokes(EXAMPLES / "rough4.xyz")[:4]
    ends = np.array([[s[0], s[-1]] for s in strokes]).reshape(-1, 3)
    dist = np.linalg.norm(ends[:, None] - ends[None], axis=2) + np.eye(8) * 1e9
    assert dist.min(axis=1).min() > 1.0  # no two stroke ends meet: every corner overshoots or gaps
    loop, _ = make_boundary(read_strokes(EXAMPLES / "rough4.xyz"), 4)
    assert any("trimmed" in n for n in loop.notes) and any("extended" in n for n in loop.notes)
