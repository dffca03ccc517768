"""Example 2: closed-form Hertz against the two normal solvers (Kik-Piotrowski and the exact half-space solver).

Problem (``scenes/hertz_check.toml``): two steel bodies with a separation f = x^2/(2 R) + y^2/(2 R_y),
R = 300 mm (rolling direction), R_y = 80 mm (lateral), N = 50 kN, E = 210 GPa, Poisson 0.28, no layer.
Hertz's theory gives the contact ellipse exactly (semi-axes a, b in mm, peak pressure p_0 in MPa, approach in mm;
:func:`calibration.hertz.geometry.hertz_ellipse`). The scene's inputs are read with ``contact.load_scene``, the
problem is built with ``contact.NormalProblem`` and solved with ``contact.solve_normal`` (the paper's fast
method, approximate: virtual penetration alpha = 0.55) and ``contact.solve_normal_with(..., method="exact")``
(boundary elements on the half-space, the yardstick).

Expected result: Hertz p_0 = 1818.5 MPa, a = 5.610 mm, b = 2.340 mm, approach 0.086681 mm; the exact solver
p_max = 1818.6 MPa, patch 11.17 x 4.66 mm; Kik-Piotrowski p_max = 1658.9 MPa (9 % low: its patch is shorter and
wider, 10.56 x 5.50 mm), approach within 3 %. ``main()`` returns the exact solver's p_max (MPa).

Run: ``python examples/ex02_hertz_check.py``.
"""

from __future__ import annotations

from pathlib import Path

import contact
from calibration.hertz.geometry import combined_modulus_MPa, hertz_ellipse
from wrlayer.shipped import scenes_dir



def main(out_dir: str | Path | None = None) -> float:
    """Hertz, Kik-Piotrowski and exact solutions of the Hertz-check scene; returns the exact p_max (MPa)."""
    scene = contact.load_scene(scenes_dir() / "hertz_check.toml")
    sep, load, mat = scene.separation, scene.load, scene.material
    prob = contact.NormalProblem(sep.y_mm, sep.f_mm, load.normal_force_N, load.rolling_radius_mm,
                                 E_MPa=mat.E_MPa, poisson=mat.poisson, alpha=scene.method.alpha,
                                 grid_mm=scene.method.grid_mm)
    hertz = hertz_ellipse(1.0 / (2.0 * load.rolling_radius_mm), 1.0 / (2.0 * sep.lateral_radius_mm),
                          load.normal_force_N, combined_modulus_MPa(mat.E_MPa, mat.poisson))
    kp = contact.solve_normal(prob)
    exact = contact.solve_normal_with(prob, method="exact")
    print(f"{'':16s} {'p_max MPa':>10s} {'length mm':>10s} {'width mm':>9s} {'delta mm':>9s}")
    print(f"{'Hertz':16s} {hertz.p0_MPa:10.1f} {2 * hertz.a_mm:10.3f} {2 * hertz.b_mm:9.3f} "
          f"{hertz.approach_mm:9.6f}")
    for name, sol in (("Kik-Piotrowski", kp), ("exact", exact)):
        print(f"{name:16s} {sol.p_max_MPa:10.1f} {sol.length_mm:10.3f} {sol.width_mm:9.3f} {sol.delta_mm:9.6f}")
    return exact.p_max_MPa


if __name__ == "__main__":
    main()
