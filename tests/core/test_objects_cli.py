"""`build --surfaces all` on the command line (ProgSurf.object_cli): a cube's twelve edges give a
STEP file of one closed shell of six faces, and the report accounts for every stroke; and the real
sketches of ../shared/data each build (skipped with the reason where that folder is absent)."""
from __future__ import annotations

import itertools
import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT.parent / "shared" / "data"
REAL = sorted(DATA.glob("cassie/*.xyz")) + sorted(DATA.glob("tigl/*/*.clean.xyz")) if DATA.is_dir() else []


def run(*args: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, HOME=os.environ.get("HOME", "/tmp"))
    env.pop("PYTHONPATH", None)
    return subprocess.run(["/usr/bin/python3", "-m", "ProgSurf", *args], cwd=ROOT, capture_output=True,
                          text=True, timeout=900, env=env)


def write_cube(path: Path) -> None:
    v = np.array(list(itertools.product([0, 1], [0, 1], [0, 1])), float) * 20.0
    lines = []
    for a in range(8):
        for b in range(a + 1, 8):
            if np.sum(v[a] != v[b]) == 1:
                lines += [f"{x:.6f} {y:.6f} {z:.6f}" for x, y, z in np.linspace(v[a], v[b], 15)] + [""]
    path.write_text("\n".join(lines))


def test_cube_edges_build_one_closed_shell_through_the_command(tmp_path):
    src = tmp_path / "cube.xyz"
    write_cube(src)
    step, report_path = tmp_path / "cube.step", tmp_path / "cube.json"
    proc = run("build", str(src), "-o", str(step), "--report", str(report_path))   # auto: a closed shell -> all
    assert proc.returncode == 0, proc.stderr + proc.stdout
    report = json.loads(report_path.read_text())
    assert report["mode"] == "all" and len(report["surfaces"]) == 6
    assert [(s["faces"], s["closed"], s["valid"], s["free_edges"]) for s in report["shells"]] == [(6, True, True, 0)]
    assert all(len(s["boundary_of"]) == 2 for s in report["strokes"])
    from ProgSurf import cad

    back = cad.read_back(step)
    assert back["faces"] == 6 and back["shells"] == 1 and back["valid"]


def test_surfaces_one_keeps_the_single_surface(tmp_path):
    src = ROOT / "examples" / "clean4.xyz"
    report_path = tmp_path / "one.json"
    proc = run("build", str(src), "-o", str(tmp_path / "one.step"), "--report", str(report_path), "--surfaces", "one")
    assert proc.returncode == 0, proc.stderr
    assert "mode" not in json.loads(report_path.read_text())


@pytest.mark.skipif(not REAL, reason=f"shared sketch data not found at {DATA}")
@pytest.mark.parametrize("path", REAL, ids=[p.name for p in REAL])
def test_real_sketch_builds_every_surface(path, tmp_path):
    report_path = tmp_path / "r.json"
    proc = run("build", str(path), "-o", str(tmp_path / "r.step"), "--report", str(report_path), "--surfaces", "all",
               "-q")
    assert proc.returncode in (0, 3), proc.stderr           # built (3: with a quality warning, named)
    report = json.loads(report_path.read_text())
    assert report["surfaces"] and all(s["valid"] for s in report["shells"])
    # every stroke accounted for: a surface it bounds or is inside, or the reason it is unused
    from ProgSurf.io import read_strokes

    assert [s["index"] for s in report["strokes"]] == list(range(len(read_strokes(path))))
    assert all(s["used"] or s["reason"] for s in report["strokes"])
