"""Manchester A-2.2 with each tangential method: ``method.tangential`` = "fastsim", "fastrip", "exact" on the exact
normal solution (and FASTSIM on Kik–Piotrowski's, the shipped scene; FASTSIM and the exact theory on the
coarse-grid exact normal solution), creep forces FX and FS of both wheels against CONTACT's published full-theory
values, the time of the 21-case sweep, and every variant's largest deviation from the exact/exact sweep (p_max, area,
FN, FX, FS of the main patch). The fast mode (``method.normal = "coarse_exact"`` with each tangential method)
against the exact mode (exact/exact): per case and wheel, the deviations of the main patch and the CPU time ratio
of the sweeps without output files (no VTK files, no frictional CSVs; :data:`TIMED`, run :data:`TIMING_ROUNDS`
times interleaved, medians).
``--report FILE``: the fast-mode part of the validation report (docs/validation/tangential.md) replaced between its
markers (:data:`BEGIN`, :data:`END`), stamped.

Units: N, s. The shipped scene ``scenes/manchester_a22.toml`` (both wheels, 21 cases) with ``method.normal`` and
``method.tangential`` changed (:func:`benchmarks.bench_manchester.run_scene`); CONTACT's reference output and the
sign conversion are bench_manchester's (:func:`contact_reference`, :func:`to_contact`). Deviation of a case: |ours -
CONTACT| / (mu FN of CONTACT's main patch), main patch (largest FN); case 11 (two patches here, one in CONTACT) is
reported apart.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import pathlib
import time

import numpy as np

from benchmarks.bench_manchester import MU, TWO_POINT_CASES, contact_reference, run_scene, to_contact
from benchmarks.harness import command_line, report_stamp
from contact.tangential.fastrip import clear_node_cache
from wrlayer.atomic_write import atomic_write_text

#: (method.normal, method.tangential) pairs measured, and how: "" as ``wrlayer simulate`` runs the scene (output
#: files included, one process), "no VTK" without the VTK files, "2 workers" the cases on 2 worker processes.
VARIANTS = (("kik_piotrowski", "fastsim", ""), ("exact", "fastsim", ""), ("exact", "fastrip", ""),
            ("exact", "exact", ""), ("exact", "exact", "no VTK"), ("exact", "exact", "2 workers"),
            ("coarse_exact", "fastsim", ""), ("coarse_exact", "fastrip", ""), ("coarse_exact", "exact", ""))
#: Main-patch quantities compared with the exact/exact sweep: (result key, relative to: "self" or "mu FN").
AGAINST_EXACT = (("p_max_MPa", "self"), ("area_mm2", "self"), ("normal_force_N", "self"), ("Fx_N", "mu FN"),
                 ("Fy_N", "mu FN"))
#: Sweeps timed without output files, the exact mode first: (method.normal, method.tangential, other [method] keys).
#: The exact theory on the coarse normal solution solves on the coarse grid itself (``fastsim_cells`` does not
#: apply to it).
#: FaStrip's cells per strip in the second exact/fastrip row (its strip solves cost cells^2 per sweep).
FASTRIP_CELLS = 30
TIMED = (("exact", "exact", {}), ("coarse_exact", "fastsim", {}), ("coarse_exact", "fastrip", {}),
         ("coarse_exact", "exact", {}), ("exact", "fastrip", {}),
         ("exact", "fastrip", {"fastsim_cells": FASTRIP_CELLS}))
TIMING_ROUNDS = 3
#: Strip width (mm) of the exact/exact sweep that checks the exact mode's own p_max and area (the scene's 0.1 mm
#: leaves the flange patches 7-8 strips wide).
FINE_GRID_MM = 0.025
#: The fast mode's targets against the exact mode: largest deviation (p_max, area, F_N relative; F_x, F_y / (mu
#: F_N)) and CPU time ratio.
FAST_TOLERANCE, FAST_SPEEDUP = 0.05, 3.0
#: The patch's and the forces' keys of :data:`AGAINST_EXACT` for the targets.
PATCH_KEYS, FORCE_KEYS = ("p_max_MPa", "area_mm2"), ("normal_force_N", "Fx_N", "Fy_N")
#: Markers of the generated part of the validation report.
BEGIN, END = "<!-- bench_tangential_a22: begin -->", "<!-- bench_tangential_a22: end -->"
COMMAND = "python -m benchmarks.bench_tangential_a22 out/bench --report docs/validation/tangential.md"


def deviations(result: dict, ref: dict, side: str) -> dict[str, np.ndarray]:
    """Per case (1..21) of one wheel: FX and FS deviation from CONTACT / (mu FN), NaN for a failed case."""
    out = {"fx_N": np.full(21, np.nan), "fs_N": np.full(21, np.nan)}
    for k, case in enumerate(result["cases"]):
        if "wheels" not in case:
            continue
        ours = to_contact(max(case["wheels"][side]["patches"], key=lambda p: p["normal_force_N"]), side)
        theirs = max(ref[(side, k + 1)], key=lambda p: p["fn_N"])
        for key in out:
            out[key][k] = abs(ours[key] - theirs[key]) / (MU * theirs["fn_N"])
    return out


def per_case_against_exact(result: dict, exact: dict) -> list[tuple[int, str, dict[str, float]]]:
    """(case 1..21, wheel, {key: deviation}) of the main patch from the exact/exact sweep for each
    :data:`AGAINST_EXACT` quantity (relative: p_max, area, FN; / (mu FN): FX, FS), every case both sweeps solved."""
    out = []
    for k, (case, ref) in enumerate(zip(result["cases"], exact["cases"])):
        if "wheels" not in case or "wheels" not in ref:
            continue
        for side in case["wheels"]:
            ours = max(case["wheels"][side]["patches"], key=lambda p: p["normal_force_N"])
            theirs = max(ref["wheels"][side]["patches"], key=lambda p: p["normal_force_N"])
            out.append((k + 1, side, {key: float((ours[key] - theirs[key]) / (
                theirs[key] if scale == "self" else MU * theirs["normal_force_N"])) for key, scale in AGAINST_EXACT}))
    return out


def against_exact(result: dict, exact: dict) -> dict[str, tuple[float, int, str]]:
    """Largest deviation of each :data:`AGAINST_EXACT` quantity of the main patch from the exact/exact sweep over
    the cases and wheels: (deviation, case 1..21, wheel); relative (p_max, area, FN) or / (mu FN)."""
    worst = {key: (0.0, 0, "") for key, _ in AGAINST_EXACT}
    for case, side, dev in per_case_against_exact(result, exact):
        for key, _ in AGAINST_EXACT:
            if abs(dev[key]) > abs(worst[key][0]):
                worst[key] = (dev[key], case, side)
    return worst


@contextlib.contextmanager
def tangential_clock():
    """Accumulates the CPU time (s) of the balance's tangential solves (``contact.wheel_rail.balance.solve_regions``,
    the one call a load's tangential solve goes through) into the yielded list's single entry."""
    from contact.wheel_rail import balance

    spent, solve = [0.0], balance.solve_regions

    def timed(*args, **kwargs):
        c0 = time.process_time()
        try:
            return solve(*args, **kwargs)
        finally:
            spent[0] += time.process_time() - c0

    balance.solve_regions = timed
    try:
        yield spent
    finally:
        balance.solve_regions = solve


def timed_sweeps(out: pathlib.Path, rounds: int = TIMING_ROUNDS) -> dict[str, dict]:
    """Each :data:`TIMED` sweep without output files (no VTK files, no frictional CSVs; result.json's record is
    built), ``rounds`` times interleaved (after one untimed run of each, which compiles and loads the kernels; each
    run starts FaStrip's node cache empty, as a new process does: the shipped nodes read, others solved):
    {"normal/tangential": {"result" (the first timed run's), "cpu_s" (the runs' CPU times), "tangential_cpu_s"
    (of which the tangential solves, :func:`tangential_clock`), "load" (1-min load averages at their starts)}}."""
    runs: dict[str, dict] = {}
    for r in range(rounds + 1):
        for normal, tangential, keys in TIMED:
            name = f"{normal}/{tangential}" + "".join(f" ({k} {v})" for k, v in keys.items())
            load = os.getloadavg()[0]
            folder = out / ("timed_" + "_".join([normal, tangential, *(f"{k}{v}" for k, v in keys.items())]))
            clear_node_cache()           # FaStrip's model coefficients: every sweep starts as a new process
            with tangential_clock() as spent:
                res, _, cpu, err = run_scene(folder, normal=normal, tangential=tangential, vtk=False,
                                             output={"frictional_csv": False}, **keys)
            rec = runs.setdefault(name, {"result": None, "cpu_s": [], "tangential_cpu_s": [], "load": [],
                                         "error": ""})
            if res is None:
                rec["error"] = err
            elif r > 0:
                rec["result"] = rec["result"] or res
                rec["cpu_s"].append(cpu)
                rec["tangential_cpu_s"].append(spent[0])
                rec["load"].append(load)
    return runs


def targets_met(worst: dict, fine_worst: dict | None, speedup: float) -> str:
    """Which of the fast mode's targets a sweep meets: speed (at least :data:`FAST_SPEEDUP` times exact/exact's),
    forces (F_N, F_x, F_y within :data:`FAST_TOLERANCE` of exact/exact's; ``worst``: :func:`against_exact`), and
    p_max and area (within it of exact/exact's, or else of the exact/exact sweep on :data:`FINE_GRID_MM` strips,
    ``fine_worst``, when given)."""
    def within(w: dict | None, keys) -> bool:
        return w is not None and all(abs(w[k][0]) <= FAST_TOLERANCE for k in keys)

    patch = "yes" if within(worst, PATCH_KEYS) else \
        f"against {FINE_GRID_MM:g} mm strips only" if within(fine_worst, PATCH_KEYS) else "no"
    return (f"speed {'yes' if speedup >= FAST_SPEEDUP else 'no'}, forces "
            f"{'yes' if within(worst, FORCE_KEYS) else 'no'}, p_max and area {patch}")


def fast_mode_markdown(runs: dict[str, dict], fine: dict | None) -> tuple[str, dict]:
    """The fast mode against the exact mode: one row per timed variant (largest deviations, CPU time ratio; p_max
    and area also against ``fine``, the exact/exact sweep on :data:`FINE_GRID_MM` strips), then the
    coarse_exact/fastsim sweep per case and wheel."""
    exact = runs["exact/exact"]
    t_exact = float(np.median(exact["cpu_s"]))
    titles = {"p_max_MPa": "p_max", "area_mm2": "area", "normal_force_N": "F_N", "Fx_N": "F_x / (mu F_N)",
              "Fy_N": "F_y / (mu F_N)"}
    loads = [v for rec in runs.values() for v in rec["load"]]
    md = [f"CPU time of the sweep without output files (no VTK files, no frictional CSVs; the result record built; "
          f"one process; median of {TIMING_ROUNDS} interleaved runs "
          f"after a warm-up run; 1-min load {min(loads):.1f}–{max(loads):.1f} on the 2 shared cores) and the "
          "largest deviation of the main patch from the exact/exact sweep over the 21 cases and both wheels (case "
          f"and wheel in brackets); targets: within {FAST_TOLERANCE:.0%} and {FAST_SPEEDUP:g} times faster:\n",
          "| method.normal / method.tangential | CPU [s] | tangential solves CPU [s] | exact/exact CPU / CPU | "
          + " | ".join(titles.values()) + f" | p_max, area against exact/exact on {FINE_GRID_MM:g} mm strips | "
          "targets met |", "|---|---|---|---|" + "---|" * (len(titles) + 2)]

    def against_fine(res: dict) -> tuple[str, dict | None]:
        if fine is None:
            return "—", None
        worst = against_exact(res, fine)
        return " / ".join(f"{worst[k][0]:+.2%} ({worst[k][1]} {worst[k][2]})" for k in PATCH_KEYS), worst

    data = {}
    for name, rec in runs.items():
        if rec["result"] is None:
            md.append(f"| {name} | failed: {rec['error'][:100]} |")
            continue
        cpu, tangential = float(np.median(rec["cpu_s"])), float(np.median(rec["tangential_cpu_s"]))
        data[name] = {"cpu_s": rec["cpu_s"], "tangential_cpu_s": rec["tangential_cpu_s"], "load": rec["load"],
                      "speedup": t_exact / cpu}
        fine_text, fine_worst = against_fine(rec["result"])
        if name == "exact/exact":
            md.append(f"| {name} | {cpu:.2f} | {tangential:.2f} | 1 |" + " — |" * len(titles) + f" {fine_text} | — |")
            continue
        worst = against_exact(rec["result"], exact["result"])
        data[name]["against_exact"] = worst
        data[name]["targets"] = targets_met(worst, fine_worst, t_exact / cpu)
        cells = [f"{worst[k][0]:+.2%} ({worst[k][1]} {worst[k][2]})" for k in titles] + [fine_text,
                                                                                         data[name]["targets"]]
        md.append(f"| {name} | {cpu:.2f} | {tangential:.2f} | {t_exact / cpu:.2f} | " + " | ".join(cells) + " |")
    fast = runs["coarse_exact/fastsim"]["result"]
    if fast is not None:
        md += ["\nThe fast mode coarse_exact/fastsim per case (deviation from exact/exact, main patch):\n",
               "| case | wheel | " + " | ".join(titles.values()) + " |", "|---|---|" + "---|" * len(titles)]
        rows = per_case_against_exact(fast, exact["result"])
        data["coarse_exact/fastsim"]["per_case"] = rows
        md += [f"| {case} | {side} | " + " | ".join(f"{dev[k]:+.2%}" for k in titles) + " |"
               for case, side, dev in rows]
    return "\n".join(md), data


def _summary(dev: dict[str, np.ndarray]) -> dict[str, float]:
    keep = np.array([k + 1 not in TWO_POINT_CASES for k in range(21)])
    return {f"{key}_{stat}": float(f(v[keep])) for key, v in dev.items()
            for stat, f in (("max", np.nanmax), ("mean", np.nanmean))}


def run(mode: str, out: pathlib.Path) -> dict:
    out = pathlib.Path(out) / "tangential_a22"
    out.mkdir(parents=True, exist_ok=True)
    ref = contact_reference()
    rows, data, results = [], {}, {}
    for normal, tangential, how in VARIANTS:
        load = os.getloadavg()[0]
        kw = {"vtk": False} if how == "no VTK" else {"workers": 2} if how == "2 workers" else {}
        res, wall, cpu, err = run_scene(out / f"{normal}_{tangential}{how.replace(' ', '_')}", normal=normal,
                                        tangential=tangential, **kw)
        name = f"{normal}/{tangential}" + (f" ({how})" if how else "")
        if res is None:
            rows.append(f"| {name} | — | — | — | failed: {err[:100]} |")
            continue
        rec = {"wall_s": wall, "cpu_s": cpu, "load_1min": load, "n_failed": res["n_failed"]}
        for side in ("right", "left"):
            dev = deviations(res, ref, side)
            rec[side] = {**_summary(dev), "per_case": {k: v.tolist() for k, v in dev.items()}}
        data[name] = rec
        results[name] = res
        cells = " | ".join(f"{rec[s]['fx_N_max']:.1%} / {rec[s]['fx_N_mean']:.1%} | "
                           f"{rec[s]['fs_N_max']:.1%} / {rec[s]['fs_N_mean']:.1%}" for s in ("right", "left"))
        rows.append(f"| {name} | {cells} | {wall:.2f} | {cpu:.2f} | {load:.2f} | {res['n_failed']} |")
    md = ["Deviation from CONTACT's full theory, |ours - CONTACT| / (mu FN), largest / mean over the cases "
          f"(without case {', '.join(map(str, TWO_POINT_CASES))}); time of the 21-case sweep (both wheels; CPU: "
          "this process only, so not the workers'), with the 1-min load average of the 2 shared cores when it "
          "started:\n",
          "| method.normal / method.tangential | right FX | right FS | left FX | left FS | wall [s] | CPU [s] | "
          "load | failed |", "|---|---|---|---|---|---|---|---|---|", *rows]
    exact = results.get("exact/exact")
    if exact is not None:
        md += ["\nAgainst the exact/exact sweep (main patch of each wheel and case, largest deviation over the sweep "
               "with its case and wheel; p_max, area, FN relative, FX, FS / (mu FN)):\n",
               "| method.normal / method.tangential | " + " | ".join(k for k, _ in AGAINST_EXACT) + " |",
               "|---|" + "---|" * len(AGAINST_EXACT)]
        for name, res in results.items():
            if name.startswith("exact/exact"):
                continue
            worst = against_exact(res, exact)
            data[name]["against_exact"] = worst
            md.append(f"| {name} | " + " | ".join(f"{worst[k][0]:+.2%} ({worst[k][1]} {worst[k][2]})"
                                                  for k, _ in AGAINST_EXACT) + " |")
    fine, _, _, _ = run_scene(out / "exact_exact_fine", normal="exact", tangential="exact", vtk=False,
                              output={"frictional_csv": False}, grid_mm=FINE_GRID_MM)
    fast_md, fast = fast_mode_markdown(timed_sweeps(out), fine)
    data["fast_mode"] = {**fast, "markdown": fast_md}
    md += ["\n### The fast mode against the exact mode\n", fast_md]
    return {"title": "Manchester A-2.2: tangential methods vs CONTACT", "markdown": "\n".join(md), "figures": [],
            "data": data}


def write_report(path: pathlib.Path, markdown: str, command: str) -> None:
    """Replace the generated part of the report at ``path`` (between :data:`BEGIN` and :data:`END`) by
    ``markdown`` under a stamp; the rest of the report stays as written."""
    text = path.read_text(encoding="utf-8")
    head, rest = text.split(BEGIN, 1)
    tail = rest.split(END, 1)[1]
    atomic_write_text(path, f"{head}{BEGIN}\n{report_stamp(command)}\n\n{markdown.strip()}\n{END}{tail}")


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.bench_tangential_a22", description=__doc__.splitlines()[0])
    ap.add_argument("out", nargs="?", type=pathlib.Path, default=pathlib.Path("out/bench"))
    ap.add_argument("--report", type=pathlib.Path, default=None,
                    help="the validation report whose generated part to replace (docs/validation/tangential.md)")
    args = ap.parse_args(argv)
    res = run("quick", args.out)
    if args.report is not None:       # the fast-mode part (the CONTACT table above it is written by hand)
        write_report(args.report, res["data"]["fast_mode"]["markdown"],
                     command_line("python -m benchmarks.bench_tangential_a22", argv))
    print(res["markdown"])


if __name__ == "__main__":
    main()
