"""The whole-object benchmark (benchmarks/objects.py, issue 18): its generator draws on its truth,
and its command runs as its docstring says and measures a build."""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from benchmarks.objects import KINDS, make_object  # noqa: E402


@pytest.mark.parametrize("kind", KINDS)
def test_the_clean_strokes_lie_on_the_truth(kind):
    """Each clean stroke lies on its object's surface, but where it runs on past the end of its
    curve (an overshoot, straight on); the sketch is the same for the same seed and another for
    another, and its truth samples lie on the truth."""
    sk = make_object(kind, 7)
    assert len(sk.strokes) == len(sk.clean) >= 6
    for noisy, clean in zip(sk.strokes, sk.clean):
        assert sk.distance(clean[len(clean) // 4: -len(clean) // 4]).max() <= 1e-3 * sk.diag
        assert np.abs(noisy - clean).max() <= 0.03 * sk.diag       # drift and jitter are small
    assert sk.distance(sk.truth_points).max() <= 1e-6 * sk.diag
    again = make_object(kind, 7)
    assert all(np.array_equal(a, b) for a, b in zip(sk.strokes, again.strokes))
    assert not np.array_equal(np.vstack(sk.strokes)[:10], np.vstack(make_object(kind, 8).strokes)[:10])


def test_the_rough_hand_draws_more_strokes_further_off():
    rough = [make_object("box", s, rough=True) for s in range(6)]
    assert sum(len(sk.strokes) for sk in rough) > 6 * 12        # curves drawn over again or in two


def test_the_benchmark_builds_a_box_and_a_tube(tmp_path):
    env = dict(os.environ, HOME=os.environ.get("HOME") or "/tmp")
    env.pop("PYTHONPATH", None)
    proc = subprocess.run(["/usr/bin/python3", str(ROOT / "benchmarks" / "objects.py"), "--per", "1", "--only", "box",
                           "tube", "--out", str(tmp_path)], cwd=str(ROOT), capture_output=True, text=True,
                          timeout=600, env=env)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip().splitlines()[-1].startswith("SUMMARY objects: built 2/2")
    results = {r["kind"]: r for r in json.loads((tmp_path / "objects.json").read_text())}
    box = results["box"]
    assert box["surfaces"] == 6 and box["shells"] == 1 and box["closed"] == 1 and box["free_edges"] == 0
    assert box["dev_rms_pct"] < 1.0
    tube = results["tube"]
    assert tube["built"] and tube["closed"] == 0 and tube["surfaces_expected"] >= 3


def test_a_redraw_of_an_open_curve_stays_on_it():
    """--rough draws some curves over again along 30-70 % of their length; on an open curve that
    part lies on the curve (drawn from up to 60 % on, it used to run on past the curve's end along
    its end tangent: up to 30 % of the curve, off a body's tip)."""
    from benchmarks.objects import NOISE, ROUGH, _body, _dense, _strokes_of

    noise = {**NOISE, **ROUGH, "oversketch_p": 1.0, "split_p": 0.0}
    rng = np.random.default_rng(5)
    curves, *_ = _body(500.0, rng)
    checked = 0
    for seed in range(40):
        for curve, closed in curves:
            if closed:
                continue
            pts, cum = _dense(curve, closed)
            drawn = _strokes_of(curve, closed, float(cum[-1]), 600.0, np.random.default_rng(seed), noise)
            assert len(drawn) == 2
            _, clean = drawn[1]
            # every point of the redraw's clean path on the curve's dense polyline
            d = np.array([np.linalg.norm(pts - p, axis=1).min() for p in clean])
            assert d.max() <= 2e-3 * cum[-1], (seed, d.max())
            checked += 1
    assert checked >= 100


@pytest.mark.parametrize("seed", [1009, 7003, 3006])
def test_rough_bodies_whose_guides_run_over_each_other_at_a_tip_make_every_loop(seed):
    """Two rough bodies (a looser hand) whose guides near a tip run over each other and are
    trimmed there: an end the trim cut away joined another guide, held at the cut, and left a
    node on that guide's piece to the tip that split a tip triangle's side (core.stroke_joins:
    17 of 18 loops; the loop with the extra node was dropped as spanning no surface). In 3006r a
    guide's short piece runs over the tip 20 % of its length and the other guide is trimmed
    against it: the crossings at the tip stay on the trimmed guide, a hook of the longer stroke
    (stroke_graph._run_trim: 23 of 24 loops with a hook of the piece). Every loop of the body is
    found: guides x (rings + 1)."""
    from ProgSurf.core.objects import stroke_network

    sk = make_object("body", seed, rough=True)
    _, choice, _ = stroke_network(sk.strokes)
    assert len(choice.cycles) == sk.surfaces


@pytest.mark.parametrize("kind,seed,was", [
    ("body", 13000, 19),    # a ring's seam 2 delta from a guide: the seam and its join two nodes, one dropped
    ("body", 13002, 17),    # a guide drawn again from 7 delta short of the tip, merged: its piece to the tip lost
    ("body", 13011, 12),    # guides 3-4 delta short of a tip; a ring drawn on 6 delta past its seam
    ("tube", 15002, 13),    # a ruling drawn in two strokes overlapping head to head 2.3 delta on a ring
    ("box", 15011, 5),      # an edge drawn so: two nodes 1.05 delta apart, a face left out
    ("grid", 15008, 8),     # a line's end 2.03 delta from the border, its last delta swerving 26 deg off
    ("grid", 13002, 4),     # (kept) a short stroke joining two halves of a border: merged, not a tail
    ("body", 13007, 20),    # (kept) a ring run on past its seam over a guide: no loop back to the seam node
    ("tube", 3011, 6),      # (kept) a ruling's end extended to a rim's lap beside the overlap cut away
])
def test_rough_sketches_drawn_loosely_at_joints_make_every_loop(kind, seed, was):
    """Rough objects (the project's generator, a looser hand) whose curves meet loosely: each
    comment says how; `was` is how many loops the network had before the rules that read these
    joints (core.stroke_joins: a ring's seam beside a stroke, meeting ends up to MEET_REACH, rings
    drawn on over their seam, extension by the last EXTEND_BACK delta; core.stroke_graph: tails
    of over-sketches, head-to-head overlaps, loops back to a node at a stroke's end). Every loop
    of the object is found."""
    from ProgSurf.core.objects import stroke_network

    sk = make_object(kind, seed, rough=True)
    _, choice, _ = stroke_network(sk.strokes)
    assert len(choice.cycles) == sk.surfaces


@pytest.mark.parametrize("kind,seed,reversed_", [("tube", 1002, (1, 3, 4, 6, 7)), ("tube", 1002, None),
                                                  ("tube", 1005, None), ("box", 1000, None),
                                                  ("body", 1001, None), ("grid", 1003, None)])
def test_a_rough_object_makes_one_network_whichever_way_its_strokes_run_and_wherever_it_lies(kind, seed, reversed_):
    """The stroke network of a rough object, its strokes drawn the other way at random and the
    sketch turned, scaled and moved: the same nodes (moved back, within 0.1 % of its size) and
    edges. tube_1002r's rim, drawn on past its seam at both ends, had the overlap cut from the end
    looked at first: drawn the other way round, its seam lay 20 mm away and the network had a node
    more (stroke_joins.ring_overlaps cuts the shorter overlap now). A ring closed across a gap at
    its seam had its seam node at its start, one end of the gap or the other as it ran (tube_1002r
    with stroke 0 reversed: 6.5 mm; tube_1005r: 2.7 mm); it lies halfway along the bridge now.
    reversed_: the strokes drawn the other way (None: at random)."""
    from ProgSurf.core.objects import stroke_network

    strokes = make_object(kind, seed, rough=True).strokes
    rng = np.random.default_rng(seed)
    rot, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    rot *= np.sign(np.linalg.det(rot))
    scale, shift = 2.5, rng.normal(size=3) * 400.0
    flip = rng.random(len(strokes)) < 0.5 if reversed_ is None else np.isin(np.arange(len(strokes)), reversed_)
    moved = [(s[::-1] if f else s) @ rot.T * scale + shift for s, f in zip(strokes, flip)]
    g0, c0, _ = stroke_network(strokes)
    g1, c1, _ = stroke_network(moved)
    p0 = np.array([n.point for n in g0.nodes])
    p1 = (np.array([n.point for n in g1.nodes]) - shift) / scale @ rot
    size = float(np.linalg.norm(np.ptp(np.vstack(strokes), axis=0)))
    assert len(p1) == len(p0)
    assert np.linalg.norm(p0[:, None] - p1[None], axis=2).min(axis=1).max() <= 1e-3 * size
    assert len(g1.edges) == len(g0.edges) and len(c1.cycles) == len(c0.cycles)


def test_the_edit_benchmark_moves_a_stroke_of_a_grid_and_builds_again_fewer_surfaces():
    """benchmarks/edits.py --generated 1 --edits 2, as its docstring says: a line per generated
    sketch and a SUMMARY; a moved stroke of the 3 x 3 grid builds again only the surfaces it
    bounds (3 of its 9: a stroke of the grid bounds 2 to 4 of them)."""
    env = dict(os.environ, HOME=os.environ.get("HOME") or "/tmp")
    env.pop("PYTHONPATH", None)
    proc = subprocess.run(["/usr/bin/python3", str(ROOT / "benchmarks" / "edits.py"), "--generated", "1", "--edits", "2"],
                          cwd=str(ROOT), capture_output=True, text=True, timeout=600, env=env)
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.strip().splitlines()
    assert lines[-1].startswith(f"SUMMARY edits: {len(KINDS)} sketches")
    grid = [ln for ln in lines if ln.startswith("grid_7000")]
    assert len(grid) == 1 and "surfaces    9" in grid[0]
    rebuilt = float(grid[0].split("surfaces built again ")[1].split()[0])
    assert 2 <= rebuilt <= 4
