"""Time against error of every normal method on the benchmark set of 30 patches, without and with the layer.

Units: ms, %, mm, N, MPa. The set is :mod:`benchmarks.fast_normal_cases` (Hertzian a/b 0.1-10, S1002 on 60E1 at
tread, gauge corner and flange from the A-2.2 sweep, two close patches, a quartic and a flat-topped separation).
Reference: the exact FFT half-space solver converged on the patch (:func:`reference`: 96 cells along x, and the
strip grid refined so that the narrowest patch spans at least :data:`REFERENCE_STRIPS` strips; at the set's 0.1 mm
strips a flange patch is only 7 strips wide, and the exact solver's own area there is 7 % high); the layer is the
paper's combined characteristic on every strip (indentation). Per method and patch class: the largest error over
the class's patches of p_max, area, approach delta (relative, %) and the lateral load centre (the strips' force
centroid; its shift as % of the reference patch width), and the median CPU time per solve (warm, compiled kernels,
median of repeated runs; the machine's load average is reported with the table).

Methods: "kik_piotrowski" (the paper's), "coarse_exact" at several lines x cells (y x x; with and without the
two-grid Richardson extrapolation), coarse_exact started from its own solve at 2 % less force (the wheel–rail
balance's warm start, :func:`solve_warm`) and the exact solver on a coarse x grid (``exact_cells`` 12: its lines
stay the strips). Tangential check (``--full``): every normal + tangential pair (FASTSIM, FaStrip, Kalker's exact theory)
on the patches without layer against exact/exact: F_x, F_y, M_z at six creepages (:data:`CREEPAGES`: combined,
each alone, smaller and larger), the worst error by creepage with the patch class where it occurs. Regenerate: ``python -m benchmarks --only
fast_normal --out out/bench`` (``--full``: every method and the tangential check), or the stamped validation
report docs/validation/fast-normal.md: ``python -m benchmarks.bench_fast_normal --report
docs/validation/fast-normal.md`` (the shipped methods; ``--full`` as above).
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import pathlib
import sys
import time

import numpy as np

from benchmarks.fast_normal_cases import CLASSES, patch_set
from benchmarks.harness import command_line, median_time, stamped_report
from contact.layer.prandtl_layer import LayerPair, PrandtlLayer
from contact.normal.coarse_exact import CoarseOptions, CoarseWarmStart, solve_coarse_exact
from contact.normal.exact import ExactOptions, solve_exact
from contact.normal.kik_piotrowski import solve_normal
from contact.scenes.paper_example import paper_characteristic
from contact.tangential.fastsim import Creepage
from contact.tangential.method import solve_for_normal_solution

COMMAND = "python -m benchmarks --only fast_normal --out out/bench"
TITLE = "Fast normal methods: time against error on the 30-patch set"
#: Strips across the narrowest patch of the reference solve (at least).
REFERENCE_STRIPS = 24
#: (row name, solve(problem, layer)) of every method measured.
METHODS = (
    ("kik_piotrowski", lambda prob, lay: solve_normal(prob, lay)),
    ("exact (default, 48 cells)", lambda prob, lay: solve_exact(prob, lay)),
    ("exact, exact_cells 12", lambda prob, lay: solve_exact(prob, lay, ExactOptions(cells=12))),
    ("coarse_exact 16 x 16", lambda prob, lay: solve_coarse_exact(prob, lay, CoarseOptions(cells=16, x_cells=16))),
    ("coarse_exact 16 x 16 + extrapolation",
     lambda prob, lay: solve_coarse_exact(prob, lay, CoarseOptions(cells=16, x_cells=16, extrapolate=True))),
    ("coarse_exact 20 x 20", lambda prob, lay: solve_coarse_exact(prob, lay, CoarseOptions(cells=20, x_cells=20))),
    ("coarse_exact 32 x 12", lambda prob, lay: solve_coarse_exact(prob, lay, CoarseOptions(cells=32, x_cells=12))),
    ("coarse_exact 40 x 12", lambda prob, lay: solve_coarse_exact(prob, lay, CoarseOptions(cells=40, x_cells=12))),
    ("coarse_exact 32 x 12, warm start", lambda prob, lay: solve_warm(prob, lay)),
)
QUICK_METHODS = ("kik_piotrowski", "exact (default, 48 cells)", "coarse_exact 32 x 12",
                 "coarse_exact 32 x 12, warm start")
#: The warm start's earlier solve: the same patch at this fraction of the force (a wheel–rail balance step).
WARM_FORCE_RATIO = 0.98


def solve_warm(prob, lay):
    """coarse_exact (defaults) started from its own solve of the same patch at :data:`WARM_FORCE_RATIO` times the
    force (:class:`contact.normal.coarse_exact.CoarseWarmStart`, the wheel–rail balance's next step); the earlier
    solve is not timed: its state is kept per (problem, layer) and copied into a fresh start for every timed solve."""
    key = (id(prob), id(lay))
    if _WARM_STATES.get(key, (None,))[0] is not prob:
        warm = CoarseWarmStart()
        solve_coarse_exact(prob.with_force(WARM_FORCE_RATIO * prob.normal_force_N), lay, warm=warm)
        _WARM_STATES[key] = (prob, warm.state)
    warm = CoarseWarmStart()
    warm.state = _WARM_STATES[key][1]
    return solve_coarse_exact(prob, lay, warm=warm)


_WARM_STATES: dict = {}
ERRORS = ("p_max", "area", "delta", "centre")
#: Tangential check: creepages (vx, vy, phi 1/mm) and friction of every patch (no layer); the first is the one
#: the per-class table and the times use, the others show each method's error by kind and size of creepage.
CREEPAGES = {"combined": Creepage(0.001, 0.001, 0.0005), "vx alone": Creepage(0.001, 0.0, 0.0),
             "vy alone": Creepage(0.0, 0.001, 0.0), "spin alone": Creepage(0.0, 0.0, 0.0005),
             "combined x0.3": Creepage(0.0003, 0.0003, 0.00015), "combined, larger": Creepage(0.003, 0.002, 0.001)}
CREEPAGE, FRICTION = CREEPAGES["combined"], 0.3
#: (row name, normal solve(problem), tangential method, FASTSIM flexibility rule) of the tangential check; the
#: reference is exact/exact.
TANGENTIAL = (
    ("kik_piotrowski + fastsim", lambda prob: solve_normal(prob), "fastsim", "three"),
    ("exact + fastsim", lambda prob: solve_exact(prob), "fastsim", "three"),
    ("exact + fastrip", lambda prob: solve_exact(prob), "fastrip", "three"),
    ("coarse_exact + fastsim", lambda prob: solve_coarse_exact(prob), "fastsim", "three"),
    ("coarse_exact + fastsim (blended flexibility)", lambda prob: solve_coarse_exact(prob), "fastsim", "blended"),
    ("coarse_exact + fastrip", lambda prob: solve_coarse_exact(prob), "fastrip", "three"),
    ("coarse_exact + exact", lambda prob: solve_coarse_exact(prob), "exact", "three"),
)
TANGENTIAL_ERRORS = ("Fx", "Fy", "Mz")
ERROR_TITLES = {"p_max": "p_max [%]", "area": "area [%]", "delta": "delta [%]", "centre": "centre [% width]",
                "Fx": "F_x [% mu N]", "Fy": "F_y [% mu N]", "Mz": "M_z [% mu N a]"}


def reference(prob, with_layer: bool):
    """The exact solver's solution converged on the patch (module docstring): (solution, strip grid (mm))."""
    lay = paper_layer(prob) if with_layer else None
    first = solve_exact(prob, lay)
    narrowest = min(p.n_strips for p in first.patches)
    refine = max(1, int(np.ceil(REFERENCE_STRIPS / narrowest)))
    if refine > 1:
        prob = dataclasses.replace(prob, grid_mm=prob.grid_mm / refine)
        lay = paper_layer(prob) if with_layer else None
    return solve_exact(prob, lay, ExactOptions(cells=96)), prob.grid_mm


def paper_layer(prob) -> LayerPair:
    """The paper's combined characteristic on every strip of ``prob``."""
    return LayerPair(combined=PrandtlLayer.uniform(paper_characteristic(), prob.strip_y_mm, name="paper layer"))


def load_centre_mm(sol) -> float:
    """Lateral force centroid of the solution's strips (mm)."""
    f = np.concatenate([0.5 * np.pi * p.p_peak_MPa * p.x_lead_mm * p.grid_mm for p in sol.patches])
    y = np.concatenate([p.y_mm for p in sol.patches])
    return float(f @ y / f.sum())


def errors(sol, ref) -> dict[str, float]:
    """Signed errors (%) of ``sol`` against ``ref``: p_max, area, delta relative; centre shift / ref width."""
    rel = lambda a, b: 100.0 * (a - b) / b  # noqa: E731
    return {"p_max": rel(sol.p_max_MPa, ref.p_max_MPa), "area": rel(sol.area_mm2, ref.area_mm2),
            "delta": rel(sol.delta_mm, ref.delta_mm),
            "centre": 100.0 * (load_centre_mm(sol) - load_centre_mm(ref)) / ref.width_mm}


def cpu_ms(fn, repeat: int) -> float:
    """Median CPU time (ms) of ``fn()`` over ``repeat`` runs after one warm-up run."""
    return 1e3 * median_time(fn, repeat, 1, time.process_time)[0]


def measure(methods=METHODS, repeat: int = 3) -> list[dict]:
    """One record per (patch, layer, method): class, names, errors (%), time (ms), or the error text."""
    rows = []
    for bp in patch_set():
        for with_layer in (False, True):
            lay = paper_layer(bp.problem) if with_layer else None
            ref, _ = reference(bp.problem, with_layer)
            for name, solve in methods:
                rec = {"kind": bp.kind, "patch": bp.name, "layer": with_layer, "method": name}
                try:
                    sol = solve(bp.problem, lay)
                    rec.update(errors(sol, ref), ms=cpu_ms(lambda: solve(bp.problem, lay), repeat))
                except Exception as err:  # a failed solve is a row of the table, not the end of the benchmark
                    rec["failed"] = f"{type(err).__name__}: {err}"
                rows.append(rec)
    return rows


def _forces(sol, prob, method: str, creepage: Creepage = CREEPAGE, flexibility: str = "three") -> np.ndarray:
    """(Fx N, Fy N, Mz N mm) summed over the patches of ``sol`` (about the strip origin)."""
    G = prob.E_MPa / (2.0 * (1.0 + prob.poisson))
    res = solve_for_normal_solution(sol, creepage, FRICTION, G, prob.poisson, method, flexibility=flexibility)
    return np.array([sum(r.Fx_N for r in res), sum(r.Fy_N for r in res), sum(r.Mz_Nmm for r in res)])


def measure_tangential(methods=TANGENTIAL, repeat: int = 3, creepages: dict = CREEPAGES) -> list[dict]:
    """One record per (patch, creepage, method) without layer: Fx, Fy error / (mu N), Mz error / (mu N a_eq)
    (a_eq = sqrt(area / pi) of the exact patch), against the exact normal + exact tangential solution; at the first
    creepage also the time (ms) of the normal and tangential solve together."""
    rows = []
    for bp in patch_set():
        prob = bp.problem
        ref_n = solve_exact(prob)
        scale = FRICTION * prob.normal_force_N * np.array([1.0, 1.0, np.sqrt(ref_n.area_mm2 / np.pi)])
        for k, (cname, creepage) in enumerate(creepages.items()):
            ref = _forces(ref_n, prob, "exact", creepage)
            for name, normal, method, flexibility in methods:
                rec = {"kind": bp.kind, "patch": bp.name, "layer": False, "method": name, "creepage": cname}
                try:
                    got = _forces(normal(prob), prob, method, creepage, flexibility)
                    rec.update(dict(zip(TANGENTIAL_ERRORS, (100.0 * (got - ref) / scale).tolist())))
                    if k == 0:
                        rec["ms"] = cpu_ms(lambda: _forces(normal(prob), prob, method, creepage, flexibility), repeat)
                except Exception as err:  # a failed solve is a row of the table, not the end of the benchmark
                    rec["failed"] = f"{type(err).__name__}: {err}"
                rows.append(rec)
    return rows


def creepage_table(rows: list[dict]) -> str:
    """Markdown: one row per tangential method and creepage, the worst |error| over the set (%) and its patch
    class; the targets' 5 % met or not."""
    head = ["method", "creepage", *(ERROR_TITLES[k] for k in TANGENTIAL_ERRORS), "within 5 %"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for name in dict.fromkeys(r["method"] for r in rows):
        for cname in dict.fromkeys(r["creepage"] for r in rows):
            ok = [r for r in rows if r["method"] == name and r["creepage"] == cname and "failed" not in r]
            if not ok:
                continue
            cells, worst = [name, cname], 0.0
            for key in TANGENTIAL_ERRORS:
                r = max(ok, key=lambda r: abs(r[key]))
                worst = max(worst, abs(r[key]))
                cells.append(f"{r[key]:+.2f} ({r['kind']})")
            lines.append("| " + " | ".join(cells + ["yes" if worst <= 5.0 else "no"]) + " |")
    return "\n".join(lines)


def table(rows: list[dict], errors=ERRORS) -> str:
    """Markdown: one row per method, class and layer; worst |error| of the class (%), median time (ms)."""
    head = ["method", "patch class", "layer", "patches", *(ERROR_TITLES[k] for k in errors), "median CPU [ms]",
            "max CPU [ms]"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    names = list(dict.fromkeys(r["method"] for r in rows))
    for name in names:
        for with_layer in (False, True):
            for kind in CLASSES:
                sel = [r for r in rows if r["method"] == name and r["kind"] == kind and r["layer"] == with_layer]
                if not sel:
                    continue
                ok = [r for r in sel if "failed" not in r]
                cells = [name, kind, "yes" if with_layer else "no", f"{len(ok)}/{len(sel)}"]
                for key in errors:
                    v = [r[key] for r in ok]
                    cells.append(f"{max(v, key=abs):+.2f}" if v else "—")
                t = [r["ms"] for r in ok]
                cells += [f"{np.median(t):.2f}" if t else "—", f"{max(t):.2f}" if t else "—"]
                lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def summary(rows: list[dict], errors=ERRORS) -> str:
    """Markdown: per method, worst |error| over the whole set and the median / max time."""
    lines = ["| method | solves ok | " + " | ".join(f"worst {ERROR_TITLES[k]}" for k in errors)
             + " | median CPU [ms] | max CPU [ms] |", "|---|---|" + "---|" * len(errors) + "---|---|"]
    for name in dict.fromkeys(r["method"] for r in rows):
        sel = [r for r in rows if r["method"] == name]
        ok = [r for r in sel if "failed" not in r]
        worst = [f"{max((abs(r[k]) for r in ok), default=float('nan')):.2f}" for k in errors]
        t = [r["ms"] for r in ok]
        lines.append(f"| {name} | {len(ok)}/{len(sel)} | " + " | ".join(worst)
                     + f" | {np.median(t):.2f} | {max(t):.2f} |")
    return "\n".join(lines)


def run(mode: str, out: pathlib.Path) -> dict:
    methods = METHODS if mode == "full" else tuple(m for m in METHODS if m[0] in QUICK_METHODS)
    load0 = os.getloadavg()[0]
    rows = measure(methods, repeat=5 if mode == "full" else 3)
    trows = measure_tangential(repeat=5) if mode == "full" else []
    first = [r for r in trows if r["creepage"] == next(iter(CREEPAGES))]
    load1 = os.getloadavg()[0]
    failed = [f"{r['method']} on {r['kind']} {r['patch']} (layer {r['layer']}): {r['failed']}" for r in rows + trows
              if "failed" in r]
    md = (f"Reference: the exact solver converged on each patch (96 cells, >= {REFERENCE_STRIPS} strips across). "
          f"Load average {load0:.1f} -> {load1:.1f} (2 cores shared). "
          f"Regenerate: `{COMMAND}` (`--full` for every method and the tangential check).\n\n"
          + summary(rows) + "\n\n" + table(rows) + "\n"
          + (f"\nTangential (no layer; vx = {CREEPAGE.vx:g}, vy = {CREEPAGE.vy:g}, phi = {CREEPAGE.phi_per_mm:g} "
             f"1/mm, mu = {FRICTION:g}) against the exact normal + exact tangential solution (defaults); F_x, F_y "
             "error / (mu N), M_z error / (mu N a), a = sqrt(area / pi); time: normal + tangential solve:\n\n"
             + summary(first, TANGENTIAL_ERRORS) + "\n\n" + table(first, TANGENTIAL_ERRORS) + "\n"
             + "\nThe worst error over the set by creepage (" + "; ".join(
                 f"{k}: vx = {c.vx:g}, vy = {c.vy:g}, phi = {c.phi_per_mm:g} 1/mm" for k, c in CREEPAGES.items())
             + "), with the patch class where it occurs:\n\n" + creepage_table(trows) + "\n"
             if trows else "\nTangential check: `--full` only.\n")
          + ("\nFailed solves:\n\n" + "\n".join(f"- {f}" for f in failed) + "\n" if failed else ""))
    return {"title": TITLE, "markdown": md,
            "figures": [], "data": {"rows": rows, "tangential": trows, "load": [load0, load1], "command": COMMAND}}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.bench_fast_normal", description=__doc__.splitlines()[0])
    ap.add_argument("--full", action="store_true", help="every method and the tangential check (longer)")
    ap.add_argument("--report", type=pathlib.Path, default=None,
                    help="write the stamped validation report here (docs/validation/fast-normal.md)")
    args = ap.parse_args(argv)
    res = run("full" if args.full else "quick", pathlib.Path("."))
    text = stamped_report(TITLE, res["markdown"], command_line("python -m benchmarks.bench_fast_normal", argv))
    if args.report:
        args.report.parent.mkdir(parents=True, exist_ok=True)
        args.report.write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
