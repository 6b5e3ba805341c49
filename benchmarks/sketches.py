"""Hand-like sketches with a known answer: ProgSurf's own sketch generator (issue 16), numpy only.

A designer draws the patch boundary, one stroke per side (sometimes one side in two strokes), then
3-8 interior strokes. :func:`make_sketch` imitates that over an analytic surface given as
(u, v) -> xyz on the unit square and a convex region polygon in it, so that a build can be measured
against the truth (benchmarks/quality.py). Deterministic per (configuration, seed).

What is drawn (fractions of a side's or a stroke's 3D length L; diag = the boundary's bounding-box
diagonal):

- boundary: the region's sides whose 3D length is not ~0 (a collapsed side makes a 3-sided patch),
  as one loop from a random side; each stroke drawn reversed with probability 0.3; each end runs
  straight on past its corner (overshoot) or stops short of it by U(0, 3%) of the side. Optionally
  one corner open (both ends 5% short) or one side drawn as two strokes overlapping by 1-4% each
  about a split point at 40-60% of it.
- interior: n = 3..8 strokes; ceil(n/2) iso curves crossing the boundary (their ends run 2-6% of L
  past it), the rest iso or diagonal curves stopping 6-15% of their span inside (and at least
  max(4% of the mean side, 8 (jitter + drift)) from the boundary); an end on a collapsed side is
  treated like a corner (U(0, 3%) over or short); exactly one stroke lifted off the surface along
  its normal by 1.5% of diag.
- pen: round(60 U(0.7, 1.3) sqrt(L / mean side)) points in [15, 250], at equal time steps of a pen
  whose speed blends a minimum-jerk bell (slow at both ends) with a constant, wobbling at 1-3
  cycles per stroke; a low-frequency drift of RMS 0.2% diag (three half-sine modes) and gaussian
  jitter of 0.1% diag per coordinate. The clean variant has the same points without drift/jitter.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

NOISE = {"npts": 60, "sigma_rel": 0.001, "drift_rel": 0.002, "corner_max": 0.03, "lift_rel": 0.015,
         "cross": (0.02, 0.06), "short": (0.06, 0.15), "split": (0.01, 0.04), "open_gap": 0.05,
         "reverse_p": 0.3}
"""The stroke plan's and the pen's figures (see the module docstring)."""

Surface = Callable[[np.ndarray, np.ndarray], np.ndarray]


# -- analytic surfaces: (u, v) in the unit square -> (..., 3) mm ---------------------------------

def saddle(W=1000.0, D=800.0, H=150.0) -> Surface:
    """Hyperbolic paraboloid over a W x D rectangle, +-H at the side midpoints, 0 at the corners."""
    return lambda u, v: np.stack([(u - .5) * W, (v - .5) * D, H * ((2 * u - 1) ** 2 - (2 * v - 1) ** 2)], -1)


def sphere_cap(W=800.0, D=800.0, R=700.0) -> Surface:
    """Spherical cap of radius R over a W x D rectangle, 0 at the corners."""
    z0 = math.sqrt(R * R - (W / 2) ** 2 - (D / 2) ** 2)

    def f(u, v):
        x, y = (u - .5) * W, (v - .5) * D
        return np.stack([x, y, np.sqrt(np.maximum(R * R - x * x - y * y, 0.0)) - z0], -1)
    return f


def section_bump(W=100.0, D=60.0, H=12.0, y1=20.0) -> Surface:
    """A bump over a flat W x D rectangle: z = H sin^2(pi x/W) sin(pi y/D) / sin(pi y1/D)."""
    k = H / math.sin(math.pi * y1 / D)
    return lambda u, v: np.stack([u * W, v * D, k * np.sin(np.pi * u) ** 2 * np.sin(np.pi * v)], -1)


def cylinder_bump(W=700.0, D=600.0, R=500.0, B=60.0) -> Surface:
    """Cylinder panel of radius R (axis along y) over W x D, plus a bump B sin(pi u) sin(pi v)."""
    z0 = math.sqrt(R * R - (W / 2) ** 2)

    def f(u, v):
        x = (u - .5) * W
        return np.stack([x, v * D, np.sqrt(np.maximum(R * R - x * x, 0.0)) - z0
                         + B * np.sin(np.pi * u) * np.sin(np.pi * v)], -1)
    return f


def ellipsoid_octant(A=500.0, B=400.0, C=300.0) -> Surface:
    """Octant of the ellipsoid with semi-axes A, B, C; the side u = 0 collapses to the pole."""
    def f(u, v):
        t, p = u * np.pi / 2, v * np.pi / 2
        return np.stack([A * np.sin(t) * np.cos(p), B * np.sin(t) * np.sin(p), C * np.cos(t)], -1)
    return f


SQUARE = ((0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0))


class Region:
    """A convex polygon in the unit square, counter-clockwise (the patch is the surface over it)."""

    def __init__(self, verts=SQUARE):
        self.verts = np.array(verts, dtype=float)
        self.n = len(self.verts)
        e = np.roll(self.verts, -1, axis=0) - self.verts
        self.inward = np.c_[-e[:, 1], e[:, 0]] / np.linalg.norm(e, axis=1)[:, None]

    def side(self, i: int) -> tuple[np.ndarray, np.ndarray]:
        """(start, end) uv of side i (from vertex i to vertex i + 1)."""
        return self.verts[i], self.verts[(i + 1) % self.n]

    def inside(self, uv, eps: float = 1e-9) -> np.ndarray:
        """(m,) True for the uv points (m, 2) inside or on the polygon."""
        uv = np.atleast_2d(uv)
        return np.all(np.einsum("mkd,kd->mk", uv[:, None, :] - self.verts[None], self.inward) >= -eps, axis=1)

    def clip(self, a, d) -> tuple[float, float]:
        """Parameter interval (t0, t1) of the line a + t d inside the polygon."""
        t0, t1 = -np.inf, np.inf
        for p, nrm in zip(self.verts, self.inward):
            num, den = nrm @ (np.asarray(a) - p), nrm @ np.asarray(d)
            if abs(den) > 1e-15:
                t0, t1 = (max(t0, -num / den), t1) if den > 0 else (t0, min(t1, -num / den))
        return t0, t1

    def nearest(self, uv) -> np.ndarray:
        """The uv points (m, 2) moved to the nearest point of the polygon (unchanged inside)."""
        uv = np.array(np.atleast_2d(uv), dtype=float)
        out = ~self.inside(uv, 0.0)
        if out.any():
            best, q = np.full(out.sum(), np.inf), uv[out].copy()
            for i in range(self.n):
                a, b = self.side(i)
                t = np.clip((uv[out] - a) @ (b - a) / ((b - a) @ (b - a)), 0.0, 1.0)
                c = a + t[:, None] * (b - a)
                dist = np.linalg.norm(uv[out] - c, axis=1)
                closer = dist < best
                q[closer], best[closer] = c[closer], dist[closer]
            uv[out] = q
        return uv


def unit_normals(fn: Surface, uv, h: float = 1e-5) -> np.ndarray:
    """(m, 3) unit normals S_u x S_v / |.| by central differences; at a collapsed point (the
    octant's pole) the normal 1e-3 .. 5e-2 further into the square."""
    uv = np.atleast_2d(np.asarray(uv, dtype=float))
    out = np.zeros((len(uv), 3))
    todo = np.arange(len(uv))
    for shrink in (0.0, 1e-3, 1e-2, 5e-2):
        q = np.clip(uv[todo], shrink + h, 1.0 - shrink - h)
        su = (fn(q[:, 0] + h, q[:, 1]) - fn(q[:, 0] - h, q[:, 1])) / (2 * h)
        sv = (fn(q[:, 0], q[:, 1] + h) - fn(q[:, 0], q[:, 1] - h)) / (2 * h)
        n = np.cross(su, sv)
        ln = np.linalg.norm(n, axis=1)
        ok = ln > 1e-9 * np.linalg.norm(su, axis=1) * np.linalg.norm(sv, axis=1) + 1e-300
        out[todo[ok]] = n[ok] / ln[ok, None]
        todo = todo[~ok]
        if not len(todo):
            break
    return out


@dataclass
class Truth:
    """The true patch: fn over the region; grid_uv (m, 2), grid_xyz (m, 3), grid_normal (m, 3) are
    the samples of a grid_n x grid_n (u, v) grid that lie inside the region."""

    fn: Surface
    region: Region
    grid_n: int = 41
    grid_uv: np.ndarray = field(init=False)
    grid_xyz: np.ndarray = field(init=False)
    grid_normal: np.ndarray = field(init=False)

    def __post_init__(self):
        self.grid_uv = self.sample_grid(self.grid_n)
        self.grid_xyz = self(self.grid_uv)
        self.grid_normal = unit_normals(self.fn, self.grid_uv)

    def sample_grid(self, n: int) -> np.ndarray:
        """(k, 2) the (u, v) of an n x n grid of the unit square that lie inside the region."""
        g = np.linspace(0.0, 1.0, n)
        uv = np.stack(np.meshgrid(g, g, indexing="ij"), -1).reshape(-1, 2)
        return uv[self.region.inside(uv)]

    def __call__(self, uv) -> np.ndarray:
        """Points (..., 3) of the surface at uv (..., 2)."""
        uv = np.asarray(uv, dtype=float)
        return self.fn(uv[..., 0], uv[..., 1])

    def normals(self, uv) -> np.ndarray:
        """Unit normals (m, 3) at uv (m, 2) (unit_normals)."""
        return unit_normals(self.fn, uv)

    def distances(self, points, steps: int = 12) -> np.ndarray:
        """(m,) distance of each point to the true patch (the surface over the region): nearest
        sample of an 81 x 81 grid, then damped Gauss-Newton in (u, v) kept in the region."""
        pts = np.asarray(points, dtype=float).reshape(-1, 3)
        uv0 = self.sample_grid(81)
        xyz0 = self(uv0)
        best = np.empty(len(pts))
        uv = np.empty((len(pts), 2))
        g2 = np.einsum("ij,ij->i", xyz0, xyz0)
        for lo in range(0, len(pts), 500):
            k = (g2[None, :] - 2.0 * pts[lo:lo + 500] @ xyz0.T).argmin(axis=1)
            uv[lo:lo + 500] = uv0[k]
            best[lo:lo + 500] = np.linalg.norm(pts[lo:lo + 500] - xyz0[k], axis=1)
        h = 1e-6
        for _ in range(steps):
            s = self(uv)
            su = (self(uv + [h, 0.0]) - self(uv - [h, 0.0])) / (2 * h)
            sv = (self(uv + [0.0, h]) - self(uv - [0.0, h])) / (2 * h)
            j = np.stack([su, sv], -1)                                   # (m, 3, 2)
            jtj = np.einsum("mki,mkj->mij", j, j)
            lam = 1e-9 * np.trace(jtj, axis1=1, axis2=2)[:, None, None] + 1e-12
            step = np.linalg.solve(jtj + lam * np.eye(2), np.einsum("mki,mk->mi", j, pts - s)[..., None])[..., 0]
            uv = self.region.nearest(np.clip(uv + step, 0.0, 1.0))
        return np.minimum(best, np.linalg.norm(pts - self(uv), axis=1))


class Path:
    """The surface along the straight uv segment a -> b, by arc length; beyond its ends it runs
    straight on along its end tangents (a hand that keeps going past a corner)."""

    def __init__(self, truth: Truth, a, b, m: int = 401):
        self.a, self.b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
        self.uv = self.a + np.linspace(0.0, 1.0, m)[:, None] * (self.b - self.a)
        self.xyz = truth(self.uv)
        self.s = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(self.xyz, axis=0), axis=1))]
        self.L = float(self.s[-1])
        unit = lambda v: v / max(np.linalg.norm(v), 1e-300)
        self.t0, self.t1 = unit(self.xyz[0] - self.xyz[4]), unit(self.xyz[-1] - self.xyz[-5])
        self.normal = truth.normals(self.uv[::10])
        self._truth = truth

    def at(self, s) -> np.ndarray:
        """(k, 3) points at arc lengths s (k,): on the surface (at the uv that the dense samples'
        arc lengths interpolate), straight on past either end."""
        s = np.asarray(s, dtype=float)
        out = self._truth(np.stack([np.interp(s, self.s, self.uv[:, d]) for d in range(2)], -1))
        out[s < 0] = self.xyz[0] + (-s[s < 0])[:, None] * self.t0
        out[s > self.L] = self.xyz[-1] + (s[s > self.L] - self.L)[:, None] * self.t1
        return out

    def normal_at(self, s) -> np.ndarray:
        """(k, 3) unit surface normals at arc lengths s (clamped to the path)."""
        s = np.clip(np.asarray(s, dtype=float), 0.0, self.L)
        n = np.stack([np.interp(s, self.s[::10], self.normal[:, d]) for d in range(3)], -1)
        return n / np.linalg.norm(n, axis=1, keepdims=True)


def pen_fractions(n: int, rng) -> np.ndarray:
    """Arc-length fractions (n,) at equal time steps of a hand: speed = a constant blended with a
    minimum-jerk bell 30 t^2 (1-t)^2 (slow at both ends), wobbling 1-3 times per stroke."""
    t = np.linspace(0.0, 1.0, 1001)
    w = rng.uniform(0.3, 0.8)
    speed = (1.0 - w + w * 30.0 * t ** 2 * (1.0 - t) ** 2) * (
        1.0 + rng.uniform(0.0, 0.4) * np.sin(2 * np.pi * rng.integers(1, 4) * t + rng.uniform(0, 2 * np.pi)))
    dist = np.r_[0.0, np.cumsum(0.5 * (speed[1:] + speed[:-1]))]
    return np.interp(np.linspace(0.0, 1.0, n), t, dist / dist[-1])


def drift(f: np.ndarray, rms: float, rng) -> np.ndarray:
    """(n, 3) smooth deviation along a stroke (fractions f): three half-sine modes with random 3D
    amplitudes (1 : 1/2 : 1/4), whose expected RMS length is `rms`."""
    w = np.array([1.0, 0.5, 0.25]) / math.sqrt(np.sum(np.array([1.0, 0.5, 0.25]) ** 2) / 2.0)
    out = np.zeros((len(f), 3))
    for k, wk in enumerate(w, start=1):
        out += rng.normal(0.0, rms * wk / math.sqrt(3.0), 3) * np.sin(
            np.pi * k * f[:, None] + rng.uniform(0, 2 * np.pi, 3))
    return out


@dataclass
class Sketch:
    """One sketch: strokes (noisy, boundary first) and clean (the same without drift or jitter),
    meta per stroke (role, kind, ends, reversed, lift_mm, ...), the truth, diag (mm)."""

    name: str
    config: str
    seed: int
    strokes: list
    clean: list
    meta: list
    truth: Truth
    diag: float
    n_boundary: int
    sides: int


class _Drawer:
    """Draws the strokes of one sketch (see the module docstring)."""

    def __init__(self, truth: Truth, rng, noise: dict):
        self.truth, self.rng, self.nz = truth, rng, noise
        reg = truth.region
        self.paths = [Path(truth, *reg.side(i)) for i in range(reg.n)]
        allp = np.vstack([p.xyz for p in self.paths])
        self.diag = float(np.linalg.norm(allp.max(0) - allp.min(0)))
        self.live = [i for i, p in enumerate(self.paths) if p.L > 1e-6 * self.diag]
        self.mean_side = float(np.mean([self.paths[i].L for i in self.live]))
        self.sigma, self.drift = noise["sigma_rel"] * self.diag, noise["drift_rel"] * self.diag
        self.min_gap = max(0.04 * self.mean_side, 8.0 * (self.sigma + self.drift))
        self.outline = np.vstack([self.paths[i].xyz for i in self.live])
        self.strokes, self.clean, self.meta = [], [], []

    def draw(self, path: Path, sa: float, sb: float, role: str, kind: str, ends: tuple, lift: float = 0.0):
        """Add one stroke along path from arc length sa to sb (may lie outside [0, L])."""
        rng, nz = self.rng, self.nz
        n = int(np.clip(round(nz["npts"] * rng.uniform(0.7, 1.3) * math.sqrt(abs(sb - sa) / self.mean_side)), 15, 250))
        f = pen_fractions(n, rng)
        s = sa + f * (sb - sa)
        clean = path.at(s) + (lift * path.normal_at(s) if lift else 0.0)
        noisy = clean + drift(f, self.drift, rng) + rng.normal(0.0, self.sigma, clean.shape)
        rev = bool(rng.random() < nz["reverse_p"])
        self.strokes.append(noisy[::-1] if rev else noisy)
        self.clean.append(clean[::-1] if rev else clean)
        self.meta.append({"role": role, "kind": kind, "uv": [path.a.tolist(), path.b.tolist()], "s": [sa, sb],
                          "L": path.L, "ends": list(ends[::-1] if rev else ends), "reversed": rev,
                          "lift_mm": lift, "n": n})

    def _corner(self, L: float, open_gap: bool) -> tuple[float, str]:
        """(mm past the corner, what): overshoot or stop short by U(0, corner_max) L, or open."""
        if open_gap:
            return -self.nz["open_gap"] * L, "open"
        e = self.rng.uniform(0.0, self.nz["corner_max"]) * L
        return (e, "over") if self.rng.random() < 0.5 else (-e, "short")

    def boundary(self, open_corner: int | None = None, split: bool = False):
        """The boundary loop from a random side; open_corner: a region vertex index left open;
        split: one random side drawn as two overlapping strokes."""
        k = int(self.rng.integers(len(self.live)))
        order = self.live[k:] + self.live[:k]
        split_side = order[int(self.rng.integers(len(order)))] if split else None
        n = self.truth.region.n
        for i in order:
            p = self.paths[i]
            e0, w0 = self._corner(p.L, open_corner == i)
            e1, w1 = self._corner(p.L, open_corner == (i + 1) % n)
            if i != split_side:
                self.draw(p, -e0, p.L + e1, "boundary", "side", ((w0, e0), (w1, e1)))
                continue
            at = self.rng.uniform(0.4, 0.6) * p.L
            o1, o2 = (self.rng.uniform(*self.nz["split"]) * p.L for _ in range(2))
            self.draw(p, -e0, at + o1, "boundary", "side_part", ((w0, e0), ("split", o1)))
            self.draw(p, at - o2, p.L + e1, "boundary", "side_part", (("split", o2), (w1, e1)))

    def _gap(self, q) -> float:
        return float(np.min(np.linalg.norm(self.outline - q, axis=1)))

    def interior(self, kind: str, a, b, lift: bool):
        """One interior stroke along the uv line through a, b: kind 'cross' (clipped to the region,
        ends run past the boundary), 'short' (clipped, 6-15% of the span in from both ends) or
        'diag' (from a to b, both inside)."""
        rng, nz, reg = self.rng, self.nz, self.truth.region
        a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
        if kind != "diag":
            t0, t1 = reg.clip(a, b - a)
            a, b = a + t0 * (b - a), a + t1 * (b - a)
        if kind != "cross":
            if kind == "short":
                f0, f1 = rng.uniform(*nz["short"], 2)
                a, b = a + f0 * (b - a), b - f1 * (b - a)
            for _ in range(60):                      # clearly off the boundary
                g0, g1 = self._gap(self.truth(a)), self._gap(self.truth(b))
                if min(g0, g1) >= self.min_gap:
                    break
                d = b - a
                a, b = (a + 0.01 * d if g0 < self.min_gap else a), (b - 0.01 * d if g1 < self.min_gap else b)
        p = Path(self.truth, a, b)
        ends = []
        for q in (a, b):
            on_collapsed = any(np.linalg.norm(self.truth(q) - self.paths[i].xyz[0]) < 1e-6 * self.diag
                               and i not in self.live for i in range(reg.n))
            if kind != "cross":
                ends.append(("inside", 0.0))
            elif on_collapsed:
                e, what = self._corner(p.L, False)
                ends.append((what, e))
            else:
                e = rng.uniform(*nz["cross"]) * p.L
                ends.append(("cross", e))
        lift_mm = nz["lift_rel"] * self.diag if lift else 0.0
        self.draw(p, -ends[0][1], p.L + ends[1][1], "interior", kind, tuple(ends), lift=lift_mm)

    def plan(self, n: int):
        """n interior strokes: ceil(n/2) crossing iso curves, the rest short iso or diagonal ones
        (at most one diagonal each way), in random order, one of them lifted."""
        rng = self.rng
        kinds = ["cross"] * ((n + 1) // 2)
        diags = [0, 1] if rng.random() < 0.5 else [1, 0]
        for _ in range(n - len(kinds)):
            kinds.append(f"diag{diags.pop(0)}" if diags and rng.random() < 0.5 else "short")
        rng.shuffle(kinds)
        lifted = int(rng.integers(n))
        used = {0: [], 1: []}
        pole_u0 = 3 not in self.live and self.truth.region.n == 4
        for j, kind in enumerate(kinds):
            if kind.startswith("diag"):
                for _ in range(200):
                    lo, hi = rng.uniform(0.1, 0.2, 2), rng.uniform(0.8, 0.9, 2)
                    a, b = (lo, hi) if kind == "diag0" else ((lo[0], hi[1]), (hi[0], lo[1]))
                    if self.truth.region.inside(np.array([a, b])).all():
                        break
                self.interior("diag", a, b, j == lifted)
                continue
            for _ in range(200):
                axis = int(rng.integers(2))                     # 0: u = c, 1: v = c
                c = rng.uniform(0.3 if (axis == 0 and pole_u0) else 0.2, 0.8)
                if all(abs(c - w) > 0.12 for w in used[axis]):
                    break
            used[axis].append(c)
            a, b = ((c, 0.0), (c, 1.0)) if axis == 0 else ((0.0, c), (1.0, c))
            self.interior(kind, a, b, j == lifted)


def make_sketch(fn: Surface, region: Region | None = None, seed: int = 0, name: str = "sketch",
                config: str = "", open_corner: int | None = None, split: bool = False,
                n_interior: int | None = None, noise: dict | None = None) -> Sketch:
    """Draw one sketch over the surface fn on region (default the unit square): the boundary loop,
    then n_interior (default random 3..8) interior strokes; deterministic per seed."""
    rng = np.random.default_rng([int(seed), 16])
    truth = Truth(fn, region or Region())
    d = _Drawer(truth, rng, dict(NOISE, **(noise or {})))
    d.boundary(open_corner=open_corner, split=split)
    nb = len(d.strokes)
    d.plan(int(n_interior or rng.integers(3, 9)))
    return Sketch(name=name, config=config, seed=int(seed), strokes=d.strokes, clean=d.clean, meta=d.meta,
                  truth=truth, diag=d.diag, n_boundary=nb, sides=len(d.live))


def _penta(rng) -> dict:
    """The pentagon: the unit square with corner (1, 1) chamfered at a random place, and one random
    corner of it left open."""
    a, b = rng.uniform(0.65, 0.8), rng.uniform(0.7, 0.85)
    return {"region": Region([(0, 0), (1, 0), (1, a), (b, 1), (0, 1)]), "open_corner": int(rng.integers(5))}


CONFIGS = {
    "saddle": (saddle, {}, None, "saddle 1000 x 800 x 150 mm, square"),
    "saddle_small": (saddle, {"W": 100.0, "D": 80.0, "H": 15.0}, None, "the saddle at 1/10 scale"),
    "dome": (sphere_cap, {}, None, "spherical cap R = 700 over 800 x 800 mm"),
    "dome_flat": (sphere_cap, {"R": 1200.0}, None, "spherical cap R = 1200 over 800 x 800 mm"),
    "section_bump": (section_bump, {}, None, "bump over a flat 100 x 60 mm boundary"),
    "cyl_bump": (cylinder_bump, {}, None, "cylinder panel R = 500, 700 x 600 mm, 60 mm bump"),
    "cyl_penta": (cylinder_bump, {}, _penta, "the cylinder panel over a pentagon, one corner open"),
    "cyl_split": (cylinder_bump, {}, lambda rng: {"split": True}, "the cylinder panel, one side in two strokes"),
    "octant": (ellipsoid_octant, {}, None, "ellipsoid octant 500/400/300 mm, 3-sided"),
}
"""name -> (surface maker, its parameters, configuration choices maker(rng) -> kwargs or None, note)."""


def family_specs(per: int = 12, seed_base: int = 0, only=()) -> list[tuple[str, str, int]]:
    """(name, configuration, seed) of every sketch of the family: per sketches of each configuration."""
    return [(f"{c}_{k}", c, seed_base + 1000 * ci + k) for ci, c in enumerate(CONFIGS)
            if not only or c in only for k in range(per)]


def make_config(config: str, seed: int, name: str | None = None) -> Sketch:
    """The sketch of one configuration (CONFIGS) and seed."""
    maker, params, choose, _ = CONFIGS[config]
    kwargs = choose(np.random.default_rng([int(seed), 7])) if choose else {}
    return make_sketch(maker(**params), seed=seed, name=name or f"{config}@{seed}", config=config, **kwargs)


def family(per: int = 12, seed_base: int = 0, only=()) -> list[Sketch]:
    """The family: len(CONFIGS) configurations x per sketches, 100 mm to 1 m across."""
    return [make_config(c, s, n) for n, c, s in family_specs(per, seed_base, only)]


def notched_plate(scale: float = 100.0, samples: int = 30, warp: float = 1e-3) -> list[np.ndarray]:
    """A sketch with a known answer whose Coons patch turns over: a 3 x 2 plate with a 1 x 1 notch
    in its far side (units of `scale` mm), drawn as five strokes, one per side of the U (the notch's
    three edges are one stroke), each edge `samples` points, on the gentle z = warp x y (mm). Every
    choice of four corners gives a patch that turns over at the notch (168 deg); its face is
    refilled over the loop's plane (core.plane_fill). Used by the core, document and GUI tests."""
    runs = ([(0, 0), (3, 0)], [(3, 0), (3, 2)], [(3, 2), (2, 2), (2, 1), (1, 1), (1, 2)], [(1, 2), (0, 2)],
            [(0, 2), (0, 0)])
    strokes = []
    for run in runs:
        pts = np.vstack([np.linspace([*a, 0.0], [*b, 0.0], samples)[:-1] for a, b in zip(run[:-1], run[1:])]
                        + [np.array([[*run[-1], 0.0]])]) * scale
        pts[:, 2] = warp * pts[:, 0] * pts[:, 1]
        strokes.append(pts)
    return strokes
