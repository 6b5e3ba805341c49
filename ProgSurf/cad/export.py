"""STEP (AP214) and IGES (BRep mode) export, read-back in a fresh process, and the skinned
exchange surface of Qin & Wright section 3.3 / 4.

    python -m ProgSurf.cad.export readback FILE   prints a JSON summary of FILE read by a fresh FreeCAD
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from ..core.errors import FitError, ProgSurfError
from ._occ import Part, Vector
from .curves import collapsed, to_vectors

STEP_SCHEMA = "AP214IS"
PYTHON = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable
REPO_ROOT = Path(__file__).resolve().parents[2]


def export_step(shape, path: str | os.PathLike) -> None:
    """Write `shape` as a STEP AP214 file (FILE_SCHEMA AUTOMOTIVE_DESIGN), millimetres."""
    Part.setStaticValue("write.step.schema", STEP_SCHEMA)
    Part.setStaticValue("write.step.unit", "MM")
    shape.exportStep(os.fspath(path))
    if not os.path.isfile(path):
        raise ProgSurfError(f"OCC did not write the STEP file {os.fspath(path)!r}; check the folder exists "
                            "and is writable")


def export_shape(shape, path: str | os.PathLike) -> None:
    """STEP or IGES by the file extension (.step/.stp, .iges/.igs)."""
    ext = os.path.splitext(os.fspath(path))[1].lower()
    if ext in (".step", ".stp"):
        export_step(shape, path)
    elif ext in (".iges", ".igs"):
        export_iges(shape, path)
    else:
        raise ProgSurfError(f"cannot export to {os.fspath(path)!r}: use a .step/.stp or .iges/.igs name")


def export_iges(shape, path: str | os.PathLike) -> None:
    """Write `shape` as IGES 5.3 in BRep mode (entities 514 shell / 510 face), so that a reader gets
    one shell with shared edges back, not loose trimmed surfaces."""
    Part.setStaticValue("write.iges.brep.mode", 1)
    Part.setStaticValue("write.iges.unit", "MM")
    shape.exportIges(os.fspath(path))
    if not os.path.isfile(path):
        raise ProgSurfError(f"OCC did not write the IGES file {os.fspath(path)!r}; check the folder exists "
                            "and is writable")


def summarize(shape, bop_check: bool = False) -> dict:
    """Face count, area, validity (BRepCheck; with bop_check also shape.check(True), the BOP argument
    analysis, which takes seconds on heavy faces), shells, free edges and seam gaps."""
    from .analysis import shell_seam_gaps

    check_error = None
    if bop_check:
        try:
            shape.check(True)
            check_error = ""
        except ValueError as exc:
            check_error = " ".join(str(exc).split())
    out = {"shape_type": shape.ShapeType, "shells": len(shape.Shells), "faces": len(shape.Faces),
           "area_mm2": float(shape.Area), "valid": bool(shape.isValid()), "check_error": check_error}
    out.update(shell_seam_gaps(shape))
    return out


def read_back(path: str | os.PathLike, bop_check: bool = False, points: str | os.PathLike | None = None,
              timeout_s: float = 300.0) -> dict:
    """Read a STEP/IGES file in a FRESH FreeCAD process and return its :func:`summarize` dict;
    with `points` (a .npy file of (m, 3) points) also 'point_distances_mm', each point's distance
    to the read-back faces."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO_ROOT), env.get("PYTHONPATH", "")]))
    env.setdefault("HOME", "/tmp")
    cmd = [PYTHON, "-m", "ProgSurf.cad.export", "readback", os.fspath(path)]
    cmd += ["--bop"] if bop_check else []
    cmd += ["--points", os.fspath(points)] if points is not None else []
    proc = subprocess.run(cmd,
                          capture_output=True, text=True, timeout=timeout_s, env=env, cwd=str(REPO_ROOT))
    lines = [ln for ln in proc.stdout.splitlines() if ln.startswith("{")]
    if proc.returncode != 0 or not lines:
        raise ProgSurfError(f"reading {os.fspath(path)!r} back failed: {proc.stderr.strip()[-400:]}")
    return json.loads(lines[-1])


SKIN_LADDER = ((17, 41), (33, 81), (65, 129))
"""(sections, samples per section) tried in turn by :func:`skin_surface` until the skin is within
the tolerance."""


def _skin(network, sections: int, samples: int):
    u = np.linspace(0.0, 1.0, samples)
    curves, apex = [], {}
    for k, v in enumerate(np.linspace(0.0, 1.0, sections)):
        pts = np.asarray(network.evaluate_uv(np.stack([u, np.full_like(u, v)], axis=1)), dtype=float)
        if collapsed(pts):     # the collapsed side of a 3-sided network: OCC cannot interpolate a point
            apex[k] = pts[0]
            curves.append(None)
            continue
        c = Part.BSplineCurve()
        c.interpolate(Points=to_vectors(pts), Parameters=[float(x) for x in u])
        curves.append(c)
    model = next((c for c in curves if c is not None), None)
    if model is None:
        raise FitError("every section of the network is one point; there is no surface to skin")
    for k, point in apex.items():  # the apex as a section: a neighbour's knots, every pole on the point
        c = model.copy()
        for i in range(1, c.NbPoles + 1):
            c.setPole(i, Vector(*point))
        curves[k] = c
    surface = Part.BSplineSurface()
    try:
        surface.buildFromNSections(curves)
    except Part.OCCError as exc:
        raise FitError(f"OCC could not skin {sections} section curves: {exc}; try fewer sections") from exc
    return surface


def skin_surface(network, tol_mm: float = 0.01):
    """One B-spline surface skinned through u-direction section curves sampled across all patches
    (Qin & Wright section 3.3: a single surface for data exchange). Section j is the curve
    u -> network.evaluate_uv(u, v_j), v_j uniform in [0, 1]; each is interpolated with the same
    parameters and OCC skins them (BSplineSurface.buildFromNSections). Sections are doubled
    (SKIN_LADDER) until the skin lies within tol_mm of the network (:func:`skin_deviation`).
    Returns (surface, deviation_mm): the last, finest skin when none is within tol_mm."""
    for sections, samples in SKIN_LADDER:
        surface = _skin(network, sections, samples)
        dev = skin_deviation(surface, network, tol_mm=tol_mm)
        if dev <= tol_mm:
            break
    return surface, dev


def skin_deviation(surface, network, n: int = 31, tol_mm: float = 0.0) -> float:
    """Largest distance from the network's points on an n x n grid of the unit square to the skinned
    surface (each point projected onto it: the skin's own v parameter is not the network's).
    cad.analysis.surface_distances projects them all; OCC's own projection (0.2 s a point near the
    apex of a 3-sided network's skin: 3.5 minutes for the finest skin of examples/three_sided) only
    the points it finds further than tol_mm, where it may have stopped short (near such an apex it
    did, by 15 times the distance). Each distance is that of a point of the surface: an upper bound."""
    from .analysis import surface_distances

    g = np.linspace(0.0, 1.0, n)
    uu, vv = np.meshgrid(g, g, indexing="ij")
    ref = np.asarray(network.evaluate_uv(np.stack([uu.ravel(), vv.ravel()], axis=1)), dtype=float)
    dist = surface_distances([(surface, tuple(surface.bounds()))], ref)
    for k in np.flatnonzero(dist > tol_mm):
        p = Vector(*ref[k])
        a, b = surface.parameter(p)
        dist[k] = min(dist[k], (surface.value(a, b) - p).Length)
    return float(dist.max())


def _main(argv: list[str]) -> int:
    import argparse

    p = argparse.ArgumentParser(prog="python -m ProgSurf.cad.export")
    p.add_argument("command", choices=["readback"])
    p.add_argument("path")
    p.add_argument("--bop", action="store_true")
    p.add_argument("--points")
    args = p.parse_args(argv)
    shape = Part.read(args.path)
    out = summarize(shape, bop_check=args.bop)
    if args.points:
        from .analysis import shape_point_distances

        out["point_distances_mm"] = shape_point_distances(shape, np.load(args.points)).tolist()
    sys.stdout.write(json.dumps(out) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(_main(sys.argv[1:]))
