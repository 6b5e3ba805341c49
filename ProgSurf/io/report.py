"""The build report as JSON (numpy and json only): what was built, what happened to every stroke,
and the quality numbers of the CAD result (issue 5: seam gaps, G1 defect, deviations, timings)."""
from __future__ import annotations

import json
import math
import os
from typing import Any, Iterable, Mapping, Sequence

import numpy as np

REPORT_VERSION = 1


def _clean(value: Any) -> Any:
    """numpy scalars/arrays -> plain JSON values; non-finite floats -> None (JSON has no NaN)."""
    if isinstance(value, Mapping):
        return {str(k): _clean(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_clean(v) for v in value]
    if isinstance(value, np.ndarray):
        return _clean(value.tolist())
    if isinstance(value, (np.integer,)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return float(value) if math.isfinite(float(value)) else None
    return value


def stroke_entries(records: Iterable) -> list[dict]:
    """[{index, role, status, reason}] from StrokeRecord-like objects, in input order."""
    return [{"index": int(r.index), "role": str(r.role), "status": str(r.status), "reason": str(r.reason or "")}
            for r in records]


def make_report(*, faces: int, records: Iterable, seams: Sequence[Mapping], stroke_deviation_mm: Mapping,
                fit_deviation_mm: Mapping, poles_per_face: Sequence[Mapping], timings_s: Mapping,
                inputs: Sequence[str] = (), outputs: Mapping | None = None,
                tolerances: Mapping | None = None, shell: Mapping | None = None,
                extra: Mapping | None = None) -> dict:
    """Assemble the report dictionary.

    seams               : one mapping per interior edge with gap_max_mm, angle_max_deg, angle_median_deg
    stroke_deviation_mm : stroke index -> largest distance of its points from the surface
    fit_deviation_mm    : region id -> largest distance of the face from its Coons sub-patch
    poles_per_face      : one mapping per face {region, u_poles, v_poles, u_degree, v_degree}
    """
    seams = [dict(s) for s in seams]
    angles = [s["angle_max_deg"] for s in seams]
    medians = [s["angle_median_deg"] for s in seams]
    report = {
        "version": REPORT_VERSION,
        "inputs": list(inputs),
        "outputs": dict(outputs or {}),
        "tolerances": dict(tolerances or {}),
        "faces": int(faces),
        "strokes": stroke_entries(records),
        "seam_gap_max_mm": max((s["gap_max_mm"] for s in seams), default=0.0),
        "seam_angle_max_deg": max(angles, default=0.0),
        "seam_angle_median_deg": float(np.median(medians)) if medians else 0.0,
        "seams": seams,
        "stroke_deviation_max_mm": max(stroke_deviation_mm.values(), default=0.0),
        "stroke_deviation_mm": {str(k): v for k, v in stroke_deviation_mm.items()},
        "fit_deviation_max_mm": max(fit_deviation_mm.values(), default=0.0),
        "fit_deviation_mm": {str(k): v for k, v in fit_deviation_mm.items()},
        "poles_per_face": [dict(p) for p in poles_per_face],
        "shell": dict(shell or {}),
        "timings_s": dict(timings_s),
    }
    report.update(dict(extra or {}))
    return _clean(report)


def write_report(report: Mapping, path: str | os.PathLike) -> None:
    """Write the report as indented JSON (UTF-8)."""
    with open(path, "w", encoding="utf-8") as fh:
        json.dump(_clean(report), fh, indent=2, allow_nan=False)
        fh.write("\n")


def read_report(path: str | os.PathLike) -> dict:
    with open(path, encoding="utf-8") as fh:
        return json.load(fh)
