"""The headless command line (issue 5):

    /usr/bin/python3 -m ProgSurf build STROKE_FILE... -o OUT.step [--iges OUT.igs] [--fcstd OUT.FCStd]
        [--png OUT.png] [--report OUT.json] [--boundary-count N] [--filter MM] [--snap MM]
        [--fit-tol MM] [--skin] [--continuity G0|G1]

Strokes are taken in file order, then in the order the files are given.

Exit codes, for every input: 0 built (one valid shell); 2 refused, with one line on stderr that names
the problem (bad option, unreadable or too large input, an output path that would overwrite an input,
another output or a directory, or could not be written; an unexpected internal error is also
reported so, in one line asking for a report); 3 built, but the quality verdict warns. Options and
output paths are checked before any work, the input's size before the build, so every run ends in
bounded time.

This module parses the command, reads the strokes, and writes the files and the summary: the build
and its measurements are the document's own (ProgSurf.app.build.build_and_measure, whose
build_report makes the JSON report), so the two give the same figures for the same strokes.
"""
from __future__ import annotations

import argparse
import math
import os
import sys
import tempfile
import time
import warnings
from typing import Optional, Sequence

import numpy as np

from .core.errors import DegenerateSketchError, InvalidOptionError, OpenBoundaryError, ProgSurfError, StrokeFileError
from .core.off_surface import moved_note
from .core.types import FIT_FRACTION, Tolerances
from .io.c3d import MIN_DURATION_S, MIN_LENGTH_MM

EXIT_OK, EXIT_BAD_INPUT, EXIT_QUALITY = 0, 2, 3

MAX_STROKES = 400
"""Most strokes one build takes: each interior stroke costs a footpoint search, a network update and
fold checks on the network it grows, so the time grows faster than the count. The largest real
sketch at hand, CASSIE's vintage_car (163 strokes), took 7.5 minutes on a 2-core machine loaded
six times over; 2000 short strokes ran for more than 5 minutes before this limit."""
MAX_POINTS = 200_000
"""Most points in all strokes together (the boundary's closing step compares every segment of one
side with every segment of the next at once). vintage_car holds about 1900."""
SKETCH_MM_RANGE = (1e-3, 1e9)
"""Smallest and largest sketch diagonal (mm) built. The tolerances scale with the sketch, but OCC's
sewing and tolerances do not below its fixed precision (1e-7 mm) or where 1e-7 mm is below the
coordinates' round-off: clean4 and fig11_general build from 1e-4 to 1e8 times their size (0.014 mm
to 1.4e10 mm), and at 1e10 times OCC sews them into 0 or 2 shells."""
FIT_FRACTION_RANGE = (1e-5, 1e-2)
"""--fit-tol allowed, as fractions of the sketch's diagonal (the automatic value is FIT_FRACTION of it).
Below: the strokes are sampled finer with the tolerance (their chords' sag) and the closing step
grows with the square of that (1e-9 mm on clean4 ran for minutes and gigabytes); above: a face may
leave its sub-patch by a visible fraction of the sketch, and is clamped with a note."""


class _Parser(argparse.ArgumentParser):
    """argparse, whose refusals are one line (its own are the usage block, then the message)."""

    def error(self, message: str):
        self.exit(EXIT_BAD_INPUT, f"progsurf: error: {message}; see python3 -m ProgSurf build --help\n")


def _whole(text: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None


def _number(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None


_NUMBER_OPTIONS = ("--boundary-count", "--filter", "--snap", "--fit-tol", "--min-duration", "--min-length",
                   "--smooth")


def _join_negative_numbers(argv: Sequence[str]) -> list:
    """'--snap -inf' -> '--snap=-inf': argparse takes a value such as -inf or -1e3 for an option name
    and refuses with "expected one argument"; joined, the value reaches the range check."""
    out, k = [], 0
    while k < len(argv):
        tok = argv[k]
        if tok in _NUMBER_OPTIONS and k + 1 < len(argv) and argv[k + 1].startswith("-"):
            try:
                float(argv[k + 1])
            except ValueError:
                pass
            else:
                out.append(f"{tok}={argv[k + 1]}")
                k += 2
                continue
        out.append(tok)
        k += 1
    return out


def _parser() -> argparse.ArgumentParser:
    p = _Parser(prog="python3 -m ProgSurf",
                                description="Progressive freeform surfaces from 3D sketch strokes "
                                            "(Qin & Wright), written as STEP/IGES.")
    sub = p.add_subparsers(dest="command", required=True)
    b = sub.add_parser("build", help="build a surface from stroke files and export it")
    b.add_argument("inputs", nargs="+", metavar="STROKE_FILE", help=".xyz/.txt/.csv/.asc point lists, .c3d or CASSIE .curves")
    b.add_argument("-o", "--output", required=True, metavar="OUT.step", help="STEP AP214 file to write")
    b.add_argument("--iges", metavar="OUT.igs", help="also write IGES (BRep mode)")
    b.add_argument("--fcstd", metavar="OUT.FCStd", help="also write a FreeCAD document with strokes and surface")
    b.add_argument("--png", metavar="OUT.png", help="also write a rendered picture")
    b.add_argument("--report", metavar="OUT.json", help="also write the JSON report")
    b.add_argument("--boundary-count", type=_whole, metavar="N",
                   help="the first N strokes are the boundary (default: classify automatically)")
    b.add_argument("--filter", type=_number, metavar="MM", help="stroke filter distance (default: automatic)")
    b.add_argument("--snap", type=_number, metavar="MM", help="snap distance of stroke ends (default: automatic)")
    b.add_argument("--fit-tol", type=_number, metavar="MM",
                   help="largest distance of a B-spline face from its Coons sub-patch (default: automatic, "
                        f"{FIT_FRACTION:g} of the sketch's diagonal)")
    b.add_argument("--skin", action="store_true",
                   help="also write OUT_skin.step: one B-spline surface skinned across all patches")
    b.add_argument("--continuity", choices=["G0", "G1"], default="G0",
                   help="continuity across seams: G0 the paper's Coons patches, G1 tangent-continuous "
                        "seams (kinked strokes stay sharp); default %(default)s")
    b.add_argument("--markers", metavar="LABEL[,LABEL]",
                   help=".c3d inputs: marker labels to draw with (default: the most-moving marker)")
    b.add_argument("--min-duration", type=_number, metavar="S",
                   help=f".c3d inputs: drop pen-down runs shorter than this (default {MIN_DURATION_S:g} s)")
    b.add_argument("--min-length", type=_number, metavar="MM",
                   help=f".c3d inputs: drop pen-down runs shorter than this (default {MIN_LENGTH_MM:g} mm)")
    b.add_argument("--smooth", type=_whole, default=0, metavar="N",
                   help=".c3d inputs: moving-average window against tracker jitter (ends kept)")
    b.add_argument("--surfaces", choices=["auto", "all", "one"], default="auto",
                   help="auto (default): one surface for one sheet of strokes (one loop round the others, "
                        "or loops that all face one way), else, or when no single boundary loop closes, every "
                        "surface (ProgSurf.object_cli); one: one surface; all: every surface of the stroke "
                        "network, one shell per part")
    b.add_argument("-q", "--quiet", action="store_true", help="no summary on stdout")
    return p


def _check_args(args) -> Tolerances:
    """The options' ranges and the output paths, before any work (InvalidOptionError)."""
    for name in ("filter", "snap", "fit_tol"):
        value = getattr(args, name)
        if value is not None and not (math.isfinite(value) and value > 0):
            raise InvalidOptionError(f"--{name.replace('_', '-')} {value:g}: give a positive, finite distance "
                                     "in mm, or leave the option out for the automatic value")
    for name in ("min_duration", "min_length"):
        value = getattr(args, name)
        if value is not None and not (math.isfinite(value) and value >= 0):
            raise InvalidOptionError(f"--{name.replace('_', '-')} {value:g}: give a finite number, 0 or more")
    if args.smooth < 0:
        raise InvalidOptionError(f"--smooth {args.smooth}: give a window of 0 or more samples")
    if args.boundary_count is not None and args.boundary_count < 3:
        raise InvalidOptionError(f"--boundary-count {args.boundary_count}: a boundary needs at least 3 strokes")
    _check_outputs(args)
    return Tolerances(filter_mm=args.filter, snap_mm=args.snap, fit_mm=args.fit_tol)


def skin_path(output: str) -> str:
    """Where --skin writes the skinned exchange surface: OUT_skin.step beside OUT.step."""
    return os.path.splitext(output)[0] + "_skin.step"


def _outputs(args) -> list:
    """(option, path) of every file the command will write."""
    outs = [("-o", args.output), ("--iges", args.iges), ("--fcstd", args.fcstd), ("--png", args.png),
            ("--report", args.report)]
    if args.skin:
        outs.append(("--skin", skin_path(args.output)))
    return [(opt, path) for opt, path in outs if path is not None]


def _same_file(a: str, b: str) -> bool:
    if os.path.realpath(a) == os.path.realpath(b):
        return True
    try:
        return os.path.samefile(a, b)      # hard links, bind mounts
    except OSError:
        return False


def _check_writable_folder(opt: str, path: str, folder: str) -> None:
    """Refuse a folder that is missing, not a folder, or that this user cannot create a file in: a
    temporary file is made there and removed (os.access says yes to root on a read-only system)."""
    if not os.path.isdir(folder):
        raise InvalidOptionError(f"{opt} {path!r}: folder {folder!r} does not exist")
    try:
        with tempfile.NamedTemporaryFile(dir=folder, prefix=".progsurf-probe-"):
            pass
    except OSError as exc:
        raise InvalidOptionError(f"{opt} {path!r}: cannot write in folder {folder!r} "
                                 f"({exc.strerror or exc}); choose another folder") from None


def _check_outputs(args) -> None:
    """Every output is a new or overwritable FILE in a folder this user can write, and no output is
    an input or another output (the report written over the STEP, or the STEP over the strokes)."""
    seen: list = []
    for opt, path in _outputs(args):
        if not path.strip():
            raise InvalidOptionError(f"{opt} is an empty path; name the file to write")
        if os.path.isdir(path):
            raise InvalidOptionError(f"{opt} {path!r} is a directory; name a file in it, e.g. "
                                     f"{os.path.join(path, 'out' + _EXTENSIONS[opt])!r}")
        for src in args.inputs:
            if _same_file(path, src):
                raise InvalidOptionError(f"{opt} {path!r} is the input stroke file {src!r}; writing it would "
                                         "destroy the strokes: name another output file")
        for other_opt, other in seen:
            if _same_file(path, other):
                raise InvalidOptionError(f"{opt} {path!r} is also the {other_opt} file; give each output its "
                                         "own name")
        seen.append((opt, path))
        if os.path.exists(path) and not os.access(path, os.W_OK):
            raise InvalidOptionError(f"{opt} {path!r} exists and is read-only; choose another name")
        _check_writable_folder(opt, path, os.path.dirname(os.path.abspath(path)))


_EXTENSIONS = {"-o": ".step", "--iges": ".igs", "--fcstd": ".FCStd", "--png": ".png", "--report": ".json",
               "--skin": ".step"}


def _check_size(strokes: list, tol: Tolerances) -> Tolerances:
    """Refuse an input too large to finish in bounded time, or of a size OCC cannot build; check
    --fit-tol against the sketch's size (refuse too small, clamp too large with a note on stderr)."""
    from .core.strokes import sketch_diagonal

    if len(strokes) > MAX_STROKES:
        raise InvalidOptionError(f"{len(strokes)} strokes: the command line builds at most {MAX_STROKES} "
                                 "(the time grows faster than the count); split the sketch or leave "
                                 "strokes out")
    points = sum(len(s) for s in strokes)
    if points > MAX_POINTS:
        raise InvalidOptionError(f"{points} points in all: the command line builds at most {MAX_POINTS}; "
                                 "thin the strokes (e.g. one point every --filter mm) first")
    diagonal = sketch_diagonal(np.vstack([np.asarray(s, dtype=float).reshape(-1, 3) for s in strokes]))
    low, high = SKETCH_MM_RANGE
    if not low <= diagonal <= high:
        raise InvalidOptionError(f"the sketch is {diagonal:.3g} mm across; ProgSurf builds sketches from "
                                 f"{low:g} to {high:g} mm across (OCC's fixed precision): scale it")
    if tol.fit_mm is None:
        return tol
    fmin, fmax = (f * diagonal for f in FIT_FRACTION_RANGE)
    if tol.fit_mm < fmin:
        raise InvalidOptionError(f"--fit-tol {tol.fit_mm:g} mm is below {FIT_FRACTION_RANGE[0]:g} of the "
                                 f"sketch's {diagonal:.4g} mm size; give {fmin:.3g} to {fmax:.3g} mm, or leave "
                                 f"it out (automatic: {FIT_FRACTION * diagonal:.3g} mm)")
    if tol.fit_mm > fmax:
        sys.stderr.write(f"progsurf: note: --fit-tol {tol.fit_mm:g} mm is more than {FIT_FRACTION_RANGE[1]:g} "
                         f"of the sketch's {diagonal:.4g} mm size; using {fmax:.3g} mm\n")
        return Tolerances(filter_mm=tol.filter_mm, snap_mm=tol.snap_mm, fit_mm=fmax, fair_mm=tol.fair_mm)
    return tol


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


def _write_fcstd(path: str, strokes: list, build_result, shape, args) -> None:
    """A document with the strokes (ProgSurf.app stroke objects) and the surface (ProgSurf.app
    surface object, recomputed by the app layer) as the build asked for it (boundary count,
    resolved tolerances, continuity, skin), plus the exported shell as a plain Part::Feature."""
    import FreeCAD

    from .app import make

    doc = FreeCAD.newDocument("ProgSurf")
    try:
        objs = [make.make_stroke_from_points(p, name=f"Stroke{i:03d}", doc=doc, recompute=False)
                for i, p in enumerate(strokes)]
        tol = build_result.tol
        kwargs = dict(filter_mm=tol.filter_mm, snap_mm=tol.snap_mm, fit_mm=tol.fit_mm, skin=args.skin,
                      recompute=False)
        count = args.boundary_count
        if count is None:
            surface = make.make_surface(all_strokes=objs, **kwargs)
        else:
            surface = make.make_surface(boundary=objs[:count], interior=objs[count:], **kwargs)
        surface.Continuity = args.continuity
        shell = doc.addObject("Part::Feature", "ExportedShell")
        shell.Shape = shape
        doc.recompute()
        if not surface.isValid():
            raise ProgSurfError(f"the document's surface object did not recompute: {surface.State}")
        doc.saveAs(os.path.abspath(path))
    finally:
        FreeCAD.closeDocument(doc.Name)


def _write(kind: str, path: str, action) -> None:
    """Run action() that writes path: an OCC or file-system failure is a refusal naming the path
    (the paths were checked before the build, but a disk can fill or a mount change meanwhile)."""
    from .cad._occ import Part

    try:
        action()
    except (OSError, Part.OCCError) as exc:
        reason = getattr(exc, "strerror", None) or " ".join(str(exc).split())[:200]
        raise ProgSurfError(f"cannot write the {kind} file {path!r}: {reason}") from None


def run_build(args, out=sys.stdout) -> dict:
    """Everything `build` does; returns the report dict. Raises ProgSurfError on bad input.

    Parses and reads the strokes, builds and measures them with the document's own orchestration
    (app.build.build_and_measure), then writes the files, the report and the summary."""
    tol = _check_args(args)
    timings: dict = {}
    clock = time.perf_counter()
    strokes = _read(args.inputs, _c3d_options(args))
    tol = _check_size(strokes, tol)
    timings["read"] = time.perf_counter() - clock
    from .object_cli import fallback_object, run_object_build, wants_object

    whole, network = wants_object(args, strokes, tol)
    if whole:
        return run_object_build(args, strokes, tol, network, timings, out)

    from . import cad
    from .app.build import build_and_measure, build_report
    from .io.report import write_report

    try:
        outcome = build_and_measure(strokes, args.boundary_count, tol, continuity=args.continuity,
                                    skin=args.skin, report=True)
    except (OpenBoundaryError, DegenerateSketchError) as exc:
        # --surfaces auto: no single loop of strokes encloses the others; every loop of the
        # network, when there is one, is what the sketch shows
        network = fallback_object(args, network)
        if network is None:
            raise
        if not args.quiet:
            print(f"no single boundary loop ({exc}); building every surface of the stroke network "
                  "(--surfaces all)", file=out)
        return run_object_build(args, strokes, tol, network, timings, out)
    timings.update(outcome.timings_s)
    result, shape = outcome.result, outcome.shell.shape
    if len(shape.Shells) != 1 or not shape.isValid():
        raise ProgSurfError(f"OCC made {len(shape.Shells)} shells (valid={shape.isValid()}) instead of one "
                            "valid shell; please report this sketch")
    gap = outcome.analysis.report.shell["seam_gap_max_mm"] if outcome.analysis.report is not None else 0.0
    if gap > result.tol.fit_mm:
        # BRepCheck passes a shell sewn onto itself (a sketch whose surface lies on itself): its
        # faces are far apart along an edge they share, and the STEP file would read back invalid
        raise ProgSurfError(f"OCC sewed a shell whose faces are {gap:.3g} mm apart along an edge they share "
                            f"(fit tolerance {result.tol.fit_mm:.3g} mm): the surface lies on itself; "
                            "check that the boundary strokes go once around the surface")

    clock = time.perf_counter()
    outputs = {"step": args.output}
    _write("STEP", args.output, lambda: cad.export_step(shape, args.output))
    if args.iges:
        _write("IGES", args.iges, lambda: cad.export_iges(shape, args.iges))
        outputs["iges"] = args.iges
    if outcome.skin is not None:
        _write("STEP", skin_path(args.output),
               lambda: cad.export_step(outcome.skin[0].toShape(), skin_path(args.output)))
        outputs["skin_step"] = skin_path(args.output)
    timings["export"] = time.perf_counter() - clock
    if args.png:
        clock = time.perf_counter()
        from .cad.render import render_png

        rejected = [r.status == "rejected" for r in result.records]
        title = f"{len(shape.Faces)} faces, {len(result.accepted)}/{len(result.records)} strokes"
        _write("PNG", args.png, lambda: render_png(shape, args.png, strokes, rejected, title=title))
        outputs["png"] = args.png
        timings["png"] = time.perf_counter() - clock
    if args.fcstd:
        clock = time.perf_counter()
        _write("FreeCAD document", args.fcstd, lambda: _write_fcstd(args.fcstd, strokes, result, shape, args))
        outputs["fcstd"] = args.fcstd
        timings["fcstd"] = time.perf_counter() - clock

    report = build_report(outcome, inputs=args.inputs, outputs=outputs, timings_s=timings)
    if args.report:
        _write("report", args.report, lambda: write_report(report, args.report))
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
    lines += [f"  stroke {s['index']} ({s['role']}) accepted; {moved_note(s['reason'])}"
              for s in strokes if s["status"] == "accepted" and moved_note(s["reason"] or "")]
    lines.append("wrote " + ", ".join(report["outputs"].values()))
    if "quality" in report:
        lines.append(report["quality"]["verdict"])
    return "\n".join(lines)


def main(argv: Optional[Sequence[str]] = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    args = _parser().parse_args(_join_negative_numbers(argv))
    try:
        with warnings.catch_warnings():
            # the contract is one line on stderr: numeric warnings of intermediate steps are not
            # the user's to read (what matters is measured and reported)
            warnings.simplefilter("ignore", RuntimeWarning)
            report = run_build(args)
    except ProgSurfError as exc:
        sys.stderr.write(f"progsurf: error: {' '.join(str(exc).split())}\n")
        return EXIT_BAD_INPUT
    except OSError as exc:
        sys.stderr.write(f"progsurf: error: {exc.strerror or exc}: {exc.filename or ''}\n")
        return EXIT_BAD_INPUT
    except MemoryError:
        sys.stderr.write("progsurf: error: out of memory; give fewer or shorter strokes\n")
        return EXIT_BAD_INPUT
    except Exception as exc:   # noqa: BLE001  the last resort: any other failure is one line, not a traceback
        where = exc.__traceback__
        while where is not None and where.tb_next is not None:
            where = where.tb_next
        origin = (f" at {os.path.basename(where.tb_frame.f_code.co_filename)}:{where.tb_lineno}"
                  if where is not None else "")
        message = " ".join(str(exc).split())[:300]
        sys.stderr.write(f"progsurf: internal error: {type(exc).__name__}: {message}{origin}; please report "
                         "it with the command and its input files\n")
        return EXIT_BAD_INPUT
    if not report.get("quality", {}).get("ok", True):
        if args.quiet:      # the verdict is part of the summary; quiet still names the problem
            sys.stderr.write(f"progsurf: {report['quality']['verdict']}\n")
        return EXIT_QUALITY
    return EXIT_OK
