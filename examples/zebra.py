"""Zebra stripes of a sketch built in G0 and in G1, side by side (issue 9's picture).

    /usr/bin/python3 examples/zebra.py [STROKES.xyz] [-o docs/g1_zebra.png]

Each face is sampled on a grid; the stripe colour is sign(sin(60 * angle between the surface normal
and a fixed direction)), drawn in plan view. Across a G1 seam the stripes run on without a jump;
across a crease they break. The titles give the largest and median seam angle away from sharp
features, measured as in the report.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.append("/usr/lib/freecad-python3/lib")

import FreeCAD  # noqa: E402,F401  (before Part and ProgSurf.cad)
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from ProgSurf import cad  # noqa: E402
from ProgSurf.core.pipeline import build_network  # noqa: E402
from ProgSurf.io import read_strokes  # noqa: E402

DIRECTION = np.array([0.3, 0.2, 1.0]) / np.linalg.norm([0.3, 0.2, 1.0])


def stripes(ax, shell, network, title: str, n: int = 90) -> None:
    g = np.linspace(0.0, 1.0, n)
    for info in shell.faces:
        s = info.surface
        u0, u1, v0, v1 = s.bounds()
        pts = np.zeros((n, n, 3))
        val = np.zeros((n, n))
        for i, a in enumerate(g):
            for j, b in enumerate(g):
                u, v = u0 + a * (u1 - u0), v0 + b * (v1 - v0)
                p = s.value(u, v)
                pts[i, j] = (p.x, p.y, p.z)
                try:
                    nrm = s.normal(u, v)
                    ang = np.arccos(np.clip(abs(DIRECTION @ np.array((nrm.x, nrm.y, nrm.z))), 0.0, 1.0))
                except Exception:  # a degenerate corner (triangle apex) has no normal
                    ang = np.nan
                val[i, j] = np.sign(np.sin(60.0 * ang))
        ax.pcolormesh(pts[..., 0], pts[..., 1], val, cmap="gray", vmin=-1, vmax=1, shading="gouraud")
    for e in network.edges().values():
        p = e.polyline.points
        ax.plot(p[:, 0], p[:, 1], color="red", lw=0.8)
    stats = cad.g1_seam_stats(shell, network)
    smooth = [st for st in stats if not st.sharp]
    mx = max((st.smooth_max_deg for st in smooth), default=0.0)
    med = float(np.median([st.angle_median_deg for st in smooth])) if smooth else 0.0
    ax.set_title(f"{title}: seam angle max {mx:.2f} deg, median {med:.3f} deg")
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="examples/zebra.py", description=__doc__.splitlines()[0])
    p.add_argument("strokes", nargs="?", default=str(ROOT / "examples" / "clean4.xyz"))
    p.add_argument("-o", "--output", default=str(ROOT / "docs" / "g1_zebra.png"))
    args = p.parse_args(argv)
    result = build_network(read_strokes(args.strokes))
    g1 = cad.build_shell(result.network, result.tol, continuity="G1")
    g0 = cad.analysis.g0_view(g1)
    fig, axes = plt.subplots(1, 2, figsize=(15, 6.8))
    stripes(axes[0], g0, result.network, "G0")
    stripes(axes[1], g1, result.network, "G1")
    fig.suptitle(f"{Path(args.strokes).name}, zebra stripes sign(sin(60 * angle(normal, fixed direction))), "
                 "plan view; red: network curves")
    fig.tight_layout()
    fig.savefig(args.output, dpi=100)
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
