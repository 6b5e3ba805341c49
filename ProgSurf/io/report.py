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


def continuity_section(continuity: str, seams: Sequence[Any], g0_seams: Sequence[Any] = (),
                       added_time_s: float | None = None) -> dict:
    """The report's G1 fields (issue 9) from G1SeamStat-like records (edge_id, region_a, region_b,
    angle_max_deg, angle_median_deg, sharp, smooth_max_deg, node_spread_deg), measured on the built
    surface and, beside it, on the G0 faces of the same strokes.

    Returns {"continuity", "seam_g1": {per-seam list, max_deg, median_deg, smooth_max_deg,
    sharp_edges}, "seam_g0": the same for G0 (when given), "g1_added_time_s"}."""
    def summary(stats: Sequence[Any]) -> dict:
        rows = [{"edge": int(s.edge_id), "regions": [int(s.region_a), int(s.region_b)],
                 "angle_max_deg": float(s.angle_max_deg), "angle_median_deg": float(s.angle_median_deg),
                 "smooth_max_deg": float(s.smooth_max_deg), "sharp": bool(s.sharp),
                 "node_spread_deg": [float(x) for x in s.node_spread_deg]} for s in stats]
        smooth = [r for r in rows if not r["sharp"]]
        return {"seams": rows,
                "max_deg": max((r["angle_max_deg"] for r in rows), default=0.0),
                "median_deg": float(np.median([r["angle_median_deg"] for r in smooth])) if smooth else 0.0,
                "smooth_max_deg": max((r["smooth_max_deg"] for r in smooth), default=0.0),
                "sharp_edges": [r["edge"] for r in rows if r["sharp"]]}

    out = {"continuity": str(continuity), "seam_g1" if continuity == "G1" else "seam_g0": summary(seams)}
    if g0_seams:
        out["seam_g0"] = summary(g0_seams)
    if added_time_s is not None:
        out["g1_added_time_s"] = float(added_time_s)
    return _clean(out)
