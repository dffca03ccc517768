"""Writes the generated part of the bad-input corpus (run from the repository root:
``python tests/inputs/make_corpus.py``). Each file is a valid base document with ONE key broken; its expected
message fragment (the key path, plus a word of the problem where useful) goes into the folder's expected.toml.
Hand-written files of the corpus (tests/inputs/bad_scenes/*.toml with "# expect:" lines) are not touched.
Units in the documents: mm, N, MPa, s, rad.
"""

from __future__ import annotations

import json
from pathlib import Path

HERE = Path(__file__).resolve().parent
DELETE = object()

# ------------------------------------------------------------------------------------------------ scenes
SCENE = {
    "title": '"corpus base scene"',
    "load": {"normal_force_N": "80000.0", "rolling_radius_mm": "460.0"},
    "material": {"E_MPa": "210000.0", "poisson": "0.3"},
    "separation": {"lateral_radius_mm": "300.0", "half_width_mm": "12.0"},
    "layers.combined": {"u_mm": "[0.0, 0.02, 0.03, 0.06]", "p_MPa": "[0.0, 1190.0, 1456.0, 1900.0]"},
    "tangential": {"creepage_x": "0.002", "creepage_y": "0.0", "spin_per_mm": "0.0", "friction": "0.3",
                   "speed_mm_s": "1000.0", "flexibility": '"three"'},
    "passes": {"max": "3", "hardening": "false", "tolerance_mm": "1e-4"},
    "method": {"alpha": "0.55", "grid_mm": "0.2", "fastsim_cells": "30"},
    "reference": {"source": '"corpus"', "p_max_MPa": "1400.0"},
}

SCENE_BAD = [
    # (file stem, section, key, TOML value or DELETE, expected fragment)
    ("title_number", None, "title", "3", "title: must be a string"),
    ("description_list", None, "description", "[1, 2]", "description: must be a string"),
    ("type_nan", None, "type", "nan", "type: must be one of"),
    ("type_inf", None, "type", "inf", "type: must be one of"),
    ("force_nan", "load", "normal_force_N", "nan", "load.normal_force_N: must be a finite number"),
    ("force_huge", "load", "normal_force_N", "1e300", "load.normal_force_N: must be of magnitude"),
    ("force_huge_integer", "load", "normal_force_N", "9" * 40, "load.normal_force_N"),
    ("force_nested", "load", "normal_force_N", "[[1.0]]", "load.normal_force_N: must be a number"),
    ("radius_bool", "load", "rolling_radius_mm", "true", "load.rolling_radius_mm: must be a number"),
    ("radius_negative", "load", "rolling_radius_mm", "-460.0", "load.rolling_radius_mm: must be >= 1"),
    ("modulus_string", "material", "E_MPa", '"210 GPa"', "material.E_MPa: must be a number"),
    ("modulus_inf", "material", "E_MPa", "inf", "material.E_MPa: must be a finite number"),
    ("modulus_tiny", "material", "E_MPa", "2.5e-33", "material.E_MPa: must be >= 1"),
    ("radius_tiny", "load", "rolling_radius_mm", "1.8e-213", "load.rolling_radius_mm: must be >= 1"),
    ("alpha_tiny", "method", "alpha", "2e-216", "method.alpha: must be >= 0.01"),
    ("poisson_nan", "material", "poisson", "nan", "material.poisson: must be a finite number"),
    ("poisson_negative", "material", "poisson", "-0.1", "material.poisson: must be >= 0"),
    ("lateral_radius_zero", "separation", "lateral_radius_mm", "0.0", "separation.lateral_radius_mm: must be >= 0.01"),
    ("lateral_radius_string", "separation", "lateral_radius_mm", '"R300"', "separation.lateral_radius_mm"),
    ("half_width_inf", "separation", "half_width_mm", "inf", "separation.half_width_mm"),
    ("half_width_huge", "separation", "half_width_mm", "1e9", "separation points over +-1e+09 mm"),
    ("step_tiny", "separation", "step_mm", "1e-9", "separation.step_mm: gives"),
    ("step_negative", "separation", "step_mm", "-0.05", "separation.step_mm: must be > 0"),
    ("layer_u_nested", "layers.combined", "u_mm", "[[0.0, 0.02], [0.03, 0.06]]",
     "layers.combined.u_mm[0]: must be a number"),
    ("layer_u_deeply_nested", "layers.combined", "u_mm", "[[[[[[0.0]]]]], 0.02, 0.03, 0.06]",
     "layers.combined.u_mm[0]"),
    ("layer_u_string_entry", "layers.combined", "u_mm", '[0.0, "0.02", 0.03, 0.06]',
     "layers.combined.u_mm[1]: must be a number"),
    ("layer_u_bool_entry", "layers.combined", "u_mm", "[0.0, true, 0.03, 0.06]",
     "layers.combined.u_mm[1]: must be a number"),
    ("layer_u_nested_100000_deep", "layers.combined", "u_mm", "[" * 100000 + "]" * 100000, "nested too deeply"),
    ("layer_p_nan_entry", "layers.combined", "p_MPa", "[0.0, nan, 1456.0, 1900.0]",
     "layers.combined.p_MPa[1]: must be a finite"),
    ("layer_p_huge_entry", "layers.combined", "p_MPa", "[0.0, 1190.0, 1456.0, 1e300]",
     "layers.combined.p_MPa[3]: must be of magnitude"),
    ("layer_p_not_list", "layers.combined", "p_MPa", "1900.0", "layers.combined.p_MPa: must be a list of numbers"),
    ("layer_long_not_concave", None, "layers.combined",
     {"u_mm": "[" + ", ".join(f"{0.001 * i:.3f}" for i in range(40)) + "]",
      "p_MPa": "[" + ", ".join(f"{2000.0 * (1.0 - 0.9 ** i) + 50.0 * max(0, i - 20):.6f}"
                               for i in range(40)) + "]"},  # concave up to segment 20, then steeper
     "segment 21 (from u = 0.02 mm) has slope"),
    ("creepage_x_string", "tangential", "creepage_x", '"0.2 %"', "tangential.creepage_x: must be a number"),
    ("creepage_y_inf", "tangential", "creepage_y", "-inf", "tangential.creepage_y: must be a finite"),
    ("spin_nested", "tangential", "spin_per_mm", "[0.001]", "tangential.spin_per_mm: must be a number"),
    ("friction_nan", "tangential", "friction", "nan", "tangential.friction: must be a finite"),
    ("speed_negative", "tangential", "speed_mm_s", "-1.0", "tangential.speed_mm_s: must be > 0"),
    ("flexibility_unknown", "tangential", "flexibility", '"triple"', "tangential.flexibility: must be one of"),
    ("flexibility_number", "tangential", "flexibility", "3", "tangential.flexibility: must be a string"),
    ("passes_huge", "passes", "max", "1000000000", "passes.max: must be <= 100000"),
    ("passes_float", "passes", "max", "3.0", "passes.max: must be an integer"),
    ("hardening_int", "passes", "hardening", "1", "passes.hardening: must be true or false"),
    ("tolerance_zero", "passes", "tolerance_mm", "0.0", "passes.tolerance_mm: must be > 0"),
    ("tolerance_nan", "passes", "tolerance_mm", "nan", "passes.tolerance_mm: must be a finite"),
    ("alpha_zero", "method", "alpha", "0.0", "method.alpha: must be >= 0.01"),
    ("alpha_string", "method", "alpha", '"0.55"', "method.alpha: must be a number"),
    ("grid_tiny", "method", "grid_mm", "1e-9", "method.grid_mm: must be >= 0.001"),
    ("grid_huge", "method", "grid_mm", "100.0", "method.grid_mm: 100 mm is wider than the separation table"),
    ("grid_inf", "method", "grid_mm", "inf", "method.grid_mm: must be a finite"),
    ("cells_huge", "method", "fastsim_cells", "1000000000", "method.fastsim_cells: must be <= 10000"),
    ("cells_one", "method", "fastsim_cells", "1", "method.fastsim_cells: must be >= 2"),
    ("cells_bool", "method", "fastsim_cells", "true", "method.fastsim_cells: must be an integer"),
    ("normal_number", "method", "normal", "1", "method.normal: must be a string"),
    ("normal_unknown", "method", "normal", '"boussinesq"', "method.normal: must be one of"),
    ("exact_cells_huge", "method", "exact_cells", "1000000000", "method.exact_cells"),
    ("exact_cells_float", "method", "exact_cells", "48.0", "method.exact_cells: must be an integer"),
    ("layer_mode_list", "method", "layer_mode", '["rolling"]', "method.layer_mode: must be a string"),
    ("reference_string_value", "reference", "p_max_MPa", '"1400"', "reference.p_max_MPa: must be a number"),
    ("reference_source_number", "reference", "source", "1", "reference.source: must be a string"),
    ("reference_unknown", "reference", "p_mean_MPa", "1.0", "reference.p_mean_MPa: unknown key"),
    ("method_not_table", None, "method", "3", "method: must be a table"),
]

# ------------------------------------------------------------------------------------------------ wheel-rail
WHEEL_RAIL = {
    "type": '"wheel_rail"',
    "title": '"corpus base wheel-rail scene"',
    "profiles": {"rail": '"60E1"', "wheel": '"S1002"'},
    "track": {"gauge_mm": "1435.0", "gauge_depth_mm": "14.0", "inclination": "40.0", "back_to_back_mm": "1360.0",
              "flange_back_y_mm": "-70.0"},
    "wheel": {"nominal_radius_mm": "460.0", "side": '"right"'},
    "wheelset": {"lateral_mm": "0.0", "yaw_rad": "0.0", "roll_rad": "0.0"},
    "load": {"vertical_load_N": "10000.0", "speed_mm_s": "2000.0"},
    "material": {"E_MPa": "210000.0", "poisson": "0.28"},
    "tangential": {"friction": "0.3"},
    "passes": {"max": "1", "hardening": "false", "tolerance_mm": "1e-6"},
    "method": {"alpha": "0.55", "grid_mm": "0.1", "fastsim_cells": "60", "merge_mm": "0.005",
               "candidate_gap_mm": "1.0", "f_cap_mm": "2.0"},
    "sweep": {"lateral_mm": "[0.0, 1.0]", "mode": '"zip"'},
    "output": {"deformed_profiles": "true"},
}

WHEEL_RAIL_BAD = [
    ("rail_profile_number", "profiles", "rail", "60", "profiles.rail: must be a string"),
    ("wheel_profile_unknown", "profiles", "wheel", '"S9999"', "profiles.wheel"),
    ("wheel_profile_missing_file", "profiles", "wheel", '"nothing.prw"', "profiles.wheel: no such profile file"),
    ("type_unknown", None, "type", '"wheel_rails"', "type: must be one of"),
    ("title_list", None, "title", "[1]", "title: must be a string"),
    ("description_bool", None, "description", "true", "description: must be a string"),
    ("inclination_rad_big", "track", "inclination_rad", "0.5", "track.inclination"),
    ("G_and_E", "material", "G_MPa", "82000.0", "material.G_MPa: give either E_MPa or G_MPa"),
    ("layers_wheel_number", "layers", "wheel", "3", "layers.wheel: must be a string"),
    ("gauge_string", "track", "gauge_mm", '"1435"', "track.gauge_mm: must be a number"),
    ("gauge_nan", "track", "gauge_mm", "nan", "track.gauge_mm: must be a finite"),
    ("gauge_depth_negative", "track", "gauge_depth_mm", "-14.0", "track.gauge_depth_mm: must be > 0"),
    ("inclination_small", "track", "inclination", "2.0", "track.inclination: 1:n needs n >= 5"),
    ("inclination_inf", "track", "inclination", "inf", "track.inclination: must be a finite"),
    ("back_to_back_bool", "track", "back_to_back_mm", "false", "track.back_to_back_mm: must be a number"),
    ("flange_back_huge", "track", "flange_back_y_mm", "1e300", "track.flange_back_y_mm: must be of magnitude"),
    ("nominal_radius_zero", "wheel", "nominal_radius_mm", "0.0", "wheel.nominal_radius_mm: must be >= 1"),
    ("side_unknown", "wheel", "side", '"middle"', "wheel.side: must be"),
    ("lateral_nested", "wheelset", "lateral_mm", "[[0.0]]", "wheelset.lateral_mm: must be a number"),
    ("yaw_big", "wheelset", "yaw_rad", "1.0", "wheelset.yaw_rad: must be <= 0.2"),
    ("roll_text", "wheelset", "roll_rad", '"automatic"', "wheelset.roll_rad: must be a number"),
    ("pitch_rate_nan", "wheelset", "pitch_rate_rad_s", "nan", "wheelset.pitch_rate_rad_s: must be a finite"),
    ("vertical_load_negative", "load", "vertical_load_N", "-10000.0", "load.vertical_load_N: must be >= 0.001"),
    ("speed_string", "load", "speed_mm_s", '"fast"', "load.speed_mm_s: must be a number"),
    ("E_inf", "material", "E_MPa", "inf", "material.E_MPa: must be a finite"),
    ("poisson_half", "material", "poisson", "0.5", "material.poisson: must be < 0.5"),
    ("friction_negative", "tangential", "friction", "-0.3", "tangential.friction: must be >= 0"),
    ("passes_huge", "passes", "max", "1000000000", "passes.max: must be <= 100000"),
    ("passes_tolerance_string", "passes", "tolerance_mm", '"0"', "passes.tolerance_mm: must be a number"),
    ("hardening_string", "passes", "hardening", '"yes"', "passes.hardening: must be true or false"),
    ("alpha_big", "method", "alpha", "2.0", "method.alpha: must be <= 1"),
    ("grid_tiny", "method", "grid_mm", "1e-9", "method.grid_mm: must be >= 0.001"),
    ("cells_huge", "method", "fastsim_cells", "1000000000", "method.fastsim_cells: must be <= 10000"),
    ("merge_negative", "method", "merge_mm", "-1.0", "method.merge_mm: must be >= 0"),
    ("candidate_gap_nan", "method", "candidate_gap_mm", "nan", "method.candidate_gap_mm: must be a finite"),
    ("f_cap_zero", "method", "f_cap_mm", "0.0", "method.f_cap_mm: must be > 0"),
    ("sweep_ten_million", "sweep", "lateral_mm", "{ start = 0.0, stop = 10.0, step = 0.000001 }",
     "sweep.lateral_mm.step: gives 1e+07 values"),
    ("sweep_product_huge", "sweep", "yaw_rad", "{ start = -0.01, stop = 0.01, step = 0.0000001 }",
     "sweep.yaw_rad.step"),
    ("sweep_nested", "sweep", "lateral_mm", "[[0.0, 1.0], [2.0]]", "sweep.lateral_mm[0]: must be a number"),
    ("sweep_string_entry", "sweep", "lateral_mm", '[0.0, "1.0"]', "sweep.lateral_mm[1]: must be a number"),
    ("sweep_step_zero", "sweep", "lateral_mm", "{ start = 0.0, stop = 1.0, step = 0.0 }",
     "sweep.lateral_mm.step: must be > 0"),
    ("sweep_roll_string", "sweep", "roll_rad", '["0.0"]', "sweep.roll_rad[0]: must be a number"),
    ("sweep_mode_unknown", "sweep", "mode", '"all"', "sweep.mode: must be"),
    ("deformed_profiles_int", "output", "deformed_profiles", "1", "output.deformed_profiles: must be true or false"),
    ("layers_combined_nested", "layers", "combined", "{ u_mm = [[0.0, 0.02]], p_MPa = [0.0, 1000.0] }",
     "layers.combined.u_mm[0]: must be a number"),
    ("layers_table_missing", "layers", "rail", '"no_table.json"', "layers.rail: no such calibration table"),
]

# ------------------------------------------------------------------------------------------------ configs
CONFIG = {
    "run": {"model": '"2d"', "workers": "1", "plots": "false", "linear_solver": '"scipy"', "scheduler": '""'},
    "material": {"E_MPa": "210000.0", "poisson": "0.3", "yield_MPa": "500.0", "H_iso_MPa": "10000.0",
                 "H_kin_MPa": "10000.0"},
    "load": {"reference_load_N": "100000.0", "max_factor": "2.0", "n_levels": "4", "unload_factors": "[1.5, 2.0]",
             "max_increment_factor": "0.25"},
    "mesh": {"elements_per_semi_axis": "3", "h_max_mm": "10.0", "order": "1"},
    "fit": {"n_segments": "3", "elastic_fraction": "0.02", "max_relative_error": "0.2"},
}
BODY = {"body": '"rail"', "profile": '"60E1"', "mate": '"S1002"', "positions_mm": "[0.0]"}

CONFIG_BAD = [
    ("run_workers_huge", "run", "workers", "1000000", "run.workers: must be <= 64"),
    ("run_scheduler_number", "run", "scheduler", "5", "run.scheduler: must be a Dask scheduler address"),
    ("run_plots_string", "run", "plots", '"no"', "run.plots: must be true or false"),
    ("run_linear_solver_unknown", "run", "linear_solver", '"mumps"', "run.linear_solver"),
    ("material_E_string", "material", "E_MPa", '"210e3"', "material.E_MPa: must be a number"),
    ("material_H_iso_inf", "material", "H_iso_MPa", "inf", "material.H_iso_MPa: must be a finite"),
    ("material_H_kin_negative", "material", "H_kin_MPa", "-1.0", "material.H_kin_MPa: must be >= 0"),
    ("material_yield_huge", "material", "yield_MPa", "1e300", "material.yield_MPa: must be of magnitude"),
    ("load_reference_bool", "load", "reference_load_N", "true", "load.reference_load_N: must be a number"),
    ("load_max_factor_big", "load", "max_factor", "100.0", "load.max_factor: must be <= 10"),
    ("load_n_levels_float", "load", "n_levels", "4.5", "load.n_levels: must be an integer"),
    ("load_unload_nested", "load", "unload_factors", "[[1.5], [2.0]]", "load.unload_factors[0]: must be a number"),
    ("load_unload_string", "load", "unload_factors", '"1.5, 2.0"', "load.unload_factors"),
    ("load_max_increment_zero", "load", "max_increment_factor", "0.0", "load.max_increment_factor: must be > 0"),
    ("mesh_h_max_below_h_min", "mesh", "h_max_mm", "0.5", "mesh.h_max_mm: 0.5 mm is below h_min"),
    ("mesh_depth_no_material", "mesh", "depth_mm", "1.0", "mesh.depth_mm"),
    ("mesh_depth_nan", "mesh", "depth_mm", "nan", "mesh.depth_mm: must be a finite"),
    ("mesh_order_three", "mesh", "order", "3", "mesh.order: must be <= 2"),
    ("mesh_grading_string", "mesh", "grading", '"0.3"', "mesh.grading: must be a number"),
    ("mesh_length_factor_small", "mesh", "length_factor", "0.5", "mesh.length_factor: must be > 1"),
    ("mesh_support_inf", "mesh", "rail_support_below_mm", "inf", "mesh.rail_support_below_mm: must be a finite"),
    ("mesh_yield_radius_negative", "mesh", "yield_search_radius_factor", "-3.0",
     "mesh.yield_search_radius_factor: must be > 0"),
    ("mesh_elements_huge", "mesh", "elements_per_semi_axis", "1e9", "mesh.elements_per_semi_axis: must be <= 100"),
    ("fit_elastic_fraction_big", "fit", "elastic_fraction", "2.0", "fit.elastic_fraction: must be <= 1"),
    ("fit_max_error_nan", "fit", "max_relative_error", "nan", "fit.max_relative_error: must be a finite"),
    ("fit_segments_bool", "fit", "n_segments", "true", "fit.n_segments: must be an integer"),
]

CONFIG_BODY_BAD = [
    ("body_body_number", "body", "1", "bodies[0].body: must be 'rail' or 'wheel'"),
    ("body_profile_list", "profile", '["60E1"]', "bodies[0].profile: must be a profile name"),
    ("body_mate_rail", "mate", '"60E1"', "bodies[0].mate"),
    ("body_positions_hundred_thousand", "positions_mm",
     "[" + ", ".join(f"{-30.0 + 6e-4 * i:.4f}" for i in range(100000)) + "]", "bodies[0].positions_mm: has 100000"),
    ("body_positions_range_huge", "positions_mm", DELETE, "bodies[0].positions.step_mm: gives"),
    ("body_positions_nested", "positions_mm", "[[0.0, 1.0]]", "bodies[0].positions_mm[0]: must be a number"),
    ("body_positions_string", "positions_mm", '["0.0"]', "bodies[0].positions_mm[0]: must be a number"),
    ("body_positions_inf", "positions_mm", "[inf]", "bodies[0].positions_mm[0]: must be a finite"),
    ("body_positions_100000_deep", "positions_mm", "[" * 100000 + "]" * 100000, "nested too deeply"),
    ("body_semi_axes_three", "semi_axes_mm", "[7.0, 5.0, 1.0]", "bodies[0].semi_axes_mm: must be [a_mm, b_mm]"),
    ("body_semi_axes_negative", "semi_axes_mm", "[7.0, -5.0]", "bodies[0].semi_axes_mm[1]: must be > 0"),
    ("body_cant_big", "rail_cant_rad", "1.0", "bodies[0].rail_cant_rad: must be <= 0.2"),
    ("body_max_lateral_radius_string", "max_lateral_radius_mm", '"300"', "bodies[0].max_lateral_radius_mm"),
    ("body_wheel_radius_nan", "wheel_radius_mm", "nan", "bodies[0].wheel_radius_mm: must be a finite"),
    ("body_material_nested", "material", "{ E_MPa = [210000.0] }", "bodies[0].material.E_MPa: must be a number"),
]


def _toml_value(v) -> str:
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{k} = {_toml_value(x)}" for k, x in v.items()) + " }"
    return v


def write_toml(path: Path, doc: dict, header: str, bodies: list[dict] | None = None) -> None:
    lines = [f"# {header}", "# Units: mm, N, MPa, s, rad.", ""]
    for key, value in doc.items():
        if not isinstance(value, dict):
            lines.append(f"{key} = {value}")
        elif key == "layers.combined" and "u_mm" in value and len(value["u_mm"]) > 200:  # long arrays: one line each
            lines.append(f"{key} = {_toml_value(value)}")
    for key, value in doc.items():
        if isinstance(value, dict) and not (key == "layers.combined" and len(value.get("u_mm", "")) > 200):
            lines += ["", f"[{key}]"] + [f"{k} = {_toml_value(v)}" for k, v in value.items()]
    for body in bodies or []:
        lines += ["", "[[bodies]]"] + [f"{k} = {_toml_value(v)}" for k, v in body.items()]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def mutate(doc: dict, section, key, value) -> dict:
    out = {k: (dict(v) if isinstance(v, dict) else v) for k, v in doc.items()}
    target = out if section is None else out.setdefault(section, {})
    if value is DELETE:
        target.pop(key, None)
    else:
        target[key] = value
    return out


def write_group(folder: Path, base: dict, bad: list, bodies=None) -> dict[str, str]:
    folder.mkdir(parents=True, exist_ok=True)
    expected = {}
    for stem, section, key, value, fragment in bad:
        doc = mutate(base, section, key, value)
        where = key if section is None else f"{section}.{key}"
        write_toml(folder / f"{stem}.toml", doc, f"corpus: {where} broken ({stem}); generated by make_corpus.py",
                   bodies)
        expected[f"{stem}.toml"] = fragment
    return expected


def write_expected(folder: Path, expected: dict[str, str]) -> None:
    lines = ["# file = fragment the one-line error message must contain (generated by make_corpus.py)", ""]
    lines += [f"{json.dumps(k)} = {json.dumps(v)}" for k, v in sorted(expected.items())]
    (folder / "expected.toml").write_text("\n".join(lines) + "\n", encoding="utf-8")


# ------------------------------------------------------------------------------------------------ profiles
def crown_points(n: int = 41) -> list[tuple[float, float]]:
    """An own test rail head: a circular crown R = 300 mm over y = -30..30 mm (z up, mm)."""
    return [(y, -(y * y) / 600.0) for y in (-30.0 + 60.0 * i / (n - 1) for i in range(n))]


def simpack(settings: dict[str, str], points=None, kind: str = "0") -> str:
    pts = crown_points() if points is None else points
    head = ["! corpus SIMPACK rail profile (own points: R300 crown); z down; lengths mm", "  header.begin",
            "    version = 1", f"    type = {kind}", "  header.end", "  spline.begin"]
    base = {"shift.y": "0.0", "shift.z": "0.0", "rotate": "0.0", "mirror.y": "0", "mirror.z": "0",
            "inversion": "0", "units.len.f": "1000.0", "units.ang.f": "1.0"}
    base.update(settings)
    body = [f"    {k} = {v}" for k, v in base.items() if v is not None]
    rows = [f"    {y:+.9e} {-z:+.9e}" for y, z in pts]
    return "\n".join(head + body + ["    point.begin"] + rows + ["    point.end", "  spline.end"]) + "\n"


PROFILE_BAD = [
    ("ang_f_zero.prr", simpack({"units.ang.f": "0"}), "units.ang.f: must be > 0"),
    ("ang_f_nan.prr", simpack({"units.ang.f": "nan"}), "units.ang.f: must be a finite"),
    ("rotate_inf.prr", simpack({"rotate": "inf"}), "rotate: must be a finite"),
    ("rotate_nan.prr", simpack({"rotate": "nan"}), "rotate: must be a finite"),
    ("rotate_text.prr", simpack({"rotate": "left"}), "rotate: must be a number"),
    ("type_inf.prr", simpack({}, kind="inf"), "header.type: must be a finite"),
    ("type_nan.prr", simpack({}, kind="nan"), "header.type: must be a finite"),
    ("type_two.prr", simpack({}, kind="2"), "header.type: must be 0 (rail) or 1 (wheel)"),
    ("len_f_zero.prr", simpack({"units.len.f": "0"}), "units.len.f: must be > 0"),
    ("len_f_negative.prr", simpack({"units.len.f": "-1000"}), "units.len.f: must be > 0"),
    ("shift_huge.prr", simpack({"shift.y": "1e300"}), "shift.y: must be of magnitude"),
    ("shift_z_inf.prr", simpack({"shift.z": "-inf"}), "shift.z: must be a finite"),
    ("mirror_two.prr", simpack({"mirror.y": "2"}), "mirror.y: must be 0 or 1"),
    ("inversion_half.prr", simpack({"inversion": "0.5"}), "inversion: must be 0 or 1"),
    ("bound_nan.prr", simpack({"bound.y.min": "nan"}), "bound.y.min: must be a finite"),
    ("point_huge.prr", simpack({}, crown_points()[:-1] + [(1e200, 1.0)]), "beyond 100000 mm"),
    ("point_inf.prr", simpack({}, crown_points()[:-1] + [(float("inf"), 1.0)]), "NaN or infinite"),
    ("units_metre_huge.prr", simpack({"units.len.f": "1e-9"}), "beyond 100000 mm"),
    ("no_points.prr", simpack({}, []), "need at least 4 profile points"),
    ("not_monotone.prr", simpack({}, [(0.0, 0.0), (1.0, 0.0), (0.5, 0.1), (2.0, 0.2)]), "not strictly monotone"),
]


def csv_text(points, header: str = "y_mm,z_mm") -> str:
    return "# corpus CSV rail profile (own points); mm, z up\n" + header + "\n" + "".join(
        f"{y!r},{z!r}\n" for y, z in points)


CSV_BAD = [
    ("huge_coordinate.csv", csv_text(crown_points()[:-1] + [(1e300, 0.0)]), "beyond 100000 mm"),
    ("huge_z.csv", csv_text(crown_points()[:20] + [(0.01, 1e12)] + crown_points()[21:]), "beyond 100000 mm"),
    ("overflow_coordinate.csv", csv_text(crown_points()[:-1]) + "1e999,0.0\n", "NaN or infinite"),
    ("nan_coordinate.csv", csv_text(crown_points()[:-1]) + "nan,0.0\n", "NaN or infinite"),
    ("three_columns.csv", csv_text(crown_points()[:-1]) + "30.0,1.0,2.0\n", "expected 2 columns"),
    ("text_value.csv", csv_text(crown_points()[:-1]) + "30.0,high\n", "non-numeric value"),
    ("empty.csv", "# nothing\n", "no profile points found"),
    ("two_points.csv", csv_text(crown_points()[:2]), "need at least 4 profile points"),
    ("repeated_y.csv", csv_text([(0.0, 0.0), (1.0, 0.0), (1.0, 0.1), (2.0, 0.2)]), "not strictly monotone"),
]


# ------------------------------------------------------------------------------------------------ tables
def table_doc() -> dict:
    ch = {"u_mm": [0.0, 0.02, 0.03, 0.06], "p_MPa": [0.0, 1190.0, 1456.0, 1900.0]}
    return {"format": "wrlayer-layer-table", "format_version": 1,
            "header": {"body": "rail", "profile": "corpus rail"},
            "positions": [{"y_mm": y, "characteristic": json.loads(json.dumps(ch))} for y in (-5.0, 0.0, 5.0)],
            "failed": []}


def _set(path_keys, value):
    def change(d):
        obj = d
        for k in path_keys[:-1]:
            obj = obj[k]
        obj[path_keys[-1]] = value
        return d
    return change


TABLE_BAD = [
    ("u_strings.json", _set(["positions", 1, "characteristic", "u_mm"], ["0", "0.02", "0.03", "0.06"]),
     "u_mm[0]: must be a number, got string"),
    ("p_booleans.json", _set(["positions", 1, "characteristic", "p_MPa"], [False, True, True, True]),
     "p_MPa[0]: must be a number, got boolean"),
    ("u_nested.json", _set(["positions", 1, "characteristic", "u_mm"], [[[0.0, 0.02]], [0.03, 0.06]]),
     "u_mm[0]: must be a number"),
    ("u_deeply_nested.json", _set(["positions", 0, "characteristic", "u_mm"], [[[[[[[[0.0]]]]]]], 0.02, 0.03]),
     "u_mm[0]: must be a number"),
    ("y_string.json", _set(["positions", 2, "y_mm"], "5.0"), "positions[2].y_mm: must be a number"),
    ("y_boolean.json", _set(["positions", 0, "y_mm"], True), "positions[0].y_mm: must be a number"),
    ("y_huge.json", _set(["positions", 2, "y_mm"], 1e300), "positions[2].y_mm: must be of magnitude"),
    ("k_strings.json", _set(["positions", 1, "k_N_per_mm3"], ["1", "2", "3"]), "k_N_per_mm3[0]: must be a number"),
    ("body_number.json", _set(["header", "body"], 1), "header.body: must be a string"),
    ("profile_list.json", _set(["header", "profile"], ["60E1"]), "header.profile: must be a string"),
    ("failed_error_number.json", _set(["failed"], [{"y_mm": 2.0, "error": 3}]), "failed[0].error: must be a string"),
    ("characteristic_list.json", _set(["positions", 1, "characteristic"], [0.0, 0.02]),
     "missing 'characteristic'"),
    ("long_not_concave.json",
     _set(["positions", 1, "characteristic"], {"u_mm": [0.01 * i for i in range(60)],
                                                "p_MPa": [100.0 * i for i in range(60)]}),
     "segment 2"),
    ("geometry_a_true.json", _set(["positions", 1, "geometry"], {"a_mm": True, "b_mm": 5.0}),
     "geometry.a_mm: must be a number, got boolean"),
    ("geometry_tiny.json", _set(["positions", 1, "geometry"], {"a_mm": 1e-300, "b_mm": 1e-300}),
     "geometry.a_mm: must be >= 0.001"),
    ("geometry_list.json", _set(["positions", 0, "geometry"], [5.0, 4.0]), "geometry: must be a table, got list"),
    ("warnings_number.json", _set(["positions", 2, "warnings"], 3), "warnings: must be a list of strings"),
]


#: Bytes that are not UTF-8 text (a binary file given by mistake), deterministic.
GARBAGE = bytes((i * 151 + 7) % 256 for i in range(600))


def main() -> None:
    expected = write_group(HERE / "bad_scenes_generated", SCENE, SCENE_BAD)
    (HERE / "bad_scenes_generated" / "binary_garbage.toml").write_bytes(GARBAGE)
    expected["binary_garbage.toml"] = "not UTF-8 text"
    write_expected(HERE / "bad_scenes_generated", expected)
    expected = write_group(HERE / "bad_wheel_rail_scenes", WHEEL_RAIL, WHEEL_RAIL_BAD)
    write_expected(HERE / "bad_wheel_rail_scenes", expected)
    folder = HERE / "bad_calibration_configs_generated"
    expected = write_group(folder, CONFIG, CONFIG_BAD, [BODY])
    for stem, key, value, fragment in CONFIG_BODY_BAD:
        body = dict(BODY)
        if value is DELETE:
            body.pop(key)
            body["positions"] = "{ start_mm = -30.0, stop_mm = 30.0, step_mm = 0.0001 }"
        else:
            body[key] = value
        write_toml(folder / f"{stem}.toml", CONFIG, f"corpus: bodies[0].{key} broken ({stem}); generated by "
                   "make_corpus.py", [body])
        expected[f"{stem}.toml"] = fragment
    (folder / "binary_garbage.toml").write_bytes(GARBAGE)
    expected["binary_garbage.toml"] = "not UTF-8 text"
    write_expected(folder, expected)
    folder = HERE / "bad_profiles"
    folder.mkdir(exist_ok=True)
    expected = {}
    for name, text, fragment in PROFILE_BAD + CSV_BAD:
        (folder / name).write_text(text, encoding="utf-8")
        expected[name] = fragment
    for name, fragment in (("binary_garbage.prr", "not UTF-8 text"), ("binary_garbage.csv", "not UTF-8 text")):
        (folder / name).write_bytes(GARBAGE)
        expected[name] = fragment
    write_expected(folder, expected)
    folder = HERE / "bad_layer_tables"
    folder.mkdir(exist_ok=True)
    expected = {}
    for name, change, fragment in TABLE_BAD:
        (folder / name).write_text(json.dumps(change(table_doc()), indent=1) + "\n", encoding="utf-8")
        expected[name] = fragment
    deep = json.dumps(table_doc()).replace('"u_mm": [0.0, 0.02, 0.03, 0.06]', '"u_mm": ' + "[" * 100000 + "]" * 100000,
                                           1)
    (folder / "u_nested_100000_deep.json").write_text(deep + "\n", encoding="utf-8")
    (folder / "binary_garbage.json").write_bytes(GARBAGE)
    expected["binary_garbage.json"] = "not UTF-8 text"
    expected["u_nested_100000_deep.json"] = "nested too deeply"
    (folder / "good.json").write_text(json.dumps(table_doc(), indent=1) + "\n", encoding="utf-8")
    write_expected(folder, expected)


if __name__ == "__main__":
    main()
