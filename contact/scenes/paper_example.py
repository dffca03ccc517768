"""The paper's example (section 5, Table 1) as inputs for the normal solver, and its published numbers.

The paper's Figs. 4 (separation) and 5 (characteristic) are not in the text; the stand-ins below follow
``../shared/reference/paper-notes.md`` (beside the repository):
- separation: parabola f(y) = y^2 / (2 R_y), R_y = 31.7 mm, on y in [-8, 8] mm (the notes: reproduces the no-layer
  patch within a few per cent; the real Fig. 4 curve is not a parabola, area and p_max differ by 5–7 %);
- E = 210 GPa, Poisson 0.3, R = 1600 mm, N = 100 kN, alpha = 0.55, grid h = 0.1 mm;
- COMBINED layer characteristic (wheel and rail together, as eq. 13 is printed) through (0, 0),
  (0.020106 mm, 1190 MPa), (0.0301 mm, 1456 MPa), (0.06 mm, 1900 MPa): p_2 = 1190 MPa (shakedown column),
  u(0) = 0.0301 mm at 1456 MPa and u_p(0) = 0.0301 - 1456/S_1 = 0.0055 mm (the values the paper reports; this
  fixes u_2 = 0.020106), then a softer third segment (slope 14.85e3 N/mm^3, our choice: only used above 1456 MPa).
- passes: the paper reports shakedown after 19 cycles; with a shakedown tolerance of 1e-4 mm per pass our run stops
  at pass 20 (the default 1e-6 mm takes 46 passes, p_max then 1190.04 MPa).
Units: mm, N, MPa.
"""

from __future__ import annotations

import numpy as np

from wrlayer.characteristic import Characteristic
from contact.normal.kik_piotrowski import NormalProblem
from contact.layer.prandtl_layer import LayerPair, PrandtlLayer

PAPER_EXAMPLE = {
    "separation_radius_mm": 31.7,
    "separation_half_width_mm": 8.0,
    "rolling_radius_mm": 1600.0,
    "normal_force_N": 100e3,
    "E_MPa": 210e3,
    "poisson": 0.3,
    "alpha": 0.55,
    "grid_mm": 0.1,
    "characteristic": {"u_mm": [0.0, 0.020106, 0.0301, 0.06], "p_MPa": [0.0, 1190.0, 1456.0, 1900.0]},
    "shakedown_tolerance_mm": 1e-4,
    "creepage": {"vx": 0.002, "vy": 0.0, "phi_per_mm": 0.0012},
    # Table 1 of the paper (lengths mm, area mm^2, delta mm, p_max MPa, forces kN)
    "table1": {
        "with_layer": {"length_mm": 29.97, "width_mm": 4.18, "area_mm2": 100.5, "delta_mm": 0.127601,
                       "p_max_MPa": 1456.0, "Fx_kN": -14.44, "Fy_kN": -18.98, "u0_mm": 0.0301, "up0_mm": 0.0055},
        "no_layer": {"length_mm": 27.36, "width_mm": 3.85, "area_mm2": 85.8, "delta_mm": 0.106330,
                     "p_max_MPa": 1724.0, "Fx_kN": -14.84, "Fy_kN": -21.24},
        "shakedown": {"passes": 19, "length_mm": 28.1, "width_mm": 4.51, "area_mm2": 114.2, "delta_mm": 0.11217,
                      "p_max_MPa": 1190.0, "Fx_kN": -18.42, "Fy_kN": -16.69},
    },
}


def paper_characteristic() -> Characteristic:
    """The combined (wheel + rail) layer characteristic of the example (stand-in for Fig. 5)."""
    return Characteristic.from_dict(PAPER_EXAMPLE["characteristic"], name="paper example characteristic")


def paper_problem(grid_mm: float | None = None, separation_radius_mm: float | None = None) -> NormalProblem:
    """The example's normal problem (parabolic stand-in separation sampled every 0.05 mm)."""
    ex = PAPER_EXAMPLE
    r_y = ex["separation_radius_mm"] if separation_radius_mm is None else separation_radius_mm
    half = ex["separation_half_width_mm"]
    y = np.linspace(-half, half, int(round(2 * half / 0.05)) + 1)
    return NormalProblem(y, y * y / (2.0 * r_y), ex["normal_force_N"], ex["rolling_radius_mm"], ex["E_MPa"],
                         ex["poisson"], alpha=ex["alpha"], grid_mm=ex["grid_mm"] if grid_mm is None else grid_mm)


def paper_layers(prob: NormalProblem) -> LayerPair:
    """The example's combined layer on the problem's strip grid."""
    return LayerPair(combined=PrandtlLayer.uniform(paper_characteristic(), prob.strip_y_mm, name="combined layer"))
