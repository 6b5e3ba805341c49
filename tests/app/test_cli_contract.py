"""The command line's contract on a fixed corpus of bad and odd inputs (issue 17).

For every input: exit 0 (built: one valid shell), 2 (refused: ONE line on stderr naming the problem)
or 3 (built, with a quality warning); never 1, never a traceback, never a hang (every run has a
subprocess timeout and a bound on its time); outputs are never written over an input or over each
other, and a refused run writes nothing.
"""
from __future__ import annotations

import json
import os
import subprocess
import time
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
PYTHON = "/usr/bin/python3"
EXAMPLES = ROOT / "examples"
REFUSE_S = 30.0
"""A refusal comes before the build: well within this, even on a loaded machine (about 1 s idle)."""
BUILD_S = 240.0
"""A bundled example builds within this on a loaded 2-core machine (2 to 20 s idle)."""


def run(*args: str, timeout: float = BUILD_S) -> tuple[subprocess.CompletedProcess, float]:
    env = dict(os.environ, HOME=os.environ.get("HOME", "/tmp"))
    env.pop("PYTHONPATH", None)
    clock = time.monotonic()
    proc = subprocess.run([PYTHON, "-m", "ProgSurf", "build", *args], cwd=ROOT, capture_output=True,
                          text=True, timeout=timeout, env=env)
    return proc, time.monotonic() - clock


def assert_refused(proc: subprocess.CompletedProcess, seconds: float, *words: str) -> str:
    """Exit 2, one stderr line naming the problem (each of `words`), no traceback, quickly."""
    lines = proc.stderr.strip().splitlines()
    assert proc.returncode == 2, (proc.returncode, proc.stderr[-2000:])
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith("progsurf: error: ") and "Traceback" not in proc.stderr
    for w in words:
        assert w in lines[0], (w, lines[0])
    assert seconds < REFUSE_S
    return lines[0]


def assert_built(proc: subprocess.CompletedProcess, step: Path) -> dict:
    """Exit 0 or 3; 3 names the quality warning in one line; the STEP reads back as one valid shell."""
    assert proc.returncode in (0, 3), (proc.returncode, proc.stderr[-2000:])
    assert "Traceback" not in proc.stderr
    if proc.returncode == 3:
        assert "quality: WARNING" in proc.stdout + proc.stderr
    from ProgSurf import cad

    back = cad.read_back(step)
    assert back["shells"] == 1 and back["valid"] and back["faces"] >= 1, back
    return back


def strokes_of(name: str) -> list:
    from ProgSurf.io import read_strokes

    return read_strokes(EXAMPLES / name)


def write(path: Path, strokes) -> Path:
    from ProgSurf.io import write_point_list

    write_point_list(path, strokes, decimals=9)
    return path


# --- options: ranges and argparse's own refusals, one line each ------------------------------------

@pytest.mark.parametrize("options, words", [
    (["--fit-tol", "inf"], ["--fit-tol inf", "finite"]),
    (["--fit-tol", "nan"], ["--fit-tol nan"]),
    (["--fit-tol", "1e-9"], ["--fit-tol 1e-09", "give", "automatic"]),
    (["--snap", "-inf"], ["--snap -inf"]),
    (["--filter", "0"], ["--filter 0"]),
    (["--min-length", "-1"], ["--min-length -1"]),
    (["--smooth", "-3"], ["--smooth -3"]),
    (["--boundary-count", "2.5"], ["--boundary-count", "'2.5'"]),
    (["--boundary-count", "2"], ["--boundary-count 2", "at least 3"]),
    (["--continuity", "G2"], ["--continuity", "'G2'"]),
    (["--no-such-option"], ["--no-such-option"]),
])
def test_a_bad_option_is_refused_in_one_line_before_any_work(tmp_path, options, words):
    out = tmp_path / "out.step"
    proc, seconds = run(str(EXAMPLES / "clean4.xyz"), "-o", str(out), *options)
    assert_refused(proc, seconds, *words)
    assert not out.exists()


def test_a_command_without_inputs_is_refused_in_one_line():
    proc, seconds = run()
    assert_refused(proc, seconds, "required")


# --- outputs: never an input, another output, a directory or an unwritable place -----------------

def test_outputs_that_would_damage_something_are_refused_with_the_path_named(tmp_path):
    folder = tmp_path / "a_folder"
    folder.mkdir()
    strokes = tmp_path / "strokes.xyz"
    strokes.write_bytes((EXAMPLES / "clean4.xyz").read_bytes())
    before = strokes.read_bytes()
    out = tmp_path / "out.step"
    cases = [
        (["-o", str(folder)], [str(folder), "directory"]),
        (["-o", str(out), "--iges", str(folder)], ["--iges", str(folder), "directory"]),
        (["-o", str(out), "--fcstd", str(folder)], ["--fcstd", str(folder), "directory"]),
        (["-o", str(strokes)], [str(strokes), "input"]),
        (["-o", str(out), "--report", str(strokes)], ["--report", "input"]),
        (["-o", str(out), "--report", str(out)], ["--report", str(out), "-o"]),
        (["-o", str(out), "--skin", "--iges", str(tmp_path / "out_skin.step")], ["--skin", "--iges"]),
        (["-o", str(tmp_path / "missing" / "out.step")], [str(tmp_path / "missing"), "does not exist"]),
    ]
    for options, words in cases:
        proc, seconds = run(str(strokes), *options)
        assert_refused(proc, seconds, *words)
    assert strokes.read_bytes() == before
    assert folder.is_dir() and not any(folder.iterdir())
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a_folder", "strokes.xyz"]


def test_an_output_in_a_folder_this_user_cannot_write_is_refused_before_the_build(tmp_path):
    if os.geteuid() == 0:      # root writes any folder with permission bits; /sys refuses it too
        folder = Path("/sys")
    else:
        folder = tmp_path / "read_only"
        folder.mkdir()
        folder.chmod(0o555)
    proc, seconds = run(str(EXAMPLES / "clean4.xyz"), "-o", str(folder / "out.step"))
    assert_refused(proc, seconds, str(folder / "out.step"), "cannot write")


# --- inputs that cannot be finished in bounded time or at all: refused up front -------------------

def test_two_thousand_short_strokes_are_refused_at_once_with_the_count(tmp_path):
    from ProgSurf.cli import MAX_STROKES

    rng = np.random.default_rng(17)
    boundary = strokes_of("clean4.xyz")[:4]
    short = [np.column_stack([c[0] + np.linspace(0, 3, 5), np.full(5, c[1]), np.zeros(5)])
             for c in 10 + 60 * rng.random((2000, 2))]
    path = write(tmp_path / "many.xyz", boundary + short)
    proc, seconds = run(str(path), "--boundary-count", "4", "-o", str(tmp_path / "o.step"))
    assert_refused(proc, seconds, "2004 strokes", f"at most {MAX_STROKES}")


def test_too_many_points_are_refused_with_the_count(tmp_path):
    from ProgSurf.cli import MAX_POINTS

    t = np.linspace(0.0, 1.0, MAX_POINTS // 4 + 1)
    sides = [np.column_stack([100 * t, 0 * t, 0 * t]), np.column_stack([100 + 0 * t, 80 * t, 0 * t]),
             np.column_stack([100 - 100 * t, 80 + 0 * t, 0 * t]), np.column_stack([0 * t, 80 - 80 * t, 0 * t])]
    path = write(tmp_path / "dense.xyz", sides)
    proc, seconds = run(str(path), "-o", str(tmp_path / "o.step"))
    assert_refused(proc, seconds, f"{4 * len(t)} points", str(MAX_POINTS))


def test_a_sketch_scaled_beyond_occs_precision_is_refused_with_its_size(tmp_path):
    path = write(tmp_path / "huge.xyz", [s * 1e10 for s in strokes_of("clean4.xyz")])
    proc, seconds = run(str(path), "-o", str(tmp_path / "o.step"))
    assert_refused(proc, seconds, "mm across", "scale it")


def test_a_c3d_file_without_a_frame_rate_is_refused_in_one_line(tmp_path):
    pytest.importorskip("c3d")
    import struct
    import sys

    sys.path.insert(0, str(ROOT / "tests" / "core"))
    from c3d_fixtures import write_c3d

    t = np.linspace(0.0, 1.0, 200)
    pts = np.zeros((200, 1, 3))
    pts[:, 0, 0], pts[:, 0, 1] = 100 * t, 10 * np.sin(6 * t)
    path = write_c3d(tmp_path / "rate0.c3d", pts, ["PEN"], rate=123.0)   # the writer refuses rate 0
    raw = path.read_bytes()
    assert raw.count(struct.pack("<f", 123.0)) == 2          # the header's rate and POINT:RATE
    path.write_bytes(raw.replace(struct.pack("<f", 123.0), struct.pack("<f", 0.0)))
    proc, seconds = run(str(path), "-o", str(tmp_path / "o.step"))
    assert_refused(proc, seconds, "POINT:RATE is 0")


# --- inputs that used to fail or hang, and build now -----------------------------------------------

def test_a_comment_between_two_strokes_separates_them():
    from ProgSurf.io import read_point_list

    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "c.xyz"
        path.write_text("# two strokes\n0 0 0\n1 0 0\n2 0 0\n# stroke 2\n0 1 0\n1 1 0\n")
        strokes = read_point_list(path)
    assert [len(s) for s in strokes] == [3, 2]


def test_the_smallest_fit_tolerance_allowed_builds_in_bounded_time(tmp_path):
    from ProgSurf.cli import FIT_FRACTION_RANGE
    from ProgSurf.core.strokes import sketch_diagonal

    strokes = strokes_of("clean4.xyz")
    smallest = FIT_FRACTION_RANGE[0] * sketch_diagonal(np.vstack(strokes)) * 1.01
    out = tmp_path / "o.step"
    proc, seconds = run(str(EXAMPLES / "clean4.xyz"), "-o", str(out), "--fit-tol", f"{smallest:.6g}", "-q")
    assert_built(proc, out)


def test_a_fit_tolerance_too_large_for_the_sketch_is_clamped_with_a_note(tmp_path):
    out, report = tmp_path / "o.step", tmp_path / "o.json"
    proc, _ = run(str(EXAMPLES / "clean4.xyz"), "-o", str(out), "--report", str(report), "--fit-tol", "1e6",
                  "-q")
    assert_built(proc, out)
    assert "note: --fit-tol 1e+06 mm" in proc.stderr
    assert json.loads(report.read_text())["tolerances"]["fit_mm"] < 1e6


@pytest.mark.parametrize("name", ["clean4.xyz", "fig11_general.xyz"])
def test_an_example_scaled_by_1000_builds(tmp_path, name):
    path = write(tmp_path / f"big_{name}", [s * 1000.0 for s in strokes_of(name)])
    out = tmp_path / "o.step"
    proc, _ = run(str(path), "-o", str(out), "-q")
    assert_built(proc, out)


def test_skin_of_the_three_sided_example_is_written(tmp_path):
    """The collapsed top side of three_sided (OCC could not interpolate its one-point section)."""
    out, report = tmp_path / "o.step", tmp_path / "o.json"
    proc, _ = run(str(EXAMPLES / "three_sided.xyz"), "-o", str(out), "--skin", "--report", str(report), "-q")
    assert_built(proc, out)
    data = json.loads(report.read_text())
    from ProgSurf import cad

    skin = cad.read_back(data["outputs"]["skin_step"])
    assert skin["faces"] == 1 and skin["valid"]
    # the skin's deviation is reported, and over the fit tolerance it is a quality warning (exit 3)
    over = data["skin"]["deviation_max_mm"] > data["tolerances"]["fit_mm"]
    assert (proc.returncode == 3) == (over or not data["quality"]["ok"])


def test_the_fcstd_holds_the_surface_the_build_asked_for(tmp_path):
    out, doc = tmp_path / "o.step", tmp_path / "o.FCStd"
    proc, _ = run(str(EXAMPLES / "clean4.xyz"), "-o", str(out), "--fcstd", str(doc), "--continuity", "G1",
                  "--fit-tol", "0.02", "-q")
    assert_built(proc, out)
    script = (
        "import sys, json; sys.path.append('/usr/lib/freecad-python3/lib'); import FreeCAD\n"
        f"sys.path.insert(0, {str(ROOT)!r})\n"
        f"d = FreeCAD.openDocument({str(doc)!r})\n"
        "s = [o for o in d.Objects if hasattr(o, 'Continuity')][0]\n"
        "print(json.dumps({'continuity': s.Continuity, 'fit': s.FitTolerance, 'skin': s.Skin,\n"
        "                  'shell': len(d.getObject('ExportedShell').Shape.Faces)}))\n")
    env = dict(os.environ, HOME=os.environ.get("HOME", "/tmp"))
    back = subprocess.run([PYTHON, "-c", script], capture_output=True, text=True, timeout=120, env=env, cwd=ROOT)
    held = json.loads([ln for ln in back.stdout.splitlines() if ln.startswith("{")][-1])
    assert held["continuity"] == "G1" and held["fit"] == pytest.approx(0.02) and not held["skin"]
    assert held["shell"] >= 1


def test_an_unexpected_error_is_one_line_asking_for_a_report(monkeypatch, capsys, tmp_path):
    """The last-resort net of main: any exception that is not the project's own is exit 2, one line."""
    from ProgSurf import cli

    def broken(args, out=None):
        raise KeyError("no such region")

    monkeypatch.setattr(cli, "run_build", broken)
    code = cli.main(["build", str(EXAMPLES / "clean4.xyz"), "-o", str(tmp_path / "o.step")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == cli.EXIT_BAD_INPUT and len(err) == 1
    assert err[0].startswith("progsurf: internal error: KeyError") and "report" in err[0]


# --- real sketches (../shared/data): build, or refuse in one line; never 1, never a hang ---------

@pytest.mark.parametrize("name, boundary", [("full_nacelle", [0, 9, 4, 5]), ("fuselage1", [0, 18, 9, 10])])
def test_tigl_networks_with_their_boundary_first_build(shared_data, tmp_path, name, boundary):
    from ProgSurf.io import read_strokes

    strokes = read_strokes(shared_data / "tigl" / name / f"{name}.noisy.xyz")
    order = boundary + [i for i in range(len(strokes)) if i not in boundary]
    path = write(tmp_path / f"{name}.xyz", [strokes[i] for i in order])
    out = tmp_path / "o.step"
    proc, _ = run(str(path), "--boundary-count", "4", "-o", str(out), "-q")
    assert_built(proc, out)


def test_a_shell_sewn_onto_itself_is_refused_not_written_invalid(tmp_path):
    """fuzz seed 17 case 235: the TiGL fuselage1 tube, boundary first, lies on itself (its end rings,
    narrower than the filter distance, are filtered to lines out and back); OCC sewed a shell that
    BRepCheck passes, 178 mm apart along an edge its faces share, and the STEP file read back invalid
    (exit 3). It is refused in one line, and nothing is written."""
    import sys

    sys.path.insert(0, str(EXAMPLES))
    from real_data_trial import tigl_boundary

    path = ROOT.parent / "shared" / "data" / "tigl" / "fuselage1" / "fuselage1.clean.xyz"
    if not path.is_file():
        pytest.skip(f"the TiGL sketch {path} is not there (../shared/data is beside the project's own checkout only)")
    from ProgSurf.io import read_strokes
    from ProgSurf.io.pointlist import write_point_list

    strokes = read_strokes(path)
    first = tigl_boundary(path)
    ordered = [strokes[i] for i in first] + [s for i, s in enumerate(strokes) if i not in first]
    sketch = tmp_path / "fuselage1.xyz"
    write_point_list(sketch, ordered)
    step = tmp_path / "out.step"
    proc, seconds = run(str(sketch), "-o", str(step), "--boundary-count", str(len(first)), "-q")
    # refused after the build (the time bound of a refusal before any work does not apply)
    assert_refused(proc, 0.0, "apart along an edge they share", "lies on itself")
    assert seconds < BUILD_S and not step.exists()
