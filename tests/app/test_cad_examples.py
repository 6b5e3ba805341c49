"""The CAD adapter on the real pipeline: the paper's three examples (and clean4) built once each,
checked as a shell, exported to STEP and IGES and read back in a fresh FreeCAD process."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ProgSurf import cad
from ProgSurf.core.network import OUTER_CURVES
from ProgSurf.core.pipeline import build_network
from ProgSurf.io import read_strokes

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ["fig9_sections.xyz", "fig10_five_sided.xyz", "fig11_general.xyz", "clean4.xyz"]
SEAM_GAP_MM = 1e-7
BOP_POLES_LIMIT = 100_000
"""shape.check(True) (the BOP argument analysis) takes minutes on faces of ~500x800 poles (fig10 today,
see the pole counts in the report); above this total it is left out and only BRepCheck runs."""


class Built:
    def __init__(self, name: str, tmp: Path):
        path = ROOT / "examples" / name
        if not path.exists():
            pytest.skip(f"example {name} not written yet (examples/make_paper_examples.py)")
        self.result = build_network(read_strokes(path))
        self.shell = cad.build_shell(self.result.network, self.result.tol)
        self.step = tmp / (path.stem + ".step")
        self.iges = tmp / (path.stem + ".igs")
        cad.export_step(self.shell.shape, self.step)
        cad.export_iges(self.shell.shape, self.iges)
        # strokes drawn where they are: accepted, and not pulled away by a later stroke (paper: later wins)
        pulled = {c for r in self.result.records for c in getattr(r, "pulled_curves", ())}
        self.kept = [r for r in self.result.accepted if r.points is not None
                     and not (set(getattr(r, "curve_ids", ())) & pulled)]
        self.points = tmp / (path.stem + ".npy")
        np.save(self.points, np.vstack([r.points for r in self.kept]))
        poles = sum(f.poles[0] * f.poles[1] for f in self.shell.faces)
        self.bop = poles <= BOP_POLES_LIMIT
        self.step_back = cad.read_back(self.step, bop_check=self.bop, points=self.points)
        self.iges_back = cad.read_back(self.iges)


@pytest.fixture(scope="module", params=EXAMPLES)
def built(request, tmp_path_factory):
    return Built(request.param, tmp_path_factory.mktemp("cad"))


def _outer_edges(network) -> int:
    return sum(1 for e in network.edges().values() if e.curve_id in OUTER_CURVES
               and np.ptp(e.polyline.points, axis=0).max() > 1e-9)


def test_one_valid_shell_with_free_edges_only_on_the_outer_boundary(built):
    shape = built.shell.shape
    assert shape.ShapeType == "Shell" and shape.isValid()
    assert len(shape.Faces) == len(built.result.network.regions())
    gaps = cad.shell_seam_gaps(shape)
    assert gaps["free_edges"] == _outer_edges(built.result.network)
    interior = sum(1 for e in built.result.network.edges().values() if e.curve_id not in OUTER_CURVES)
    assert gaps["shared_edges"] == interior


def test_seams_are_closed_and_faces_follow_their_coons_patches(built):
    seams = cad.seam_stats(built.shell)
    assert len(seams) == sum(1 for e in built.result.network.edges().values() if e.curve_id not in OUTER_CURVES)
    assert max(s.gap_max_mm for s in seams) <= SEAM_GAP_MM
    assert cad.shell_seam_gaps(built.shell.shape)["seam_gap_max_mm"] <= SEAM_GAP_MM
    fit = cad.fit_deviation(built.shell, built.result.network)
    assert max(fit.values()) <= built.result.tol.fit_mm


def test_step_read_back_in_a_fresh_process_matches(built):
    back, shape = built.step_back, built.shell.shape
    assert "AUTOMOTIVE_DESIGN" in built.step.read_text(errors="replace")[:4000]   # AP214
    assert back["faces"] == len(shape.Faces) and back["shells"] == 1 and back["valid"]
    if built.bop:
        assert back["check_error"] == ""     # shape.check(True): BRepCheck and BOP analysis, no C0 faces
    assert abs(back["area_mm2"] - shape.Area) <= 1e-6 * shape.Area
    assert back["seam_gap_max_mm"] <= SEAM_GAP_MM
    assert back["free_edges"] == _outer_edges(built.result.network)


def test_iges_read_back_in_a_fresh_process_matches(built):
    back, shape = built.iges_back, built.shell.shape
    assert back["faces"] == len(shape.Faces) and back["shells"] == 1 and back["valid"]
    assert abs(back["area_mm2"] - shape.Area) <= 1e-6 * shape.Area
    assert back["seam_gap_max_mm"] <= SEAM_GAP_MM


def test_accepted_strokes_lie_on_the_exported_surface(built):
    """Distances measured on the STEP file's faces, read back in a fresh process."""
    assert built.kept, "no accepted stroke to check"
    d = np.asarray(built.step_back["point_distances_mm"])
    assert d.max() <= built.result.tol.snap_mm
    here = np.concatenate([cad.point_distances(built.shell, r.points) for r in built.kept])
    # the same surfaces, so the same distances, up to where a projection settles: near a seam
    # the two processes may stop at footpoints on different faces (clean4: 0.0014 vs 0.0003 mm
    # for one of 451 points); a quarter of the fit tolerance still catches a surface moved by
    # the export
    assert np.allclose(d, here, atol=max(1e-3, 0.25 * built.result.tol.fit_mm))

