"""Run a Python script inside the real FreeCAD GUI under Xvfb, and judge the run.

Usage from a GUI test (tests/gui/test_*.py)::

    from harness import run_in_freecad_gui, require_gui

    def test_something():
        require_gui()                       # skips, with a reason, when Xvfb/FreeCAD are absent
        run = run_in_freecad_gui('''
    Gui.activateWorkbench("ProgSurfWorkbench")
    doc = App.newDocument("T")
    Gui.runCommand("ProgSurf_ImportStrokes")
    doc.recompute()
    png = screenshot("after_import")         # saves the active 3D view, returns the path
    stats = image_stats(png)
    check(stats["stddev"] > 5, f"3D view is blank: {stats}")
    report("objects", [o.Name for o in doc.Objects])
    ''', timeout=240)
        assert run.ok, run.explain()
        assert "Stroke" in run.values["objects"][0]

The script runs in `freecad` (GUI, main window shown) started by `xvfb-run -a`, with a private
HOME whose FreeCAD Mod folder links this checkout, so the user's own settings and add-ons play
no part. Names available to the script:

    App, FreeCAD, Gui, FreeCADGui, QtCore, QtGui (PySide)
    OUT                        folder for the run's files (screenshots); `run.out_dir`
    check(condition, message)  records a failure when condition is false (the script goes on)
    report(key, value)         a JSON-safe value handed back in `run.values[key]`
    process_events(seconds=0.2)  lets Qt paint
    screenshot(name, width=800, height=600, background="White") -> path of the 3D view PNG
    grab_window(name) -> path of a PNG of the whole main window
    image_stats(path) -> {"width", "height", "mean", "stddev" (grey levels), "colours" (distinct
                          colours), "foreground" (share of pixels unlike the top-left one)}

A run fails (`run.ok` is False, `run.failures` says why) when: a `check` failed; the script
raised; a document object is invalid after the script (an exception inside recompute; pass
allow_invalid=True to expect that); FreeCAD's output holds "Traceback" or "Exception"; FreeCAD
crashed, exited non-zero or ran past `timeout`.
"""
from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
FAIL_WORDS = ("Traceback", "Exception")
RESULT_FILE = "result.json"

_PRELUDE = r'''
import json, os, sys, time, traceback
import FreeCAD, FreeCADGui
from PySide import QtCore, QtGui
App, Gui = FreeCAD, FreeCADGui
OUT = {out!r}
_RESULT = {{"failures": [], "values": {{}}, "checks": 0}}


def process_events(seconds=0.2):
    end = time.monotonic() + seconds
    while True:
        QtGui.QApplication.processEvents()
        if time.monotonic() >= end:
            break
        time.sleep(0.02)


def check(condition, message):
    _RESULT["checks"] += 1
    if not condition:
        _RESULT["failures"].append("check failed: " + str(message))


def report(key, value):
    _RESULT["values"][key] = value


def screenshot(name, width=800, height=600, background="White"):
    process_events()
    path = os.path.join(OUT, name + ".png")
    Gui.ActiveDocument.ActiveView.saveImage(path, width, height, background)
    return path


def grab_window(name):
    # From the X server, not QWidget.grab(): only the server's copy holds the OpenGL 3D view.
    process_events(0.5)
    path = os.path.join(OUT, name + ".png")
    mw = Gui.getMainWindow()
    QtGui.QApplication.primaryScreen().grabWindow(mw.winId()).save(path)
    return path


def image_stats(path):
    image = QtGui.QImage(path)
    if image.isNull():
        return {{"width": 0, "height": 0, "mean": 0.0, "stddev": 0.0, "colours": 0,
                "foreground": 0.0}}
    step = max(1, min(image.width(), image.height()) // 150)
    greys, colours, background, foreground = [], set(), image.pixel(0, 0) & 0xFFFFFF, 0
    for y in range(0, image.height(), step):
        for x in range(0, image.width(), step):
            rgb = image.pixel(x, y) & 0xFFFFFF
            colours.add(rgb)
            foreground += rgb != background
            red, green, blue = (rgb >> 16) & 255, (rgb >> 8) & 255, rgb & 255
            greys.append(0.299 * red + 0.587 * green + 0.114 * blue)
    mean = sum(greys) / len(greys)
    var = sum((g - mean) ** 2 for g in greys) / len(greys)
    return {{"width": image.width(), "height": image.height(), "mean": mean,
            "stddev": var ** 0.5, "colours": len(colours),
            "foreground": foreground / len(greys)}}


def _invalid_objects():
    bad = []
    for doc in App.listDocuments().values():
        for obj in doc.Objects:
            if not obj.isValid() or "Invalid" in obj.State or "Error" in obj.State:
                bad.append("{{}}.{{}} is invalid after the script: State={{}}".format(
                    doc.Name, obj.Name, obj.State))
    return bad


_code = 1
try:
    process_events(0.5)
    with open({user!r}, encoding="utf-8") as _f:
        exec(compile(_f.read(), {user!r}, "exec"), dict(globals()))
    process_events(0.2)
    if not {allow_invalid!r}:
        _RESULT["failures"].extend(_invalid_objects())
    _code = 0 if not _RESULT["failures"] else 3
except BaseException:
    traceback.print_exc()
    _RESULT["failures"].append("the script raised:\n" + traceback.format_exc())
    _code = 4
finally:
    with open(os.path.join(OUT, {result!r}), "w", encoding="utf-8") as _f:
        json.dump(_RESULT, _f, default=repr)
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(_code)
'''


@dataclass(frozen=True)
class GuiRun:
    """What one FreeCAD GUI run did. `values` is what the script passed to report()."""

    returncode: int | None
    output: str
    out_dir: Path
    failures: tuple[str, ...]
    values: dict = field(default_factory=dict)
    checks: int = 0

    @property
    def ok(self) -> bool:
        return not self.failures

    def explain(self) -> str:
        """The failures and the tail of FreeCAD's output, for an assertion message."""
        tail = "\n".join(self.output.splitlines()[-40:])
        return ("FreeCAD GUI run failed:\n  - " + "\n  - ".join(self.failures)
                + f"\n--- FreeCAD output (tail), files in {self.out_dir} ---\n{tail}")


def gui_unavailable_reason() -> str | None:
    """Why a GUI test cannot run here, or None when it can."""
    for tool in ("xvfb-run", "freecad", "xauth"):
        if shutil.which(tool) is None:
            return f"{tool} is not installed: run ./install.sh (apt packages xvfb, xauth, freecad)"
    return None


def require_gui() -> None:
    """Skip the calling test, with the reason, when the GUI cannot be started here."""
    reason = gui_unavailable_reason()
    if reason:
        pytest.skip(reason)


def _private_home(base: Path) -> Path:
    """A HOME whose FreeCAD Mod folder links this checkout and nothing else."""
    home = base / "home"
    mod = home / ".local" / "share" / "FreeCAD" / "Mod"
    mod.mkdir(parents=True)
    (mod / "ProgSurf").symlink_to(ROOT, target_is_directory=True)
    return home


def run_in_freecad_gui(script_text: str, timeout: float = 180.0, out_dir: Path | None = None,
                       allow_invalid: bool = False,
                       allowed_output: tuple[str, ...] = ()) -> GuiRun:
    """Run `script_text` inside the FreeCAD GUI under Xvfb and return the judged GuiRun.

    script_text    Python run after FreeCAD's main window is up (see the module docstring for
                   the helpers it can call); it need not end the process.
    timeout        seconds before FreeCAD is killed and the run fails.
    out_dir        where screenshots and result.json go; a new temporary folder by default.
    allow_invalid  do not fail on objects left invalid (a test that expects a recompute error).
    allowed_output lines of output containing one of these strings are not searched for
                   "Traceback"/"Exception" (for a message the test provokes on purpose).
    """
    work = Path(tempfile.mkdtemp(prefix="progsurf-gui-"))
    out = Path(out_dir) if out_dir else work / "out"
    out.mkdir(parents=True, exist_ok=True)
    user = work / "user_script.py"
    user.write_text(script_text, encoding="utf-8")
    runner = work / "run_gui_script.py"
    runner.write_text(_PRELUDE.format(out=str(out), user=str(user), result=RESULT_FILE,
                                      allow_invalid=allow_invalid), encoding="utf-8")
    runtime = work / "xdg-runtime"
    runtime.mkdir(mode=0o700)
    env = dict(os.environ, HOME=str(_private_home(work)), QTWEBENGINE_DISABLE_SANDBOX="1",
               XDG_RUNTIME_DIR=str(runtime), LANG="C.UTF-8", LC_ALL="C.UTF-8")
    for var in ("DISPLAY", "WAYLAND_DISPLAY", "QT_QPA_PLATFORM", "XDG_CONFIG_HOME",
                "XDG_DATA_HOME", "XDG_CACHE_HOME"):
        env.pop(var, None)
    command = ["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24", "freecad", str(runner)]
    proc = subprocess.Popen(command, cwd=work, env=env, stdin=subprocess.DEVNULL,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            start_new_session=True)
    failures = []
    try:
        output, _ = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        output, _ = proc.communicate()
        failures.append(f"FreeCAD did not finish within {timeout} s and was killed")
    text = output.decode("utf-8", errors="replace")
    (out / "freecad_output.txt").write_text(text, encoding="utf-8")

    result_path = out / RESULT_FILE
    values, checks = {}, 0
    if result_path.is_file():
        result = json.loads(result_path.read_text(encoding="utf-8"))
        failures.extend(result["failures"])
        values, checks = result["values"], result["checks"]
    else:
        failures.append("FreeCAD ended before the script finished (crash or early exit)")
    if proc.returncode not in (0, None) and not failures:
        failures.append(f"FreeCAD exited with code {proc.returncode}")
    for line in text.splitlines():
        if any(word in line for word in FAIL_WORDS) and not any(a in line for a in allowed_output):
            failures.append(f"FreeCAD output: {line.strip()}")
    return GuiRun(returncode=proc.returncode, output=text, out_dir=out,
                  failures=tuple(failures), values=values, checks=checks)
