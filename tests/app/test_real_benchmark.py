"""benchmarks/real.py (issue 18's speed target on the real sketches), run as its README says on
sketches a user's clone has (the bundled examples), so that it cannot rot: what each line says is
what the build's own report says. No timing assertions."""
from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import tempfile
import unittest
from pathlib import Path

from ProgSurf.io import read_strokes
from ProgSurf.io.curves import write_curves

ROOT = Path(__file__).resolve().parents[2]
PYTHON = "/usr/bin/python3"
REAL = ROOT / "benchmarks" / "real.py"
SKETCHES = ("fig11_general.xyz", "three_sided.xyz")


def _run(*args: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, HOME=os.environ.get("HOME") or "/tmp")
    env.pop("PYTHONPATH", None)       # the command must find ProgSurf and FreeCAD by itself
    return subprocess.run([PYTHON, str(REAL), *args], cwd=str(ROOT), capture_output=True, text=True,
                          timeout=600, env=env)


class RealBenchmarkTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        data = Path(cls.tmp.name) / "data" / "some"
        data.mkdir(parents=True)
        for name in SKETCHES[:1]:
            shutil.copy(ROOT / "examples" / name, data / name)
        # the second as CASSIE writes its sketches: 'v N', then N points in metres
        write_curves(data / (SKETCHES[1][:-4] + ".curves"), read_strokes(ROOT / "examples" / SKETCHES[1]))
        # an .xyz beside a .curves of its name is the one measured (../shared holds CASSIE's as both)
        shutil.copy(ROOT / "examples" / SKETCHES[0], data / (SKETCHES[0][:-4] + ".curves"))
        cls.out = Path(cls.tmp.name) / "out"
        cls.proc = _run("--data", str(data.parent), "--out", str(cls.out))

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_each_line_says_what_the_builds_report_says(self):
        self.assertEqual(self.proc.returncode, 0, self.proc.stderr)
        lines = {ln.split()[0]: ln for ln in self.proc.stdout.splitlines() if re.match(r"\S+ +strokes ", ln)}
        self.assertEqual(sorted(lines), sorted(n[:-4] for n in SKETCHES))
        total = 0
        for name, ln in lines.items():
            report = json.loads((self.out / f"{name}.json").read_text())
            self.assertTrue((self.out / f"{name}.step").stat().st_size > 0)
            fields = dict(re.findall(r"(surfaces|faces|used|folding|creases) +(\d+)", ln))
            self.assertEqual(int(fields["surfaces"]), len(report["surfaces"]), ln)
            self.assertEqual(int(fields["faces"]), report["faces"], ln)
            self.assertEqual(int(fields["used"]), report["strokes_used"], ln)
            self.assertEqual(int(fields["folding"]), sum(1 for s in report["surfaces"] if s["folds"]), ln)
            total += len(report["surfaces"])
            wall, ratio = re.search(r"([\d.]+) s = +(\d+) x ref", ln).groups()
            self.assertGreater(float(wall), 0.0)
            self.assertGreater(int(ratio), 0)
        self.assertIn(f"SUMMARY real: built 2/2, surfaces {total},", self.proc.stdout)
        # the target is read on the sketch with the most strokes (fig11_general: 6 against 4)
        self.assertRegex(self.proc.stdout, r"largest sketch fig11_general \(6 strokes\): [\d.]+ s = \d+ x the "
                                           r"reference; target < 10 s: (met|NOT met)")
        self.assertEqual((self.out / "real.txt").read_text().splitlines()[-1].split(":")[0], "largest sketch fig11_general (6 strokes)")

    def test_without_sketches_it_says_there_is_nothing_to_measure(self):
        with tempfile.TemporaryDirectory() as empty:
            proc = _run("--data", empty)
            self.assertEqual(proc.returncode, 0, proc.stderr)
            self.assertIn("no sketches to measure", proc.stdout)
            proc = _run("--data", str(Path(empty) / "absent"))
            self.assertIn("is absent", proc.stdout)


if __name__ == "__main__":
    unittest.main()
