"""Markdown tables and the PNG plot of one benchmark run (issue 8)."""
from __future__ import annotations

import math

CORE_TARGET_MS = 10.0
FACES_TARGET_MS = 50.0
TARGET_REGIONS = 50


def _f(x, digits: int = 1) -> str:
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "n/a"
    if isinstance(x, int):
        return str(x)
    return f"{x:.{digits}f}" if abs(x) >= 10 ** -digits or x == 0 else f"{x:.1e}"


def latency_table(rows: list) -> str:
    out = ["| regions | touched | core median ms | core p95 ms | incremental median ms | p95 ms | faces rebuilt"
           " | full shell median ms | p95 ms (n) | G1 incremental median ms (n) | fit tol mm | rejected/probes"
           " | machine ref ms |",
           "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        c, i, s = r["core"], r["incremental"], r["full_shell"]
        g = r.get("g1_incremental", {"median_ms": float("nan"), "n": 0})
        out.append(f"| {r['regions']} | {_f(r['regions_touched_median'])} | {_f(c['median_ms'])} | {_f(c['p95_ms'])}"
                   f" | {_f(i['median_ms'])} | {_f(i['p95_ms'])} | {_f(r['faces_rebuilt_median'])}"
                   f" | {_f(s['median_ms'])} | {_f(s['p95_ms'])} ({s['n']}) | {_f(g['median_ms'])} ({g['n']})"
                   f" | {r['fit_mm']} | {r['rejected']}/{r['probes']} | {_f(r.get('reference_ms', float('nan')))} |")
    return "\n".join(out)


def target_lines(rows: list) -> str:
    at = min(rows, key=lambda r: abs(r["regions"] - TARGET_REGIONS))
    c, i, s = at["core"]["median_ms"], at["incremental"]["median_ms"], at["full_shell"]["median_ms"]
    return (f"At {at['regions']} regions: core median {_f(c)} ms = {_f(c / CORE_TARGET_MS, 2)} x the "
            f"{CORE_TARGET_MS:.0f} ms target; with faces {_f(i)} ms (incremental shell) = "
            f"{_f(i / FACES_TARGET_MS, 2)} x and {_f(s)} ms (full rebuild from nothing) = "
            f"{_f(s / FACES_TARGET_MS, 2)} x the {FACES_TARGET_MS:.0f} ms target. The machine reference "
            f"was {_f(at.get('reference_ms', float('nan')))} ms while this row ran (the mean of before and "
            "after it; lower is faster).")


def peers_table(rows: list) -> str:
    out = ["| surface | k | ProgSurf s | Filling s | ratio PS/Fill | dev max PS / Fill mm | dev RMS PS / Fill mm"
           " | curve dev PS / Fill mm | poles/face PS / Fill | faces PS |",
           "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        p, f = r["progsurf"], r["filling"]
        cell = lambda e, fn: fn(e) if e["ok"] else "FAIL"
        out.append(
            f"| {r['surface']} | {r['k']} | {cell(p, lambda e: _f(e['time_s'], 3))} | {cell(f, lambda e: _f(e['time_s'], 3))}"
            f" | {_f(r['time_ratio'])} | {cell(p, lambda e: _f(e['truth']['max_mm'], 3))} / {cell(f, lambda e: _f(e['truth']['max_mm'], 3))}"
            f" | {cell(p, lambda e: _f(e['truth']['rms_mm'], 3))} / {cell(f, lambda e: _f(e['truth']['rms_mm'], 3))}"
            f" | {cell(p, lambda e: _f(e['curve_dev_mm'], 3))} / {cell(f, lambda e: _f(e['curve_dev_mm'], 3))}"
            f" | {cell(p, lambda e: _f(e['poles']['mean'], 0))} / {cell(f, lambda e: _f(e['poles']['mean'], 0))}"
            f" | {cell(p, lambda e: str(e['poles']['faces']))} |")
    coons = [r for r in rows if "coons" in r]
    if coons:
        out += ["", "| surface | k | Coons (GeomFillSurface) s | ratio PS/Coons | dev max Coons mm | dev RMS Coons mm | poles Coons |",
                "|---|---:|---:|---:|---:|---:|---:|"]
        for r in coons:
            c, p = r["coons"], r["progsurf"]
            if not c["ok"]:
                out.append(f"| {r['surface']} | 0 | FAIL | n/a | n/a | n/a | n/a |")
                continue
            ratio = p["time_s"] / c["time_s"] if p["ok"] else float("nan")
            out.append(f"| {r['surface']} | 0 | {_f(c['time_s'], 4)} | {_f(ratio)} | {_f(c['truth']['max_mm'], 3)}"
                       f" | {_f(c['truth']['rms_mm'], 3)} | {_f(c['poles']['mean'], 0)} |")
    fails = [f"{r['surface']} k={r['k']} {name}: {r[name].get('error', r[name].get('state'))}"
             for r in rows for name in ("progsurf", "filling", "coons") if name in r and not r[name]["ok"]]
    if fails:
        out += ["", "Failures: " + "; ".join(fails)]
    return "\n".join(out)


def scale_table(s: dict) -> str:
    out = [f"{s['strokes']} random interior strokes (5-20% of the side) over the {s['surface']}; "
           f"peak RSS of the scale process {_f(s['peak_rss_mb'])} MB.", "",
           "| build | regions | accepted | core s | shell s | STEP export s | STEP MB | re-import s | faces back | total s |",
           "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for name in ("pipeline", "fit_checked"):
        b = s.get(name)
        if b is None:
            continue
        core = b.get("core_s", b.get("core_and_fit_checks_s"))
        if not b.get("ok") and "error" in b:
            out.append(f"| {name} | {b['regions']} | {b['accepted']} | {_f(core, 2)} | FAIL: {b['error'][:90]} | | | | | |")
            continue
        total = core + b["shell_s"] + b["export_s"]
        out.append(f"| {name} | {b['regions']} | {b['accepted']} | {_f(core, 2)} | {_f(b['shell_s'], 2)}"
                   f" | {_f(b['export_s'], 2)} | {_f(b['step_bytes'] / 1e6, 1)} | {_f(b['reimport_s'], 2)}"
                   f" | {b['reimport_faces']} | {_f(total, 2)} |")
    if "fit_checked" in s:
        out.append(f"\nfit_checked dropped {s['fit_checked']['dropped_unfittable']} stroke(s) the adapter could not fit.")
    a = s.get("add_last")
    if a and a.get("ok"):
        out.append(f"\nThe last stroke added as the document adds it (the earlier {a['reused_strokes']} strokes' "
                   f"network continued, the earlier shell reused): core {_f(a['core_s'] * 1e3, 0)} ms, shell "
                   f"{_f(a['shell_s'] * 1e3, 0)} ms ({a['curves_fitted']} curves fitted, {a['faces_built']} faces "
                   f"built of {a['regions']}; stroke {a['status']}).")
    elif a:
        out.append(f"\nThe last stroke added as the document adds it: FAIL: {a.get('error', '')[:120]}")
    return "\n".join(out)


def profile_table(p: dict) -> str:
    out = [f"cProfile of add_stroke, {p['probes']} strokes on clones of a {p['regions']}-region network.", "",
           "| function | calls | own s | cumulative s |", "|---|---:|---:|---:|"]
    for e in p["top"]:
        out.append(f"| `{e['function']}` | {e['calls']} | {e['tottime_s']:.3f} | {e['cumtime_s']:.3f} |")
    out += ["", "Top by own time:", "", "| function | calls | own s |", "|---|---:|---:|"]
    for e in p["top_tottime"][:5]:
        out.append(f"| `{e['function']}` | {e['calls']} | {e['tottime_s']:.3f} |")
    return "\n".join(out)


def plot(lat: list, peers: list, path: str) -> None:
    """Cost per stroke against network size (log-log) and ProgSurf/Filling time ratio against k."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 4.8))
    x = [r["regions"] for r in lat]
    for key, label, colour in (("core", "core (add_stroke)", "C0"),
                               ("incremental", "core + incremental shell", "C1"),
                               ("full_shell", "core + full shell rebuild", "C3")):
        med = [r[key]["median_ms"] for r in lat]
        p95 = [r[key]["p95_ms"] for r in lat]
        a.plot(x, med, "o-", color=colour, label=f"{label}, median")
        a.plot(x, p95, "x:", color=colour, alpha=0.6, label="p95")
    g1 = [r.get("g1_incremental", {}).get("median_ms", float("nan")) for r in lat]
    if any(math.isfinite(v) for v in g1):
        a.plot(x, g1, "s-", color="C2", label="core + incremental G1 shell, median")
    a.axhline(CORE_TARGET_MS, color="C0", ls="--", lw=0.8)
    a.axhline(FACES_TARGET_MS, color="C1", ls="--", lw=0.8)
    a.axvline(TARGET_REGIONS, color="grey", ls=":", lw=0.8)
    a.text(x[0], CORE_TARGET_MS * 1.1, "core target 10 ms", color="C0", fontsize=8)
    a.text(x[0], FACES_TARGET_MS * 1.1, "faces target 50 ms", color="C1", fontsize=8)
    a.set_xscale("log")
    a.set_yscale("log")
    a.set_xlabel("regions in the network")
    a.set_ylabel("time to add one stroke, ms")
    a.set_title("Interactive latency")
    a.legend(fontsize=7)
    for surface in sorted({r["surface"] for r in peers}):
        rows = [r for r in peers if r["surface"] == surface and math.isfinite(r["time_ratio"])]
        b.plot([r["k"] for r in rows], [r["time_ratio"] for r in rows], "o-", label=surface)
    b.axhline(1.0, color="grey", ls="--", lw=0.8)
    b.set_yscale("log")
    b.set_xlabel("interior curves k")
    b.set_ylabel("wall time ProgSurf / Surface::Filling")
    b.set_title("Against Surface::Filling (same curves)")
    b.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
