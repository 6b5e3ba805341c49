"""A picture of the result without a GUI: matplotlib (Agg) of the shell's tessellation, Lambert
shaded, with the strokes drawn on top (accepted dark, rejected red dashed)."""
from __future__ import annotations

import os
from typing import Sequence

import numpy as np

from ..core.types import FloatArray
from ..optional import require


def render_png(shape, path: str | os.PathLike, strokes: Sequence[FloatArray] = (),
               rejected: Sequence[bool] = (), title: str = "", deflection_mm: float | None = None,
               size_px: tuple[int, int] = (1200, 900)) -> None:
    """Write a PNG of `shape` (tessellated with shape.tessellate) and the strokes, isometric view."""
    matplotlib = require("matplotlib", "drawing a picture of the surface (--png)")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    box = shape.BoundBox
    deflection = deflection_mm if deflection_mm is not None else max(box.DiagonalLength, 1e-6) / 400.0
    verts, tris = shape.tessellate(deflection)
    v = np.array([tuple(p) for p in verts], dtype=float).reshape(-1, 3)
    t = np.array(tris, dtype=int).reshape(-1, 3)
    fig = plt.figure(figsize=(size_px[0] / 100.0, size_px[1] / 100.0), dpi=100)
    ax = fig.add_subplot(111, projection="3d")
    if len(t):
        tri = v[t]
        n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
        light = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
        shade = 0.35 + 0.65 * np.abs(n @ light)   # two-sided: open shells are seen from both sides
        colors = np.clip(np.outer(shade, [0.55, 0.7, 0.9]), 0, 1)
        ax.add_collection3d(Poly3DCollection(tri, facecolors=colors, edgecolors="none", alpha=0.95))
    flags = list(rejected) + [False] * (len(strokes) - len(rejected))
    for pts, rej in zip(strokes, flags):
        p = np.asarray(pts, dtype=float).reshape(-1, 3)
        ax.plot(p[:, 0], p[:, 1], p[:, 2], color="red" if rej else "black",
                linestyle="--" if rej else "-", linewidth=1.0)
    allp = np.vstack([v] + [np.asarray(s, dtype=float).reshape(-1, 3) for s in strokes]) if len(v) else \
        np.vstack([np.asarray(s, dtype=float).reshape(-1, 3) for s in strokes])
    centre = 0.5 * (allp.min(axis=0) + allp.max(axis=0))
    half = 0.5 * float(np.ptp(allp, axis=0).max()) or 1.0
    for setter, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), centre):
        setter(c - half, c + half)
    ax.set_box_aspect((1, 1, 1))
    ax.view_init(elev=30, azim=-60)
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_zlabel("z [mm]")
    if title:
        ax.set_title(title)
    fig.tight_layout()
    fig.savefig(os.fspath(path))
    plt.close(fig)
