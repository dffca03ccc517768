"""FEM validation: 3D elastic-plastic half-space under a prescribed circular Hertz pressure (issue 12, item 6).

Problem (units mm, N, MPa): quarter block 20 mm (unstructured gmsh P2 tetrahedra, element size h within 1.5 mm of
the load centre), circular Hertz pressure p0 sqrt(1 - (r/a)^2) with a = 1 mm, far faces clamped, symmetry planes
x = 0 and y = 0; steel E = 210 GPa, nu = 0.3, Y = 500 MPa, either elastic-perfectly plastic or with the
calibration's linear hardening (H_iso = H_kin = 10 GPa, `calibration/configs/default.toml`). The pressure is
prescribed (no indenter): p0 rises to the levels below in steps of at most 0.1 Y, and the body is
unloaded to zero from some of them (one step, restarted from the loaded state).

Independent reference: the closed-form Hertz stresses on the load axis (K. L. Johnson, Contact Mechanics,
Cambridge University Press 1985, eq. 3.45, p. 62; evaluated by
`calibration.fem.verification_meshes.hertz_axis_first_yield`) give the pressure and depth of first yield. A
published table or figure of the ELASTIC-PLASTIC response under a prescribed Hertz pressure (residual dent,
plastic-zone depth, load at which the plastic zone reaches the surface, against p0/Y) was searched for and not
found in a form that could be read (see docs/calibration.md, "Validation against an independent reference");
those rows give our converged values and say "not found" in the published column.
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
}
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
#: report rows: key -> (label, scale, format)
ROW_KEYS = {"z_top": ("plastic zone top z / a", 1.0, "{:.3f}"),
            "z_bottom": ("plastic zone bottom z / a", 1.0, "{:.3f}"),
            "volume": ("plastic zone volume / a³", 1.0, "{:.3f}"),
            "dent_mm": ("residual dent [µm]", 1000.0, "{:.3f}")}


def plastic_zone(disc, state) -> dict:
    """Extent of the yielded region (quadrature points with equivalent plastic strain > 0), lengths / a.

    z_top / z_bottom: smallest / largest depth of a yielded point; r_max: largest distance from the load axis;
    volume: yielded volume of the whole (4 x quarter) model / a^3. Resolution: the quadrature points, i.e. a
    fraction of the element size h (no point lies on the surface: the top cannot be closer than about 0.1 h).
    """
    x = disc.qp_coordinates()
    yielded = state.eq_plastic_strain > 0
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
    rows, state = [], None
    for f in levels_y:
        p0 = f * Y_MPA
        t0 = time.perf_counter()
        res = solve_load_path(mesh, material, LOAD, [p0], options=opts, disc=disc, initial_state=state)
        state = res.state
        u = res.history[-1].u_centre_mm
        row = {"p0_over_Y": f, "u_mm": u, "u_pl_mm": u - c_el * p0, "newton": sum(i.newton_iters for i in res.history),
               **plastic_zone(disc, state)}
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


def _plot(cases: dict, elastic: dict, hs, ref_fy: float, ref_depth: float, out: pathlib.Path) -> pathlib.Path:
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
    colours = {"elastic-perfectly plastic": "C0", "linear hardening (H_iso = H_kin = 10 GPa)": "C3"}
    for (name, h), rows in cases.items():
        if h not in hs[-2:]:
            continue
        ls = "-" if h == hs[-1] else ":"
        p = [r["p0_over_Y"] for r in rows]
        lab = f"{'EPP' if 'perfectly' in name else 'hardening'}, h = {h}"
        ax[1].plot(p, [r["z_top"] for r in rows], ls, color=colours[name], marker="v", ms=4, label=lab + ": top")
        ax[1].plot(p, [r["z_bottom"] for r in rows], ls, color=colours[name], marker="^", ms=4, label=lab + ": bottom")
        scale = MATERIALS[name].E_MPa / (Y_MPA * A_MM)
        ax[2].plot(p, [r["u_pl_mm"] * scale for r in rows], ls, color=colours[name], marker="o", ms=4,
                   label=lab + ": u_pl loaded")
        pd = [(r["p0_over_Y"], r["dent_mm"] * scale) for r in rows if "dent_mm" in r]
        ax[2].plot(*zip(*pd), "x", color=colours[name], ms=8, mew=2 if h == hs[-1] else 1, label=lab + ": dent")
    ax[1].axvline(ref_fy, color="k", lw=0.8, ls="--")
    ax[1].axhline(ref_depth, color="grey", lw=0.8, ls="--")
    ax[1].invert_yaxis()
    ax[1].set_xlabel("p0 / Y [-]")
    ax[1].set_ylabel("plastic zone depth / a [-]")
    ax[1].set_title("plastic zone: top and bottom (dashed: first yield)")
    ax[1].legend(fontsize=7, ncol=2, loc="center right")
    ax[2].set_xlabel("p0 / Y [-]")
    ax[2].set_ylabel("centre displacement x E / (Y a) [-]")
    ax[2].set_title("inelastic centre displacement and residual dent")
    ax[2].legend(fontsize=7)
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
    fig = _plot(cases, elastic, hs, ref_fy, ref_depth, out)

    hc, hf = hs[-2:]
    md = [__doc__.split("\n\n", 1)[1].strip(), "",
          "Meshes: " + ", ".join(f"h = {h} mm ({meshes[h]['n_dofs']} dofs)" for h in hs)
          + f"; 'mesh diff.' is (h = {hc}) / (h = {hf}) - 1. Wall times: "
          + "; ".join(f"h = {h}: " + ", ".join(f"{k} {v:.0f}" for k, v in meshes[h].items() if k.endswith(" s")
                                              or k == "setup_s") for h in hs) + " s.", "",
          "| quantity | published | ours (finest mesh) | deviation | mesh diff. | source |", "|---|---|---|---|---|---|"]
    e_c, e_f = elastic[hc], elastic[hf]
    src = "Johnson (1985) eq. 3.45 (axis stresses), p. 62; evaluated here"
    md.append(f"| first yield p0 / Y (elastic solve) | {ref_fy:.4f} | {e_f['first_yield_over_Y']:.4f} | "
              f"{_pct(e_f['first_yield_over_Y'], ref_fy):+.2f} % | "
              f"{_pct(e_c['first_yield_over_Y'], e_f['first_yield_over_Y']):+.2f} % | {src} |")
    md.append(f"| depth of first yield z / a | {ref_depth:.3f} | {e_f['depth_over_a']:.3f} "
              f"(fit to the points near the axis) | {_pct(e_f['depth_over_a'], ref_depth):+.1f} % | "
              f"{_pct(e_c['depth_over_a'], e_f['depth_over_a']):+.1f} % | {src} |")
    for name in MATERIALS:
        rc, rf = cases[(name, hc)], cases[(name, hf)]
        short = "EPP" if "perfectly" in name else "hardening"
        tc, tf = top_reaches(rc, TOP_DEPTH), top_reaches(rf, TOP_DEPTH)
        md.append(f"| {short}: p0 / Y at which the plastic zone's top rises to z = {TOP_DEPTH:g} a | not found | "
                  f"{tf:.3f} | — | {_pct(tc, tf):+.1f} % | — |")
        for f, keys in ((2.0, ("z_top", "z_bottom", "volume", "dent_mm")), (2.4, ("z_top",)),
                        (3.0, ("z_bottom", "volume", "dent_mm"))):
            r_c = next(r for r in rc if abs(r["p0_over_Y"] - f) < 1e-9)
            r_f = next(r for r in rf if abs(r["p0_over_Y"] - f) < 1e-9)
            for key in keys:
                label, scale, fmt = ROW_KEYS[key]
                vf, vc = r_f[key], r_c[key]
                md.append(f"| {short}, p0 = {f:g} Y: {label} | not found | {fmt.format(vf * scale)} | — | "
                          f"{_pct(vc, vf):+.1f} % | — |")
    md += ["", "Mesh sequence (h in mm; the quantities of the table above):", "",
           "| h | dofs | first yield p0/Y | EPP dent 2 Y µm | EPP dent 3 Y µm | EPP bottom 3 Y z/a | "
           "hardening dent 2 Y µm | hardening dent 3 Y µm | hardening bottom 3 Y z/a |", "|---|---|---|---|---|---|---|---|---|"]
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
            md.append(f"| {'EPP' if 'perfectly' in name else 'hardening'} | {r['p0_over_Y']:g} | "
                      f"{r['u_mm'] * 1000:.3f} | {r['u_pl_mm'] * 1000:.3f} | {dent} | {r['z_top']:.3f} | "
                      f"{r['z_bottom']:.3f} | {r['r_max']:.3f} | {r['volume']:.4f} |")
    if step_check:
        md += ["", f"Load-step check (h = {hc} mm): (steps of {step_y:g} Y) / (steps of {step_y / 2:g} Y) - 1 for the "
               "residual dent and u_pl at the unloading levels:", "",
               "| material | p0/Y | dent | u_pl |", "|---|---|---|---|"]
        for name, rows in step_check.items():
            for r, r0 in zip(rows, cases[(name, hc)]):
                if "dent_mm" in r:
                    md.append(f"| {'EPP' if 'perfectly' in name else 'hardening'} | {r['p0_over_Y']:g} | "
                              f"{_pct(r0['dent_mm'], r['dent_mm']):+.2f} % | {_pct(r0['u_pl_mm'], r['u_pl_mm']):+.2f} % |")
    data = {"reference": {"first_yield_over_Y": ref_fy, "depth_over_a": ref_depth,
                          "source": "Johnson 1985 eq. 3.45 (axis stresses), evaluated numerically"},
            "meshes": {str(h): meshes[h] for h in hs}, "step_Y": step_y,
            "elastic": {str(h): {k: v for k, v in elastic[h].items() if not k.startswith("axis_")} for h in hs},
            "cases": {f"{name} | h={h}": rows for (name, h), rows in cases.items()},
            "step_check": step_check, "machine": machine_info()}
    json.dumps(data)  # must be serialisable
    return {"title": "FEM validation: elastic-plastic half-space under a Hertz pressure", "markdown": "\n".join(md),
            "figures": [fig], "data": data}
