"""Steady curves: the curving creepages against the hand formulas, the unbalanced acceleration and load transfer,
and curve conditions read from a wear scene."""

import dataclasses
import math
import re

import numpy as np
import pytest

from contact.__main__ import main
from contact.wear.collective import Condition
from contact.wear.condition import side_inputs, solve_condition
from contact.wear.curving import G_MM_S2, CurveSpec
from contact.wear.planning import build_tasks
from contact.wear.scene import parse_wear_scene
from contact.wheel_rail.kinematics import creepages
from wrlayer.errors import InputError

V, R0, E0 = 20000.0, 460.0, 750.0


def _right_wheel(gamma, r, yaw=0.0, kappa_per_mm=0.0):
    """The right wheel's contact at the contact angle gamma and rolling radius r, e0 from the centre, pure rolling
    at r0, in a curve of curvature kappa (yaw rate -V kappa)."""
    n = np.array([0.0, -math.sin(gamma), math.cos(gamma)])  # rail into wheel: the flange side pushes towards -Y
    axle = np.array([-math.sin(yaw), math.cos(yaw), 0.0])
    point = np.array([0.0, E0, -r])
    return creepages(point, n, np.zeros(3), axle, V, V / R0, -V * kappa_per_mm)


@pytest.mark.parametrize("radius_m", [300.0, -600.0, 2000.0])
@pytest.mark.parametrize("gamma, r", [(0.025, 461.5), (1.0, 478.0)])
def test_curve_creepages_against_the_hand_formulas(radius_m, gamma, r):
    """By hand (Omega = omega a + psi' e_Z, v = V e_X + Omega x (P - C), no yaw): the right wheel's contact at
    Y = e0 below the centre gives vx = 1 - r / r0 + e0 / R (the curve adds e0 / R: positive on the outer wheel of a
    left curve, negative on the inner wheel of a right curve), vy = 0 and phi = -sin(gamma) / r0 - cos(gamma) / R."""
    kappa = 1.0 / (radius_m * 1e3)
    got = _right_wheel(gamma, r, kappa_per_mm=kappa)
    assert got.vx == pytest.approx(1.0 - r / R0 + E0 * kappa, abs=1e-15)
    assert got.vy == pytest.approx(0.0, abs=1e-15)
    assert got.phi_per_mm == pytest.approx(-math.sin(gamma) / R0 - math.cos(gamma) * kappa, abs=1e-15)
    straight = _right_wheel(gamma, r)
    assert got.vx - straight.vx == pytest.approx(E0 / (radius_m * 1e3), rel=1e-9)


def test_pure_rolling_position_and_attack_angle_by_hand():
    """Linear curving creepages (Wickens): at the rolling radius r = r0 (1 + e0 / R) of the outer wheel the
    longitudinal creepage vanishes; an attack angle psi gives vy = -(r / r0) sin(psi) cos(gamma) - (e0 / r0)
    sin(psi) sin(gamma) (v_Y = -omega r sin psi, v_Z = -omega e0 sin psi, projected on t = (0, cos g, sin g))."""
    radius_mm, gamma, psi = 600e3, 0.04, 3e-3
    r = R0 * (1.0 + E0 / radius_mm)
    assert _right_wheel(gamma, r, kappa_per_mm=1.0 / radius_mm).vx == pytest.approx(0.0, abs=1e-15)
    got = _right_wheel(gamma, r, yaw=psi, kappa_per_mm=1.0 / radius_mm)
    by_hand = -(r / R0) * math.sin(psi) * math.cos(gamma) - (E0 / R0) * math.sin(psi) * math.sin(gamma)
    assert got.vy == pytest.approx(by_hand, rel=1e-12)
    assert got.vx == pytest.approx(1.0 - (r / R0) * math.cos(psi) + E0 / radius_mm, abs=1e-15)


def test_unbalanced_acceleration_and_load_transfer_by_hand():
    """V = 100 km/h, R = 1000 m, cant 100 mm, s0 = 1500 mm: a_u = V^2 / R - g h_t / s0 = 771.60 - 654.00 mm/s^2;
    the same curve given by its cant deficiency I = a_u s0 / g; h = 1800 mm, e0 = 750 mm, Q = 60 kN: Q_outer =
    Q (1 + a_u h / (g e0)); a left curve (kappa > 0) loads the right wheel, a right curve the left one."""
    v, kappa = 100.0 / 3.6 * 1e3, 1e-3
    a_u = v ** 2 / 1e6 - G_MM_S2 * 100.0 / 1500.0
    assert a_u == pytest.approx(117.6049, rel=1e-5)
    curve = CurveSpec(cant_mm=100.0, cg_height_mm=1800.0)
    assert curve.unbalanced_acceleration_mm_s2(kappa, v, 1435.0) == pytest.approx(a_u, rel=1e-12)
    deficiency = CurveSpec(cant_deficiency_mm=a_u * 1500.0 / G_MM_S2, cg_height_mm=1800.0)
    assert deficiency.unbalanced_acceleration_mm_s2(kappa, 1.0, 1435.0) == pytest.approx(a_u, rel=1e-12)
    shift = a_u * 1800.0 / (G_MM_S2 * 750.0)
    right, left = curve.side_loads(kappa, 60000.0, v, 1435.0, 750.0)
    assert (right, left) == pytest.approx((60000.0 * (1 + shift), 60000.0 * (1 - shift)), rel=1e-12)
    assert right + left == pytest.approx(120000.0, rel=1e-12)
    assert curve.side_loads(-kappa, 60000.0, v, 1435.0, 750.0) == pytest.approx((left, right), rel=1e-12)
    assert CurveSpec().side_loads(kappa, 60000.0, v, 1435.0, 750.0) == (60000.0, 60000.0)  # h = 0: no transfer


@pytest.mark.parametrize("spec, match", [
    (dict(cant_mm=100.0, cant_deficiency_mm=50.0), "not both"),
    (dict(cant_mm=400.0), "300 mm"),
    (dict(cg_height_mm=5000.0), "overturning"),
])
def test_bad_curves_are_input_errors(spec, match):
    with pytest.raises(InputError, match=match):
        CurveSpec(**spec).side_loads(0.01, 60000.0, 40000.0, 1435.0, 750.0)


def test_curve_condition_from_a_scene_loads_and_yaw_rate(wear_dict, tmp_path):
    """A [[collective.condition]] with a curve: curvature 1/R, yaw rate -V / R, the outer (right) wheel loaded by
    the transfer; the task of each side gets its own wheel's load (side_inputs)."""
    curve = {"lateral_mm": 4.0, "yaw_rad": 0.002, "weight": 1.0, "curvature_1_per_m": 0.002, "cant_mm": 80.0,
             "cg_height_mm": 1500.0, "speed_mm_s": 20000.0}
    data = wear_dict(wheel={"side": "both"})
    data["collective"] = {"condition": [curve]}
    scene = parse_wear_scene(data, tmp_path / "w.toml")
    (c,) = scene.collective.conditions
    spec = CurveSpec(cant_mm=80.0, cg_height_mm=1500.0)
    right, left = spec.side_loads(0.002, 40000.0, 20000.0, 1435.0, scene.wheel_rail.layout.taping_line_mm)
    assert c.curvature_1_per_m == pytest.approx(1 / 500.0) and c.yaw_rate_rad_s == pytest.approx(-20000.0 / 500e3)
    assert (c.vertical_load_right_N, c.vertical_load_left_N) == pytest.approx((right, left)) and right > left
    assert "curve 1/R = 0.002 1/m" in c.describe()
    tasks = build_tasks(scene, scene.initial_profiles, 1, 1.0)
    assert {t.side: side_inputs(t).vertical_load_N for t in tasks} == pytest.approx({"right": right, "left": left})


def test_straight_condition_keeps_its_inputs(make_scene):
    """Straight track, one load: the solver gets the task's inputs unchanged."""
    scene = make_scene()
    (task,) = build_tasks(scene, scene.initial_profiles, 1, 1.0)
    assert side_inputs(task) == task.inputs
    assert Condition(0.0, 0.0, 1.0, 1.0, 1.0).yaw_rate_rad_s == 0.0


@pytest.mark.parametrize("row, match", [
    ({"cant_mm": 50.0}, r"condition\[0\]\.cant_mm: needs a curve"),
    ({"curvature_1_per_m": 0.05}, r"condition\[0\]\.curvature_1_per_m: "),
    ({"curvature_1_per_m": 0.003, "cg_height_mm": 1500.0, "vertical_load_right_N": 5e4}, "not both"),
    ({"curvature_1_per_m": 0.003, "cant_mm": 100.0, "cant_deficiency_mm": 20.0}, r"cant_deficiency_mm: give"),
    ({"curvature_1_per_m": 0.003, "bank_mm": 1.0}, "bank_mm"),
])
def test_bad_curve_keys_exit_2_with_one_line(row, match, wear_dict, write_scene, tmp_path, capsys):
    path = write_scene(wear_dict(collective=None))
    table = "".join(f"{k} = {v!r}\n" for k, v in {"lateral_mm": 1.0, "weight": 1.0, **row}.items())
    path.write_text(path.read_text() + "\n[[collective.condition]]\n" + table)
    assert main(["wear", str(path), "--out", str(tmp_path / "out"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and err.startswith("error: w.toml: collective.condition[0]"), err
    assert re.search(match, err), err


def test_per_wheel_loads_on_straight_track(wear_dict, tmp_path):
    """vertical_load_right_N / vertical_load_left_N of a table reach each side's solver; vertical_load_N stays the
    mean wheel load of the description."""
    data = wear_dict(wheel={"side": "both"})
    data["collective"] = {"condition": [{"lateral_mm": 1.0, "weight": 1.0, "vertical_load_right_N": 45000.0,
                                         "vertical_load_left_N": 35000.0}]}
    scene = parse_wear_scene(data, tmp_path / "w.toml")
    tasks = build_tasks(scene, scene.initial_profiles, 1, 1.0)
    assert {t.side: side_inputs(t).vertical_load_N for t in tasks} == {"right": 45000.0, "left": 35000.0}
    assert scene.collective.conditions[0].curvature_1_per_m == 0.0


def test_wear_condition_in_a_curve_gets_the_yaw_rate_terms(make_scene):
    """Through the wear loop's solver: the same position solved on straight track and in a left curve (kappa =
    1/500 m) differs at the right (outer) wheel's contact by kappa (P - C)_Y in vx, the outer wheel's faster
    centre, with (P - C)_Y = taping line + the wheel profile's contact coordinate, and by -kappa cos(gamma) in the
    spin (sin(gamma) = -phi r0 from the straight solution: pure rolling at r0)."""
    scene = make_scene(layers=None, wear={"inelastic": False})
    (task,) = build_tasks(scene, scene.initial_profiles, 1, 1.0)
    straight = solve_condition(task).patches[0]
    curved = solve_condition(dataclasses.replace(task, condition=dataclasses.replace(task.condition,
                                                                                     curvature_1_per_m=2e-3)))
    curved = curved.patches[0]
    arm = scene.wheel_rail.layout.taping_line_mm + curved.first_contact.y_wheel_mm
    assert curved.first_contact.y_wheel_mm == pytest.approx(straight.first_contact.y_wheel_mm, abs=1e-9)
    assert curved.creepage_x - straight.creepage_x == pytest.approx(2e-6 * arm, rel=1e-5)
    sin_gamma = -straight.spin_per_mm * scene.wheel_rail.wheel.nominal_radius_mm  # phi = -sin(gamma) / r0
    assert curved.spin_per_mm - straight.spin_per_mm == pytest.approx(-2e-6 * math.sqrt(1 - sin_gamma ** 2),
                                                                             rel=1e-9)


@pytest.mark.parametrize("passes, memory, traction", [({}, "rolling", 0.0),
                                                      ({"memory": "relaxed"}, "relaxed", 0.0),
                                                      ({"traction_coefficient": 0.2}, "rolling", 0.2),
                                                      ({"hardening": True}, "state_kept", 0.0)])
def test_wear_tasks_carry_the_passes_memory(make_scene, passes, memory, traction):
    """The wear loop's passes keep the scene's memory rule and traction coefficient (only their number is the
    condition's)."""
    scene = make_scene(passes={"max": 8, **passes})
    (task,) = build_tasks(scene, scene.initial_profiles, 1, 1.0)
    opts = task.inputs.passes.options
    assert (opts.rule, opts.traction_coefficient) == (memory, traction)
    assert 1 <= opts.max_passes <= 8 and opts.tolerance_mm == scene.wheel_rail.passes.tolerance_mm
