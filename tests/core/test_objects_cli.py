"""`build --surfaces all` on the command line (ProgSurf.object_cli): a cube's twelve edges give a
STEP file of one closed shell of six faces, and the report accounts for every stroke; and the real
sketches of ../shared/data each build (skipped with the reason where that folder is absent)."""
from __future__ import annotations

import itertools
import json
import re
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT.parent / "shared" / "data"
REAL = sorted(DATA.glob("cassie/*.xyz")) + sorted(DATA.glob("tigl/*/*.clean.xyz")) if DATA.is_dir() else []


def run(*args: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, HOME=os.environ.get("HOME", "/tmp"))
    env.pop("PYTHONPATH", None)
    return subprocess.run(["/usr/bin/python3", "-m", "ProgSurf", *args], cwd=ROOT, capture_output=True,
                          text=True, timeout=900, env=env)


def write_cube(path: Path) -> None:
    v = np.array(list(itertools.product([0, 1], [0, 1], [0, 1])), float) * 20.0
    lines = []
    for a in range(8):
        for b in range(a + 1, 8):
            if np.sum(v[a] != v[b]) == 1:
                lines += [f"{x:.6f} {y:.6f} {z:.6f}" for x, y, z in np.linspace(v[a], v[b], 15)] + [""]
    path.write_text("\n".join(lines))


def test_cube_edges_build_one_closed_shell_through_the_command(tmp_path):
    src = tmp_path / "cube.xyz"
    write_cube(src)
    step, report_path, fcstd = tmp_path / "cube.step", tmp_path / "cube.json", tmp_path / "cube.FCStd"
    proc = run("build", str(src), "-o", str(step), "--report", str(report_path), "--fcstd", str(fcstd),
               "--surfaces", "auto")                      # auto: a closed shell -> all
    assert proc.returncode == 0, proc.stderr + proc.stdout
    report = json.loads(report_path.read_text())
    assert report["mode"] == "all" and len(report["surfaces"]) == 6
    assert [(s["faces"], s["closed"], s["valid"], s["free_edges"]) for s in report["shells"]] == [(6, True, True, 0)]
    assert all(len(s["boundary_of"]) == 2 for s in report["strokes"])
    from ProgSurf import cad

    back = cad.read_back(step)
    assert back["faces"] == 6 and back["shells"] == 1 and back["valid"]
    # the FreeCAD document holds one parametric SurfaceNetwork on the twelve strokes, as the report
    import FreeCAD

    doc = FreeCAD.openDocument(str(fcstd))
    try:
        net = doc.getObject("SurfaceNetwork")
        assert len(net.Strokes) == 12 and net.LastError == ""
        assert (len(net.Shape.Faces), net.ClosedShells) == (6, 1)
        assert net.FitTolerance == pytest.approx(report["tolerances"]["fit_mm"])
        assert [line.split(": ", 1)[1] for line in net.StrokeAccounting] == [s["summary"] for s in report["strokes"]]
        assert net.Shape.Area == pytest.approx(doc.getObject("ExportedShell").Shape.Area, rel=1e-9)
    finally:
        FreeCAD.closeDocument(doc.Name)


def test_surfaces_one_keeps_the_single_surface(tmp_path):
    src = ROOT / "examples" / "clean4.xyz"
    report_path = tmp_path / "one.json"
    proc = run("build", str(src), "-o", str(tmp_path / "one.step"), "--report", str(report_path), "--surfaces", "one")
    assert proc.returncode == 0, proc.stderr
    assert "mode" not in json.loads(report_path.read_text())


@pytest.mark.skipif(not REAL, reason=f"shared sketch data not found at {DATA}")
@pytest.mark.parametrize("path", REAL, ids=[p.name for p in REAL])
def test_real_sketch_network_makes_surfaces_and_accounts_for_every_stroke(path):
    """The numeric core on every real sketch (the CAD half is the CLI test below, on one sketch:
    all nine through the CAD adapter take about 80 s of CPU, too much for every suite run)."""
    from ProgSurf.core.objects import build_object
    from ProgSurf.io import read_strokes

    strokes = read_strokes(path)
    build = build_object(strokes)
    assert build.surfaces
    assert all(reason for _, reason in build.failed)
    assert [r.index for r in build.roles] == list(range(len(strokes)))
    assert all(r.used or r.reason for r in build.roles)
    # an unused stroke's reason says why it is unused, not only what was cut from it
    done_to_it = re.compile(r"^(hook of [0-9.e+-]+ mm removed at its (start|end)|over-sketched run along another stroke "
                            r"trimmed \((start|end)\))$")
    assert all(r.used or not all(done_to_it.match(p) for p in r.reason.split("; ")) for r in build.roles), [
        r for r in build.roles if not r.used and all(done_to_it.match(p) for p in r.reason.split("; "))]
    # each network curve bounds at most two surfaces (the manifold choice)
    uses: dict = {}
    for surf in build.surfaces:
        for e in surf.sides:
            uses[e] = uses.get(e, 0) + 1
    assert max(uses.values()) <= 2
    # no surface's loop passes through one node twice (it crosses itself in its surface: on the
    # CASSIE sketches 02-0-2, 10-2-1, teapot and vintage_car every such loop turned its patch over)
    # (a curve drawn across a divided loop, core.loop_split, is no graph edge: it starts where the
    # side before it ends, and ends where the side after it starts)
    edges = build.graph.edges
    for surf in build.surfaces:
        sides = surf.cycle.sides
        ends = [None if e >= len(edges) else (edges[e].node1, edges[e].node0) if rev
                else (edges[e].node0, edges[e].node1) for e, rev in sides]
        for k, pair in enumerate(ends):
            if pair is None:
                ends[k] = (ends[k - 1][1], ends[(k + 1) % len(ends)][0])
        assert all(ends[k][1] == ends[(k + 1) % len(ends)][0] for k in range(len(ends))), sides
        starts = [a for a, _ in ends]
        assert len(set(starts)) == len(starts), sides
    # each curve across lies between two nodes of its loop, in the graph's nodes exactly
    for curve, *_ in build.divisions:
        across = build.polylines[curve]
        points = np.array([n.point for n in build.graph.nodes])
        assert sum(1 for s in build.surfaces if curve in s.sides) == 2
        assert min(np.linalg.norm(points - across[0], axis=1)) < build.graph.delta


SMALL = DATA / "cassie" / "04-1-1.xyz"


@pytest.mark.skipif(not SMALL.is_file(), reason=f"shared sketch {SMALL} not found")
def test_real_sketch_builds_through_the_command(tmp_path):
    report_path = tmp_path / "r.json"
    proc = run("build", str(SMALL), "-o", str(tmp_path / "r.step"), "--report", str(report_path),
               "--surfaces", "all", "-q")
    assert proc.returncode in (0, 3), proc.stderr           # built (3: with a quality warning, named)
    report = json.loads(report_path.read_text())
    assert report["surfaces"] and all(s["valid"] for s in report["shells"])
    assert all(s["used"] or s["reason"] for s in report["strokes"])
    from ProgSurf import cad

    assert cad.read_back(tmp_path / "r.step")["faces"] == report["faces"]


HELIBODY = DATA / "tigl" / "helibody" / "helibody.noisy.xyz"


@pytest.mark.skipif(not HELIBODY.is_file(), reason=f"shared sketch {HELIBODY} not found")
def test_the_noisy_helicopter_builds_one_closed_shell():
    """helibody (TiGL, noisy): its guides run 0.5-1 delta apart over the tail boom, and its boom
    rings are cut into pieces shorter than delta. Its guides came in and out of delta there and
    were pinched together at each place (stroke_graph._side_by_side), and the rings' pieces,
    judged over their first 30 % (9 mm, within the noise), turned out of their plane and put the
    guides out of order round their nodes (stroke_cycles.TANGENT_LEAST): 3 open shells with 32
    free edges. Now one closed shell, whose faces share their curves exactly (each network curve
    fitted once, cad.shared_edges: seams within 1e-6 mm, not the 8.2 mm of surface-by-surface
    fitting), every face within its fit allowance, no crease between surfaces."""
    from ProgSurf.app.objects import build_object_and_measure
    from ProgSurf.io import read_strokes

    out = build_object_and_measure(read_strokes(HELIBODY))
    assert len(out.build.surfaces) >= 70
    assert len(out.shells) == 1 and out.shells[0]["closed"] and out.shells[0]["free_edges"] == 0
    assert all(s["valid"] for s in out.shells)
    assert max(s["seam_gap_max_mm"] for s in out.shells) <= 1e-6
    assert out.model.folds_across == ()
    assert [p for p in out.problems if "fold(s) inside surfaces" not in p] == []


@pytest.mark.skipif(not HELIBODY.is_file(), reason=f"shared sketch {HELIBODY} not found")
def test_the_noisy_helicopter_is_tangent_continuous_in_g1():
    """helibody (TiGL, noisy) in G1: every surface side along a smooth shared curve meets its
    neighbour within a degree (cad.object_g1.TANGENT_DEG) at the measured points. It had 20 of
    210 beyond: 16 next to their ends, where the pieces of a boom ring or guide kinked at their
    nodes (core.node_tangents; a ring also at its seam) and the twist compromise reached over
    10 % of a side (cad.g1.ACROSS_END_KNOTS); 4 all along, where the face across had its correction turned
    over and stayed G0 while this one aimed at the mean of the two normals, keeping half the angle
    (14.7 of 29.4 deg; now it aims at that face's normal, cad.object_g1.following)."""
    from ProgSurf.app.objects import build_object_and_measure
    from ProgSurf.io import read_strokes

    out = build_object_and_measure(read_strokes(HELIBODY), continuity="G1")
    across = out.model.across
    assert across["smooth_sides"] >= 150
    assert across["tangent_sides"] == across["smooth_sides"], across
    assert across["angle_max_deg"] < 1.0, across
    assert len(out.shells) == 1 and out.shells[0]["closed"] and out.shells[0]["free_edges"] == 0


HELIBODY_CLEAN = DATA / "tigl" / "helibody" / "helibody.clean.xyz"


@pytest.mark.skipif(not HELIBODY_CLEAN.is_file(), reason=f"shared sketch {HELIBODY_CLEAN} not found")
def test_the_helicopter_nose_cap_is_smooth():
    """helibody (TiGL, clean): the nose cap's strips converge to its tip. With every loop's corners
    where the paper's merge puts them, 52 of its 115 surfaces turned over and the strips met in 33
    creases (ribs in the render); with the corners of a folding loop chosen where its Coons patch
    turns least (core.loop_corners), at most 10 fold and none creases against its neighbour, in
    one closed shell."""
    from ProgSurf.app.objects import build_object_and_measure
    from ProgSurf.io import read_strokes

    out = build_object_and_measure(read_strokes(HELIBODY_CLEAN))
    assert len(out.build.surfaces) >= 100
    assert out.model.folds_across == ()
    assert sum(1 for f in out.folds if f) <= 10
    assert len(out.shells) == 1 and out.shells[0]["closed"] and out.shells[0]["free_edges"] == 0


FUSELAGE_CLEAN = DATA / "tigl" / "fuselage1" / "fuselage1.clean.xyz"


@pytest.mark.skipif(not FUSELAGE_CLEAN.is_file(), reason=f"shared sketch {FUSELAGE_CLEAN} not found")
def test_the_clean_fuselage_passes_every_check():
    """fuselage1 (TiGL, clean): one closed shell of 72 surfaces that passes every check. Its tail
    tip triangle read a crease of 116 deg against its neighbour on one OpenBLAS kernel (the sample
    fell exactly on the neighbour's corner) and none on another; points next to the other face's
    corners are not checked (cad.object_g1.CORNER_SKIP), as its ends are not."""
    from ProgSurf.app.objects import build_object_and_measure
    from ProgSurf.io import read_strokes

    out = build_object_and_measure(read_strokes(FUSELAGE_CLEAN))
    assert len(out.build.surfaces) == 72
    assert len(out.shells) == 1 and out.shells[0]["closed"] and out.shells[0]["valid"]
    assert out.problems == [], out.problems




def test_creases_between_surfaces_that_no_stroke_draws_are_reported():
    """A body of revolution from the project's object generator (benchmarks/objects.py, body
    2004): two of its neighbouring loops fold onto each other along the stroke they share, where
    the strokes at the ends make them meet at a far smaller angle. The verdict names them and the
    report lists each with the stroke it runs along (cad.object_g1.across_folds); the exact
    tapered tube and the cube have none (test_objects). (The noisy TiGL helicopter had 3 such
    creases until its boom's guides stopped being pinched together; vintage_car had 10 while
    edges jumped to their nodes in one segment; the rough body 7001 had one until the ends of its
    meridians that miss its tip met there, stroke_joins._meeting_ends.)"""
    import sys

    sys.path.insert(0, str(ROOT))
    from benchmarks.objects import make_object
    from ProgSurf.app.objects import build_object_and_measure, object_report
    from ProgSurf.cad.object_g1 import FOLD_RISE_DEG

    out = build_object_and_measure(make_object("body", 2004).strokes)
    found = out.model.folds_across
    assert len(found) >= 1
    assert all(f["angle_deg"] > f["ends_deg"] + FOLD_RISE_DEG for f in found)
    assert any("crease(s) between surfaces" in p for p in out.problems)
    listed = object_report(out)["folds_across_surfaces"]
    assert len(listed) == len(found) and all(f["strokes"] for f in listed)


def test_by_default_a_cube_builds_every_surface_and_a_square_one(tmp_path):
    """--surfaces auto is the default (issue 18): the cube's edges (loops facing every way) make six
    surfaces, the bundled clean4 sketch (one loop round the others) its single surface."""
    cube = tmp_path / "cube.xyz"
    write_cube(cube)
    proc = run("build", str(cube), "-o", str(tmp_path / "cube.step"), "--report", str(tmp_path / "cube.json"))
    assert proc.returncode == 0, proc.stderr
    report = json.loads((tmp_path / "cube.json").read_text())
    assert report["mode"] == "all" and len(report["surfaces"]) == 6
    # the single surface's headline measures, over the object: each flat face meets its
    # neighbours at the cube's right angles, and no face has a seam inside it
    assert report["seam_angle_max_deg"] == pytest.approx(90.0, abs=1e-6)
    assert all(s["seam_angle_max_deg"] == 0.0 for s in report["surfaces"])
    assert report["fit_deviation_max_mm"] == max(s["fit_deviation_max_mm"] for s in report["surfaces"])
    proc = run("build", str(ROOT / "examples" / "clean4.xyz"), "-o", str(tmp_path / "c4.step"),
               "--report", str(tmp_path / "c4.json"))
    assert proc.returncode == 0, proc.stderr
    assert "mode" not in json.loads((tmp_path / "c4.json").read_text())


def test_by_default_a_sketch_with_no_single_boundary_loop_builds_every_surface(tmp_path):
    """A U-shaped sheet of five 100 mm squares (a 3x2 grid without its middle top square): one
    part whose loops all face one way, so --surfaces auto tries the single surface first; its
    border leaves a 100 mm gap across the notch of the U, the single surface is refused, and auto
    then builds the network's 5 surfaces and says why. (vintage_car showed this until its loops
    faced less one way, 0.60 < 0.7, when the ends that miss one point started to meet there.)"""
    from ProgSurf.io.pointlist import write_point_list

    def lift(a, b, n):
        p = np.linspace(np.asarray(a, float), np.asarray(b, float), n)
        return np.c_[p, 2e-4 * p[:, 0] * p[:, 1]]

    strokes = ([lift([0, 0], [300, 0], 60), lift([0, 100], [300, 100], 60), lift([0, 200], [100, 200], 30),
                lift([200, 200], [300, 200], 30)] + [lift([x, 0], [x, 200], 40) for x in (0, 100, 200, 300)])
    sketch = tmp_path / "u.xyz"
    write_point_list(sketch, strokes)
    report_path = tmp_path / "r.json"
    proc = run("build", str(sketch), "-o", str(tmp_path / "r.step"), "--report", str(report_path))
    assert "no single boundary loop" in proc.stdout
    report = json.loads(report_path.read_text())
    assert report["mode"] == "all" and len(report["surfaces"]) == 5
    # exit 0 when every check passes, 3 (files written) when one fails
    assert proc.returncode == (0 if report["quality"]["ok"] else 3), proc.stderr
    assert (tmp_path / "r.step").is_file()


@pytest.mark.skipif(not SMALL.is_file(), reason=f"shared sketch {SMALL} not found")
def test_a_sketch_whose_loops_face_every_way_builds_every_surface(tmp_path):
    """04-1-1 (CASSIE, a lamp): its loops face every way round the shade, so --surfaces auto
    builds every surface at once; the single surface is refused with the gap that stops one loop."""
    report_path = tmp_path / "r.json"
    proc = run("build", str(SMALL), "-o", str(tmp_path / "r.step"), "--report", str(report_path))
    report = json.loads(report_path.read_text())
    assert report["mode"] == "all" and len(report["surfaces"]) >= 3
    assert proc.returncode == (0 if report["quality"]["ok"] else 3), proc.stderr
    proc = run("build", str(SMALL), "-o", str(tmp_path / "one.step"), "--surfaces", "one")
    assert proc.returncode == 2 and "gap" in proc.stderr


@pytest.mark.skipif(not SMALL.is_file(), reason=f"shared sketch {SMALL} not found")
def test_a_loop_drawn_on_over_its_own_start_keeps_its_surfaces():
    """04-1-1's stroke 20 is a loop whose last 56 mm (15.2 % of it) run back over its start, its
    seam beside stroke 11: it closes at the node there, and that last piece, a loop back to the
    same node, is dropped (stroke_graph._along_itself; kept, the shade's rear lost a loop: 7 of 8).
    Since two strokes touching along a run meet at the run's middle (session 24, for the same
    network whichever way the strokes run) the loop of strokes 21, 10 and 7 at the shade's top is
    lost too: 7 loops, and a self-loop on stroke 20 and a two-sided sliver beside it without the
    rule. Since a face cut at a bridge is kept (session 33) stroke 20 bounds one loop, with stroke
    12: a round one (4 pi area / perimeter^2 = 0.82; a sliver's is near 0)."""
    from ProgSurf.core.objects import stroke_network, steady_tolerances
    from ProgSurf.core.stroke_cycles import vector_area
    from ProgSurf.io import read_strokes

    strokes = read_strokes(SMALL)
    graph, choice, _ = stroke_network(strokes, steady_tolerances(strokes))
    assert len(choice.cycles) >= 7
    assert not [e for e in graph.edges if e.node0 == e.node1 and e.stroke == 20]
    for c in choice.cycles:
        if 20 in {graph.edges[e].stroke for e in c.edge_ids}:
            loop = c.loop_points(graph)
            perimeter = np.linalg.norm(np.diff(np.vstack([loop, loop[:1]]), axis=0), axis=1).sum()
            assert 4 * np.pi * np.linalg.norm(vector_area(loop)) / perimeter ** 2 > 0.5


NACELLE = DATA / "tigl" / "full_nacelle" / "full_nacelle.clean.xyz"


@pytest.mark.skipif(not NACELLE.is_file(), reason=f"shared sketch {NACELLE} not found")
def test_the_nacelle_inlet_lip_is_built():
    """full_nacelle (TiGL, clean): its guides run from the inner ring (stroke 0) forward round the
    inlet lip and back along the outside. The strip round the lip was left out and the inner ring
    taken as a stroke inside the surfaces behind the lip (pulling them 200 mm inwards) while the
    verdict said "ok"; now the inner ring bounds the 4 lip surfaces and is inside none
    (core.stroke_cycles._flip_weak, _turning), 16 surfaces in one shell, open at both ends."""
    from ProgSurf.app.objects import build_object_and_measure, object_report
    from ProgSurf.io import read_strokes

    out = build_object_and_measure(read_strokes(NACELLE))
    report = object_report(out)
    inner = report["strokes"][0]
    assert len(out.build.surfaces) == 16
    assert len(inner["boundary_of"]) == 4 and inner["interior_to"] == []
    shell, = out.shells
    assert shell["valid"] and shell["faces"] == 16 and not shell["closed"] and shell["seam_gap_max_mm"] <= 1e-6


VR_0722 = DATA / "cassie" / "07-2-2.xyz"


@pytest.mark.skipif(not VR_0722.is_file(), reason=f"shared sketch {VR_0722} not found")
def test_a_stroke_drawn_there_and_back_keeps_one_piece_whichever_way_it_runs():
    """07-2-2's stroke 22 runs from one node to another and back, twice (two pairs of pieces
    within delta of each other between the same nodes): one piece of each pair is kept, the
    longer, whichever way the stroke was drawn (the first along it was kept: drawn the other way,
    another piece, another node normal, and 35 or 36 loops)."""
    from ProgSurf.core.objects import stroke_network
    from ProgSurf.io import read_strokes

    strokes = read_strokes(VR_0722)
    turned = [s[::-1] if k == 22 else s for k, s in enumerate(strokes)]
    g0, c0, _ = stroke_network(strokes)
    g1, c1, _ = stroke_network(turned)

    def pieces(g):
        return sorted((tuple(sorted((tuple(np.round(g.nodes[e.node0].point, 3)), tuple(np.round(g.nodes[e.node1].point, 3))))),
                       round(e.length, 3)) for e in g.edges if e.stroke == 22)

    assert pieces(g0) == pieces(g1)
    assert len(c0.cycles) == len(c1.cycles)
