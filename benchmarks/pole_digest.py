"""Poles of every face ProgSurf builds from a fixed set of inputs, for comparing two checkouts.

    /usr/bin/python3 benchmarks/pole_digest.py OUT.npz [--checkout DIR] [--no-real]
    /usr/bin/python3 benchmarks/pole_digest.py --compare A.npz B.npz

Inputs: every bundled example (examples/*.xyz, examples/*.c3d) in G0 and G1, the benchmark's
50-region saddle network (benchmarks.latency.grow) in G0 and G1, and every real sketch of
../shared/data that builds with the automatic boundary (G0). Each face's poles, weights and knots
are stored under "<input>/<continuity>/<face index>". --compare prints, per key, the largest
difference, and exits 1 if any key differs or is missing on one side.
"""
from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


def _collect(checkout: Path, real: bool) -> dict:
    sys.path.append("/usr/lib/freecad-python3/lib")
    import numpy as np
    import FreeCAD  # noqa: F401  (before Part)

    # FreeCAD's import puts its user Mod folder first on sys.path; when that links another
    # checkout, its ProgSurf would be the one measured (as tests/conftest.py, put ours back first)
    while str(checkout) in sys.path:
        sys.path.remove(str(checkout))
    sys.path.insert(0, str(checkout))
    from ProgSurf.core import pipeline
    from ProgSurf import cad
    from ProgSurf.io import read_strokes

    assert Path(pipeline.__file__).resolve().is_relative_to(checkout.resolve()), pipeline.__file__
    build_net = getattr(pipeline, "build_network", None) or getattr(pipeline, "build")
    build_shell = cad.build_shell
    out: dict = {}

    def faces(key: str, net, tol, continuity: str) -> None:
        try:
            shell = build_shell(net, tol, continuity=continuity)
        except Exception as exc:  # noqa: BLE001 -- recorded, compared as text
            out[f"{key}/{continuity}/error"] = np.array(f"{type(exc).__name__}: {exc}")
            print(f"{key} {continuity}: {type(exc).__name__}", flush=True)
            return
        for i, f in enumerate(shell.faces):
            s = f.surface
            out[f"{key}/{continuity}/{i}/poles"] = np.array([[tuple(p) for p in row] for row in s.getPoles()])
            out[f"{key}/{continuity}/{i}/uknots"] = np.array(s.getUKnots() + [float(m) for m in s.getUMultiplicities()])
            out[f"{key}/{continuity}/{i}/vknots"] = np.array(s.getVKnots() + [float(m) for m in s.getVMultiplicities()])
        print(f"{key} {continuity}: {len(shell.faces)} faces", flush=True)

    inputs = sorted((checkout / "examples").glob("*.xyz")) + sorted((checkout / "examples").glob("*.c3d"))
    for path in inputs:
        res = build_net(read_strokes(str(path)))
        for c in ("G0", "G1"):
            faces(path.name, res.network, res.tol, c)
    sys.path.insert(0, str(checkout / "benchmarks"))
    from benchmarks import latency
    from benchmarks.surfaces import BENCH_TOL

    nets, _ = latency.grow([50])
    for target, net in nets.items():
        for c in ("G0", "G1"):
            faces(f"bench{target}", net, BENCH_TOL, c)
    data = checkout.parent / "shared" / "data"
    if real and data.is_dir():
        for path in sorted(data.glob("**/*.xyz")):
            name = str(path.relative_to(data))
            try:
                res = build_net(read_strokes(str(path)))
            except Exception as exc:  # noqa: BLE001
                out[f"{name}/error"] = np.array(f"{type(exc).__name__}: {exc}")
                print(f"{name}: {type(exc).__name__}", flush=True)
                continue
            faces(name, res.network, res.tol, "G0")
    return out


def _compare(a_path: str, b_path: str) -> int:
    import numpy as np

    a, b = np.load(a_path), np.load(b_path)
    bad = 0
    for k in sorted(set(a.files) | set(b.files)):
        if k not in a.files or k not in b.files:
            print(f"MISSING in {'A' if k not in a.files else 'B'}: {k}")
            bad += 1
            continue
        x, y = a[k], b[k]
        if x.dtype.kind in "US" or y.dtype.kind in "US":
            if str(x) != str(y):
                print(f"DIFF {k}: {x} | {y}")
                bad += 1
            continue
        if x.shape != y.shape or not np.array_equal(x, y):
            d = float(np.abs(x - y).max()) if x.shape == y.shape else float("inf")
            print(f"DIFF {k}: shape {x.shape} vs {y.shape}, max {d:.3g}")
            bad += 1
    print(f"{len(set(a.files) | set(b.files))} arrays compared, {bad} differ")
    return 1 if bad else 0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", nargs="?")
    ap.add_argument("--checkout", type=Path, default=Path(__file__).resolve().parents[1])
    ap.add_argument("--no-real", action="store_true")
    ap.add_argument("--compare", nargs=2, metavar=("A", "B"))
    args = ap.parse_args(argv)
    if args.compare:
        return _compare(*args.compare)
    import numpy as np

    np.savez_compressed(args.out, **_collect(args.checkout, not args.no_real))
    return 0


if __name__ == "__main__":
    sys.exit(main())
