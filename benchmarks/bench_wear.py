"""Wear loop benchmark (units mm, km, s): time per step against the number of conditions and the contact grid,
the split of a step between geometry, normal, tangential, wear law and profile update (cProfile), and how the
result changes with the number of steps and with the smoothing width.

Base case: the shipped example scenes/wear/s1002_60e1.toml (S1002 on 60E1 1:40, both wheels, calibrated layers,
60 kN per wheel, Archard/Jendel map), in-process (workers = 1). Timings are wall times on a shared machine.
"""

from __future__ import annotations

import cProfile
import pathlib
import pstats
import time
import tomllib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from contact.wear.loop import run_wear
from contact.wear.scene import parse_wear_scene
from wrlayer.plotting import save_figure

SCENE = pathlib.Path(__file__).resolve().parents[1] / "scenes" / "wear" / "s1002_60e1.toml"
# No published S1002/UIC60 wear result with its inputs stated could be read for this project, so there is no
# scenes/wear/published_*.toml to run beside ours (docs/wear.md, 'Limitations').
PUBLISHED_STATUS = ("not done - no published S1002 on UIC60/60E1 wear result with stated inputs could be read "
                    "(docs/wear.md, 'Limitations')")


def _scene(**over):
    data = tomllib.loads(SCENE.read_text())
    for key, value in over.items():
        data[key] = {**data.get(key, {}), **value}
    return parse_wear_scene(data, SCENE)


def _one_step_time(scene) -> float:
    t0 = time.perf_counter()
    run_wear(scene, show_progress=False)
    return time.perf_counter() - t0


def _deviation(run) -> dict:
    """Largest normal distance (mm) of each final profile from its initial one, and the final rolling-radius
    difference (mm)."""
    out = {}
    last = run.steps[-1]
    for side, bodies in run.initial_profiles.items():
        for body, prof in bodies.items():
            pts = last.profiles[side][body].points
            inside = (pts[:, 0] > prof.y_min + 1) & (pts[:, 0] < prof.y_max - 1)
            d, _ = prof.signed_distance(pts[inside])
            out[f"{side}_{body}_max_change_mm"] = float(np.max(np.abs(d)))
    out["delta_r_mm"] = last.conicity.delta_r_mm
    out["n_steps_done"] = len(run.steps)
    return out


def _split(scene) -> dict:
    """Cumulative times (s) of the parts of one step, from cProfile (each part counted at its call site, so that
    nested calls are not counted twice)."""
    prof = cProfile.Profile()
    prof.enable()
    t0 = time.perf_counter()
    run_wear(scene, show_progress=False)
    total = time.perf_counter() - t0
    prof.disable()
    st = pstats.Stats(prof)

    def cum(name: str, caller: str | None = None) -> float:
        t = 0.0
        for (file, _, fn), row in st.stats.items():
            if fn != name:
                continue
            if caller is None:
                t += row[3]
            else:
                t += sum(v[3] for (cf, _, cfn), v in row[4].items() if cfn == caller)
        return t

    solve_found = cum("_solve_found", "_solve_with_search")
    tangential = cum("patch_tangential")
    return {"geometry: contact search + rail placement + rigid roll": cum("search_contacts", "_solve_with_search")
            + cum("place_rail", "solve_condition") + cum("wheelset_roll", "build_tasks"),
            "normal: load balance, Kik-Piotrowski with layers, passes": solve_found - tangential,
            "tangential: FASTSIM": tangential,
            "wear law on the cells": cum("wear_of", "solve_condition"),
            "profile update: deposit, smoothing, new spline": cum("of", "wear_step")
            + cum("deposit", "depth_rates") + cum("smooth", "<dictcomp>") + cum("updated", "wear_step"),
            "rolling-radius difference": cum("radius_difference", "wear_step"),
            "total step (profiled, with cProfile overhead)": total}


#: one wear step of 100 km without step control (the timing runs)
ONE_STEP = {"wear": {"distance_km": 100.0, "steps": 1, "max_depth_per_step_mm": 10.0}}


def _time_vs_conditions(n_conds) -> list[float]:
    """Time per step (s) against the number of conditions (both wheels: 2 tasks per condition)."""
    t_cond = []
    for n in n_conds:
        lat = list(np.linspace(-3.0, 3.0, n)) if n > 1 else [0.0]
        sc = _scene(collective={"lateral_mm": lat, "yaw_rad": [0.0] * n, "weights": "uniform"}, **ONE_STEP)
        _one_step_time(sc) if n == n_conds[0] else None  # warm-up (numba, caches)
        t_cond.append(_one_step_time(sc))
    return t_cond


def _convergence(steps_list, smoothing) -> tuple[list[dict], list[dict]]:
    """Profile change against the number of steps (no step control: max depth 1 mm, 2000 km) and against the
    smoothing width (2 steps of 1000 km)."""
    conv = []
    for n in steps_list:
        r = run_wear(_scene(wear={"distance_km": 2000.0, "steps": n, "max_depth_per_step_mm": 1.0}),
                     show_progress=False)
        conv.append({"steps": n, **_deviation(r)})
    smooth = []
    for sigma in smoothing:
        r = run_wear(_scene(wear={"distance_km": 2000.0, "steps": 2, "max_depth_per_step_mm": 1.0,
                                  "smoothing_mm": sigma}), show_progress=False)
        smooth.append({"smoothing_mm": sigma, **_deviation(r)})
    return conv, smooth


def _normal_methods() -> list[dict]:
    """One step with Kik–Piotrowski and with the exact solver, interleaved medians of 3 runs after a warm-up."""
    cfgs = {"kik_piotrowski": {}, "exact (24 cells)": {"normal": "exact", "exact_cells": 24},
            "exact (48 cells)": {"normal": "exact"}}
    scenes = {k: _scene(method=v, **ONE_STEP) for k, v in cfgs.items()}
    for sc in scenes.values():
        run_wear(sc, show_progress=False)
    times = {k: [] for k in scenes}
    last = {}
    for _ in range(3):
        for k, sc in scenes.items():
            t0 = time.perf_counter()
            last[k] = run_wear(sc, show_progress=False)
            times[k].append(time.perf_counter() - t0)
    methods = []
    for k in scenes:
        st = last[k].steps[0].bodies["right", "wheel"].stats
        methods.append({"method": k, "s_per_step": float(np.median(times[k])), "wear_max_mm": st["wear_max_mm"],
                        "worn_area_mm2": st["worn_area_mm2"], "inelastic_max_mm": st["inelastic_max_mm"]})
    return methods


def _laws() -> list[dict]:
    """The two wear laws on the same first step (rates on the new profiles), per 1000 km."""
    laws = []
    for law in ("archard", "usfd"):
        r = run_wear(_scene(wear={"law": law, **ONE_STEP["wear"]}), show_progress=False)
        st = r.steps[0]
        for body in ("wheel", "rail"):
            b = st.bodies["right", body]
            laws.append({"law": law, "body": body, "max_mm_per_1000km": b.stats.wear_max_mm / st.length_km * 1e3,
                         "area_mm2_per_1000km": b.stats.worn_area_mm2 / st.length_km * 1e3})
    return laws


def _plot(n_conds, t_cond: list[float], conv: list[dict], out: pathlib.Path) -> pathlib.Path:
    fig, ax = plt.subplots(1, 2, figsize=(9, 3.5))
    ax[0].plot(n_conds, t_cond, "o-")
    ax[0].set_xlabel("conditions (x 2 wheels)")
    ax[0].set_ylabel("wall time per step (s)")
    ax[0].grid(alpha=0.3)
    ax[1].plot([c["steps"] for c in conv], [c["right_wheel_max_change_mm"] for c in conv], "o-", label="wheel")
    ax[1].plot([c["steps"] for c in conv], [c["right_rail_max_change_mm"] for c in conv], "s-", label="rail")
    ax[1].set_xlabel("steps for 2000 km")
    ax[1].set_ylabel("max profile change (mm)")
    ax[1].legend()
    ax[1].grid(alpha=0.3)
    fig.tight_layout()
    fig_path = out / "wear_benchmark.png"
    save_figure(fig, fig_path)
    return fig_path


def _markdown(d: dict) -> str:
    """The report section from the ``data`` of :func:`run`."""
    md = ["Base: scenes/wear/s1002_60e1.toml, both wheels, in-process, wall times on a shared 2-core machine.", "",
          "| conditions | tasks | s per step |", "|---|---|---|"]
    md += [f"| {n} | {2 * n} | {t:.2f} |" for n, t in zip(d["conditions"], d["time_per_step_s"])]
    md += ["", "| grid_mm | FASTSIM cells | s per step (5 conditions) |", "|---|---|---|"]
    md += [f"| {g} | {c} | {t:.2f} |" for (g, c), t in zip(d["grids"], d["time_per_step_grid_s"])]
    md += ["", "| part of one step (cProfile, cumulative) | s |", "|---|---|"]
    md += [f"| {k} | {v:.2f} |" for k, v in d["split_s"].items()]
    md += ["", "| steps (2000 km) | wheel max change mm | rail max change mm | dr mm |", "|---|---|---|---|"]
    md += [f"| {c['steps']} | {c['right_wheel_max_change_mm']:.4f} | {c['right_rail_max_change_mm']:.4f} | "
           f"{c['delta_r_mm']:.4f} |" for c in d["step_convergence"]]
    md += ["", "| smoothing sigma mm (2 steps) | wheel max change mm | rail max change mm | dr mm |",
           "|---|---|---|---|"]
    md += [f"| {c['smoothing_mm']} | {c['right_wheel_max_change_mm']:.4f} | {c['right_rail_max_change_mm']:.4f} | "
           f"{c['delta_r_mm']:.4f} |" for c in d["smoothing"]]
    md += ["", "| law (first step, right side) | body | max wear mm per 1000 km | worn area mm^2 per 1000 km |",
           "|---|---|---|---|"]
    md += [f"| {c['law']} | {c['body']} | {c['max_mm_per_1000km']:.4f} | {c['area_mm2_per_1000km']:.3f} |"
           for c in d["laws"]]
    if d["normal_methods"]:
        md += ["", "| normal method (one step) | s per step | wheel max wear mm | worn area mm^2 | inelastic mm |",
               "|---|---|---|---|---|"]
        md += [f"| {m['method']} | {m['s_per_step']:.2f} | {m['wear_max_mm']:.4f} | {m['worn_area_mm2']:.3f} | "
               f"{m['inelastic_max_mm']:.4f} |" for m in d["normal_methods"]]
    md += ["", f"Published comparison: {d['published']}"]
    return "\n".join(md)


def run(mode: str, out: pathlib.Path) -> dict:
    out = pathlib.Path(out)
    out.mkdir(parents=True, exist_ok=True)
    quick = mode == "quick"
    n_conds = (1, 3, 5) if quick else (1, 3, 5, 9)
    t_cond = _time_vs_conditions(n_conds)
    # time per step against the contact grid (strip width, FASTSIM cells per strip), 5 conditions
    grids = ((0.2, 20), (0.1, 40)) if quick else ((0.2, 20), (0.1, 40), (0.05, 60))
    t_grid = [_one_step_time(_scene(method={"grid_mm": g, "fastsim_cells": c}, **ONE_STEP)) for g, c in grids]
    split = _split(_scene(**ONE_STEP))
    conv, smooth = _convergence((1, 2, 4, 8) if quick else (1, 2, 4, 8, 16),
                                (0.0, 1.0, 2.0, 4.0) if quick else (0.0, 0.5, 1.0, 2.0, 4.0))
    methods = [] if quick else _normal_methods()
    laws = _laws()
    fig_path = _plot(n_conds, t_cond, conv, out)
    data = {"conditions": list(n_conds), "time_per_step_s": t_cond,
            "grids": [list(g) for g in grids], "time_per_step_grid_s": t_grid, "split_s": split,
            "step_convergence": conv, "smoothing": smooth, "laws": laws, "normal_methods": methods,
            "published": PUBLISHED_STATUS}
    return {"title": "Wear loop: time per step, split, step and smoothing convergence", "markdown": _markdown(data),
            "figures": [str(fig_path)], "data": data}
