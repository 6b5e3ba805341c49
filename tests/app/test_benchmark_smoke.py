"""The benchmark (issue 8) at its smallest size, run as the README says, so that it cannot rot.

Checks the structure and sanity of the numbers, never their speed: no timing assertions.
"""
from __future__ import annotations

import json
import math
import os
import subprocess
import tempfile
import unittest
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PYTHON = "/usr/bin/python3"
RUN = ROOT / "benchmarks" / "run.py"


def _finite(x) -> bool:
    return isinstance(x, (int, float)) and math.isfinite(x)


class BenchmarkSmokeTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        if not RUN.exists():
            raise unittest.SkipTest("benchmarks/run.py is missing")
        cls.tmp = tempfile.TemporaryDirectory()
        out = Path(cls.tmp.name)
        env = dict(os.environ, HOME=os.environ.get("HOME") or "/tmp")
        env.pop("PYTHONPATH", None)   # the command must find ProgSurf and FreeCAD by itself
        cls.proc = subprocess.run([PYTHON, str(RUN), "--smoke", "--out", str(out)], cwd=str(ROOT),
                                  capture_output=True, text=True, timeout=900, env=env)
        cls.out = out
        cls.raw = json.loads((out / "bench.json").read_text()) if (out / "bench.json").exists() else None

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_command_succeeds_and_writes_table_plot_json(self):
        self.assertEqual(self.proc.returncode, 0, self.proc.stderr[-2000:])
        md = (self.out / "bench.md").read_text()
        self.assertEqual(md.strip(), self.proc.stdout.strip())
        for heading in ("Interactive latency", "Surface::Filling", "Scale", "Profile", "Quality"):
            self.assertIn(heading, md)
        self.assertEqual((self.out / "bench.png").read_bytes()[:8], b"\x89PNG\r\n\x1a\n")

    def test_latency_rows_cover_every_size_with_finite_times(self):
        rows = self.raw["latency"]
        self.assertEqual([r["target"] for r in rows], self.raw["config"]["sizes"])
        for r in rows:
            self.assertGreaterEqual(r["regions"], r["target"])
            for key in ("core", "incremental", "full_shell"):
                self.assertGreater(r[key]["n"], 0, (r["target"], key))
                self.assertTrue(_finite(r[key]["median_ms"]) and r[key]["median_ms"] > 0)
                self.assertGreaterEqual(r[key]["p95_ms"], r[key]["median_ms"])
            # adding faces can only cost more than the core step it contains
            self.assertGreater(r["full_shell"]["median_ms"], r["core"]["median_ms"])

    def test_peer_rows_have_every_tool_and_sane_deviations(self):
        cfg = self.raw["config"]
        rows = self.raw["peers"]
        self.assertEqual([(r["surface"], r["k"]) for r in rows],
                         [(s, k) for s in cfg["surfaces"] for k in cfg["ks"]])
        for r in rows:
            tools = ("progsurf", "filling", "coons") if r["k"] == 0 else ("progsurf", "filling")
            self.assertEqual("coons" in r, r["k"] == 0)
            for name in tools:
                e = r[name]
                self.assertTrue(e["ok"], (r["surface"], r["k"], name, e))
                truth = e["truth"]
                self.assertTrue(_finite(truth["max_mm"]) and _finite(truth["rms_mm"]))
                self.assertLessEqual(truth["rms_mm"], truth["max_mm"])
                self.assertGreater(truth["samples"], 100)
                # every tool interpolates the boundary of a smooth 60 mm-high surface: within 5 mm
                self.assertLess(truth["max_mm"], 5.0, (r["surface"], r["k"], name))
                self.assertTrue(_finite(e["curve_dev_mm"]))
                self.assertGreaterEqual(e["poles"]["mean"], 16)   # at least a bicubic patch
            self.assertTrue(_finite(r["time_ratio"]) and r["time_ratio"] > 0)
            self.assertEqual(r["progsurf"]["poles"]["faces"], r["progsurf"]["regions"])

    def test_scale_exports_and_reads_back_the_same_faces(self):
        s = self.raw["scale"]
        self.assertEqual(s["strokes"], self.raw["config"]["scale_strokes"])
        for name in ("pipeline", "fit_checked"):
            b = s[name]
            self.assertTrue(b["ok"], b)
            self.assertEqual(b["reimport_faces"], b["faces"])
            self.assertEqual(b["faces"], b["regions"])
            self.assertGreater(b["step_bytes"], 0)
            for key in ("shell_s", "export_s", "reimport_s"):
                self.assertTrue(_finite(b[key]) and b[key] > 0)
        self.assertTrue(_finite(s["peak_rss_mb"]) and s["peak_rss_mb"] > 0)

    def test_quality_section_counts_every_sketch_in_g0_and_g1(self):
        q = self.raw["quality"]
        names = [r["name"] for r in q["results"]]
        self.assertEqual(len(names), len(set(names)))
        self.assertGreater(len(names), 0)
        for c in ("G0", "G1"):
            s = q["summary"][c]
            self.assertEqual(s["total"], len(names))
            self.assertLessEqual(s["folded"], s["built"])
            self.assertLessEqual(s["fit_ok"], s["built"])
            for r in q["results"]:
                m = r[c]
                self.assertIn("built", m, (r["name"], c))
                if m["built"]:   # the lifted stroke is 1.5% of the diagonal off the truth
                    self.assertTrue(_finite(m["dev_max_pct"]) and m["dev_max_pct"] >= m["dev_rms_pct"] > 0)
                    self.assertGreater(m["faces"], 0)
                else:
                    self.assertTrue(m["error"])
        lines = (self.out / "quality.txt").read_text().splitlines()
        self.assertEqual(len(lines), 2 * len(names))

    def test_profile_lists_ten_functions_led_by_add_stroke(self):
        top = self.raw["profile"]["top"]
        self.assertEqual(len(top), 10)
        self.assertIn("add_stroke", top[0]["function"])
        cum = [e["cumtime_s"] for e in top]
        self.assertEqual(cum, sorted(cum, reverse=True))


if __name__ == "__main__":
    unittest.main()
