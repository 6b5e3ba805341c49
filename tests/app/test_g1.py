"""G1 seams (issue 9) on the bundled examples and random progressive sketches: G0 and G1 built from
the same strokes and measured side by side; G1 must meet the targets away from intended sharp
features (found by rule: kinked strokes, sharp nodes), keep the strokes and the outer boundary, and
stay one watertight valid shell after STEP export and re-import; and never make the surface worse
than G0 (issue 16): within 0.2 % of the diagonal of the G0 faces everywhere, no fold G0 has not, a
crease that cannot be rounded within that bound left as G0 makes it."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from benchmarks.surfaces import random_sketch
from ProgSurf import cad
from ProgSurf.cad import g1 as cad_g1
from ProgSurf.core.continuity import KINK_ANGLE_DEG, KINK_WINDOW
from ProgSurf.core.pipeline import build_network
from ProgSurf.io import read_strokes

ROOT = Path(__file__).resolve().parents[2]
SEAM_GAP_MM = 1e-7
WORSE_FRACTION = 0.002
"""Issue 16: G1 never raises the deviation from the truth by more than 0.2 % of the diagonal over G0;
a G1 face within that of its G0 face at the same parameters bounds it (triangle inequality)."""
MAX_DEG, MEDIAN_DEG = 1.0, 0.1
EXAMPLES = {"fig9_sections.xyz": 4, "fig11_general.xyz": 4, "clean4.xyz": None, "three_sided.xyz": None,
            "rough4.xyz": None, "fig10_five_sided.xyz": None}


class Case:
    def __init__(self, name: str, strokes: list, boundary, tmp: Path):
        self.name = name
        self.result = build_network(strokes, boundary=boundary)
        net = self.result.network
        self.g0 = cad.build_shell(net, self.result.tol, continuity="G0")
        self.g1 = cad.build_shell(net, self.result.tol, continuity="G1")
        self.stats0 = cad.g1_seam_stats(cad.analysis.g0_view(self.g1), net)
        self.stats1 = cad.g1_seam_stats(self.g1, net)
        self.step = tmp / f"{name}_g1.step"
        cad.export_step(self.g1.shape, self.step)
        self.back = cad.read_back(self.step)


def _cases():
    out = [(name, bc) for name, bc in EXAMPLES.items()]
    # 8, 9 and 12 missed the targets before (thin triangles at a three-curve node; a flux fit ringing
    # in knot spans without samples; strokes nearly through one point): kept as regressions
    out += [(f"random{seed}", seed) for seed in (1, 7, 8, 9, 12)]
    return out


@pytest.fixture(scope="module", params=_cases(), ids=lambda c: c[0])
def case(request, tmp_path_factory):
    name, arg = request.param
    tmp = tmp_path_factory.mktemp("g1")
    if name.startswith("random"):
        return Case(name, random_sketch(arg), 4, tmp)
    path = ROOT / "examples" / name
    if not path.exists():
        pytest.skip(f"example {name} not written yet")
    return Case(path.stem, read_strokes(path), arg, tmp)


def test_g0_is_measured_beside_g1_on_the_same_seams(case, request):
    assert [s.edge_id for s in case.stats0] == [s.edge_id for s in case.stats1]
    assert case.g1.continuity == "G1" and case.g0.continuity == "G0" and not case.g0.sharp_edges
    # the G0 faces the G1 shell was made from are the G0 shell's faces (same strokes, same network)
    assert [f.poles for f in case.g1.g0_faces] == [f.poles for f in case.g0.faces]
    smooth0 = max((s.smooth_max_deg for s in case.stats0 if not s.sharp), default=0.0)
    smooth1 = max((s.smooth_max_deg for s in case.stats1 if not s.sharp), default=0.0)
    assert smooth1 <= max(smooth0, 0.05) + 1e-9      # G1 never makes a seam worse than G0


def test_g1_meets_the_seam_angle_targets_except_sharp_features(case, request):
    smooth = [s for s in case.stats1 if not s.sharp]
    # the defect G1 leaves sits at a corner whose curves are not tangent-plane compatible (the
    # fluxes give way within its first knot span): up to half the node's own spread there
    for s in smooth:
        assert s.smooth_max_deg <= max(MAX_DEG, 0.5 * max(s.node_spread_deg, default=0.0)), s
    if smooth:
        assert float(np.median([s.angle_median_deg for s in smooth])) <= MEDIAN_DEG
    assert all(s.angle_median_deg <= MEDIAN_DEG for s in smooth)


def _turning_max_deg(points: np.ndarray, window: float = KINK_WINDOW) -> float:
    """Largest angle (deg) between the chords entering and leaving an inner vertex of a polyline,
    each reaching `window` x its length (or to its end), by a plain loop: the kink rule of
    core.continuity.sharp_edges written a second time, as the oracle of the sharp flags."""
    pts = np.asarray(points, dtype=float)
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))])
    h = window * arc[-1]
    worst = 0.0
    for i in range(1, len(pts) - 1):
        lo = next((j for j in range(i, -1, -1) if arc[j] <= arc[i] - h), 0)
        hi = next((j for j in range(i, len(pts)) if arc[j] >= arc[i] + h), len(pts) - 1)
        a, b = pts[i] - pts[lo], pts[hi] - pts[i]
        if np.linalg.norm(a) > 0 and np.linalg.norm(b) > 0:
            cos = a @ b / (np.linalg.norm(a) * np.linalg.norm(b))
            worst = max(worst, float(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))))
    return worst


# Known open: since a 3-sided region collapses at its sharpest corner, these networks have a seam
# ending at a collapsed apex, whose corner normal is round-off: the node reads as sharp (87-89 deg
# spread) and this oracle wants G1 to keep the seam's 0.4 / 7.5 deg crease there, which G1 rounds.
# The spread of a collapsed corner must be left out of both (cad.analysis.node_spreads, cad.g1);
# leaving it out today uncovers seam angles measured at the apex itself.
APEX_SPREAD = ("random8", "random12")


def test_sharp_features_are_found_by_rule_and_kept(case, request):
    if case.name in APEX_SPREAD:
        request.applymarker(pytest.mark.xfail(strict=True, reason="a collapsed apex reads as a sharp node "
                                              "(see APEX_SPREAD)"))
    edges = case.result.network.edges()
    for s0, s1 in zip(case.stats0, case.stats1):
        # by rule: a seam is sharp where its curve kinks (turns by more than KINK_ANGLE_DEG within
        # KINK_WINDOW), for G0 as for G1; the oracle decides away from the threshold itself
        turn = _turning_max_deg(edges[s1.edge_id].polyline.points)
        if abs(turn - KINK_ANGLE_DEG) > 1e-6:
            assert s0.sharp == s1.sharp == (turn > KINK_ANGLE_DEG), (s1.edge_id, turn)
        if s1.sharp:                       # a kinked seam keeps its G0 crease
            assert s1.angle_max_deg == pytest.approx(s0.angle_max_deg, abs=0.05)
        # a sharp node (corner normals spread > 5 deg) keeps its crease: G1 does not hide it
        # (on seams with a real G0 crease: a flat seam's 1e-6 deg are rounding, on both sides).
        # The crease is the node's own spread; G0's largest angle near such a node can be a fold
        # of a sliver face (random12: 151 deg beside a 29 deg node), which G1 need not copy
        # (a G0 seam whose faces disagree by more than 90 deg is a fold that G1 leaves alone,
        # cad.g1.DISAGREE_DEG, not a crease it must keep)
        if max(s1.node_spread_deg) > 5.0 and 0.1 < s0.angle_max_deg <= 90.0:
            assert s1.angle_max_deg >= 0.5 * min(s0.angle_max_deg, max(s0.node_spread_deg))


def test_boundaries_strokes_and_outer_boundary_are_unchanged(case):
    t = np.linspace(0.0, 1.0, 41)
    for f0, f1 in zip(case.g0.faces, case.g1.faces):
        for side in ((t, 0 * t), (1 + 0 * t, t), (t, 1 + 0 * t), (0 * t, t)):
            p0 = np.array([tuple(f0.surface.value(float(s), float(r))) for s, r in zip(*side)])
            p1 = np.array([tuple(f1.surface.value(float(s), float(r))) for s, r in zip(*side)])
            assert np.abs(p0 - p1).max() <= 1e-9
    fit = case.result.tol.fit_mm
    curves = np.vstack([e.polyline.points[:: max(1, len(e.polyline.points) // 8)]
                        for e in case.result.network.edges().values()])
    d0, d1 = cad.point_distances(case.g0, curves), cad.point_distances(case.g1, curves)
    assert d1.max() <= d0.max() + 1e-4      # the network curves lie on the G1 shell as on the G0 one (to the distance measurement's precision)
    kept = [r for r in case.result.accepted if r.points is not None and len(r.points)]
    for rec in kept[:3]:
        pts = np.asarray(rec.points)[:: max(1, len(rec.points) // 12)]
        # a rough stroke's raw points lie up to its fairing tolerance beside the curve: G1 may move
        # the surface near them by more than the fit tolerance, but never beyond the snap distance
        d0, d1 = cad.point_distances(case.g0, pts).max(), cad.point_distances(case.g1, pts).max()
        assert d1 <= max(d0 + fit, case.result.tol.snap_mm)


def test_g1_shell_is_watertight_and_valid_after_step_round_trip(case):
    shape = case.g1.shape
    assert shape.ShapeType == "Shell" and shape.isValid()
    assert max((s.gap_max_mm for s in case.stats1), default=0.0) <= SEAM_GAP_MM
    assert cad.shell_seam_gaps(shape)["seam_gap_max_mm"] <= SEAM_GAP_MM
    assert case.back["faces"] == len(shape.Faces) and case.back["shells"] == 1 and case.back["valid"]


def _moved_mm(f0, f1) -> float:
    """Largest |S1(s, r) - S0(s, r)| of two faces on a grid dense near their sides (the bands)."""
    g = np.unique(np.concatenate([np.linspace(0.0, 1.0, 33), np.linspace(0.0, 0.06, 13),
                                  np.linspace(0.94, 1.0, 13)]))
    p0 = np.array([[tuple(f0.surface.value(float(a), float(b))) for b in g] for a in g])
    p1 = np.array([[tuple(f1.surface.value(float(a), float(b))) for b in g] for a in g])
    return float(np.linalg.norm(p1 - p0, axis=-1).max())


def _bbox_diagonal(network) -> float:
    pts = np.vstack([e.polyline.points for e in network.edges().values()])
    return float(np.linalg.norm(pts.max(axis=0) - pts.min(axis=0)))


def test_g1_faces_lie_within_the_bound_of_their_g0_faces(case):
    diagonal = _bbox_diagonal(case.result.network)
    bound = cad_g1.offset_limit_mm(case.result.network)
    assert bound <= WORSE_FRACTION * diagonal
    moved = [_moved_mm(f0, f1) for f0, f1 in zip(case.g0.faces, case.g1.faces)]
    assert max(moved) <= bound * (1 + 1e-9)
    summary = cad_g1.bound_summary(case.g1, case.result.network)
    assert summary["offset_bound_mm"] == bound and summary["offset_max_mm"] <= bound * (1 + 1e-9)


def test_g1_adds_no_fold(case):
    folds0, folds1 = cad.analysis.folds(case.g0), cad.analysis.folds(case.g1)
    assert {f.regions for f in folds1 if f.kind == "face"} <= {f.regions for f in folds0 if f.kind == "face"}
    assert {f.edge for f in folds1 if f.kind == "seam"} <= {f.edge for f in folds0 if f.kind == "seam"}


@pytest.mark.parametrize("name", ["clean4", "random8"])
def test_a_crease_beyond_the_bound_is_left_as_g0_makes_it(name, monkeypatch):
    # a bound far below any crease's rounding: every creased seam is left G0, and the G1 faces are
    # the G0 faces (to the bound), so G1 adds nothing where it cannot round a crease within it
    monkeypatch.setattr(cad_g1, "OFFSET_FRACTION", 1e-9)
    strokes = random_sketch(8) if name == "random8" else read_strokes(ROOT / "examples" / f"{name}.xyz")
    result = build_network(strokes, boundary=4 if name == "random8" else None)
    net = result.network
    g1 = cad.build_shell(net, result.tol, continuity="G1")
    stats0 = cad.g1_seam_stats(cad.analysis.g0_view(g1), net)
    stats1 = cad.g1_seam_stats(g1, net)
    summary = cad_g1.bound_summary(g1, net)
    creased = {s.edge_id for s in stats0 if not s.sharp and s.angle_median_deg > 0.01}
    assert creased and creased <= set(summary["seams_left_g0"])
    for s0, s1 in zip(stats0, stats1):
        # (the seam's ends at a sharp node are left out: a collapsed corner's normal is round-off)
        if s1.edge_id in creased:
            assert s1.smooth_max_deg == pytest.approx(s0.smooth_max_deg, abs=1e-6)
    bound = cad_g1.offset_limit_mm(net)
    assert max(_moved_mm(f0, f1) for f0, f1 in zip(g1.g0_faces, g1.faces)) <= bound * (1 + 1e-9)


def test_g1_puts_faces_back_to_g0_where_together_they_would_fold():
    """Issue 16, "G1 never makes it worse": G1 faces that each keep within their bound can still meet
    at a crease G0 does not have (the project family's octant_2 had creases of 168-179 deg around a
    3-sided face before 3-sided patches took their meridians straight to the apex; no sketch of the
    family does it now). The faces of such a new fold go back to G0 (cad.shell.keep_no_new_fold).
    Here it is given clean4's G0 faces and, as G1 faces, the same faces with one of them bulged
    along its normal so far that it creases against its neighbours and turns over (a real B-spline
    face, as a correction beyond its bound would make it)."""
    from dataclasses import replace

    from ProgSurf.cad.analysis import face_folds
    from ProgSurf.cad.shell import keep_no_new_fold

    result = build_network(read_strokes(ROOT / "examples" / "clean4.xyz"))
    g0 = cad.build_shell(result.network, result.tol, continuity="G0")
    sharp = g0.sharp_edges
    before = {(f.kind, f.regions) for f in face_folds(g0.faces, sharp)}
    k = len(g0.faces) // 2
    info = g0.faces[k]
    surface = info.surface.copy()
    u0, u1, v0, v1 = surface.bounds()
    normal = surface.normal(0.5 * (u0 + u1), 0.5 * (v0 + v1))
    box = info.face.BoundBox
    lift = normal * (3.0 * box.DiagonalLength)
    for i in range(2, surface.NbUPoles):
        for j in range(2, surface.NbVPoles):
            surface.setPole(i, j, surface.getPole(i, j) + lift)
    bulged = replace(info, surface=surface, face=surface.toShape())
    g1_faces = list(g0.faces)
    g1_faces[k] = bulged
    new = {(f.kind, f.regions) for f in face_folds(g1_faces, sharp)} - before
    assert new, "the bulged face does not fold: the case does not exercise keep_no_new_fold"
    faces, back = keep_no_new_fold(tuple(g0.faces), g1_faces, sharp)
    assert info.region_id in back
    assert len(back) < len(g0.faces), "every face went back: the G1 faces away from the fold were lost"
    assert not {(f.kind, f.regions) for f in face_folds(faces, sharp)} - before
    for f, f0, f1 in zip(faces, g0.faces, g1_faces):
        assert f is (f0 if f.region_id in back else f1)


def _crowded_knots(extra=()) -> np.ndarray:
    """A clamped cubic knot vector with even spans and 20 spans of 5e-6 at 0.9616 (as a curve fit
    left them on a face of a sketchgen dome: its G1 face reached 20 km), and the knots `extra`."""
    inner = np.concatenate([np.linspace(0.0, 0.96, 25)[1:], 0.9616 + 5e-6 * np.arange(21), extra])
    return np.concatenate([[0.0] * 4, np.sort(inner), [1.0] * 4])


@pytest.mark.parametrize("width", cad_g1.BAND_WIDTHS)
@pytest.mark.parametrize("end", (0, 1))
def test_band_blend_stays_bounded_where_knots_crowd(width, end):
    from ProgSurf.core.bspline import basis_matrix
    from ProgSurf.core.continuity import BAND_PEAK, band_blend

    k = _crowded_knots(cad_g1._band_knots(width, end))     # as cad.g1._correction inserts them
    c = cad_g1._band_coeffs(tuple(k.tolist()), width, end)
    # B-spline coefficients of a function bounded by BAND_PEAK * width stay near that bound; a
    # basis function that no fitting sample reached took 1400 (times a flux of 16 mm)
    assert np.abs(c).max() <= 2.0 * BAND_PEAK * width + 1e-9
    t = np.unique(np.concatenate([np.linspace(0.0, 1.0, 2001), np.linspace(0.9616, 0.9617, 201)]))
    want = band_blend(t, width) if end == 0 else -band_blend(1.0 - t, width)
    assert np.abs(basis_matrix(k, t) @ c - want).max() <= 0.05 * BAND_PEAK * width


def test_the_bound_sees_a_move_inside_a_crowded_knot_span():
    kv = _crowded_knots()
    ku = np.array([0.0] * 4 + [0.5] + [1.0] * 4)
    nu, nv = len(ku) - 4, len(kv) - 4
    delta = np.zeros((nu, nv, 3))
    j = 24 + 10       # a pole whose basis function lives on the crowded spans only
    delta[:, j, 2] = 100.0
    refined = cad_g1._Refined(np.zeros((nu, nv, 3)), ku, kv, ())
    # the basis function peaks at 2/3 inside its support; the move there is 67 mm, which a grid
    # stepping over spans of 5e-6 reads as 0
    assert cad_g1._moved(refined, delta, (0.25,) * 4) >= 0.6 * 100.0
