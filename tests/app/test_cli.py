"""The headless command line, run as a user would: /usr/bin/python3 -m ProgSurf build ..."""
from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
PYTHON = "/usr/bin/python3"
EXAMPLE = ROOT / "examples" / "fig9_sections.xyz"


def run(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess:
    env = dict(os.environ, HOME=os.environ.get("HOME", "/tmp"))
    env.pop("PYTHONPATH", None)   # the command must find FreeCAD and ProgSurf by itself
    return subprocess.run([PYTHON, "-m", "ProgSurf", *args], cwd=cwd, capture_output=True, text=True,
                          timeout=600, env=env)


def c3d_for_the_command() -> bool:
    """Whether the command can import the c3d package: from this checkout's .venv (where it looks,
    as Init.py does) or from its own Python. This process may import it from elsewhere (another
    checkout's .venv, appended by FreeCAD's user Mod folder), so that is not asked."""
    if any(ROOT.glob(".venv/lib/python3*/site-packages/c3d/__init__.py")):
        return True
    return subprocess.run([PYTHON, "-c", "import c3d"], capture_output=True).returncode == 0


@pytest.fixture(scope="module")
def success(tmp_path_factory):
    if not EXAMPLE.exists():
        pytest.skip(f"{EXAMPLE.name} not written yet")
    tmp = tmp_path_factory.mktemp("cli")
    out = {k: tmp / f"out.{k}" for k in ("step", "igs", "json", "png")}
    proc = run("build", str(EXAMPLE), "-o", str(out["step"]), "--iges", str(out["igs"]),
               "--report", str(out["json"]), "--png", str(out["png"]))
    return proc, out


def test_build_writes_step_iges_png_and_report(success):
    proc, out = success
    assert proc.returncode == 0, proc.stderr
    report = json.loads(out["json"].read_text())
    from ProgSurf import cad

    back = cad.read_back(out["step"])
    assert back["faces"] == report["faces"] > 0 and back["shells"] == 1 and back["valid"]
    assert cad.read_back(out["igs"])["faces"] == report["faces"]
    assert out["png"].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert report["seam_gap_max_mm"] <= 1e-7
    assert report["fit_deviation_max_mm"] <= report["tolerances"]["fit_mm"]
    assert {"read", "boundary", "base", "fit", "export"} <= set(report["timings_s"])
    assert len(report["poles_per_face"]) == report["faces"]
    strokes = report["strokes"]
    assert [s["index"] for s in strokes] == list(range(len(strokes)))
    assert all(s["role"] in ("boundary", "interior") and s["status"] in ("accepted", "rejected") for s in strokes)
    assert f"{report['faces']} faces" in proc.stdout


def test_strokes_from_several_files_are_taken_in_order(tmp_path):
    if not EXAMPLE.exists():
        pytest.skip(f"{EXAMPLE.name} not written yet")
    blocks = EXAMPLE.read_text().strip().split("\n\n")
    (tmp_path / "a.xyz").write_text("\n\n".join(blocks[:4]) + "\n")
    (tmp_path / "b.xyz").write_text("\n\n".join(blocks[4:]) + "\n")
    proc = run("build", str(tmp_path / "a.xyz"), str(tmp_path / "b.xyz"), "-o", str(tmp_path / "o.step"),
               "--report", str(tmp_path / "o.json"), "--boundary-count", "4", "-q")
    assert proc.returncode == 0, proc.stderr
    report = json.loads((tmp_path / "o.json").read_text())
    assert [s["role"] for s in report["strokes"][:4]] == ["boundary"] * 4
    from ProgSurf.io import read_strokes

    assert len(report["strokes"]) == len(read_strokes(EXAMPLE))


def test_a_one_patch_surface_is_exported_as_a_shell_of_one_face(tmp_path):
    """The method's base case, boundary strokes only (issue 17): one face, written and read back
    as one shell (OCC's sewing of one face gives no shell; it was exit 1 "0 shells")."""
    blocks = (ROOT / "examples" / "clean4.xyz").read_text().strip().split("\n\n")
    (tmp_path / "b.xyz").write_text("\n\n".join(blocks[:4]) + "\n")
    proc = run("build", str(tmp_path / "b.xyz"), "-o", str(tmp_path / "o.step"), "--report",
               str(tmp_path / "o.json"), "-q")
    assert proc.returncode == 0, proc.stderr
    report = json.loads((tmp_path / "o.json").read_text())
    assert report["faces"] == 1 and report["shell"]["valid"]
    from ProgSurf.cad import read_back

    back = read_back(str(tmp_path / "o.step"))
    assert back["faces"] == 1 and back["shells"] == 1


def _bad_boundary(path: Path) -> None:
    """Four short strokes at the corners of a 1 m square: gaps far wider than any closing limit."""
    t = np.linspace(0, 1, 10)[:, None]
    strokes = [np.array([0, 0, 0]) + t * [10, 0, 0], np.array([1000, 0, 0]) + t * [0, 10, 0],
               np.array([1000, 1000, 0]) - t * [10, 0, 0], np.array([0, 1000, 0]) - t * [0, 10, 0]]
    path.write_text("\n\n".join("\n".join(" ".join(f"{v:.3f}" for v in p) for p in s) for s in strokes) + "\n")


@pytest.mark.parametrize("case", ["missing", "malformed", "open_boundary", "bad_option"])
def test_bad_input_exits_2_with_one_line(tmp_path, case):
    stroke_file = tmp_path / "s.xyz"
    extra: list = []
    if case == "missing":
        stroke_file = tmp_path / "nope.xyz"
    elif case == "malformed":
        stroke_file.write_text("0 0 0\n1 0 0\n1 x 0\n")
    elif case == "open_boundary":
        _bad_boundary(stroke_file)
    else:
        _bad_boundary(stroke_file)
        extra = ["--fit-tol", "-1"]
    proc = run("build", str(stroke_file), "-o", str(tmp_path / "o.step"), *extra)
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in proc.stderr
    expected = {"missing": "nope.xyz", "malformed": "line 3", "open_boundary": "gap",
                "bad_option": "--fit-tol"}[case]
    assert expected in lines[0]
    assert not (tmp_path / "o.step").exists()


def test_c3d_input_takes_marker_labels(tmp_path):
    """A motion-capture file builds end to end with --markers; an unknown label is bad input."""
    if not c3d_for_the_command():
        pytest.skip("the c3d package is not installed for the command: .venv/bin/pip install c3d "
                    "(./install.sh does)")
    c3d = ROOT / "examples" / "sketch_mocap.c3d"
    report = tmp_path / "mocap.json"
    ok = run("build", str(c3d), "-o", str(tmp_path / "mocap.step"), "--markers", "pen",
             "--report", str(report), "-q")
    assert ok.returncode == 0, ok.stderr
    data = json.loads(report.read_text())
    assert [s["role"] for s in data["strokes"]] == ["boundary"] * 4 + ["interior"] * 2
    assert data["faces"] >= 2
    bad = run("build", str(c3d), "-o", str(tmp_path / "x.step"), "--markers", "NOPE")
    assert bad.returncode == 2
    assert "NOPE" in bad.stderr and "PEN" in bad.stderr and "Traceback" not in bad.stderr


def test_skin_writes_one_exchange_surface_on_the_patches(tmp_path):
    """--skin (paper section 3.3): OUT_skin.step holds one B-spline face lying within the fit
    tolerance of the patch network, checked here independently of the command's own report."""
    example = ROOT / "examples" / "clean4.xyz"
    step, report = tmp_path / "c.step", tmp_path / "c.json"
    proc = run("build", str(example), "-o", str(step), "--skin", "--report", str(report), "-q")
    assert proc.returncode == 0, proc.stderr
    data = json.loads(report.read_text())
    skin_step = Path(data["outputs"]["skin_step"])
    assert skin_step == tmp_path / "c_skin.step"
    import FreeCAD  # noqa: F401  (before Part)
    import Part

    from ProgSurf.core.pipeline import build_network
    from ProgSurf.io import read_strokes

    skin = Part.read(str(skin_step))
    assert len(skin.Faces) == 1 and skin.isValid()
    surface = skin.Faces[0].Surface
    assert (surface.NbUPoles, surface.NbVPoles) == (data["skin"]["u_poles"], data["skin"]["v_poles"])
    # the same strokes through the core give the network the skin was made from
    net = build_network(read_strokes(example)).network
    g = np.linspace(0.0, 1.0, 23)
    uv = np.array([(a, b) for a in g for b in g])
    dist = [skin.distToShape(Part.Vertex(FreeCAD.Vector(*map(float, p))))[0]
            for p in np.asarray(net.evaluate_uv(uv))]
    fit = data["tolerances"]["fit_mm"]
    assert max(dist) <= fit + 1e-6, max(dist)
    assert data["skin"]["deviation_max_mm"] <= fit
    # the exchange surface spans the same area as the patches (to the skin's own deviation)
    patches = Part.read(str(step))
    assert skin.Area == pytest.approx(patches.Area, rel=1e-3)


def test_a_stroke_drawn_off_the_surface_is_moved_onto_it_and_the_summary_says_so(tmp_path):
    """A flat 100 mm square, two sections on it, and a third stroke across them drawn 2 mm above
    the plane all along (the snap distance is 2.8 mm): it is put on the plane and its line says so;
    the report's note for it is the same."""
    t = np.linspace(0.0, 1.0, 41)[:, None]
    o = np.zeros_like(t)
    strokes = [np.hstack([100 * t, o, o]), np.hstack([100 + o, 100 * t, o]),
               np.hstack([100 - 100 * t, 100 + o, o]), np.hstack([o, 100 - 100 * t, o]),
               np.hstack([30 + o, 100 * t, o]), np.hstack([70 + o, 100 * t, o]),
               np.hstack([-1 + 102 * t, 50 + o, 2 + o])]
    path = tmp_path / "lifted.xyz"
    path.write_text("\n\n".join("\n".join(" ".join(f"{v:.6f}" for v in p) for p in s) for s in strokes) + "\n")
    out = run("build", str(path), "-o", str(tmp_path / "lifted.step"), "--report", str(tmp_path / "r.json"))
    assert out.returncode == 0, out.stderr
    line = next(x for x in out.stdout.splitlines() if x.startswith("  stroke 6 "))
    assert "accepted; it missed the" in line and "by 2 mm alike (drawn off the surface): moved onto them" in line
    report = json.loads((tmp_path / "r.json").read_text())
    assert line.split("accepted; ")[1] in report["strokes"][6]["reason"]
    # the surface stays on the plane (pulled to the stroke as drawn, it would rise 2 mm)
    import FreeCAD  # noqa: F401  (before Part)
    import Part
    box = Part.read(str(tmp_path / "lifted.step")).BoundBox
    assert max(abs(box.ZMin), abs(box.ZMax)) < 0.01
