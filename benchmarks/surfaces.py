"""Closed-form test surfaces and stroke generators for the benchmarks (issue 8).

Every surface is a height field z(x, y) over the square [0, SIDE]^2 mm, so the ground truth of any
point of a result is known exactly. Strokes are sampled from the surface: the boundary is its four
sides, interior strokes are iso-sections (the peer comparison) or random short strokes (the
latency and scale runs).
"""
from __future__ import annotations

from typing import Callable

import numpy as np

from ProgSurf.core.network import PatchNetwork
from ProgSurf.core.progressive import add_stroke
from ProgSurf.core.types import FloatArray, Tolerances

SIDE = 100.0
"""Side of the square domain, mm."""

Height = Callable[[FloatArray, FloatArray], FloatArray]


def saddle(x: FloatArray, y: FloatArray) -> FloatArray:
    """Hyperbolic paraboloid, +-30 mm."""
    return 30.0 * ((x - 50.0) ** 2 - (y - 50.0) ** 2) / 2500.0


def dome(x: FloatArray, y: FloatArray) -> FloatArray:
    """Elliptic paraboloid cap, 0 mm at the corners, 40 mm at the centre."""
    return 40.0 * (1.0 - ((x - 50.0) ** 2 + (y - 50.0) ** 2) / 5000.0)


def wave(x: FloatArray, y: FloatArray) -> FloatArray:
    """One sine period across x times half a cosine period across y, +-10 mm."""
    return 10.0 * np.sin(2.0 * np.pi * x / SIDE) * np.cos(np.pi * y / SIDE)


SURFACES: dict[str, Height] = {"saddle": saddle, "dome": dome, "wave": wave}

BENCH_TOL = Tolerances(filter_mm=0.5, snap_mm=2.0, fit_mm=0.01)
"""Explicit filter, snap (2% of the side, as the pipeline's automatic snap would be) and fit
distances (0.01 mm, the fit tolerance's default before it became relative to the sketch), so that
every run of the benchmark uses the same values."""


def on_surface(z: Height, xy: FloatArray) -> FloatArray:
    """(n, 3) points of the surface above the (n, 2) points xy."""
    xy = np.asarray(xy, dtype=float)
    return np.c_[xy, z(xy[:, 0], xy[:, 1])]


def boundary_strokes(z: Height, n: int = 41) -> list[FloatArray]:
    """The four sides as one closed loop: bottom, right, top (reversed), left (reversed)."""
    t = np.linspace(0.0, SIDE, n)
    c, f = np.zeros(n), np.full(n, SIDE)
    return [on_surface(z, np.c_[t, c]), on_surface(z, np.c_[f, t]),
            on_surface(z, np.c_[t[::-1], f]), on_surface(z, np.c_[c, t[::-1]])]


def section_positions(k: int) -> tuple[FloatArray, FloatArray]:
    """x positions of the x = const sections and y positions of the y = const sections for k
    interior curves: ceil(k/2) and floor(k/2), evenly spaced inside the square."""
    nx, ny = (k + 1) // 2, k // 2
    return (np.linspace(0.0, SIDE, nx + 2)[1:-1], np.linspace(0.0, SIDE, ny + 2)[1:-1])


def section_curves(z: Height, k: int, n: int = 41) -> list[FloatArray]:
    """k interior iso-section curves from side to side (x = const ones first, then y = const)."""
    xs, ys = section_positions(k)
    t = np.linspace(0.0, SIDE, n)
    return ([on_surface(z, np.c_[np.full(n, x), t]) for x in xs]
            + [on_surface(z, np.c_[t, np.full(n, y)]) for y in ys])


def random_stroke(z: Height, rng: np.random.Generator, length: tuple = (0.10, 0.35)) -> FloatArray:
    """A straight (in x, y) stroke of random centre, direction and length (fractions of the side),
    kept 1 mm inside the domain and sampled every ~2 mm on the surface; its ends may stop short of
    every boundary (footpoint ends) or reach one (snapped ends)."""
    centre = rng.uniform(0.08 * SIDE, 0.92 * SIDE, 2)
    angle = rng.uniform(0.0, np.pi)
    span = rng.uniform(*length) * SIDE
    d = np.array([np.cos(angle), np.sin(angle)])
    p = np.clip(centre - 0.5 * span * d, 1.0, SIDE - 1.0)
    q = np.clip(centre + 0.5 * span * d, 1.0, SIDE - 1.0)
    s = np.linspace(0.0, 1.0, max(8, int(span / 2.0)))
    return on_surface(z, p + np.outer(s, q - p))


def base_network(z: Height, n: int = 41) -> PatchNetwork:
    """The base Coons patch of the surface's four sides (one region)."""
    t = np.linspace(0.0, SIDE, n)
    c, f = np.zeros(n), np.full(n, SIDE)
    return PatchNetwork(on_surface(z, np.c_[t, c]), on_surface(z, np.c_[f, t]),
                        on_surface(z, np.c_[t, f]), on_surface(z, np.c_[c, t]))


Keep = Callable[[PatchNetwork, PatchNetwork, object], bool]
"""keep(before, after, record) -> False to drop an accepted growth stroke again."""


def grow_networks(z: Height, targets: list[int], seed: int = 1, tol: Tolerances = BENCH_TOL,
                  max_strokes: int = 2000, keep: Keep | None = None) -> tuple[dict[int, PatchNetwork], dict]:
    """Networks of about each target region count: random strokes are added to one network and a
    clone is kept the first time it has at least `target` regions. An accepted stroke for which
    keep(before, after, record) is False is undone. Returns (target -> network, counts of the
    growth strokes: accepted, rejected by the core, dropped by keep)."""
    rng = np.random.default_rng(seed)
    net = base_network(z)
    out: dict[int, PatchNetwork] = {}
    counts = {"accepted": 0, "rejected": 0, "dropped": 0}
    pending = sorted(targets)
    for i in range(max_strokes):
        while pending and len(net) >= pending[0]:
            out[pending.pop(0)] = net.clone()
        if not pending:
            break
        before = net.clone()
        rec = add_stroke(net, random_stroke(z, rng), i, tol, tol.snap_mm)
        if rec.status != "accepted":
            counts["rejected"] += 1
        elif keep is not None and not keep(before, net, rec):
            net = before
            counts["dropped"] += 1
        else:
            counts["accepted"] += 1
    return out, counts


def random_sketch(seed: int) -> list:
    """A random progressive sketch (tests/app/test_g1.py, tests/core/test_progressive.py,
    examples/g1_trial.py): four boundary strokes on z = height(x, y) over a w x h rectangle, then
    2-3 interior strokes on the same surface running (a little beyond) from one side to the
    opposite one."""
    rng = np.random.default_rng(seed)
    w, h = rng.uniform(60, 160, 2)
    a, b = rng.uniform(-0.25, 0.25, 2)
    height = lambda x, y: a * w * np.sin(np.pi * x / w) * np.sin(np.pi * y / h) + b * x + 0.1 * a * y
    i = np.linspace(0, 1, 25)
    on = lambda x, y: np.c_[x, y, height(x, y)]
    strokes = [on(w * i, 0 * i), on(w + 0 * i, h * i), on(w * i[::-1], h + 0 * i), on(0 * i, h * i[::-1])]
    for k in range(int(rng.integers(2, 4))):
        t = np.linspace(-0.01, 1.01, 30)
        p0, p1 = rng.uniform(0.2, 0.8, 2)
        if k % 2 == 0:
            x, y = w * (p0 + (p1 - p0) * t), h * t
        else:
            x, y = w * t, h * (p0 + (p1 - p0) * t)
        strokes.append(on(x, y))
    return strokes
