"""FASTSIM benchmark: run time vs discretisation, convergence, Kalker's linear theory, the paper's Table 1.

Units: ms, mm, N, MPa, W/mm^2, N/mm. Elliptic (Hertz) stand-in patches on strips; the paper's creepages
vx = 0.002, phi = 0.0012 1/mm, E = 210 GPa, nu = 0.28, V = 1 m/s.
"""

from __future__ import annotations

import itertools
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from benchmarks.harness import machine_info, median_time, peak_memory_mb
from contact.tangential.fastsim import (
    Creepage,
    _march,
    equivalent_ellipse,
    simplified_theory_fx_ratio,
    solve_tangential,
)
from contact.tangential.kalker_coefficients import creep_coefficients
from contact.normal.patch import Patch
from wrlayer.plotting import save_figure

E_MPA, NU = 210000.0, 0.28
G_MPA = E_MPA / (2 * (1 + NU))
PAPER_CREEP = Creepage(vx=0.002, vy=0.0, phi_per_mm=0.0012)
NORMAL_N = 1.0e5
# Table 1 of the paper: (column, patch length mm, width mm, Fx kN, Fy kN, p_max MPa, W_T max, P_T max W/mm^2)
PAPER_TABLE1 = [
    ("with Prandtl body", 29.97, 4.18, -14.44, -18.98, 1456, 43.11, 5.90),
    ("without layer", 27.36, 3.85, -14.84, -21.24, 1724, 35.37, 6.48),
    ("after shakedown", 28.1, 4.51, -18.42, -16.69, 1190, 37.87, 4.72),
]


def hertz_patch(a_mm: float, b_mm: float, normal_N: float, ny: int) -> Patch:
    """Elliptic patch on ny strips: x_l(y) = a sqrt(1 - y^2/b^2), p_peak(y) = p0 sqrt(1 - y^2/b^2)."""
    p0 = 3 * normal_N / (2 * np.pi * a_mm * b_mm)
    h = 2 * b_mm / ny
    y = -b_mm + (np.arange(ny) + 0.5) * h
    r = np.sqrt(1 - (y / b_mm) ** 2)
    return Patch(h, y, a_mm * r, p0 * r)


def analytic_fx_ratio(patch: Patch, vx: float, L1: float, mu: float) -> float:
    """|Fx| / (mu N) of continuum FASTSIM (one flexibility) on a p_peak ~ x_l patch, pure vx (exact)."""
    return simplified_theory_fx_ratio(vx * patch.x_lead_mm[0] / (L1 * mu * patch.p_peak_MPa[0]))


def _timings(quick: bool) -> dict:
    patch_cache = {}
    rows = []
    grid = [(31, nx) for nx in (20, 40, 60, 120, 240)] + [(ny, 60) for ny in (11, 61, 121)]
    if not quick:
        grid += [(31, 480), (241, 60)]
    repeat = 15 if quick else 41
    for ny, nx in grid:
        patch = patch_cache.setdefault(ny, hertz_patch(13.68, 1.925, NORMAL_N, ny))
        total, _ = median_time(lambda p=patch, n=nx: solve_tangential(p, PAPER_CREEP, G_MPA, NU, 0.3, nx=n),
                               repeat=repeat)
        ell = equivalent_ellipse(patch, G_MPA, NU)
        pn = patch.p_peak_MPa[:, None] * np.ones((1, nx))
        args = (patch.x_lead_mm, np.zeros(patch.n_strips), patch.y_mm, pn, nx, ell.L1_mm_per_MPa, ell.L2_mm_per_MPa,
                PAPER_CREEP.vx / ell.L1_mm_per_MPa, 0.0, PAPER_CREEP.phi_per_mm / ell.L3_mm_per_MPa, 0.3)
        kernel, _ = median_time(lambda a=args: _march(*a), repeat=repeat)
        rows.append({"ny": ny, "nx": nx, "solve_ms": total * 1e3, "kernel_ms": kernel * 1e3})
    return {"rows": rows}


def _convergence(quick: bool, out: pathlib.Path) -> tuple[dict, str]:
    patch = hertz_patch(13.68, 1.925, NORMAL_N, 31)
    nx_ref = 4000 if quick else 16000
    nxs = [10, 17, 30, 55, 100, 180, 320, 570] + ([] if quick else [1000, 1800])  # not nested: the slip
    # onset falls at a different place in its cell for each nx (nested grids would repeat the same phase)
    mu = 0.3
    ref = solve_tangential(patch, PAPER_CREEP, G_MPA, NU, mu, nx=nx_ref)
    keys = {"Fx": "Fx_N", "Fy": "Fy_N", "Mz": "Mz_Nmm", "PT_max": "PT_max_W_per_mm2", "WT_max": "WT_max_N_per_mm",
            "slip_area": "slip_area_mm2"}
    errors = {k: [] for k in keys}
    for nx in nxs:
        r = solve_tangential(patch, PAPER_CREEP, G_MPA, NU, mu, nx=nx)
        for k, attr in keys.items():
            errors[k].append(abs(getattr(r, attr) / getattr(ref, attr) - 1))
    # pure vx against the exact continuum solution
    L1 = equivalent_ellipse(patch, G_MPA, NU).L1_mm_per_MPa
    analytic = {}
    for vx in (5e-4, 2e-3):
        exact = analytic_fx_ratio(patch, vx, L1, mu)
        analytic[vx] = [abs(-solve_tangential(patch, Creepage(vx=vx), G_MPA, NU, mu, nx=nx).Fx_N
                            / (mu * patch.normal_force_N()) / exact - 1) for nx in nxs]
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    for k, e in errors.items():
        ax1.loglog(nxs, np.maximum(e, 1e-16), "o-", label=k)
    ax1.set(xlabel="cells per strip nx", ylabel=f"relative error vs nx = {nx_ref}",
            title="paper creepages (vx 0.002, phi 0.0012/mm), mu 0.3")
    ax1.grid(True, which="both", alpha=0.3)
    ax1.legend(fontsize=8)
    for vx, e in analytic.items():
        ax2.loglog(nxs, np.maximum(e, 1e-16), "o-", label=f"Fx, vx = {vx:g}")
    ax2.set(xlabel="cells per strip nx", ylabel="relative error vs exact continuum FASTSIM",
            title="pure longitudinal creepage, elliptic patch")
    ax2.grid(True, which="both", alpha=0.3)
    ax2.legend(fontsize=8)
    fig.tight_layout()
    png = out / "fastsim_convergence.png"
    _save(fig, png)
    lines = ["| nx | " + " | ".join(keys) + " | Fx exact (vx=5e-4) | Fx exact (vx=2e-3) |",
             "|---" * (len(keys) + 3) + "|"]
    for i, nx in enumerate(nxs):
        lines.append(f"| {nx} | " + " | ".join(f"{errors[k][i]:.1e}" for k in keys)
                     + f" | {analytic[5e-4][i]:.1e} | {analytic[2e-3][i]:.1e} |")
    md = (f"Relative errors against nx = {nx_ref} (same 31-strip patch; columns 2-7) and against the exact "
          "continuum simplified theory for pure vx (last two columns, 'Fx exact'):\n\n" + "\n".join(lines))
    data = {"nx": nxs, "nx_reference": nx_ref, "errors_vs_fine": errors,
            "errors_vs_exact_vx": {str(k): v for k, v in analytic.items()}, "png": str(png)}
    return data, md


def _linear_theory() -> tuple[list, str]:
    rows = []
    for a, b in ((6.0, 4.0), (13.68, 1.925), (2.0, 6.0)):
        patch = hertz_patch(a, b, NORMAL_N, 41)
        c = creep_coefficients(a / b, NU)
        s = 1e-7
        cases = {
            "Fx(vx)": (solve_tangential(patch, Creepage(vx=s), G_MPA, NU, 0.3).Fx_N, -G_MPA * a * b * c.C11 * s),
            "Fy(vy)": (solve_tangential(patch, Creepage(vy=s), G_MPA, NU, 0.3).Fy_N, -G_MPA * a * b * c.C22 * s),
            "Fy(phi)": (solve_tangential(patch, Creepage(phi_per_mm=s), G_MPA, NU, 0.3).Fy_N,
                        -G_MPA * a * b * np.sqrt(a * b) * c.C23 * s),
        }
        for name, (got, want) in cases.items():
            rows.append({"a_mm": a, "b_mm": b, "case": name, "fastsim": got, "kalker": want, "rel_err": got / want - 1})
    md = ["| a x b (mm) | force | FASTSIM / Kalker linear - 1 |", "|---|---|---|"]
    md += [f"| {r['a_mm']} x {r['b_mm']} | {r['case']} | {r['rel_err']:+.2e} |" for r in rows]
    return rows, "\n".join(md)


def _paper_table(mus=(0.3, 0.4), rules=("three", "single", "blended")) -> tuple[list, str]:
    rows = []
    for (col, length, width, fx, fy, pmax, wt, pt), mu, rule in itertools.product(PAPER_TABLE1, mus, rules):
        patch = hertz_patch(length / 2, width / 2, NORMAL_N, 31)
        r = solve_tangential(patch, PAPER_CREEP, G_MPA, NU, mu, speed_mm_s=1000.0, nx=60, flexibility=rule)
        rows.append({"column": col, "mu": mu, "flexibility": rule, "Fx_kN": r.Fx_N / 1e3, "Fy_kN": r.Fy_N / 1e3,
                     "p_max_MPa": float(patch.p_peak_MPa.max()), "WT_max_N_per_mm": r.WT_max_N_per_mm,
                     "PT_max_W_per_mm2": r.PT_max_W_per_mm2,
                     "paper": {"Fx_kN": fx, "Fy_kN": fy, "p_max_MPa": pmax, "WT_max": wt, "PT_max": pt}})
    md = [("| column | mu | flexibility | Fx kN (paper) | Fy kN (paper) | p_max MPa (paper) "
           "| W_T max N/mm (paper, printed 'Nm/m') | P_T max W/mm^2 (paper) | W_T/P_T mm (paper) |"),
          "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        p = r["paper"]
        md.append(f"| {r['column']} | {r['mu']} | {r['flexibility']} | {r['Fx_kN']:.2f} ({p['Fx_kN']}) "
                  f"| {r['Fy_kN']:.2f} ({p['Fy_kN']}) | {r['p_max_MPa']:.0f} ({p['p_max_MPa']}) "
                  f"| {r['WT_max_N_per_mm']:.1f} ({p['WT_max']}) | {r['PT_max_W_per_mm2']:.2f} ({p['PT_max']}) "
                  f"| {r['WT_max_N_per_mm'] / r['PT_max_W_per_mm2']:.1f} ({p['WT_max'] / p['PT_max']:.1f}) |")
    return rows, "\n".join(md)


def _save(fig, png: pathlib.Path) -> None:

    save_figure(fig, png)


def _timing_figure(timing: dict, out: pathlib.Path) -> pathlib.Path:
    rows = timing["rows"]
    fig, ax = plt.subplots(figsize=(6, 4))
    cells = [r["ny"] * r["nx"] for r in rows]
    ax.loglog(cells, [r["solve_ms"] for r in rows], "o", label="solve_tangential (total)")
    ax.loglog(cells, [r["kernel_ms"] for r in rows], "s", label="numba march only")
    ax.axhline(1.0, color="grey", ls=":", label="1 ms")
    ax.set(xlabel="cells (strips x nx)", ylabel="median time (ms)", title="FASTSIM run time")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    png = out / "fastsim_timing.png"
    _save(fig, png)
    return png


def run(mode: str, out: pathlib.Path) -> dict:
    quick = mode != "full"
    out = pathlib.Path(out)
    out.mkdir(parents=True, exist_ok=True)
    solve_tangential(hertz_patch(6, 4, NORMAL_N, 5), PAPER_CREEP, G_MPA, NU, 0.3)  # compile / load numba cache
    timing = _timings(quick)
    timing_png = _timing_figure(timing, out)
    conv, conv_md = _convergence(quick, out)
    linear, linear_md = _linear_theory()
    paper, paper_md = _paper_table()
    typical = hertz_patch(13.68, 1.925, NORMAL_N, 31)
    _, mem_typical = peak_memory_mb(lambda: solve_tangential(typical, PAPER_CREEP, G_MPA, NU, 0.3, nx=60))
    big = hertz_patch(13.68, 1.925, NORMAL_N, 121)
    _, mem_big = peak_memory_mb(lambda: solve_tangential(big, PAPER_CREEP, G_MPA, NU, 0.3, nx=240))
    t_md = ["| strips ny | cells nx | solve (ms) | march kernel (ms) |", "|---|---|---|---|"]
    t_md += [f"| {r['ny']} | {r['nx']} | {r['solve_ms']:.3f} | {r['kernel_ms']:.3f} |" for r in timing["rows"]]
    markdown = "\n\n".join([
        ("Elliptic (Hertz) stand-in patches on strips, E = 210 GPa, nu = 0.28, paper creepages vx = 0.002, "
         "phi = 0.0012 1/mm, V = 1 m/s. Timings are medians (benchmarks.harness.median_time) on a shared machine."),
        "**Run time** (patch 27.36 x 3.85 mm):\n\n" + "\n".join(t_md),
        (f"Peak Python-heap memory of one solve: {mem_typical:.2f} MiB (31 x 60 cells), {mem_big:.2f} MiB "
         "(121 x 240 cells)."),
        "**Convergence with nx** (reference: the same solver at a much finer nx; and, for pure vx, the exact "
        "continuum solution of the simplified theory, contact.tangential.fastsim.simplified_theory_fx_ratio):\n\n"
        + conv_md,
        "**Kalker's linear theory** (reference: Fx = -G a b C11 vx, Fy = -G a b (C22 vy + sqrt(ab) C23 phi), "
        "C_ij from Kalker 1990 Table E3), 41 strips, nx = 60, creepage 1e-7:\n\n" + linear_md,
        "**Paper Table 1** (reference: the paper's printed values, in parentheses). Our patches are Hertz ellipses "
        "with the paper's length and width at 100 kN, not the paper's non-elliptic patches (Fig. 4 is not "
        "available), and the paper's friction coefficient is not stated, so only trends and ratios are "
        "comparable. W_T/P_T (mm at V = 1 m/s) is an effective slip length; ours is 2-3 times the paper's, "
        "which suggests the paper's W_T differs from ours by a unit or definition factor.\n\n" + paper_md,
    ])
    return {
        "title": "FASTSIM (Kalker's simplified theory on strip patches)",
        "markdown": markdown,
        "figures": [str(timing_png), conv["png"]],
        "data": {"timing": timing, "convergence": conv, "linear_theory": linear, "paper_table1": paper,
                 "memory_MiB": {"31x60": mem_typical, "121x240": mem_big}, "machine": machine_info()},
    }


if __name__ == "__main__":  # manual run: python -m benchmarks.bench_fastsim [quick|full] [out_dir]
    import json
    import sys

    res = run(sys.argv[1] if len(sys.argv) > 1 else "quick",
              pathlib.Path(sys.argv[2] if len(sys.argv) > 2 else "out/bench/fastsim"))
    print(res["markdown"])
    print(json.dumps(res["figures"]))
