"""The ``[collective]`` table of a wear scene: running conditions as tables, a sweep, or a multibody export (units
mm, N, s, rad; curve radius in m).

Three forms (exactly one):

- ``[[collective.condition]]`` tables: lateral_mm (0), yaw_rad (0), vertical_load_N and speed_mm_s (the scene's
  ``[load]``), weight, label, pitch_rate_rad_s (traction/braking; default the scene's), vertical_load_right_N /
  vertical_load_left_N (per wheel; default vertical_load_N) and a steady curve: curvature_1_per_m (signed, positive
  to the left), cant_mm or cant_deficiency_mm, cg_height_mm, wheelset_position ("given" | "balance") and the
  balance's suspension (:class:`contact.wear.curving.CurveSpec`);
- a sweep: lateral_mm (list or {start, stop, step}), yaw_rad (one number or a list of the same length), weights (a
  list of the same length, or "uniform");
- ``csv = "export.csv"`` with weight_by ("distance" | "time") and max_conditions (20): a multibody code's export
  merged into conditions (:mod:`contact.wear.mbs_collective`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from contact.scenes.scene import SceneKeys
from contact.wear.collective import MAX_CONDITIONS, MAX_CURVATURE_1_PER_M, Condition
from contact.wear.curving import CurveSpec
from contact.wear.mbs_collective import MbsCollective, read_mbs_collective
from contact.wheel_rail.scene import WheelRailScene
from contact.wheel_rail.sweep import sweep_values
from wrlayer.csv_input import CsvTable
from wrlayer.errors import InputError
from wrlayer.section_keys import key_names, read_section

CURVE_KEYS = key_names(CurveSpec)
CONDITION_KEYS = ("lateral_mm", "yaw_rad", "vertical_load_N", "speed_mm_s", "weight", "label", "pitch_rate_rad_s",
                  "vertical_load_right_N", "vertical_load_left_N", "curvature_1_per_m") + CURVE_KEYS


def parse_collective(col: SceneKeys, wheel_rail: WheelRailScene, base: Path
                     ) -> tuple[list[Condition], CsvTable | None]:
    """The conditions of ``[collective]`` and, for a multibody export, the table as read."""
    if "csv" in col.table:
        col.check_known(("csv", "weight_by", "max_conditions"))
        try:
            spec = MbsCollective(col.text("csv"), col.text("weight_by", "distance"),
                                 col.integer("max_conditions", 20, ge=1, le=MAX_CONDITIONS))
        except InputError as err:
            raise InputError(f"{col.file}: {err.what}", err.problem) from None
        return read_mbs_collective(spec, base, f"{col.what('csv')} ({spec.csv})", wheel_rail.wheel.nominal_radius_mm)
    if "condition" in col.table:
        return _tables(col, wheel_rail), None
    return _sweep(col, wheel_rail), None


def _curve(keys: SceneKeys, wheel_rail: WheelRailScene, load: float, speed: float) -> dict:
    """The Condition fields of a curve table (curvature, per-side loads); {} on straight track."""
    kappa = keys.number("curvature_1_per_m", 0.0, ge=-MAX_CURVATURE_1_PER_M, le=MAX_CURVATURE_1_PER_M)
    if kappa == 0.0:
        present = [k for k in CURVE_KEYS if k in keys.table]
        if present:
            raise keys.error(present[0], "needs a curve (curvature_1_per_m != 0)")
        return {}
    try:
        curve = read_section(CurveSpec, keys, also_known=CONDITION_KEYS)
        right, left = curve.side_loads(kappa, load, speed, wheel_rail.layout.gauge_mm,
                                       wheel_rail.layout.taping_line_mm)
    except InputError as err:
        raise (err if err.what.startswith(keys.file) else keys.error(err.what, err.problem)) from None
    given = [k for k in ("lateral_mm", "yaw_rad") if k in keys.table]
    if curve.wheelset_position == "balance" and given:
        raise keys.error(given[0], 'is found by the balance with wheelset_position = "balance"; do not give it')
    out = {"curvature_1_per_m": kappa, "balance": curve.balance(kappa, speed, wheel_rail.layout.gauge_mm)}
    if curve.cg_height_mm > 0:
        side_given = [k for k in ("vertical_load_right_N", "vertical_load_left_N") if k in keys.table]
        if side_given:
            raise keys.error(side_given[0], "give per-wheel loads or cg_height_mm (the load transfer), not both")
        out.update(vertical_load_right_N=right, vertical_load_left_N=left)
    return out


def _tables(col: SceneKeys, wheel_rail: WheelRailScene) -> list[Condition]:
    Q0, V0 = wheel_rail.load.vertical_load_N, wheel_rail.load.speed_mm_s
    col.check_known(("condition",))
    rows = col.table["condition"]
    if not isinstance(rows, list) or not rows:
        raise col.error("condition", "must be an array of tables [[collective.condition]]")
    if len(rows) > MAX_CONDITIONS:
        raise col.error("condition", f"at most {MAX_CONDITIONS} conditions, got {len(rows)}")
    out = []
    for k, row in enumerate(rows):
        keys = SceneKeys(col.file, f"{col.prefix}.condition[{k}]", row)
        keys.check_known(CONDITION_KEYS)
        pitch = keys.number("pitch_rate_rad_s", gt=0.0) if "pitch_rate_rad_s" in keys.table else None
        load, speed = keys.number("vertical_load_N", Q0, gt=0.0), keys.number("speed_mm_s", V0, gt=0.0)
        sides = {k2: keys.number(k2, gt=0.0) for k2 in ("vertical_load_right_N", "vertical_load_left_N")
                 if k2 in keys.table}
        out.append(Condition(keys.number("lateral_mm", 0.0), keys.number("yaw_rad", 0.0, gt=-0.2, lt=0.2), load,
                             speed, keys.number("weight"), keys.text("label", ""), pitch,
                             **{**sides, **_curve(keys, wheel_rail, load, speed)}))
    return out


def _sweep(col: SceneKeys, wheel_rail: WheelRailScene) -> list[Condition]:
    Q0, V0 = wheel_rail.load.vertical_load_N, wheel_rail.load.speed_mm_s
    col.check_known(("lateral_mm", "yaw_rad", "weights"))
    if "lateral_mm" not in col.table:
        raise col.error("lateral_mm", "give [[collective.condition]] tables, a sweep (lateral_mm, weights) or a "
                                      "multibody export (csv)")
    lat = sweep_values(col, "lateral_mm") if isinstance(col.table["lateral_mm"], dict) else col.array("lateral_mm", 1)
    if lat.size > MAX_CONDITIONS:
        raise col.error("lateral_mm", f"at most {MAX_CONDITIONS} conditions, got {lat.size}")
    yaw_value = col.table.get("yaw_rad", 0.0)
    yaw = np.full(lat.size, col.number("yaw_rad", 0.0)) if not isinstance(yaw_value, list) \
        else col.array("yaw_rad", 1)
    if yaw.size != lat.size:
        raise col.error("yaw_rad", f"needs {lat.size} values (one per lateral_mm), got {yaw.size}")
    w_value = col.table.get("weights")
    if w_value is None:
        raise col.error("weights", "required: a list (one weight per condition) or \"uniform\"")
    if w_value == "uniform":
        weights = np.full(lat.size, 1.0 / lat.size)
    else:
        weights = col.array("weights", 1)
        if weights.size != lat.size:
            raise col.error("weights", f"needs {lat.size} values (one per lateral_mm), got {weights.size}")
    return [Condition(float(a), float(b), Q0, V0, float(w)) for a, b, w in zip(lat, yaw, weights)]


__all__ = ["CONDITION_KEYS", "CURVE_KEYS", "parse_collective"]
