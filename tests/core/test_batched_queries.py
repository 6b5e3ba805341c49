"""The fold checks evaluate all their samples together (issue 16: they were most of a stroke's
time): every batched query gives, bit for bit, what its one-at-a-time form gives for each of its
sets, so nothing relative (a set's largest normal, its Newton stopping test) leaks between sets."""
import numpy as np
import pytest

from benchmarks.surfaces import BENCH_TOL, SURFACES, grow_networks
from ProgSurf.core import folds
from ProgSurf.core.folds import face_turn_deg, find_folds, normal_sets, region_normals, seam_angle_deg
from ProgSurf.core.preimage import bilinear, inverse_bilinear, inverse_bilinear_sets
from ProgSurf.core.types import Polyline, evaluate_polylines


@pytest.fixture(scope="module")
def net():
    """The benchmark's saddle grown to about 30 regions: quads, triangles, long and short sides."""
    nets, _ = grow_networks(SURFACES["saddle"], [30], seed=3, tol=BENCH_TOL)
    return nets[30]


def test_polylines_together_are_each_polyline_alone():
    rng = np.random.default_rng(0)
    polys = [Polyline(rng.normal(size=(n, 3)), np.r_[0.0, np.sort(rng.uniform(0, 1, n - 2)), 1.0])
             for n in (2, 3, 17)] + [Polyline(np.ones((1, 3)), np.array([0.0]))]
    jobs = [(polys[i % 4], rng.uniform(-0.2, 1.2, 1 + i)) for i in range(9)] + [(polys[2], np.array([0.0, 1.0]))]
    together = evaluate_polylines(jobs)
    assert np.array_equal(together, np.concatenate([p.evaluate(t) for p, t in jobs]))
    # long jobs (searched one by one) and short ones (searched together) alike
    long = [(p, rng.uniform(-0.2, 1.2, 600)) for p in polys] + [(polys[1], np.linspace(0.0, 1.0, 601))]
    assert np.array_equal(evaluate_polylines(long), np.concatenate([p.evaluate(t) for p, t in long]))


def test_inverse_bilinear_of_many_sets_is_each_set_alone(net):
    rng = np.random.default_rng(1)
    sets = []
    for rid in net.region_ids:
        ids, tri = net.region_corners(rid)
        corners = np.array([net.node_uv(n) for n in ids])
        # points inside (slow and fast to converge) and a few outside the region
        w = rng.dirichlet(np.ones(4), size=int(rng.integers(1, 12)))
        uv = w @ corners + rng.normal(scale=0.02, size=(len(w), 2)) * (rng.uniform(size=(len(w), 1)) < 0.3)
        sets.append((corners, uv, tri))
    assert any(t for _, _, t in sets) and not all(t for _, _, t in sets)
    for (s, r), (corners, uv, tri) in zip(inverse_bilinear_sets(sets), sets):
        s1, r1 = inverse_bilinear(corners, uv, tri)
        assert np.array_equal(s, s1) and np.array_equal(r, r1)


def test_regions_evaluated_together_are_each_region_alone(net):
    rng = np.random.default_rng(2)
    sets = [(rid, rng.uniform(0, 1, k), rng.uniform(0, 1, k)) for rid, k in zip(net.region_ids * 2, range(1, 99, 3))]
    together = net.evaluate_regions(sets)
    assert np.array_equal(together, np.concatenate([net.evaluate_region(rid, s, r) for rid, s, r in sets]))


def test_normals_of_many_sets_are_each_set_alone(net):
    """Sets of 1 to 19 samples, each with one on a region's top side (a triangle's collapsed side,
    where which normals count as defined depends on the set's own largest derivatives)."""
    rng = np.random.default_rng(3)
    jobs = []
    for rid in net.region_ids:
        k = int(rng.integers(1, 20))
        jobs.append((rid, rng.uniform(0, 1, k), np.r_[1.0, rng.uniform(0, 1, k - 1)]))
    got = normal_sets(net, jobs)
    for (unit, ok), (rid, s, r) in zip(got, jobs):
        unit1, ok1 = region_normals(net, rid, s, r)
        assert np.array_equal(ok, ok1) and np.array_equal(unit, unit1)


def test_find_folds_reports_the_one_at_a_time_checks(net, monkeypatch):
    """find_folds over every region, with thresholds lowered so that it reports every seam and face,
    gives each angle exactly as seam_angle_deg and face_turn_deg compute it alone; over a subset,
    every seam of the subset with the same angle."""
    owners = {e: tuple(o) for e, o in net.edge_regions().items() if len(o) == 2}
    monkeypatch.setattr(folds, "SEAM_FOLD_DEG", -1.0)
    monkeypatch.setattr(folds, "FACE_TURN_DEG", -1.0)
    found = find_folds(net)
    seams = {f.edge: f.angle_deg for f in found if f.kind == "seam"}
    faces = {f.regions[0]: f.angle_deg for f in found if f.kind == "face"}
    assert set(seams) == set(owners) and set(faces) == set(net.region_ids)
    for e, angle in seams.items():
        assert angle == seam_angle_deg(net, e, owners[e])
    for rid, turn in faces.items():
        assert turn == face_turn_deg(net, rid)
    some = set(net.region_ids[::3])
    part = find_folds(net, some)
    assert {f.edge for f in part if f.kind == "seam"} == {e for e, o in owners.items() if set(o) & some}
    assert all(f.angle_deg == seams[f.edge] for f in part if f.kind == "seam")
    assert {f.regions[0] for f in part if f.kind == "face"} == some


def test_facets_made_together_are_each_region_alone(net):
    """The footpoint facets of every region a stroke left without them are made in one batch: each
    region's grid and pre-image are, bit for bit, evaluate_region and local_to_uv of that region."""
    work = net.clone()
    work._facets.clear()
    parts = work._facet_parts()
    n = work.mesh_density
    ss, rr = np.meshgrid(np.linspace(0.0, 1.0, n + 1), np.linspace(0.0, 1.0, n + 1), indexing="ij")
    assert [p.rid for p in parts] == work.region_ids
    for p in parts:
        assert np.array_equal(p.grid_xyz, work.evaluate_region(p.rid, ss, rr))
        assert np.array_equal(p.grid_uv, work.local_to_uv(p.rid, ss, rr))
        flat = p.grid_xyz.reshape(-1, 3)
        assert np.array_equal(p.box, np.stack([flat.min(axis=0), flat.max(axis=0)]))


def test_inverse_bilinear_maps_back(net):
    """Each region's local (s, r) of points inside it map back to the points (triangles by Cramer's
    rule, quads by Newton), however many regions' points are inverted together."""
    rng = np.random.default_rng(4)
    sets = []
    for rid in net.region_ids:
        ids, tri = net.region_corners(rid)
        corners = np.array([net.node_uv(n) for n in ids])
        w = rng.dirichlet(np.ones(3 if tri else 4), size=int(rng.integers(1, 9)))
        sets.append((corners, w @ corners[:3 if tri else 4], tri))
    for (s, r), (corners, uv, tri) in zip(inverse_bilinear_sets(sets), sets):
        assert np.allclose(bilinear(corners, s, r), uv, atol=1e-12)


def test_surface_points_of_many_regions_are_each_region_alone(net):
    """evaluate_uv inverts and evaluates all regions' points together: each region's points are
    what uv_to_local and evaluate_region give for them (the region's points as one set)."""
    rng = np.random.default_rng(5)
    uv = rng.uniform(0, 1, (200, 2))
    got = net.evaluate_uv(uv)
    rids = net.locate_many(uv)
    assert len(set(rids.tolist())) > 10
    for rid in set(rids.tolist()):
        held = rids == rid
        assert np.array_equal(got[held], net.evaluate_region(rid, *net.uv_to_local(rid, uv[held])))
    assert np.array_equal(net.evaluate_uv(uv[7]), net.evaluate_uv(uv[7:8])[0])
    # several sets at once: each as evaluate_uv gives it alone (a set's points in one region are
    # inverted together, so sets that share a region are kept apart)
    sets = [uv[:50], uv[50:51], uv[51:], uv[:50] + 1e-3]
    for got_set, one in zip(net.evaluate_uv_sets(sets), sets):
        assert np.array_equal(got_set, net.evaluate_uv(one))


def test_side_points_are_the_side_polylines_points(net):
    """The apex of a 3-sided region is chosen from its sides' points alone (_side_points): the
    points of the side views, bit for bit, in both directions along every side."""
    checked = 0
    for rid in net.region_ids:
        k = net.region_corner_ids(rid)
        for i in range(len(k)):
            for a, b in ((k[i], k[(i + 1) % len(k)]), (k[(i + 1) % len(k)], k[i])):
                assert np.array_equal(net._side_points(rid, a, b), net._side(rid, a, b).polyline.points)
                checked += len(net._side(rid, a, b).edges) > 1
    assert checked      # sides of several edges among them


def _snaps_over_every_segment(pts, snap, segs):
    """snap_candidates as it was before it left out the far segments: every segment measured."""
    from ProgSurf.core.stroke_ends import SNAP_TIE_FRACTION
    from ProgSurf.core.strokes import cumulative_length

    a, b, eid, t0, t1, outer = segs
    h = max(1, len(pts) // 2)
    p = pts[:h]
    ab = b - a
    ll = np.einsum("ij,ij->i", ab, ab)
    w = np.clip(np.einsum("hsk,sk->hs", p[:, None, :] - a[None], ab) / np.where(ll > 1e-300, ll, 1.0), 0.0, 1.0)
    close = a[None] + w[..., None] * ab[None]
    d = np.linalg.norm(p[:, None, :] - close, axis=2)
    d = np.where(outer[None, :] | (cumulative_length(pts)[:h, None] <= 2.0 * snap), d, np.inf)
    j, s = np.unravel_index(int(np.argmin(d)), d.shape)
    if not d[j, s] < snap:
        return []
    tie = SNAP_TIE_FRACTION * snap
    near = (d <= d[j, s] + tie) & (np.linalg.norm(close - close[j, s], axis=2) <= tie)
    near[j, s] = False
    return [(int(k), int(eid[q]), float(t0[q] + w[k, q] * (t1[q] - t0[q])), close[k, q])
            for k, q in [(j, s)] + list(zip(*np.nonzero(near)))]


def test_snap_candidates_measure_only_the_segments_that_can_snap(net):
    """Leaving out the segments far from the stroke's first half changes no snap: the same snaps
    (edge, parameter, point, in the same order) as measuring every segment, for strokes that
    start on an edge, at a node (tied snaps), near one, or nowhere near."""
    from ProgSurf.core.stroke_ends import snap_candidates

    rng = np.random.default_rng(6)
    segs = net.edge_segments()
    a, b = segs[0], segs[1]
    size = float(np.ptp(np.vstack([a, b]), axis=0).max())
    found = 0
    for i in range(60):
        k = int(rng.integers(len(a)))
        start = a[k] + rng.uniform(0, 1) * (b[k] - a[k]) if i % 3 else a[k]
        step = rng.normal(size=3) * size / 40
        pts = start + rng.normal(scale=size / 200, size=3) * (i % 2) + np.outer(np.linspace(0, 1, 12), step)
        for snap in (size / 100, size / 20):
            want = _snaps_over_every_segment(pts, snap, segs)
            got = snap_candidates(pts, snap, segs)
            assert len(got) == len(want)
            for x, y in zip(got, want):
                assert x[:3] == y[:3] and np.array_equal(x[3], y[3])
            found += bool(got)
    assert 0 < found < 120


def test_regions_evaluated_at_distinct_parameters_are_the_points(net):
    """evaluate_regions_indexed (each side once per distinct parameter, as the fold checks' central
    differences on a 9 x 9 grid repeat them) gives, bit for bit, evaluate_regions of the points."""
    rng = np.random.default_rng(7)
    g = np.linspace(0.0, 1.0, 9)
    sets = []
    for rid in net.region_ids[:12]:
        sv, rv = np.r_[g, rng.uniform(0, 1, 5)], np.r_[rng.uniform(0, 1, 3), g]
        k = int(rng.integers(1, 120))
        sets.append((rid, sv, rv, rng.integers(0, len(sv), k), rng.integers(0, len(rv), k)))
    got = net.evaluate_regions_indexed(sets)
    assert np.array_equal(got, net.evaluate_regions([(rid, sv[si], rv[ri]) for rid, sv, rv, si, ri in sets]))


def test_region_differences_are_the_central_differences_of_the_points(net):
    """region_differences (each side once per distinct (region, parameter), found by one sort; the
    blends' differences written out) gives the central differences of evaluate_regions' points,
    within round-off of the points' size over the step (the differences of points lose those
    digits, the written-out form does not), at the sides and corners too, for a sample given
    more than once and in any order of regions."""
    from ProgSurf.core.preimage import clip01

    rng = np.random.default_rng(8)
    g = np.linspace(0.0, 1.0, 9)
    rids = net.region_ids[:10]
    which = rng.permutation(np.concatenate([np.full(k, i) for i, k in enumerate(rng.integers(1, 60, len(rids)))]))
    s = np.where(rng.uniform(size=len(which)) < 0.7, rng.choice(g, len(which)), rng.uniform(0, 1, len(which)))
    r = np.where(rng.uniform(size=len(which)) < 0.7, rng.choice(g, len(which)), rng.uniform(0, 1, len(which)))
    s[:3], r[:3] = [0.0, -0.0, 1.0], [-0.0, 0.0, 0.0]
    h = 1e-4
    s0, s1, r0, r1 = clip01(s - h), clip01(s + h), clip01(r - h), clip01(r + h)
    du, dv = net.region_differences(rids, which, s, r, s0, s1, r0, r1)

    def points(a, b):
        return np.concatenate([net.evaluate_regions([(rids[w], a[j:j + 1], b[j:j + 1])]) for j, w in enumerate(which)])

    want_u = (points(s1, r) - points(s0, r)) / (s1 - s0)[:, None]
    want_v = (points(s, r1) - points(s, r0)) / (r1 - r0)[:, None]
    size = np.abs(points(s, r)).max()
    for got, want, step in ((du, want_u, s1 - s0), (dv, want_v, r1 - r0)):
        err = np.linalg.norm(got - want, axis=1)
        assert np.all(err <= 1e-12 * size / step + 1e-9 * np.linalg.norm(want, axis=1)), err.max()
    # one region alone gives the same as among the others
    alone = which == which[0]
    du1, dv1 = net.region_differences([rids[which[0]]], np.zeros(int(alone.sum()), dtype=int), s[alone], r[alone],
                                      s0[alone], s1[alone], r0[alone], r1[alone])
    assert np.array_equal(du1, du[alone]) and np.array_equal(dv1, dv[alone])


def test_polyline_rows_are_each_polyline_alone():
    from ProgSurf.core.types import evaluate_polyline_rows

    rng = np.random.default_rng(10)
    polys = [Polyline(rng.normal(size=(n, 3)), np.r_[0.0, np.sort(rng.uniform(0, 1, n - 2)), 1.0])
             for n in (2, 5, 30)] + [Polyline(np.ones((1, 3)), np.array([0.0]))]
    polys = polys + polys[:2]                   # a polyline given twice
    rows = rng.integers(0, len(polys), 500)
    t = rng.uniform(-0.2, 1.2, 500)
    t[:4] = [0.0, -0.0, 1.0, 0.5]
    got = evaluate_polyline_rows(polys, rows, t)
    assert np.array_equal(got, np.array([polys[i].evaluate(x) for i, x in zip(rows, t)]))
    assert evaluate_polyline_rows(polys, np.zeros(0, dtype=int), np.zeros(0)).shape == (0, 3)


def test_cross3_is_np_cross_bit_for_bit():
    from ProgSurf.core.types import cross3

    rng = np.random.default_rng(9)
    for shape in [(5, 3), (1000, 3), (3,), (4, 7, 3)]:
        a = rng.normal(size=shape) * 10.0 ** rng.uniform(-5, 5, size=shape)
        b = rng.normal(size=shape)
        assert np.array_equal(np.cross(a, b).view(np.int64), cross3(a, b).view(np.int64))
    q, a = rng.normal(size=3), rng.normal(size=(6, 3))
    assert np.array_equal(np.cross(q, a), cross3(q, a)) and np.array_equal(np.cross(a, q), cross3(a, q))


def test_corner_angle_is_measured_as_point_at_length_gives_it():
    """corner_angle_deg (run for every corner of every new 3-sided region) takes the point at its
    reach by one interpolation and clamps without np.clip: the angle is, bit for bit, the one
    point_at_length and np.clip give."""
    from ProgSurf.core.strokes import corner_angle_deg, cumulative_length, point_at_length

    def slow(a, b, reach):
        dirs = []
        for p in (a, b):
            d = point_at_length(p, reach * cumulative_length(p)[-1]) - p[0]
            n = float(np.linalg.norm(d))
            if not n > 0:
                return 180.0
            dirs.append(d / n)
        return float(np.degrees(np.arccos(np.clip(dirs[0] @ dirs[1], -1.0, 1.0))))

    rng = np.random.default_rng(10)
    for i in range(300):
        a = np.cumsum(rng.normal(size=(int(rng.integers(2, 20)), 3)), axis=0)
        b = a.copy() if i % 7 == 0 else np.cumsum(rng.normal(size=(int(rng.integers(2, 20)), 3)), axis=0)
        b[0] = a[0]
        for reach in (0.1, 0.0, 1.0):
            assert corner_angle_deg(a, b, reach) == slow(a, b, reach)
