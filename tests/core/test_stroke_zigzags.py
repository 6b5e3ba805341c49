"""Zigzag strokes (core.stroke_zigzags): stitching drawn along a curve is left out of the network,
with the curve it follows named, at any size; a curve that crosses another again and again without
zigzagging, and the curve a zigzag follows, are kept."""
from __future__ import annotations

import numpy as np
import pytest

from ProgSurf.core.objects import build_object, stroke_network
from ProgSurf.core.stroke_zigzags import ZIGZAG_RATIO, zigzag_along, zigzags
from ProgSurf.io import read_strokes
from test_stroke_graph import line


def band(scale: float = 1.0) -> list:
    """A strip 200 x 40 over a gentle arch, drawn as two rails (strokes 0, 1) and five cross strokes:
    four 50 x 40 cells."""
    def lift(p):
        return np.c_[p, 10.0 * np.sin(np.pi * p[:, 0] / 200.0)] * scale
    rails = [lift(line([-4, y], [204, y], 60)[:, :2]) for y in (0.0, 40.0)]
    crosses = [lift(line([x, -4], [x, 44], 20)[:, :2]) for x in (0.0, 50.0, 100.0, 150.0, 200.0)]
    return rails + crosses


def stitching(scale: float = 1.0, height: float = 8.0, pitch: float = 10.0, apart: float = 0.0) -> np.ndarray:
    """A zigzag along rail 0 of `band`, inside the strip: teeth `height` high every `pitch`, touching
    the rail (or, apart > 0, a second curve that far from it, the teeth then running between the two)."""
    xs = np.arange(8.0, 192.0, pitch / 2)
    ys = np.where(np.arange(len(xs)) % 2 == 0, 0.0, height)
    if apart:
        ys = np.where(np.arange(len(xs)) % 2 == 0, 0.0, apart)
    pts = np.c_[xs, ys]
    dense = np.vstack([line(a, b, 6)[:-1] for a, b in zip(pts[:-1], pts[1:])] + [pts[-1:]])
    return np.c_[dense, 10.0 * np.sin(np.pi * dense[:, 0] / 200.0)] * scale


@pytest.mark.parametrize("scale", [0.5, 1.0, 5.0])
def test_stitching_along_a_rail_is_left_out_naming_the_rail(scale):
    strokes = band(scale) + [stitching(scale)]
    graph = stroke_network(strokes)[0]
    z = len(strokes) - 1
    assert "zigzag along stroke 0" in graph.notes[z]
    assert graph.edges_of_stroke(z) == []
    assert all(graph.edges_of_stroke(i) for i in range(z))          # the rail and the rest are kept


def test_stitching_makes_no_sliver_surfaces_and_is_reported_unused():
    plain = build_object(band())
    stitched = build_object(band() + [stitching()])
    assert len(plain.surfaces) == 4
    assert len(stitched.surfaces) == 4
    role = stitched.roles[-1]
    assert not role.used and "zigzag along stroke 0" in role.reason


def test_a_zigzag_between_two_curves_touching_each_in_turn_is_left_out():
    """A welt drawn as two close curves with the stitching running between them (CASSIE 07-2-2's
    rim): the zigzag never leaves either curve by much, but touches each again and again."""
    strokes = band()
    second = strokes[0] + np.array([0.0, 8.0, 0.0])
    second[:, 2] = 10.0 * np.sin(np.pi * second[:, 0] / 200.0)
    graph = stroke_network(strokes + [second, stitching(apart=8.0)])[0]
    assert "zigzag along stroke" in graph.notes[len(strokes) + 1]
    assert graph.edges_of_stroke(len(strokes))                      # the second curve is kept


def test_a_wave_crossing_a_curve_again_and_again_is_kept():
    """A long, low wave across a rail crosses it six times but is hardly longer than the way it
    goes: a curve of the sketch, not stitching."""
    x = np.linspace(0.0, 200.0, 200)
    wave = np.c_[x, 6.0 * np.sin(2 * np.pi * x / 66.0), 10.0 * np.sin(np.pi * x / 200.0)]
    strokes = band() + [wave]
    graph = stroke_network(strokes)[0]
    assert "zigzag" not in graph.notes.get(len(strokes) - 1, "")
    assert graph.edges_of_stroke(len(strokes) - 1)


def test_a_small_ring_round_a_curve_is_no_zigzag():
    """An eyelet drawn as a ring of radius 2 delta, one and a half laps, round a lace that runs
    through it: it touches the lace and leaves it three times and is about pi / 2 times as long as
    the lace's part it spans, but that part is only its diameter (ZIGZAG_RUN)."""
    delta = 4.0
    th = np.linspace(0.0, 3.0 * np.pi, 120)
    ring = np.c_[2 * delta * np.cos(th), np.zeros_like(th), 2 * delta * np.sin(th)]
    lace = line([-40.0, 0.0, 0.0], [40.0, 0.0, 0.0], 80)
    assert zigzag_along(ring, lace, delta, 0.8) == 0.0
    assert zigzags([lace, ring], [0, 1], delta, 0.8) == {}


def test_the_rail_is_never_the_zigzag_and_the_ratio_sets_them_apart():
    rail, zig = band()[0], stitching()
    delta = 4.0
    assert zigzag_along(zig, rail, delta, 0.8) >= ZIGZAG_RATIO
    assert zigzag_along(rail, zig, delta, 0.8) < ZIGZAG_RATIO
    assert zigzags([rail, zig], [0, 1], delta, 0.8) == {1: 0}
    # low teeth (a wobbly over-sketch): no longer than the way it goes by the ratio
    low = stitching(height=2.0)
    assert zigzag_along(low, rail, delta, 0.8) < ZIGZAG_RATIO


def test_the_real_shoes_stitching_is_left_out_and_nothing_else(shared_data):
    """CASSIE 07-2-2 (a shoe): its two stitching strokes (39, 40, a mirrored pair) zigzag along the
    welt's curves 0 and 1; no other stroke of it, and none of the other real VR sketches, is taken
    for one."""
    for path in sorted((shared_data / "cassie").glob("*.curves")):
        graph = stroke_network(read_strokes(path))[0]
        found = {i: note for i, note in graph.notes.items() if "zigzag" in note}
        if path.stem == "07-2-2":
            assert sorted(found) == [39, 40]
            assert "along stroke 0" in found[39] and "along stroke 1" in found[40]
        else:
            assert found == {}, path.name
