"""Editing a whole built sketch: one stroke moved, the network rebuilt (issue 18, item 6).

    /usr/bin/python3 benchmarks/edits.py                               # the real sketches (../shared/data)
    /usr/bin/python3 benchmarks/edits.py --only vintage_car --edits 3
    /usr/bin/python3 benchmarks/edits.py --generated 4                 # the objects benchmark's sketches

What the FreeCAD document object does when a stroke moves: the sketch is built once with a
core.objects.BuildCache (`first`), then each of `--edits` strokes in turn (spread over the sketch)
is moved by 0.2 % of the sketch's diagonal and the whole network is built again with that cache
(`edit`, the median of the edits), as app.objects.build_object_and_measure does for the document.
A line per sketch: surfaces, the first build and the median edit (seconds and times the machine
reference measured in the same run, benchmarks.run.machine_reference_ms), first / edit, and how
many surfaces an edit built again (median): only those the moved stroke touches should be. With
--generated N, the objects benchmark's sketches (benchmarks.objects.make_object, N per kind)
instead, so that a clone without ../shared has something to measure.
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT.parent / "shared" / "data"
EDITS = 5
MOVE = 0.002
"""A moved stroke is shifted by this fraction of the sketch's diagonal (along its third axis)."""


def measure(name: str, strokes: list, edits: int) -> dict:
    """The first build and the edits of one sketch (module docstring)."""
    from ProgSurf.app.objects import build_object_and_measure
    from ProgSurf.core.objects import BuildCache, steady_tolerances

    strokes = [np.asarray(s, dtype=float) for s in strokes]
    tol = steady_tolerances(strokes)
    every = np.vstack(strokes)
    shift = np.array([0.0, 0.0, MOVE * float(np.linalg.norm(every.max(axis=0) - every.min(axis=0)))])
    cache = BuildCache()
    t0 = time.perf_counter()
    first = build_object_and_measure(strokes, tol, cache=cache)
    first_s = time.perf_counter() - t0
    times, rebuilt = [], []
    for k in np.linspace(0, len(strokes) - 1, min(edits, len(strokes))).round().astype(int):
        moved = list(strokes)
        moved[k] = moved[k] + shift
        t0 = time.perf_counter()
        out = build_object_and_measure(moved, tol, cache=cache)
        times.append(time.perf_counter() - t0)
        rebuilt.append(len(out.build.rebuilt))
    return {"name": name, "surfaces": len(first.build.surfaces), "first_s": first_s,
            "edit_s": statistics.median(times), "rebuilt": statistics.median(rebuilt), "edits": len(times)}


def line(r: dict, reference_ms: float) -> str:
    ref = reference_ms / 1000.0
    return (f"{r['name']:22s} surfaces {r['surfaces']:4d}  first {r['first_s']:5.2f} s = {r['first_s'] / ref:5.0f} x ref"
            f"  edit {r['edit_s']:5.2f} s = {r['edit_s'] / ref:5.0f} x ref  first/edit {r['first_s'] / r['edit_s']:5.1f}"
            f"  surfaces built again {r['rebuilt']:g} of {r['surfaces']} (median of {r['edits']})")


def main(argv: list | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", default=str(DATA), help="folder searched for .xyz and .curves sketches")
    ap.add_argument("--only", nargs="*", default=(), help="sketch names (file names without extension)")
    ap.add_argument("--edits", type=int, default=EDITS, help="strokes moved in turn per sketch")
    ap.add_argument("--generated", type=int, default=0, help="the objects benchmark's sketches, N per kind")
    args = ap.parse_args(argv)
    sys.path.insert(0, str(ROOT))
    from benchmarks.quality import setup_path
    setup_path()            # FreeCAD first, then this checkout ahead of any linked one
    from benchmarks.run import machine_reference_ms

    todo: list = []
    if args.generated:
        from benchmarks.objects import KINDS, make_object
        for kind in KINDS:
            for seed in range(args.generated):
                sk = make_object(kind, 7000 + seed)
                todo.append((sk.name, lambda sk=sk: sk.strokes))
    else:
        from benchmarks.real import sketches
        from ProgSurf.io import read_strokes
        data = Path(args.data)
        paths = [p for p in sketches(data) if not args.only or p.stem in args.only] if data.is_dir() else []
        todo = [(p.stem, lambda p=p: read_strokes(p)) for p in paths]
    if not todo:
        print(f"no sketches to measure: {args.data} is absent or holds none of {list(args.only) or 'its sketches'}")
        return 0
    reference = machine_reference_ms()
    results = []
    for name, strokes in todo:
        results.append(measure(name, strokes(), args.edits))
        print(line(results[-1], reference), flush=True)
    reference = 0.5 * (reference + machine_reference_ms())
    first = sum(r["first_s"] for r in results)
    edit = sum(r["edit_s"] for r in results)
    print(f"SUMMARY edits: {len(results)} sketches, first builds {first:.1f} s, one edit each {edit:.1f} s "
          f"(first/edit {first / edit:.1f}); machine reference {reference:.1f} ms")
    return 0


if __name__ == "__main__":
    sys.exit(main())
