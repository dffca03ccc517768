"""Benchmark of the normal contact solver with the Prandtl layer (contact.normal.kik_piotrowski, contact.passes.passes).

Speed: median time per normal solve on the paper's example scene (no layer / with the combined layer) and for full
runs to shakedown. Accuracy: (1) vs the paper's Table 1 (a parabolic stand-in separation; see
contact/scenes/paper_example.py), (2) vs Hertz for a circular contact with alpha = 0.5 (where the KP patch is exactly
the Hertz patch, so the error is the discretisation's), (3) grid convergence: error vs a very fine grid, and time.
Units: s, ms, mm, MPa, MiB.
"""

from __future__ import annotations

import pathlib
import statistics
import time

import numpy as np

from benchmarks.harness import median_time, peak_memory_mb
from contact.normal.kik_piotrowski import NormalProblem, solve_normal
from contact.scenes.paper_example import PAPER_EXAMPLE, paper_layers, paper_problem
from contact.passes.passes import PassesOptions, run_passes
from wrlayer.plotting import save_figure


def _row(cells) -> str:
    return "| " + " | ".join(str(c) for c in cells) + " |"


def _paper_table() -> tuple[str, dict]:
    prob = paper_problem()
    no = solve_normal(prob)
    recs_1e4, _ = run_passes(prob, paper_layers(prob), PassesOptions(tolerance_mm=1e-4))
    recs_1e6, _ = run_passes(prob, paper_layers(prob), PassesOptions(tolerance_mm=1e-6))
    t1 = PAPER_EXAMPLE["table1"]
    cols = [("without layer", no.__dict__, t1["no_layer"]),
            ("with layer (pass 1)", recs_1e4[0].__dict__, t1["with_layer"]),
            (f"shakedown, tol 1e-4 mm ({len(recs_1e4)} passes)", recs_1e4[-1].__dict__, t1["shakedown"]),
            (f"shakedown, tol 1e-6 mm ({len(recs_1e6)} passes)", recs_1e6[-1].__dict__, t1["shakedown"])]
    keys = [("length_mm", "length [mm]", 2), ("width_mm", "width [mm]", 2), ("area_mm2", "area [mm^2]", 1),
            ("delta_mm", "delta [mm]", 5), ("p_max_MPa", "p_max [MPa]", 0), ("u0_mm", "u(0) [mm]", 4),
            ("up0_mm", "u_p(0) [mm]", 4)]
    lines = [_row(["quantity"] + [f"{c[0]}: ours / paper" for c in cols]), _row(["---"] * (len(cols) + 1))]
    data = {}
    for key, title, nd in keys:
        cells = [title]
        for name, ours, paper in cols:
            v = ours.get(key)
            ref = paper.get(key)
            if v is None:
                cells.append("—")
                continue
            txt = f"{v:.{nd}f}"
            if ref is not None:
                txt += f" / {ref:.{nd}f} ({100 * (v - ref) / ref:+.1f} %)"
            cells.append(txt)
            data.setdefault(name, {})[key] = v
        lines.append(_row(cells))
    return "\n".join(lines), data


def _timings(repeat: int) -> tuple[str, dict]:
    prob = paper_problem()
    layers = paper_layers(prob)
    cases = {
        "normal, no layer": lambda: solve_normal(prob),
        "normal, combined layer (pass 1)": lambda: solve_normal(prob, layers),
        "shakedown run, tol 1e-4 mm (20 passes)": lambda: run_passes(prob, layers, PassesOptions(tolerance_mm=1e-4)),
        "shakedown run, tol 1e-6 mm (46 passes)": lambda: run_passes(prob, layers, PassesOptions()),
        "hardening run (state kept)": lambda: run_passes(prob, layers, PassesOptions(hardening=True)),
    }
    out = {}
    lines = [_row(["case (paper scene, h = 0.1 mm)", "median wall time [ms]", "median CPU time [ms]",
                   "delta evaluations / passes"]), _row(["---"] * 4)]
    for name, fn in cases.items():
        med, _ = median_time(fn, repeat=repeat, warmup=2)
        cpu = []
        for _ in range(repeat):
            t0 = time.process_time()
            fn()
            cpu.append(time.process_time() - t0)
        res = fn()
        extra = (res.iterations["delta_evaluations"] if hasattr(res, "iterations") else len(res[0]))
        out[name] = {"wall_s": med, "cpu_s": statistics.median(cpu)}
        lines.append(_row([name, f"{1e3 * med:.2f}", f"{1e3 * statistics.median(cpu):.2f}", extra]))
    _, mem = peak_memory_mb(lambda: run_passes(prob, layers, PassesOptions()))
    lines.append("")
    lines.append(f"Peak Python-heap allocation of a full shakedown run (tracemalloc): {mem:.2f} MiB.")
    out["peak_memory_MiB_shakedown"] = mem
    return "\n".join(lines), out


def _halfspace_reference(prob: NormalProblem, h: float, delta: float) -> tuple[np.ndarray, np.ndarray, object]:
    """Exact elastic half-space contact (both bodies, the KP problem's E, nu; no layer) on square cells of side h
    (mm) over the 3D separation f(y) + x^2/(2R) < ``delta`` (mm): piecewise-constant pressure, exact rectangle
    kernel influence matrix, active-set iteration of Kalker's NORM type. Returns (x, y, solve) with
    solve(approach) -> cell pressures (MPa). A CONTACT-like reference for the region interaction."""
    from contact.normal.boussinesq import rectangle_kernel_integral
    step = max(1, int(round(h / prob.grid_mm)))
    yc, fc = prob.strip_y_mm[::step], prob.separation_on_grid_mm[::step]
    xmax = np.sqrt(2 * prob.rolling_radius_mm * delta)
    xc = np.arange(-np.ceil(xmax / h), np.ceil(xmax / h) + 1) * h
    x2, y2 = np.meshgrid(xc, yc)
    f2 = np.meshgrid(xc, fc)[1] + x2 ** 2 / (2 * prob.rolling_radius_mm)
    keep = f2 < delta
    x, y, f = x2[keep], y2[keep], f2[keep]
    dx, dy = x[:, None] - x[None, :], y[:, None] - y[None, :]
    a = prob.elastic_compliance_factor * rectangle_kernel_integral(dx - h / 2, dx + h / 2, dy - h / 2, dy + h / 2)

    def solve(approach: float) -> np.ndarray:
        on = f < approach
        for _ in range(200):
            idx = np.flatnonzero(on)
            p = np.zeros(f.size)
            p[idx] = np.linalg.solve(a[np.ix_(idx, idx)], approach - f[idx])
            if np.any(p < 0):
                on &= p >= 0
                continue
            pen = ~on & (f - approach + a @ p < -1e-12 * approach)
            if not pen.any():
                return p
            on |= pen
        raise RuntimeError("half-space reference: active set did not settle")
    return x, y, solve


def _two_regions(quick: bool, repeat: int) -> tuple[str, dict]:
    """scenes/two_patches.toml: regions with / without elastic interaction vs the exact half-space solution."""
    import dataclasses
    from scipy.optimize import brentq
    from contact.scenes.scene import load_scene
    from contact.scenes.simulation import build_layers
    scene = load_scene(pathlib.Path(__file__).resolve().parents[1] / "scenes" / "two_patches.toml")
    prob = scene.normal_problem()
    layers = build_layers(scene, prob.strip_y_mm)
    split = 6.0                                                   # y (mm) between the two valleys
    lines = [_row(["solver (elastic, no layer)", "delta [mm]", "p_max main / second [MPa]",
                   "N second / N [%]", "time with layer [ms]"]), _row(["---"] * 5)]
    data = {}
    for inter in (True, False):
        pr = dataclasses.replace(prob, region_interaction=inter)
        sol = solve_normal(pr)
        sec = [r for r in sol.regions if sol.strip_y_mm[r.reference] > split]
        main = [r for r in sol.regions if sol.strip_y_mm[r.reference] <= split]
        med, _ = median_time(lambda: solve_normal(pr, layers), repeat=repeat, warmup=1)
        name = f"KP, region_interaction={inter}"
        share = 100 * sum(r.normal_force_N for r in sec) / pr.normal_force_N
        data[name] = {"delta_mm": sol.delta_mm, "p_max_main_MPa": max(r.p0_MPa for r in main),
                      "p_max_second_MPa": max(r.p0_MPa for r in sec), "second_share_percent": share,
                      "time_with_layer_s": med}
        lines.append(_row([name, f"{sol.delta_mm:.5f}", f"{data[name]['p_max_main_MPa']:.0f} / "
                           f"{data[name]['p_max_second_MPa']:.0f}", f"{share:.2f}", f"{1e3 * med:.2f}"]))
    h = 0.4 if quick else 0.2
    x, y, solve = _halfspace_reference(prob, h, 2.5 * data["KP, region_interaction=True"]["delta_mm"])
    n = prob.normal_force_N
    d = brentq(lambda a: solve(a).sum() * h * h - n, 1e-3, 2.5 * data["KP, region_interaction=True"]["delta_mm"],
               xtol=1e-10)
    p = solve(d)
    sec = y > split
    name = f"exact half-space, cells {h} mm"
    data[name] = {"delta_mm": d, "p_max_main_MPa": float(p[~sec].max()), "p_max_second_MPa": float(p[sec].max()),
                  "second_share_percent": float(100 * p[sec].sum() * h * h / n)}
    lines.append(_row([name, f"{d:.5f}", f"{p[~sec].max():.0f} / {p[sec].max():.0f}",
                       f"{data[name]['second_share_percent']:.2f}", "—"]))
    lines.append("")
    lines.append("The exact solution's p_max is a cell mean (cells of the given size); the KP method's p_max is "
                 "lower than Hertz/exact for elongated patches anyway (see the Hertz comparison in "
                 "tests/contact/test_kik_piotrowski.py); the approach delta and the load split are the quantities "
                 "the region interaction changes.")
    return "\n".join(lines), data


def _hertz_circle(grids) -> tuple[str, dict]:
    """Circle R_x = R_y = 300 mm, alpha = 0.5: KP = Hertz up to the discretisation."""
    r, n, e, nu = 300.0, 1e5, 2.1e5, 0.3
    e_star = e / (2 * (1 - nu ** 2))
    a = (3 * n * r / (4 * e_star)) ** (1 / 3)
    p0, d = 3 * n / (2 * np.pi * a * a), a * a / r
    y = np.linspace(-3 * a, 3 * a, 1201)
    lines = [_row(["h [mm]", "delta error", "p_max error", "length error"]), _row(["---"] * 4)]
    data = {}
    for h in grids:
        s = solve_normal(NormalProblem(y, y * y / (2 * r), n, r, e, nu, alpha=0.5, grid_mm=h))
        errs = (s.delta_mm / d - 1, s.p_max_MPa / p0 - 1, s.length_mm / (2 * a) - 1)
        data[h] = errs
        lines.append(_row([h] + [f"{v:+.2e}" for v in errs]))
    return "\n".join(lines), data


def _convergence(grids, h_ref, out: pathlib.Path, repeat: int) -> tuple[str, dict, list]:
    ref = solve_normal(paper_problem(grid_mm=h_ref), paper_layers(paper_problem(grid_mm=h_ref)))
    rows, data = [], {}
    for h in grids:
        prob = paper_problem(grid_mm=h)
        layers = paper_layers(prob)
        sol = solve_normal(prob, layers)
        med, _ = median_time(lambda: solve_normal(prob, layers), repeat=repeat, warmup=1)
        err = {k: abs(getattr(sol, k) / getattr(ref, k) - 1) for k in ("delta_mm", "p_max_MPa", "area_mm2")}
        data[h] = {"time_s": med, **err}
        rows.append(_row([h, f"{1e3 * med:.2f}"] + [f"{err[k]:.2e}" for k in ("delta_mm", "p_max_MPa", "area_mm2")]))
    md = "\n".join([_row(["h [mm]", "time [ms]", "delta error", "p_max error", "area error"]),
                    _row(["---"] * 5)] + rows)
    figs = []
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import matplotlib.ticker
        fig, ax = plt.subplots(1, 2, figsize=(9, 3.6))
        hs = np.array(grids)
        for k, lab in (("delta_mm", "delta"), ("p_max_MPa", "p_max"), ("area_mm2", "area")):
            ax[0].loglog(hs, [max(data[h][k], 1e-12) for h in grids], "o-", label=lab)
        ax[0].set_xticks(hs, [f"{h:g}" for h in hs])
        ax[0].xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax[0].set_xlabel("grid h [mm]")
        ax[0].set_ylabel(f"relative error vs h = {h_ref} mm")
        ax[0].legend()
        ax[1].loglog([1e3 * data[h]["time_s"] for h in grids], [max(data[h]["delta_mm"], 1e-12) for h in grids],
                     "o-")
        for h in grids:
            ax[1].annotate(f"h={h}", (1e3 * data[h]["time_s"], max(data[h]["delta_mm"], 1e-12)), fontsize=7)
        ax[1].set_xlabel("time per normal solve with layer [ms]")
        ax[1].set_ylabel("delta relative error")
        fig.suptitle("KP normal solve with the layer, paper scene: error and time vs grid")
        fig.tight_layout()
        path = out / "contact_grid_convergence.png"
        save_figure(fig, path)
        figs.append(path)
    except ImportError:
        pass
    return md, data, figs


def run(mode: str, out: pathlib.Path) -> dict:
    quick = mode != "full"
    out.mkdir(parents=True, exist_ok=True)
    repeat = 7 if quick else 21
    grids = [0.4, 0.2, 0.1, 0.05, 0.025] if quick else [0.4, 0.2, 0.1, 0.05, 0.025, 0.0125]
    h_ref = 0.0125 if quick else 0.00625
    paper_md, paper_data = _paper_table()
    time_md, time_data = _timings(repeat)
    hertz_md, hertz_data = _hertz_circle([0.4, 0.2, 0.1, 0.05])
    conv_md, conv_data, figs = _convergence(grids, h_ref, out, repeat=3 if quick else 7)
    two_md, two_data = _two_regions(quick, repeat)
    md = "\n\n".join([
        "### Paper example vs Table 1 (parabolic stand-in separation R_y = 31.7 mm, combined layer; "
        "reference: the paper's Table 1)", paper_md,
        "### Run times (median; the machine is shared: CPU time is the steadier number)", time_md,
        "### Discretisation error vs Hertz (circle R = 300 mm, alpha = 0.5, no layer; reference: Hertz)", hertz_md,
        f"### Grid convergence (paper scene with layer; reference: the same solver at h = {h_ref} mm)", conv_md,
        "### Two contact regions with / without elastic interaction (scenes/two_patches.toml; reference: exact "
        "elastic half-space solution, Boussinesq influence matrix on square cells, active set)", two_md,
    ])
    return {"title": "Normal contact: Kik–Piotrowski with the Prandtl layer, passes to shakedown",
            "markdown": md, "figures": [str(f) for f in figs],
            "data": {"paper": paper_data, "timings_s": time_data,
                     "hertz_circle": {str(k): v for k, v in hertz_data.items()},
                     "grid_convergence": {str(k): v for k, v in conv_data.items()},
                     "two_regions": two_data}}


if __name__ == "__main__":
    import sys
    res = run(sys.argv[1] if len(sys.argv) > 1 else "quick", pathlib.Path("out/bench"))
    print(res["markdown"])
