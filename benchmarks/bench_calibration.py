"""Calibration benchmark: fit error against the number of segments N (justifies the default N), 2D against 3D
indentation (run time and characteristic difference against the finest 3D model run), and the cold/warm
``make calibrate`` times (read from the last run's summary in out/calibration, or measured in "full" mode).

Errors are measured against: the FEM points of each calibrated position (fit error, in mm and relative to the
largest u), the FEM unloading runs (eq. 8 residual error), and the finest 3D run (2D/3D comparison).
"""

from __future__ import annotations

import dataclasses
import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

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
        cmd = [sys.executable, "-m", "calibration", "run", str(ROOT / "calibration/configs/default.toml"), "--out",
               str(DEFAULT_OUT), "--quiet"]
        import shutil

        shutil.rmtree(DEFAULT_OUT, ignore_errors=True)
        t0 = time.perf_counter()
        subprocess.run(cmd, check=False, capture_output=True)
        info["cold_s"] = time.perf_counter() - t0
        if summary.is_file():  # per-position FEM time in the workers, apart from the field output
            info["cold_fem_seconds"] = json.loads(summary.read_text()).get("fem_seconds")
        t0 = time.perf_counter()
        subprocess.run(cmd, check=False, capture_output=True)
        info["warm_s"] = time.perf_counter() - t0
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


#: The three positions of the convergence study: crown, gauge corner, wheel flange root.
CONVERGENCE_POSITIONS = (("rail", 0.0, "crown"), ("rail", -35.0, "gauge corner"), ("wheel", -37.5, "flange root"))


def convergence_case(body: str, y_mm: float, mesh_kw: dict, load_kw: dict | None = None, threads: int = 1,
                     linear_solver: str = "auto") -> dict:
    """One 3D indentation of the default calibration's material and load path at a position (the conforming
    rule of the pipeline applied) with mesh settings ``mesh_kw``: first yield, inelastic displacement u_pl at
    every load level (as multiples of p_y), FEM residual dents, dofs, seconds (wall, with ``threads`` BLAS
    threads)."""
    from calibration.config import load_config, material_of
    from calibration.indentation import IndentationJob, indent
    from calibration.tasks import position_geometry
    from wrlayer.runner import limited_threads
    from meshes.profiles import get_profile

    cfg = load_config(ROOT / "calibration" / "configs" / "default.toml")
    b = next(x for x in cfg.bodies if x.body == body)
    profile, mate = get_profile(b.profile), get_profile(b.mate)
    geo, warning = position_geometry(b, profile, mate, y_mm, cfg.reference_load_N)
    mesh = dataclasses.replace(cfg.mesh, **mesh_kw)
    load = dataclasses.replace(cfg.load, **(load_kw or {}))
    t0 = time.perf_counter()
    with limited_threads(threads):
        res = indent(IndentationJob(profile=profile, geometry=geo, material=material_of(b), model="3d", mesh=mesh,
                                    load=load, linear_solver=linear_solver))
    p = np.asarray(res.p_MPa)
    return {"body": body, "y_mm": y_mm, "mesh": mesh_kw, "load": load_kw or {}, "a_mm": geo.a_mm,
            "b_mm": geo.b_mm, "warning": warning, "seconds": time.perf_counter() - t0, "threads": threads,
            "n_dofs": res.n_dofs, "newton": res.newton_iterations, "first_yield_MPa": res.first_yield_MPa,
            "linear_solves": res.linear_solves, "factorisations": res.factorisations,
            "p_factor": (p / res.first_yield_MPa).tolist(), "u_pl_mm": res.u_pl_mm,
            "peak_factor": (np.asarray(res.unload_peaks_MPa) / res.first_yield_MPa).tolist(),
            "residual_fem_mm": res.residual_fem_mm}


def convergence_errors(case: dict, ref: dict) -> dict:
    """Relative differences of ``case`` against the finer ``ref``: first yield, the peak layer displacement (u_pl
    at the highest level), the residual dent at every unloading level, and u_pl at every load level above
    1.2 p_y (compared at the same multiple of each run's p_y), each relative to the reference value."""
    upl_ref = np.interp(case["p_factor"], ref["p_factor"], ref["u_pl_mm"])
    upl = np.asarray(case["u_pl_mm"])
    above = np.asarray(case["p_factor"]) > 1.2
    res = np.asarray(case["residual_fem_mm"]) / np.asarray(ref["residual_fem_mm"]) - 1.0
    return {"first_yield": case["first_yield_MPa"] / ref["first_yield_MPa"] - 1.0,
            "peak_u_pl": upl[-1] / upl_ref[-1] - 1.0,
            "u_pl_levels_max": float(np.max(np.abs(upl[above] / upl_ref[above] - 1.0))),
            "residual_levels": res.tolist()}


def _loglog_interp(x, xp, fp):
    """Interpolate a positive, steeply growing curve (u_pl against p0) linearly in log-log coordinates."""
    xp, fp = np.asarray(xp, dtype=float), np.asarray(fp, dtype=float)
    ok = (xp > 0) & (fp > 0)
    return np.exp(np.interp(np.log(np.asarray(x, dtype=float)), np.log(xp[ok]), np.log(fp[ok])))


def convergence_at_same_pressure(body: str, y_mm: float, mesh_kw: dict, ref_mesh_kw: dict) -> dict:
    """Mesh convergence compared at the same ABSOLUTE pressures (what the contact solver reads from a table: u(p)
    in MPa): the case ``mesh_kw`` runs the default load path (levels and unloading peaks at multiples of its own
    p_y); the reference ``ref_mesh_kw`` runs a load path scaled by r = p_y(case) / p_y(ref) (max_factor and
    unload_factors x r), so that it unloads from the same absolute peaks and reaches the same peak pressure.
    Returns both runs and the deviations: first yield, peak u_pl (same p0), residual dents (same peaks), the
    largest deviation of u_pl at the case's load levels above 1.2 p_y (reference interpolated in log-log)."""
    from calibration.config import load_config

    load = load_config(ROOT / "calibration" / "configs" / "default.toml").load
    case = convergence_case(body, y_mm, mesh_kw)
    probe = convergence_case(body, y_mm, ref_mesh_kw, {"max_factor": 1.01, "n_levels": 1, "unload_factors": [1.01]})
    r = case["first_yield_MPa"] / probe["first_yield_MPa"]
    ref = convergence_case(body, y_mm, ref_mesh_kw, {"max_factor": load.max_factor * r,
                                                     "unload_factors": [f * r for f in load.unload_factors]})
    p_case = np.asarray(case["p_factor"]) * case["first_yield_MPa"]
    p_ref = np.asarray(ref["p_factor"]) * ref["first_yield_MPa"]
    above = np.asarray(case["p_factor"]) > 1.2
    upl_case = np.asarray(case["u_pl_mm"])
    upl_ref = _loglog_interp(p_case[above], p_ref, ref["u_pl_mm"])
    peaks_case = np.asarray(case["peak_factor"]) * case["first_yield_MPa"]
    peaks_ref = np.asarray(ref["peak_factor"]) * ref["first_yield_MPa"]
    return {"case": case, "ref": ref, "ratio_p_y": r,
            "peak_pressures_MPa": {"case": peaks_case.tolist(), "ref": peaks_ref.tolist()},
            "errors": {"first_yield": r - 1.0,
                       "peak_u_pl": float(upl_case[-1] / upl_ref[-1] - 1.0),
                       "u_pl_levels_max": float(np.max(np.abs(upl_case[above] / upl_ref - 1.0))),
                       "residual_levels": (np.asarray(case["residual_fem_mm"])
                                           / np.asarray(ref["residual_fem_mm"]) - 1.0).tolist()}}


#: The finer references of the convergence study (isotropic, elements per semi-axis): 6 at the crown, 8 at the
#: conforming positions (docs/calibration.md, "Validated accuracy").
CONVERGENCE_REFERENCES = {0.0: 6, -35.0: 8, -37.5: 8}


def mesh_convergence_same_pressure(default_kw: dict | None = None) -> list[dict]:
    """:func:`convergence_at_same_pressure` of the default mesh against the isotropic references at the three
    CONVERGENCE_POSITIONS."""
    default_kw = default_kw or {}
    return [{"position": name, **convergence_at_same_pressure(
        body, y, default_kw, {"elements_per_semi_axis": CONVERGENCE_REFERENCES[y], "style": "isotropic"})}
            for body, y, name in CONVERGENCE_POSITIONS]


#: Positions of the end-to-end check: (label, rail position y (mm), combined lateral radius (mm),
#: rolling radius (mm)) at 100 kN. The crown is the geometry of scenes/calibrated_layers.toml (rail crown R300 on a
#: flat tread); y = -15 mm (the 60E1's R80 region) takes the curvatures the table records there:
#: 1 / (k_y + k_y,mate) = 1 / (0.0125 - 0.008168) and 1 / (k_x + k_x,mate) = 1 / 0.0021684 per mm.
END_TO_END_POSITIONS = (("crown y = 0", 0.0, 300.0, 460.0), ("y = -15 mm (R80)", -15.0, 230.8, 461.2))


def _contact_first_pass(table_path: Path, scale: bool, work: Path, tag: str, y_mm: float = 0.0,
                        lateral_radius_mm: float = 300.0, rolling_radius_mm: float = 460.0) -> dict:
    """A one-pass scene at 100 kN with the rail table's layer at ``y_mm`` as the only layer (``scale_to_patch`` =
    ``scale``) on the separation y^2 / (2 R_lateral) and the rolling radius given: the first pass's result (patch,
    p_max, u_p(0)). The defaults are the crown scene of scenes/calibrated_layers.toml."""
    toml = "\n".join([
        f'title = "end to end {tag}"', "[load]", "normal_force_N = 100000.0", f"rolling_radius_mm = {rolling_radius_mm}",
        "[material]", "E_MPa = 210000.0", "poisson = 0.3", "[separation]", f"lateral_radius_mm = {lateral_radius_mm}",
        "half_width_mm = 25.0", "[layer.rail]", f'table = "{table_path}"', f"position_mm = {y_mm}",
        f"scale_to_patch = {'true' if scale else 'false'}", "[passes]", "max = 1", "[method]", "alpha = 0.55",
        "grid_mm = 0.1", ""])
    work.mkdir(parents=True, exist_ok=True)
    (work / f"{tag}.toml").write_text(toml)
    subprocess.run([sys.executable, "-m", "contact", "simulate", str(work / f"{tag}.toml"), "--out",
                    str(work / tag)], check=True, capture_output=True, cwd=ROOT)
    return json.loads((work / tag / "result.json").read_text())["passes"][0]


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


#: References of :func:`convergence_every_position`: the isotropic mesh with 8 elements per semi-axis (no finer
#: zone) where a/b < AUTO_EXTRUDED_ASPECT, the extruded one with 6 on the more elongated patches (an isotropic 8
#: there would need 200,000-370,000 dofs).
EVERY_POSITION_REFERENCES = {"isotropic": {"elements_per_semi_axis": 8, "style": "isotropic",
                                           "yield_zone_refinement": 1.0},
                             "extruded": {"elements_per_semi_axis": 6, "style": "extruded"}}


def every_position_references(default_kw: dict | None = None) -> list[tuple[str, float, str, dict]]:
    """Every position of the default configuration (29) as (body, y (mm), the default mesh's style with
    ``default_kw``, its reference's mesh settings from EVERY_POSITION_REFERENCES)."""
    from calibration.config import load_config
    from calibration.indentation import AUTO_EXTRUDED_ASPECT, mesh_style
    from calibration.pipeline import position_geometry
    from meshes.profiles import get_profile

    cfg = load_config(ROOT / "calibration" / "configs" / "default.toml")
    out = []
    for b in cfg.bodies:
        profile, mate = get_profile(b.profile), get_profile(b.mate)
        for y in b.positions_mm:
            geo, _ = position_geometry(b, profile, mate, y, cfg.reference_load_N)
            style = mesh_style(geo, dataclasses.replace(cfg.mesh, **(default_kw or {})))
            elongated = geo.a_mm >= AUTO_EXTRUDED_ASPECT * geo.b_mm
            out.append((b.body, float(y), style, EVERY_POSITION_REFERENCES["extruded" if elongated else "isotropic"]))
    return out


def convergence_every_position(default_kw: dict | None = None) -> list[dict]:
    """The default mesh (with ``default_kw``) against EVERY_POSITION_REFERENCES at every position of the default
    configuration (29 positions, 58 FEM runs; about 40 min on one core): each row a :func:`convergence_case` with
    its ``style`` (the default's), ``errors`` (:func:`convergence_errors`) and the reference's mesh, dofs and
    seconds. Levels are multiples of each mesh's own p_y; at equal p0:
    :mod:`benchmarks.calibration_mesh_same_pressure`."""
    rows = []
    for body, y, style, ref_kw in every_position_references(default_kw):
        ref = convergence_case(body, y, ref_kw)
        case = convergence_case(body, y, default_kw or {})
        rows.append(dict(case, style=style, errors=convergence_errors(case, ref), reference=ref["mesh"],
                         reference_dofs=ref["n_dofs"], reference_seconds=ref["seconds"]))
    return rows


def every_position_markdown(rows: list[dict]) -> list[str]:
    """Table of :func:`convergence_every_position`."""
    md = ["| position | a/b | style | dofs (default / ref) | s (default / ref) | reference | first yield | peak u_pl | "
          "max u_pl at the levels | residual dents |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        e = r["errors"]
        md.append(f"| {r['body']} y = {r['y_mm']:g}{' (conforming)' if r['warning'] else ''} | "
                  f"{r['a_mm'] / r['b_mm']:.1f} | {r['style']} | {r['n_dofs']} / {r['reference_dofs']} | "
                  f"{r['seconds']:.1f} / {r['reference_seconds']:.0f} | {r['reference']['style']} "
                  f"{r['reference']['elements_per_semi_axis']:g} | {100 * e['first_yield']:+.2f} % | "
                  f"{100 * e['peak_u_pl']:+.2f} % | {100 * e['u_pl_levels_max']:.2f} % | "
                  f"{' / '.join(f'{100 * x:+.2f}' for x in e['residual_levels'])} % |")
    return md


def mesh_convergence(levels=(3, 4, 6, 8), style: str = "isotropic") -> list[dict]:
    """The convergence study at CONVERGENCE_POSITIONS: each mesh (``style``: mesh.style) against the finest (the
    last level)."""
    out = []
    for body, y, _ in CONVERGENCE_POSITIONS:
        cases = [convergence_case(body, y, {"elements_per_semi_axis": e, "style": style}) for e in levels]
        for c in cases:
            c["errors"] = convergence_errors(c, cases[-1])
        out += cases
    return out


#: The three convergence positions plus the two most elongated patches of the default run
#: (wheel field side y = 30, a/b = 10.2; flange flank y = -45, a/b = 13.6).
STYLE_POSITIONS = CONVERGENCE_POSITIONS + (("wheel", 30.0, "wheel field side"), ("wheel", -45.0, "flange flank"))


def style_comparison(levels=(3, 4, 6), reference: dict | None = None) -> list[dict]:
    """Extruded (mesh.style = "extruded") against isotropic meshes at STYLE_POSITIONS, run alternately (old/new)
    so that both see the same machine load; every case's errors against ``reference`` (default: the isotropic
    mesh with 8 elements per semi-axis at the conforming positions, 6 at the crown, the extruded one with 6 on
    the elongated patches, where the isotropic 6 would take an estimated 370,000 dofs). About 30 runs of 10-170 s
    each (docs/calibration.md, "Mesh styles")."""
    ref_mesh = reference or {"rail 0": {"elements_per_semi_axis": 6, "style": "isotropic"},
                             "rail -35": {"elements_per_semi_axis": 8, "style": "isotropic"},
                             "wheel -37.5": {"elements_per_semi_axis": 8, "style": "isotropic"},
                             "wheel 30": {"elements_per_semi_axis": 6, "style": "extruded"},
                             "wheel -45": {"elements_per_semi_axis": 6, "style": "extruded"}}
    out = []
    for body, y, _ in STYLE_POSITIONS:
        ref = convergence_case(body, y, ref_mesh[f"{body} {y:g}"])
        cases = []
        for e in levels:
            for style in ("isotropic", "extruded"):
                if style == "isotropic" and e != 4 and body == "wheel" and y in (30.0, -45.0):
                    continue  # the isotropic meshes of the elongated patches: only the default (4) is affordable
                kw = {"elements_per_semi_axis": e, "style": style}
                if kw != ref_mesh[f"{body} {y:g}"]:  # the reference is run once
                    cases.append(convergence_case(body, y, kw))
        for c in cases + [ref]:
            c["errors"] = convergence_errors(c, ref)
            c["reference"] = ref_mesh[f"{body} {y:g}"]
        out += cases + [ref]
    return out


if __name__ == "__main__":  # python -m benchmarks.bench_calibration BODY Y MESH_JSON [THREADS]: one case as JSON
    # (MESH_JSON: MeshSettings fields, e.g. '{"elements_per_semi_axis": 4, "style": "extruded"}')
    print(json.dumps(convergence_case(sys.argv[1], float(sys.argv[2]), json.loads(sys.argv[3]),
                                      threads=int(sys.argv[4]) if len(sys.argv) > 4 else 1)))


#: The references of the convergence study: the finest isotropic runs of docs/calibration.md.
REFERENCE_MESHES = {"rail 0": {"elements_per_semi_axis": 6, "style": "isotropic"},
                          "rail -35": {"elements_per_semi_axis": 8, "style": "isotropic"},
                          "wheel -37.5": {"elements_per_semi_axis": 8, "style": "isotropic"}}


def structured_comparison(levels=(3, 4, 6, 8), reference: dict | None = None) -> list[dict]:
    """mesh.style = "structured" (meshes.meshing.structured_core_mesh) at CONVERGENCE_POSITIONS for each of
    ``levels``, and the isotropic default (4 per semi-axis) run alternately with the structured 4, so that both
    see the same machine load. Every case's errors against ``reference`` (default REFERENCE_MESHES:
    ``errors``) and against the finest structured run (``errors_own``). About 20 runs of 10-250 s each
    (docs/calibration.md, "Validated accuracy")."""
    ref_mesh = reference or REFERENCE_MESHES
    out = []
    for body, y, _ in CONVERGENCE_POSITIONS:
        ref = convergence_case(body, y, ref_mesh[f"{body} {y:g}"])
        cases = []
        for e in levels:
            cases.append(convergence_case(body, y, {"elements_per_semi_axis": e, "style": "structured"}))
            if e == 4:
                cases.append(convergence_case(body, y, {"elements_per_semi_axis": 4, "style": "isotropic"}))
        own = max((c for c in cases if c["mesh"]["style"] == "structured"),
                  key=lambda c: c["mesh"]["elements_per_semi_axis"])
        for c in cases + [ref]:
            c["errors"] = convergence_errors(c, ref)
            c["errors_own"] = convergence_errors(c, own)
            c["reference"] = ref_mesh[f"{body} {y:g}"]
        out += cases + [ref]
    return out


def yield_zone_comparison(settings=({"elements_per_semi_axis": 4}, {"elements_per_semi_axis": 4,
                                                                    "yield_zone_refinement": 2.0},
                                    {"elements_per_semi_axis": 3, "yield_zone_refinement": 2.0}),
                          reference: dict | None = None) -> list[dict]:
    """Isotropic meshes with and without mesh.yield_zone_refinement at CONVERGENCE_POSITIONS, run alternately, each
    against ``reference`` (default REFERENCE_MESHES; docs/calibration.md, "Mesh convergence")."""
    ref_mesh = reference or REFERENCE_MESHES
    out = []
    for body, y, _ in CONVERGENCE_POSITIONS:
        ref = convergence_case(body, y, ref_mesh[f"{body} {y:g}"])
        cases = [convergence_case(body, y, {"style": "isotropic", **kw}) for kw in settings]
        for c in cases + [ref]:
            c["errors"] = convergence_errors(c, ref)
            c["reference"] = ref_mesh[f"{body} {y:g}"]
        out += cases + [ref]
    return out
