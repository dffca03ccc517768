"""Benchmark of the normal contact solver with the Prandtl layer (contact.kik_piotrowski, contact.passes).

Speed: median time per normal solve on the paper's example scene (no layer / with the combined layer) and for full
runs to shakedown. Accuracy: (1) vs the paper's Table 1 (a parabolic stand-in separation; see
contact/paper_example.py), (2) vs Hertz for a circular contact with alpha = 0.5 (where the KP patch is exactly
the Hertz patch, so the error is the discretisation's), (3) grid convergence: error vs a very fine grid, and time.
Units: s, ms, mm, MPa, MiB.
"""

from __future__ import annotations

import pathlib
import statistics
import time

import numpy as np

from benchmarks.harness import median_time, peak_memory_mb
from contact.kik_piotrowski import NormalProblem, solve_normal
from contact.paper_example import PAPER_EXAMPLE, paper_layers, paper_problem
from contact.passes import PassesOptions, run_passes


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
        from meshes.atomic_write import atomic_write_bytes
        import io
        buf = io.BytesIO()
        fig.savefig(buf, format="png", dpi=110)
        plt.close(fig)
        atomic_write_bytes(path, buf.getvalue())
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
    md = "\n\n".join([
        "### Paper example vs Table 1 (parabolic stand-in separation R_y = 31.7 mm, combined layer; "
        "reference: the paper's Table 1)", paper_md,
        "### Run times (median; the machine is shared: CPU time is the steadier number)", time_md,
        "### Discretisation error vs Hertz (circle R = 300 mm, alpha = 0.5, no layer; reference: Hertz)", hertz_md,
        f"### Grid convergence (paper scene with layer; reference: the same solver at h = {h_ref} mm)", conv_md,
    ])
    return {"title": "Normal contact: Kik–Piotrowski with the Prandtl layer, passes to shakedown",
            "markdown": md, "figures": [str(f) for f in figs],
            "data": {"paper": paper_data, "timings_s": time_data,
                     "hertz_circle": {str(k): v for k, v in hertz_data.items()},
                     "grid_convergence": {str(k): v for k, v in conv_data.items()}}}


if __name__ == "__main__":
    import sys
    res = run(sys.argv[1] if len(sys.argv) > 1 else "quick", pathlib.Path("out/bench"))
    print(res["markdown"])
