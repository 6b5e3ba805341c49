"""A seeded, bounded robustness fuzz of the command line (issue 17).

    /usr/bin/python3 benchmarks/fuzz.py --cases 500 --seed 17 --jobs 2 --out out/fuzz
    /usr/bin/python3 benchmarks/fuzz.py --seed 17 --only 42,97 --out out/fuzz    # repeat some cases

Every case takes one source sketch (examples/*.xyz, examples/*.c3d and, when ../shared/data is
beside the checkout, the real CASSIE and TiGL sketches), mutates it (drop or duplicate points and
strokes, reverse, shuffle, split, scale, move, rotate), writes it as a point list and runs the real
command line on it, `/usr/bin/python3 -m ProgSurf build CASE.xyz -o CASE.step --report CASE.json -q`,
in a subprocess with a time limit. The case and its mutation follow from (seed, case number) alone.

Each outcome is classified:
    ok        exit 0, the STEP file reads back as one valid shell with the report's faces
    refused   exit 2 with exactly one stderr line "progsurf: error: ..."
    quality   exit 3, the same valid STEP, and a report whose quality verdict is not ok
    BAD       anything else: exit 1 or any other code, a traceback, more than one stderr line on a
              refusal, a timeout, a missing or invalid STEP on exit 0/3, or a broken invariance.
Invariance mutations (rotate, translate, scale, reverse_all, reverse_some, shuffle_boundary and
rigid, which combines them) must give the outcome of the unmutated sketch and, when it builds, the
same surface moved by the same transform: the largest distance between the two shells' sample
points (both ways, measured in the unmutated sketch's units) within its fit tolerance
(report["tolerances"]["fit_mm"]).

Prints counts per outcome and per mutation, every BAD case with a one-line repro command, and the
time taken; writes OUT/summary.json, and OUT/bad/case_N.xyz (the mutated input) for each BAD case.
The shell comparison runs in a subprocess of this file (`--compare`), which imports FreeCAD.
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from collections import Counter, defaultdict
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Optional

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
PYTHON = "/usr/bin/python3"
DATA = ROOT.parent / "shared" / "data"
TIMEOUT_S = 120.0
"""Per run of the command line; a case that takes longer is a hang (BAD)."""
COMPARE_TIMEOUT_S = 120.0
SCALES = (0.05, 20.0)
"""Range of the invariance mutation 'scale' (log-uniform); 'scale_extreme' goes far beyond it."""
OUTCOMES = ("ok", "refused", "quality", "BAD")


# ---------------------------------------------------------------------------------------- sources

@dataclass
class Source:
    """One sketch to mutate: its strokes ((n, 3) float arrays, mm) and the command's options."""
    name: str
    path: Path
    strokes: list
    boundary_count: Optional[int] = None
    weight: float = 1.0


def _tigl_boundary(xyz: Path) -> Optional[list]:
    """The TiGL network's boundary as examples/README.md names it (examples/real_data_trial.py's
    tigl_boundary, loaded from its file: examples/ is no package)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("real_data_trial", ROOT / "examples" / "real_data_trial.py")
    trial = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(trial)
    return trial.tigl_boundary(xyz)


def load_sources(real: bool = True, real_max_points: int = 1500) -> list:
    """The bundled examples and, when present and asked for, the real sketches of ../shared/data
    (TiGL networks written boundary-first with --boundary-count 4, as examples/README.md says;
    CASSIE sketches with the automatic boundary). Real sketches with more than real_max_points
    points are left out (their builds take minutes)."""
    if str(ROOT) not in sys.path:
        sys.path.insert(0, str(ROOT))
    from ProgSurf.io import read_strokes
    from ProgSurf.venv_site import add_venv_site_packages

    add_venv_site_packages(str(ROOT))
    sources = []
    for path in sorted((ROOT / "examples").glob("*.xyz")) + sorted((ROOT / "examples").glob("*.c3d")):
        sources.append(Source(path.stem, path, read_strokes(str(path))))
    if real and DATA.is_dir():
        for path in sorted(DATA.glob("*/*.xyz")) + sorted(DATA.glob("tigl/*/*.xyz")):
            strokes = read_strokes(str(path))
            if sum(len(s) for s in strokes) > real_max_points:
                continue
            boundary = _tigl_boundary(path)
            count = None
            if boundary is not None:
                strokes = [strokes[i] for i in boundary] + [s for i, s in enumerate(strokes) if i not in boundary]
                count = len(boundary)
            sources.append(Source(path.name.replace(".xyz", ""), path, strokes, count, weight=0.5))
    return sources


# -------------------------------------------------------------------------------------- mutations

@dataclass
class Mutated:
    strokes: list
    what: str
    transform: Optional[np.ndarray] = None
    """(4, 4): the mutated sketch is this transform of the source (an invariance case), else None."""
    boundary_count: Optional[int] = None


def _rotation(rng: np.random.Generator) -> np.ndarray:
    q = rng.normal(size=4)
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def _affine(strokes: list, m: np.ndarray) -> list:
    return [s @ m[:3, :3].T + m[:3, 3] for s in strokes]


def _diag(strokes: list) -> float:
    pts = np.vstack(strokes)
    return float(np.linalg.norm(pts.max(0) - pts.min(0))) or 1.0


def _homogeneous(lin: np.ndarray, shift=(0.0, 0.0, 0.0)) -> np.ndarray:
    m = np.eye(4)
    m[:3, :3] = lin
    m[:3, 3] = shift
    return m


def _boundary_positions(src: Source, roles: Optional[list]) -> list:
    if src.boundary_count is not None:
        return list(range(min(src.boundary_count, len(src.strokes))))
    return [i for i, r in enumerate(roles or []) if r == "boundary"]


def m_rotate(src, rng, roles):
    c = np.vstack(src.strokes).mean(0)
    r = _rotation(rng)
    m = _homogeneous(r, c - r @ c) if rng.random() < 0.5 else _homogeneous(r)
    return Mutated(_affine(src.strokes, m), "rotation " + np.array2string(r, precision=3).replace("\n", ""), m)


def m_translate(src, rng, roles):
    t = rng.normal(size=3) * _diag(src.strokes) * 10 ** rng.uniform(-1, 1.3)
    m = _homogeneous(np.eye(3), t)
    return Mutated(_affine(src.strokes, m), f"translation by {np.round(t, 2).tolist()}", m)


def m_scale(src, rng, roles):
    k = float(np.exp(rng.uniform(*np.log(SCALES))))
    m = _homogeneous(np.eye(3) * k)
    return Mutated(_affine(src.strokes, m), f"scale by {k:.4g}", m)


def m_reverse_all(src, rng, roles):
    return Mutated([s[::-1].copy() for s in src.strokes], "every stroke reversed", np.eye(4))


def m_reverse_some(src, rng, roles):
    flip = rng.random(len(src.strokes)) < 0.5
    return Mutated([s[::-1].copy() if f else s for s, f in zip(src.strokes, flip)],
                   f"strokes {np.flatnonzero(flip).tolist()} reversed", np.eye(4))


def m_shuffle_boundary(src, rng, roles):
    pos = _boundary_positions(src, roles)
    perm = list(rng.permutation(pos)) if pos else []
    strokes = list(src.strokes)
    for p, q in zip(pos, perm):
        strokes[p] = src.strokes[q]
    return Mutated(strokes, f"boundary strokes at {pos} taken in order {[int(q) for q in perm]}", np.eye(4))


def m_rigid(src, rng, roles):
    """All of the above at once: boundary order, stroke directions, rotation, translation, scale."""
    a = m_shuffle_boundary(src, rng, roles)
    b = m_reverse_some(Source(src.name, src.path, a.strokes, src.boundary_count), rng, roles)
    r = _rotation(rng)
    k = float(np.exp(rng.uniform(*np.log(SCALES))))
    m = _homogeneous(r * k, rng.normal(size=3) * _diag(src.strokes))
    return Mutated(_affine(b.strokes, m), f"{a.what}; {b.what}; rotated, scaled by {k:.4g}, moved", m)


def _pick(n: int, rng, k: int = 1) -> list:
    return sorted(rng.choice(n, size=min(k, n), replace=False).tolist())


def m_drop_points(src, rng, roles):
    strokes = [s.copy() for s in src.strokes]
    i = int(rng.integers(len(strokes)))
    s = strokes[i]
    keep = rng.random(len(s)) > rng.uniform(0.05, 0.95)
    if rng.random() < 0.2:          # down to one or two points
        keep[:] = False
        keep[_pick(len(s), rng, int(rng.integers(1, 3)))] = True
    strokes[i] = s[keep] if keep.any() else s[:1]
    return Mutated(strokes, f"stroke {i}: {len(s) - len(strokes[i])} of {len(s)} points dropped",
                   boundary_count=src.boundary_count)


def m_duplicate_points(src, rng, roles):
    strokes = [s.copy() for s in src.strokes]
    i = int(rng.integers(len(strokes)))
    s = strokes[i]
    rep = np.ones(len(s), int)
    rep[_pick(len(s), rng, int(rng.integers(1, max(2, len(s) // 3))))] += int(rng.integers(1, 4))
    strokes[i] = np.repeat(s, rep, axis=0)
    return Mutated(strokes, f"stroke {i}: {int(rep.sum()) - len(s)} points repeated", boundary_count=src.boundary_count)


def m_drop_stroke(src, rng, roles):
    if len(src.strokes) < 2:
        return m_drop_points(src, rng, roles)
    i = int(rng.integers(len(src.strokes)))
    strokes = [s for j, s in enumerate(src.strokes) if j != i]
    count = src.boundary_count
    if count is not None and i < count:
        count -= 1
    return Mutated(strokes, f"stroke {i} dropped", boundary_count=count)


def m_duplicate_stroke(src, rng, roles):
    i = int(rng.integers(len(src.strokes)))
    j = int(rng.integers(len(src.strokes) + 1))
    strokes = list(src.strokes)
    strokes.insert(j, src.strokes[i].copy())
    count = src.boundary_count
    if count is not None and j < count:
        count += 1
    return Mutated(strokes, f"stroke {i} repeated at {j}", boundary_count=count)


def m_split_stroke(src, rng, roles):
    i = int(rng.integers(len(src.strokes)))
    s = src.strokes[i]
    if len(s) < 4:
        return m_duplicate_stroke(src, rng, roles)
    k = int(rng.integers(2, len(s) - 1))
    gap = int(rng.integers(0, 2))
    strokes = list(src.strokes[:i]) + [s[:k], s[k - 1 + gap:]] + list(src.strokes[i + 1:])
    count = src.boundary_count
    if count is not None and i < count:
        count += 1
    return Mutated(strokes, f"stroke {i} split at point {k}" + (" with a gap" if gap else ""), boundary_count=count)


def m_shuffle(src, rng, roles):
    perm = rng.permutation(len(src.strokes))
    return Mutated([src.strokes[p] for p in perm], f"strokes in order {perm.tolist()}",
                   boundary_count=src.boundary_count)


def m_move_stroke(src, rng, roles):
    strokes = list(src.strokes)
    i = int(rng.integers(len(strokes)))
    d = rng.normal(size=3) * _diag(src.strokes) * 10 ** rng.uniform(-3, 0)
    strokes[i] = strokes[i] + d
    return Mutated(strokes, f"stroke {i} moved by {np.round(d, 3).tolist()}", boundary_count=src.boundary_count)


def m_move_points(src, rng, roles):
    strokes = [s.copy() for s in src.strokes]
    i = int(rng.integers(len(strokes)))
    k = _pick(len(strokes[i]), rng, int(rng.integers(1, 4)))
    strokes[i][k] += rng.normal(size=(len(k), 3)) * _diag(src.strokes) * 10 ** rng.uniform(-3, -0.5)
    return Mutated(strokes, f"stroke {i}: points {k} moved", boundary_count=src.boundary_count)


def m_scale_extreme(src, rng, roles):
    k = float(10 ** rng.choice([rng.uniform(-5, -2), rng.uniform(2, 5)]))
    m = _homogeneous(np.eye(3) * k)
    return Mutated(_affine(src.strokes, m), f"scale by {k:.3g}", boundary_count=src.boundary_count)


def m_flatten(src, rng, roles):
    """Every point pressed into one plane through the centroid (a planar sketch, or nearly)."""
    pts = np.vstack(src.strokes)
    c = pts.mean(0)
    n = np.linalg.svd(pts - c)[2][int(rng.integers(3))]
    k = rng.choice([0.0, 1e-9, 1e-3])
    return Mutated([s - np.outer((s - c) @ n, n) * (1 - k) for s in src.strokes], "pressed flat",
                   boundary_count=src.boundary_count)


INVARIANT: dict = {"rotate": m_rotate, "translate": m_translate, "scale": m_scale, "reverse_all": m_reverse_all,
                   "reverse_some": m_reverse_some, "shuffle_boundary": m_shuffle_boundary, "rigid": m_rigid}
CONTRACT: dict = {"drop_points": m_drop_points, "duplicate_points": m_duplicate_points, "drop_stroke": m_drop_stroke,
                  "duplicate_stroke": m_duplicate_stroke, "split_stroke": m_split_stroke, "shuffle": m_shuffle,
                  "move_stroke": m_move_stroke, "move_points": m_move_points, "scale_extreme": m_scale_extreme,
                  "flatten": m_flatten}
MUTATIONS: dict = {**INVARIANT, **CONTRACT}


def mutate(src: Source, mutation: str, rng: np.random.Generator, roles: Optional[list]) -> Mutated:
    out = MUTATIONS[mutation](src, rng, roles)
    if out.transform is not None:
        out.boundary_count = src.boundary_count
    return out


def plan_case(seed: int, number: int, sources: list, mutations: Optional[list] = None):
    """(source, mutation name, rng) of case `number`: a function of the seed and number alone."""
    rng = np.random.default_rng([seed, number])
    w = np.array([s.weight for s in sources])
    src = sources[int(rng.choice(len(sources), p=w / w.sum()))]
    names = mutations or list(MUTATIONS)
    return src, names[int(rng.integers(len(names)))], rng


# ----------------------------------------------------------------------------------- running

def write_xyz(path: Path, strokes: list, comment: str) -> None:
    """Point list with every float written exactly (repr): a case reads back bit for bit."""
    lines = ["# " + line for line in comment.splitlines()]
    for i, s in enumerate(strokes):
        if i:
            lines.append("")
        lines += [f"{x!r} {y!r} {z!r}" for x, y, z in np.asarray(s, float).tolist()]
    path.write_text("\n".join(lines) + "\n")


def _env() -> dict:
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    env.pop("PYTHONPATH", None)
    return env


def run_cli(inp: Path, out_dir: Path, boundary_count: Optional[int], timeout: float, cwd: Path = ROOT) -> dict:
    """The real command line on one input; returns exit code, stderr, seconds and the output paths."""
    step, report = out_dir / "out.step", out_dir / "out.json"
    cmd = [PYTHON, "-m", "ProgSurf", "build", str(inp), "-o", str(step), "--report", str(report), "-q"]
    if boundary_count is not None:
        cmd += ["--boundary-count", str(boundary_count)]
    clock = time.perf_counter()
    proc = subprocess.Popen(cmd, cwd=cwd, env=_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, errors="replace", start_new_session=True)
    try:
        stdout, stderr = proc.communicate(timeout=timeout)
        code = proc.returncode
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, 9)
        stdout, stderr = proc.communicate()
        code = None
    return {"cmd": cmd, "code": code, "stdout": stdout, "stderr": stderr, "seconds": time.perf_counter() - clock,
            "step": step, "report": report}


def compare(step: Path, base_step: Optional[Path] = None, transform: Optional[np.ndarray] = None,
            timeout: float = COMPARE_TIMEOUT_S) -> dict:
    """Read STEP back (and compare it with base_step moved by transform) in a FreeCAD subprocess."""
    cmd = [PYTHON, str(Path(__file__).resolve()), "--compare", str(step)]
    if base_step is not None:
        cmd += ["--against", str(base_step), "--transform", json.dumps(np.asarray(transform).tolist())]
    try:
        run = subprocess.run(cmd, cwd=ROOT, env=_env(), capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"error": f"the STEP check took more than {timeout:g} s"}
    try:
        return json.loads(run.stdout.strip().splitlines()[-1])
    except (ValueError, IndexError):
        return {"error": f"the STEP check failed: {run.stderr.strip()[-300:]}"}


def classify(run: dict) -> tuple:
    """(outcome, reason) by the exit-code contract; a built case still needs its STEP checked."""
    code, err = run["code"], run["stderr"]
    lines = [line for line in err.splitlines() if line.strip()]
    if code is None:
        return "BAD", "timeout"
    if "Traceback" in err:
        return "BAD", f"exit {code} with a traceback: {lines[-1] if lines else ''}"
    if code == 2:
        if len(lines) != 1 or not lines[0].startswith("progsurf: error: "):
            return "BAD", f"refusal with {len(lines)} stderr lines: {' | '.join(lines)[:300]}"
        return "refused", lines[0]
    if code in (0, 3):
        return ("ok" if code == 0 else "quality"), ""
    return "BAD", f"exit {code}: {' | '.join(lines)[:300]}"


def check_built(run: dict, outcome: str, base_step: Optional[Path] = None,
                transform: Optional[np.ndarray] = None) -> tuple:
    """(why a built case (exit 0 or 3) is BAD or None, the STEP check): report and STEP present,
    quality as the exit code says, one valid shell of the report's faces (a whole-object build: the
    report's shells); with base_step, the
    check also measures the distance to it (see compare)."""
    if not run["report"].is_file():
        return "no report written", {}
    report = json.loads(run["report"].read_text())
    quality_ok = report.get("quality", {}).get("ok", True)
    if quality_ok != (outcome == "ok"):
        return f"exit {run['code']} but report quality ok={quality_ok}", {}
    if not run["step"].is_file():
        return "no STEP written", {}
    got = compare(run["step"], base_step, transform)
    if "error" in got:
        return got["error"], got
    # one shell, or in a whole-object build (issue 18) the report's one shell per connected part
    shells = len(report["shells"]) if isinstance(report.get("shells"), list) else 1
    if got["shells"] != shells or not got["valid"] or got["faces"] != report["faces"]:
        return (f"STEP reads back as {got['shells']} shells, valid={got['valid']}, {got['faces']} faces "
                f"(report: {report['faces']})"), got
    return None, got


@dataclass
class Case:
    number: int
    source: str
    mutation: str
    what: str = ""
    outcome: str = ""
    reason: str = ""
    code: Optional[int] = None
    seconds: float = 0.0
    distance_ratio: Optional[float] = None
    repro: str = ""
    boundary_count: Optional[int] = None
    extra: dict = field(default_factory=dict)


class Fuzzer:
    def __init__(self, seed: int, out: Path, jobs: int = 2, timeout: float = TIMEOUT_S, real: bool = True,
                 mutations: Optional[list] = None, sources: Optional[list] = None,
                 log: Callable[[str], None] = print, checkout: Path = ROOT):
        self.checkout = Path(checkout)
        self.seed, self.out, self.jobs, self.timeout = seed, Path(out), jobs, timeout
        self.sources = sources if sources is not None else load_sources(real)
        self.mutations = mutations
        self.log = log
        self.base: dict = {}
        self.lock = threading.Lock()
        (self.out / "bad").mkdir(parents=True, exist_ok=True)
        (self.out / "base").mkdir(parents=True, exist_ok=True)

    def _repro(self, inp: Path, count: Optional[int]) -> str:
        extra = f" --boundary-count {count}" if count is not None else ""
        return (f"cd {self.checkout} && {PYTHON} -m ProgSurf build {inp} -o /tmp/fuzz_case.step "
                f"--report /tmp/fuzz_case.json -q{extra}")

    def baseline(self, src: Source) -> dict:
        """The unmutated source, written as a point list, built once: the invariance reference."""
        folder = self.out / "base" / src.name
        folder.mkdir(parents=True, exist_ok=True)
        inp = folder / "input.xyz"
        write_xyz(inp, src.strokes, f"{src.name}: unmutated ({src.path})")
        run = run_cli(inp, folder, src.boundary_count, self.timeout * 3, self.checkout)
        outcome, reason = classify(run)
        if outcome in ("ok", "quality"):
            reason = check_built(run, outcome)[0] or ""
            if reason:
                outcome = "BAD"
        roles, fit = None, None
        if run["report"].is_file():
            report = json.loads(run["report"].read_text())
            # a whole-object build (--surfaces, issue 18) reports no boundary/interior roles
            roles = [s.get("role", "") for s in report["strokes"]]
            fit = report["tolerances"]["fit_mm"]
        return {"outcome": outcome, "reason": reason, "roles": roles, "fit_mm": fit, "step": run["step"],
                "seconds": run["seconds"], "repro": self._repro(inp, src.boundary_count)}

    def run_case(self, number: int) -> Case:
        src, mutation, rng = plan_case(self.seed, number, self.sources, self.mutations)
        base = self.base[src.name]
        mut = mutate(src, mutation, rng, base["roles"])
        case = Case(number, src.name, mutation, mut.what, boundary_count=mut.boundary_count)
        with tempfile.TemporaryDirectory(prefix=f"fuzz{number}_") as tmp:
            tmp = Path(tmp)
            inp = tmp / f"case_{number}.xyz"
            write_xyz(inp, mut.strokes, f"fuzz seed {self.seed} case {number}: {src.name}, {mutation}: {mut.what}")
            run = run_cli(inp, tmp, mut.boundary_count, self.timeout, self.checkout)
            case.code, case.seconds = run["code"], run["seconds"]
            case.outcome, case.reason = classify(run)
            invariance = mut.transform is not None and base["outcome"] in ("ok", "quality")
            got = {}
            if case.outcome in ("ok", "quality"):
                bad, got = check_built(run, case.outcome, base["step"] if invariance else None, mut.transform)
                if bad:
                    case.outcome, case.reason = "BAD", bad
            if mut.transform is not None and case.outcome != "BAD":
                self._check_invariance(case, base, got)
            if case.outcome == "BAD":
                kept = self.out / "bad" / inp.name
                shutil.copy(inp, kept)
                case.repro = self._repro(kept, mut.boundary_count)
                if mut.transform is not None:
                    case.repro += (f"   # invariance: {PYTHON} benchmarks/fuzz.py --seed {self.seed} "
                                   f"--only {number} --out {self.out}")
        return case

    def _check_invariance(self, case: Case, base: dict, got: dict) -> None:
        if base["outcome"] == "BAD":
            return
        if "distance_max" in got:
            case.distance_ratio = got["distance_max"] / base["fit_mm"]
            case.extra = {"distance_max_mm": got["distance_max"], "fit_mm": base["fit_mm"],
                          "faces": [got["base_faces"], got["faces"]]}
        if case.outcome != base["outcome"]:
            case.outcome, case.reason = "BAD", (f"invariance: {case.mutation} gave '{case.outcome}' where the "
                                                f"sketch as drawn gave '{base['outcome']}' {base['reason'][:120]}"
                                                + (f" (distance {case.distance_ratio:.2f} x the fit tolerance)"
                                                   if case.distance_ratio is not None else ""))
            return
        if case.distance_ratio is not None and case.distance_ratio > 1.0:
            case.outcome, case.reason = "BAD", (
                f"invariance: {case.mutation} moved the surface by {got['distance_max']:.3g} mm = "
                f"{case.distance_ratio:.2f} x the fit tolerance {base['fit_mm']:.3g} mm "
                f"(faces {got['base_faces']} -> {got['faces']})")

    def run(self, numbers: list) -> list:
        clock = time.perf_counter()
        needed = {plan_case(self.seed, n, self.sources, self.mutations)[0].name for n in numbers}
        todo = [s for s in self.sources if s.name in needed]
        with ThreadPoolExecutor(self.jobs) as pool:
            for src, base in zip(todo, pool.map(self.baseline, todo)):
                self.base[src.name] = base
                self.log(f"base {src.name}: {base['outcome']} {base['reason'][:100]} ({base['seconds']:.1f} s)")
        cases = []
        with ThreadPoolExecutor(self.jobs) as pool:
            for i, case in enumerate(pool.map(self.run_case, numbers), 1):
                cases.append(case)
                if case.outcome == "BAD" or i % 25 == 0:
                    counts = Counter(c.outcome for c in cases)
                    self.log(f"[{i}/{len(numbers)} {time.perf_counter() - clock:.0f} s; "
                             + " ".join(f"{o} {counts.get(o, 0)}" for o in OUTCOMES) + f"] case {case.number} "
                             f"{case.source} {case.mutation}: {case.outcome} {case.reason[:160]}")
        self.seconds = time.perf_counter() - clock
        return cases


def summarise(cases: list, fuzzer: Fuzzer, command: str) -> str:
    counts = Counter(c.outcome for c in cases)
    per = defaultdict(Counter)
    for c in cases:
        per[c.mutation][c.outcome] += 1
    lines = [f"{len(cases)} cases, seed {fuzzer.seed}, {fuzzer.jobs} jobs, {fuzzer.seconds:.0f} s "
             f"({fuzzer.seconds / max(len(cases), 1):.2f} s a case)",
             "outcomes: " + ", ".join(f"{o} {counts.get(o, 0)}" for o in OUTCOMES),
             f"{'mutation':18s}" + "".join(f"{o:>9s}" for o in OUTCOMES) + "  worst distance / fit tol"]
    for m in MUTATIONS:
        if m in per:
            ratios = [c.distance_ratio for c in cases if c.mutation == m and c.distance_ratio is not None]
            worst = f"{max(ratios):.3f} ({len(ratios)} compared)" if ratios else ""
            lines.append(f"{m:18s}" + "".join(f"{per[m].get(o, 0):9d}" for o in OUTCOMES) + "  " + worst)
    src_counts = Counter(c.source for c in cases)
    lines.append("sources: " + ", ".join(f"{k} {v}" for k, v in sorted(src_counts.items())))
    bad = [c for c in cases if c.outcome == "BAD"]
    if bad:
        lines.append(f"BAD cases ({len(bad)}):")
        for c in bad:
            lines += [f"  case {c.number} ({c.source}, {c.mutation}: {c.what[:100]}): {c.reason}",
                      f"    repro: {c.repro}"]
    lines.append(f"repeat: {command}")
    return "\n".join(lines)


# ---------------------------------------------------------------------------- STEP comparison

def _evaluators(shape) -> list:
    """One numpy evaluator (core.bspline_surface.SurfaceDerivatives) and its bounds per face."""
    if str(ROOT) not in sys.path:
        sys.path.insert(0, str(ROOT))
    from ProgSurf.cad.faces import is_plain_bspline, surface_derivatives

    out = []
    for face in shape.Faces:
        if not is_plain_bspline(face.Surface):
            raise ValueError(f"a face of type {face.Surface.TypeId} is not a plain B-spline surface")
        out.append((surface_derivatives(face.Surface), tuple(face.ParameterRange)))
    return out


def _samples(faces: list, total: int, inside: bool = False) -> tuple:
    """Points on every face on an n x n grid of its parameter range: (m, 3) points, (m,) face
    index, (m, 2) parameters. inside: the grid's cell centres instead, none on the face's border
    (starts for the projection that are not on the collapsed side of a 3-sided face)."""
    n = max(4, int(np.sqrt(total / max(len(faces), 1))))
    pts, owner, uvs = [], [], []
    w = (np.arange(n) + 0.5) / n if inside else np.linspace(0.0, 1.0, n)
    for k, (ev, (u0, u1, v0, v1)) in enumerate(faces):
        u, v = np.meshgrid(u0 + w * (u1 - u0), v0 + w * (v1 - v0), indexing="ij")
        uv = np.column_stack([u.ravel(), v.ravel()])
        pts.append(ev.evaluate(uv[:, 0], uv[:, 1])[0])
        owner.append(np.full(len(uv), k))
        uvs.append(uv)
    return np.vstack(pts), np.concatenate(owner), np.vstack(uvs)


def _distances(points: np.ndarray, faces: list, dense: tuple, candidates: int = 3, starts: int = 6) -> np.ndarray:
    """Distance of each point to the shell: projected (clamped Gauss-Newton) onto each of the
    `candidates` faces with the nearest dense samples, from that face's `starts` nearest samples
    (a face's samples crowd at a collapsed side and thin out beside it, where one start can stall
    on the face's border)."""
    from scipy.spatial import cKDTree

    from ProgSurf.core.bspline_surface import project_points

    dense_pts, owner, uvs = dense
    near = np.empty((len(points), len(faces)))
    start = np.empty((len(points), len(faces), starts), dtype=int)
    for k in range(len(faces)):
        rows = np.flatnonzero(owner == k)
        dist, j = cKDTree(dense_pts[rows]).query(points, k=starts)
        near[:, k], start[:, k] = dist[:, 0], rows[j]
    best = near.min(axis=1)
    order = np.argsort(near, axis=1)[:, :candidates]
    for k, (ev, bounds) in enumerate(faces):
        rows = np.flatnonzero((order == k).any(axis=1))
        for i in range(starts if len(rows) else 0):
            d = project_points(ev, bounds, points[rows], uvs[start[rows, k, i]])
            np.minimum.at(best, rows, d)
    return best


def compare_main(step: str, against: Optional[str], transform: Optional[str]) -> dict:
    sys.path.append("/usr/lib/freecad-python3/lib")
    import FreeCAD  # noqa: F401  (before Part)
    import Part

    shape = Part.Shape()
    shape.read(step)
    got = {"shells": len(shape.Shells), "valid": bool(shape.isValid()), "faces": len(shape.Faces)}
    if against is None or not shape.Faces:
        return got
    base = Part.Shape()
    base.read(against)
    to_mutated, to_base = shell_distance(base, shape, np.array(json.loads(transform)))
    got.update(base_faces=len(base.Faces), distance_max=max(to_mutated, to_base),
               distance_base_to_mutated=to_mutated, distance_mutated_to_base=to_base)
    return got


def shell_distance(base, shape, transform: Optional[np.ndarray] = None) -> tuple:
    """How far the shell `shape` is from the shell `base` moved by transform (4, 4) (default: not
    moved), both ways, in base's units: (largest distance of base's sample points, moved, from
    shape; largest distance of shape's sample points, moved back, from base). Both are Part shapes
    of plain B-spline faces (ProgSurf's); each face is sampled on a grid of its parameters."""
    m = np.eye(4) if transform is None else np.asarray(transform, dtype=float)
    lin, shift = m[:3, :3], m[:3, 3]
    k = abs(np.linalg.det(lin)) ** (1 / 3)
    inv = np.linalg.inv(lin)
    base_faces, mut_faces = _evaluators(base), _evaluators(shape)
    base_pts, mut_pts = _samples(base_faces, 3000)[0], _samples(mut_faces, 3000)[0]
    base_dense, mut_dense = _samples(base_faces, 20000, True), _samples(mut_faces, 20000, True)
    to_mut, to_base = base_pts @ lin.T + shift, (mut_pts - shift) @ inv.T
    d1 = _exact_largest(to_mut, _distances(to_mut, mut_faces, mut_dense), shape) / k
    d2 = _exact_largest(to_base, _distances(to_base, base_faces, base_dense), base)
    return float(d1.max()), float(d2.max())


def _exact_largest(points: np.ndarray, distances: np.ndarray, shape, batch: int = 32, budget: int = 512) -> np.ndarray:
    """The projected distances (m,) with the largest ones measured again by OCC (distToShape of a
    vertex, BRepExtrema): a face that turns over (a fold) can stretch a sliver of its parameters
    over a long way, and no projection start of the dense grid then lies near a point there (the
    unmutated fuselage1.noisy measured 145 mm from itself). Both measures are distances to a point
    of the shell, so their smaller one is still never below the true distance. Points are measured
    again, largest first, until the largest one left is no larger than those measured (then the
    maximum is OCC's), is negligible (1e-9 of the shell's size), or `budget` points were measured."""
    import FreeCAD
    import Part

    d = distances.copy()
    order = np.argsort(-d, kind="stable")
    negligible = 1e-9 * shape.BoundBox.DiagonalLength
    done = 0
    while done < min(budget, len(order)) and d[order[done]] > negligible:
        if done and d[order[done]] <= d[order[:done]].max():
            break
        for i in order[done:done + batch]:
            exact = shape.distToShape(Part.Vertex(FreeCAD.Vector(*(float(x) for x in points[i]))))[0]
            d[i] = min(d[i], exact)
        done += len(order[done:done + batch])
    return d


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--cases", type=int, default=500)
    p.add_argument("--seed", type=int, default=17)
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--out", default=str(ROOT / "out" / "fuzz"))
    p.add_argument("--timeout", type=float, default=TIMEOUT_S, help="seconds a run of the command may take")
    p.add_argument("--only", help="case numbers, comma-separated (repeat these cases)")
    p.add_argument("--mutations", help="comma-separated subset of: " + ", ".join(MUTATIONS))
    p.add_argument("--no-real", action="store_true", help="leave out ../shared/data")
    p.add_argument("--checkout", default=str(ROOT), help="run the command line of this checkout (default: this one)")
    p.add_argument("--compare", help=argparse.SUPPRESS)
    p.add_argument("--against", help=argparse.SUPPRESS)
    p.add_argument("--transform", help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.compare:
        print(json.dumps(compare_main(args.compare, args.against, args.transform)))
        return 0
    mutations = args.mutations.split(",") if args.mutations else None
    fuzzer = Fuzzer(args.seed, Path(args.out), args.jobs, args.timeout, real=not args.no_real, mutations=mutations,
                    checkout=Path(args.checkout))
    numbers = [int(n) for n in args.only.split(",")] if args.only else list(range(args.cases))
    cases = fuzzer.run(numbers)
    command = f"{PYTHON} benchmarks/fuzz.py " + " ".join(argv if argv is not None else sys.argv[1:])
    text = summarise(cases, fuzzer, command)
    print(text)
    (fuzzer.out / "summary.txt").write_text(text + "\n")
    (fuzzer.out / "summary.json").write_text(json.dumps(
        {"seed": args.seed, "seconds": fuzzer.seconds, "cases": [
            {k: (str(v) if isinstance(v, Path) else v) for k, v in c.__dict__.items()} for c in cases]}, indent=1))
    return 1 if any(c.outcome == "BAD" for c in cases) else 0


if __name__ == "__main__":
    sys.exit(main())
