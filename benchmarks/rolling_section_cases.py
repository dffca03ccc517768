"""The rolling section gap's cases: the positions rolled on their profile sections, the tractions, the levels and
each case's rolling configuration (units mm, MPa). Read by :mod:`benchmarks.bench_rolling_section_gap` (the gap's
report) and :mod:`benchmarks.rolling_section_static` (the sections' static dents under mesh refinement)."""

from __future__ import annotations

import pathlib
from dataclasses import asdict, replace

from benchmarks import rolling_gap_cases as gap_cases
from calibration.rolling.config import RollingConfig, parse_rolling_config

ROOT = pathlib.Path(__file__).resolve().parents[1]
#: (case name, table, y in mm, label) of the positions rolled on their sections.
POSITIONS = (("crown", "scenes/tables/rail_60E1_default.json", 0.0, "rail crown"),
             ("corner", "scenes/tables/rail_60E1_default.json", -35.0, "rail gauge corner"),
             ("field", "scenes/tables/rail_60E1_default.json", 25.0, "rail field side"),
             ("tread", "scenes/tables/wheel_S1002_default.json", 0.0, "wheel tread"),
             ("flange", "scenes/tables/wheel_S1002_default.json", -37.5, "wheel flange root"),
             ("inner", "scenes/tables/wheel_S1002_default.json", -22.5, "wheel inner tread"),
             ("gauge", "scenes/tables/rail_60E1_default.json", -25.0, "rail gauge side"),
             ("corner_upper", "scenes/tables/rail_60E1_default.json", -30.0, "rail gauge corner, upper"),
             ("gauge_upper", "scenes/tables/rail_60E1_default.json", -20.0, "rail gauge side, upper"),
             ("tread_oval", "scenes/tables/wheel_S1002_default.json", -7.5, "wheel tread, oval patch"))
TRACTIONS = gap_cases.TRACTIONS
#: The levels p0 / p_y of the section's own first yield: from near first yield to 2.1 p_y.
LEVELS = (1.15, 1.3, 1.5, 1.7, 2.1)
N_PASSES = 5
#: The passes compared (1-based).
COMPARED = (1, 2, 5)
#: The layer's target: within this fraction of the FEM groove.
TARGET = 0.05


def section_config(table: str, y_mm: float, c: float) -> RollingConfig:
    """The rolling configuration of one position and traction on its section: the gap's coarse discretisation
    (:data:`benchmarks.rolling_gap_cases.GAP_TRACK`, ``GAP_MESH``) with :data:`N_PASSES` passes."""
    data = {"contact": {"body": "section", "table": table, "y_mm": y_mm, "traction_coefficient": c,
                        "levels": list(LEVELS), "level_unit": "p_y"},
            "track": asdict(replace(gap_cases.GAP_TRACK, n_passes=N_PASSES)),
            "mesh": asdict(gap_cases.GAP_MESH), "run": {"plots": False}}
    return parse_rolling_config(data, f"section gap {table} y = {y_mm:g} mm, c = {c:g}")


def case_name(name: str, c: float) -> str:
    return f"{name}_c{c:.1f}"


__all__ = ["COMPARED", "LEVELS", "N_PASSES", "POSITIONS", "ROOT", "TARGET", "TRACTIONS", "case_name",
           "section_config"]
