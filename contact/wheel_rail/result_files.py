"""The result of a wheel_rail scene as plain data: per patch, per wheel, the input echo, ``cases.csv`` (units mm, N,
MPa, s, rad; conventions: :data:`CONVENTIONS`, docs/wheel-rail.md).
"""

from __future__ import annotations

import csv
import hashlib
import io
import math
from typing import Any

import numpy as np

from contact.wheel_rail.solve import PatchSolution, WheelRailSolution
from contact.wheel_rail.reference_point import weighted_centre_eta
from contact.wheel_rail.scene import WheelRailScene

def patch_result(p: PatchSolution) -> dict[str, Any]:
    """JSON-serialisable numbers of one loaded patch (track-frame forces; see contact.wheel_rail.contact_search for the
    location conventions)."""
    c, ns = p.candidate, p.normal
    t = p.tangential
    ref = p.reference
    sign = p.strip_sign
    out = {
        "contact_point": ref.kind, "eta_ref_mm": ref.eta_mm,
        "y_rail_mm": ref.y_rail_mm, "y_wheel_mm": ref.y_wheel_mm,
        "Y_track_mm": float(p.point_track[1]), "Z_track_mm": float(p.point_track[2]),
        "X_lead_mm": float(p.point_track[0]),
        "first_contact": {"y_rail_mm": c.y_rail_mm, "y_wheel_mm": c.y_wheel_mm, "Y_track_mm": sign * c.Y_mm,
                          "Z_track_mm": c.Z_mm, "X_lead_mm": c.X_mm, "contact_angle_rad": c.contact_angle_rad},
        "weighted_centre": _weighted_centre_result(p),
        "contact_angle_rad": ref.angle_rad, "contact_angle_deg": math.degrees(ref.angle_rad),
        "wheel_contact_angle_rad": c.wheel_contact_angle_rad, "wheel_radius_mm": c.wheel_radius_mm,
        "rolling_radius_kp_mm": c.rolling_radius_kp_mm, "normal_gap_mm": c.normal_gap_mm,
        "normal_force_N": p.normal_force_N, "delta_mm": ns.delta_mm, "delta0_mm": ns.delta0_mm,
        "area_mm2": ns.area_mm2, "p_max_MPa": ns.p_max_MPa, "length_mm": ns.length_mm, "width_mm": ns.width_mm,
        "n_regions": len(ns.patches),
        "regions": [{"eta_min_mm": float(pt.y_mm[0]), "eta_max_mm": float(pt.y_mm[-1]), "p0_MPa": r.p0_MPa,
                     "normal_force_N": r.normal_force_N} for pt, r in zip(ns.patches, ns.regions)],
        "creepage_x": p.kinematics.vx, "creepage_y": p.kinematics.vy, "spin_per_mm": p.kinematics.phi_per_mm,
        "Fx_N": p.Fx_N, "Fy_N": p.Fy_N, "Mz_Nmm": p.Mz_Nmm,
        "WT_max": max((r.WT_max_N_per_mm for r in t), default=None),
        "PT_max_W_per_mm2": max((r.PT_max_W_per_mm2 for r in t), default=None),
        "force_on_wheel_track_N": p.force_track_N().tolist(),
        "normal_track": p.normal_track.tolist(), "lateral_track": p.lateral_track.tolist(),
        "elastic": bool(ns.elastic), "u0_mm": ns.u0_mm,
        "layer_scaled_to_patch": None if p.layer_patch_mm is None else {
            "a_mm": p.layer_patch_mm[0], "b_mm": p.layer_patch_mm[1], "balances": p.layer_scaling_solves},
    }
    y, f = p.problem.strip_y_mm, p.problem.separation_on_grid_mm
    near = f <= 2.0 * ns.delta0_mm  # the strips in contact and their neighbourhood
    out["strips"] = {"eta_mm": y[near].tolist(), "f_mm": f[near].tolist(), "p_peak_MPa": ns.p_peak_MPa[near].tolist(),
                     "y_rail_mm": p.rail_y_of_strip[near].tolist(), "y_wheel_mm": p.wheel_y_of_strip[near].tolist()}
    if p.passes:
        out["passes"] = [{**r.summary(), "max_cumulative_residual_mm":
                          {b: float(np.max(v, initial=0.0)) for b, v in r.cumulative_residual_mm.items()}}
                         for r in p.passes]
    return out


def _weighted_centre_result(p: PatchSolution) -> dict[str, float]:
    c = p.candidate
    eta = weighted_centre_eta(c, p.normal.delta_mm)
    return {"eta_mm": eta, "y_rail_mm": float(c.rail_coordinate(eta)), "y_wheel_mm": float(c.wheel_coordinate(eta)),
            "Y_track_mm": p.strip_sign * float(c.Y_mm + eta * c.lateral[1]), "Z_track_mm": float(c.Z_mm + eta
                                                                                                  * c.lateral[2])}


def wheel_result(sol: WheelRailSolution) -> dict[str, Any]:
    Q = sol.inputs.vertical_load_N
    force = sum((p.force_track_N() for p in sol.patches), np.zeros(3))
    return {
        "side": sol.inputs.side, "wheel_height_mm": sol.search.wheel_height_mm, "approach_mm": sol.approach_mm,
        "vertical_balance_rel": sol.vertical_balance_rel, "balance": sol.inputs.balance,
        "balance_iterations": sol.balance_iterations, "vertical_force_N": float(force[2]),
        "merge_mm": sol.merge_mm,
        "normal_vertical_N": float(sum(p.normal_force_N * p.normal_track[2] for p in sol.patches)),
        "force_on_wheel_track_N": force.tolist(), "Y_over_Q": float(force[1] / Q), "n_patches": len(sol.patches),
        "patches": [{**patch_result(p), "load_share": p.vertical_N / float(force[2])} for p in sol.patches],
        "unloaded_candidates": [{"y_rail_mm": c.y_rail_mm, "y_wheel_mm": c.y_wheel_mm, "normal_gap_mm": c.normal_gap_mm,
                                 "contact_angle_rad": c.contact_angle_rad} for c in sol.unloaded],
        "flange_tip": {"y_wheel_mm": sol.search.flange_tip[0], "Y_side_mm": sol.search.flange_tip[1]},
    }


CSV_COLUMNS = ("case", "lateral_mm", "yaw_rad", "roll_rad", "pitch_rate_rad_s", "vertical_load_N", "speed_mm_s",
               "side", "patch", "contact_point", "y_rail_mm", "y_wheel_mm", "Y_track_mm", "Z_track_mm",
               "y_rail_first_contact_mm", "y_rail_weighted_centre_mm",
               "contact_angle_deg", "normal_force_N", "load_share", "Fx_N", "Fy_N", "Mz_Nmm", "p_max_MPa",
               "area_mm2", "creepage_x", "creepage_y", "spin_per_mm", "delta_mm", "approach_mm", "Y_over_Q",
               "vertical_force_N", "vertical_balance_rel", "time_s", "error")


def cases_csv(result: dict[str, Any]) -> str:
    """The per-case table of a wheel_rail result as CSV text (columns :data:`CSV_COLUMNS`; units in the names)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(CSV_COLUMNS)
    for e in result["cases"]:
        head = {k: e.get(k) for k in CSV_COLUMNS[:7]}
        head["case"] = e["case"]
        if "error" in e:
            w.writerow([head.get(k, "") if k in head else (e["error"] if k == "error" else "") for k in CSV_COLUMNS])
            continue
        for side, wr in e["wheels"].items():
            for j, pr in enumerate(wr["patches"]):
                row = {**head, **{k: pr.get(k) for k in CSV_COLUMNS if k in pr}, "side": side, "patch": j,
                       "y_rail_first_contact_mm": pr["first_contact"]["y_rail_mm"],
                       "y_rail_weighted_centre_mm": pr["weighted_centre"]["y_rail_mm"],
                       "approach_mm": wr["approach_mm"], "Y_over_Q": wr["Y_over_Q"],
                       "vertical_force_N": wr["vertical_force_N"], "vertical_balance_rel": wr["vertical_balance_rel"],
                       "time_s": e.get("time_s"), "error": ""}
                w.writerow(["" if row.get(k) is None else (f"{row[k]:.10g}" if isinstance(row[k], float) else row[k])
                            for k in CSV_COLUMNS])
    return buf.getvalue()


CONVENTIONS = {
    "y_rail_mm": "rail profile coordinate of the contact point: from the head centre line, + towards the field side "
                 "(gauge side negative); same for both rails",
    "y_wheel_mm": "wheel profile coordinate (S1002: S, 0 at the taping line, + towards the field side, flange "
                  "negative); same for both wheels",
    "Y_track_mm": "lateral track coordinate of the wheel contact point (from the track centre, + towards the right "
                  "rail)",
    "contact_point": "y_rail_mm, y_wheel_mm, Y_track_mm, Z_track_mm, X_lead_mm of a patch are its reference point "
                     "(method.contact_point: first_contact = rigid first contact, weighted_centre = centre of the "
                     "interpenetration region weighted by the depth), in the contact plane; creepages, spin, FASTSIM "
                     "and Mz refer to it; first_contact and weighted_centre are both reported; see docs/wheel-rail.md",
    "vertical_force_N": "Z component of the total contact force on the wheel (normal + tangential); the balance "
                        "(method.balance = total) makes it equal the vertical load",
    "load_share": "a patch's share of the wheel's vertical force",
    "contact_angle_rad": "angle of the contact normal at the reference point (weighted centre: the weighted mean "
                         "angle; first_contact.contact_angle_rad: the candidate's) from the vertical, positive when "
                         "it tilts towards the track centre (flange contact ~ +1.2 rad), same sign for both wheels",
    "rolling_radius_kp_mm": "Kik-Piotrowski radius in the rolling direction: 1/(k_c cos^2 b + k_m sin^2 b); without "
                            "yaw r / cos(wheel contact angle)",
    "strips": "per strip of a patch (track orientation, eta = 0 at the contact point): separation f in the contact "
              "plane (shifted to min 0), peak pressure p(0, eta), and the strip's profile coordinates on rail and wheel",
    "lateral_mm/yaw_rad/roll_rad": "wheelset displacement towards the right rail; yaw counter-clockwise seen from "
                                   "above; roll lifting the right wheel",
}


def inputs_echo(scene: WheelRailScene) -> dict[str, Any]:
    """The resolved inputs of the scene as written in result.json ("inputs")."""
    lay = scene.layout
    inp = scene.inputs()
    layers = scene.layers
    path = scene.path
    return {
        "scene_file": str(path.resolve()),
        "content_sha256": hashlib.sha256(path.read_bytes()).hexdigest() if path.is_file() else None,
        "title": scene.data.get("title", ""), "description": scene.data.get("description", ""),
        "rail_profile": scene.rail_profile.name, "wheel_profile": scene.wheel_profile.name,
        "track": {"gauge_mm": lay.gauge_mm, "gauge_depth_mm": lay.gauge_depth_mm,
                  "inclination_rad": lay.inclination_rad, "back_to_back_mm": lay.back_to_back_mm,
                  "flange_back_y_mm": lay.flange_back_y_mm, "nominal_radius_mm": lay.nominal_radius_mm},
        "sides": scene.sides, "roll": "auto" if scene.roll_auto else "given",
        "vertical_load_N": inp.vertical_load_N, "speed_mm_s": inp.speed_mm_s,
        "pitch_rate_rad_s": inp.pitch_rate_rad_s if inp.pitch_rate_rad_s is not None
        else inp.speed_mm_s / lay.nominal_radius_mm,
        "friction": inp.friction, "E_MPa": inp.E_MPa, "poisson": inp.poisson, "G_MPa": inp.G_MPa,
        "method": {"alpha": inp.alpha, "grid_mm": inp.grid_mm, "fastsim_cells": inp.fastsim_cells,
                   "normal": inp.normal_method.name, "exact_cells": inp.normal_method.exact_cells,
                   "layer_mode": inp.normal_method.layer_mode, "contact_point": inp.contact_point,
                   "balance": inp.balance, **vars(inp.search)},
        "sweep_csv": None if scene.sweep.csv is None else scene.sweep.csv.to_dict(),
        "passes": vars(inp.passes),
        "layers": None if layers is None else (
            {"combined": layers.solver.combined.to_dict()} if layers.combined is not None else
            {**layers.solver.names, "sha256": layers.sha256}),
        "scene_toml": scene.data,
    }


__all__ = ["CONVENTIONS", "CSV_COLUMNS", "cases_csv", "inputs_echo", "patch_result", "wheel_result"]
