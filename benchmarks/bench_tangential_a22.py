"""Manchester A-2.2 with each tangential method: ``method.tangential`` = "fastsim", "fastrip", "exact" on the exact
normal solution (and FASTSIM on Kik–Piotrowski's, the shipped scene; FASTSIM and the exact theory on the
coarse-grid exact normal solution), creep forces FX and FS of both wheels against CONTACT's published full-theory
values, the time of the 21-case sweep, and every variant's largest deviation from the exact/exact sweep (p_max, area,
FN, FX, FS of the main patch).

Units: N, s. The shipped scene ``scenes/manchester_a22.toml`` (both wheels, 21 cases) with ``method.normal`` and
``method.tangential`` changed (:func:`benchmarks.bench_manchester.run_scene`); CONTACT's reference output and the
sign conversion are bench_manchester's (:func:`contact_reference`, :func:`to_contact`). Deviation of a case: |ours -
CONTACT| / (mu FN of CONTACT's main patch), main patch (largest FN); case 11 (two patches here, one in CONTACT) is
reported apart.
"""

from __future__ import annotations

import os
import pathlib
import sys

import numpy as np

from benchmarks.bench_manchester import MU, TWO_POINT_CASES, contact_reference, run_scene, to_contact

#: (method.normal, method.tangential) pairs measured, and how: "" as ``wrlayer simulate`` runs the scene (output
#: files included, one process), "no VTK" without the VTK files, "2 workers" the cases on 2 worker processes.
VARIANTS = (("kik_piotrowski", "fastsim", ""), ("exact", "fastsim", ""), ("exact", "fastrip", ""),
            ("exact", "exact", ""), ("exact", "exact", "no VTK"), ("exact", "exact", "2 workers"),
            ("coarse_exact", "fastsim", ""), ("coarse_exact", "exact", ""))
#: Main-patch quantities compared with the exact/exact sweep: (result key, relative to: "self" or "mu FN").
AGAINST_EXACT = (("p_max_MPa", "self"), ("area_mm2", "self"), ("normal_force_N", "self"), ("Fx_N", "mu FN"),
                 ("Fy_N", "mu FN"))


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


def against_exact(result: dict, exact: dict) -> dict[str, tuple[float, int, str]]:
    """Largest deviation of each :data:`AGAINST_EXACT` quantity of the main patch from the exact/exact sweep over
    the cases and wheels: (deviation, case 1..21, wheel); relative (p_max, area, FN) or / (mu FN)."""
    worst = {key: (0.0, 0, "") for key, _ in AGAINST_EXACT}
    for k, (case, ref) in enumerate(zip(result["cases"], exact["cases"])):
        if "wheels" not in case or "wheels" not in ref:
            continue
        for side in case["wheels"]:
            ours = max(case["wheels"][side]["patches"], key=lambda p: p["normal_force_N"])
            theirs = max(ref["wheels"][side]["patches"], key=lambda p: p["normal_force_N"])
            for key, scale in AGAINST_EXACT:
                den = theirs[key] if scale == "self" else MU * theirs["normal_force_N"]
                dev = (ours[key] - theirs[key]) / den
                if abs(dev) > abs(worst[key][0]):
                    worst[key] = (float(dev), k + 1, side)
    return worst


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
    return {"title": "Manchester A-2.2: tangential methods vs CONTACT", "markdown": "\n".join(md), "figures": [],
            "data": data}


if __name__ == "__main__":  # manual run: python -m benchmarks.bench_tangential_a22 [out_dir]
    print(run("quick", pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "out/bench"))["markdown"])
