"""Scale (issue 8, item 3): a sketch of N random interior strokes over the saddle, end to end.

Run in a fresh process by benchmarks/run.py so that the peak resident memory (ru_maxrss) is this
sketch's alone. Two builds:
- pipeline : ProgSurf.core.pipeline.build_network of boundary + N strokes (the core), then cad.build_shell,
             STEP export and a fresh-process read-back, if the adapter can fit the network;
- fit-checked : the same strokes added one by one, dropping every accepted stroke whose changed
             curves the adapter cannot fit (see README, core.curve_fit), so that the STEP numbers exist even
             when the pipeline network cannot be exported.
"""
from __future__ import annotations

import os
import resource
import time

import numpy as np

from ProgSurf import cad
from ProgSurf.core.errors import ProgSurfError
from ProgSurf.core.pipeline import build_network
from ProgSurf.core.progressive import add_stroke

from .latency import fits
from .surfaces import BENCH_TOL, SURFACES, base_network, boundary_strokes, random_stroke

def peak_rss_mb() -> float:
    """Peak resident memory of this process in MB: VmHWM of /proc/self/status, the high-water mark
    of this process's own memory. (ru_maxrss is not: after fork/vfork and exec it keeps the parent's
    peak, so a child of the benchmark reported the benchmark's own 280 MB.)"""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


STROKE_LENGTH = (0.05, 0.20)
"""Scale strokes are shorter than the latency ones (5-20% of the side): a detailed sketch."""


def _export(net, folder: str, name: str) -> dict:
    out: dict = {}
    t0 = time.perf_counter()
    try:
        shell = cad.build_shell(net, BENCH_TOL)
    except ProgSurfError as err:
        return {"ok": False, "error": " ".join(str(err).split())[:200], "shell_s": time.perf_counter() - t0}
    out["shell_s"] = time.perf_counter() - t0
    out["faces"] = len(shell.faces)
    out["poles_total"] = int(sum(f.surface.NbUPoles * f.surface.NbVPoles for f in shell.faces))
    path = os.path.join(folder, f"{name}.step")
    t0 = time.perf_counter()
    cad.export_step(shell.shape, path)
    out["export_s"] = time.perf_counter() - t0
    out["step_bytes"] = os.path.getsize(path)
    t0 = time.perf_counter()
    back = cad.read_back(path)
    out["reimport_s"] = time.perf_counter() - t0
    out["reimport_faces"] = back["faces"]
    out["reimport_valid"] = back["valid"]
    out["ok"] = back["faces"] == out["faces"]
    return out


def _add_last(z, strokes: list) -> dict:
    """The last stroke added the way the document adds it on recompute: pipeline.build_network with the
    earlier result (only the new stroke is added to a copy of its network) and cad.build_shell
    with the earlier shell. The earlier build is not timed."""
    boundary = boundary_strokes(z)
    before = build_network(boundary + strokes[:-1], boundary=4, tol=BENCH_TOL)
    try:
        before_shell = cad.build_shell(before.network, BENCH_TOL)
    except ProgSurfError as err:
        return {"ok": False, "error": " ".join(str(err).split())[:200]}
    t0 = time.perf_counter()
    after = build_network(boundary + strokes, boundary=4, tol=BENCH_TOL, previous=before)
    t1 = time.perf_counter()
    try:
        shell = cad.build_shell(after.network, BENCH_TOL, previous=before_shell)
    except ProgSurfError as err:
        return {"ok": False, "error": " ".join(str(err).split())[:200]}
    t2 = time.perf_counter()
    return {"ok": True, "core_s": t1 - t0, "shell_s": t2 - t1, "regions": len(after.network),
            "reused_strokes": after.timings_s.get("reused strokes", 0), "status": after.records[-1].status,
            "faces_built": shell.reused["faces"][1], "curves_fitted": shell.reused["curves"][1]}


def run_scale(n_strokes: int, folder: str, seed: int = 7, surface: str = "saddle",
              fit_checked: bool | None = None) -> dict:
    """Build, fit, export and re-import a sketch of n_strokes random interior strokes. The
    fit-checked build runs when fit_checked is True, or (None) when the pipeline's shell failed."""
    z = SURFACES[surface]
    rng = np.random.default_rng(seed)
    strokes = [random_stroke(z, rng, STROKE_LENGTH) for _ in range(n_strokes)]
    result: dict = {"strokes": n_strokes, "surface": surface}

    t0 = time.perf_counter()
    res = build_network(boundary_strokes(z) + strokes, boundary=4, tol=BENCH_TOL)
    core_s = time.perf_counter() - t0
    pipe = {"core_s": core_s, "regions": len(res.network), "accepted": len(res.accepted) - 4,
            "rejected": len(res.rejected)}
    pipe.update(_export(res.network, folder, "scale_pipeline"))
    pipe["total_s"] = core_s + pipe.get("shell_s", 0.0) + pipe.get("export_s", 0.0)
    result["pipeline"] = pipe
    result["add_last"] = _add_last(z, strokes)
    if fit_checked is False or (fit_checked is None and pipe.get("ok")):
        result["peak_rss_mb"] = peak_rss_mb()
        return result

    net = base_network(z)
    t0 = time.perf_counter()
    dropped = accepted = 0
    for i, s in enumerate(strokes):
        before = net.clone()
        rec = add_stroke(net, s, i, BENCH_TOL, BENCH_TOL.snap_mm)
        if rec.status != "accepted":
            continue
        if fits(before, net, BENCH_TOL):
            accepted += 1
        else:
            net, dropped = before, dropped + 1
    checked = {"core_and_fit_checks_s": time.perf_counter() - t0, "regions": len(net),
               "accepted": accepted, "dropped_unfittable": dropped}
    checked.update(_export(net, folder, "scale_fit_checked"))
    result["fit_checked"] = checked
    result["peak_rss_mb"] = peak_rss_mb()
    return result
