"""Corners of a loop whose Coons patch would fold (core.loop_corners), and the vertices the sewing
needs where a neighbour's corner lies inside a face's edge (cad.object_shell.with_vertices)."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ProgSurf.core.folds import find_folds
from ProgSurf.core.loop_corners import FOLD_DEG, choose_sides, default_sides, patch_turn_deg, patch_turns_deg
from ProgSurf.core.objects import build_object

R = 100.0
DATA = Path(__file__).resolve().parents[2].parent / "shared" / "data"
LAMP = DATA / "cassie" / "10-2-1.xyz"


def _sphere(theta, phi):
    return R * np.column_stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)])


def nose_cap(tip_deg: float = 8.0, meridians: int = 8) -> list:
    """A hemisphere drawn as a designer draws a nose: its rim, a small ring round the pole and
    meridians from the rim to the ring, so that strips converge to the tip (the TiGL helicopter's
    nose cap is such a net)."""
    ring = np.radians(tip_deg)
    phi = np.linspace(0.0, 2 * np.pi, 121)
    strokes = [_sphere(np.full_like(phi, np.pi / 2), phi), _sphere(np.full_like(phi, ring), phi)]
    for k in range(meridians):
        a = 2 * np.pi * (k + 0.5) / meridians
        th = np.linspace(np.pi / 2, ring, 40)
        strokes.append(_sphere(th, np.full_like(th, a)))
    return strokes


def test_a_flat_square_keeps_its_corners():
    t = np.linspace(0.0, 1.0, 20)[:, None]
    c = np.array([[0, 0, 0], [100, 0, 0], [100, 80, 0], [0, 80, 0]], float)
    sides = [c[k] + t * (c[(k + 1) % 4] - c[k]) for k in range(4)]
    assert patch_turn_deg(sides, 20.0) < 1e-6
    assert choose_sides(sides) is None


def test_the_nose_caps_loops_keep_the_papers_corners_and_none_folds():
    """The ring round the pole is one loop of 8 sides, and strips converge to the tip: with every
    edge cut where the fit put its nodes and leaving them along its stroke (core.objects
    edge_polylines), the paper's merged corners fold no surface of the cap, so none is given other
    corners. (When edges were cut by scaled arc lengths and jumped to their nodes in one segment,
    the ring's patch turned over, 180 deg, and two strips 172-177 deg: they needed other corners.)"""
    build = build_object(nose_cap())
    assert len(build.surfaces) == 9 and not build.failed
    for k, surf in enumerate(build.surfaces):
        assert find_folds(surf.result.network) == [], k
        assert not [n for n in surf.result.boundary.notes if "corners moved" in n], k
        sides = [np.asarray(s) for s in surf.cycle.polylines_from(build.polylines)]
        reach = 0.15 * float(np.linalg.norm(np.ptp(np.vstack(sides), axis=0)))
        assert patch_turn_deg(default_sides(sides)[0], reach) < 60.0, k
    cap = max(range(len(build.surfaces)), key=lambda k: len(build.surfaces[k].sides))
    assert len(build.surfaces[cap].sides) == 8


@pytest.mark.skipif(not LAMP.exists(), reason="needs ../shared/data (CASSIE 10-2-1), absent from a user's clone")
def test_the_lamps_folding_loops_get_corners_where_their_patch_turns_less():
    """10-2-1 (CASSIE, a lamp): some of its rough loops fold with the paper's merged corners (their
    Coons patch turns more than FOLD_DEG inside it); each of those is given other corners, with
    which its patch turns at least GAIN_DEG less, and the surface's note says by how much."""
    from ProgSurf.core.loop_corners import GAIN_DEG
    from ProgSurf.io import read_strokes

    import re

    build = build_object(read_strokes(LAMP))
    moved = 0
    for k, surf in enumerate(build.surfaces):
        sides = [np.asarray(s) for s in surf.cycle.polylines_from(build.polylines)]
        reach = 0.15 * float(np.linalg.norm(np.ptp(np.vstack(sides), axis=0)))
        notes = [n for n in surf.result.boundary.notes if "corners moved" in n]
        if not notes:
            continue
        moved += 1
        paper, other = (float(x) for x in re.findall(r"(\d+) deg", notes[0])[:2])
        b = surf.result.boundary
        shaped = [b.bottom, b.right, b.top[::-1], b.left[::-1]]
        if np.allclose(b.top, b.top[0]):
            shaped = [b.bottom, b.right, b.left[::-1]]
        assert paper > FOLD_DEG and other <= paper - GAIN_DEG, (k, notes[0])
        # the patch of the corners the surface was built on turns as little as the note says
        # (read, as choose_sides reads it, on the dense grid too)
        assert patch_turns_deg([shaped], reach, dense=True)[0] == pytest.approx(other, abs=0.5), k
    assert moved >= 3


def test_the_nose_cap_is_one_shell_without_a_fold():
    """The cap's faces sewn into one shell that passes every check; its rim is free, in the 9
    pieces its 8 meridians and its own start cut."""
    from ProgSurf.app.objects import build_object_and_measure

    out = build_object_and_measure(nose_cap())
    assert out.problems == []
    assert len(out.shells) == 1 and out.shells[0]["valid"]
    assert out.shells[0]["free_edges"] == 9


def test_a_face_gets_a_vertex_where_a_point_lies_inside_its_edge():
    import Part
    from FreeCAD import Vector

    from ProgSurf.cad.object_shell import with_vertices

    face = Part.makePlane(100.0, 50.0)
    split = with_vertices(face, [np.array([40.0, 0.0, 0.0]), np.array([0.0, 0.0, 0.0]), np.array([50.0, 20.0, 0.0])])
    assert len(face.Edges) == 4 and len(split.Edges) == 5           # only the point inside an edge
    assert split.Area == pytest.approx(face.Area, rel=1e-12) and split.isValid()
    assert any(v.Point.isEqual(Vector(40, 0, 0), 1e-9) for v in split.Vertexes)
    assert with_vertices(face, [np.array([50.0, 20.0, 0.0])]) is face




@pytest.mark.skipif(not LAMP.is_file(), reason=f"shared sketch {LAMP} not found")
def test_a_lamp_with_moved_corners_stays_sewn():
    """10-2-1 (CASSIE, a lamp): moving the corners of its folding loops left faces whose corner lay
    inside a neighbour's edge, and Surface::Sewing did not join 6 of them (7 shells where the
    paper's corners gave 5); with a vertex there (with_vertices) it is 5 shells again, and fewer
    of its surfaces fold (40 of 46 with the paper's corners). Its 8-sided loop through one node
    twice (a bow tie, which folded) is two loops since stroke_cycles._pinched: 47 surfaces, and
    one more shell of one face (6)."""
    from ProgSurf.app.objects import build_object_and_measure
    from ProgSurf.io import read_strokes

    out = build_object_and_measure(read_strokes(LAMP))
    assert len(out.shells) <= 6
    assert sum(1 for f in out.folds if f) <= 38


def test_corner_choices_measured_together_turn_as_each_does_alone():
    """choose_sides screens hundreds of corner choices in one batch (patch_turns_deg, tucks_deg):
    each choice must measure what it measures alone, whatever the others in the batch, and the
    batch's shared side arrays (the same array at the same place) must not leak between choices."""
    from ProgSurf.core.folds import tuck_deg, tucks_deg
    from ProgSurf.core.loop_corners import _cut, _places, patch_turns_deg

    rng = np.random.default_rng(7)
    # a loop over a saddle, with a dent that makes some choices fold and others not
    t = np.linspace(0.0, 2 * np.pi, 61)[:-1]
    ring = np.column_stack([100 * np.cos(t), 70 * np.sin(t), 30 * np.cos(2 * t) + 25 * (np.abs(t - 2) < 0.4)])
    sides = [ring[k:k + 11] if k + 11 <= 60 else np.vstack([ring[k:], ring[:1]]) for k in range(0, 60, 10)]
    loop, places = _places(sides, [True] * 6)
    made: dict = {}
    choices = [_cut(loop, sorted(rng.choice(places, 4, replace=False)), made) for _ in range(40)]
    choices += [_cut(loop, sorted(rng.choice(places, 3, replace=False)), made) for _ in range(20)]
    together = patch_turns_deg(choices, 40.0, 4)
    alone = [patch_turns_deg([[s.copy() for s in c]], 40.0, 4)[0] for c in choices]
    assert together == alone
    assert min(together) < FOLD_DEG < max(together)          # the batch holds both kinds
    assert patch_turns_deg(choices[::-1], 40.0, 4) == together[::-1]
    # the tuck measure alone and in a batch, with undefined normals among them
    normals = rng.normal(size=(5, 30, 3))
    normals /= np.linalg.norm(normals, axis=-1)[..., None]
    points = rng.uniform(0.0, 50.0, size=(5, 30, 3))
    ok = rng.uniform(size=(5, 30)) > 0.2
    ok[4, 1:] = False                                         # one defined normal: no pair, no tuck
    batch = tucks_deg(normals, ok, points, 20.0)
    assert batch == [tuck_deg(normals[i], ok[i], points[i], 20.0) for i in range(5)]
    assert batch[4] == 0.0 and max(batch[:4]) > 90.0


def _lip_quarter(leg: float = 300.0, r: float = 60.0, radius: float = 800.0) -> list:
    """A quarter of a nacelle's intake lip (TiGL full_nacelle's front surfaces): a U profile (an
    inner leg, a half circle of radius r round the lip, an outer leg) turned 90 deg about the x
    axis at `radius`; its loop is the inner ring, the U at 90 deg, the outer ring, the U at 0 deg."""
    a = np.linspace(0.0, 1.0, 60)
    t = np.linspace(0.0, np.pi, 60)
    prof = np.vstack([np.column_stack([leg * (1 - a), np.full(60, -r)]),
                      np.column_stack([-r * np.sin(t), -r * np.cos(t)])[1:],
                      np.column_stack([leg * a, np.full(60, r)])[1:]])

    def turned(x, rad, phi):
        return np.column_stack([x, rad * np.cos(phi), rad * np.sin(phi)])

    phi = np.linspace(0.0, np.pi / 2, 60)
    inner = turned(np.full(60, prof[0, 0]), radius + prof[0, 1], phi)
    outer = turned(np.full(60, prof[-1, 0]), radius + prof[-1, 1], phi)
    return [inner, turned(prof[:, 0], radius + prof[:, 1], np.pi / 2), outer[::-1],
            turned(prof[::-1, 0], radius + prof[::-1, 1], 0.0)]


def test_a_lip_that_bends_right_over_keeps_its_corners_rather_than_fold_along_a_line(monkeypatch):
    """A lip's patch turns 180 deg (its inner and outer skins face apart a lip's width from each
    other), so the turn checks read it as folding; but it bends smoothly, a few degrees from one
    sample to the next. Corners that read as turning less twisted it into a band folded along a
    line (TiGL full_nacelle's front quarters, rendered): such corners are not taken."""
    from ProgSurf.core import loop_corners
    from ProgSurf.core.loop_corners import CREASE_DEG, patch_creases_deg

    sides = _lip_quarter()
    reach = 0.15 * float(np.linalg.norm(np.ptp(np.vstack(sides), axis=0)))
    assert patch_turn_deg(sides, reach) > FOLD_DEG                 # the checks call it a fold
    assert patch_creases_deg([sides])[0] < 45.0                    # it bends smoothly
    assert choose_sides(sides) is None
    # the corners the turn checks alone would take: folded along a line
    monkeypatch.setattr(loop_corners, "CREASE_DEG", float("inf"))
    other = choose_sides(sides)
    assert other is not None and patch_creases_deg([other[0]])[0] > CREASE_DEG


def test_a_narrow_tuck_between_the_coarse_grids_lines_is_seen_on_the_dense_grid():
    """A square loop whose bottom side dips in a narrow notch (2 mm wide, 20 deep, on a 1 m side):
    its Coons patch carries the notch across as a narrow tuck. The FACE_SAMPLES grid's lines (every 12.5 %)
    pass either side of it and read a patch that does not fold; the FOLD_DENSE grid, the built
    face's check, reads the tuck's turn (choose_sides judges a loop's paper corners on it: CASSIE
    10-2-1's surface 12 read 69 deg on the coarse grid, 93 on the dense, and its face was reported
    folding at 92)."""
    from ProgSurf.core.folds import FOLD_DENSE
    from ProgSurf.core.loop_corners import patch_turns_deg

    t = np.linspace(0.0, 1.0, 4001)
    notch = 20.0 * np.clip(1.0 - np.abs(t - 0.54) / 0.001, 0.0, None)      # 20 mm deep, 2 mm wide
    bottom = np.c_[1000 * t, 0 * t, -notch]
    right = np.c_[1000 + 0 * t, 1000 * t, 0 * t]
    top = np.c_[1000 * (1 - t), 1000 + 0 * t, 0 * t]
    left = np.c_[0 * t, 1000 * (1 - t), 0 * t]
    sides = [bottom, right, top, left]
    # (by arc length, as the patch maps its sides, the notch lies between 0.55 and 0.59 of the bottom)
    cum = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(bottom, axis=0), axis=1))] / 1.0
    lo, hi = cum[np.flatnonzero(notch)[[0, -1]]] / cum[-1]
    assert 0.5 < lo < hi < 0.6
    reach = 0.15 * np.linalg.norm([1000.0, 1000.0, 20.0])
    coarse = patch_turns_deg([sides], reach)[0]
    dense = patch_turns_deg([sides], reach, dense=True)[0]
    assert FOLD_DENSE >= 33
    assert coarse < FOLD_DEG < dense, (coarse, dense)


@pytest.mark.skipif(not LAMP.is_file(), reason=f"shared sketch {LAMP} not found (../shared/data, absent from a user's clone)")
def test_the_lamps_loop_with_a_narrow_tuck_gets_corners_that_do_not_fold():
    """CASSIE 10-2-1's loop of strokes 49, 22, 14 and 21: with the paper's corners its patch tucks
    narrowly (69 deg on the coarse grid, 93 on the dense), and kept, its built face folded (92 deg).
    Judged on the dense grid, it gets other corners and its face does not fold."""
    from ProgSurf.app.objects import build_object_and_measure
    from ProgSurf.core.objects import side_strokes
    from ProgSurf.io.pointlist import read_point_list

    out = build_object_and_measure(read_point_list(LAMP))
    g = out.build.graph
    # (side_strokes: a divided loop's parts have a curve across, which is no graph edge)
    found = [k for k, surf in enumerate(out.build.surfaces)
             if sorted(set(side_strokes(g, [e for e, _ in surf.cycle.sides]))) == [14, 21, 22, 49]]
    assert len(found) == 1
    assert not out.folds[found[0]]


def test_a_ring_cut_into_four_arcs_does_not_fold_where_two_arcs_meet_almost_tangent():
    """A ring merged to four sides has corners on one smooth curve: there the patch's partial
    derivatives are parallel up to the polyline's kinks, and the sign of their cross product is
    chance (the nose cap's ring: one corner 0.01 deg off tangency read its normal upside down, a
    180 deg "fold", on one machine's BLAS and not on another's). A corner that meets within
    folds.TANGENT_CORNER_DEG of tangency is not read; a corner pushed in further still folds the
    patch around it, and is read."""
    radius = 50.0
    phi = np.radians(np.arange(0.0, 361.0, 3.0))
    ring = np.column_stack([radius * np.cos(phi), radius * np.sin(phi), np.zeros_like(phi)])

    def turn(push: float) -> tuple[float, float]:
        loop = ring.copy()
        loop[90] *= (radius - push) / radius              # the corner at 270 deg, pushed in
        loop[-1] = loop[0]
        a, b = loop[90] - loop[89], loop[91] - loop[90]
        kink = float(np.degrees(np.arctan2(np.cross(a, b)[2], a @ b)))     # < 0: reflex
        sides = [loop[0:31], loop[30:61], loop[60:91], loop[90:121]]
        return kink, patch_turn_deg(sides, 0.15 * 2 * radius)

    for push in (0.05, 0.07, 0.075, 0.08):              # 0.8 deg convex to 0.5 deg reflex
        kink, got = turn(push)
        assert -1.0 < kink < 1.0 and got < 1.0, (push, kink, got)
    kink, got = turn(0.5)                                # 19 deg reflex: the patch folds there
    assert kink < -10.0 and got > 90.0, (kink, got)
