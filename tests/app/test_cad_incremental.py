"""Incremental shell update (cad.build_shell(..., previous=)): after one more stroke only what it
touched is fitted, built and sewn again. Of a curve the stroke split or pulled, only the changed
edges are refitted, joined C2 to the kept ones, so the result is not pole for pole the shell built
from nothing, but it meets the same guarantees: every edge within the fit tolerance of the network,
a valid shell with the same topology, seams closed."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ProgSurf import cad
from ProgSurf.cad import edges as cad_edges
from ProgSurf.cad._occ import Part
from ProgSurf.core.pipeline import build_network
from ProgSurf.core.progressive import add_stroke
from ProgSurf.io import read_strokes

ROOT = Path(__file__).resolve().parents[2]


class Step:
    def __init__(self, network, tol):
        self.network, self.tol = network, tol


@pytest.fixture(scope="module")
def steps():
    """clean4, then clean4 with one more short stroke drawn on its surface near a corner: a user
    adding a stroke to a surface that already has several patches."""
    result = build_network(read_strokes(ROOT / "examples" / "clean4.xyz"))
    after = result.network.clone()
    uv = np.linspace([0.06, 0.08], [0.2, 0.16], 25)
    stroke = np.asarray(after.evaluate_uv(uv)) + [0.0, 0.0, 0.3]
    record = add_stroke(after, stroke, 99, result.tol, result.tol.snap_mm)
    assert record.status == "accepted", record.reason
    return Step(result.network, result.tol), Step(after, result.tol)


def _free_edges(shape) -> int:
    return sum(1 for e in shape.Edges if len(shape.ancestorsOfType(e, Part.Face)) == 1)


def _check_like_a_full_build(incr, full, network, tol):
    """incr, made from an earlier shell, against `full`, made from nothing, of the same network."""
    assert [f.region_id for f in incr.faces] == [f.region_id for f in full.faces]
    edges = network.edges()
    bound = tol.fit_mm * cad_edges.EDGE_FIT_FRACTION * (1 + 1e-6)
    for eid, curve in incr.edge_curves.items():       # every edge, refitted or kept, within tolerance
        assert cad.curves.curve_deviation(curve, edges[eid].polyline) <= bound
    shape = incr.shape
    assert shape.ShapeType == "Shell" and shape.isValid()
    assert len(shape.Faces) == len(full.shape.Faces) and len(shape.Edges) == len(full.shape.Edges)
    assert _free_edges(shape) == _free_edges(full.shape)          # only the outer boundary is free
    # one orientation: the two faces on a shared edge run along it in opposite directions
    for e in shape.Edges:
        uses = [x.Orientation for f in shape.ancestorsOfType(e, Part.Face) for x in f.Edges if x.isSame(e)]
        assert len(uses) == 1 or sorted(uses) == ["Forward", "Reversed"]
    assert cad.shell_seam_gaps(shape)["seam_gap_max_mm"] <= 1e-7
    assert shape.Area == pytest.approx(full.shape.Area, rel=1e-4)


def _smooth_nodes(result, network):
    """At every node inside a network curve (not a kink): the angle (deg) between the tangents of
    the two pieces meeting there, and the relative jump of the second derivative with respect to
    the curve's pre-image length (a C2 join has both ~0)."""
    edges = network.edges()
    out = []
    by_curve: dict = {}
    for e in edges.values():
        by_curve.setdefault(e.curve_id, []).append(e)
    for group in by_curve.values():
        chain = cad_edges.curve_chain(group)
        if chain is None:
            continue
        for (a, ra), (b, rb) in zip(chain, chain[1:]):
            if cad_edges.kinked(a, ra, b, rb):
                continue
            la, lb = cad_edges.uv_length(a), cad_edges.uv_length(b)
            d1a, d2a = cad_edges.end_derivatives(result.edge_curves[a.id], ra, True, 1.0 / la)
            d1b, d2b = cad_edges.end_derivatives(result.edge_curves[b.id], rb, False, 1.0 / lb)
            cos = float(d1a @ d1b) / (np.linalg.norm(d1a) * np.linalg.norm(d1b))
            angle = float(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))))
            jump = float(np.linalg.norm(d2a - d2b) / max(np.linalg.norm(d2a), np.linalg.norm(d2b), 1e-9))
            out.append((angle, jump))
    return out


def test_unchanged_curves_and_faces_are_reused_and_the_shell_is_like_a_full_build(steps):
    before, after = steps
    first = cad.build_shell(before.network, before.tol)
    assert first.reused == {"curves": (0, len({e.curve_id for e in before.network.edges().values()})),
                            "faces": (0, len(first.faces)), "sewn": (0, len(first.faces)),
                            "local_sew": False}
    full = cad.build_shell(after.network, after.tol)
    incr = cad.build_shell(after.network, after.tol, previous=first)
    reused_curves, fitted = incr.reused["curves"]
    reused_faces, built = incr.reused["faces"]
    assert reused_curves > 0 and fitted > 0           # the new stroke and what it crossed
    assert reused_faces > 0 and built > 0
    assert reused_faces + built == len(full.faces)
    assert incr.reused["sewn"] == (reused_faces, len(full.faces))   # kept faces come pre-sewn
    assert incr.reused["local_sew"]          # and only the faces around the change are sewn again
    # a reused face is the very face of the first build
    kept = {id(f) for f in first.faces}
    assert sum(1 for f in incr.faces if id(f) in kept) == reused_faces
    _check_like_a_full_build(incr, full, after.network, after.tol)


def test_a_partly_refitted_curve_joins_its_kept_pieces_c2():
    """A 30-region network and five more strokes, each built from the shell before it: the pieces
    refitted around each change meet the kept ones with the same tangent and second derivative,
    as the pieces of one whole fit do."""
    from benchmarks.latency import grow
    from benchmarks.surfaces import BENCH_TOL, SURFACES, random_stroke

    nets, _ = grow([30])
    net, tol = nets[30].clone(), BENCH_TOL
    shell = cad.build_shell(net, tol)
    rng = np.random.default_rng(5)
    partial = 0
    for k in range(5):
        while add_stroke(trial := net.clone(), random_stroke(SURFACES["saddle"], rng), 900 + k, tol,
                         tol.snap_mm).status != "accepted":
            pass
        net = trial
        shell = cad.build_shell(net, tol, previous=shell)
        partial += shell.reused["curves"][1]
        assert shell.reused["local_sew"]         # sewn into the last shell around the change only
    joins = _smooth_nodes(shell, net)
    full = cad.build_shell(net, tol)
    whole = _smooth_nodes(full, net)
    print("refitted joins: max angle %.2g deg, max d2 jump %.2g; one whole fit: %.2g deg, %.2g" % (
        max(a for a, _ in joins), max(j for _, j in joins), max(a for a, _ in whole), max(j for _, j in whole)))
    assert partial > 0 and len(joins) > 10
    # as smooth as one whole fit of the same curves, to the round-off of cutting and re-parametrising
    # pieces (a node where the polyline kinks by less than the kink rule still gets its C0 knot in both)
    assert max(a for a, _ in joins) <= max(a for a, _ in whole) + 1e-4
    assert max(j for _, j in joins) <= max(j for _, j in whole) + 1e-4
    _check_like_a_full_build(shell, full, net, tol)


def test_a_rebuild_of_the_same_network_reuses_everything(steps):
    _, after = steps
    first = cad.build_shell(after.network, after.tol)
    again = cad.build_shell(after.network, after.tol, previous=first)
    assert again.reused["curves"][1] == 0 and again.reused["faces"][1] == 0
    assert again.shape.Area == pytest.approx(first.shape.Area, rel=1e-12)


def test_a_changed_tolerance_fits_everything_again(steps):
    _, after = steps
    first = cad.build_shell(after.network, after.tol)
    from dataclasses import replace

    other = cad.build_shell(after.network, replace(after.tol, fit_mm=after.tol.fit_mm * 2), previous=first)
    assert other.reused["curves"][0] == 0 and other.reused["faces"][0] == 0


def test_g1_faces_far_from_the_new_stroke_are_reused_and_the_same():
    """A 30-region network grown with random strokes over a saddle (the benchmark's), then one more
    stroke: the G1 faces it does not reach (through a changed face, curve or node) are reused."""
    from benchmarks.latency import grow
    from benchmarks.surfaces import BENCH_TOL, SURFACES, random_stroke

    nets, _ = grow([30])
    net, tol = nets[30], BENCH_TOL
    rng = np.random.default_rng(3)
    later = net.clone()
    while add_stroke(later, random_stroke(SURFACES["saddle"], rng), 999, tol, tol.snap_mm).status != "accepted":
        later = net.clone()
    before, after = Step(net, tol), Step(later, tol)
    first = cad.build_shell(before.network, before.tol, continuity="G1")
    full = cad.build_shell(after.network, after.tol, continuity="G1")
    incr = cad.build_shell(after.network, after.tol, continuity="G1", previous=first)
    g1_reused = sum(1 for k in incr.cache.g1_faces if k in first.cache.g1_faces)
    assert 0 < g1_reused < len(incr.faces)
    assert len(incr.cache.g1_faces) == len(incr.faces)   # nothing stale is kept
    kept = {id(f) for f in first.faces}
    assert sum(1 for f in incr.faces if id(f) in kept) == g1_reused   # reused G1 faces are the same faces
    _check_like_a_full_build(incr, full, after.network, after.tol)


def test_going_back_to_the_strokes_before_gives_the_very_same_shell(steps):
    """Undo: after a stroke was added (and its curves partly refitted), a build of the network
    before it, from the newer shell, takes every curve and face from the generation kept in the
    cache (cad.shell.ShellCache.older) instead of refitting them: the old shell, face for face."""
    before, after = steps
    first = cad.build_shell(before.network, before.tol)
    second = cad.build_shell(after.network, after.tol, previous=first)
    back = cad.build_shell(before.network, before.tol, previous=second)
    assert back.reused["curves"][1] == 0 and back.reused["faces"][1] == 0
    assert [id(f) for f in back.faces] == [id(f) for f in first.faces]
    assert back.shape.Area == pytest.approx(first.shape.Area, rel=1e-12)
    assert back.shape.isValid() and back.shape.ShapeType == "Shell"
    assert len(back.shape.Edges) == len(first.shape.Edges) and _free_edges(back.shape) == _free_edges(first.shape)


def test_the_cache_keeps_one_older_generation_and_looks_in_both(steps):
    """ShellCache: a build keeps the cache of the build before it (one generation, not a chain),
    and `lookup` finds there what this build no longer holds; the sewn shell's vertex points
    cover exactly the faces of the one sewn-face map."""
    before, after = steps
    first = cad.build_shell(before.network, before.tol)
    second = cad.build_shell(after.network, after.tol, previous=first)
    third = cad.build_shell(after.network, after.tol, previous=second)
    assert first.cache.older is None and second.cache.older is not None
    assert third.cache.older.older is None and third.cache.older.faces is second.cache.faces
    gone = [k for k in second.cache.older.faces if k not in second.cache.faces]
    assert gone                                          # faces the stroke replaced
    for k in gone:
        assert second.cache.lookup("faces", k) is first.cache.faces[k]
        assert third.cache.lookup("faces", k) is None    # two builds back: dropped
    for build in (first, second, third):
        assert build.cache.sewn_shell.shape is build.shape
        assert build.cache.sewn_shell.vertices.keys() == build.cache.sewn.keys()
