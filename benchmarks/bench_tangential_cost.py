"""The exact tangential solve against the exact normal solve on the same grid: time against error at several
tolerances, the grid's discretisation error beside it, and the ratio of times at equal error.

Units: ms (CPU time), mm, N, MPa. Scenes: the separations of :data:`SCENES`
at the paper's creepages vx = 0.002, phi = 0.0012 1/mm, E = 210 GPa, nu = 0.28, mu = 0.3, on the exact normal
solver's grid (0.1 mm lines, ``exact_cells`` cells across the patch). Each solver's error is measured against its
own tightly converged solution on the same grid (normal: CG to 1e-10; tangential: Gauss–Seidel to 1e-12, on the
tight pressure), in comparable measures: normal max |dp| / p_max (the force is the load: |dF_N| / F_N = 0 by
construction) and |d delta| / delta; tangential max |dq| / (mu p_max) and |dF| / (mu F_N). Discretisation error:
the same outputs (p_max, delta; F = (Fx, Fy), max |q|) against the grid twice as fine in both directions (lines
0.05 mm, 2 ``exact_cells``), both solved tightly. Times: median CPU time of interleaved cold solves (the other
tolerances' and solver's runs in between), which a shared machine disturbs less than wall time.
"""

from __future__ import annotations

import os
import statistics
import time

import numpy as np

from contact.normal.exact import ExactOptions, solve_exact
from contact.scenes.scene import parse_scene
from contact.tangential.exact_rolling import RollingField, RollingOptions, solve_rolling
from contact.tangential.fastsim import Creepage
from contact.tangential.method import PressureGrid

#: CG tolerances of the normal solve timed (its default among them).
NORMAL_TOLS = (1e-3, 1e-4, ExactOptions().cg_tol, 1e-6, 1e-7)
#: Tolerances of the exact tangential solve timed (its default among them).
ROLLING_TOLS = (1e-3, 3e-4, 1e-4, 1e-5, 1e-6, 1e-8)
E_MPA, NU, MU = 210000.0, 0.28, 0.3
G_MPA = E_MPA / (2 * (1 + NU))
CREEPAGE = Creepage(0.002, 0.0, 0.0012)
#: The scenes' separations f(y) (mm) and normal loads (N): a long, nearly full-slip patch and two interacting ones.
SCENES = {"quartic f = y^4/8000, 100 kN": (lambda y: y ** 4 / (4 * 2000.0), 1e5),
          "two patches f = min((y+5)^2/80, 0.005+(y-5)^2/80), 60 kN":
              (lambda y: np.minimum((y + 5) ** 2 / 80, 0.005 + (y - 5) ** 2 / 80), 6e4)}


def scene(sep, normal_N: float, normal: str, cells: int = 48, grid_mm: float = 0.1):
    """A contact scene on the separation ``sep`` (mm of y, mm) at ``normal_N`` with the paper's creepages, solved by
    ``normal`` on lines of ``grid_mm`` (the separation table twice as fine) and ``cells`` exact cells."""
    y = np.round(np.arange(-14.0, 14.0001, min(0.05, grid_mm / 2)), 4)
    data = {"title": "tangential benchmark", "load": {"normal_force_N": normal_N, "rolling_radius_mm": 460.0},
            "material": {"E_MPa": E_MPA, "poisson": NU}, "separation": {"y_mm": y.tolist(), "f_mm": sep(y).tolist()},
            "tangential": {"creepage_x": 0.002, "creepage_y": 0.0, "spin_per_mm": 0.0012, "friction": MU},
            "method": {"normal": normal, "grid_mm": grid_mm}}
    if normal == "exact":
        data["method"]["exact_cells"] = cells
    return parse_scene(data, "benchmark.toml")


def cpu_medians(fns: dict, repeat: int = 5) -> dict:
    """Median CPU time (s) of each callable, runs interleaved after one untimed round."""
    for fn in fns.values():
        fn()
    times: dict = {k: [] for k in fns}
    for _ in range(repeat):
        for k, fn in fns.items():
            t0 = time.process_time()
            fn()
            times[k].append(time.process_time() - t0)
    return {k: statistics.median(v) for k, v in times.items()}


def rolling(grid: PressureGrid, tol: float) -> RollingField:
    """The exact tangential solve of the grid's pressure at the paper's creepages to ``tol``."""
    X, Y = np.meshgrid(grid.x_mm, grid.y_mm)
    return solve_rolling(grid.x_mm, grid.y_mm, grid.p_MPa, CREEPAGE.vx - CREEPAGE.phi_per_mm * Y,
                         CREEPAGE.vy + CREEPAGE.phi_per_mm * X, MU, G_MPA, NU, RollingOptions(tol=tol))


def _outputs(sol, tang: RollingField, grid: PressureGrid) -> dict:
    """Normal p_max (MPa), delta (mm), F_N (N); tangential F (N, (Fx, Fy)) and max |q| (MPa)."""
    area = grid.dx_mm * grid.dy_mm
    return {"p_max": float(sol.field.p_MPa.max()), "delta": float(sol.delta_mm), "F_N": float(grid.p_MPa.sum() * area),
            "F": np.array([tang.tx_MPa.sum(), tang.ty_MPa.sum()]) * area,
            "q_max": float(np.hypot(tang.tx_MPa, tang.ty_MPa).max())}


def _tight(sep, normal_N: float, cells: int, grid_mm: float):
    prob = scene(sep, normal_N, "exact", cells, grid_mm).normal_problem()
    sol = solve_exact(prob, None, ExactOptions(cells=cells, cg_tol=1e-10))
    grid = PressureGrid.from_exact(sol)
    tang = rolling(grid, 1e-12)
    return prob, sol, grid, tang


def _discretisation(coarse: dict, fine: dict) -> dict:
    """The coarse grid's outputs against the fine grid's, in the measures of the solver errors."""
    scale = MU * fine["F_N"]
    return {"p_max": abs(coarse["p_max"] - fine["p_max"]) / fine["p_max"],
            "delta": abs(coarse["delta"] - fine["delta"]) / fine["delta"],
            "F": float(np.hypot(*(coarse["F"] - fine["F"])) / scale),
            "q_max": abs(coarse["q_max"] - fine["q_max"]) / (MU * fine["p_max"])}


def _case(sep, normal_N: float, cells: int) -> dict:
    """Time against error of both solvers on one scene and cell count, with the discretisation error."""
    prob, ref, grid, tref = _tight(sep, normal_N, cells, 0.1)
    out = _outputs(ref, tref, grid)
    fine = _tight(sep, normal_N, 2 * cells, 0.05)
    disc = _discretisation(out, _outputs(fine[1], fine[3], fine[2]))
    opts = {t: ExactOptions(cells=cells, cg_tol=t) for t in NORMAL_TOLS}
    fns = {("normal", t): (lambda o=o: solve_exact(prob, None, o)) for t, o in opts.items()}
    fns.update({("tangential", t): (lambda t=t: rolling(grid, t)) for t in ROLLING_TOLS})
    times = cpu_medians(fns)
    p_ref, normal, tangential = ref.field.p_MPa, [], []
    for t, o in opts.items():
        s = solve_exact(prob, None, o)
        dp = np.abs(s.field.p_MPa - p_ref).max() if s.field.p_MPa.shape == p_ref.shape else np.nan
        normal.append({"tol": t, "ms": 1e3 * times[("normal", t)], "steps": int(s.iterations["cg_iterations"]),
                       "error": float(dp / out["p_max"]), "delta_error": abs(s.delta_mm - ref.delta_mm) / ref.delta_mm})
    area = grid.dx_mm * grid.dy_mm
    for t in ROLLING_TOLS:
        r = rolling(grid, t)
        dq = np.hypot(r.tx_MPa - tref.tx_MPa, r.ty_MPa - tref.ty_MPa).max()
        dF = np.array([(r.tx_MPa - tref.tx_MPa).sum(), (r.ty_MPa - tref.ty_MPa).sum()]) * area
        tangential.append({"tol": t, "ms": 1e3 * times[("tangential", t)], "steps": r.iterations,
                           "error": float(dq / (MU * out["p_max"])),
                           "F_error": float(np.hypot(*dF) / (MU * out["F_N"]))})
    return {"grid": list(grid.p_MPa.shape), "normal": normal, "tangential": tangential, "discretisation": disc,
            **_ratios(normal, tangential)}


def _ratios(normal: list[dict], tangential: list[dict]) -> dict:
    """Time ratios tangential / normal at the default tolerances, and at equal error: the tangential time at the
    normal default's pressure error, interpolated linearly in log error between the two tolerances that bracket it
    (the nearest one's outside their range)."""
    n_def = next(r for r in normal if r["tol"] == ExactOptions().cg_tol)
    t_def = next(r for r in tangential if r["tol"] == RollingOptions().tol)
    pts = sorted((r["error"], r["ms"], r["tol"]) for r in tangential)
    err = np.log([p[0] for p in pts])
    at = float(np.clip(np.log(n_def["error"]), err[0], err[-1]))
    ms = float(np.interp(at, err, [p[1] for p in pts]))
    tol = float(np.exp(np.interp(at, err, np.log([p[2] for p in pts]))))
    return {"ratio_default": t_def["ms"] / n_def["ms"], "equal_error_tol": tol, "ratio_equal_error": ms / n_def["ms"]}


def normal_vs_tangential(quick: bool) -> list[dict]:
    """:func:`_case` on every scene at 24 and 48 cells (and 96 unless ``quick``)."""
    rows = []
    for name, (sep, normal_N) in SCENES.items():
        for cells in (24, 48) if quick else (24, 48, 96):
            rows.append({"scene": name, "cells": cells, "load_1min": os.getloadavg()[0],
                         **_case(sep, normal_N, cells)})
    return rows


def markdown(rows: list[dict]) -> str:
    """The time-against-error table and the summary at equal error."""
    t = ["| scene | cells | solver | tol | CPU [ms] | CG steps / sweeps | max error | force or delta error |",
         "|---" * 8 + "|"]
    for r in rows:
        t += [f"| {r['scene'][:9]} | {r['cells']} | normal | {e['tol']:g} | {e['ms']:.1f} | {e['steps']} | "
              f"{e['error']:.1e} | {e['delta_error']:.1e} |" for e in r["normal"]]
        t += [f"| {r['scene'][:9]} | {r['cells']} | tangential | {e['tol']:g} | {e['ms']:.1f} | {e['steps']} | "
              f"{e['error']:.1e} | {e['F_error']:.1e} |" for e in r["tangential"]]
    s = ["| scene | cells | grid | discretisation p_max / delta | discretisation F / q_max | ratio at defaults | "
         "tol at equal error | ratio at equal error |", "|---" * 8 + "|"]
    s += [f"| {r['scene'][:9]} | {r['cells']} | {r['grid'][0]} x {r['grid'][1]} | {r['discretisation']['p_max']:.1e} "
          f"/ {r['discretisation']['delta']:.1e} | {r['discretisation']['F']:.1e} / "
          f"{r['discretisation']['q_max']:.1e} | {r['ratio_default']:.2f} | {r['equal_error_tol']:.0e} | "
          f"{r['ratio_equal_error']:.2f} |" for r in rows]
    return "\n\n".join([__doc__.split("\n\n", 1)[1].strip(),
                        "**Time against error** (max error: normal max |dp| / p_max, tangential max |dq| / (mu "
                        "p_max); force or delta error: normal |d delta| / delta, tangential |dF| / (mu F_N)):\n\n"
                        + "\n".join(t),
                        "**Summary** (discretisation: against the grid twice as fine, normal relative, tangential "
                        "over mu F_N and mu p_max; ratio = tangential / normal CPU time):\n\n" + "\n".join(s)])


if __name__ == "__main__":  # manual run: python -m benchmarks.bench_tangential_cost [--full]
    import sys

    print(markdown(normal_vs_tangential("--full" not in sys.argv)))
