"""The report of ``bench_fem_validation``: the figure and the Markdown tables (units mm, MPa, µm; lengths / a).

Every function reads one :class:`~benchmarks.fem_validation_cases.ValidationRun`; the numbers and their
formatting are those of the benchmark's report.
"""

from __future__ import annotations

import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from benchmarks.fem_validation_cases import (A_MM, COMPARE, MATERIALS, ROW_KEYS, SHORT, TAMAAS_EQUIVALENT,
                                             TAMAAS_HARDENING, TAMAAS_LEVELS, TOP_DEPTH, Y_MPA, ZONE_THRESHOLD,
                                             ValidationRun, grid_label, pct, tamaas_row, top_reaches)
from wrlayer.plotting import save_figure


def plot(run: ValidationRun, out: pathlib.Path) -> pathlib.Path:
    """The figure: elastic axis stress against Johnson, plastic-zone extent and inelastic displacement / dent."""
    cases, elastic, hs, ref_fy, ref_depth, tam = run.cases, run.elastic, run.hs, run.ref_fy, run.ref_depth, run.tam
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
        trows = [r for f in (*TAMAAS_LEVELS, 3.4) if (r := tamaas_row(tam, name, 0, f)) is not None]
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


def reference_markdown(run: ValidationRun, intro: str) -> list[str]:
    """The introduction, the meshes and their wall times, and the table of the quantities against their published
    or independent reference (finest mesh)."""
    hs, meshes, elastic, tam, ref_fy, ref_depth = run.hs, run.meshes, run.elastic, run.tam, run.ref_fy, run.ref_depth
    t_tam = run.t_tam
    hc, hf = hs[-2:]
    md = [intro, "",
          "Meshes: " + ", ".join(f"h = {h} mm ({meshes[h]['n_dofs']} dofs)" for h in hs)
          + f"; 'mesh diff.' is (h = {hc}) / (h = {hf}) - 1. Wall times: "
          + "; ".join(f"h = {h}: " + ", ".join(f"{k} {v:.0f}" for k, v in meshes[h].items() if k.endswith(" s")
                                              or k == "setup_s") for h in hs) + f" s; Tamaas {t_tam:.0f} s.", "",
          "| quantity | published / reference | ours (finest mesh) | deviation | mesh diff. | source |",
          "|---|---|---|---|---|---|"]
    e_c, e_f = elastic[hc], elastic[hf]
    src = "Johnson (1985) eq. 3.45 (axis stresses), p. 62; evaluated here"
    md.append(f"| first yield p0 / Y (elastic solve) | {ref_fy:.4f} | {e_f['first_yield_over_Y']:.4f} | "
              f"{pct(e_f['first_yield_over_Y'], ref_fy):+.2f} % | "
              f"{pct(e_c['first_yield_over_Y'], e_f['first_yield_over_Y']):+.2f} % | {src} |")
    md.append(f"| depth of first yield z / a | {ref_depth:.3f} | {e_f['depth_over_a']:.3f} "
              f"(fit to the points near the axis) | {pct(e_f['depth_over_a'], ref_depth):+.1f} % | "
              f"{pct(e_c['depth_over_a'], e_f['depth_over_a']):+.1f} % | {src} |")
    tam_src = (f"Tamaas {tam['version']} (Frérot et al. 2019), grid [0] {grid_label(tam['grids'][0])}; run here"
               if tam.get("available") else "")
    for name in MATERIALS:
        md += _material_rows(run, name, tam_src)
    return md


def _material_rows(run: ValidationRun, name: str, tam_src: str) -> list[str]:
    """Rows of the reference table for one material: onset of the zone's rise and the values at 2.0-3.0 Y."""
    hc, hf = run.hs[-2:]
    tam = run.tam
    rc, rf = run.cases[(name, hc)], run.cases[(name, hf)]
    short = SHORT[name]
    tc, tf = top_reaches(rc, TOP_DEPTH), top_reaches(rf, TOP_DEPTH)
    md = [f"| {short}: p0 / Y at which the plastic zone's top rises to z = {TOP_DEPTH:g} a | not found | "
          f"{tf:.3f} | — | {pct(tc, tf):+.1f} % | — |"]
    for f, keys in ((2.0, ("z_top", "z_bottom", "volume", "dent_mm")), (2.4, ("z_top",)),
                    (2.6, ("dent_mm",)), (3.0, ("z_bottom", "volume", "dent_mm"))):
        r_c = next(r for r in rc if abs(r["p0_over_Y"] - f) < 1e-9)
        r_f = next(r for r in rf if abs(r["p0_over_Y"] - f) < 1e-9)
        t_name = TAMAAS_EQUIVALENT.get(name, name)
        t_row = tamaas_row(tam, t_name, 0, f) if t_name in TAMAAS_HARDENING else None
        for key in keys:
            label, scale, fmt = ROW_KEYS[key]
            vf, vc = r_f[key], r_c[key]
            tkey = {"dent_mm": "dent_um"}.get(key, key)
            if t_row is not None and tkey in t_row:
                tv = t_row[tkey] / (1000.0 if key == "dent_mm" else 1.0)
                pub, dev, s_ = fmt.format(tv * scale), f"{pct(vf, tv):+.1f} %", tam_src
                if t_name != name:
                    s_ += f" ({SHORT[t_name]}: the monotonic equivalent, see below)"
            elif t_name not in TAMAAS_HARDENING and tam.get("available"):
                pub, dev, s_ = "— (Tamaas: isotropic hardening only)", "—", "—"
            elif tam.get("available"):
                pub, dev, s_ = "— (not computed with Tamaas)", "—", "—"
            else:
                pub, dev, s_ = "not found", "—", "—"
            md.append(f"| {short}, p0 = {f:g} Y: {label} | {pub} | {fmt.format(vf * scale)} | {dev} | "
                      f"{pct(vc, vf):+.1f} % | {s_} |")
    return md


def tamaas_markdown(run: ValidationRun) -> list[str]:
    """The Tamaas section of the report: verification of the reference and the comparison table."""
    tam, cases, hs, ref_fy = run.tam, run.cases, run.hs, run.ref_fy
    if not tam.get("available"):
        return ["", f"**Independent reference (Tamaas): not run** — {tam.get('reason', 'unknown reason')}."]
    hc, hf = hs[-2:]
    grids = tam["grids"]
    md = ["", f"**Independent reference: Tamaas {tam['version']}** ({tam['citation']}); the same prescribed "
          "pressure, load steps and unloadings, solved by `benchmarks/tamaas_reference.py` on a periodic "
          "half-space (period L, plastic layer 0 <= z <= Lz, grid spacing dx in x, y and z). Grids: "
          + "; ".join(f"[{i}] {grid_label(g)}" for i, g in enumerate(grids))
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
        md.append(f"| [{i}] | {e['first_yield_over_Y']:.4f} | {pct(e['first_yield_over_Y'], ref_fy):+.2f} % | "
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
            t0 = tamaas_row(tam, name, 0, f)
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
                    return f"{pct(x, ref):+.1f} %" if relative else f"{x - ref:+.3f} a"

                cells = [SHORT[name], f"{f:g}", label, fmt.format(tv), fmt.format(fv), diff(fv, tv), diff(fcv, fv)]
                for k in range(1, len(grids)):
                    tk = tamaas_row(tam, name, k, f)
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


def equivalent_markdown(run: ValidationRun) -> list[str]:
    """The mixed law against its proportional-loading equivalent: the path effect measured on the FEM (same mesh
    ``h``, the finest) and the FEM mixed law against Tamaas' equivalent."""
    tam, cases, h = run.tam, run.cases, run.hs[-1]
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
            t0 = tamaas_row(tam, equal, 0, f)
            tam_dent = t0.get("dent_um") if t0 else None
            md.append(f"| {f:g} | {m['u_pl_mm'] * 1000:.3f} | {pct(m['u_pl_mm'], i['u_pl_mm']):+.2f} % | "
                      + (f"{m['dent_mm'] * 1000:.3f} | {pct(m['dent_mm'], i['dent_mm']):+.2f} % | " if dent
                         else "| | ")
                      + (f"{tam_dent:.3f} | {pct(m['dent_mm'] * 1000, tam_dent):+.1f} % |"
                         if dent and tam_dent is not None else "— | — |"))
    return md


def tables_markdown(run: ValidationRun) -> list[str]:
    """The mesh sequence, all levels of the finest mesh and (full mode) the load-step check."""
    hs, meshes, elastic, cases = run.hs, run.meshes, run.elastic, run.cases
    hc, hf = hs[-2:]
    md = ["", "Mesh sequence (h in mm; the quantities of the table above):", "",
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
    step_check, step_y = run.step_check, run.step_y
    if step_check:
        md += ["", f"Load-step check (h = {hc} mm): (steps of {step_y:g} Y) / (steps of {step_y / 2:g} Y) - 1 for the "
               "residual dent and u_pl at the unloading levels:", "",
               "| material | p0/Y | dent | u_pl |", "|---|---|---|---|"]
        for name, rows in step_check.items():
            for r, r0 in zip(rows, cases[(name, hc)]):
                if "dent_mm" in r:
                    md.append(f"| {SHORT[name]} | {r['p0_over_Y']:g} | "
                              f"{pct(r0['dent_mm'], r['dent_mm']):+.2f} % | {pct(r0['u_pl_mm'], r['u_pl_mm']):+.2f} % |")
    return md


def markdown(run: ValidationRun, intro: str) -> str:
    """The whole report section."""
    return "\n".join(reference_markdown(run, intro) + tamaas_markdown(run) + equivalent_markdown(run)
                     + tables_markdown(run))
