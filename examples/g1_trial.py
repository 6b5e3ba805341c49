"""G0 against G1 on random progressive sketches (issue 9): seam angles, validity, time.

    /usr/bin/python3 examples/g1_trial.py [--seeds 12] [--noise 0 0.08]

The sketches are benchmarks.surfaces.random_sketch(seed) (four boundary strokes on a random height
field, 2-3 interior strokes across it), optionally with Gaussian jitter (mm) on every point. Per
sketch it prints the largest seam angle away from sharp features in G0 and G1, the worst per-seam
median in G1, the number of sharp seams, whether the G1 shell is valid, the build times, and OK when
G1 meets the targets (max <= 1 deg, median <= 0.1 deg) or MISS when it does not.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests" / "app"))
sys.path.append("/usr/lib/freecad-python3/lib")

import FreeCAD  # noqa: E402,F401  (before Part and ProgSurf.cad)
import numpy as np  # noqa: E402

from ProgSurf import cad  # noqa: E402
from ProgSurf.core.errors import ProgSurfError  # noqa: E402
from ProgSurf.core.pipeline import build_network  # noqa: E402
from benchmarks.surfaces import random_sketch  # noqa: E402
from test_g1 import MAX_DEG, MEDIAN_DEG  # noqa: E402


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="examples/g1_trial.py", description=__doc__.splitlines()[0])
    p.add_argument("--seeds", type=int, default=12)
    p.add_argument("--noise", type=float, nargs="+", default=[0.0, 0.08])
    args = p.parse_args(argv)
    ok = total = 0
    for noise in args.noise:
        for seed in range(1, args.seeds + 1):
            rng = np.random.default_rng(seed)
            strokes = [s + rng.normal(0.0, noise, s.shape) for s in random_sketch(seed)]
            total += 1
            try:
                r = build_network(strokes, boundary=4)
                t = time.perf_counter()
                g1 = cad.build_shell(r.network, r.tol, continuity="G1")
                t1 = time.perf_counter() - t
            except ProgSurfError as exc:
                print(f"noise {noise} seed {seed}: {type(exc).__name__}: {exc}")
                continue
            s0 = cad.g1_seam_stats(cad.analysis.g0_view(g1), r.network)
            s1 = cad.g1_seam_stats(g1, r.network)
            g0max = max((s.smooth_max_deg for s in s0 if not s.sharp), default=0.0)
            g1max = max((s.smooth_max_deg for s in s1 if not s.sharp), default=0.0)
            med = max((s.angle_median_deg for s in s1 if not s.sharp), default=0.0)
            good = g1max <= MAX_DEG and med <= MEDIAN_DEG and g1.shape.isValid()
            ok += good
            print(f"noise {noise} seed {seed}: {len(r.network)} regions, {len(r.accepted)}/{len(r.records)} "
                  f"strokes accepted; G0 max {g0max:.2f} deg, G1 max {g1max:.3f} deg, worst median "
                  f"{med:.4f} deg, {sum(s.sharp for s in s1)} sharp, valid {g1.shape.isValid()}, "
                  f"G1 shell {t1:.2f} s: {'OK' if good else 'MISS'}", flush=True)
    print(f"{ok} of {total} sketches meet the G1 targets")
    return 0


if __name__ == "__main__":
    sys.exit(main())
