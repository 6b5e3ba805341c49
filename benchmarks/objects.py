"""Hand-like sketches of whole objects with a known truth, and how their builds measure (issue 18).

    /usr/bin/python3 benchmarks/objects.py --per 4 --seed-base 0 --out /tmp/objects   # 16 sketches, ~3 min

A designer who sketches an object draws the curves of all its surfaces at once. This draws, over
four analytic objects, the curve network a designer would draw, each curve one stroke by a hand
(benchmarks.sketches' pen: uneven speed, a low drift and jitter, ends that overshoot or stop short,
closed curves drawn round with an overlap or a gap at their seam, some strokes reversed), at a
size from 100 mm to 1 m (log-uniform per seed):

- box: the 12 edges of a box (sides 1 : 0.5-1 : 0.3-1): 6 surfaces, one closed shell;
- tube: a cylinder's rims and 0-1 rings between them, 3-6 rulings: rulings x (rings - 1)
  surfaces, one open shell;
- body: a body of revolution (an ellipsoid of slenderness 2-4) with 4-6 guides from tip to tip and
  2-4 section rings: guides x (rings + 1) surfaces, one closed shell (3-sided at the tips);
- grid: 3-4 curves each way over a saddle (height 15 % of its width): (n - 1)^2 surfaces, one
  open shell.

Each sketch is built as the command line's `--surfaces all` builds it (app.objects.
build_object_and_measure) in a fresh process and measured: the surfaces and shells against the
expected ones, the surfaces that fold and the creases between surfaces (the report's own checks),
strokes left unused, and the distance between the result and the truth both ways (the truth's
samples to the faces, the faces' samples to the truth: RMS and max, % of the object's diagonal).
The time of each build is printed beside a machine reference measured in the same run
(benchmarks.run.machine_reference_ms), as a ratio.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from benchmarks.sketches import NOISE, drift, pen_fractions  # noqa: E402

KINDS = ("box", "tube", "body", "grid")

Curve = Callable[[np.ndarray], np.ndarray]


@dataclass
class ObjectSketch:
    """One object sketch: strokes (noisy) and clean (the same without drift or jitter), the truth's
    distance function and samples, what a build should make, the diagonal (mm)."""

    name: str
    kind: str
    seed: int
    strokes: list
    clean: list
    distance: Callable[[np.ndarray], np.ndarray]
    truth_points: np.ndarray
    surfaces: int
    closed: bool
    diag: float
    meta: dict = field(default_factory=dict)


def _dense(curve: Curve, closed: bool, n: int = 2001) -> tuple[np.ndarray, np.ndarray]:
    t = np.linspace(0.0, 1.0, n)
    pts = curve(t)
    if closed:
        pts[-1] = pts[0]
    cum = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))]
    return pts, cum


def _along(pts: np.ndarray, cum: np.ndarray, s: np.ndarray, closed: bool) -> np.ndarray:
    """Points at arc lengths s: a closed curve goes round again; an open one runs straight on past
    its ends along its end tangents."""
    L = cum[-1]
    if closed:
        s = np.mod(s, L)
    out = np.stack([np.interp(np.clip(s, 0.0, L), cum, pts[:, k]) for k in range(3)], axis=-1)
    if not closed:
        for end, mask in ((0, s < 0.0), (1, s > L)):
            if mask.any():
                a, b = (pts[0], pts[5]) if end == 0 else (pts[-1], pts[-6])
                tangent = (a - b) / np.linalg.norm(a - b)
                over = np.where(end == 0, -s, s - L)[mask]
                out[mask] = a + over[:, None] * tangent
    return out


def _hand(curve: Curve, closed: bool, mean_len: float, diag: float, rng, noise: dict,
          part: tuple | None = None) -> tuple:
    """One stroke along a curve by a hand: (noisy, clean) points. part: (a, b), shares of the
    curve's length, to draw only that stretch (ends exactly there); None: the whole curve, its ends
    over or short (a closed one round once, with an overlap or a gap at its seam)."""
    pts, cum = _dense(curve, closed)
    L = float(cum[-1])
    corner = noise["corner_max"] * L
    if part is not None:
        s0, s1 = part[0] * L, part[1] * L
    elif closed:
        s0 = rng.uniform(0.0, L)
        s1 = s0 + L + rng.uniform(-corner, corner)          # an overlap or a gap at the seam
    else:
        s0 = -rng.uniform(-corner, corner)
        s1 = L + rng.uniform(-corner, corner)               # overshoot or stop short at each end
    n = int(np.clip(round(noise["npts"] * rng.uniform(0.7, 1.3) * math.sqrt(abs(s1 - s0) / mean_len)), 15, 250))
    f = pen_fractions(n, rng)
    clean = _along(pts, cum, s0 + f * (s1 - s0), closed)
    noisy = clean + drift(f, noise["drift_rel"] * diag, rng) + rng.normal(0.0, noise["sigma_rel"] * diag, clean.shape)
    if rng.random() < noise["reverse_p"]:
        return noisy[::-1], clean[::-1]
    return noisy, clean


ROUGH = {"corner_max": 0.06, "drift_rel": 0.004, "sigma_rel": 0.002, "oversketch_p": 0.25, "split_p": 0.15}
"""--rough: a looser hand, as VR sketches are drawn: ends up to 6 % of a curve over or short, twice
the drift and jitter, a quarter of the curves drawn over again along 30-70 % of their length (a
second stroke), and some open curves drawn as two strokes overlapping by 1-4 % of it each."""


def _strokes_of(curve: Curve, closed: bool, mean_len: float, diag: float, rng, noise: dict) -> list:
    """The strokes a hand draws for one curve: [(noisy, clean)]."""
    out = []
    if not closed and rng.random() < noise.get("split_p", 0.0):
        at = rng.uniform(0.4, 0.6)
        o1, o2 = rng.uniform(0.01, 0.04, 2)
        e0, e1 = rng.uniform(-noise["corner_max"], noise["corner_max"], 2)
        out += [_hand(curve, closed, mean_len, diag, rng, noise, (-e0, at + o1)),
                _hand(curve, closed, mean_len, diag, rng, noise, (at - o2, 1.0 + e1))]
    else:
        out.append(_hand(curve, closed, mean_len, diag, rng, noise))
    if rng.random() < noise.get("oversketch_p", 0.0):
        a = rng.uniform(0.0, 0.6)
        length = rng.uniform(0.3, 0.7)
        if not closed:
            # a redraw of part of an open curve stays on it (drawn from a + length up to 1.3 it ran
            # on past the curve's end along its end tangent: 157 mm off a body's tip, radially)
            a = min(a, 1.0 - length)
        out.append(_hand(curve, closed, mean_len, diag, rng, noise, (a, a + length)))
    return out


def _line(a, b) -> Curve:
    a, b = np.asarray(a, float), np.asarray(b, float)
    return lambda t: a + np.asarray(t)[:, None] * (b - a)


def _box(size: float, rng) -> tuple:
    half = 0.5 * size * np.array([1.0, rng.uniform(0.5, 1.0), rng.uniform(0.3, 1.0)])
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * half
    curves = [(_line(corners[a], corners[b]), False) for a in range(8) for b in range(a + 1, 8)
              if np.sum(corners[a] != corners[b]) == 1]

    def distance(p):
        q = np.abs(p) - half
        outside = np.linalg.norm(np.maximum(q, 0.0), axis=1)
        return np.where(q.max(axis=1) > 0, outside, -q.max(axis=1))

    g = np.linspace(-1.0, 1.0, 9)
    a, b = [x.ravel() for x in np.meshgrid(g, g)]
    samples = []
    for axis in range(3):
        u, v = [k for k in range(3) if k != axis]
        for side in (-1.0, 1.0):
            p = np.zeros((len(a), 3))
            p[:, axis], p[:, u], p[:, v] = side * half[axis], a * half[u], b * half[v]
            samples.append(p)
    return curves, distance, np.vstack(samples), 6, True


def _tube(size: float, rng) -> tuple:
    H, R = size, size * rng.uniform(0.2, 0.4)
    rings = 2 + int(rng.integers(0, 2))
    rulings = int(rng.integers(3, 7))
    phase = rng.uniform(0, 2 * np.pi)
    zs = np.linspace(0.0, H, rings)
    curves = [((lambda t, z=z: np.c_[R * np.cos(2 * np.pi * t), R * np.sin(2 * np.pi * t), np.full_like(t, z)]), True)
              for z in zs]
    for k in range(rulings):
        a = phase + 2 * np.pi * k / rulings
        curves.append((_line([R * np.cos(a), R * np.sin(a), 0.0], [R * np.cos(a), R * np.sin(a), H]), False))

    def distance(p):
        return np.abs(np.hypot(p[:, 0], p[:, 1]) - R)

    th, z = [x.ravel() for x in np.meshgrid(np.linspace(0, 2 * np.pi, 24, endpoint=False), np.linspace(0, H, 9))]
    return curves, distance, np.c_[R * np.cos(th), R * np.sin(th), z], rulings * (rings - 1), False


def _body(size: float, rng) -> tuple:
    L = size
    R = L / (2.0 * rng.uniform(2.0, 4.0))
    guides, rings = int(rng.integers(4, 7)), int(rng.integers(2, 5))
    phase = rng.uniform(0, 2 * np.pi)

    def radius(x):
        return R * np.sqrt(np.clip(1.0 - (2.0 * x / L - 1.0) ** 2, 0.0, None))

    stations = L * np.sort(rng.uniform(0.15, 0.85, rings))
    while rings > 1 and np.min(np.diff(stations)) < 0.12 * L:
        stations = L * np.sort(rng.uniform(0.15, 0.85, rings))
    curves = [((lambda t, x=x: np.c_[np.full_like(t, x), radius(x) * np.cos(2 * np.pi * t),
                                      radius(x) * np.sin(2 * np.pi * t)]), True) for x in stations]
    for k in range(guides):
        a = phase + 2 * np.pi * k / guides
        # from tip to tip, evenly in the angle of the ellipse (dense at the tips, as a hand slows)
        curves.append(((lambda t, a=a: np.c_[0.5 * L * (1.0 - np.cos(np.pi * t)), R * np.sin(np.pi * t) * np.cos(a),
                                             R * np.sin(np.pi * t) * np.sin(a)]), False))
    prof_x = 0.5 * L * (1.0 - np.cos(np.linspace(0.0, np.pi, 721)))
    prof = np.c_[prof_x, radius(prof_x)]

    def distance(p):
        q = np.c_[p[:, 0], np.hypot(p[:, 1], p[:, 2])]
        a, ab = prof[:-1], np.diff(prof, axis=0)
        w = np.clip(np.einsum("kij,ij->ki", q[:, None, :] - a[None], ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
        return np.linalg.norm(a[None] + w[..., None] * ab[None] - q[:, None, :], axis=2).min(axis=1)

    th, u = [x.ravel() for x in np.meshgrid(np.linspace(0, 2 * np.pi, 24, endpoint=False), np.linspace(0.05, 0.95, 11))]
    x = 0.5 * L * (1.0 - np.cos(np.pi * u))
    samples = np.c_[x, radius(x) * np.cos(th), radius(x) * np.sin(th)]
    return curves, distance, samples, guides * (rings + 1), True


def _grid(size: float, rng) -> tuple:
    W, D = size, size * rng.uniform(0.6, 1.0)
    H = 0.15 * size
    n = int(rng.integers(3, 5))

    def z(x, y):
        return H * ((2.0 * x / W - 1.0) ** 2 - (2.0 * y / D - 1.0) ** 2)

    curves = []
    for c in np.linspace(0.0, 1.0, n):
        curves.append(((lambda t, c=c: np.c_[t * W, np.full_like(t, c * D), z(t * W, np.full_like(t, c * D))]), False))
        curves.append(((lambda t, c=c: np.c_[np.full_like(t, c * W), t * D, z(np.full_like(t, c * W), t * D)]), False))

    def distance(p):
        return np.abs(p[:, 2] - z(p[:, 0], p[:, 1])) / np.sqrt(1.0 + (4.0 * H / W) ** 2 + (4.0 * H / D) ** 2)

    x, y = [a.ravel() for a in np.meshgrid(np.linspace(0, W, 11), np.linspace(0, D, 11))]
    return curves, distance, np.c_[x, y, z(x, y)], (n - 1) ** 2, False


MAKERS = {"box": _box, "tube": _tube, "body": _body, "grid": _grid}


def make_object(kind: str, seed: int, noise: dict | None = None, rough: bool = False) -> ObjectSketch:
    """One object sketch of `kind`, deterministic per seed: a size 100 mm - 1 m (log-uniform), a
    random rotation and the curves in random order, each drawn by a hand."""
    rng = np.random.default_rng([int(seed), 18, KINDS.index(kind)])
    nz = dict(NOISE, **(ROUGH if rough else {}), **(noise or {}))
    size = float(np.exp(rng.uniform(np.log(100.0), np.log(1000.0))))
    curves, distance, truth_points, surfaces, closed = MAKERS[kind](size, rng)
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    q *= np.sign(np.linalg.det(q))
    shift = rng.normal(size=3) * size
    dense = [_dense(c, closed_c) for c, closed_c in curves]
    every = np.vstack([pts for pts, _ in dense])
    diag = float(np.linalg.norm(every.max(axis=0) - every.min(axis=0)))
    mean_len = float(np.mean([cum[-1] for _, cum in dense]))
    drawn = [pair for k in range(len(curves)) for pair in _strokes_of(curves[k][0], curves[k][1], mean_len, diag, rng, nz)]
    strokes, clean = [], []
    for k in rng.permutation(len(drawn)):
        strokes.append(drawn[k][0] @ q.T + shift)
        clean.append(drawn[k][1] @ q.T + shift)
    return ObjectSketch(f"{kind}_{seed}{'r' if rough else ''}", kind, int(seed), strokes, clean,
                        lambda p: np.abs(distance((np.asarray(p) - shift) @ q)), truth_points @ q.T + shift,
                        surfaces, closed, diag, {"size_mm": size, "curves": len(curves)})


def measure(sk: ObjectSketch, clean: bool = False) -> dict:
    """Build one object sketch as `--surfaces all` does and measure it (module docstring)."""
    from benchmarks.quality import face_samples
    from ProgSurf.app.objects import build_object_and_measure
    from ProgSurf.cad.analysis import shape_point_distances

    t0 = time.perf_counter()
    try:
        out = build_object_and_measure(sk.clean if clean else sk.strokes)
    except Exception as exc:    # noqa: BLE001  (any failure is "not built"; the kind is reported)
        return {"built": False, "error": f"{type(exc).__name__}: {exc}"[:300], "time_s": time.perf_counter() - t0}
    build_s = time.perf_counter() - t0
    shape = out.model.shape
    pts, _, _ = face_samples(shape)
    d = np.concatenate([shape_point_distances(shape, sk.truth_points), sk.distance(pts)]) if len(pts) else np.array([np.inf])
    shells = list(out.shells)
    return {"built": True, "time_s": build_s, "surfaces": len(out.build.surfaces), "surfaces_expected": sk.surfaces,
            "shells": len(shells), "closed": sum(bool(s["closed"]) for s in shells), "closed_expected": sk.closed,
            "free_edges": sum(int(s["free_edges"]) for s in shells),
            "folding": sum(1 for f in out.folds if f), "creases": len(out.model.folds_across),
            "unused": sum(1 for r in out.build.roles if not r.used), "strokes": len(sk.strokes),
            "dev_rms_pct": 100.0 * float(np.sqrt(np.mean(d ** 2))) / sk.diag,
            "dev_max_pct": 100.0 * float(d.max()) / sk.diag, "size_mm": sk.meta["size_mm"]}


def shape_ok(r: dict) -> bool:
    """The object the sketch shows: its surfaces, one shell, closed where the object is closed."""
    return (r.get("built") and r["surfaces"] == r["surfaces_expected"] and r["shells"] == 1
            and (r["closed"] == 1) == bool(r["closed_expected"]))


def specs(per: int, seed_base: int) -> list:
    return [(kind, seed_base + k) for kind in KINDS for k in range(per)]


def _child(kind: str, seed: int, clean: bool, rough: bool, result: str) -> None:
    sk = make_object(kind, seed, rough=rough)
    Path(result).write_text(json.dumps({"name": sk.name, "kind": kind, "seed": seed, **measure(sk, clean)}))


def run(todo: list, jobs: int = 2, clean: bool = False, rough: bool = False, timeout_s: float = 600.0,
        progress=None) -> list:
    """Each (kind, seed) measured in a fresh process (this file with --child), `jobs` at a time."""
    from benchmarks.quality import in_children, python

    def command(spec, path):
        return ([python(), str(Path(__file__).resolve()), "--child", spec[0], str(spec[1]), "--result", str(path)]
                + (["--clean"] if clean else []) + (["--rough"] if rough else []))

    def lost(spec, why, seconds):
        return {"name": f"{spec[0]}_{spec[1]}", "kind": spec[0], "seed": spec[1], "built": False, "error": why,
                "time_s": seconds}

    return in_children(todo, command, lost, jobs, timeout_s, progress)


def line(r: dict) -> str:
    if not r.get("built"):
        return f"{r['name']:11s} NOT BUILT: {r.get('error', '')}"
    return (f"{r['name']:11s} {r['size_mm']:6.0f} mm  surfaces {r['surfaces']:3d}/{r['surfaces_expected']:<3d} "
            f"shells {r['shells']} closed {r['closed']}{'' if r['closed_expected'] else ' (open object)'}  "
            f"folding {r['folding']:2d} creases {r['creases']}  unused {r['unused']}/{r['strokes']}  "
            f"dev_rms {r['dev_rms_pct']:5.2f}% dev_max {r['dev_max_pct']:5.2f}%  {r['time_s']:5.1f} s"
            f"{'' if shape_ok(r) else '  SHAPE WRONG'}")


def summary(results: list, reference_ms: float) -> str:
    built = [r for r in results if r.get("built")]
    n = len(results)
    if not built:
        return f"SUMMARY objects: built 0/{n}"
    folding = sum(r["folding"] for r in built)
    surfaces = sum(r["surfaces"] for r in built)
    times = np.array([r["time_s"] for r in built])
    return (f"SUMMARY objects: built {len(built)}/{n}, the object's surfaces and shell {sum(map(shape_ok, built))}/{n}, "
            f"sketches with no fold {sum(r['folding'] == 0 and r['creases'] == 0 for r in built)}/{n}, "
            f"folding surfaces {folding}/{surfaces}, creases {sum(r['creases'] for r in built)}, "
            f"strokes unused {sum(r['unused'] for r in built)}/{sum(r['strokes'] for r in built)}, "
            f"dev_rms median {np.median([r['dev_rms_pct'] for r in built]):.2f}% worst "
            f"{max(r['dev_rms_pct'] for r in built):.2f}%, dev_max median {np.median([r['dev_max_pct'] for r in built]):.2f}%; "
            f"build time median {np.median(times):.1f} s = {1000.0 * np.median(times) / reference_ms:.0f} x the "
            f"machine reference ({reference_ms:.1f} ms), worst {times.max():.1f} s")


def main(argv: list | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--per", type=int, default=4, help="sketches per kind of object")
    ap.add_argument("--seed-base", type=int, default=0)
    ap.add_argument("--only", nargs="*", default=(), choices=KINDS)
    ap.add_argument("--clean", action="store_true", help="the strokes without drift or jitter")
    ap.add_argument("--rough", action="store_true", help="a looser hand (ROUGH): ends further over or short, "
                    "more drift and jitter, curves drawn over again or in two strokes")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--out", default=None, help="folder for objects.txt and objects.json")
    ap.add_argument("--child", nargs=2, metavar=("KIND", "SEED"), help=argparse.SUPPRESS)
    ap.add_argument("--result", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        _child(args.child[0], int(args.child[1]), args.clean, args.rough, args.result)
        return 0
    from benchmarks.run import machine_reference_ms

    todo = [s for s in specs(args.per, args.seed_base) if not args.only or s[0] in args.only]
    reference = machine_reference_ms()
    results = run(todo, jobs=args.jobs, clean=args.clean, rough=args.rough, progress=lambda r: print(line(r), flush=True))
    reference = 0.5 * (reference + machine_reference_ms())
    text = summary(results, reference) + (f" (--seed-base {args.seed_base}{', clean' if args.clean else ''}"
                                          f"{', rough' if args.rough else ''})")
    print(text)
    if args.out:
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        (out / "objects.txt").write_text("\n".join(line(r) for r in results) + "\n" + text + "\n")
        (out / "objects.json").write_text(json.dumps(results, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
