"""Calibration benchmark: fit error against the number of segments N (justifies the default N), 2D against 3D
indentation (run time and characteristic difference against the finest 3D model run), and the cold/warm
``make calibrate`` times (read from the last run's summary in out/calibration, or measured in "full" mode).

Errors are measured against: the FEM points of each calibrated position (fit error, in mm and relative to the
largest u), the FEM unloading runs (eq. 8 residual error), and the finest 3D run (2D/3D comparison).
"""

from __future__ import annotations

import dataclasses
import json
import time
from pathlib import Path

import numpy as np

from benchmarks.calibration_mesh_convergence import (convergence_every_position, every_position_markdown,
                                                      mesh_convergence, mesh_convergence_same_pressure)
from benchmarks.harness import machine_info

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_OUT = ROOT / "out" / "calibration"


def _fem_points(out: Path) -> list[dict]:
    """FEM points of every position of a finished run (from the layer tables)."""
    pts = []
    for body in ("rail", "wheel"):
        f = out / f"{body}_layer_table.json"
        if not f.is_file():
            continue
        data = json.loads(f.read_text())
        for pos in data["positions"]:
            pts.append({"body": body, "y_mm": pos["y_mm"], "p": np.asarray(pos["fem_points"]["p_MPa"]),
                        "u": np.asarray(pos["fem_points"]["u_mm"]), "s1": pos["slopes_N_per_mm3"][0],
                        "p2": pos["first_yield_fem_MPa"], "peaks": np.asarray(pos["residual_peaks_MPa"]),
                        "res": np.asarray(pos["residual_fem_mm"])})
    return pts


def _coarse_points(work: Path) -> list[dict]:
    from calibration.config import load_config
    from calibration.pipeline import run_calibration

    cfg = load_config(ROOT / "calibration" / "configs" / "test_coarse.toml")
    run_calibration(cfg, work, show_progress=False, log=lambda *a: None)
    return _fem_points(work)


def fit_error_vs_segments(points: list[dict], n_values=range(2, 9)) -> list[dict]:
    """Max/RMS fit error (relative to max u) and eq. (8) residual error per N over all positions."""
    from calibration.fit.characteristic_fit import fit_characteristic
    from wrlayer.errors import WrLayerError

    rows = []
    for n in n_values:
        rel_max, rel_rms, res_err, secs, fails = [], [], [], 0.0, 0
        for pt in points:
            t0 = time.perf_counter()
            try:
                fit = fit_characteristic(pt["p"], pt["u"], n, s1_N_per_mm3=pt["s1"], p2_MPa=pt["p2"],
                                         max_relative_error=10.0)
            except WrLayerError:
                fails += 1
                continue
            secs += time.perf_counter() - t0
            umax = float(pt["u"].max())
            rel_max.append(fit.max_error_mm / umax)
            rel_rms.append(fit.rms_error_mm / umax)
            if pt["peaks"].size:
                err = fit.characteristic.residual_displacement(pt["peaks"]) - pt["res"]
                res_err.append(float(np.max(np.abs(err) / np.maximum(pt["res"], 1e-12 * umax) * (pt["res"] > 0.02 * umax))))
        rows.append({"n_segments": n, "worst_max_rel": max(rel_max, default=np.nan),
                     "mean_rms_rel": float(np.mean(rel_rms)) if rel_rms else np.nan,
                     "worst_residual_rel": max(res_err, default=np.nan),
                     "fit_seconds_per_position": secs / max(1, len(points) - fails), "failures": fails})
    return rows


def model_comparison(quick: bool) -> list[dict]:
    """Rail y = 0: 2D and 3D indentations on several meshes; run time, first yield p_y and FEM residual dents
    after unloading from 1.5 and 2.5 p_y, against the finest 3D run (the last; quadratic tetrahedra)."""
    from calibration.hertz.geometry import local_geometry
    from calibration.indentation import IndentationJob, LoadSettings, MeshSettings, indent
    from calibration.fem.material import J2Material
    from meshes.profiles import get_profile

    rail, wheel = get_profile("60E1"), get_profile("S1002")
    geo = local_geometry(rail, 0.0, wheel, 100000.0, 210000.0, 0.3)
    mat = J2Material(210000.0, 0.3, 500.0, 10000.0, 10000.0)
    load = LoadSettings(max_factor=2.5, n_levels=6, unload_factors=(1.5, 2.5), max_increment_factor=0.25)
    runs = [("2d", MeshSettings(elements_per_semi_axis=6, order=2)),
            ("3d", MeshSettings(elements_per_semi_axis=2, order=1, h_max_mm=12.0)),
            ("3d", MeshSettings(elements_per_semi_axis=2, order=2, h_max_mm=10.0))]
    if not quick:
        runs[1:1] = [("2d", MeshSettings(elements_per_semi_axis=12, order=2))]
        runs += [("3d", MeshSettings(elements_per_semi_axis=3, order=1, h_max_mm=10.0)),
                 ("3d", MeshSettings(elements_per_semi_axis=3, order=2, h_max_mm=10.0)),
                 ("3d", MeshSettings(elements_per_semi_axis=4, order=2, h_max_mm=10.0))]
    out = []
    for model, mesh in runs:
        t0 = time.perf_counter()
        res = indent(IndentationJob(profile=rail, geometry=geo, material=mat, model=model, mesh=mesh, load=load,
                                    linear_solver="scipy"))
        out.append({"model": model, "mesh": dataclasses.asdict(mesh), "seconds": time.perf_counter() - t0,
                    "n_dofs": res.n_dofs, "first_yield_MPa": res.first_yield_MPa,
                    "peaks_MPa": res.unload_peaks_MPa, "residual_fem_mm": res.residual_fem_mm,
                    "p_factor": (np.asarray(res.unload_peaks_MPa) / res.first_yield_MPa).tolist()})
    ref = out[-1]
    for r in out:
        r["first_yield_diff_vs_ref"] = r["first_yield_MPa"] / ref["first_yield_MPa"] - 1.0
        r["residual_diff_vs_ref_mm"] = (np.asarray(r["residual_fem_mm"]) - np.asarray(ref["residual_fem_mm"])).tolist()
    return out


def make_times(full: bool) -> dict:
    """Cold and warm `make calibrate` times: measured in full mode (cold into a fresh folder), else read."""
    info = {}
    summary = DEFAULT_OUT / "summary.json"
    if full:
        import shutil

        from calibration.config import load_config
        from calibration.pipeline import calibrate

        cfg = load_config(ROOT / "calibration" / "configs" / "default.toml")
        shutil.rmtree(DEFAULT_OUT, ignore_errors=True)
        for key in ("cold_s", "warm_s"):  # the same run as `make calibrate`, without its start-up
            t0 = time.perf_counter()
            calibrate(cfg, DEFAULT_OUT, show_progress=False, log=lambda message: None)
            info[key] = time.perf_counter() - t0
            if key == "cold_s" and summary.is_file():  # per-position FEM time in the workers, apart from fields
                info["cold_fem_seconds"] = json.loads(summary.read_text()).get("fem_seconds")
    elif summary.is_file():
        s = json.loads(summary.read_text())
        info["last_run_s"] = s["seconds"]
        info["last_run_computed"] = s["positions_computed"]
        info["last_run_fem_seconds"] = s.get("fem_seconds")  # absent when nothing was computed
    return info


def run(mode: str, out: Path) -> dict:
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    quick = mode != "full"
    points = _fem_points(DEFAULT_OUT) if (DEFAULT_OUT / "rail_layer_table.json").is_file() else \
        _coarse_points(out / "calibration_coarse")
    source = "out/calibration (default run)" if (DEFAULT_OUT / "rail_layer_table.json").is_file() else \
        "the coarse test configuration"
    rows = fit_error_vs_segments(points, range(2, 9) if not quick else (2, 3, 4, 5, 6))
    md = [f"FEM points of {len(points)} position(s) from {source}.", "",
          "| N | worst max error / max u | mean RMS / max u | worst eq. (8) residual error (rel.) | fit s/position |",
          "|---|---|---|---|---|"]
    for r in rows:
        md.append(f"| {r['n_segments']} | {100 * r['worst_max_rel']:.2f} % | {100 * r['mean_rms_rel']:.3f} % | "
                  f"{100 * r['worst_residual_rel']:.1f} % | {r['fit_seconds_per_position']:.2f} |")
    figures = []
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(5, 3.2))
        ax.semilogy([r["n_segments"] for r in rows], [r["worst_max_rel"] for r in rows], "o-", label="worst max")
        ax.semilogy([r["n_segments"] for r in rows], [r["mean_rms_rel"] for r in rows], "s-", label="mean RMS")
        ax.set_xlabel("segments N")
        ax.set_ylabel("fit error / max u")
        ax.legend()
        fig.tight_layout()
        fig.savefig(out / "calibration_fit_error_vs_n.png", dpi=100)
        plt.close(fig)
        figures.append(out / "calibration_fit_error_vs_n.png")
    except Exception:  # pictures are optional in the report
        pass
    comp = model_comparison(quick)
    md += ["", "2D plane strain vs 3D local model, rail 60E1 y = 0 (reference: the finest 3D run listed last):", "",
           "| model | mesh (elements/semi-axis, order) | dofs | time [s] | p_y [MPa] | p_y vs ref | residual dents [mm] |",
           "|---|---|---|---|---|---|---|"]
    for c in comp:
        md.append(f"| {c['model']} | {c['mesh']['elements_per_semi_axis']:g}, {c['mesh']['order']} | {c['n_dofs']} | "
                  f"{c['seconds']:.1f} | {c['first_yield_MPa']:.0f} | {100 * c['first_yield_diff_vs_ref']:+.1f} % | "
                  f"{', '.join(f'{x:.4f}' for x in c['residual_fem_mm'])} |")
    conv = mesh_convergence() if not quick else []
    if conv:
        md += ["", "3D mesh convergence (default load path; reference: 6 elements per semi-axis; dents after "
               "unloading from 1.5 / 2.0 / 2.5 p_y; one BLAS thread):", "",
               "| position | elements/semi-axis | dofs | s | solves | first yield | peak u_pl | residual dents |",
               "|---|---|---|---|---|---|---|---|"]
        for c in conv:
            e = c["errors"]
            md.append(f"| {c['body']} y = {c['y_mm']:g} | {c['mesh']['elements_per_semi_axis']:g} | {c['n_dofs']} | "
                      f"{c['seconds']:.1f} | {c['linear_solves']} | {100 * e['first_yield']:+.2f} % | "
                      f"{100 * e['peak_u_pl']:+.2f} % | "
                      f"{' / '.join(f'{100 * x:+.2f}' for x in e['residual_levels'])} % |")
    same_p = mesh_convergence_same_pressure() if not quick else []
    if same_p:
        md += ["", "Default mesh against the finer references at the SAME ABSOLUTE pressures (the reference's load path "
               "scaled by p_y(default) / p_y(reference): same unloading peaks and peak pressure; u_pl at the default's "
               "levels above 1.2 p_y, reference interpolated log-log):", "",
               "| position | dofs (default / ref) | first yield | peak u_pl | max u_pl at the levels | residual dents at "
               "the same peaks |", "|---|---|---|---|---|---|"]
        for r in same_p:
            e = r["errors"]
            md.append(f"| {r['position']} | {r['case']['n_dofs']} / {r['ref']['n_dofs']} | {100 * e['first_yield']:+.2f} % "
                      f"| {100 * e['peak_u_pl']:+.2f} % | {100 * e['u_pl_levels_max']:.2f} % | "
                      f"{' / '.join(f'{100 * x:+.2f}' for x in e['residual_levels'])} % |")
    every = convergence_every_position() if not quick else []
    if every:
        md += ["", "Default mesh at every position of the default configuration against a finer mesh (isotropic 8 "
               "per semi-axis without the finer zone below a/b = 4, extruded 6 above; at multiples of each mesh's "
               "own p_y; one BLAS thread):", ""] + every_position_markdown(every)
    e2e = end_to_end(out / "end_to_end")
    md += ["", "End to end on the 60E1 (100 kN, rail layer of scenes/tables/rail_60E1_default.json): contact "
           "solver dent u_p(0) vs the FEM dent under the Hertz pressure of the solver's own patch and p_max:", "",
           "| position | characteristic | patch a x b [mm] | p_max [MPa] | contact u_p(0) [µm] | FEM dent [µm] | "
           "deviation |", "|---|---|---|---|---|---|---|"]
    for r in e2e:
        md.append(f"| {r['position']} | {r['case']} | {r['a_mm']:.2f} x {r['b_mm']:.2f} | {r['p_max_MPa']:.0f} | "
                  f"{1e3 * r['contact_up0_mm']:.2f} | {1e3 * r['fem_dent_mm']:.2f} | {100 * r['deviation']:+.1f} % |")
    times = make_times(not quick)
    md += ["", f"make calibrate: {json.dumps(times)}", "", f"machine: {json.dumps(machine_info())[:300]}"]
    return {"title": "Calibration: fit error vs N, 2D vs 3D, make calibrate times", "markdown": "\n".join(md),
            "figures": [str(f) for f in figures],
            "data": {"fit_vs_n": rows, "models": comp, "times": times, "convergence": conv,
                     "convergence_same_pressure": same_p, "convergence_every_position": every,
                     "end_to_end": e2e}}


END_TO_END_POSITIONS = (("crown y = 0", 0.0, 300.0, 460.0), ("y = -15 mm (R80)", -15.0, 230.8, 461.2))


def _contact_first_pass(table_path: Path, scale: bool, work: Path, tag: str, y_mm: float = 0.0,
                        lateral_radius_mm: float = 300.0, rolling_radius_mm: float = 460.0) -> dict:
    """A one-pass scene at 100 kN with the rail table's layer at ``y_mm`` as the only layer (``scale_to_patch`` =
    ``scale``) on the separation y^2 / (2 R_lateral) and the rolling radius given: the first pass's result (patch,
    p_max, u_p(0)). The defaults are the crown scene of scenes/calibrated_layers.toml."""
    toml = "\n".join([
        f'title = "end to end {tag}"', "[load]", "normal_force_N = 100000.0", f"rolling_radius_mm = {rolling_radius_mm}",
        "[material]", "E_MPa = 210000.0", "poisson = 0.3", "[separation]", f"lateral_radius_mm = {lateral_radius_mm}",
        "half_width_mm = 25.0", "[layers]", f'rail = "{table_path}"', f"position_mm = {{rail = {y_mm}}}",
        f"scale_to_patch = {'true' if scale else 'false'}", "[passes]", "max = 1", "[method]", "alpha = 0.55",
        "grid_mm = 0.1", ""])
    from contact import run_scene_file

    work.mkdir(parents=True, exist_ok=True)
    (work / f"{tag}.toml").write_text(toml)
    return run_scene_file(work / f"{tag}.toml", work / tag)["passes"][0]


def _fem_dent_mm(a_mm: float, b_mm: float, p0_MPa: float, y_mm: float = 0.0) -> float:
    """FEM residual dent (mm) of the 60E1 at ``y_mm`` after the Hertz pressure p0 on the a x b patch (default 3D
    mesh and material, support 35 mm below)."""
    from calibration.config import load_config, material_of
    from calibration.fem.assembly import discretise
    from calibration.fem.elastoplastic_solver import SolverOptions, solve_load_path
    from calibration.hertz.geometry import given_geometry
    from calibration.hertz.load import HertzLoad
    from calibration.indentation import add_support_boundary, build_mesh
    from wrlayer.runner import limited_threads
    from meshes.profiles import get_profile

    cfg = load_config(ROOT / "calibration" / "configs" / "default.toml")
    rail = get_profile("60E1")
    geo = given_geometry(rail, y_mm, a_mm, b_mm)
    mesh = build_mesh(rail, geo, "3d", cfg.mesh)
    disc = discretise(mesh, cfg.mesh.order)
    bc = add_support_boundary(mesh, cfg.mesh.rail_support_below_mm)
    load = HertzLoad(geo.y_mm, b_mm, a_mm, z0_mm=geo.z_mm)
    opts = SolverOptions(dirichlet=bc, max_increment_MPa=150.0, rtol=1e-6, etol=1e-8, max_unload_increment_MPa=p0_MPa)
    with limited_threads(1):
        peak = solve_load_path(mesh, material_of(cfg.bodies[0]), load, [p0_MPa], disc=disc, options=opts)
        unl = solve_load_path(mesh, material_of(cfg.bodies[0]), load, [0.0], disc=disc, options=opts,
                              initial_state=peak.state)
    return float(unl.history[-1].u_centre_mm)


def end_to_end(work: Path, positions=END_TO_END_POSITIONS) -> list[dict]:
    """End to end: the contact solver's residual dent u_p(0) (rail layer of the shipped 3D table) against the
    FEM dent under the Hertz pressure of the contact solver's own patch (a = length/2, b = width/2) and peak
    pressure, at each of ``positions``; without scaling, and with the scene key ``scale_to_patch = true`` (the
    characteristic scaled to the solver's own patch by a fixed point, contact.scenes.simulation)."""
    table_path = ROOT / "scenes" / "tables" / "rail_60E1_default.json"
    rows = []
    for label, y, r_lat, r_roll in positions:
        tag = "crown" if y == 0.0 else f"y{y:g}"
        for name, scale in (("calibrated patch, not scaled", False), ("scaled to its own patch", True)):
            p = _contact_first_pass(table_path, scale, work, f"{tag}_{'scaled' if scale else 'unscaled'}", y, r_lat,
                                    r_roll)
            a, b = p["length_mm"] / 2, p["width_mm"] / 2
            dent = _fem_dent_mm(a, b, p["p_max_MPa"], y)
            rows.append({"position": label, "y_mm": y, "case": name, "a_mm": a, "b_mm": b, "p_max_MPa": p["p_max_MPa"],
                         "contact_up0_mm": p["up0_mm"], "fem_dent_mm": dent, "deviation": p["up0_mm"] / dent - 1.0})
    return rows
