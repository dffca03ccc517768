"""Quasi-static curving against hand-worked cases: a conical free wheelset on the pure rolling line (Boocock 1969),
the same with cant deficiency (the creep forces carry m a_u), an S1002 wheelset pressed into flange contact in a
tight curve; and the wear scene's ``wheelset_position = "balance"``."""

import dataclasses
import json
import math
import re

import pytest

from contact.__main__ import main
from contact.scenes.sections import TangentialSpec
from contact.wear.curving import G_MM_S2, CurvingBalance
from contact.wear.quasi_static import QuasiStaticCurving, Wheelset
from contact.wheel_rail.inputs import WheelRailInputs
from contact.wheel_rail.sections import WheelLoadSpec, WheelRailMethodSpec
from contact.wheel_rail.solve import solve_wheel
from contact.wheel_rail.track_geometry import TrackLayout, place_rail
from meshes.profiles import Profile, Rail60E1, S1002
from meshes.profiles.pieces import line_piece
from wrlayer.errors import ConvergenceError, InputError

Q, V, R0 = 50000.0, 20000.0, 460.0


def cone(slope: float, y_c: float = 0.0) -> Profile:
    """A conical wheel z = slope (y - y_c) (as the contact-geometry tests' cones, shifted so that the radius is r0
    at y_c; the radius grows towards the flange side, -y)."""
    return Profile(f"cone {slope:g}", "wheel", [line_piece(-60.0, 60.0, (-60.0 - y_c) * slope, slope)])


def wheelset(wheel: Profile, radius_m: float, normal: str = "auto") -> tuple[Wheelset, WheelRailInputs]:
    layout, rail = TrackLayout(), Rail60E1()
    inputs = WheelRailInputs(layout=layout, load=WheelLoadSpec(Q, V), tangential=TangentialSpec(0.3),
                             yaw_rate_rad_s=-V / (radius_m * 1e3), method=WheelRailMethodSpec(normal=normal))
    placed = place_rail(rail, layout)
    return Wheelset({s: (rail, wheel) for s in ("right", "left")}, {s: placed for s in ("right", "left")},
                    {s: dataclasses.replace(inputs, side=s) for s in ("right", "left")}), inputs


def conical_case(slope: float, radius_m: float, a_u: float, **suspension):
    """The balance of a free conical wheelset whose centred contact has the rolling radius r0 exactly; also the
    centred contact point (half distance e0 in the track, contact angle)."""
    rail = Rail60E1()
    first, inputs = wheelset(cone(slope), radius_m)
    centred = solve_wheel(rail, cone(slope), inputs).patches[0].candidate
    ws, _ = wheelset(cone(slope, centred.y_wheel_mm), radius_m)
    found = QuasiStaticCurving(ws, CurvingBalance(a_u, **suspension), 1.0 / (radius_m * 1e3), centred.Y_mm,
                               "cone").solve()
    return found, centred


def test_conical_free_wheelset_runs_on_the_pure_rolling_line():
    """By hand (Boocock 1969; Wickens ch. 7): the contact stays on the round rail head where its slope is the
    cone's, so Delta r = 2 lambda y exactly and e0 is the contact's distance from the centre line; the yaw rate
    -V/R adds +-e0/R to the wheels' longitudinal creepages, which vanish together at y0 = e0 r0 / (lambda R),
    psi = 0, no longitudinal creep force. The spins' curve terms -cos(gamma)/R add a lateral force f23 2/R that a
    yaw of f23 / (f22 R) ~ 2e-6 rad balances. Measured: y 6.86005 mm against 6.85907 mm (1.4e-4)."""
    slope, radius_m = 0.05, 1000.0
    found, centred = conical_case(slope, radius_m, 0.0)
    y0 = centred.Y_mm * R0 / (slope * radius_m * 1e3)
    assert found.lateral_mm == pytest.approx(y0, rel=5e-4)
    assert abs(found.yaw_rad) < 1e-5
    assert abs(found.longitudinal_N) < 1.0 and abs(found.creep_lateral_N) < 1.0        # creep forces ~0 (N)
    assert found.pitch_rate_rad_s == pytest.approx(V / R0, rel=1e-4)   # free: pure rolling at the patch's radius
    assert abs(found.lateral_residual_N) <= 1e-4 * 2 * Q and abs(found.yaw_residual_Nmm) <= 1e-4 * 2 * Q * 750


def test_a_right_hand_curve_mirrors_the_position():
    """R = -1000 m (a curve to the right, the left rail outer): y = -y0, the same |psi|."""
    left, _ = conical_case(0.05, 1000.0, 0.0)
    right, _ = conical_case(0.05, -1000.0, 0.0)
    assert right.lateral_mm == pytest.approx(-left.lateral_mm, abs=1e-4)
    assert right.yaw_rad == pytest.approx(-left.yaw_rad, abs=1e-7)


def test_no_balance_is_a_convergence_error():
    """A stiff yaw spring (1e12 N mm/rad) to a frame yawed 20 mrad asks for a yaw moment of 2e10 N mm that the
    creep forces of a flangeless cone (at most about 2 mu Q e0 = 2.3e7 N mm) cannot give at any y: reported, not
    returned."""
    with pytest.raises(ConvergenceError, match="yaw moment does not change sign"):
        conical_case(0.05, 1000.0, 0.0, yaw_stiffness_Nmm_per_rad=1e12, frame_yaw_rad=0.02)


def test_cant_deficiency_is_carried_by_the_creep_forces():
    """By hand: with equal loads and contact angles gamma the normal forces' lateral parts cancel except for the
    creep forces' own vertical parts (the wheels' vertical balance, N cos g + F_s t_Z = Q), so the track-lateral
    contact force is sum F_s / cos(gamma) and the lateral balance gives sum F_s t_Y = sum F_s cos(gamma) =
    -m a_u cos^2(gamma) with m = 2 Q / g: 0.25 % less than m a_u at lambda = 0.05, more than the tolerance."""
    slope, radius_m, a_u = 0.05, 1000.0, 500.0
    found, centred = conical_case(slope, radius_m, a_u)
    m_a_u = 2.0 * Q / G_MM_S2 * a_u
    assert found.external_lateral_N == pytest.approx(m_a_u, rel=1e-12)
    tolerance = 1e-4 * 2 * Q
    cos2 = math.cos(centred.contact_angle_rad) ** 2
    assert found.creep_lateral_N == pytest.approx(-m_a_u * cos2, abs=tolerance)
    assert abs(found.creep_lateral_N + m_a_u) > tolerance
    assert found.yaw_rad < -1e-4    # vy ~ -psi > 0: the attack angle makes the inward creep force (towards -Y)


def test_lateral_spring_force_is_carried_by_the_creep_forces():
    """A lateral spring k_y = 500 N/mm to the centre line pulls the wheelset back by k_y y; as with cant
    deficiency the creep forces then carry sum F_s cos(gamma) = k_y y cos^2(gamma), and y stays near the pure
    rolling line (the yaw moment is still the longitudinal creep forces')."""
    found, centred = conical_case(0.05, 1000.0, 0.0, lateral_stiffness_N_per_mm=500.0)
    spring = 500.0 * found.lateral_mm
    assert found.creep_lateral_N == pytest.approx(spring * math.cos(centred.contact_angle_rad) ** 2, abs=1e-4 * 2 * Q)
    assert found.lateral_mm == pytest.approx(centred.Y_mm * R0 / (0.05 * 1e6), rel=0.02)
    assert found.yaw_rad > 1e-4                # the outward creep force of a positive attack angle


@pytest.mark.slow
def test_tight_curve_presses_the_wheelset_into_flange_contact():
    """S1002 on 60E1 (1:40), R = 150 m, free wheelset: the pure rolling line would need Delta r = 2 e0 r0 / R =
    4.6 mm, more than the tread gives, so the outer (right) wheel runs on its flange root: its patch has a contact
    angle above 0.3 rad and its normal force's lateral part carries the creep forces of both wheels. Kik-Piotrowski,
    as the wear loop (with the exact solver the vertical balance of the two-patch flange contact at y = 6 mm
    stalls: docs/limitations.md)."""
    radius_m = 150.0
    ws, _ = wheelset(S1002(), radius_m, "kik_piotrowski")
    found = QuasiStaticCurving(ws, CurvingBalance(0.0), 1.0 / (radius_m * 1e3), 750.0, "S1002").solve()
    solutions = ws.solve(found.lateral_mm, found.yaw_rad, found.pitch_rate_rad_s, "check")
    flange = max(solutions["right"].patches, key=lambda p: p.candidate.contact_angle_rad)
    assert flange.candidate.contact_angle_rad > 0.3 and found.lateral_mm > 5.0
    normal_lateral = flange.normal_force_N * flange.normal_track[1]
    assert normal_lateral < -0.5 * found.creep_lateral_N < 0.0
    total = sum(float(p.force_track_N()[1]) for s in solutions.values() for p in s.patches)
    assert abs(total) <= 1e-4 * 2 * Q


def _balance_scene(wear_dict, write_scene, **curve):
    """A both-wheel scene without layers, one condition in a 1000 m curve with 50 mm cant deficiency."""
    path = write_scene(wear_dict(wheel={"side": "both"}, layers=None, wear={"inelastic": False, "distance_km": 1.0},
                                 load={"vertical_load_N": Q, "speed_mm_s": V}, collective=None))
    row = {"weight": 1.0, "curvature_1_per_m": 1e-3, "cant_deficiency_mm": 50.0, "wheelset_position": "balance",
           **curve}
    table = "".join(f"{k} = {json.dumps(v)}\n" for k, v in row.items())
    path.write_text(path.read_text() + "\n[[collective.condition]]\n" + table)
    return path


@pytest.mark.slow
def test_wear_scene_finds_and_records_the_position(wear_dict, write_scene, tmp_path):
    """``wheelset_position = "balance"``: result.json records y, psi and the residuals of the step, and the
    condition's balance inputs."""
    path = _balance_scene(wear_dict, write_scene, yaw_stiffness_Nmm_per_rad=5e9)
    assert main(["wear", str(path), "--out", str(tmp_path / "out"), "--quiet"]) == 0
    result = json.loads((tmp_path / "out" / "result.json").read_text())
    (step,) = result["steps"]
    (found,) = step["balance"]
    assert found["condition"] == 0 and 0.0 < found["lateral_mm"] < 10.0
    assert abs(found["lateral_residual_N"]) <= 10.0 and abs(found["yaw_residual_Nmm"]) <= 7500.0
    assert result["inputs"]["conditions"][0]["balance"]["yaw_stiffness_Nmm_per_rad"] == 5e9


@pytest.mark.parametrize("curve, match", [
    ({"lateral_mm": 2.0}, r"condition\[0\]\.lateral_mm: is found by the balance"),
    ({"wheelset_position": "given", "yaw_stiffness_Nmm_per_rad": 1e9}, r"yaw_stiffness_Nmm_per_rad: needs"),
    ({"wheelset_position": "balanced"}, r"wheelset_position"),
    ({"lateral_stiffness_N_per_mm": -1.0}, r"lateral_stiffness_N_per_mm"),
])
def test_bad_balance_keys_exit_2(curve, match, wear_dict, write_scene, tmp_path, capsys):
    path = _balance_scene(wear_dict, write_scene, **curve)
    assert main(["wear", str(path), "--out", str(tmp_path / "out"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and err.startswith("error: w.toml: collective.condition[0]"), err
    assert re.search(match, err), err


def test_a_straight_condition_cannot_be_balanced():
    ws, _ = wheelset(S1002(), 1000.0)
    with pytest.raises(InputError, match="needs a curve"):
        QuasiStaticCurving(ws, CurvingBalance(0.0), 0.0, 750.0, "straight")
