"""Write the paper's Fig. 9 and Fig. 11 examples (Qin & Wright 2006, section 5) as sketches.

    /usr/bin/python3 examples/make_paper_examples.py [outdir]

fig9_sections.xyz : a flat 100 x 60 mm base and two section strokes at y=20 then y=40 whose ends
                    touch the left and right boundary curves (Fig. 9a, 9b).
fig11_general.xyz : four boundary curves of 25 points each (so point i of a side maps to i/24); an
                    interior stroke from point 11 of the bottom to point 11 of the top, over-sketched
                    by one point at its second end (pre-image (11/24,0)-(11/24,1)); then a stroke with
                    free ends crossing it, 6 mm above it in 3D, so the first stroke is pulled to it.
Deterministic: no random draws.
"""
from __future__ import annotations

import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
if ROOT not in sys.path:
    sys.path.insert(0, ROOT)

from ProgSurf.io.pointlist import write_point_list  # noqa: E402


def fig9() -> list[np.ndarray]:
    x = np.linspace(0.0, 100.0, 21)
    y = np.linspace(0.0, 60.0, 13)
    zero_x, zero_y = np.zeros_like(x), np.zeros_like(y)
    boundary = [np.c_[x, zero_x, zero_x], np.c_[zero_y + 100, y, zero_y],
                np.c_[x[::-1], zero_x + 60, zero_x], np.c_[zero_y, y[::-1], zero_y]]
    s = np.linspace(0.0, 100.0, 26)
    first = np.c_[s, np.full_like(s, 20.0), 12.0 * np.sin(np.pi * s / 100.0)]
    second = np.c_[s, np.full_like(s, 40.0), 8.0 * np.sin(np.pi * s / 100.0)]
    return boundary + [first, second]


def fig11() -> list[np.ndarray]:
    i = np.arange(25) / 24.0
    bottom = np.c_[120 * i, 0 * i, 5 * np.sin(np.pi * i)]
    top = np.c_[120 * i, 0 * i + 90, 5 * np.sin(np.pi * i)]
    left = np.c_[0 * i, 90 * i, 0 * i]
    right = np.c_[0 * i + 120, 90 * i, 0 * i]
    boundary = [bottom, right, top[::-1], left[::-1]]
    v = np.arange(26) / 24.0                                  # one point past the top: over-sketch
    x0 = 120 * 11 / 24
    first = np.c_[np.full_like(v, x0), 90 * v, 5 * np.sin(np.pi * 11 / 24) + 10 * np.sin(np.pi * np.clip(v, 0, 1))]
    u = np.linspace(0.1, 0.9, 30)
    second = np.c_[120 * u, np.full_like(u, 50.0), 5 * np.sin(np.pi * u) + 10 * np.sin(np.pi * 50 / 90) + 6.0]
    return boundary + [first, second]


def main(outdir: str = os.path.dirname(os.path.abspath(__file__))) -> None:
    write_point_list(os.path.join(outdir, "fig9_sections.xyz"), fig9(),
                     comments=["Qin & Wright 2006 Fig. 9: flat base, section strokes at y=20 then y=40",
                               "boundary strokes first: 4; then 2 interior strokes touching the left and right sides",
                               "made by examples/make_paper_examples.py (deterministic)"])
    write_point_list(os.path.join(outdir, "fig11_general.xyz"), fig11(),
                     comments=["Qin & Wright 2006 Fig. 11: stroke with pre-image (11/24,0)-(11/24,1), then a",
                               "stroke with free ends crossing it 6 mm above it",
                               "boundary strokes first: 4 (25 points each); then 2 interior strokes",
                               "made by examples/make_paper_examples.py (deterministic)"])


if __name__ == "__main__":
    main(*sys.argv[1:])
