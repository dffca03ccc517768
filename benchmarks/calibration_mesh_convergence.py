"""The calibration mesh's convergence studies: the default 3D mesh against finer references at a few positions and
at every position of the default configuration, at each mesh's own multiples of p_y and at the same peak pressures,
and the mesh styles compared (units mm, MPa, s). Run by ``python -m benchmarks.bench_calibration --full``
(:mod:`benchmarks.bench_calibration`) and :mod:`benchmarks.calibration_mesh_same_pressure`.

``python -m benchmarks.calibration_mesh_convergence BODY Y MESH_JSON [THREADS]`` prints one case as JSON
(MESH_JSON: MeshSettings fields, e.g. ``'{"elements_per_semi_axis": 4, "style": "extruded"}'``).
"""

from __future__ import annotations

import dataclasses
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent


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


if __name__ == "__main__":  # one case as JSON (module docstring)
    print(json.dumps(convergence_case(sys.argv[1], float(sys.argv[2]), json.loads(sys.argv[3]),
                                      threads=int(sys.argv[4]) if len(sys.argv) > 4 else 1)))
