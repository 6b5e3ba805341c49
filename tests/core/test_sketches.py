"""The project's sketch generator (benchmarks.sketches) draws what its docstring says it draws.

numpy only: the strokes are checked against the truth they were drawn from.
"""
from __future__ import annotations

import numpy as np
import pytest

from benchmarks import sketches as S

NZ = S.NOISE


@pytest.fixture(scope="module")
def fam():
    """Three sketches of every configuration."""
    return S.family(per=3, seed_base=11)


def _middle(points: np.ndarray) -> np.ndarray:
    """The middle half of a stroke's points: over the region for every stroke kind (a crossing
    stroke runs at most 6% of its length past the boundary)."""
    n = len(points)
    return points[n // 4: n - n // 4]


def test_deterministic_per_seed():
    a, b, c = S.make_config("cyl_penta", 5), S.make_config("cyl_penta", 5), S.make_config("cyl_penta", 6)
    assert len(a.strokes) == len(b.strokes)
    for p, q in zip(a.strokes + a.clean, b.strokes + b.clean):
        np.testing.assert_array_equal(p, q)
    assert np.array_equal(a.truth.region.verts, b.truth.region.verts)
    assert len(a.strokes) != len(c.strokes) or any(
        len(p) != len(q) or not np.allclose(p, q) for p, q in zip(a.strokes, c.strokes))


def test_family_covers_every_configuration(fam):
    assert len(fam) == 3 * len(S.CONFIGS)
    assert len({s.name for s in fam}) == len(fam)
    assert {s.config for s in fam} == set(S.CONFIGS)
    for s in fam:
        roles = [m["role"] for m in s.meta]
        assert roles == ["boundary"] * s.n_boundary + ["interior"] * (len(roles) - s.n_boundary)
        assert 3 <= len(roles) - s.n_boundary <= 8
        expect = {"octant": (3, 3), "cyl_penta": (5, 5), "cyl_split": (4, 5)}.get(s.config, (4, 4))
        assert (s.sides, s.n_boundary) == expect, s.name
        assert all(15 <= len(p) <= 250 for p in s.strokes)
        assert all(p.shape == q.shape for p, q in zip(s.strokes, s.clean))
    diags = [s.diag for s in fam]
    assert 100.0 < min(diags) < 150.0 and 1000.0 < max(diags) < 1400.0   # 100 mm .. 1 m sketches


def test_boundary_ends_overshoot_or_stop_short_within_three_percent(fam):
    kinds = set()
    for s in fam:
        corners = s.truth(s.truth.region.verts)
        for m, c in zip(s.meta[:s.n_boundary], s.clean[:s.n_boundary]):
            for (what, mm), p in zip(m["ends"], (c[0], c[-1])):
                kinds.add(what)
                if what == "split":
                    assert NZ["split"][0] * m["L"] <= mm <= NZ["split"][1] * m["L"]
                    continue
                bound = (NZ["open_gap"] if what == "open" else NZ["corner_max"]) * m["L"]
                gap = np.linalg.norm(corners - p, axis=1).min()
                assert abs(mm) <= bound * (1 + 1e-9), (s.name, what, mm, bound)
                assert gap <= abs(mm) * (1 + 1e-3) + 1e-6 * s.diag, (s.name, what, gap, mm)
                if what == "over":      # straight on along the end tangent: exactly mm past the corner
                    assert gap == pytest.approx(mm, rel=1e-6, abs=1e-6 * s.diag)
    assert {"over", "short", "open", "split"} <= kinds
    rev = [m["reversed"] for s in fam for m in s.meta]
    assert 0.15 < np.mean(rev) < 0.45


def test_interior_plan_crosses_stops_short_and_lifts_exactly_one(fam):
    for s in fam:
        inner = s.meta[s.n_boundary:]
        n = len(inner)
        assert sum(m["kind"] == "cross" for m in inner) == (n + 1) // 2
        assert sum(m["lift_mm"] > 0 for m in inner) == 1
        outline = np.vstack([s.truth(np.linspace(*s.truth.region.side(i), 200)) for i in range(s.truth.region.n)])
        for m, c in zip(inner, s.clean[s.n_boundary:]):
            if m["kind"] == "cross":
                for what, mm in m["ends"]:
                    if what == "cross":
                        assert NZ["cross"][0] * m["L"] <= mm <= NZ["cross"][1] * m["L"]
            elif not m["lift_mm"]:     # both ends at least 8 (jitter + drift) = 2.4% diag off the boundary
                gap = min(np.linalg.norm(outline - p, axis=1).min() for p in (c[0], c[-1]))
                assert gap >= 0.99 * 8 * (NZ["sigma_rel"] + NZ["drift_rel"]) * s.diag, (s.name, gap)


def test_lifted_stroke_is_off_the_truth_by_one_and_a_half_percent(fam):
    for s in fam:
        k = next(i for i, m in enumerate(s.meta) if m["lift_mm"] > 0)
        d = s.truth.distances(_middle(s.clean[k]))
        np.testing.assert_allclose(d, NZ["lift_rel"] * s.diag, rtol=0.02, err_msg=s.name)


def test_clean_strokes_lie_on_the_truth_and_noisy_ones_carry_drift_and_jitter(fam):
    jitter, rms = [], []
    for s in fam:
        for m, c, q in zip(s.meta, s.clean, s.strokes):
            if m["lift_mm"]:
                continue
            assert s.truth.distances(_middle(c)).max() < 1e-6 * s.diag, (s.name, m["kind"])
            r = q - c
            hp = r[1:-1] - 0.5 * (r[:-2] + r[2:])          # drift is smooth: this is the jitter
            jitter.append(np.sqrt((hp ** 2).mean() / 1.5) / s.diag)
            rms.append(np.sqrt((r ** 2).sum(1).mean()) / s.diag)
    assert np.median(jitter) == pytest.approx(NZ["sigma_rel"], rel=0.1)
    # drift (0.2%) and jitter (0.1% per coordinate) together
    assert 0.0015 < np.median(rms) < 0.0035


def test_pen_is_slow_at_both_ends(fam):
    ratios = []
    for s in fam:
        for c in s.clean:
            seg = np.linalg.norm(np.diff(c, axis=0), axis=1)
            e = max(1, len(seg) // 10)
            ratios.append(np.r_[seg[:e], seg[-e:]].mean() / seg[len(seg) // 3: 2 * len(seg) // 3].mean())
    assert np.median(ratios) < 0.6


def test_truth_distances_and_normals():
    for config in ("octant", "cyl_penta", "dome"):
        s = S.make_config(config, 2)
        t = s.truth
        assert t.region.inside(t.grid_uv).all()
        np.testing.assert_allclose(np.linalg.norm(t.grid_normal, axis=1), 1.0, atol=1e-9)
        uv = t.sample_grid(15) * 0.96 + 0.02
        uv = uv[t.region.inside(uv)]
        off = np.random.default_rng(0).uniform(-0.01, 0.01, len(uv)) * s.diag
        np.testing.assert_allclose(t.distances(t(uv) + off[:, None] * t.normals(uv)), np.abs(off),
                                   atol=1e-6 * s.diag)
