"""ProgSurf against FreeCAD's own Surface workbench on the same curve sets (issue 8, item 2).

Peers: Surface::Filling (OCC GeomPlate; boundary edges + interior curves as unbound edges) and
Surface::GeomFillSurface with FillType Coons (boundary only, k = 0). Every peer edge is a
Part.BSplineCurve interpolating the same sampled points ProgSurf gets, in a Part::Feature.
Wall time covers points -> result shape for both: edge interpolation + recompute for the peers,
pipeline.build_network + cad.build_shell for ProgSurf.
"""
from __future__ import annotations

import time

import numpy as np

from ProgSurf import cad
from ProgSurf.cad._occ import FreeCAD, Part, Vector
from ProgSurf.core.pipeline import build_network

from .surfaces import BENCH_TOL, SIDE, SURFACES, Height, boundary_strokes, section_curves

GRID = 21
"""Samples per direction of every face's parameter square for the ground-truth deviation."""


def _bspline_edge(doc, points: np.ndarray, name: str):
    curve = Part.BSplineCurve()
    curve.interpolate([Vector(*map(float, p)) for p in points])
    obj = doc.addObject("Part::Feature", name)
    obj.Shape = curve.toShape()
    return obj


def run_filling(boundary: list, interior: list) -> dict:
    """Surface::Filling of the boundary edges with the interior curves as unbound edges."""
    doc = FreeCAD.newDocument("BenchFilling")
    try:
        t0 = time.perf_counter()
        bound = [_bspline_edge(doc, p, f"B{i}") for i, p in enumerate(boundary)]
        inner = [_bspline_edge(doc, p, f"I{i}") for i, p in enumerate(interior)]
        fill = doc.addObject("Surface::Filling", "Filling")
        fill.BoundaryEdges = [(o, "Edge1") for o in bound]
        if inner:
            fill.UnboundEdges = [(o, "Edge1") for o in inner]
        doc.recompute()
        wall = time.perf_counter() - t0
        ok = fill.isValid() and not fill.Shape.isNull() and len(fill.Shape.Faces) > 0
        return {"ok": bool(ok), "state": list(fill.State), "time_s": wall,
                "shape": fill.Shape.copy() if ok else None}
    finally:
        FreeCAD.closeDocument(doc.Name)


def run_coons(boundary: list) -> dict:
    """Surface::GeomFillSurface, FillType Coons, of the four boundary edges."""
    doc = FreeCAD.newDocument("BenchCoons")
    try:
        t0 = time.perf_counter()
        bound = [_bspline_edge(doc, p, f"B{i}") for i, p in enumerate(boundary)]
        fill = doc.addObject("Surface::GeomFillSurface", "Coons")
        fill.BoundaryList = [(o, "Edge1") for o in bound]
        fill.FillType = "Coons"
        doc.recompute()
        wall = time.perf_counter() - t0
        ok = fill.isValid() and not fill.Shape.isNull() and len(fill.Shape.Faces) > 0
        return {"ok": bool(ok), "state": list(fill.State), "time_s": wall,
                "shape": fill.Shape.copy() if ok else None}
    finally:
        FreeCAD.closeDocument(doc.Name)


def run_progsurf(boundary: list, interior: list) -> dict:
    """pipeline.build_network (boundary = the first four strokes) + cad.build_shell."""
    t0 = time.perf_counter()
    res = build_network(boundary + interior, boundary=4, tol=BENCH_TOL)
    shell = cad.build_shell(res.network, res.tol)
    wall = time.perf_counter() - t0
    rejected = [r.index for r in res.records if r.status != "accepted"]
    return {"ok": True, "time_s": wall, "shape": shell.shape, "shell": shell, "rejected": rejected,
            "regions": len(res.network)}


def _face_samples(face) -> np.ndarray:
    """(m, 3) points of a face on a GRID x GRID grid of its parameter range, inside its domain."""
    u0, u1, v0, v1 = face.ParameterRange
    surf = face.Surface
    pts = []
    for u in np.linspace(u0, u1, GRID):
        for v in np.linspace(v0, v1, GRID):
            if face.isPartOfDomain(float(u), float(v)):
                pts.append(tuple(surf.value(float(u), float(v))))
    return np.array(pts, dtype=float).reshape(-1, 3)


def ground_truth_deviation(shape, z: Height) -> dict:
    """Vertical deviation |z_result - z(x, y)| at dense samples of every face whose (x, y) lies in
    the domain: max and RMS in mm, and the count of samples used."""
    pts = np.vstack([_face_samples(f) for f in shape.Faces])
    inside = np.all((pts[:, :2] >= -1e-6) & (pts[:, :2] <= SIDE + 1e-6), axis=1)
    dz = np.abs(pts[inside, 2] - z(pts[inside, 0], pts[inside, 1]))
    return {"max_mm": float(dz.max()), "rms_mm": float(np.sqrt(np.mean(dz ** 2))), "samples": int(inside.sum()),
            "outside_domain": int((~inside).sum())}


def poles(shape) -> dict:
    """Poles per face (NbUPoles * NbVPoles of each face's B-spline surface): mean, max and total."""
    counts = []
    for f in shape.Faces:
        s = f.Surface
        counts.append(s.NbUPoles * s.NbVPoles if hasattr(s, "NbUPoles") else 0)
    return {"faces": len(counts), "mean": float(np.mean(counts)), "max": int(max(counts)), "total": int(sum(counts))}


def curve_deviation(shape, curves: list, per_curve: int = 21) -> float:
    """Largest distance of the interior curves' points (per_curve each) from the result's faces."""
    if not curves:
        return 0.0
    pts = np.vstack([c[np.linspace(0, len(c) - 1, per_curve).round().astype(int)] for c in curves])
    return float(cad.shape_point_distances(shape, pts).max())


def compare(surface: str, k: int) -> dict:
    """One row: ProgSurf, Filling (and Coons for k = 0) on boundary + k section curves of `surface`."""
    z = SURFACES[surface]
    boundary, interior = boundary_strokes(z), section_curves(z, k)
    row: dict = {"surface": surface, "k": k}
    tools = {"progsurf": lambda: run_progsurf(boundary, interior),
             "filling": lambda: run_filling(boundary, interior)}
    if k == 0:
        tools["coons"] = lambda: run_coons(boundary)
    for name, run in tools.items():
        try:
            out = run()
        except (Part.OCCError, ValueError, RuntimeError) as err:   # ProgSurfError is a ValueError
            out = {"ok": False, "error": " ".join(str(err).split())[:200]}
        entry = {"ok": out["ok"], "time_s": out.get("time_s", float("nan"))}
        for key in ("error", "state", "rejected", "regions"):
            if key in out:
                entry[key] = out[key]
        if out["ok"]:
            entry["truth"] = ground_truth_deviation(out["shape"], z)
            entry["curve_dev_mm"] = curve_deviation(out["shape"], interior)
            entry["poles"] = poles(out["shape"])
        row[name] = entry
    f, p = row["filling"], row["progsurf"]
    row["time_ratio"] = p["time_s"] / f["time_s"] if f["ok"] and p["ok"] else float("nan")
    return row
