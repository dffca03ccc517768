"""The files of a wheel_rail result: the conventions of result.json, and ``cases.csv`` (one row per
loaded patch: pose, location, angle, N, Fx, Fy, p_max, area, creepages, Y/Q, balance residual, run time;
:data:`CSV_COLUMNS`) (units mm, N, MPa, s, rad; conventions: :data:`CONVENTIONS`, docs/wheel-rail.md).
"""

from __future__ import annotations

import csv
import io

from contact.wheel_rail.results import SweepResult
from wrlayer.json_io import jsonable

#: Columns of cases.csv (one row per loaded patch; a failed case gets one row with its error).
CSV_COLUMNS = ("case", "lateral_mm", "yaw_rad", "roll_rad", "pitch_rate_rad_s", "vertical_load_N", "speed_mm_s",
               "side", "patch", "contact_point", "y_rail_mm", "y_wheel_mm", "Y_track_mm", "Z_track_mm",
               "y_rail_first_contact_mm", "y_rail_weighted_centre_mm",
               "contact_angle_deg", "normal_force_N", "load_share", "Fx_N", "Fy_N", "Mz_Nmm", "p_max_MPa",
               "area_mm2", "creepage_x", "creepage_y", "spin_per_mm", "delta_mm", "approach_mm", "Y_over_Q",
               "vertical_force_N", "vertical_balance_rel", "time_s", "error")


#: Columns of cases.csv taken from the case record and from the patch record (by field name).
CASE_COLUMNS = CSV_COLUMNS[:7]
PATCH_COLUMNS = ("contact_point", "y_rail_mm", "y_wheel_mm", "Y_track_mm", "Z_track_mm", "contact_angle_deg",
                 "normal_force_N", "load_share", "Fx_N", "Fy_N", "Mz_Nmm", "p_max_MPa", "area_mm2", "creepage_x",
                 "creepage_y", "spin_per_mm", "delta_mm")


def cases_csv(result: SweepResult) -> str:
    """The per-case table of a wheel_rail result as CSV text (columns :data:`CSV_COLUMNS`; units in the names;
    a number that is not finite is left empty, as in result.json)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(CSV_COLUMNS)
    for case in result.cases:
        head = {k: jsonable(getattr(case, k)) for k in CASE_COLUMNS}
        if case.error is not None:
            w.writerow([head.get(k, "") if k in head else (case.error if k == "error" else "") for k in CSV_COLUMNS])
            continue
        for side, wr in case.wheels.items():
            for j, patch in enumerate(wr.patches):
                row = {**head, **{k: jsonable(getattr(patch, k)) for k in PATCH_COLUMNS}, "side": side, "patch": j,
                       "y_rail_first_contact_mm": patch.first_contact.y_rail_mm,
                       "y_rail_weighted_centre_mm": patch.weighted_centre.y_rail_mm,
                       "approach_mm": wr.approach_mm, "Y_over_Q": wr.Y_over_Q,
                       "vertical_force_N": wr.vertical_force_N, "vertical_balance_rel": wr.vertical_balance_rel,
                       "time_s": case.time_s, "error": ""}
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


__all__ = ["CASE_COLUMNS", "CONVENTIONS", "CSV_COLUMNS", "PATCH_COLUMNS", "cases_csv"]
