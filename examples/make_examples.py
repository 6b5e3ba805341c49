"""Write the bundled example sketches (point-list format) into this folder.

    /usr/bin/python3 examples/make_examples.py [outdir]
    /usr/bin/python3 examples/make_examples.py --plot docs/examples.png   (needs matplotlib)

Deterministic: every random draw comes from a fixed seed, so running it again rewrites the same
bytes.  Each sketch samples closed-form surfaces, so a test can check strokes against the truth.
"""
from __future__ import annotations

import os
import sys
from typing import Callable

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
if ROOT not in sys.path:
    sys.path.insert(0, ROOT)

from ProgSurf.io.pointlist import write_point_list  # noqa: E402

Surface = Callable[[np.ndarray, np.ndarray], np.ndarray]


def saddle(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Gentle saddle over about 100 x 80 mm: z in about -8..10 mm."""
    return 10.0 * ((x - 50.0) / 50.0) ** 2 - 8.0 * ((y - 40.0) / 40.0) ** 2 + 0.05 * x


def dome(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Low dome: 15 mm high at (50, 40)."""
    return 15.0 * (1.0 - ((x - 50.0) / 70.0) ** 2 - ((y - 40.0) / 60.0) ** 2)


def on_surface(xy: np.ndarray, surface: Surface) -> np.ndarray:
    return np.column_stack([xy, surface(xy[:, 0], xy[:, 1])])


def plan_curve(p0, p1, bulge: float, n: int) -> np.ndarray:
    """(n, 2) plan-view curve from p0 to p1 bowed sideways by `bulge` mm at its middle."""
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    t = np.linspace(0.0, 1.0, n)[:, None]
    d = p1 - p0
    normal = np.array([-d[1], d[0]]) / np.linalg.norm(d)
    return p0 + t * d + bulge * np.sin(np.pi * t) * normal


def hand(xyz: np.ndarray, rng: np.random.Generator, wobble: float, jitter: float) -> np.ndarray:
    """Hand-like noise: a slow wobble (two random sine waves per axis) plus small jitter, and
    speed-dependent spacing (points bunch where the hand slows down)."""
    n = xyz.shape[0]
    t = np.linspace(0.0, 1.0, n)[:, None]
    freq = rng.uniform(0.5, 2.0, size=(2, 3))
    phase = rng.uniform(0, 2 * np.pi, size=(2, 3))
    slow = wobble * (np.sin(2 * np.pi * freq[0] * t + phase[0]) + 0.5 * np.sin(2 * np.pi * freq[1] * t + phase[1]))
    out = xyz + slow + rng.normal(0.0, jitter, size=xyz.shape)
    speed = 0.4 + np.sin(np.pi * np.linspace(0.0, 1.0, n)) ** 2  # slow at both ends
    s = np.concatenate([[0.0], np.cumsum(speed[:-1])])
    s = (n - 1) * s / s[-1]
    keep = np.unique(np.round(s).astype(int))
    return out[keep]


def extend(xy: np.ndarray, start: float, end: float) -> np.ndarray:
    """Lengthen (positive) or shorten (negative) a plan curve at its ends by the given mm, along its
    end directions: the overshoots and gaps of a quick sketch."""
    def shift(pts: np.ndarray, amount: float) -> np.ndarray:
        if amount >= 0:
            d = pts[-1] - pts[-3]
            d = d / np.linalg.norm(d)
            steps = np.arange(1, int(np.ceil(amount)) + 1)[:, None] * (amount / np.ceil(amount))
            return np.vstack([pts, pts[-1] + steps * d]) if amount > 0 else pts
        seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
        cum = np.concatenate([[0.0], np.cumsum(seg)])
        return pts[cum <= cum[-1] + amount]
    return shift(shift(xy, end)[::-1], start)[::-1]


QUAD = [(0.0, 0.0), (100.0, 0.0), (102.0, 80.0), (-2.0, 78.0)]
QUAD_BULGE = [-3.0, -4.0, -3.0, -2.5]  # negative = outwards for a counter-clockwise loop


def clean4() -> tuple[list[np.ndarray], list[str]]:
    sides = [plan_curve(QUAD[k], QUAD[(k + 1) % 4], QUAD_BULGE[k], 101) for k in range(4)]
    boundary = [on_surface(xy, saddle) for xy in sides]
    interior = [
        on_surface(plan_curve((35.0, 1.5), (33.0, 77.0), 4.0, 77), saddle),
        on_surface(plan_curve((15.0, 40.0), (85.0, 45.0), -6.0, 71), saddle),
        on_surface(plan_curve((62.0, 12.0), (88.0, 66.0), 3.0, 55), saddle),
    ]
    notes = ["clean 4-sided sketch on the saddle z = 10((x-50)/50)^2 - 8((y-40)/40)^2 + 0.05x, about 104 x 80 mm",
             "boundary strokes first: 4 (bottom, right, top, left, drawn head to tail, meeting exactly)",
             "then 3 interior strokes lying on the surface (the first runs bottom to top, 1.5 mm inside)"]
    return boundary + interior, notes


def rough4() -> tuple[list[np.ndarray], list[str]]:
    rng = np.random.default_rng(20240604)
    over = [(4.0, -3.5), (5.0, 3.0), (-4.0, 6.0), (2.5, -5.0)]  # (start, end) mm: + overshoot, - gap
    boundary = []
    for k in range(4):
        xy = extend(plan_curve(QUAD[k], QUAD[(k + 1) % 4], QUAD_BULGE[k], 120), *over[k])
        boundary.append(hand(on_surface(xy, saddle), rng, wobble=0.6, jitter=0.15))
    order = rng.permutation(4)
    boundary = [boundary[i] if rng.random() < 0.5 else boundary[i][::-1] for i in order]
    interior = [
        hand(on_surface(plan_curve((35.0, 4.0), (33.0, 74.0), 4.0, 90), saddle), rng, 0.4, 0.1),
        hand(on_surface(plan_curve((15.0, 40.0), (85.0, 45.0), -6.0, 90), saddle), rng, 0.4, 0.1),
        hand(on_surface(plan_curve((62.0, 12.0), (88.0, 66.0), 3.0, 70), saddle), rng, 0.4, 0.1),
    ]
    notes = ["rough 4-sided sketch of the same saddle as clean4.xyz, with hand-like noise (wobble 0.6 mm,",
             "jitter 0.15 mm, uneven point spacing), overshoots of 2.5-6 mm and gaps of 3.5-5 mm at corners",
             "boundary strokes first: 4, in random order and direction (seed 20240604)",
             "then 3 noisy interior strokes"]
    return boundary + interior, notes


# Fig. 10 of Qin & Wright 2006: five boundary curves A-E; C and E meet at an open corner; B and C are
# nearly in line, so the merge criterion (closest chord orientation) joins them.  Loop order A B C E D.
PENTA = {"A": [(0.0, 0.0), (100.0, 5.0)], "B": [(100.0, 5.0), (108.0, 40.0)],
         "C": [(108.0, 40.0), (110.0, 82.0)], "E": [(110.0, 82.0), (5.0, 90.0)],
         "D": [(5.0, 90.0), (0.0, 0.0)]}


def fig10_five_sided() -> tuple[list[np.ndarray], list[str]]:
    rng = np.random.default_rng(10)
    bulge = {"A": -4.0, "B": -2.0, "C": -1.5, "E": -5.0, "D": -3.0}
    ends = {"A": (1.0, 1.5), "B": (-0.5, 0.5), "C": (0.5, -5.0), "E": (-6.0, 2.0), "D": (1.5, 1.0)}
    curves = {}
    for name, (p0, p1) in PENTA.items():
        n = max(30, int(np.hypot(*np.subtract(p1, p0))))
        xy = extend(plan_curve(p0, p1, bulge[name], n), *ends[name])
        curves[name] = hand(on_surface(xy, dome), rng, wobble=0.3, jitter=0.1)
    # gently curved in plan, so its pre-image is straight within Tolerances.param, as in the paper
    interior = hand(on_surface(plan_curve((20.0, 30.0), (90.0, 60.0), -3.0, 80), dome), rng, 0.3, 0.1)
    notes = ["the 5-sided boundary with an open corner of Qin & Wright 2006, Fig. 10, on the dome",
             "z = 15(1 - ((x-50)/70)^2 - ((y-40)/60)^2)",
             "boundary strokes first: 5, in file order A B C D E; around the loop they run A B C E D",
             "C and E stop short of each other (open corner, gap about 10 mm); B and C are nearly in line,",
             "so the merge criterion (closest chord orientation, 2006 section 2.1) joins B and C",
             "then 1 interior stroke whose ends do not touch the boundary"]
    return [curves[k] for k in "ABCDE"] + [interior], notes


def three_sided() -> tuple[list[np.ndarray], list[str]]:
    rng = np.random.default_rng(3)
    tri = [(0.0, 0.0), (100.0, 0.0), (45.0, 85.0)]
    bulge = [-4.0, -5.0, -5.0]
    ends = [(1.5, 2.0), (-2.0, 1.0), (2.0, -2.5)]
    boundary = []
    for k in range(3):
        xy = extend(plan_curve(tri[k], tri[(k + 1) % 3], bulge[k], 100), *ends[k])
        boundary.append(hand(on_surface(xy, dome), rng, wobble=0.25, jitter=0.08))
    interior = hand(on_surface(plan_curve((20.0, 12.0), (75.0, 20.0), -10.0, 60), dome), rng, 0.2, 0.08)
    notes = ["3-sided sketch on the dome z = 15(1 - ((x-50)/70)^2 - ((y-40)/60)^2), about 100 x 85 mm",
             "boundary strokes first: 3, with small overshoots and gaps at the corners",
             "then 1 interior stroke; the base surface has a degenerate side at one corner (Fig. 4)"]
    return boundary + [interior], notes


EXAMPLES = {"clean4.xyz": clean4, "rough4.xyz": rough4, "fig10_five_sided.xyz": fig10_five_sided,
            "three_sided.xyz": three_sided}
BOUNDARY_COUNT = {"clean4.xyz": 4, "rough4.xyz": 4, "fig10_five_sided.xyz": 5, "three_sided.xyz": 3}


def write_examples(outdir: str) -> list[str]:
    """Write every example into outdir; returns the paths written."""
    os.makedirs(outdir, exist_ok=True)
    paths = []
    for name, make in EXAMPLES.items():
        strokes, notes = make()
        path = os.path.join(outdir, name)
        write_point_list(path, strokes, comments=[f"{name}: " + notes[0]] + notes[1:] +
                         ["made by examples/make_examples.py (deterministic)"], decimals=4)
        paths.append(path)
    return paths


SIDE_COLOURS = {"bottom": "tab:red", "right": "tab:green", "top": "tab:blue", "left": "tab:orange"}


def plot_examples(png: str, folder: str) -> None:
    """Each bundled example: its raw strokes in plan (top row) and the closed, four-sided boundary
    from `make_boundary` in 3D with the interior strokes (bottom row)."""
    import matplotlib  # lazy: only this optional plot needs it

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ProgSurf.core.boundary import make_boundary
    from ProgSurf.io import read_strokes

    fig = plt.figure(figsize=(18, 9.5))
    for col, name in enumerate(EXAMPLES):
        strokes = read_strokes(os.path.join(folder, name))
        nb = BOUNDARY_COUNT[name]
        loop, interior = make_boundary(strokes)
        ax = fig.add_subplot(2, 4, col + 1)
        for i, s in enumerate(strokes):
            ax.plot(s[:, 0], s[:, 1], "-", lw=1.2, color="0.35" if i < nb else "tab:purple")
            ax.plot(*s[0, :2], "o", ms=3, color="k")
            ax.annotate(str(i) if name != "fig10_five_sided.xyz" or i >= 5 else "ABCDE"[i],
                        s[len(s) // 2, :2], fontsize=9, color="k")
        ax.set_title(f"{name}\nraw strokes (plan; dot = start)", fontsize=10)
        ax.set_aspect("equal")
        ax3 = fig.add_subplot(2, 4, col + 5, projection="3d")
        for (side, colour), src in zip(SIDE_COLOURS.items(), loop.source):
            pts = getattr(loop, side)
            ax3.plot(pts[:, 0], pts[:, 1], pts[:, 2], ".-", ms=2, lw=1.5, color=colour,
                     label=f"{side} {list(src)}")
        for i in interior:
            s = strokes[i]
            ax3.plot(s[:, 0], s[:, 1], s[:, 2], "-", lw=1, color="tab:purple")
        c = loop.corners
        ax3.scatter(c[:, 0], c[:, 1], c[:, 2], color="k", s=18)
        for k, p in enumerate(c):
            ax3.text(p[0], p[1], p[2], f" c{k}", fontsize=8)
        ax3.set_title(f"closed: {len(loop.bottom)} x {len(loop.left)} points" +
                      (" (triangle)" if loop.triangle else ""), fontsize=10)
        ax3.legend(fontsize=7, loc="upper left")
        ax3.view_init(elev=35, azim=-60)
        ax3.set_box_aspect((1, 0.85, 0.3))
    fig.tight_layout()
    fig.savefig(png, dpi=90)


if __name__ == "__main__":
    here = os.path.dirname(os.path.abspath(__file__))
    if len(sys.argv) > 2 and sys.argv[1] == "--plot":
        plot_examples(sys.argv[2], here)
    else:
        for p in write_examples(sys.argv[1] if len(sys.argv) > 1 else here):
            print(p)
