"""`build --surfaces all|one|auto` (issue 18): the whole-object branch of the command line.

`all` builds every surface of the stroke network (app.objects) into one shell per connected
part; `one` is the single progressive surface (cli.run_build as before); `auto` (the default)
builds one surface for one sheet of curves (core.objects.choose_mode: its outer border one loop
round the others, or its loops all facing one way, or no loop at all) and every surface otherwise,
and also every surface when the single surface is refused for want of one boundary loop
(fallback_object).
--boundary-count and --skin name one surface, so with them `auto` is `one`.
"""
from __future__ import annotations

import os
import sys
import time
from typing import Optional

from .core.errors import ProgSurfError


def wants_object(args, strokes: list, tol) -> tuple[bool, Optional[tuple]]:
    """(build every surface?, the stroke network: core.objects.stroke_network's result, or None
    when it was not needed to decide). With --surfaces auto the network made to choose is kept
    for fallback_object, should the single surface be refused."""
    mode = getattr(args, "surfaces", "one")
    if mode == "one" or (mode == "auto" and (args.boundary_count is not None or args.skin)):
        return False, None
    if mode == "all" and (args.boundary_count is not None or args.skin):
        raise ProgSurfError("--surfaces all builds every loop of the network; --boundary-count and --skin "
                            "name one surface: give --surfaces one with them")
    from .core.objects import choose_mode, stroke_network

    network = stroke_network(strokes, tol)
    return mode == "all" or choose_mode(network[1], network[0]) == "all", network


def fallback_object(args, network: Optional[tuple]) -> Optional[tuple]:
    """--surfaces auto, after the single surface was refused for want of one boundary loop (its
    strokes leave a gap, or none encloses the others): the stroke network (made by wants_object)
    to build every surface of, when it has a loop of curves; None otherwise (and for the other
    modes, where wants_object made none)."""
    if getattr(args, "surfaces", "one") != "auto" or network is None:
        return None
    return network if network[1].cycles else None


def _write_fcstd(path: str, strokes: list, outcome, continuity: str) -> None:
    """A document with the strokes (ProgSurf.app stroke objects) and one SurfaceNetwork object on
    them (recomputed by the app layer with the build's resolved tolerances and continuity), plus the
    exported shell as a plain Part::Feature."""
    import FreeCAD

    from .app import make

    doc = FreeCAD.newDocument("ProgSurfObject")
    try:
        objs = [make.make_stroke_from_points(p, name=f"Stroke{i:03d}", doc=doc, recompute=False)
                for i, p in enumerate(strokes)]
        tol = outcome.build.tol
        network = make.make_surface_network(objs, filter_mm=tol.filter_mm, snap_mm=tol.snap_mm,
                                            fit_mm=tol.fit_mm, recompute=False)
        network.Continuity = continuity
        doc.addObject("Part::Feature", "ExportedShell").Shape = outcome.shape
        doc.recompute()
        if not network.isValid() or network.LastError:
            raise ProgSurfError(f"the document's network object did not recompute: {network.State} "
                                f"{network.LastError}")
        doc.saveAs(os.path.abspath(path))
    finally:
        FreeCAD.closeDocument(doc.Name)


def run_object_build(args, strokes: list, tol, network: tuple, timings: dict, out=sys.stdout) -> dict:
    """Build every surface, write STEP (and IGES, FCStd, PNG, the report), print the summary;
    returns the report."""
    from . import cad
    from .app.objects import build_object_and_measure, object_report, object_summary
    from .io.report import write_report

    outcome = build_object_and_measure(strokes, tol, continuity=args.continuity, network=network)
    timings.update(outcome.timings_s)
    shape = outcome.shape
    clock = time.perf_counter()
    outputs = {"step": args.output}
    cad.export_step(shape, args.output)
    if args.iges:
        cad.export_iges(shape, args.iges)
        outputs["iges"] = args.iges
    timings["export"] = time.perf_counter() - clock
    if args.png:
        from .cad.render import render_png

        used = [r.used for r in outcome.build.roles]
        render_png(shape, args.png, strokes, [not u for u in used],
                   title=f"{len(outcome.build.surfaces)} surfaces, {len(shape.Faces)} faces, "
                         f"{sum(used)}/{len(used)} strokes")
        outputs["png"] = args.png
    if args.fcstd:
        _write_fcstd(args.fcstd, strokes, outcome, args.continuity)
        outputs["fcstd"] = args.fcstd
    report = object_report(outcome, inputs=args.inputs, outputs=outputs, timings_s=timings)
    if args.report:
        write_report(report, args.report)
    if not args.quiet:
        out.write(object_summary(report) + "\n")
    return report
