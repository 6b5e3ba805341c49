"""Issue 17 on the real TiGL networks of ../shared/data: the surface does not depend on where the
sketch lies, how it is turned, or in which order and direction its boundary strokes were drawn.
Both networks are tubes cut open along a seam, where the method's choices have exact ties that
round-off used to break: a profile thinner than the filter distance is filtered to a line out and
back (fuselage1: every stroke end on it, and every point over the flat surface it makes, is reached
at two pre-images), and each closed profile can be run either way round (full_nacelle)."""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from ProgSurf.core.boundary import make_boundary
from ProgSurf.core.footpoint import Facets, real_footpoint
from ProgSurf.core.pipeline import build_network, resolve_tolerances
from ProgSurf.core.types import Tolerances
from ProgSurf.io import read_strokes

ROOT = Path(__file__).resolve().parents[2]
TIGL = ROOT.parent / "shared" / "data" / "tigl"
sys.path.insert(0, str(ROOT / "examples"))
from real_data_trial import tigl_boundary  # noqa: E402


def _tigl(name: str) -> tuple[list, int]:
    """The TiGL network `name` boundary first (examples/README.md), and its boundary count."""
    path = TIGL / name.split(".")[0] / f"{name}.xyz"
    if not path.is_file():
        pytest.skip(f"the TiGL sketch {path} is not there (../shared/data is beside the project's own checkout only)")
    strokes = read_strokes(path)
    first = tigl_boundary(path)
    return [strokes[i] for i in first] + [s for i, s in enumerate(strokes) if i not in first], len(first)


def _rotation(rng: np.random.Generator) -> np.ndarray:
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    return q * np.sign(np.linalg.det(q))


def _hausdorff(a: np.ndarray, b: np.ndarray) -> float:
    d = np.linalg.norm(a[:, None] - b[None], axis=2)
    return float(max(d.min(axis=0).max(), d.min(axis=1).max()))


def _surface_points(net, n: int = 25) -> np.ndarray:
    g = np.linspace(0.0, 1.0, n)
    u, v = np.meshgrid(g, g)
    return net.evaluate_uv(np.column_stack([u.ravel(), v.ravel()]))


def test_a_rotated_and_moved_fuselage_builds_the_same_surface():
    """fuselage1 (clean): its end profiles, 200 mm rings on a 38 m fuselage, are filtered to lines
    out and back; rotated (fuzz seed 17 case 14) the one stroke accepted among 15 was another one
    and the surface moved by 1550 mm, 409 times the fit tolerance. Rotated and moved, every stroke
    has the same fate and the surface is the same, moved, within a thousandth of the fit tolerance."""
    strokes, count = _tigl("fuselage1.clean")
    rng = np.random.default_rng(17)
    rot = _rotation(rng)
    shift = rng.normal(size=3) * 1e4
    moved = [s @ rot.T + shift for s in strokes]
    a, b = build_network(strokes, boundary=count), build_network(moved, boundary=count)
    assert [r.status for r in b.records] == [r.status for r in a.records]
    assert any(r.status == "accepted" for r in a.records[count:])
    back = (_surface_points(b.network) - shift) @ rot
    assert _hausdorff(_surface_points(a.network), back) <= 1e-3 * a.tol.fit_mm


def test_a_nacelle_with_its_boundary_strokes_shuffled_and_reversed_closes_the_same_loop():
    """full_nacelle (noisy): two rings and two guides along one seam. The ring that came later in
    the input was the one turned round, so with the boundary strokes shuffled and the guides
    reversed (fuzz seed 17 case 70) each ring was closed at its other end, the loop's sides moved by
    up to 100 mm and the build had 1 face instead of 2. Now the same four sides, to round-off."""
    strokes, count = _tigl("full_nacelle.noisy")
    # (the rings are strokes 0 and 2, the guides 1 and 3)
    shuffled = [strokes[2], strokes[0], strokes[3][::-1].copy(), strokes[1][::-1].copy()]
    tol = resolve_tolerances(strokes[:count], Tolerances())
    loop_a, _ = make_boundary(strokes[:count], count, tol)
    loop_b, _ = make_boundary(shuffled, count, tol)
    for side in loop_a.sides:
        assert min(_hausdorff(np.asarray(side), np.asarray(other)) for other in loop_b.sides) <= 1e-6 * tol.fit_mm


def test_a_footpoint_on_two_coincident_sheets_takes_the_expected_one():
    """Two sheets on each other (one triangle, twice, at different pre-images): the footpoint is the
    one nearest the pre-image the caller expects, whichever comes first; without one, the first."""
    tri = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    low = np.array([[0.0, 0.0], [0.4, 0.0], [0.0, 0.4]])
    high = 1.0 - low
    q = np.array([0.2, 0.2, 0.5])
    for first, second in ((low, high), (high, low)):
        facets = Facets(np.stack([tri, tri]), np.stack([first, second]), np.array([0, 1]))
        assert np.allclose(real_footpoint(q, facets, near_uv=np.array([0.9, 0.9])).uv, np.array([0.6, 0.2, 0.2]) @ high)
        assert np.allclose(real_footpoint(q, facets, near_uv=np.array([0.1, 0.1])).uv, np.array([0.6, 0.2, 0.2]) @ low)
        assert np.allclose(real_footpoint(q, facets).uv, np.array([0.6, 0.2, 0.2]) @ first)
