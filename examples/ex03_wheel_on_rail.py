"""Example 3: one wheel on its rail, Manchester contact benchmark A-2.2, case 3 (right wheel), against CONTACT.

Problem: the benchmark's S1002 wheel on its UIC60 (60E1) rail read from the benchmark's profile files
(``../shared/reference/profiles/MBench_*_v3.pr?``; the rail file is already canted 1:40), gauge 1435 mm,
back-to-back 1360 mm, nominal radius 460 mm, G = 82 GPa and Poisson 0.28 (E_MPa = 2 G (1 + nu) = 209920 MPa),
friction 0.3; case 3: lateral displacement 1.0 mm, yaw 2.4 mrad, roll 5.049e-5 rad, pitch rate 4.3465752 rad/s,
speed 2000 mm/s, vertical load 10 kN (``../shared/reference/mbench_a22_inputs.csv``, CONTACT's roll and pitch
signs converted). Contact reference point: the depth-weighted centre of the interpenetration (CONTACT's); the
vertical load balances the whole contact force; normal solver: the exact half-space solver.

Built with ``meshes.load_profile``, ``contact.TrackLayout``, ``contact.WheelsetPose``, ``contact.WheelRailInputs``
and ``contact.solve_wheel``; the whole 21-case sweep is ``scenes/manchester_a22.toml``
(``contact.run_scene_file``).

Expected result: one patch, normal force 9835 N, p_max = 741 MPa, area 23.9 mm^2; CONTACT (full non-Hertzian
solution, ``benchmarks/data/contact_mbench_a22.csv``): 9827 N, 741.3 MPa, 24.2 mm^2. ``main()`` returns p_max (MPa).

Run: ``python examples/ex03_wheel_on_rail.py``.
"""

from __future__ import annotations

from pathlib import Path

import contact
import meshes
from contact.wheel_rail.scene_files import reference_dir

G_MPA, POISSON = 82000.0, 0.28


def main(out_dir: str | Path | None = None) -> float:
    """Solve case 3 of A-2.2 for the right wheel; returns the main patch's p_max (MPa)."""
    ref = reference_dir()
    rail = meshes.load_profile(ref / "profiles" / "MBench_UIC60_v3.prr")
    wheel = meshes.load_profile(ref / "profiles" / "MBench_S1002_v3.prw")
    layout = contact.TrackLayout(gauge_mm=1435.0, gauge_depth_mm=14.0, inclination_rad=0.0,
                                 back_to_back_mm=1360.0, flange_back_y_mm=-70.0, nominal_radius_mm=460.0)
    inputs = contact.WheelRailInputs(
        layout=layout, pose=contact.WheelsetPose(lateral_mm=1.0, yaw_rad=0.0024, roll_rad=5.049e-05),
        side="right", load=contact.WheelLoadSpec(vertical_load_N=10000.0, speed_mm_s=2000.0),
        pitch_rate_rad_s=4.3465752, tangential=contact.TangentialSpec(friction=0.3),
        material=contact.MaterialSpec(E_MPa=2.0 * G_MPA * (1.0 + POISSON), poisson=POISSON),
        method=contact.WheelRailMethodSpec(normal="exact", contact_point="weighted_centre", balance="total"))
    sol = contact.solve_wheel(rail, wheel, inputs, case="A-2.2 case 3, right wheel")
    main_patch = max(sol.patches, key=lambda p: p.normal_force_N)
    print(f"{len(sol.patches)} patch(es); main patch: N = {main_patch.normal_force_N:.0f} N, "
          f"p_max = {main_patch.normal.p_max_MPa:.1f} MPa, area = {main_patch.normal.area_mm2:.1f} mm^2, "
          f"Fx = {main_patch.Fx_N:.0f} N; vertical force {sol.vertical_force_N:.1f} N")
    print("CONTACT:      N = 9827 N, p_max = 741.3 MPa, area = 24.2 mm^2")
    return main_patch.normal.p_max_MPa


if __name__ == "__main__":
    main()
