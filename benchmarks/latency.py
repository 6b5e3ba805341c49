"""Interactive latency (issue 8, item 1) and the profile of the per-stroke core update (item 4).

For networks of about 1, 10, 50, 200 and 500 regions, grown with random strokes over a closed-form
surface, the NEXT stroke is timed on fresh clones of the network (the clone is not timed):

- core        : ProgSurf.core.progressive.add_stroke alone;
- full shell  : add_stroke + ProgSurf.cad.build_shell of the whole network from nothing: every
                edge curve refitted, every face rebuilt, all sewn;
- incremental : add_stroke + cad.build_shell(..., previous=the network's shell), what the document
                object does on recompute: curves and faces whose inputs did not change are reused;
                of a curve the stroke split or pulled only the changed edges are refitted (joined
                C2 to the kept pieces); the faces along changed edges are built again and sewn
                into the kept, already sewn faces;
- G1          : the same incremental update in G1 mode from the network's G1 shell: G1 faces whose
                G0 face and neighbours are unchanged are reused; the difference to the incremental
                column is the time G1 adds per stroke.
"""
from __future__ import annotations

import cProfile
import io
import pstats
import time
from dataclasses import replace

import numpy as np

from ProgSurf import cad
from ProgSurf.cad import edges as cad_edges
from ProgSurf.core.errors import FitError
from ProgSurf.core.progressive import add_stroke
from ProgSurf.core.types import Tolerances

from .surfaces import BENCH_TOL, SURFACES, grow_networks, random_stroke


def _changed_curves(old, new) -> set:
    """Curve ids of the edges of `new` that are new or differ from `old` (the network replaces an
    edge's immutable polyline, or a node, whenever it changes)."""
    before, after = old.edges(), new.edges()
    out = set()
    for eid, e in after.items():
        o = before.get(eid)
        if (o is None or o.polyline is not e.polyline or (o.node0, o.node1) != (e.node0, e.node1)
                or not np.array_equal(old.node_xyz(e.node0), new.node_xyz(e.node0))
                or not np.array_equal(old.node_xyz(e.node1), new.node_xyz(e.node1))):
            out.add(e.curve_id)
    return out


def fits(old, new, tol: Tolerances) -> bool:
    """True when the adapter can fit every curve the stroke changed (used to keep growth strokes;
    see README: core.curve_fit cannot pass exactly through two nodes very close on one curve)."""
    edges = new.edges()
    nodes = cad_edges.node_points(edges)
    tol_mm = tol.fit_mm * cad_edges.EDGE_FIT_FRACTION
    changed = _changed_curves(old, new)
    try:
        for cid in changed:
            group = [e for e in edges.values() if e.curve_id == cid]
            chain = cad_edges.curve_chain(group)
            if chain is not None:
                cad_edges.fit_curve(chain, nodes, tol_mm, cid)
            else:
                for e in group:
                    cad.curves.fit_polyline(e.polyline, tol_mm, start=nodes[e.node0], end=nodes[e.node1])
    except FitError:
        return False
    return True


FIT_LADDER_MM = (0.01, 0.05, 0.2, 1.0)
"""Fit tolerances tried in turn when the adapter cannot fit a network curve within the default
(Tolerances().fit_mm = 0.01 mm): the benchmark reports which one it took."""


def shell_with_fallback(net, tol: Tolerances):
    """cad.build_shell at the first fit tolerance of FIT_LADDER_MM that works.
    Returns (ShellResult, fit_mm used, [(fit_mm, error message) of the failed attempts])."""
    failures = []
    for fit in FIT_LADDER_MM:
        t = replace(tol, fit_mm=fit)
        try:
            return cad.build_shell(net, t), fit, failures
        except FitError as err:
            failures.append((fit, str(err)))
    raise FitError(f"no shell within fit tolerances {FIT_LADDER_MM} mm: {failures[-1][1]}")


def _stats(values: list) -> dict:
    if not values:
        return {"n": 0, "median_ms": float("nan"), "p95_ms": float("nan")}
    a = np.asarray(values) * 1e3
    return {"n": len(a), "median_ms": float(np.median(a)), "p95_ms": float(np.percentile(a, 95))}


LANDING = 0.02
"""A growth stroke that would take the network past a target size by more than this fraction of
the target (at least 1 region) is undone and another one drawn, so that each row is measured at its
size: since the fold repair splits the regions around a crease, one stroke may add 6 or more, and
the first network of at least 50 regions had 55."""


def grow(sizes: list[int], surface: str = "saddle", seed: int = 1, tol: Tolerances = BENCH_TOL):
    """grow_networks keeping only strokes the adapter can fit and that do not overshoot a target
    (LANDING): (target -> network, growth counts; "dropped" counts the strokes the adapter could
    not fit, "overshot" those undone for overshooting)."""
    overshot = []

    def keep(before, after, rec) -> bool:
        if any(len(before) < t < len(after) - max(1, int(LANDING * t)) for t in sizes):
            overshot.append(rec.index)
            return False
        return fits(before, after, tol)

    nets, counts = grow_networks(SURFACES[surface], sizes, seed=seed, tol=tol, keep=keep)
    return nets, dict(counts, dropped=counts["dropped"] - len(overshot), overshot=len(overshot))


def measure_latency(nets: dict, growth: dict, probes: int, shell_probes: dict, surface: str = "saddle",
                    seed: int = 1, tol: Tolerances = BENCH_TOL, reference=None) -> list[dict]:
    """One row per network (target size -> network from :func:`grow`): regions, and median/p95 ms
    of the core, full-shell (at most shell_probes[target] probes) and incremental variants over
    accepted probe strokes; rejected probes are counted, not timed.
    reference: a function giving the machine reference in ms (run.machine_reference_ms), measured
    before and after each row: this VM's speed drifts by up to 50% within a run."""
    z = SURFACES[surface]
    rows = []
    for target in sorted(nets):
        ref_before = reference() if reference is not None else float("nan")
        net = nets[target]
        base_shell, fit_mm, fit_failures = shell_with_fallback(net, tol)
        ftol = replace(tol, fit_mm=fit_mm)
        base_g1 = None          # the G1 shell before the stroke (not timed), for the G1 column
        rng = np.random.default_rng(seed + 1000)
        core, full, incr, g1, touched, faces_rebuilt, rejected, fit_fail = [], [], [], [], [], [], 0, 0
        for p in range(probes):
            stroke = random_stroke(z, rng)
            work = net.clone()
            t0 = time.perf_counter()
            rec = add_stroke(work, stroke, 10_000 + p, tol, tol.snap_mm)
            t1 = time.perf_counter()
            if rec.status != "accepted":
                rejected += 1
                continue
            core.append(t1 - t0)
            touched.append(len(rec.regions_removed))
            try:
                t2 = time.perf_counter()
                shell = cad.build_shell(work, ftol, previous=base_shell)
                incr.append(t1 - t0 + time.perf_counter() - t2)
                faces_rebuilt.append(shell.reused["faces"][1])
                if len(full) < shell_probes.get(target, 1):
                    if base_g1 is None:
                        base_g1 = cad.build_shell(net, ftol, continuity="G1", previous=base_shell)
                    t3 = time.perf_counter()
                    cad.build_shell(work, ftol, continuity="G1", previous=base_g1)
                    g1.append(t1 - t0 + time.perf_counter() - t3)
                    t3 = time.perf_counter()
                    cad.build_shell(work, ftol)
                    full.append(t1 - t0 + time.perf_counter() - t3)
            except FitError:
                fit_fail += 1
        rows.append({"target": target, "regions": len(net), "probes": probes, "rejected": rejected,
                     "fit_mm": fit_mm, "fit_failures_at_default": len(fit_failures), "probe_fit_failures": fit_fail,
                     "growth": growth,
                     "regions_touched_median": float(np.median(touched)) if touched else float("nan"),
                     "faces_rebuilt_median": float(np.median(faces_rebuilt)) if faces_rebuilt else float("nan"),
                     "core": _stats(core), "full_shell": _stats(full), "incremental": _stats(incr),
                     "g1_incremental": _stats(g1),
                     "reference_ms": 0.5 * (ref_before + (reference() if reference is not None else float("nan")))})
    return rows


def profile_core(net, probes: int, surface: str = "saddle", seed: int = 1,
                 tol: Tolerances = BENCH_TOL, top: int = 10) -> dict:
    """cProfile of add_stroke on clones of `net`: the top functions by cumulative and by own time."""
    z = SURFACES[surface]
    rng = np.random.default_rng(seed + 2000)
    strokes = [random_stroke(z, rng) for _ in range(probes)]
    clones = [net.clone() for _ in strokes]
    prof = cProfile.Profile()
    prof.enable()
    for k, (work, stroke) in enumerate(zip(clones, strokes)):
        add_stroke(work, stroke, 20_000 + k, tol, tol.snap_mm)
    prof.disable()
    stats = pstats.Stats(prof)
    entries = []
    for (filename, line, name), (cc, nc, tt, ct, _) in stats.stats.items():
        entries.append({"function": f"{_short(filename)}:{line}({name})", "calls": nc,
                        "tottime_s": tt, "cumtime_s": ct})
    entries.sort(key=lambda e: -e["cumtime_s"])
    text = io.StringIO()
    pstats.Stats(prof, stream=text).sort_stats("cumulative").print_stats(top + 5)
    return {"regions": len(net), "probes": probes, "top": entries[:top],
            "top_tottime": sorted(entries, key=lambda e: -e["tottime_s"])[:top], "text": text.getvalue()}


def _short(filename: str) -> str:
    for marker in ("ProgSurf/", "numpy/", "benchmarks/"):
        if marker in filename:
            return marker + filename.split(marker, 1)[1]
    return filename
