"""Helpers that write C3D test files with the `c3d` library's own Writer.

Used by tests/core/test_c3d.py and examples/make_c3d_example.py. The tests know every
sample they write, so they can check the reader's stroke splits exactly.

Conventions of `write_c3d`:
    points : (n_frames, n_markers, 3) float, in the file's `units`
    valid  : (n_frames, n_markers) bool or None; False is written as residual -1 (occluded).
             NaN and (0, 0, 0) samples are written as they are, with a valid residual,
             the way some capture systems fill gaps.
    scale  : POINT:SCALE; negative = float storage, positive = 16-bit integers times `scale`.
             With integer storage the Writer truncates `points / scale`, so callers that need
             exact values should use `quantise(points, scale)` with a power-of-two scale.
"""
from __future__ import annotations

import warnings
from pathlib import Path
from typing import Optional, Sequence

import numpy as np

import c3d


def quantise(points: np.ndarray, scale: float) -> np.ndarray:
    """Round points to multiples of `scale` so integer storage keeps them exactly."""
    return np.round(np.asarray(points, dtype=float) / scale) * scale


def write_c3d(
    path: Path,
    points: np.ndarray,
    labels: Sequence[str],
    rate: float = 100.0,
    units: str = "mm",
    scale: float = -1.0,
    valid: Optional[np.ndarray] = None,
    residual: float = 0.5,
    first_frame: int = 1,
) -> Path:
    """Write a C3D file of marker trajectories; returns `path`."""
    pts = np.asarray(points, dtype=float)
    if pts.ndim != 3 or pts.shape[2] != 3:
        raise ValueError(f"points must be (n_frames, n_markers, 3), got {pts.shape}")
    n_frames, n_markers, _ = pts.shape
    if len(labels) != n_markers:
        raise ValueError(f"{len(labels)} labels for {n_markers} markers")
    ok = np.ones((n_frames, n_markers), bool) if valid is None else np.asarray(valid, bool)
    res = abs(scale) * np.round(residual / abs(scale)) if scale > 0 else residual

    # An object array of (points, analog) pairs: the Writer's own np.array() call cannot
    # broadcast a list of pairs when a frame has no markers.
    frames = np.empty((n_frames, 2), dtype=object)
    no_analog = np.zeros((0, 0), np.float32)
    for i in range(n_frames):
        f = np.zeros((n_markers, 5), np.float32)
        f[:, :3] = pts[i]
        f[:, 3] = np.where(ok[i], res, -1.0)
        f[:, 4] = np.where(ok[i], 3.0, -1.0)  # 3 = cameras 1 and 2 saw it
        frames[i, 0] = f
        frames[i, 1] = no_analog

    writer = c3d.Writer(point_rate=float(rate), point_scale=float(scale), point_units=units)
    if n_markers:
        writer.set_point_labels(list(labels))
    if first_frame != 1:
        writer.set_start_frame(first_frame)
    writer.add_frames(frames)
    path = Path(path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # "No analog data found in file."
        with open(path, "wb") as handle:
            writer.write(handle)
    return path


def runs_to_trajectory(
    n_frames: int, runs: Sequence[tuple[int, int]], f
) -> tuple[np.ndarray, np.ndarray]:
    """A (n_frames, 3) trajectory valid only on `runs` ((first, last) 0-based inclusive).

    f(t) -> (k, 3) gives the position at frame indices t; returns (points, valid).
    """
    pts = np.zeros((n_frames, 3))
    valid = np.zeros(n_frames, bool)
    for a, b in runs:
        t = np.arange(a, b + 1)
        pts[a : b + 1] = f(t)
        valid[a : b + 1] = True
    return pts, valid
