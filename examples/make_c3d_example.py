"""Write examples/sketch_mocap.c3d: a motion-capture sketch of a gentle surface, as Qin & Wright record it.

One marker ("PEN") at 100 Hz, units metres, float storage. The designer draws a 4-sided boundary
(bottom, right, top, left; about 100 x 80 mm) and then 2 interior strokes over the surface

    z(x, y) = 8 sin(pi x / 100) sin(pi y / 80) + 0.05 x      (mm)

covering the marker between strokes (pen-up). Hand speed varies along each stroke while the
capture rate is fixed, so point density varies (the paper's reason for the distance filter), and
every sample carries seeded tracker jitter. Pen-up gaps are written three ways real systems do:
residual -1, zero-filled samples, and NaN samples. One 0.05 s flicker of the covered marker is
included; the reader drops it (min_duration_s).

Run:  .venv/bin/python examples/make_c3d_example.py     (needs the `c3d` package)
The output is deterministic; tests/core/test_c3d.py checks that the bundled file matches it.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests" / "core"))
from c3d_fixtures import write_c3d  # noqa: E402  (shared with the tests: one writer helper)

OUTPUT = ROOT / "examples" / "sketch_mocap.c3d"
RATE_HZ = 100.0
# Optical tracker noise (1 sigma). With 0.25 mm the closing step of the pipeline, as of writing,
# sees the jittery ends at corner (0, 0) cross unless the strokes are read with smooth=5.
JITTER_MM = 0.1
SEED = 20240607

# (start xy, end xy, duration s): the rough boundary with small overshoots/gaps at the corners,
# then two interior strokes ending a few mm inside the boundary.
STROKES_XY = [
    ((-1.5, 0.8), (101.0, -0.6), 1.8),    # bottom
    ((100.6, -1.2), (99.2, 81.3), 1.5),   # right
    ((101.2, 79.4), (-0.8, 80.9), 1.9),   # top
    ((0.7, 81.5), (-0.9, -1.3), 1.4),     # left
    ((3.0, 38.0), (97.0, 43.0), 1.6),     # interior, across x
    ((52.0, 3.0), (47.0, 77.0), 1.3),     # interior, across y
]
GAPS_S = [0.3, 0.4, 0.35, 0.5, 0.45, 0.4, 0.3]  # covered before, between and after the strokes


def surface_z(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The closed-form surface the strokes are drawn over (mm)."""
    return 8.0 * np.sin(np.pi * x / 100.0) * np.sin(np.pi * y / 80.0) + 0.05 * x


def _stroke(start, end, duration_s: float, bow: float, rng: np.random.Generator) -> np.ndarray:
    """A hand stroke: slightly bowed in the plan, varying speed, on the surface, with jitter."""
    n = int(round(duration_s * RATE_HZ))
    tau = np.linspace(0.0, 1.0, n)
    s = tau - 0.8 * np.sin(2.0 * np.pi * tau) / (2.0 * np.pi)  # speed varies 0.2x..1.8x
    a, b = np.asarray(start, float), np.asarray(end, float)
    d = b - a
    normal = np.array([-d[1], d[0]]) / np.linalg.norm(d)
    xy = a + s[:, None] * d + (bow * np.sin(np.pi * s))[:, None] * normal
    xyz = np.column_stack([xy, surface_z(xy[:, 0], xy[:, 1])])
    return xyz + rng.normal(0.0, JITTER_MM, xyz.shape)


def make_example(path: Path = OUTPUT) -> Path:
    """Write the example C3D file to `path` and return it."""
    rng = np.random.default_rng(SEED)
    samples: list[np.ndarray] = []
    valid: list[np.ndarray] = []
    hidden = np.array([[40.0, 30.0, 60.0]]) / 1000.0  # where the covered hand is: unused data

    def cover(seconds: float, style: str) -> None:
        n = int(round(seconds * RATE_HZ))
        block = np.repeat(hidden, n, axis=0)
        if style == "zero":
            block = np.zeros_like(block)
        elif style == "nan":
            block = np.full_like(block, np.nan)
        samples.append(block)
        valid.append(np.full(n, style != "residual"))

    styles = ["residual", "residual", "zero", "residual", "nan", "residual", "residual"]
    bows = [1.2, -0.8, 1.0, -1.5, 2.0, -1.0]
    for k, (start, end, duration) in enumerate(STROKES_XY):
        cover(GAPS_S[k], styles[k])
        if k == 4:  # a flicker: the covered marker is seen for 5 frames, then covered again
            samples.append(np.repeat(np.array([[60.0, 20.0, 30.0]]) / 1000.0, 5, axis=0))
            valid.append(np.ones(5, bool))
            cover(0.2, "residual")
        stroke_mm = _stroke(start, end, duration, bows[k], rng)
        samples.append(stroke_mm / 1000.0)
        valid.append(np.ones(len(stroke_mm), bool))
    cover(GAPS_S[-1], styles[-1])

    points_m = np.vstack(samples)[:, None, :]
    return write_c3d(path, points_m, ["PEN"], rate=RATE_HZ, units="m",
                     valid=np.concatenate(valid)[:, None])


if __name__ == "__main__":
    print(make_example())
