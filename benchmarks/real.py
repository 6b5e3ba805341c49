"""The real sketches of ../shared/data built whole, as a user builds them (issue 18).

    /usr/bin/python3 benchmarks/real.py --out /tmp/real            # the 12 sketches, ~2 min
    /usr/bin/python3 benchmarks/real.py --only vintage_car teapot  # some of them

Each sketch (CASSIE's VR strokes, TiGL's aircraft curve networks) is built by the command line a
user runs, `python3 -m ProgSurf build F -o F.step --surfaces all --report F.json`, in a fresh
process, and timed from outside it (start-up and export included). A line per sketch: strokes,
surfaces and faces, shells (closed), strokes used, surfaces reported folding, creases across
surfaces the strokes do not draw, the build's wall time and that time over a machine reference
measured in the same run (benchmarks.run.machine_reference_ms). The issue's speed target is
checked on the largest sketch (most strokes): it builds in under TARGET_S seconds.

Where ../shared/data is absent (a user's clone) there is nothing to measure: it says so and
exits 0. Give another folder of .xyz (or CASSIE .curves) sketches with --data.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT.parent / "shared" / "data"

TARGET_S = 10.0
"""Issue 18: the largest real sketch (vintage_car, 163 strokes) builds in under this many seconds."""


def sketches(data: Path) -> list[Path]:
    """The .xyz sketches under data, and the CASSIE .curves ones with no .xyz of their name beside
    them (../shared holds each CASSIE sketch as both), by name."""
    xyz = list(data.rglob("*.xyz"))
    curves = [p for p in data.rglob("*.curves") if not p.with_suffix(".xyz").exists()]
    return sorted(xyz + curves, key=lambda p: p.name)


def build(path: Path, out: Path) -> dict:
    """Build one sketch through the command line in a fresh process; its report, the wall time and
    the process's exit code (a report of None when it wrote none)."""
    name = path.stem
    report = out / f"{name}.json"
    report.unlink(missing_ok=True)
    cmd = [sys.executable, "-m", "ProgSurf", "build", str(path), "-o", str(out / f"{name}.step"),
           "--surfaces", "all", "--report", str(report)]
    t0 = time.perf_counter()
    done = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    (out / f"{name}.log").write_text(done.stdout + done.stderr)
    data = json.loads(report.read_text()) if report.exists() else None
    return {"name": name, "strokes": _count_strokes(path), "exit": done.returncode, "wall_s": wall,
            "report": data, "last_line": (done.stdout.strip().splitlines() or [""])[-1]}


def _count_strokes(path: Path) -> int:
    """The strokes of a sketch (the reader's own count)."""
    from ProgSurf.io import read_strokes

    return len(read_strokes(path))


def line(r: dict, reference_ms: float) -> str:
    rep = r["report"]
    ratio = 1000.0 * r["wall_s"] / reference_ms
    if rep is None:
        return (f"{r['name']:22s} strokes {r['strokes']:4d}  NOT BUILT (exit {r['exit']}: {r['last_line'][:90]})"
                f"  {r['wall_s']:5.1f} s = {ratio:4.0f} x ref")
    surfaces = rep["surfaces"]
    folding = sum(1 for s in surfaces if s.get("folds"))
    shells = rep["shells"]
    closed = sum(1 for s in shells if s.get("closed"))
    return (f"{r['name']:22s} strokes {r['strokes']:4d}  surfaces {len(surfaces):4d} faces {rep['faces']:4d}"
            f"  shells {len(shells):3d} ({closed} closed)  used {rep['strokes_used']:4d}"
            f"  folding {folding:3d}  creases {len(rep.get('folds_across_surfaces') or []):3d}"
            f"  {r['wall_s']:5.1f} s = {ratio:4.0f} x ref")


def summary(results: list, reference_ms: float) -> str:
    built = [r for r in results if r["report"] is not None]
    surfaces = sum(len(r["report"]["surfaces"]) for r in built)
    folding = sum(1 for r in built for s in r["report"]["surfaces"] if s.get("folds"))
    used = sum(r["report"]["strokes_used"] for r in built)
    strokes = sum(r["strokes"] for r in results)
    text = (f"SUMMARY real: built {len(built)}/{len(results)}, surfaces {surfaces}, folding {folding}, "
            f"strokes used {used} of {strokes}; machine reference {reference_ms:.1f} ms")
    if results:
        big = max(results, key=lambda r: r["strokes"])
        met = "met" if big["report"] is not None and big["wall_s"] < TARGET_S else "NOT met"
        text += (f"\nlargest sketch {big['name']} ({big['strokes']} strokes): {big['wall_s']:.1f} s = "
                 f"{1000.0 * big['wall_s'] / reference_ms:.0f} x the reference; target < {TARGET_S:.0f} s: {met}")
    return text


def main(argv: list | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", default=str(DATA), help="folder searched for .xyz and .curves sketches (default ../shared/data)")
    ap.add_argument("--only", nargs="*", default=(), help="sketch names (file names without .xyz or .curves)")
    ap.add_argument("--out", default=None, help="folder for the STEP files, reports, logs and real.txt")
    args = ap.parse_args(argv)
    data = Path(args.data)
    todo = [p for p in sketches(data) if not args.only or p.stem in args.only] if data.is_dir() else []
    if not todo:
        print(f"no sketches to measure: {data} is absent or holds none of {list(args.only) or 'its .xyz or .curves files'}")
        return 0
    sys.path.insert(0, str(ROOT))
    from benchmarks.run import machine_reference_ms

    out = Path(args.out) if args.out else Path(tempfile.mkdtemp(prefix="progsurf-real-"))
    out.mkdir(parents=True, exist_ok=True)
    reference = machine_reference_ms()
    results = []
    for path in todo:
        results.append(build(path, out))
        print(line(results[-1], reference), flush=True)
    reference = 0.5 * (reference + machine_reference_ms())
    text = summary(results, reference)
    print(text)
    (out / "real.txt").write_text("\n".join(line(r, reference) for r in results) + "\n" + text + "\n")
    (out / "real.json").write_text(json.dumps(results, indent=1))
    print(f"wrote {out / 'real.txt'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
