"""Benchmark of the exact half-space normal solver (contact.normal.exact) and of the Kik–Piotrowski error against it.

1. Time against error on the paper scene (N = 100 kN, R = 1600 mm, R_y = 31.7 mm, E = 210 GPa, nu = 0.3; strip grid
   h = 0.1 mm) without layer and with the paper's combined layer (indentation and rolling modes), for a range of
   ``method.exact_cells``; error against the same solver on a much finer grid (h = 0.05 mm, 256 cells).
2. A full pass (exact normal + FASTSIM on the patch) at the default cell count.
3. "KP error vs exact": the Kik–Piotrowski solver's error against the exact solver (128 cells) on a set of
   separations, without and with the layer (indentation mode, the KP layer model).
4. Side by side with ContactMechanics (PyPI, optional ``bench`` dependency): the Hertz check scene on one square
   0.1 mm grid, the same Polonsky–Keer problem solved by ContactMechanics and by our half-space + CG.
Timings: median of repeated runs after a warm-up, on a machine shared with other jobs (load average reported).
Units: ms, mm, MPa, N.
"""

from __future__ import annotations

import os
import pathlib
import time

import numpy as np

from benchmarks.harness import median_time
from contact.layer.prandtl_layer import LayerPair, PrandtlLayer
from contact.normal.exact import DEFAULT_CELLS, ExactOptions, solve_exact
from contact.normal.halfspace import HalfSpace, compliance_factor
from contact.normal.constrained_cg import constrained_cg
from contact.normal.kik_piotrowski import NormalProblem, solve_normal
from contact.scenes.paper_example import paper_characteristic
from contact.tangential.fastsim import Creepage, solve_tangential
from wrlayer.plotting import save_figure

E, NU, N, R = 210000.0, 0.3, 1.0e5, 1600.0
KEYS = (("p_max_MPa", "p_max"), ("area_mm2", "area"), ("delta_mm", "delta"), ("length_mm", "length"),
        ("width_mm", "width"))


def _cpu_and_wall(fn, repeat: int) -> tuple[float, float]:
    """Median CPU time (this process, s) and median wall time (s) of ``fn()`` after one warm-up run. On this
    shared machine the CPU time is the steadier number (waiting for a core does not count)."""
    fn()
    cpu, wall = [], []
    for _ in range(repeat):
        c0, w0 = time.process_time(), time.perf_counter()
        fn()
        cpu.append(time.process_time() - c0)
        wall.append(time.perf_counter() - w0)
    return float(np.median(cpu)), float(np.median(wall))


def _row(cells) -> str:
    return "| " + " | ".join(str(c) for c in cells) + " |"


def _problem(y, f, grid_mm=0.1) -> NormalProblem:
    return NormalProblem(y, f, N, R, E, NU, grid_mm=grid_mm)


def _layer(prob: NormalProblem) -> LayerPair:
    return LayerPair(combined=PrandtlLayer.uniform(paper_characteristic(), prob.strip_y_mm, name="paper layer"))


def _paper(grid_mm=0.1) -> NormalProblem:
    y = np.linspace(-8.0, 8.0, 641)
    return _problem(y, y * y / (2 * 31.7), grid_mm)


def _err(sol, ref, key) -> float:
    return 100.0 * (getattr(sol, key) - getattr(ref, key)) / getattr(ref, key)


def _time_error(cells_list, repeat) -> tuple[str, dict]:
    lines = [_row(["case", "exact_cells", "grid (lines x cells)", "CG it.", "layer it.", "median CPU [ms]",
                   "median wall [ms]", "p_max err [%]", "area err [%]", "delta err [%]"]), _row(["---"] * 10)]
    data = {}
    for case, mode, with_layer in (("no layer", "indentation", False), ("layer, indentation", "indentation", True),
                                   ("layer, rolling", "rolling", True)):
        fine = _paper(0.05)
        ref = solve_exact(fine, _layer(fine) if with_layer else None, ExactOptions(cells=256, layer_mode=mode))
        prob = _paper()
        layer = _layer(prob) if with_layer else None
        for cells in cells_list:
            opts = ExactOptions(cells=cells, layer_mode=mode)
            sol = solve_exact(prob, layer, opts)
            cpu, t = _cpu_and_wall(lambda: solve_exact(prob, layer, opts), repeat)
            e = {k: _err(sol, ref, k) for k, _ in KEYS}
            data[f"{case}/{cells}"] = {"time_s": t, "cpu_s": cpu, "errors_percent": e, "iterations": sol.iterations}
            it = sol.iterations
            lines.append(_row([case, f"**{cells}**" if cells == DEFAULT_CELLS else cells,
                               f"{it['grid_cells'][0]} x {it['grid_cells'][1]}", it["cg_iterations"],
                               it["layer_iterations"], f"{1e3 * cpu:.1f}", f"{1e3 * t:.1f}", f"{e['p_max_MPa']:+.3f}",
                               f"{e['area_mm2']:+.3f}", f"{e['delta_mm']:+.4f}"]))
    return "\n".join(lines), data


def _time_error_figure(data: dict, out: pathlib.Path) -> list[pathlib.Path]:
    """error (p_max, area) against CPU time per case, one point per cell count."""

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt


    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
    for case in ("no layer", "layer, indentation", "layer, rolling"):
        keys = [k for k in data if k.startswith(case + "/")]
        cells = [int(k.split("/")[1]) for k in keys]
        t = [1e3 * data[k]["cpu_s"] for k in keys]
        for ax, q in zip(axes, ("p_max_MPa", "area_mm2")):
            err = [max(abs(data[k]["errors_percent"][q]), 1e-4) for k in keys]
            ax.loglog(t, err, "o-", label=case)
            for ti, ei, c in zip(t, err, cells):
                ax.annotate(str(c), (ti, ei), fontsize=7)
    for ax, q in zip(axes, ("p_max", "area")):
        ax.set_xlabel("CPU time per solve [ms] (shared machine)")
        ax.set_ylabel(f"|{q} error| [%] vs fine reference")
        ax.axhline(1.0, color="0.6", lw=0.8)
        ax.legend(fontsize=8)
    fig.suptitle("Exact solver on the paper scene: error against time (labels: exact_cells)")
    fig.tight_layout()
    path = out / "exact_time_error.png"
    save_figure(fig, path)
    return [path]


def _full_pass(repeat) -> tuple[str, dict]:
    prob = _paper()
    layer = _layer(prob)
    creep = Creepage(0.002, 0.0, 0.0012)
    G = E / (2 * (1 + NU))
    out, data = [_row(["step", "median CPU [ms]", "median wall [ms]"]), _row(["---"] * 3)], {}

    def normal():
        return solve_exact(prob, layer, ExactOptions(layer_mode="rolling"))

    sol = normal()

    def tangential():
        return [solve_tangential(pt, creep, G, NU, 0.3) for pt in sol.patches]

    def full():
        s = normal()
        return [solve_tangential(pt, creep, G, NU, 0.3) for pt in s.patches]

    for name, fn in (("KP pre-solve (grid placement)", lambda: solve_normal(prob, layer)),
                     ("exact normal, rolling layer", normal), ("FASTSIM on the exact patch", tangential),
                     ("full pass (normal + FASTSIM)", full)):
        cpu, t = _cpu_and_wall(fn, repeat)
        data[name] = {"wall_s": t, "cpu_s": cpu}
        out.append(_row([name, f"{1e3 * cpu:.1f}", f"{1e3 * t:.1f}"]))
    return "\n".join(out), data


def _separations() -> list[tuple[str, np.ndarray, np.ndarray]]:
    y8 = np.linspace(-8.0, 8.0, 641)
    y20 = np.linspace(-20.0, 20.0, 1601)
    out = [(f"parabola R_y = {ry:g} mm", y, y * y / (2 * ry)) for ry, y in
           ((31.7, y8), (100.0, y8), (300.0, y20), (1600.0, y20))]
    out.append(("quartic f = 0.002 y^4 (flat-topped)", y8, 0.002 * y8 ** 4))
    out.append(("asymmetric: R_y = 20 mm (y < 0), 80 mm (y > 0)", y8, np.where(y8 < 0, y8 ** 2 / 40.0, y8 ** 2 / 160.0)))
    y2 = np.linspace(-8.0, 14.0, 881)
    out.append(("two minima 6 mm apart (R_y = 25 mm, second 0.02 mm higher)", y2,
                np.minimum(y2 ** 2 / 50.0, (y2 - 6.0) ** 2 / 50.0 + 0.02)))
    return out


def _kp_vs_exact(repeat) -> tuple[str, dict]:
    lines = [_row(["separation", "layer", "exact p_max [MPa]", "exact area [mm^2]", "KP p_max err [%]",
                   "KP area err [%]", "KP delta err [%]", "KP length err [%]", "KP width err [%]", "exact time [ms]"]),
             _row(["---"] * 10)]
    data = {}
    for name, y, f in _separations():
        prob = _problem(y, f)
        for with_layer in (False, True):
            layer = _layer(prob) if with_layer else None
            kp = solve_normal(prob, layer)
            ex = solve_exact(prob, layer, ExactOptions(cells=128))
            t, _ = median_time(lambda: solve_exact(prob, layer), repeat=repeat)
            e = {k: _err(kp, ex, k) for k, _ in KEYS}
            data[f"{name}/{'layer' if with_layer else 'no layer'}"] = {"errors_percent": e, "exact_p_max": ex.p_max_MPa,
                                                                      "exact_area": ex.area_mm2, "time_s": t}
            lines.append(_row([name, "paper layer" if with_layer else "none", f"{ex.p_max_MPa:.0f}",
                               f"{ex.area_mm2:.1f}"] + [f"{e[k]:+.1f}" for k, _ in KEYS] + [f"{1e3 * t:.1f}"]))
    return "\n".join(lines), data


def _contact_mechanics(repeat) -> tuple[str, dict]:
    """The Hertz check scene (R_x = 300, R_y = 80 mm, N = 50 kN, E = 210 GPa, nu = 0.28) on one square 0.1 mm
    grid of 160 x 80 cells (16 x 8 mm): ContactMechanics' free-boundary FFT half-space + its Polonsky–Keer CG
    against our HalfSpace + constrained_cg on the same cells; errors against Hertz."""
    try:
        from ContactMechanics import FreeFFTElasticHalfSpace
        from ContactMechanics.Optimization.ConstrainedConjugateGradients import constrained_conjugate_gradients
        from SurfaceTopography import Topography
    except ImportError as err:
        return f"ContactMechanics not installed ({err}); `pip install ContactMechanics` to run this part.", {}
    from scipy.special import ellipk
    e_, nu_, n_, rx, ry, h = 210000.0, 0.28, 5.0e4, 300.0, 80.0, 0.1
    # Hertz (the scene's [reference], elliptic integrals): e^2 = 0.82606, a = 5.6104, b = 2.3399 mm
    a, b = 5.610435219431539, 2.339900329769085
    p0 = 3 * n_ / (2 * np.pi * a * b)
    e_star = e_ / (2 * (1 - nu_ ** 2))
    delta = p0 * b * ellipk(1 - (b / a) ** 2) / e_star
    nx, ny = 160, 80
    x = (np.arange(nx) - (nx - 1) / 2) * h
    y = (np.arange(ny) - (ny - 1) / 2) * h
    f = x[None, :] ** 2 / (2 * rx) + y[:, None] ** 2 / (2 * ry)

    def ours():
        hs = HalfSpace(ny, nx, h, h, compliance_factor(e_, nu_))
        r = constrained_cg(hs.displacement, f, 0.0, 0.0, h * h, np.where(f < f.min() + 0.05, 1.0, 0.0),
                           force_N=n_, tol=1e-6)
        return r.p_MPa, r.delta_mm

    def theirs():
        sub = FreeFFTElasticHalfSpace((nx, ny), young=e_star, physical_sizes=(nx * h, ny * h))
        topo = Topography(-f.T, physical_sizes=(nx * h, ny * h))
        res = constrained_conjugate_gradients(sub, topo, external_force=n_, pentol=1e-9)
        return np.abs(res.jac).T / (h * h), float(res.offset), res

    p_o, d_o = ours()
    p_t, d_t, res_t = theirs()
    t_o, _ = median_time(ours, repeat=repeat)
    t_t, _ = median_time(theirs, repeat=repeat)
    rows = [_row(["solver (same 160 x 80 grid, 0.1 mm)", "median time [ms]", "p_max err [%]", "area err [%]",
                  "delta err [%]"]), _row(["---"] * 5)]
    data = {}
    for name, p, d, t in (("ours: HalfSpace + constrained_cg", p_o, d_o, t_o),
                          (f"ContactMechanics {_version('ContactMechanics')}", p_t, d_t, t_t)):
        e = {"p_max": 100 * (p.max() / p0 - 1), "area": 100 * ((p > 0).sum() * h * h / (np.pi * a * b) - 1),
             "delta": 100 * (abs(d) / delta - 1)}
        data[name] = {"time_s": t, "errors_percent": e}
        rows.append(_row([name, f"{1e3 * t:.1f}", f"{e['p_max']:+.3f}", f"{e['area']:+.3f}", f"{e['delta']:+.4f}"]))
    diff = float(np.abs(p_o - p_t).max() / p_o.max())
    data["max_pressure_difference_rel"] = diff
    rows.append(f"\nLargest pressure difference between the two solutions: {100 * diff:.3f} % of p_max "
                "(area: cells with p > 0, no edge refinement).")
    return "\n".join(rows), data


def _version(pkg: str) -> str:
    from importlib import metadata
    try:
        return metadata.version(pkg)
    except metadata.PackageNotFoundError:
        return "?"


def run(mode: str, out: pathlib.Path) -> dict:
    quick = mode != "full"
    out.mkdir(parents=True, exist_ok=True)
    repeat = 7 if quick else 21
    cells = [12, 16, 24, 48, 96] if quick else [8, 12, 16, 24, 32, 48, 64, 96, 128, 192]
    load = os.getloadavg()
    t0 = time.perf_counter()
    te_md, te_data = _time_error(cells, repeat)
    figs = _time_error_figure(te_data, out)
    fp_md, fp_data = _full_pass(repeat)
    kp_md, kp_data = _kp_vs_exact(max(3, repeat // 2))
    cm_md, cm_data = _contact_mechanics(repeat)
    md = "\n\n".join([
        f"Load average at the start: {load[0]:.2f} (1 min) on a machine shared with other jobs; times are medians "
        f"after a warm-up and include the KP pre-solve that places the grid. Default exact_cells = {DEFAULT_CELLS}.",
        "### Time against error, paper scene (strip grid 0.1 mm; reference: exact solver, 0.05 mm lines, 256 cells)",
        te_md, "### One pass on the paper scene with the layer (rolling), default cells", fp_md,
        "### KP error vs exact (N = 100 kN, R = 1600 mm, grid 0.1 mm; exact at 128 cells; layer: the paper's "
        "characteristic, indentation mode)", kp_md,
        "### Side by side with ContactMechanics (Hertz check scene, no layer)", cm_md])
    return {"title": "Exact half-space normal contact (FFT boundary elements) and the KP error",
            "markdown": md, "figures": [str(f) for f in figs],
            "data": {"time_error": te_data, "full_pass_s": fp_data, "kp_vs_exact": kp_data,
                     "contact_mechanics": cm_data, "total_s": time.perf_counter() - t0, "loadavg": load}}


if __name__ == "__main__":
    import sys
    res = run(sys.argv[1] if len(sys.argv) > 1 else "quick", pathlib.Path("out/bench"))
    print(res["markdown"])
