"""ProgSurf benchmarks (issue 8): interactive latency, against FreeCAD's Surface::Filling and
GeomFillSurface, scale, the profile of the core update, and (issue 16) quality on hand-like
sketches with a known answer (benchmarks/quality.py).

    /usr/bin/python3 benchmarks/run.py [--out out/bench] [--smoke] [--quality-per N] [--no-quality]

Writes OUT/bench.md (the tables, also printed), OUT/bench.png, OUT/bench.json (raw numbers) and
OUT/quality.txt (one line per quality sketch and continuity).
--smoke runs everything at its smallest size (a minute or so; the test suite runs it).
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))
os.environ.setdefault("HOME", "/tmp")
# ProgSurf's matrices are small (tens to hundreds of rows): OpenBLAS threads only spin against the
# main thread on a 2-core machine (2 of 5 minutes of system time, ~15% wall time on the latency
# probes). Set before numpy is imported; the variable, if already set, wins.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

FULL = {"sizes": [1, 10, 50, 200, 500], "probes": 20, "shell_probes": {1: 5, 10: 5, 50: 5, 200: 3, 500: 2},
        "surfaces": ["saddle", "dome", "wave"], "ks": [0, 1, 2, 4, 8, 16], "scale_strokes": 200,
        "profile_size": 200, "profile_probes": 10, "quality_per": 12, "quality_only": []}
SMOKE = {"sizes": [1, 10], "probes": 3, "shell_probes": {1: 1, 10: 1}, "surfaces": ["saddle"], "ks": [0, 1],
         "scale_strokes": 4, "profile_size": 10, "profile_probes": 2, "quality_per": 1,
         "quality_only": ["saddle_small", "section_bump"]}
QUALITY_SEED_BASE = 0
"""benchmarks.sketches.family(per, seed_base=QUALITY_SEED_BASE): the same sketches in every run."""


def _scale_in_child(n: int, out: Path, fit_checked: bool) -> dict:
    """Run the scale part in a fresh process so its peak memory is its own."""
    path = out / "scale.json"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")])))
    proc = subprocess.run([sys.executable, str(Path(__file__).resolve()), "--part", "scale",
                           "--strokes", str(n), "--out", str(out)] + (["--fit-checked"] if fit_checked else []),
                          capture_output=True, text=True, env=env, cwd=str(ROOT), timeout=1800)
    if proc.returncode != 0:
        raise RuntimeError(f"scale run failed: {proc.stderr.strip()[-800:]}")
    return json.loads(path.read_text())


def _quality(cfg: dict, out: Path, jobs: int) -> dict | None:
    """The quality section (benchmarks/quality.py) on benchmarks.sketches.family(cfg["quality_per"]):
    {"text": markdown, "summary": per continuity, "results": per sketch}; None when quality_per is 0.
    The sketches are built in child processes; their lines go to stderr and OUT/quality.txt."""
    if not cfg["quality_per"]:
        return None
    from benchmarks import quality
    from benchmarks.sketches import family_specs

    specs = family_specs(cfg["quality_per"], QUALITY_SEED_BASE, cfg["quality_only"])
    lines = []

    def progress(res):
        lines.extend(quality.line(res, c) for c in quality.CONTINUITIES)
        sys.stderr.write("\n".join(lines[-len(quality.CONTINUITIES):]) + "\n")

    results = quality.run(specs, quality.CONTINUITIES, jobs=jobs, progress=progress)
    (out / "quality.txt").write_text("\n".join(quality.line(r, c) for r in results for c in quality.CONTINUITIES) + "\n")
    text = "\n\n".join([
        f"{len(specs)} sketches of `benchmarks.sketches.family(per={cfg['quality_per']}, "
        f"seed_base={QUALITY_SEED_BASE})`{' (configurations ' + ', '.join(cfg['quality_only']) + ')' if cfg['quality_only'] else ''}, "
        "noisy strokes, each built through `app.build.build_and_measure(strokes, None, Tolerances())` in G0 and "
        "in G1 (one process per sketch). Figures in % are of the boundary's bounding-box diagonal; the "
        "lifted stroke alone puts a floor near 1.5% under dev_max. FOLD = a shared edge whose faces' "
        "normals differ by more than 60 deg (9 points, 5-95% of the edge) or a face whose normal is more "
        "than 90 deg from the truth's. Within the fit tolerance = the report's fit deviation at most "
        "the tolerance the build used. One line per sketch: OUT/quality.txt.",
        quality.section(results, quality.CONTINUITIES)])
    return {"text": text, "summary": {c: quality.summary(results, c) for c in quality.CONTINUITIES},
            "results": results}


def _json_safe(x):
    if isinstance(x, dict):
        return {str(k): _json_safe(v) for k, v in x.items() if k not in ("shape", "shell")}
    if isinstance(x, (list, tuple)):
        return [_json_safe(v) for v in x]
    if isinstance(x, float) and x != x:
        return None
    return x


def machine_reference_ms(repeats: int = 5) -> float:
    """A fixed workload independent of ProgSurf (small least-squares solves and a Python loop, the
    mix ProgSurf runs): the fastest of `repeats`, in ms. Printed at the start and the end of a run,
    so that runs on a VM whose speed drifts (10-25% here) can be compared."""
    import numpy as np

    rng = np.random.default_rng(0)
    a = rng.random((120, 40))
    b = rng.random((120, 3))
    best = float("inf")
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(100):
            np.linalg.lstsq(a, b, rcond=None)
        total = 0
        for i in range(200_000):
            total += i
        best = min(best, time.perf_counter() - t0)
    return best * 1e3


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="benchmarks/run.py", description=__doc__.splitlines()[0])
    p.add_argument("--out", default=str(ROOT / "out" / "bench"), help="output folder (default out/bench)")
    p.add_argument("--smoke", action="store_true", help="smallest size of everything")
    p.add_argument("--quality-per", type=int, metavar="N",
                   help="quality sketches per configuration (default 12, 108 sketches; smoke: 1 of 2 configurations)")
    p.add_argument("--no-quality", action="store_true", help="leave out the quality section")
    p.add_argument("--jobs", type=int, default=2, help="quality builds run at once (default 2)")
    p.add_argument("--part", choices=["scale"], help=argparse.SUPPRESS)
    p.add_argument("--strokes", type=int, default=200, help=argparse.SUPPRESS)
    p.add_argument("--fit-checked", action="store_true", help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    if args.part == "scale":
        from benchmarks.scale import run_scale
        (out / "scale.json").write_text(json.dumps(_json_safe(run_scale(args.strokes, str(out), fit_checked=args.fit_checked or None)), indent=1))
        return 0

    from benchmarks import latency, peers, report

    cfg = dict(SMOKE if args.smoke else FULL)
    if args.quality_per is not None:
        cfg.update(quality_per=args.quality_per, quality_only=[])
    if args.no_quality:
        cfg["quality_per"] = 0
    t_start = time.perf_counter()
    clock: dict = {"reference_start_ms": machine_reference_ms()}

    t0 = time.perf_counter()
    sizes = sorted(set(cfg["sizes"]) | {cfg["profile_size"]})
    nets, growth = latency.grow(sizes)
    lat = latency.measure_latency({s: nets[s] for s in cfg["sizes"]}, growth, cfg["probes"], cfg["shell_probes"],
                                  reference=machine_reference_ms)
    clock["latency_s"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    prof = latency.profile_core(nets[cfg["profile_size"]], cfg["profile_probes"])
    clock["profile_s"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    peer_rows = [peers.compare(s, k) for s in cfg["surfaces"] for k in cfg["ks"]]
    clock["peers_s"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    scale = _scale_in_child(cfg["scale_strokes"], out, fit_checked=args.smoke)
    clock["scale_s"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    qual = _quality(cfg, out, args.jobs)
    clock["quality_s"] = time.perf_counter() - t0
    clock["reference_end_ms"] = machine_reference_ms()
    clock["total_s"] = time.perf_counter() - t_start

    report.plot(lat, peer_rows, str(out / "bench.png"))
    md = "\n\n".join([
        f"# ProgSurf benchmark{' (smoke)' if args.smoke else ''}",
        f"{platform.node()}, {os.cpu_count()} cores, Python {platform.python_version()}; "
        f"wall time {clock['total_s']:.0f} s (latency {clock['latency_s']:.0f}, profile {clock['profile_s']:.0f}, "
        f"peers {clock['peers_s']:.0f}, scale {clock['scale_s']:.0f}, quality {clock['quality_s']:.0f}). Machine reference "
        f"(benchmarks/run.py:machine_reference_ms, lower is faster): {clock['reference_start_ms']:.1f} ms at "
        f"the start, {clock['reference_end_ms']:.1f} ms at the end.",
        "## 1. Interactive latency (saddle, random strokes)",
        f"Growth strokes: {growth['accepted']} kept, {growth['rejected']} rejected by the core, "
        f"{growth['dropped']} dropped because the CAD adapter could not fit them, "
        f"{growth.get('overshot', 0)} undone because they took the network past a row's size "
        f"(latency.LANDING).",
        report.latency_table(lat), report.target_lines(lat),
        "incremental = core + cad.build_shell(previous=shell of the network before the stroke): "
        "unchanged curves and faces reused; of a curve the stroke split or pulled only the changed "
        "edges refitted (joined C2 to the kept pieces); the faces along changed edges built again "
        "and sewn locally into the last shell, with the kept faces around them (what the document object does on recompute). "
        "full shell = core + the shell built from nothing. "
        "G1 incremental = the same from the network's G1 shell (G1 faces reused where their G0 face and "
        "neighbours are unchanged); "
        "the difference to the incremental column is the time G1 adds per stroke.",
        "## 2. Against Surface::Filling and GeomFillSurface (Coons)",
        "dev = vertical deviation |z - z_true(x,y)| on a 21x21 grid of every face; curve dev = largest "
        "distance of the interior curves' points from the result.",
        report.peers_table(peer_rows),
        "## 3. Scale", report.scale_table(scale),
        "## 4. Profile of the core update", report.profile_table(prof)]
        + ([] if qual is None else ["## 5. Quality on hand-like sketches", qual["text"]]))
    (out / "bench.md").write_text(md + "\n")
    raw = {"config": cfg, "clock_s": clock, "growth": growth, "latency": lat, "peers": peer_rows,
           "scale": scale, "profile": {k: v for k, v in prof.items() if k != "text"},
           "quality": None if qual is None else {k: v for k, v in qual.items() if k != "text"}}
    (out / "bench.json").write_text(json.dumps(_json_safe(raw), indent=1))
    sys.stdout.write(md + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
