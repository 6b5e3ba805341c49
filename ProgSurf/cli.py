"""The headless command line (issue 5):

    /usr/bin/python3 -m ProgSurf build STROKE_FILE... -o OUT.step [--iges OUT.igs] [--fcstd OUT.FCStd]
        [--png OUT.png] [--report OUT.json] [--boundary-count N] [--filter MM] [--snap MM]
        [--fit-tol MM] [--skin] [--continuity G0|G1]

Strokes are taken in file order, then in the order the files are given. Exit 0 on success, 2 on bad
input (one line on stderr, no traceback), 1 when OCC fails on valid input.

This module parses the command, reads the strokes, and writes the files and the summary: the build
and its measurements are the document's own (ProgSurf.app.build.build_and_measure, whose
build_report makes the JSON report), so the two give the same figures for the same strokes.
"""
from __future__ import annotations

import argparse
import os
import sys
import time
from typing import Optional, Sequence

from .core.errors import FitError, ProgSurfError
from .core.types import FIT_FRACTION, Tolerances
from .io.c3d import MIN_DURATION_S, MIN_LENGTH_MM

EXIT_OK, EXIT_FAILED, EXIT_BAD_INPUT, EXIT_QUALITY = 0, 1, 2, 3


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python3 -m ProgSurf",
                                description="Progressive freeform surfaces from 3D sketch strokes "
                                            "(Qin & Wright), written as STEP/IGES.")
    sub = p.add_subparsers(dest="command", required=True)
    b = sub.add_parser("build", help="build a surface from stroke files and export it")
    b.add_argument("inputs", nargs="+", metavar="STROKE_FILE", help=".xyz/.txt/.csv/.asc point lists or .c3d")
    b.add_argument("-o", "--output", required=True, metavar="OUT.step", help="STEP AP214 file to write")
    b.add_argument("--iges", metavar="OUT.igs", help="also write IGES (BRep mode)")
    b.add_argument("--fcstd", metavar="OUT.FCStd", help="also write a FreeCAD document with strokes and surface")
    b.add_argument("--png", metavar="OUT.png", help="also write a rendered picture")
    b.add_argument("--report", metavar="OUT.json", help="also write the JSON report")
    b.add_argument("--boundary-count", type=int, metavar="N",
                   help="the first N strokes are the boundary (default: classify automatically)")
    b.add_argument("--filter", type=float, metavar="MM", help="stroke filter distance (default: automatic)")
    b.add_argument("--snap", type=float, metavar="MM", help="snap distance of stroke ends (default: automatic)")
    b.add_argument("--fit-tol", type=float, metavar="MM",
                   help="largest distance of a B-spline face from its Coons sub-patch (default: automatic, "
                        f"{FIT_FRACTION:g} of the sketch's diagonal)")
    b.add_argument("--skin", action="store_true",
                   help="also write OUT_skin.step: one B-spline surface skinned across all patches")
    b.add_argument("--continuity", choices=["G0", "G1"], default="G0",
                   help="continuity across seams: G0 the paper's Coons patches, G1 tangent-continuous "
                        "seams (kinked strokes stay sharp); default %(default)s")
    b.add_argument("--markers", metavar="LABEL[,LABEL]",
                   help=".c3d inputs: marker labels to draw with (default: the most-moving marker)")
    b.add_argument("--min-duration", type=float, metavar="S",
                   help=f".c3d inputs: drop pen-down runs shorter than this (default {MIN_DURATION_S:g} s)")
    b.add_argument("--min-length", type=float, metavar="MM",
                   help=f".c3d inputs: drop pen-down runs shorter than this (default {MIN_LENGTH_MM:g} mm)")
    b.add_argument("--smooth", type=int, default=0, metavar="N",
                   help=".c3d inputs: moving-average window against tracker jitter (ends kept)")
    b.add_argument("--surfaces", choices=["auto", "all", "one"], default="auto",
                   help="all: every surface of the stroke network, one shell per part; one: one surface; "
                        "auto: one when one loop encloses the other strokes, else all (ProgSurf.object_cli)")
    b.add_argument("-q", "--quiet", action="store_true", help="no summary on stdout")
    return p


def _check_args(args) -> Tolerances:
    for name in ("filter", "snap", "fit_tol"):
        value = getattr(args, name)
        if value is not None and not value > 0:
            raise ProgSurfError(f"--{name.replace('_', '-')} {value} must be a positive distance in mm")
    if args.boundary_count is not None and args.boundary_count < 3:
        raise ProgSurfError(f"--boundary-count {args.boundary_count}: a boundary needs at least 3 strokes")
    for out in filter(None, (args.output, args.iges, args.fcstd, args.png, args.report)):
        folder = os.path.dirname(os.path.abspath(out))
        if not os.path.isdir(folder):
            raise ProgSurfError(f"cannot write {out!r}: folder {folder!r} does not exist")
    return Tolerances(filter_mm=args.filter, snap_mm=args.snap, fit_mm=args.fit_tol)


def _use_checkout_venv() -> None:
    """PyPI-only packages (c3d) live in the checkout's .venv, made by install.sh on this same
    Python: make them importable when the command runs under /usr/bin/python3 (as Init.py does)."""
    from .venv_site import add_venv_site_packages

    add_venv_site_packages(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def _read(paths: Sequence[str], c3d_options: Optional[dict] = None) -> list:
    from .io import read_strokes

    _use_checkout_venv()
    strokes = []
    for path in paths:
        options = c3d_options if str(path).lower().endswith(".c3d") and c3d_options else {}
        strokes.extend(read_strokes(path, **options))
    return strokes


def _c3d_options(args) -> dict:
    """Options of the motion-capture reader taken from the command line (.c3d inputs only)."""
    options: dict = {}
    if args.markers:
        options["markers"] = [m.strip() for m in args.markers.split(",") if m.strip()]
    if args.min_duration is not None:
        options["min_duration_s"] = args.min_duration
    if args.min_length is not None:
        options["min_length_mm"] = args.min_length
    if args.smooth:
        options["smooth"] = args.smooth
    return options


def _write_fcstd(path: str, strokes: list, build_result, shape, boundary_count: Optional[int]) -> None:
    """A document with the strokes (ProgSurf.app stroke objects) and the surface (ProgSurf.app
    surface object, recomputed by the app layer), plus the exported shell as a plain Part::Feature."""
    import FreeCAD

    from .app import make

    doc = FreeCAD.newDocument("ProgSurf")
    try:
        objs = [make.make_stroke_from_points(p, name=f"Stroke{i:03d}", doc=doc, recompute=False)
                for i, p in enumerate(strokes)]
        tol = build_result.tol
        kwargs = dict(filter_mm=tol.filter_mm, snap_mm=tol.snap_mm, fit_mm=tol.fit_mm, recompute=False)
        if boundary_count is None:
            surface = make.make_surface(all_strokes=objs, **kwargs)
        else:
            surface = make.make_surface(boundary=objs[:boundary_count], interior=objs[boundary_count:], **kwargs)
        shell = doc.addObject("Part::Feature", "ExportedShell")
        shell.Shape = shape
        doc.recompute()
        if not surface.isValid():
            raise ProgSurfError(f"the document's surface object did not recompute: {surface.State}")
        doc.saveAs(os.path.abspath(path))
    finally:
        FreeCAD.closeDocument(doc.Name)


def run_build(args, out=sys.stdout) -> dict:
    """Everything `build` does; returns the report dict. Raises ProgSurfError on bad input.

    Parses and reads the strokes, builds and measures them with the document's own orchestration
    (app.build.build_and_measure), then writes the files, the report and the summary."""
    tol = _check_args(args)
    timings: dict = {}
    clock = time.perf_counter()
    strokes = _read(args.inputs, _c3d_options(args))
    timings["read"] = time.perf_counter() - clock
    from .object_cli import run_object_build, wants_object

    network = wants_object(args, strokes, tol)
    if network is not None:
        return run_object_build(args, strokes, tol, network, timings, out)

    from . import cad
    from .app.build import build_and_measure, build_report
    from .io.report import write_report

    outcome = build_and_measure(strokes, args.boundary_count, tol, continuity=args.continuity,
                                skin=args.skin, report=True)
    timings.update(outcome.timings_s)
    result, shape = outcome.result, outcome.shell.shape
    if len(shape.Shells) != 1 or not shape.isValid():
        raise FitError(f"OCC made {len(shape.Shells)} shells (valid={shape.isValid()}) instead of one valid "
                       "shell; report this sketch")

    clock = time.perf_counter()
    outputs = {"step": args.output}
    cad.export_step(shape, args.output)
    if args.iges:
        cad.export_iges(shape, args.iges)
        outputs["iges"] = args.iges
    if outcome.skin is not None:
        skin, skin_dev = outcome.skin
        skin_path = os.path.splitext(args.output)[0] + "_skin.step"
        cad.export_step(skin.toShape(), skin_path)
        outputs["skin_step"] = skin_path
        if skin_dev > result.tol.fit_mm:
            print(f"warning: the skinned exchange surface lies up to {skin_dev:.3g} mm from the patches "
                  f"(fit tolerance {result.tol.fit_mm:.3g} mm)", file=sys.stderr)
    timings["export"] = time.perf_counter() - clock
    if args.png:
        clock = time.perf_counter()
        from .cad.render import render_png

        render_png(shape, args.png, strokes, [r.status == "rejected" for r in result.records],
                   title=f"{len(shape.Faces)} faces, {len(result.accepted)}/{len(result.records)} strokes")
        outputs["png"] = args.png
        timings["png"] = time.perf_counter() - clock
    if args.fcstd:
        clock = time.perf_counter()
        _write_fcstd(args.fcstd, strokes, result, shape, args.boundary_count)
        outputs["fcstd"] = args.fcstd
        timings["fcstd"] = time.perf_counter() - clock

    report = build_report(outcome, inputs=args.inputs, outputs=outputs, timings_s=timings)
    if args.report:
        write_report(report, args.report)
    if not args.quiet:
        out.write(summary(report) + "\n")
    return report


def summary(report: dict) -> str:
    """A short human summary of a report."""
    strokes = report["strokes"]
    acc = sum(s["status"] == "accepted" for s in strokes)
    lines = [f"{report['faces']} faces in one shell; strokes: {acc} accepted, {len(strokes) - acc} rejected",
             f"seam gap max {report['seam_gap_max_mm']:.2e} mm; seam normal angle max "
             f"{report['seam_angle_max_deg']:.2f} deg (median {report['seam_angle_median_deg']:.2f})",
             f"fit deviation max {report['fit_deviation_max_mm']:.4f} mm; stroke deviation max "
             f"{report['stroke_deviation_max_mm']:.4f} mm",
             f"continuity {report['continuity']}; seam angle away from sharp features max "
             f"{report.get('seam_' + report['continuity'].lower(), {}).get('smooth_max_deg', 0.0):.2f} deg",
             f"poles per face max {max((p['u_poles'] * p['v_poles'] for p in report['poles_per_face']), default=0)}"]
    lines += [f"  stroke {s['index']} ({s['role']}) rejected: {s['reason']}" for s in strokes
              if s["status"] == "rejected"]
    lines.append("wrote " + ", ".join(report["outputs"].values()))
    if "quality" in report:
        lines.append(report["quality"]["verdict"])
    return "\n".join(lines)


def main(argv: Optional[Sequence[str]] = None) -> int:
    args = _parser().parse_args(argv)
    try:
        report = run_build(args)
    except ProgSurfError as exc:
        sys.stderr.write(f"progsurf: error: {' '.join(str(exc).split())}\n")
        return EXIT_FAILED if isinstance(exc, FitError) else EXIT_BAD_INPUT
    except OSError as exc:
        sys.stderr.write(f"progsurf: error: {exc.strerror or exc}: {exc.filename or ''}\n")
        return EXIT_BAD_INPUT
    if not report.get("quality", {}).get("ok", True):
        if args.quiet:      # the verdict is part of the summary; quiet still names the problem
            sys.stderr.write(f"progsurf: {report['quality']['verdict']}\n")
        return EXIT_QUALITY
    return EXIT_OK
