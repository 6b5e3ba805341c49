"""Run ProgSurf's build on every real sketch in ../shared/data and say, per file, what became of it.

    /usr/bin/python3 examples/real_data_trial.py [--data DIR] [--cli] [--only NAME]

Per file: the boundary used, the number of regions, accepted/rejected interior strokes with the
reason of each rejection -- or the ProgSurfError message.  Any other exception is a bug in ProgSurf:
it is printed with its type and the script exits 1.  TiGL networks (a `.json` next to the file lists
profiles, then guides) are built twice: with the automatic boundary and with the boundary of
`examples/README.md` (`tigl_boundary`).  `--cli` also runs the command line on each file that builds.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path
from typing import Optional

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from ProgSurf.core.errors import ProgSurfError  # noqa: E402
from ProgSurf.core.pipeline import build_network  # noqa: E402
from ProgSurf.io import read_strokes, write_point_list  # noqa: E402

DATA = ROOT.parent / "shared" / "data"


def tigl_boundary(xyz: Path) -> Optional[list[int]]:
    """For a TiGL curve network: [first profile, last guide, last profile, first guide] (stroke
    indices), the seam of the closed profiles; None when no .json with roles sits next to the file."""
    meta = xyz.parent / (xyz.name.split(".")[0] + ".json")
    if not meta.is_file():
        return None
    roles = [s["role"] for s in json.loads(meta.read_text())["strokes"]]
    profiles = [i for i, r in enumerate(roles) if r.startswith("profiles")]
    guides = [i for i, r in enumerate(roles) if r.startswith("guides")]
    if not profiles or not guides:
        return None
    return [profiles[0], guides[-1], profiles[-1], guides[0]]


def trial(strokes: list, boundary) -> dict:
    """Build once; a dict with 'ok', and either the outcome or the error."""
    clock = time.perf_counter()
    try:
        res = build_network(strokes, boundary=boundary)
    except ProgSurfError as exc:
        return {"ok": False, "error": f"{type(exc).__name__}: {' '.join(str(exc).split())}",
                "seconds": time.perf_counter() - clock}
    inner = [r for r in res.records if r.role != "boundary"]
    return {"ok": True, "seconds": time.perf_counter() - clock,
            "boundary": [list(s) for s in res.boundary.source],
            "regions": len(res.network.regions()), "check": res.network.check(),
            "accepted": [r.index for r in inner if r.status == "accepted"],
            "rejected": [(r.index, r.reason) for r in inner if r.status == "rejected"],
            "unused_boundary": [r.index for r in res.records if r.role == "boundary" and r.status == "rejected"]}


def describe(name: str, label: str, out: dict, verbose: bool) -> str:
    head = f"{name} [{label}] ({out['seconds']:.1f} s): "
    if not out["ok"]:
        return head + "FAILED  " + out["error"]
    lines = [head + f"BUILT {out['regions']} regions, boundary sides {out['boundary']}, "
             f"interior accepted {len(out['accepted'])}, rejected {len(out['rejected'])}"
             + (f", check problems {out['check']}" if out["check"] else "")]
    reasons = Counter(r.split(";")[0].split(":")[0] for _, r in out["rejected"])
    for reason, count in reasons.most_common():
        lines.append(f"    {count} x {reason}")
    if verbose:
        lines += [f"    stroke {i}: {r}" for i, r in out["rejected"]]
    return "\n".join(lines)


def run_cli(path: Path, boundary) -> str:
    """Run the command line; a list boundary is given by writing the strokes boundary-first."""
    with tempfile.TemporaryDirectory() as tmp:
        src = path
        args = []
        if isinstance(boundary, list):
            strokes = read_strokes(str(path))
            order = boundary + [i for i in range(len(strokes)) if i not in boundary]
            src = Path(tmp) / path.name
            write_point_list(str(src), [strokes[i] for i in order],
                             comments=[f"{path.name} with strokes {boundary} (the boundary) first"])
            args = ["--boundary-count", str(len(boundary))]
        cmd = [sys.executable, "-m", "ProgSurf", "build", str(src), "-o", str(Path(tmp) / "out.step"),
               "--report", str(Path(tmp) / "out.json"), "-q", *args]
        run = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, timeout=900)
        return f"exit {run.returncode} {run.stderr.strip()}"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=DATA)
    ap.add_argument("--only", help="run only files whose name contains this")
    ap.add_argument("--cli", action="store_true", help="also run the command line on files that build")
    ap.add_argument("-v", "--verbose", action="store_true", help="list every rejected stroke")
    args = ap.parse_args(argv)
    files = sorted(args.data.glob("**/*.xyz"))
    if args.only:
        files = [f for f in files if args.only in f.name]
    if not files:
        print(f"no .xyz files under {args.data}")
        return 1
    for path in files:
        name = str(path.relative_to(args.data))
        strokes = read_strokes(str(path))
        runs = [("auto", None)]
        tb = tigl_boundary(path)
        if tb is not None:
            runs.append((f"boundary {tb}", tb))
        for label, boundary in runs:
            try:
                out = trial(strokes, boundary)
            except Exception as exc:  # noqa: BLE001 -- the point of the trial: report any crash
                print(f"{name} [{label}]: CRASH {type(exc).__name__}: {exc}")
                return 1
            print(describe(name, label, out, args.verbose), flush=True)
            if args.cli and out["ok"]:
                print(f"    cli: {run_cli(path, boundary)}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
