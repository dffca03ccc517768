"""Manchester contact benchmark, case A-2.2: the shipped scene ``scenes/manchester_a22.toml`` (S1002 on UIC60 1:40 from
the benchmark's own profile files, per-case inputs from the benchmark CSV, 10 kN vertical force per wheel including
the tangential forces, both wheels, weighted-centre reference point) for every normal method, against CONTACT's
reference output (``benchmarks/data/contact_mbench_a22.csv``, see its header). Units: mm, N, MPa, s, rad.

Reported per case and wheel: contact position (rail profile coordinate of the reference point), normal force FN,
p_max, area, creep forces FX, FS and the creepages, all converted to CONTACT's sign convention for the comparison
(docs/wheel-rail.md: CONTACT's creepages and creep forces are the negatives of wrlayer's, its left-rail coordinate
and left contact angle are mirrored); run time per method; and the effect of the two modelling choices this case
exposes (balance with or without the tangential forces, first-contact or weighted-centre reference point).
"""

from __future__ import annotations

import copy
import csv
import math
import os
import pathlib
import time
import tomllib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from contact.scenes.cost import wheel_rail_cost
from contact.wheel_rail.parse import parse_wheel_rail_scene
from contact.run_files import run_wheel_rail_scene
from contact.wheel_rail.scene_files import reference_dir
from wrlayer.errors import InputError
from wrlayer.jit import run_mode
from wrlayer.plotting import save_figure

ROOT = pathlib.Path(__file__).resolve().parents[1]
SCENE = ROOT / "scenes" / "manchester_a22.toml"
CONTACT_CSV = ROOT / "benchmarks" / "data" / "contact_mbench_a22.csv"
METHODS = ("kik_piotrowski", "exact")
MU = 0.3
#: Case 11 (lateral 5 mm): two-point contact in wrlayer (gauge corner + tread), one patch in CONTACT.
TWO_POINT_CASES = (11,)


def contact_reference() -> dict[tuple[str, int], list[dict]]:
    """CONTACT's patches per (wheel, case number 1..21)."""
    rows = [ln for ln in CONTACT_CSV.read_text(encoding="utf-8").splitlines() if not ln.startswith("#")]
    out: dict[tuple[str, int], list[dict]] = {}
    for r in csv.DictReader(rows):
        rec = {k: (v if k == "wheel" else float(v)) for k, v in r.items()}
        out.setdefault((r["wheel"], int(r["case"])), []).append(rec)
    return out


def to_contact(patch: dict, side: str) -> dict[str, float]:
    """A wrlayer patch result in CONTACT's conventions (docs/wheel-rail.md, 'Comparing with CONTACT')."""
    mirror = -1.0 if side == "left" else 1.0
    return {"ycp_r_mm": mirror * patch["y_rail_mm"], "deltcp_rad": -mirror * patch["contact_angle_rad"],
            "fn_N": patch["normal_force_N"], "fx_N": -patch["Fx_N"], "fs_N": -patch["Fy_N"],
            "approach_mm": patch["delta_mm"], "pmax_MPa": patch["p_max_MPa"], "area_mm2": patch["area_mm2"],
            "cksi": -patch["creepage_x"], "ceta": -patch["creepage_y"], "cphi_per_mm": -patch["spin_per_mm"]}


def _scene_data(sweep: dict | None = None, workers: int = 1, output: dict | None = None, **method) -> dict:
    data = copy.deepcopy(tomllib.loads(SCENE.read_text(encoding="utf-8")))
    data["method"].update(method)
    data.setdefault("output", {}).update(output or {})
    data["sweep"].update(sweep or {})
    if workers > 1:
        data.setdefault("run", {})["workers"] = workers
    return data


def run_scene(out: pathlib.Path, sweep: dict | None = None, vtk: bool | None = None, workers: int = 1,
              output: dict | None = None, **method) -> tuple[dict | None, float, float, str]:
    """(result or None, wall time s, CPU time s of this process, error text) of the shipped scene with ``method``
    keys changed; ``vtk``: write the VTK files (None: the scene's default, as ``wrlayer simulate``); ``workers``:
    the cases on that many local processes (their CPU time is not in this process's); ``output``: [output] keys
    changed (e.g. ``{"frictional_csv": False}``). The kernels run in the mode ``wrlayer simulate`` chooses for the
    scene (:func:`wrlayer.jit.run_mode` with the scene's cost estimate)."""
    t0, c0 = time.perf_counter(), time.process_time()
    try:
        scene = parse_wheel_rail_scene(_scene_data(sweep, workers, output, **method), SCENE)
        with run_mode(wheel_rail_cost(scene).seconds):
            res = run_wheel_rail_scene(scene, out, plots=False, vtk=vtk).to_dict()
    except InputError as err:
        return None, time.perf_counter() - t0, time.process_time() - c0, str(err)
    return res, time.perf_counter() - t0, time.process_time() - c0, ""


def _main(patches: list[dict]) -> dict:
    return max(patches, key=lambda p: p["normal_force_N"])


def _row(cells) -> str:
    return "| " + " | ".join(str(c) for c in cells) + " |"


def _fmt(v: float, nd: int) -> str:
    return f"{v:.{nd}f}" if v is not None and math.isfinite(v) else "—"


def case_table(results: dict[str, dict], ref: dict, side: str) -> tuple[str, list[dict]]:
    """Markdown table per case of one wheel: each method's main patch (and the patch count) vs CONTACT."""
    cols = [("ycp_r_mm", "y_r [mm]", 2), ("fn_N", "FN [N]", 0), ("pmax_MPa", "p_max [MPa]", 0),
            ("area_mm2", "area [mm²]", 1), ("fx_N", "FX [N]", 0), ("fs_N", "FS [N]", 0),
            ("cksi", "ξ [1e-3]", 3), ("ceta", "η [1e-3]", 3), ("cphi_per_mm", "φ [1e-3/mm]", 4)]
    names = [m for m in METHODS if results.get(m)]
    head = ["case", "lateral [mm]", "patches " + "/".join(["ours"] * len(names) + ["CONTACT"])]
    head += [f"{title} " + " / ".join(_short(m) for m in names) + " / CONTACT" for _, title, _ in cols]
    lines = [_row(head), _row(["---"] * len(head))]
    data = []
    for k in range(21):
        rc = ref[(side, k + 1)]
        rmain = max(rc, key=lambda p: p["fn_N"])
        ours = {m: results[m]["cases"][k] for m in names}
        cells = [k + 1, f"{ours[names[0]]['lateral_mm']:.1f}" if names else ""]
        counts = [str(len(ours[m]["wheels"][side]["patches"])) if "error" not in ours[m] else "err" for m in names]
        cells.append("/".join(counts + [str(len(rc))]))
        conv = {m: to_contact(_main(ours[m]["wheels"][side]["patches"]), side) for m in names if "error" not in ours[m]}
        rec = {"case": k + 1, "side": side, "contact": rmain, **{m: conv.get(m) for m in names}}
        data.append(rec)
        for key, _, nd in cols:
            scale = 1e3 if key in ("cksi", "ceta", "cphi_per_mm") else 1.0
            vals = [_fmt(conv[m][key] * scale, nd) if m in conv else "err" for m in names]
            cells.append(" / ".join(vals + [_fmt(rmain[key] * scale, nd)]))
        lines.append(_row(cells))
    return "\n".join(lines) + "\n", data


def _short(method: str) -> str:
    return {"kik_piotrowski": "KP", "exact": "exact"}[method]


def _plot(data_by_side: dict[str, list[dict]], names: list[str], path: pathlib.Path) -> None:
    keys = [("ycp_r_mm", "y_r (CONTACT frame) [mm]"), ("fn_N", "FN [N]"), ("pmax_MPa", "p_max [MPa]"),
            ("area_mm2", "area [mm²]"), ("fx_N", "FX on rail [N]"), ("fs_N", "FS on rail [N]")]
    fig, axes = plt.subplots(2, len(keys), figsize=(22, 7.5), constrained_layout=True)
    lateral = np.arange(21) * 0.5
    for row, side in enumerate(("right", "left")):
        data = data_by_side[side]
        for ax, (key, title) in zip(axes[row], keys):
            ax.plot(lateral, [d["contact"][key] for d in data], "ko", mfc="none", label="CONTACT (reference)")
            for m, style in zip(names, ("-", "--")):
                ax.plot(lateral, [d[m][key] if d.get(m) else np.nan for d in data], style, label=f"wrlayer {_short(m)}")
            ax.set_title(f"{side} wheel: {title}", fontsize=9)
            ax.set_xlabel("lateral displacement [mm]", fontsize=8)
            ax.grid(alpha=0.3)
            ax.tick_params(labelsize=8)
    axes[0, 0].legend(fontsize=8)
    fig.suptitle("Manchester benchmark A-2.2 (10 kN, μ = 0.3): wrlayer vs CONTACT's reference output", fontsize=11)
    save_figure(fig, path)


def _errors(data: list[dict], method: str, key: str, skip=()) -> float:
    """Largest deviation from CONTACT over the cases (not in ``skip``): relative |ours - CONTACT| / |CONTACT| for FN,
    p_max and area; for the creep forces FX, FS relative to the friction limit mu FN of CONTACT's patch."""
    devs = []
    for d in data:
        if not d.get(method) or d["case"] in skip:
            continue
        ref = d["contact"]
        scale = MU * ref["fn_N"] if key in ("fx_N", "fs_N") else abs(ref[key])
        devs.append(abs(d[method][key] - ref[key]) / scale)
    return max(devs) if devs else float("nan")


def _choices_table(out: pathlib.Path, ref: dict) -> tuple[str, dict]:
    """Right wheel, a tread case (2) and a flange case (14): the balance and reference-point choices vs CONTACT."""
    variants = [("total", "weighted_centre", "per case"), ("normal", "weighted_centre", "per case"),
                ("total", "first_contact", "per case"), ("total", "weighted_centre", "V / r0")]
    lines = [_row(["method.balance", "method.contact_point", "pitch rate", "case", "FN [N]", "FX [N]", "FS [N]",
                   "F_Z wheel [N]", "Y/Q", "ξ [1e-3]", "y_r [mm]"]), _row(["---"] * 11)]
    data = {}
    # the same cases without the per-case pitch rate (pure rolling at the nominal radius, as before per-case inputs)
    src = (reference_dir() / "mbench_a22_inputs.csv").read_text(encoding="utf-8").splitlines()
    rows = list(csv.reader(ln for ln in src if not ln.startswith("#")))
    keep = [i for i, h in enumerate(rows[0]) if h != "pitch_rate_rad_s"]
    no_pitch = out / "a22_inputs_without_pitch_rate.csv"
    no_pitch.write_text("\n".join(",".join(r[i] for i in keep) for r in rows) + "\n", encoding="utf-8")
    for bal, point, pitch in variants:
        sweep = {} if pitch == "per case" else {"csv": str(no_pitch.resolve())}  # a scene resolves paths
        res, _, _, err = run_scene(out / f"{bal}_{point}_{pitch.replace(' ', '').replace('/', '')}", sweep=sweep,
                            balance=bal, contact_point=point)
        if res is None:
            raise RuntimeError(f"variant balance={bal}, contact_point={point}, pitch rate {pitch}: {err}")
        for case in (2, 14):
            w = res["cases"][case - 1]["wheels"]["right"]
            p = to_contact(_main(w["patches"]), "right")
            data[f"{bal}/{point}/{pitch}/{case}"] = {**p, "vertical_force_N": w["vertical_force_N"],
                                                     "Y_over_Q": w["Y_over_Q"]}
            lines.append(_row([bal, point, pitch, case, f"{p['fn_N']:.0f}", f"{p['fx_N']:.0f}", f"{p['fs_N']:.0f}",
                               f"{w['vertical_force_N']:.0f}", f"{w['Y_over_Q']:.3f}", f"{p['cksi'] * 1e3:.3f}",
                               f"{p['ycp_r_mm']:.2f}"]))
    for case in (2, 14):
        rc = max(ref[("right", case)], key=lambda p: p["fn_N"])
        lines.append(_row(["CONTACT", "(weighted centre)", "per case", case, f"{rc['fn_N']:.0f}", f"{rc['fx_N']:.0f}",
                           f"{rc['fs_N']:.0f}", f"{rc['fz_tr_N']:.0f}", f"{-rc['fy_tr_N'] / 1e4:.3f}",
                           f"{rc['cksi'] * 1e3:.3f}", f"{rc['ycp_r_mm']:.2f}"]))
    return "\n".join(lines) + "\n", data


def run(mode: str, out: pathlib.Path) -> dict:
    out = pathlib.Path(out)
    out.mkdir(parents=True, exist_ok=True)
    if not (reference_dir() / "profiles" / "MBench_UIC60_v3.prr").is_file():
        raise InputError("reference material", f"not found at {reference_dir()} (set WRLAYER_REFERENCE)")
    ref = contact_reference()
    results, timings = {}, {}
    for m in METHODS:
        repeats = 2 if m == "kik_piotrowski" else 1
        runs = [run_scene(out / f"run_{m}_{k}", normal=m) for k in range(repeats)]
        res, _, _, err = runs[-1]
        timings[m] = {"wall_s": [r[1] for r in runs], "cpu_s": [r[2] for r in runs], "error": err}
        if res is not None:
            timings[m]["per_case_s"] = [c.get("time_s") for c in res["cases"]]
            timings[m]["n_failed"] = res["n_failed"]
        results[m] = res
    names = [m for m in METHODS if results[m]]
    tables, data_by_side = {}, {}
    for side in ("right", "left"):
        tables[side], data_by_side[side] = case_table(results, ref, side)
    fig = out / "manchester_a22.png"
    _plot(data_by_side, names, fig)
    choices, choice_data = _choices_table(out, ref)
    summary = {}
    for m in names:
        for side in ("right", "left"):
            d = data_by_side[side]
            labels = (("all cases", ()), ("without case 11", TWO_POINT_CASES)) if side == "right" else \
                (("all cases", ()),)
            for label, skip in labels:
                rec = {key: _errors(d, m, key, skip) for key in ("fn_N", "fx_N", "fs_N", "pmax_MPa", "area_mm2")}
                rec["max_abs_dy_mm"] = max(abs(x[m]["ycp_r_mm"] - x["contact"]["ycp_r_mm"]) for x in d
                                           if x.get(m) and x["case"] not in skip)
                for key in ("cksi", "ceta", "cphi_per_mm"):
                    rec[f"max_abs_d{key}"] = max(abs(x[m][key] - x["contact"][key]) for x in d
                                                 if x.get(m) and x["case"] not in skip)
                summary[f"{m}/{side}/{label}"] = rec
    md = [f"Machine load while measuring: {os.getloadavg()[0]:.2f} (1-min load average; 2 cores shared).\n",
          "| method | wall time per sweep [s] | CPU time [s] | cases failed | note |", "|---|---|---|---|---|"]
    for m in METHODS:
        t = timings[m]
        wall = ", ".join(f"{v:.2f}" for v in t["wall_s"])
        cpu = ", ".join(f"{v:.2f}" for v in t["cpu_s"])
        md.append(f"| {m} | {wall} | {cpu} | {t.get('n_failed', '—')} | {t['error'][:120] or '21 cases x 2 wheels'} |")
    md.append("\nLargest deviation from CONTACT over the cases (main patch; FN, p_max, area relative to CONTACT's "
              "value, FX and FS relative to CONTACT's mu FN):\n")
    md.append("| method / wheel / cases | FN | FX / mu FN | FS / mu FN | p_max | area | max abs(Δy_r) [mm] | "
              "max abs(Δξ), abs(Δη) [1e-3], abs(Δφ) [1e-3/mm] |")
    md.append("|---|---|---|---|---|---|---|---|")
    for k, v in summary.items():
        md.append(f"| {k} | {v['fn_N']:.1%} | {v['fx_N']:.1%} | {v['fs_N']:.1%} | {v['pmax_MPa']:.1%} | "
                  f"{v['area_mm2']:.1%} | {v['max_abs_dy_mm']:.2f} | {v['max_abs_dcksi'] * 1e3:.3f}, "
                  f"{v['max_abs_dceta'] * 1e3:.3f}, {v['max_abs_dcphi_per_mm'] * 1e3:.4f} |")
    md.append("\nRight wheel, per case (ours in CONTACT's sign convention / CONTACT):\n")
    md.append(tables["right"])
    md.append("\nLeft wheel, per case:\n")
    md.append(tables["left"])
    md.append("\nModelling choices (right wheel, KP):\n")
    md.append(choices)
    return {"title": "Manchester benchmark A-2.2 (both wheels, vs CONTACT)", "markdown": "\n".join(md),
            "figures": [str(fig)], "data": {"timings": timings, "summary": summary, "choices": choice_data,
                                            "cases": data_by_side}}
