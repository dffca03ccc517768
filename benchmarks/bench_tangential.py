"""Tangential methods side by side: FASTSIM, FaStrip and Kalker's exact theory, time against error; the exact
tangential solve against the exact normal solve on the same grid; the two FASTSIM spin-centre defects.

Units: ms, mm, N, MPa. Hertzian pressures on grids of rectangular cells (:class:`PressureGrid`), the paper's
creepages vx = 0.002, phi = 0.0012 1/mm (and pure vx, pure vy), E = 210 GPa, nu = 0.28, mu = 0.3. Reference:
the exact solver on a fine grid. The strip methods run on the grid's lines (one strip per line) with nx cells.
"""

from __future__ import annotations

import pathlib
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from benchmarks.bench_tangential_cost import G_MPA, MU, NU, SCENES, normal_vs_tangential, scene
from benchmarks.bench_tangential_cost import markdown as cost_markdown
from benchmarks.harness import machine_info, median_time
from contact.normal.exact import fastsim_pressure, strip_centres
from contact.normal.patch import Patch
from contact.scenes.simulation import simulate
from contact.tangential.fastsim import Creepage
from contact.tangential.method import TANGENTIAL_METHODS, PressureGrid, solve_on_grid
from contact.tangential.spin_centre import solve_about_centroid
from wrlayer.plotting import save_figure

NORMAL_N = 1.0e5
CREEPAGES = {"paper (vx 0.002, phi 0.0012)": Creepage(0.002, 0.0, 0.0012), "vx 0.002": Creepage(0.002, 0.0, 0.0),
             "vy 0.002": Creepage(0.0, 0.002, 0.0)}
#: Hertz patches (a, b) in mm at 100 kN: round, and the paper's no-layer patch size (27.36 x 3.85 mm).
PATCHES = {"6 x 4": (6.0, 4.0), "13.68 x 1.925": (13.68, 1.925)}


def hertz_grid(a: float, b: float, nx: int) -> PressureGrid:
    """Hertz pressure of 100 kN on nx cells along 2a and square-ish cells along y (at least 8 lines), 2 free cells
    each side."""
    ny = max(8, 2 * int(round(nx * b / a / 2)))
    p0 = 3 * NORMAL_N / (2 * np.pi * a * b)
    x = (np.arange(-(nx // 2 + 2), nx // 2 + 2) + 0.5) * 2 * a / nx
    y = (np.arange(-(ny // 2 + 2), ny // 2 + 2) + 0.5) * 2 * b / ny
    X, Y = np.meshgrid(x, y)
    return PressureGrid(x, y, p0 * np.sqrt(np.clip(1 - (X / a) ** 2 - (Y / b) ** 2, 0, None)))


def _forces(res) -> np.ndarray:
    r = res[0]
    return np.array([r.Fx_N, r.Fy_N, r.Mz_Nmm])


def _time_error(quick: bool) -> list[dict]:
    """Median time and error (relative to |F| of the reference; Mz relative to its own reference) of every method
    at several resolutions, on every patch and creepage."""
    rows = []
    fine = 64 if quick else 128
    exact_n = (16, 24, 32) if quick else (16, 24, 32, 48, 64)
    strip_n = (20, 60) if quick else (20, 40, 60, 120)
    for pname, (a, b) in PATCHES.items():
        ref_grid = hertz_grid(a, b, fine)
        for cname, cr in CREEPAGES.items():
            ref = _forces(solve_on_grid(ref_grid, cr, MU, G_MPA, NU, "exact"))
            scale = max(np.hypot(ref[0], ref[1]), 1e-9)
            cases = [("exact", n, n) for n in exact_n] + [(m, 32, k) for m in ("fastsim", "fastrip") for k in strip_n]
            for method, n, k in cases:
                grid = hertz_grid(a, b, n)
                run = lambda: solve_on_grid(grid, cr, MU, G_MPA, NU, method, nx=k)  # noqa: E731
                t, _ = median_time(run, repeat=3 if quick else 5)
                got = _forces(run())
                err = np.abs(got - ref)
                rows.append({"patch": pname, "creepage": cname, "method": method, "grid_nx": n, "strip_nx": k,
                             "ms": 1e3 * t, "Fx_N": got[0], "Fy_N": got[1], "Mz_Nmm": got[2],
                             "F_error": float(np.hypot(err[0], err[1]) / scale),
                             "Mz_error": float(err[2] / max(abs(ref[2]), 1e-9)) if abs(ref[2]) > 1 else 0.0,
                             "ref_Fx_N": ref[0], "ref_Fy_N": ref[1], "ref_Mz_Nmm": ref[2]})
    return rows


def _defects(quick: bool) -> list[dict]:
    """Fx, Fy (N) as the scene runner computes them (FASTSIM, spin about each patch's reference strip), FASTSIM with
    the spin about each patch's force centroid and the creepages about the scene origin (the fix), FaStrip and
    the exact theory on the exact normal solver's grid."""
    rows = []
    for name, (sep, normal_N) in SCENES.items():
        for normal, cells in [("kik_piotrowski", 48)] + [("exact", c) for c in ((48,) if quick else (24, 48, 96))]:
            sc = scene(sep, normal_N, normal, cells)
            snap = simulate(sc).first
            sol = snap.solution
            cr = Creepage(0.002, 0.0, 0.0012)
            row = {"scene": name, "normal": normal, "cells": cells, "y_ref_mm": list(snap.y_ref_mm),
                   "as_run": [sum(t.Fx_N for t in snap.tangential), sum(t.Fy_N for t in snap.tangential)]}
            fixed = []
            for i, (lp, yr) in enumerate(zip(snap.local_patches, snap.y_ref_mm)):
                kw = {} if sol.field is None else {"pressure_cells_MPa": fastsim_pressure(sol, i, 60),
                                                   "strip_centre_mm": strip_centres(sol, i)}
                scene_patch = Patch(lp.grid_mm, lp.y_mm + yr, lp.x_lead_mm, lp.p_peak_MPa)
                fixed.append(solve_about_centroid(scene_patch, cr, G_MPA, NU, MU, **kw))
            row["fastsim_fixed"] = [sum(t.Fx_N for t in fixed), sum(t.Fy_N for t in fixed)]
            if sol.field is not None:
                grid = PressureGrid.from_exact(sol)
                for method in ("fastrip", "exact"):
                    t0 = time.perf_counter()
                    res = solve_on_grid(grid, cr, MU, G_MPA, NU, method)
                    row[method] = [sum(r.Fx_N for r in res), sum(r.Fy_N for r in res)]
                    row[method + "_ms"] = 1e3 * (time.perf_counter() - t0)
            rows.append(row)
    return rows


def _figure(rows: list[dict], out: pathlib.Path) -> pathlib.Path:
    fig, axes = plt.subplots(1, len(PATCHES), figsize=(11, 4))
    marks = {"fastsim": "o", "fastrip": "s", "exact": "^"}
    for ax, pname in zip(np.atleast_1d(axes), PATCHES):
        for method, mk in marks.items():
            sel = [r for r in rows if r["patch"] == pname and r["method"] == method]
            ax.loglog([r["ms"] for r in sel], [max(r["F_error"], 1e-5) for r in sel], mk, label=method, alpha=0.7)
        ax.set(xlabel="median time (ms)", ylabel="|F - F_ref| / |F_ref|", title=f"Hertz {pname} mm")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    png = out / "tangential_time_error.png"
    save_figure(fig, png)
    return png


def _markdown(rows, defects, nt) -> str:
    t = ["| patch | creepage | method | grid nx | strip nx | time (ms) | F error | Mz error |", "|---" * 8 + "|"]
    t += [f"| {r['patch']} | {r['creepage']} | {r['method']} | {r['grid_nx']} | "
          f"{r['strip_nx'] if r['method'] != 'exact' else '-'} | {r['ms']:.1f} | {100 * r['F_error']:.2f} % | "
          f"{100 * r['Mz_error']:.1f} % |" for r in rows]
    d = ["| scene | normal | cells | y_ref (mm) | as run Fx, Fy (kN) | FASTSIM fixed | FaStrip | exact |",
         "|---" * 8 + "|"]
    kn = lambda v: "-" if v is None else f"{v[0] / 1e3:.2f}, {v[1] / 1e3:.2f}"  # noqa: E731
    d += [f"| {r['scene']} | {r['normal']} | {r['cells']} | {', '.join(f'{v:.2f}' for v in r['y_ref_mm'])} | "
          f"{kn(r['as_run'])} | {kn(r['fastsim_fixed'])} | {kn(r.get('fastrip'))} | {kn(r.get('exact'))} |"
          for r in defects]
    return "\n\n".join([
        __doc__.split("\n\n", 1)[1].strip(),
        "**Time against error** (F error: |(Fx, Fy) - reference| / |reference|; reference: exact theory on the "
        "finest grid):\n\n" + "\n".join(t),
        "**Exact tangential against exact normal solve** (benchmarks.bench_tangential_cost). " + cost_markdown(nt),
        "**FASTSIM spin-centre defects** (scene creepages vx = 0.002, phi = 0.0012 1/mm about the scene origin; "
        "'as run': contact.scenes.simulation today, spin about each patch's reference strip y_ref; 'fixed': "
        "contact.tangential.spin_centre.solve_about_centroid):\n\n" + "\n".join(d),
    ])


def run(mode: str, out: pathlib.Path) -> dict:
    quick = mode != "full"
    out = pathlib.Path(out)
    out.mkdir(parents=True, exist_ok=True)
    for m in TANGENTIAL_METHODS:                                   # compile / load the numba caches
        solve_on_grid(hertz_grid(6.0, 4.0, 8), CREEPAGES["vx 0.002"], MU, G_MPA, NU, m)
    rows = _time_error(quick)
    nt = normal_vs_tangential(quick)
    defects = _defects(quick)
    png = _figure(rows, out)
    return {"title": "Tangential methods: FASTSIM, FaStrip, exact (Kalker's full theory)",
            "markdown": _markdown(rows, defects, nt), "figures": [str(png)],
            "data": {"time_error": rows, "normal_vs_tangential": nt, "defects": defects, "machine": machine_info()}}


if __name__ == "__main__":  # manual run: python -m benchmarks.bench_tangential [--quick|--full] [out_dir]
    import json
    import sys

    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    res = run("full" if "--full" in sys.argv else "quick", pathlib.Path(args[0] if args else "out/bench/tangential"))
    print(res["markdown"])
    print(json.dumps(res["figures"]))
