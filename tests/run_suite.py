"""Run ProgSurf's whole test suite, three levels, and print one closing line of totals.

    1. core + app   pytest tests/core tests/app          (FreeCAD's Python, via .venv)
    2. freecad -t   freecadcmd -t TestProgSurfApp        (tests/app as FreeCAD users run them)
    3. gui          pytest tests/gui                     (real FreeCAD GUI under Xvfb)

Usage: .venv/bin/python tests/run_suite.py   (what `make test` runs, after ./install.sh)
Exit status 0 only when no level failed; the last line reads "N passed, N failed, N skipped".
Each level's output goes to the terminal as it runs; JUnit XML lands in out/test-results/.
"""
from __future__ import annotations

import importlib.util
import os
import re
import signal
import subprocess
import sys
import threading
import time
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
RESULTS = ROOT / "out" / "test-results"
# a loaded machine may need longer: PROGSURF_LEVEL_TIMEOUT_S=<seconds>
LEVEL_TIMEOUT_S = float(os.environ.get("PROGSURF_LEVEL_TIMEOUT_S", 20 * 60))
TEST_TIMEOUT_S = 600  # one hanging test fails alone (pytest-timeout) instead of the whole level
PYTEST_NO_TESTS = 5


@dataclass(frozen=True)
class LevelResult:
    name: str
    passed: int
    failed: int
    skipped: int
    seconds: float
    note: str = ""


def run_streaming(command: list[str], timeout: float) -> tuple[int, str]:
    """Run command from the repository root, echo its output live, return (status, output)."""
    print(f"\n=== {' '.join(command)}", flush=True)
    env = dict(os.environ, PYTHONUNBUFFERED="1", QTWEBENGINE_DISABLE_SANDBOX="1")
    proc = subprocess.Popen(command, cwd=ROOT, env=env, stdin=subprocess.DEVNULL,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            errors="replace")
    watchdog = threading.Timer(timeout, proc.kill)
    watchdog.start()
    lines = []
    try:
        for line in proc.stdout:
            sys.stdout.write(line)
            lines.append(line)
    finally:
        watchdog.cancel()
    sys.stdout.flush()
    status = proc.wait()
    if status == -signal.SIGKILL:
        print(f"run_suite: killed after {timeout} s", flush=True)
    return status, "".join(lines)


def junit_counts(path: Path) -> tuple[int, int, int]:
    """(passed, failed, skipped) from a pytest JUnit XML file; errors count as failures."""
    root = ET.parse(path).getroot()
    suites = [root] if root.tag == "testsuite" else list(root.iter("testsuite"))
    tests = sum(int(s.get("tests", 0)) for s in suites)
    failed = sum(int(s.get("failures", 0)) + int(s.get("errors", 0)) for s in suites)
    skipped = sum(int(s.get("skipped", 0)) for s in suites)
    return tests - failed - skipped, failed, skipped


def pytest_level(name: str, paths: list[str]) -> LevelResult:
    start = time.monotonic()
    xml = RESULTS / f"{name}.xml"
    xml.unlink(missing_ok=True)
    command = [sys.executable, "-m", "pytest", *paths, "-q", "-rs", f"--junitxml={xml}"]
    if importlib.util.find_spec("pytest_timeout") is not None:
        command.append(f"--timeout={TEST_TIMEOUT_S}")
    status, _ = run_streaming(command, LEVEL_TIMEOUT_S)
    seconds = time.monotonic() - start
    if status == PYTEST_NO_TESTS:
        return LevelResult(name, 0, 0, 0, seconds, "no tests collected")
    if not xml.is_file():
        return LevelResult(name, 0, 1, 0, seconds, f"pytest exited {status} without results")
    passed, failed, skipped = junit_counts(xml)
    if status != 0 and failed == 0:
        return LevelResult(name, passed, 1, skipped, seconds, f"pytest exited {status}")
    return LevelResult(name, passed, failed, skipped, seconds)


def parse_unittest_output(text: str) -> tuple[int, int, int] | None:
    """(passed, failed, skipped) from unittest's closing lines, or None when there are none."""
    ran = re.findall(r"^Ran (\d+) tests? in ", text, re.MULTILINE)
    status = re.findall(r"^(OK|FAILED)\b(?: \((.*)\))?\s*$", text, re.MULTILINE)
    if not ran or not status:
        return None
    total = int(ran[-1])
    verdict, details = status[-1]
    # unittest writes "expected failures=1" and "unexpected successes=1", with a space
    details = re.sub(r"(expected|unexpected) (failures|successes)", r"\1_\2", details or "")
    counts = {k: int(v) for k, v in re.findall(r"(\w+)=(\d+)", details)}
    failed = counts.get("failures", 0) + counts.get("errors", 0) \
        + counts.get("unexpected_successes", 0)
    if verdict == "FAILED" and failed == 0:
        failed = 1
    skipped = counts.get("skipped", 0) + counts.get("expected_failures", 0)
    return total - failed - skipped, failed, skipped


def _venv_site():
    """ProgSurf/venv_site.py, loaded by its path (standard library only, as Init.py does)."""
    spec = importlib.util.spec_from_file_location("progsurf_venv_site",
                                                  ROOT / "ProgSurf" / "venv_site.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def freecad_level() -> LevelResult:
    start = time.monotonic()
    link = Path.home() / ".local" / "share" / "FreeCAD" / "Mod" / "ProgSurf"
    if not link.exists() or link.resolve() != ROOT:
        return LevelResult("freecadcmd", 0, 1, 0, 0.0,
                           f"{link} does not lead to {ROOT}: run ./install.sh first")
    # FreeCAD finds TestProgSurfApp (tests/) only in a checkout install.sh marked as a
    # developer install (Init.py, ProgSurf/venv_site.py); an Addon Manager install has no tests
    marker = ROOT / _venv_site().INSTALL_MARKER
    if not marker.is_file():
        return LevelResult("freecadcmd", 0, 1, 0, 0.0,
                           f"{marker} is missing: run ./install.sh (it lets FreeCAD load tests/)")
    status, text = run_streaming(["freecadcmd", "-t", "TestProgSurfApp"], LEVEL_TIMEOUT_S)
    seconds = time.monotonic() - start
    counts = parse_unittest_output(text)
    if counts is None:
        return LevelResult("freecadcmd", 0, 1, 0, seconds, "no unittest summary in the output")
    passed, failed, skipped = counts
    if status != 0 and failed == 0:
        return LevelResult("freecadcmd", passed, 1, skipped, seconds, f"exit status {status}")
    return LevelResult("freecadcmd", passed, failed, skipped, seconds)


def main() -> int:
    RESULTS.mkdir(parents=True, exist_ok=True)
    levels = [pytest_level("core-app", ["tests/core", "tests/app"]),
              freecad_level(),
              pytest_level("gui", ["tests/gui"])]
    print("\n=== ProgSurf test suite")
    for lv in levels:
        note = f"  ({lv.note})" if lv.note else ""
        print(f"  {lv.name:<11} {lv.passed:4d} passed {lv.failed:4d} failed "
              f"{lv.skipped:4d} skipped  {lv.seconds:6.1f} s{note}")
    passed = sum(lv.passed for lv in levels)
    failed = sum(lv.failed for lv in levels)
    skipped = sum(lv.skipped for lv in levels)
    print(f"{passed} passed, {failed} failed, {skipped} skipped", flush=True)
    return 1 if failed or passed == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
