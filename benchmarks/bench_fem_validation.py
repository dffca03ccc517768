"""FEM validation: 3D elastic-plastic half-space under a prescribed circular Hertz pressure.

Problem (units mm, N, MPa): quarter block 20 mm (unstructured gmsh P2 tetrahedra, element size h within 1.5 mm of
the load centre), circular Hertz pressure p0 sqrt(1 - (r/a)^2) with a = 1 mm, far faces clamped, symmetry planes
x = 0 and y = 0; steel E = 210 GPa, nu = 0.3, Y = 500 MPa, either elastic-perfectly plastic or with the
calibration's linear hardening (H_iso = H_kin = 10 GPa, `calibration/configs/default.toml`), or isotropic
hardening only (H_iso = 10 GPa or 20 GPa, H_kin = 0, for the comparison with Tamaas). The pressure is
prescribed (no indenter): p0 rises to the levels below in steps of at most 0.1 Y, and the body is
unloaded to zero from some of them (one step, restarted from the loaded state).

Independent references: (1) the closed-form Hertz stresses on the load axis (K. L. Johnson, Contact Mechanics,
Cambridge University Press 1985, eq. 3.45, p. 62; evaluated by
`calibration.fem.verification_meshes.hertz_axis_first_yield`) give the pressure and depth of first yield; (2) the
elastic-plastic response (residual dent, plastic-zone top and bottom) is compared with the same load path solved
by Tamaas, the Fourier-accelerated volume-integral method of Frérot, Bonnet, Molinari & Anciaux (CMAME 351, 951,
2019; `benchmarks/tamaas_reference.py`), for elastic-perfectly plastic and isotropic hardening (H_iso = 10 GPa,
H_kin = 0). Tamaas has no kinematic hardening; the calibration's mixed law (H_iso = H_kin = 10 GPa) is compared
with Tamaas' isotropic hardening of the summed modulus, H = 20 GPa, which it equals wherever the stress path of a
point is proportional (the back stress and the yield radius then grow along one direction: the uniaxial slope is
H_iso + H_kin either way); how far the Hertz load path is from that is measured on our FEM (mixed against isotropic
20 GPa on the same mesh). No published table or figure of this response could be read (docs/calibration.md, "Validation against an independent reference").
If Tamaas is not installed, the report says so and gives the FEM values alone.
"""

from __future__ import annotations

import json
import pathlib
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from benchmarks.harness import machine_info
from calibration.fem.assembly import discretise
from calibration.fem.elastoplastic_solver import SolverOptions, solve_load_path
from calibration.fem.material import J2Material, von_mises_MPa
from calibration.fem.verification_meshes import hertz_axis_first_yield, hertz_block_gmsh
from calibration.hertz.load import HertzLoad
from wrlayer.plotting import save_figure

Y_MPA = 500.0
A_MM = 1.0
BLOCK_MM = 20.0
FINE_MM = 1.5
MATERIALS = {
    "elastic-perfectly plastic": J2Material(210000.0, 0.3, Y_MPA),
    "linear hardening (H_iso = H_kin = 10 GPa)": J2Material(210000.0, 0.3, Y_MPA, 10000.0, 10000.0),
    "isotropic hardening (H_iso = 10 GPa, H_kin = 0)": J2Material(210000.0, 0.3, Y_MPA, 10000.0, 0.0),
    "isotropic hardening (H_iso = 20 GPa, H_kin = 0)": J2Material(210000.0, 0.3, Y_MPA, 20000.0, 0.0),
}
#: short names of the materials in the tables
SHORT = {"elastic-perfectly plastic": "EPP", "linear hardening (H_iso = H_kin = 10 GPa)": "hardening",
         "isotropic hardening (H_iso = 10 GPa, H_kin = 0)": "iso. hardening",
         "isotropic hardening (H_iso = 20 GPa, H_kin = 0)": "iso. 20 GPa"}
#: Tamaas hardening modulus (MPa) of the materials it can model (isotropic hardening only)
TAMAAS_HARDENING = {"elastic-perfectly plastic": 0.0, "isotropic hardening (H_iso = 10 GPa, H_kin = 0)": 10000.0,
                    "isotropic hardening (H_iso = 20 GPa, H_kin = 0)": 20000.0}
#: materials Tamaas cannot model -> the isotropic material they equal under proportional loading (module docstring)
TAMAAS_EQUIVALENT = {"linear hardening (H_iso = H_kin = 10 GPa)": "isotropic hardening (H_iso = 20 GPa, H_kin = 0)"}
#: p0 / Y compared with Tamaas (quick; full adds 3.4)
TAMAAS_LEVELS = (2.0, 2.6, 3.0)
DIRICHLET = {"fixed": [0, 1, 2], "side": [0, 1, 2], "symmetry": [0], "sym_y": [1]}
LOAD = HertzLoad(0.0, A_MM, a_mm=A_MM)
#: largest load step (x Y) on the way up
STEP_Y = 0.1
#: p0 / Y at which the state is recorded (loading)
LEVELS_Y = (1.8, 2.0, 2.2, 2.4, 2.6, 2.8, 3.0)
#: p0 / Y from which the body is unloaded to zero (residual dent)
UNLOAD_Y = (2.0, 2.6, 3.0)
#: depth (x a) whose crossing by the top of the plastic zone is reported (the zone rises towards the surface)
TOP_DEPTH = 0.1
#: second plastic-zone threshold (equivalent plastic strain), reported beside "> 0" for both FEM and Tamaas
ZONE_THRESHOLD = 1e-5
#: report rows: key -> (label, scale, format)
ROW_KEYS = {"z_top": ("plastic zone top z / a", 1.0, "{:.3f}"),
            "z_bottom": ("plastic zone bottom z / a", 1.0, "{:.3f}"),
            "volume": ("plastic zone volume / a³", 1.0, "{:.3f}"),
            "dent_mm": ("residual dent [µm]", 1000.0, "{:.3f}")}


def plastic_zone(disc, state, threshold: float = 0.0) -> dict:
    """Extent of the yielded region (quadrature points with equivalent plastic strain > ``threshold``), lengths / a.

    z_top / z_bottom: smallest / largest depth of a yielded point; r_max: largest distance from the load axis;
    volume: yielded volume of the whole (4 x quarter) model / a^3. Resolution: the quadrature points, i.e. a
    fraction of the element size h (no point lies on the surface: the top cannot be closer than about 0.1 h).
    """
    x = disc.qp_coordinates()
    yielded = state.eq_plastic_strain > threshold
    if not yielded.any():
        return {"z_top": float("nan"), "z_bottom": float("nan"), "r_max": float("nan"), "volume": 0.0}
    depth = -x[2][yielded]
    r = np.hypot(x[0][yielded], x[1][yielded])
    return {"z_top": float(depth.min()) / A_MM, "z_bottom": float(depth.max()) / A_MM,
            "r_max": float(r.max()) / A_MM, "volume": 4.0 * float(disc.dx[yielded].sum()) / A_MM ** 3}


def elastic_reference(disc, mesh) -> dict:
    """Elastic solve at p0 = 1 MPa: first yield / Y (the solver's: largest quadrature-point von Mises stress),
    the depth / a of the von Mises maximum, centre compliance (mm/MPa) and the von Mises stress of the quadrature
    points near the axis (r < 0.15 a) for the figure.

    No quadrature point lies on the axis, so the depth of the maximum is located by a least-squares fit
    vm = c0 + c1 z + c2 z^2 + c3 z^3 + c4 r^2 to the points with r < 0.3 a and 0.2 a < z < 0.8 a (maximum of the
    cubic on that range). The maximum is flat: other fits (quadratic on 0.25-0.75 a, quartic on 0.2-0.9 a) move
    the depth by up to 5 %, the peak value by 0.3 %."""
    mat = MATERIALS["elastic-perfectly plastic"]
    res = solve_load_path(mesh, mat, LOAD, [1.0], options=SolverOptions(dirichlet=DIRICHLET), disc=disc)
    u = res.state.u_mm
    vm = von_mises_MPa(disc.strain(u) @ mat.elastic_matrix())
    x = disc.qp_coordinates()
    r, z = np.hypot(x[0], x[1]) / A_MM, -x[2] / A_MM
    sel = (r < 0.3) & (z > 0.2) & (z < 0.8)
    coef = np.linalg.lstsq(np.column_stack([z[sel] ** k for k in range(4)] + [r[sel] ** 2]), vm[sel], rcond=None)[0]
    zz = np.linspace(0.2, 0.8, 6001)
    depth = float(zz[np.argmax(sum(coef[k] * zz ** k for k in range(4)))])
    near_axis = r < 0.15
    return {"first_yield_over_Y": res.first_yield_p0_MPa / Y_MPA, "depth_over_a": depth,
            "compliance_mm_per_MPa": res.history[-1].u_centre_mm,
            "axis_depth": z[near_axis].tolist(), "axis_vm_per_p0": vm[near_axis].tolist()}


def load_path(disc, mesh, material: J2Material, levels_y, unload_y, step_y: float, c_el: float) -> list[dict]:
    """Load through ``levels_y`` x Y (steps <= step_y x Y), record the centre displacement, its inelastic part
    u_pl = u - c_el p0 and the plastic zone at each level; unload to zero from ``unload_y`` (residual dent)."""
    opts = SolverOptions(dirichlet=DIRICHLET, max_increment_MPa=step_y * Y_MPA)
    rows, state, branch = [], None, None
    for f in levels_y:
        p0 = f * Y_MPA
        t0 = time.perf_counter()
        res = solve_load_path(mesh, material, LOAD, [p0], options=opts, disc=disc, initial_state=state,
                              branch_points=branch)
        state, branch = res.state, res.branch_points
        u = res.history[-1].u_centre_mm
        zone_thr = plastic_zone(disc, state, ZONE_THRESHOLD)
        row = {"p0_over_Y": f, "u_mm": u, "u_pl_mm": u - c_el * p0, "newton": sum(i.newton_iters for i in res.history),
               **plastic_zone(disc, state), "z_top_thr": zone_thr["z_top"], "z_bottom_thr": zone_thr["z_bottom"]}
        if any(abs(f - g) < 1e-9 for g in unload_y):
            un = solve_load_path(mesh, material, LOAD, [0.0], options=opts, disc=disc, initial_state=state)
            row["dent_mm"] = un.history[-1].u_centre_mm
        row["time_s"] = time.perf_counter() - t0
        rows.append(row)
    return rows


def top_reaches(rows: list[dict], depth: float) -> float:
    """p0 / Y at which the top of the plastic zone rises to ``depth`` (x a), linear between the recorded levels
    (NaN when it is not crossed)."""
    p = [r["p0_over_Y"] for r in rows if np.isfinite(r["z_top"])]
    z = [r["z_top"] for r in rows if np.isfinite(r["z_top"])]
    for (p1, z1), (p2, z2) in zip(zip(p, z), zip(p[1:], z[1:])):
        if z1 > depth >= z2:
            return float(p1 + (p2 - p1) * (z1 - depth) / (z1 - z2))
    return float("nan")


def _pct(a: float, b: float) -> float:
    return (a / b - 1.0) * 100.0


def _grid_label(g: dict) -> str:
    return f"L = {g['period_a']:g} a, dx = a/{round(1 / g['dx_a'])}, Lz = {g['depth_a']:g} a"


def tamaas_reference(quick: bool) -> dict:
    """Solve the same load path with Tamaas (``benchmarks/tamaas_reference.py``) for the materials it can model
    (EPP, isotropic hardening) on the grids of ``TAMAAS_GRIDS``. Returns {"available": False, "reason": ...} when
    Tamaas cannot be imported; a run that raises is recorded with its error instead of stopping the benchmark."""
    from benchmarks import tamaas_reference as tr

    version = tr.tamaas_version()
    if version is None:
        return {"available": False, "reason": "the Python package `tamaas` is not importable here "
                "(it is in the `bench` extra: `pip install -e '.[bench]'`)"}
    grids = TAMAAS_GRIDS["quick" if quick else "full"]
    levels = TAMAAS_LEVELS if quick else TAMAAS_LEVELS + (3.4,)
    runs = {}
    for name, hard in TAMAAS_HARDENING.items():
        for i, g in enumerate(grids):
            st = tr.TamaasSettings(**g, hardening_MPa=hard, levels_Y=levels, unload_Y=levels, step_Y=STEP_Y,
                                   threshold=ZONE_THRESHOLD)
            try:
                runs[(name, i)] = tr.solve(st)
            except Exception as exc:  # reported in the table, the FEM part still stands
                runs[(name, i)] = {"error": f"{type(exc).__name__}: {exc}"}
    return {"available": True, "version": version, "grids": grids, "runs": runs, "citation": tr.CITATION}


#: Tamaas grids (lengths / a): the first is the reference of the tables, the others give its grid difference
TAMAAS_GRIDS = {"quick": [{"period_a": 8.0, "dx_a": 1 / 8, "depth_a": 2.0}],
                "full": [{"period_a": 8.0, "dx_a": 1 / 16, "depth_a": 2.5},
                         {"period_a": 8.0, "dx_a": 1 / 8, "depth_a": 2.5},
                         {"period_a": 16.0, "dx_a": 1 / 8, "depth_a": 2.5}]}
#: compared quantities: key -> (label, FEM key, FEM scale to the Tamaas unit, format)
COMPARE = {"u_pl_um": ("inelastic centre displacement under load u_pl [µm]", "u_pl_mm", 1000.0, "{:.3f}"),
           "dent_um": ("residual dent after unloading [µm]", "dent_mm", 1000.0, "{:.3f}"),
           "z_top": ("plastic zone top z / a (eps_p > 0)", "z_top", 1.0, "{:.3f}"),
           "z_bottom": ("plastic zone bottom z / a (eps_p > 0)", "z_bottom", 1.0, "{:.3f}"),
           "z_top_thr": (f"plastic zone top z / a (eps_p > {ZONE_THRESHOLD:g})", "z_top_thr", 1.0, "{:.3f}"),
           "z_bottom_thr": (f"plastic zone bottom z / a (eps_p > {ZONE_THRESHOLD:g})", "z_bottom_thr", 1.0,
                            "{:.3f}")}


def _tamaas_row(tam: dict, name: str, grid: int, f: float) -> dict | None:
    run = tam.get("runs", {}).get((name, grid)) if tam.get("available") else None
    if not run or "error" in run:
        return None
    return next((r for r in run["levels"] if abs(r["p0_over_Y"] - f) < 1e-9), None)


def _plot(cases: dict, elastic: dict, hs, ref_fy: float, ref_depth: float, tam: dict,
          out: pathlib.Path) -> pathlib.Path:
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.6))
    zeta = np.linspace(1e-4, 3.0, 400)
    nu = 0.3
    s_r = -(1 + nu) * (1 - zeta * np.arctan(1 / zeta)) + 0.5 / (1 + zeta ** 2)
    s_z = -1 / (1 + zeta ** 2)
    ax[0].plot(np.abs(s_z - s_r), zeta, "k-", label="Johnson (1985) eq. 3.45, r = 0")
    for h, mk in zip(hs[-2:], ("o", "s")):
        e = elastic[h]
        ax[0].plot(e["axis_vm_per_p0"], e["axis_depth"], mk, ms=3, alpha=0.6, label=f"FEM h = {h} mm, r < 0.15 a")
    ax[0].axhline(ref_depth, color="grey", lw=0.8, ls="--")
    ax[0].invert_yaxis()
    ax[0].set_xlabel("von Mises / p0 [-]")
    ax[0].set_ylabel("depth z / a [-]")
    ax[0].set_title(f"elastic: first yield p0 = {ref_fy:.3f} Y at z = {ref_depth:.3f} a")
    ax[0].legend(fontsize=8)
    colours = dict(zip(MATERIALS, ("C0", "C3", "C2", "C1")))
    for (name, h), rows in cases.items():
        if h not in hs[-2:]:
            continue
        ls = "-" if h == hs[-1] else ":"
        p = [r["p0_over_Y"] for r in rows]
        lab = f"{SHORT[name]}, h = {h}"
        ax[1].plot(p, [r["z_top"] for r in rows], ls, color=colours[name], marker="v", ms=4, label=lab + ": top")
        ax[1].plot(p, [r["z_bottom"] for r in rows], ls, color=colours[name], marker="^", ms=4, label=lab + ": bottom")
        scale = MATERIALS[name].E_MPa / (Y_MPA * A_MM)
        ax[2].plot(p, [r["u_pl_mm"] * scale for r in rows], ls, color=colours[name], marker="o", ms=4,
                   label=lab + ": u_pl loaded")
        pd = [(r["p0_over_Y"], r["dent_mm"] * scale) for r in rows if "dent_mm" in r]
        ax[2].plot(*zip(*pd), "x", color=colours[name], ms=8, mew=2 if h == hs[-1] else 1, label=lab + ": dent")
    for name in TAMAAS_HARDENING:
        trows = [r for f in (*TAMAAS_LEVELS, 3.4) if (r := _tamaas_row(tam, name, 0, f)) is not None]
        if not trows:
            continue
        p = [r["p0_over_Y"] for r in trows]
        ax[1].plot(p, [r["z_top"] for r in trows], "D", mfc="none", color=colours[name], ms=8,
                   label=f"Tamaas {SHORT[name]}: top, bottom")
        ax[1].plot(p, [r["z_bottom"] for r in trows], "D", mfc="none", color=colours[name], ms=8)
        scale = MATERIALS[name].E_MPa / (Y_MPA * A_MM * 1000.0)
        ax[2].plot(p, [r["dent_um"] * scale for r in trows], "D", mfc="none", color=colours[name], ms=9,
                   label=f"Tamaas {SHORT[name]}: dent")
    ax[1].axvline(ref_fy, color="k", lw=0.8, ls="--")
    ax[1].axhline(ref_depth, color="grey", lw=0.8, ls="--")
    deepest = max((r["z_bottom"] for rows in cases.values() for r in rows if np.isfinite(r["z_bottom"])), default=1.0)
    ax[1].set_ylim(deepest + 1.0, -0.05)  # room below the data for the legend
    ax[1].set_xlabel("p0 / Y [-]")
    ax[1].set_ylabel("plastic zone depth / a [-]")
    ax[1].set_title("plastic zone: top and bottom (dashed: first yield)")
    ax[1].legend(fontsize=6, ncol=2, loc="lower left")
    ax[2].set_xlabel("p0 / Y [-]")
    ax[2].set_ylabel("centre displacement x E / (Y a) [-]")
    ax[2].set_title("inelastic centre displacement and residual dent")
    ax[2].legend(fontsize=6)
    for a in ax:
        a.grid(alpha=0.3)
    fig.tight_layout()
    path = out / "fem_validation.png"
    save_figure(fig, path)
    return path


def run(mode: str, out: pathlib.Path) -> dict:
    """Benchmark entry point (``python -m benchmarks --only fem_validation``). One BLAS/MKL thread, as in the
    calibration's workers (docs/calibration.md: more threads than free cores cost 2.5x on this machine)."""
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1):
        return _run(mode, out)


def _tamaas_markdown(tam: dict, cases: dict, hs, ref_fy: float, ref_depth: float) -> list[str]:
    """The Tamaas section of the report: verification of the reference and the comparison table."""
    if not tam.get("available"):
        return ["", f"**Independent reference (Tamaas): not run** — {tam.get('reason', 'unknown reason')}."]
    hc, hf = hs[-2:]
    grids = tam["grids"]
    md = ["", f"**Independent reference: Tamaas {tam['version']}** ({tam['citation']}); the same prescribed "
          "pressure, load steps and unloadings, solved by `benchmarks/tamaas_reference.py` on a periodic "
          "half-space (period L, plastic layer 0 <= z <= Lz, grid spacing dx in x, y and z). Grids: "
          + "; ".join(f"[{i}] {_grid_label(g)}" for i, g in enumerate(grids))
          + ". Dent and u_pl are u_z(centre) - u_z(cell corner) (Tamaas) and against the clamped far faces (FEM).",
          "", "Verification of the reference (elastic field of the grid, Tamaas' operators; onset on the load path):",
          "", "| grid | first yield p0/Y (grid max) | vs Johnson 1.6128 | depth z/a (axis parabola) | "
          "max axis |vm - Johnson| / p0 | last elastic / first plastic step p0/Y | time s |", "|---|---|---|---|---|---|---|"]
    for i, g in enumerate(grids):
        run = tam["runs"].get(("elastic-perfectly plastic", i), {})
        if "error" in run:
            md.append(f"| [{i}] | failed: {run['error']} | | | | | |")
            continue
        e = run["elastic"]
        onset = run["onset_Y"] or ("—", "—")
        md.append(f"| [{i}] | {e['first_yield_over_Y']:.4f} | {_pct(e['first_yield_over_Y'], ref_fy):+.2f} % | "
                  f"{e['depth_over_a']:.3f} | {e['axis_vm_max_dev_per_p0']:.4f} | {onset[0]:g} / {onset[1]:g} | "
                  f"{run['time_s']:.0f} |")
    for (name, i), run in tam["runs"].items():
        if run.get("stopped"):
            md.append(f"\nTamaas {SHORT[name]}, grid [{i}]: {run['stopped']}.")
    md += ["", f"Comparison (FEM: h = {hf} mm; deviation of the dent: FEM / Tamaas [0] - 1; of the plastic-zone "
           f"depths: FEM - Tamaas [0] in units of a, resolution Tamaas dz = {grids[0]['dx_a']:g} a (grid layers), "
           f"FEM about 0.1-0.2 h (quadrature points); FEM mesh diff. = (h = {hc}) / (h = {hf}) - 1 or the "
           "difference; Tamaas grid diff. = grid [k] against grid [0], same form). Tamaas models isotropic "
           "hardening only; the calibration's mixed law (H_iso = H_kin = 10 GPa) is compared through its "
           "proportional-loading equivalent, isotropic hardening with 20 GPa (next table).", "",
           "| material | p0/Y | quantity | Tamaas [0] | FEM | deviation | FEM mesh diff. |"
           + "".join(f" Tamaas [{k}] diff. |" for k in range(1, len(grids))),
           "|---|---|---|---|---|---|---|" + "---|" * (len(grids) - 1)]
    upl_dent = []
    for name in TAMAAS_HARDENING:
        fem_f = {r["p0_over_Y"]: r for r in cases[(name, hf)]}
        fem_c = {r["p0_over_Y"]: r for r in cases[(name, hc)]}
        for f in (*TAMAAS_LEVELS, 3.4):
            t0 = _tamaas_row(tam, name, 0, f)
            if t0 is None or f not in fem_f:
                continue
            if "dent_um" in t0 and "dent_mm" in fem_f[f]:
                upl_dent += [abs(t0["u_pl_um"] / t0["dent_um"] - 1), abs(fem_f[f]["u_pl_mm"] / fem_f[f]["dent_mm"] - 1)]
            for key in ("dent_um", "z_top", "z_bottom"):
                label, fkey, scale, fmt = COMPARE[key]
                tv, fv = t0.get(key), fem_f[f].get(fkey)
                if tv is None or fv is None:
                    continue
                fv *= scale
                fcv = fem_c[f][fkey] * scale
                relative = key == "dent_um"

                def diff(x: float, ref: float) -> str:
                    return f"{_pct(x, ref):+.1f} %" if relative else f"{x - ref:+.3f} a"

                cells = [SHORT[name], f"{f:g}", label, fmt.format(tv), fmt.format(fv), diff(fv, tv), diff(fcv, fv)]
                for k in range(1, len(grids)):
                    tk = _tamaas_row(tam, name, k, f)
                    cells.append("—" if tk is None else diff(tk[key], tv))
                md.append("| " + " | ".join(cells) + " |")
    if upl_dent:
        rev = max((r.get("unload_reverse_yield", 0.0) for run in tam["runs"].values() if "levels" in run
                   for r in run["levels"]), default=float("nan"))
        md += ["", f"Unloading: the loaded inelastic displacement u_pl and the dent differ by at most "
               f"{max(upl_dent) * 100:.2f} % in both models; largest growth of the Tamaas cumulated plastic strain "
               f"during an unloading: {rev:.1e}. The zone extents with the threshold eps_p > {ZONE_THRESHOLD:g} "
               "instead of > 0 are in the JSON data."]
    return md


def _equivalent_markdown(tam: dict, cases: dict, h: float) -> list[str]:
    """The mixed law against its proportional-loading equivalent: the path effect measured on the FEM (same mesh
    ``h``) and the FEM mixed law against Tamaas' equivalent."""
    md = []
    for name, equal in TAMAAS_EQUIVALENT.items():
        mixed = {r["p0_over_Y"]: r for r in cases[(name, h)]}
        iso = {r["p0_over_Y"]: r for r in cases[(equal, h)]}
        md += ["", f"**{SHORT[name]} ({name}) through its monotonic equivalent {SHORT[equal]} ({equal})**, "
               f"FEM h = {h} mm. Path effect = FEM {SHORT[name]} / FEM {SHORT[equal]} - 1 (same mesh, same load "
               "path): how far the Hertz loading is from proportional at the yielding points. Against Tamaas = "
               f"FEM {SHORT[name]} / Tamaas {SHORT[equal]} [0] - 1.", "",
               "| p0/Y | u_pl µm (mixed) | path effect on u_pl | dent µm (mixed) | path effect on the dent | "
               "Tamaas dent µm | mixed against Tamaas |", "|---|---|---|---|---|---|---|"]
        for f in sorted(mixed):
            m, i = mixed[f], iso[f]
            dent = "dent_mm" in m
            t0 = _tamaas_row(tam, equal, 0, f)
            tam_dent = t0.get("dent_um") if t0 else None
            md.append(f"| {f:g} | {m['u_pl_mm'] * 1000:.3f} | {_pct(m['u_pl_mm'], i['u_pl_mm']):+.2f} % | "
                      + (f"{m['dent_mm'] * 1000:.3f} | {_pct(m['dent_mm'], i['dent_mm']):+.2f} % | " if dent
                         else "| | ")
                      + (f"{tam_dent:.3f} | {_pct(m['dent_mm'] * 1000, tam_dent):+.1f} % |"
                         if dent and tam_dent is not None else "— | — |"))
    return md


def _run(mode: str, out: pathlib.Path) -> dict:
    out = pathlib.Path(out)
    quick = mode == "quick"
    # quick: the two coarser meshes (under a minute on 2 busy cores); full: the numbers of the docs and a step check
    hs = (0.35, 0.25) if quick else (0.25, 0.18, 0.13)
    step_y = STEP_Y
    levels = LEVELS_Y if quick else LEVELS_Y + (3.2, 3.4)
    unload = UNLOAD_Y if quick else UNLOAD_Y + (3.4,)
    ref_fy, ref_depth = hertz_axis_first_yield(0.3)
    elastic, cases, meshes = {}, {}, {}
    for h in hs:
        t0 = time.perf_counter()
        mesh = hertz_block_gmsh(h, FINE_MM, BLOCK_MM, order=2, dim=3)
        disc = discretise(mesh)
        elastic[h] = elastic_reference(disc, mesh)
        meshes[h] = {"n_dofs": int(disc.n_dofs), "n_elements": int(mesh.t.shape[1]),
                     "setup_s": time.perf_counter() - t0}
        for name, mat in MATERIALS.items():
            t1 = time.perf_counter()
            cases[(name, h)] = load_path(disc, mesh, mat, levels, unload, step_y,
                                         elastic[h]["compliance_mm_per_MPa"])
            meshes[h][f"{name} s"] = time.perf_counter() - t1
    # load-step check (full mode): the coarser mesh with half the step
    step_check = {}
    if not quick:
        mesh = hertz_block_gmsh(hs[-2], FINE_MM, BLOCK_MM, order=2, dim=3)
        disc = discretise(mesh)
        for name, mat in MATERIALS.items():
            step_check[name] = load_path(disc, mesh, mat, levels, unload, step_y / 2,
                                         elastic[hs[-2]]["compliance_mm_per_MPa"])
    t_tam = time.perf_counter()
    tam = tamaas_reference(quick)
    t_tam = time.perf_counter() - t_tam
    fig = _plot(cases, elastic, hs, ref_fy, ref_depth, tam, out)

    hc, hf = hs[-2:]
    md = [__doc__.split("\n\n", 1)[1].strip(), "",
          "Meshes: " + ", ".join(f"h = {h} mm ({meshes[h]['n_dofs']} dofs)" for h in hs)
          + f"; 'mesh diff.' is (h = {hc}) / (h = {hf}) - 1. Wall times: "
          + "; ".join(f"h = {h}: " + ", ".join(f"{k} {v:.0f}" for k, v in meshes[h].items() if k.endswith(" s")
                                              or k == "setup_s") for h in hs) + f" s; Tamaas {t_tam:.0f} s.", "",
          "| quantity | published / reference | ours (finest mesh) | deviation | mesh diff. | source |",
          "|---|---|---|---|---|---|"]
    e_c, e_f = elastic[hc], elastic[hf]
    src = "Johnson (1985) eq. 3.45 (axis stresses), p. 62; evaluated here"
    md.append(f"| first yield p0 / Y (elastic solve) | {ref_fy:.4f} | {e_f['first_yield_over_Y']:.4f} | "
              f"{_pct(e_f['first_yield_over_Y'], ref_fy):+.2f} % | "
              f"{_pct(e_c['first_yield_over_Y'], e_f['first_yield_over_Y']):+.2f} % | {src} |")
    md.append(f"| depth of first yield z / a | {ref_depth:.3f} | {e_f['depth_over_a']:.3f} "
              f"(fit to the points near the axis) | {_pct(e_f['depth_over_a'], ref_depth):+.1f} % | "
              f"{_pct(e_c['depth_over_a'], e_f['depth_over_a']):+.1f} % | {src} |")
    tam_src = (f"Tamaas {tam['version']} (Frérot et al. 2019), grid [0] {_grid_label(tam['grids'][0])}; run here"
               if tam.get("available") else "")
    for name in MATERIALS:
        rc, rf = cases[(name, hc)], cases[(name, hf)]
        short = SHORT[name]
        tc, tf = top_reaches(rc, TOP_DEPTH), top_reaches(rf, TOP_DEPTH)
        md.append(f"| {short}: p0 / Y at which the plastic zone's top rises to z = {TOP_DEPTH:g} a | not found | "
                  f"{tf:.3f} | — | {_pct(tc, tf):+.1f} % | — |")
        for f, keys in ((2.0, ("z_top", "z_bottom", "volume", "dent_mm")), (2.4, ("z_top",)),
                        (2.6, ("dent_mm",)), (3.0, ("z_bottom", "volume", "dent_mm"))):
            r_c = next(r for r in rc if abs(r["p0_over_Y"] - f) < 1e-9)
            r_f = next(r for r in rf if abs(r["p0_over_Y"] - f) < 1e-9)
            t_name = TAMAAS_EQUIVALENT.get(name, name)
            t_row = _tamaas_row(tam, t_name, 0, f) if t_name in TAMAAS_HARDENING else None
            for key in keys:
                label, scale, fmt = ROW_KEYS[key]
                vf, vc = r_f[key], r_c[key]
                tkey = {"dent_mm": "dent_um"}.get(key, key)
                if t_row is not None and tkey in t_row:
                    tv = t_row[tkey] / (1000.0 if key == "dent_mm" else 1.0)
                    pub, dev, s_ = fmt.format(tv * scale), f"{_pct(vf, tv):+.1f} %", tam_src
                    if t_name != name:
                        s_ += f" ({SHORT[t_name]}: the monotonic equivalent, see below)"
                elif t_name not in TAMAAS_HARDENING and tam.get("available"):
                    pub, dev, s_ = "— (Tamaas: isotropic hardening only)", "—", "—"
                elif tam.get("available"):
                    pub, dev, s_ = "— (not computed with Tamaas)", "—", "—"
                else:
                    pub, dev, s_ = "not found", "—", "—"
                md.append(f"| {short}, p0 = {f:g} Y: {label} | {pub} | {fmt.format(vf * scale)} | {dev} | "
                          f"{_pct(vc, vf):+.1f} % | {s_} |")
    md += _tamaas_markdown(tam, cases, hs, ref_fy, ref_depth)
    md += _equivalent_markdown(tam, cases, hf)
    md += ["", "Mesh sequence (h in mm; the quantities of the table above):", "",
           "| h | dofs | first yield p0/Y | " + " | ".join(f"{SHORT[n]} dent 2 Y µm | {SHORT[n]} dent 3 Y µm | "
                                                        f"{SHORT[n]} bottom 3 Y z/a" for n in MATERIALS) + " |",
           "|---|---|---|" + "---|---|---|" * len(MATERIALS)]
    for h in hs:
        cells = [f"{h:g}", str(meshes[h]["n_dofs"]), f"{elastic[h]['first_yield_over_Y']:.4f}"]
        for name in MATERIALS:
            rows = {r["p0_over_Y"]: r for r in cases[(name, h)]}
            cells += [f"{rows[2.0]['dent_mm'] * 1000:.3f}", f"{rows[3.0]['dent_mm'] * 1000:.3f}",
                      f"{rows[3.0]['z_bottom']:.3f}"]
        md.append("| " + " | ".join(cells) + " |")
    md += ["", "All levels (finest mesh; u_pl = u - c_el p0 is the inelastic centre displacement, c_el the "
           "mesh's elastic compliance; dent after unloading to zero; plastic zone = quadrature points with "
           "equivalent plastic strain > 0):", "",
           "| material | p0/Y | u µm | u_pl µm | dent µm | zone top z/a | bottom z/a | r_max/a | volume/a³ |",
           "|---|---|---|---|---|---|---|---|---|"]
    for name in MATERIALS:
        for r in cases[(name, hf)]:
            dent = f"{r['dent_mm'] * 1000:.3f}" if "dent_mm" in r else ""
            md.append(f"| {SHORT[name]} | {r['p0_over_Y']:g} | "
                      f"{r['u_mm'] * 1000:.3f} | {r['u_pl_mm'] * 1000:.3f} | {dent} | {r['z_top']:.3f} | "
                      f"{r['z_bottom']:.3f} | {r['r_max']:.3f} | {r['volume']:.4f} |")
    if step_check:
        md += ["", f"Load-step check (h = {hc} mm): (steps of {step_y:g} Y) / (steps of {step_y / 2:g} Y) - 1 for the "
               "residual dent and u_pl at the unloading levels:", "",
               "| material | p0/Y | dent | u_pl |", "|---|---|---|---|"]
        for name, rows in step_check.items():
            for r, r0 in zip(rows, cases[(name, hc)]):
                if "dent_mm" in r:
                    md.append(f"| {SHORT[name]} | {r['p0_over_Y']:g} | "
                              f"{_pct(r0['dent_mm'], r['dent_mm']):+.2f} % | {_pct(r0['u_pl_mm'], r['u_pl_mm']):+.2f} % |")
    tam_data = {k: v for k, v in tam.items() if k != "runs"}
    tam_data["runs"] = {f"{name} | grid {i}": v for (name, i), v in tam.get("runs", {}).items()}
    tam_data["time_s"] = t_tam
    data = {"reference": {"first_yield_over_Y": ref_fy, "depth_over_a": ref_depth,
                          "source": "Johnson 1985 eq. 3.45 (axis stresses), evaluated numerically"},
            "meshes": {str(h): meshes[h] for h in hs}, "step_Y": step_y,
            "elastic": {str(h): {k: v for k, v in elastic[h].items() if not k.startswith("axis_")} for h in hs},
            "cases": {f"{name} | h={h}": rows for (name, h), rows in cases.items()},
            "step_check": step_check, "tamaas": tam_data, "machine": machine_info()}
    json.dumps(data)  # must be serialisable
    return {"title": "FEM validation: elastic-plastic half-space under a Hertz pressure", "markdown": "\n".join(md),
            "figures": [fig], "data": data}
