"""Quality of ProgSurf on hand-like sketches with a known answer (issue 16).

    /usr/bin/python3 benchmarks/quality.py [--per 12] [--seed-base 0] [--jobs 2] [--only CONFIG]
        [--clean] [--continuity G0 G1] [--out DIR]

Every sketch of benchmarks.sketches.family is built through the product's public entry,
ProgSurf.app.build.build_and_measure(strokes, None, Tolerances(), continuity=...), in G0 and in G1;
a ProgSurfError (or any other error) counts as "not built". Each sketch runs in its own fresh
process (OCC's memory only grows; this file with --child), `--jobs` at a time. Per build it measures (figures in % are of
the boundary's bounding-box diagonal):

- fit: the report's fit deviation (largest distance of a face from its Coons sub-patch) against
  the fit tolerance the build used (result.tol.fit_mm);
- dev_rms, dev_max: distance between the result and the truth both ways: the truth's samples of a
  21 x 21 (u, v) grid inside the region to the result (cad.analysis.shape_point_distances), and
  the result's 7 x 7 samples per face to the true patch (sketches.Truth.distances). The lifted
  stroke alone puts a floor near 1.5% under dev_max;
- seam_in: the largest angle between the normals of the two faces along any shared edge of the
  built shape, at 9 points between 5% and 95% of the edge (OCC normalAt; the ends are left out,
  where a 3-sided face's collapsed corner has no normal);
- flip: faces with a normal more than 90 deg from the truth's normal at the nearest truth sample
  (7 x 7 samples per face, 3% in from its sides, the global orientation aligned first);
- FOLD: seam_in > 60 deg or flip > 0 (a fin, tuck or crease no stroke asked for);
- rejected strokes, and whether every stroke got its drawn role (boundary / interior).
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
FREECAD_LIB = "/usr/lib/freecad-python3/lib"
FOLD_SEAM_DEG = 60.0
FLIP_DEG = 90.0
SEAM_POINTS, SEAM_MARGIN = 31, 0.05
FACE_GRID, FACE_INSET = 7, 0.03
TRUTH_GRID = 21
CONTINUITIES = ("G0", "G1")


def setup_path() -> None:
    """Import FreeCAD (before Part), then put this checkout first on sys.path: FreeCAD's user Mod
    folder may link another checkout of ProgSurf."""
    if FREECAD_LIB not in sys.path:
        sys.path.append(FREECAD_LIB)
    import FreeCAD  # noqa: F401
    for folder in (str(ROOT), str(ROOT / "benchmarks")):   # the latter: sys.path[0] of this file run as a script
        while folder in sys.path:
            sys.path.remove(folder)
    sys.path.insert(0, str(ROOT))


def _unit(v) -> np.ndarray | None:
    n = np.array([v.x, v.y, v.z])
    ln = np.linalg.norm(n)
    return n / ln if ln > 1e-12 else None


def _edge_uv(face, edge, pcurve, frac: float, p) -> tuple[float, float]:
    """(u, v) on face of the point p at fraction frac of edge: from the edge's curve on the face
    (exact and fast), or OCC's projection of p where the two disagree or there is no such curve."""
    if pcurve is not None:
        c, first, last = pcurve[0], pcurve[-2], pcurve[-1]
        uv = c.value(float(first + frac * (last - first)))
        if (face.valueAt(uv.x, uv.y) - p).Length <= max(1e-6, 10.0 * edge.Tolerance):
            return uv.x, uv.y
    return face.Surface.parameter(p)


def seam_fold(shape) -> tuple[float, int]:
    """(largest angle in deg between the normals of the two faces of a shared edge, sampled at
    SEAM_POINTS points between SEAM_MARGIN and 1 - SEAM_MARGIN of each edge; number of edges whose
    largest angle exceeds FOLD_SEAM_DEG). Normals by OCC's Face.normalAt (face orientation included)."""
    import Part

    worst, over = 0.0, 0
    for e in shape.Edges:
        faces = shape.ancestorsOfType(e, Part.Face)
        if len(faces) != 2 or e.Length <= 0:
            continue
        curves = []
        for f in faces:
            try:
                curves.append(f.curveOnSurface(e))
            except Exception:       # noqa: BLE001  (no curve on this face: projected instead)
                curves.append(None)
        a, b = e.ParameterRange
        emax = 0.0
        for frac in np.linspace(SEAM_MARGIN, 1.0 - SEAM_MARGIN, SEAM_POINTS):
            p = e.valueAt(float(a + frac * (b - a)))
            try:
                ns = [_unit(f.normalAt(*_edge_uv(f, e, c, frac, p))) for f, c in zip(faces, curves)]
            except Exception:       # noqa: BLE001  (OCC: no normal here)
                continue
            if ns[0] is not None and ns[1] is not None:
                emax = max(emax, float(np.degrees(np.arccos(np.clip(ns[0] @ ns[1], -1.0, 1.0)))))
        worst = max(worst, emax)
        over += emax > FOLD_SEAM_DEG
    return worst, over


def face_samples(shape) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(points (m, 3), unit normals (m, 3), face index (m,)) of FACE_GRID x FACE_GRID samples of each
    face's parameter range, FACE_INSET in from its sides; points without a normal are left out."""
    pts, nrm, owner = [], [], []
    for k, f in enumerate(shape.Faces):
        u0, u1, v0, v1 = f.ParameterRange
        for u in np.linspace(u0 + FACE_INSET * (u1 - u0), u1 - FACE_INSET * (u1 - u0), FACE_GRID):
            for v in np.linspace(v0 + FACE_INSET * (v1 - v0), v1 - FACE_INSET * (v1 - v0), FACE_GRID):
                try:
                    n = _unit(f.normalAt(float(u), float(v)))
                except Exception:   # noqa: BLE001
                    continue
                if n is not None:
                    q = f.valueAt(float(u), float(v))
                    pts.append((q.x, q.y, q.z))
                    nrm.append(n)
                    owner.append(k)
    return np.array(pts).reshape(-1, 3), np.array(nrm).reshape(-1, 3), np.array(owner, dtype=int)


def flipped_faces(points, normals, owner, truth) -> tuple[int, float]:
    """(faces with a sample whose normal is more than FLIP_DEG from the truth's normal at the nearest
    truth grid sample, largest such angle in deg); the result's orientation is first turned to
    agree with the truth's on the median sample."""
    if not len(points):
        return 0, 0.0
    d2 = ((points[:, None, :] - truth.grid_xyz[None]) ** 2).sum(-1)
    dots = np.einsum("ij,ij->i", normals, truth.grid_normal[d2.argmin(axis=1)])
    sign = 1.0 if np.median(dots) >= 0 else -1.0
    ang = np.degrees(np.arccos(np.clip(sign * dots, -1.0, 1.0)))
    return len(set(owner[ang > FLIP_DEG].tolist())), float(ang.max())


def truth_deviation(shape, points, truth, diag) -> tuple[float, float]:
    """(RMS, max) distance between result and truth in % of diag: the truth's TRUTH_GRID samples to
    the result's faces, and the result's face samples `points` to the true patch."""
    from ProgSurf.cad.analysis import shape_point_distances

    tpts = truth(truth.sample_grid(TRUTH_GRID))
    d = np.concatenate([shape_point_distances(shape, tpts), truth.distances(points)])
    return 100.0 * float(np.sqrt(np.mean(d ** 2))) / diag, 100.0 * float(d.max()) / diag


def measure_build(sketch, continuity: str, clean: bool = False) -> dict:
    """Build one sketch through build_and_measure in `continuity` and measure it against its truth
    (the module docstring); {"built": False, "error": ...} if the build raised."""
    from ProgSurf.app.build import build_and_measure
    from ProgSurf.core.errors import ProgSurfError
    from ProgSurf.core.types import Tolerances

    t0 = time.perf_counter()
    try:
        out = build_and_measure(sketch.clean if clean else sketch.strokes, None, Tolerances(),
                                continuity=continuity)
    except Exception as exc:    # noqa: BLE001  (any failure is "not built"; the kind is reported)
        kind = "" if isinstance(exc, ProgSurfError) else " (not a ProgSurfError)"
        return {"built": False, "error": f"{type(exc).__name__}{kind}: {exc}"[:300],
                "time_s": time.perf_counter() - t0}
    build_s = time.perf_counter() - t0
    shape, records = out.shape, sorted(out.result.records, key=lambda r: r.index)
    pts, nrm, owner = face_samples(shape)
    seam_in, seams_over = seam_fold(shape)
    flips, normal_max = flipped_faces(pts, nrm, owner, sketch.truth)
    dev_rms, dev_max = truth_deviation(shape, pts, sketch.truth, sketch.diag)
    fit, fit_tol = float(out.analysis.fit_deviation_mm), float(out.result.tol.fit_mm)
    return {"built": True, "faces": len(shape.Faces), "time_s": build_s,
            "rejected": sum(r.status == "rejected" for r in records),
            "roles_ok": [r.role for r in records] == [m["role"] for m in sketch.meta],
            "fit_mm": fit, "fit_tol_mm": fit_tol, "fit_ok": fit <= fit_tol,
            # the report's own contract: every face within the fit tolerance plus its sides' chord sag
            "fit_allowance_ok": not out.analysis.fit_over, "report_ok": not out.analysis.problems,
            "report_seam_deg": float(out.analysis.seam_angle_deg),
            "dev_rms_pct": dev_rms, "dev_max_pct": dev_max,
            "seam_in_deg": seam_in, "seams_over": seams_over, "flip_faces": flips, "normal_max_deg": normal_max,
            "fold": bool(seam_in > FOLD_SEAM_DEG or flips > 0)}


def _child(spec, continuities, clean, result_path) -> None:
    """One sketch in this fresh process: every continuity's measure_build, written to result_path
    as JSON."""
    setup_path()
    from benchmarks.sketches import make_config

    name, config, seed = spec
    sk = make_config(config, seed, name)
    res = {"name": name, "config": config, "seed": seed, "diag_mm": sk.diag, "strokes": len(sk.strokes),
           "boundary": sk.n_boundary}
    for c in continuities:
        res[c] = measure_build(sk, c, clean)
    Path(result_path).write_text(json.dumps(res))


def python() -> str:
    """The Python that builds the sketches: this one, unless it is FreeCAD's own executable
    (freecadcmd runs the tests too), then /usr/bin/python3."""
    return sys.executable if Path(sys.executable).name.startswith("python") else "/usr/bin/python3"


def in_children(jobs_list: list, command, lost, jobs: int = 2, timeout_s: float = 900.0, progress=None) -> list:
    """Run one fresh process per item of jobs_list, `jobs` at a time: command(item, result_path)
    is its argument list (run from the project's root; it writes its result as JSON to
    result_path). A process that fails or outlives timeout_s gives lost(item, why) instead.
    progress(result) is called as each ends. Results in the order of jobs_list."""
    import subprocess
    import tempfile

    env = dict(os.environ)
    env.setdefault("OPENBLAS_NUM_THREADS", "1")   # small matrices: BLAS threads only spin
    pending, running, done = list(range(len(jobs_list))), {}, {}
    with tempfile.TemporaryDirectory(prefix="progsurf-children-") as tmp:
        while pending or running:
            while pending and len(running) < max(1, jobs):
                k = pending.pop(0)
                path = Path(tmp) / f"{k}.json"
                proc = subprocess.Popen(command(jobs_list[k], path), cwd=str(ROOT), env=env, stdin=subprocess.DEVNULL,
                                        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
                running[k] = (proc, path, time.monotonic())
            time.sleep(0.2)
            for k, (proc, path, t0) in list(running.items()):
                if proc.poll() is None and time.monotonic() - t0 <= timeout_s:
                    continue
                if proc.poll() is None:
                    proc.kill()
                    error = f"timed out after {timeout_s:.0f} s"
                else:
                    error = f"the build process exited {proc.returncode}"
                err = proc.communicate()[1] or ""
                if proc.returncode == 0 and path.exists():
                    res = json.loads(path.read_text())
                else:
                    tail = (err.strip().splitlines() or [""])[-1][:200]
                    res = lost(jobs_list[k], f"{error}: {tail}", time.monotonic() - t0)
                del running[k]
                done[k] = res
                if progress:
                    progress(res)
    return [done[k] for k in range(len(jobs_list))]


def run(specs, continuities=CONTINUITIES, jobs: int = 2, clean: bool = False, timeout_s: float = 900.0,
        progress=None) -> list[dict]:
    """Measure every (name, config, seed) of specs, each in its own fresh process (this file run
    with --child), `jobs` at a time; a process that fails or outlives timeout_s counts as not built.
    progress(result) is called as each sketch ends. Results in the order of specs."""
    def command(spec, path):
        return ([python(), str(Path(__file__).resolve()), "--child", spec[0], spec[1], str(spec[2]),
                 "--result", str(path), "--continuity", *continuities] + (["--clean"] if clean else []))

    def lost(spec, why, seconds):
        gone = {"built": False, "error": why, "time_s": seconds}
        return {"name": spec[0], "config": spec[1], "seed": spec[2], **{c: gone for c in continuities}}

    return in_children(list(specs), command, lost, jobs, timeout_s, progress)


def line(res: dict, continuity: str) -> str:
    """One sketch's figures in one continuity, as one line."""
    r = res[continuity]
    head = f"{res['name']:16s} {continuity}"
    if not r["built"]:
        return f"{head} NOT BUILT ({r['time_s']:.1f} s): {r['error']}"
    return (f"{head} {r['time_s']:5.1f} s faces {r['faces']:3d} rej {r['rejected']} roles "
            f"{'ok ' if r['roles_ok'] else 'BAD'} fit {r['fit_mm']:.4f}/{r['fit_tol_mm']:.3g} mm"
            f"{'' if r['fit_ok'] else ' OVER'} dev_rms {r['dev_rms_pct']:5.2f}% dev_max {r['dev_max_pct']:5.2f}% "
            f"seam_in {r['seam_in_deg']:5.1f} (report {r['report_seam_deg']:5.1f}) flip {r['flip_faces']} nmax {r['normal_max_deg']:5.1f}"
            f"{'  FOLD' if r['fold'] else ''}")


def summary(results: list, continuity: str) -> dict:
    """Counts and figures of one continuity over all results: built, folded, within the fit
    tolerance, dev_rms / dev_max median and worst (% diag), rejected strokes, roles wrong."""
    rs = [r[continuity] for r in results]
    built = [r for r in rs if r["built"]]
    stat = lambda key, f: float(f([r[key] for r in built])) if built else float("nan")
    return {"total": len(rs), "built": len(built), "folded": sum(r["fold"] for r in built),
            "fit_ok": sum(r["fit_ok"] for r in built),
            "fit_mm_median": stat("fit_mm", np.median), "fit_mm_worst": stat("fit_mm", np.max),
            "dev_rms_median_pct": stat("dev_rms_pct", np.median), "dev_rms_worst_pct": stat("dev_rms_pct", np.max),
            "dev_max_median_pct": stat("dev_max_pct", np.median), "dev_max_worst_pct": stat("dev_max_pct", np.max),
            "seam_in_median_deg": stat("seam_in_deg", np.median), "seam_in_worst_deg": stat("seam_in_deg", np.max),
            "rejected_strokes": sum(r["rejected"] for r in built), "roles_wrong": sum(not r["roles_ok"] for r in built),
            "time_median_s": stat("time_s", np.median)}


def table(results: list, continuities=CONTINUITIES) -> str:
    """Markdown table of the summaries, one column per continuity (G0 beside G1)."""
    s = {c: summary(results, c) for c in continuities}
    f = lambda x, d=2: "n/a" if x != x else f"{x:.{d}f}"
    rows = [("built", lambda v: f"{v['built']}/{v['total']}"),
            ("folded (seam_in > 60 deg or a flipped face)", lambda v: f"{v['folded']}/{v['total']}"),
            ("within the fit tolerance", lambda v: f"{v['fit_ok']}/{v['built']}"),
            ("fit deviation median / worst mm", lambda v: f"{f(v['fit_mm_median'], 4)} / {f(v['fit_mm_worst'], 3)}"),
            ("dev_rms median / worst % diag", lambda v: f"{f(v['dev_rms_median_pct'])} / {f(v['dev_rms_worst_pct'])}"),
            ("dev_max median / worst % diag", lambda v: f"{f(v['dev_max_median_pct'])} / {f(v['dev_max_worst_pct'])}"),
            ("seam_in median / worst deg", lambda v: f"{f(v['seam_in_median_deg'], 1)} / {f(v['seam_in_worst_deg'], 1)}"),
            ("strokes rejected", lambda v: str(v["rejected_strokes"])),
            ("roles wrong (sketches)", lambda v: str(v["roles_wrong"])),
            ("build time median s", lambda v: f(v["time_median_s"], 1))]
    out = ["| | " + " | ".join(continuities) + " |", "|---|" + "---:|" * len(continuities)]
    out += [f"| {label} | " + " | ".join(fn(s[c]) for c in continuities) + " |" for label, fn in rows]
    return "\n".join(out)


def by_config(results: list, continuity: str) -> str:
    """Markdown table per configuration: built, folded, within fit tolerance, dev_max median."""
    out = [f"| configuration ({continuity}) | built | folded | fit ok | dev_max median % |", "|---|---:|---:|---:|---:|"]
    for cfg in dict.fromkeys(r["config"] for r in results):
        s = summary([r for r in results if r["config"] == cfg], continuity)
        out.append(f"| {cfg} | {s['built']}/{s['total']} | {s['folded']} | {s['fit_ok']} | "
                   f"{s['dev_max_median_pct']:.2f} |")
    return "\n".join(out)


def _names(results: list, test, most: int = 12) -> str:
    """The names of the results that pass test, the first `most` of them."""
    names = [r["name"] for r in results if test(r)]
    more = f" and {len(names) - most} more" if len(names) > most else ""
    return (", ".join(names[:most]) + more) if names else "none"


def section(results: list, continuities=CONTINUITIES) -> str:
    """The markdown of a quality run: the summary (G0 beside G1), per configuration, why builds
    failed (errors with their numbers as N, counted), and the names of the sketches not built,
    folded or over the fit tolerance (the first 12 of each)."""
    import re

    parts = [table(results, continuities)] + [by_config(results, c) for c in continuities]
    for c in continuities:
        rs = [r[c] | {"name": r["name"]} for r in results]
        reasons: dict = {}
        for r in rs:
            if not r["built"]:
                key = re.sub(r"\d+(\.\d+)?", "N", r["error"])[:160]
                reasons[key] = reasons.get(key, 0) + 1
        why = "; ".join(f"{n} x {k}" for k, n in sorted(reasons.items(), key=lambda kv: -kv[1]))
        parts.append(f"{c}: not built: {_names(rs, lambda r: not r['built'])}{' (' + why + ')' if why else ''}. "
                     f"Folded: {_names(rs, lambda r: r['built'] and r['fold'])}. "
                     f"Over the fit tolerance: {_names(rs, lambda r: r['built'] and not r['fit_ok'])}.")
    return "\n\n".join(parts)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="benchmarks/quality.py", description=__doc__.splitlines()[0])
    p.add_argument("--per", type=int, default=12, help="sketches per configuration (default 12: 108 sketches)")
    p.add_argument("--seed-base", type=int, default=0)
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--only", action="append", default=[], help="only this configuration (repeatable)")
    p.add_argument("--clean", action="store_true", help="build the clean strokes (no jitter or drift)")
    p.add_argument("--continuity", nargs="+", default=list(CONTINUITIES), choices=CONTINUITIES)
    p.add_argument("--out", help="write quality.md and quality.json here")
    p.add_argument("--child", nargs=3, metavar=("NAME", "CONFIG", "SEED"), help=argparse.SUPPRESS)
    p.add_argument("--result", help=argparse.SUPPRESS)
    a = p.parse_args(argv)
    if a.child:
        _child((a.child[0], a.child[1], int(a.child[2])), a.continuity, a.clean, a.result)
        return 0
    sys.path.insert(0, str(ROOT))
    from benchmarks.sketches import family_specs

    specs = family_specs(a.per, a.seed_base, a.only)
    t0 = time.perf_counter()
    results = run(specs, a.continuity, a.jobs, a.clean,
                  progress=lambda r: print("\n".join(line(r, c) for c in a.continuity), flush=True))
    md = (f"{len(specs)} sketches ({'clean' if a.clean else 'noisy'}), {time.perf_counter() - t0:.0f} s\n\n"
          + section(results, a.continuity))
    print(md)
    if a.out:
        Path(a.out).mkdir(parents=True, exist_ok=True)
        (Path(a.out) / "quality.md").write_text(md + "\n")
        (Path(a.out) / "quality.json").write_text(json.dumps(
            {"summary": {c: summary(results, c) for c in a.continuity}, "results": results}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
