"""Example 1: the paper's example (Piotrowski, section 5, Table 1), first pass with the Prandtl layer.

Problem: two steel bodies pressed together by N = 100 kN, rolling radius R = 1600 mm, a lateral separation
f(y) = y^2 / (2 R_y) with R_y = 31.7 mm on y in [-8, 8] mm, E = 210 GPa (``E_MPa = 210e3``), Poisson 0.3,
virtual-penetration factor alpha = 0.55 (eq. 9), strips of 0.1 mm. One combined layer characteristic p(u) for
wheel and rail together through (0.020106 mm, 1190 MPa), (0.0301 mm, 1456 MPa), (0.06 mm, 1900 MPa).

The problem is built in code and solved with the Kik-Piotrowski method (``contact.solve_normal``), then the same
example is run from its scene file ``scenes/paper_with_layer.toml`` (``contact.load_scene`` + ``contact.simulate``),
which also repeats the passes and solves the tangential problem.

Expected result (paper's Table 1 in brackets): approach delta = 0.127109 mm (0.127601), p_max = 1517 MPa (1456),
patch 29.91 x 4.30 mm (29.97 x 4.18), layer displacement u(0) = 0.0342 mm (0.0301). ``main()`` returns delta (mm).

Run: ``python examples/ex01_paper_table1.py``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import contact
from wrlayer.shipped import scenes_dir

R_Y_MM = 31.7                                             # lateral radius of the separation (mm)
CHARACTERISTIC = {"u_mm": [0.0, 0.020106, 0.0301, 0.06], "p_MPa": [0.0, 1190.0, 1456.0, 1900.0]}


def paper_solution() -> contact.NormalSolution:
    """The first pass of the paper's example, built in code."""
    y = np.linspace(-8.0, 8.0, 321)                       # the separation table, every 0.05 mm
    prob = contact.NormalProblem(y_mm=y, f_mm=y ** 2 / (2.0 * R_Y_MM), normal_force_N=100e3,
                                 rolling_radius_mm=1600.0, E_MPa=210e3, poisson=0.3, alpha=0.55, grid_mm=0.1)
    characteristic = contact.Characteristic.from_dict(CHARACTERISTIC, name="paper example layer")
    layer = contact.LayerPair(combined=contact.PrandtlLayer.uniform(characteristic, prob.strip_y_mm,
                                                                    name="combined layer"))
    return contact.solve_normal(prob, layer)


def main(out_dir: str | Path | None = None) -> float:
    """Solve the example in code and from its scene file; print both; return the approach delta (mm)."""
    sol = paper_solution()
    print("in code:   ", sol)
    run = contact.simulate(contact.load_scene(scenes_dir() / "paper_with_layer.toml"))
    first = run.result.passes[0]  # a frozen PassRecord; run.result.to_dict() is the result.json data
    print(f"scene file: delta = {first.delta_mm:.6f} mm, p_max = {first.p_max_MPa:.0f} MPa, "
          f"Fx = {first.Fx_N / 1e3:.2f} kN ({run.result.n_passes} pass)")
    print("paper:      delta = 0.127601 mm, p_max = 1456 MPa, Fx = -14.44 kN")
    return sol.delta_mm


if __name__ == "__main__":
    main()
