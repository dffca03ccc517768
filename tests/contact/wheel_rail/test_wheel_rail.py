"""One wheel on its rail: vertical load balance, left/right symmetry, layers looked up per strip, deformed profiles
written and read back."""

import math

import numpy as np
import pytest

from wrlayer.characteristic import Characteristic
from wrlayer.layer_table import LayerTable
from contact.wheel_rail.deformed import deformed_profile, residual_on_profiles, rigid_roll
from contact.scenes.layers import LayerSources
from contact.wheel_rail.inputs import WheelRailInputs
from contact.wheel_rail.sections import WheelLoadSpec, WheelRailMethodSpec
from contact.wheel_rail.solve import solve_wheel
from contact.wheel_rail.track_geometry import WheelsetPose
from wrlayer.errors import InputError, PatchTruncated

#: These cases' F_Z is continuous at the balance: the iteration meets 1e-8 of Q (the accepted limit is wider only
#: where F_Z jumps across Q).
CONTINUOUS_BALANCE = 1e-6


def _vertical(sol):
    """Vertical component of the total contact force on the wheel (normal + tangential), N."""
    return sum(float(p.force_track_N()[2]) for p in sol.patches)


@pytest.mark.parametrize("d", [0.5, 5.2, 7.0])
def test_vertical_load_balance(rail60, s1002, placed, d):
    sol = solve_wheel(rail60, s1002, WheelRailInputs(pose=WheelsetPose(d), load=WheelLoadSpec(vertical_load_N=12000.0)), placed_rail=placed)
    assert abs(_vertical(sol) - 12000.0) / 12000.0 < CONTINUOUS_BALANCE
    assert sol.vertical_balance_rel < 1e-8
    if d == 5.2:  # two-point contact (tread + flange root), both loaded
        assert len(sol.patches) == 2
        assert sol.approach_mm > 0
        for p in sol.patches:  # each patch's approach follows the common vertical approach
            c = p.candidate
            assert p.normal.delta_mm == pytest.approx(sol.approach_mm * math.cos(c.contact_angle_rad)
                                                      - c.normal_gap_mm, rel=1e-6)


def _mirror_check(a, b):
    assert len(a.patches) == len(b.patches)
    for p, q in zip(a.patches, b.patches):
        assert p.candidate.y_rail_mm == pytest.approx(q.candidate.y_rail_mm, abs=1e-9)
        assert p.candidate.y_wheel_mm == pytest.approx(q.candidate.y_wheel_mm, abs=1e-9)
        assert p.normal_force_N == pytest.approx(q.normal_force_N, rel=1e-9)
        assert p.normal.p_max_MPa == pytest.approx(q.normal.p_max_MPa, rel=1e-9)
        assert p.point_track[1] == pytest.approx(-q.point_track[1], abs=1e-9)
        assert p.kinematics.vx == pytest.approx(q.kinematics.vx, abs=1e-12)
        assert p.kinematics.vy == pytest.approx(-q.kinematics.vy, abs=1e-12)
        assert p.kinematics.phi_per_mm == pytest.approx(-q.kinematics.phi_per_mm, abs=1e-12)
        assert p.Fx_N == pytest.approx(q.Fx_N, rel=1e-6, abs=1e-6)
        assert p.Fy_N == pytest.approx(-q.Fy_N, rel=1e-6, abs=1e-6)
        fa, fb = p.force_track_N(), q.force_track_N()
        assert fa[1] == pytest.approx(-fb[1], rel=1e-6, abs=1e-6) and fa[2] == pytest.approx(fb[2], rel=1e-9)


def test_centred_wheelset_left_right_mirrored(rail60, s1002, placed):
    right = solve_wheel(rail60, s1002, WheelRailInputs(side="right"), placed_rail=placed)
    left = solve_wheel(rail60, s1002, WheelRailInputs(side="left"), placed_rail=placed)
    _mirror_check(right, left)
    assert rigid_roll(placed, s1002, right.inputs.layout, WheelsetPose(0.0)) == pytest.approx(0.0, abs=1e-12)


def test_displaced_yawed_wheelset_mirrored(rail60, s1002, placed):
    # right wheel at (d, psi, phi) is the mirror image of the left wheel at (-d, -psi, -phi)
    pose = WheelsetPose(5.0, 0.012, 0.0004)
    right = solve_wheel(rail60, s1002, WheelRailInputs(side="right", pose=pose), placed_rail=placed)
    left = solve_wheel(rail60, s1002, WheelRailInputs(side="left", pose=WheelsetPose(-5.0, -0.012, -0.0004)),
                       placed_rail=placed)
    _mirror_check(right, left)
    assert any(abs(p.Fy_N) > 100 for p in right.patches)


def _table(body, ys, p2):
    positions = []
    for y, p in zip(ys, p2):
        u2 = p / 6.0e4
        positions.append({"y_mm": float(y), "characteristic": {"u_mm": [0.0, u2, u2 + 0.03],
                                                               "p_MPa": [0.0, p, p + 300.0]}})
    return LayerTable({"body": body, "profile": "test"}, positions, source=f"{body} test table")


def test_layers_per_strip_residuals_and_deformed_profiles(rail60, s1002, placed, tmp_path):
    from meshes.profiles.io import read_profile, write_simpack, write_text

    rail_t = _table("rail", np.linspace(-36, 36, 13), np.linspace(500, 900, 13))
    wheel_t = _table("wheel", np.linspace(-60, 40, 11), np.full(11, 600.0))
    layers = LayerSources(rail=rail_t, wheel=wheel_t, names={"rail": "r", "wheel": "w"})
    inputs = WheelRailInputs(pose=WheelsetPose(6.0))
    sol = solve_wheel(rail60, s1002, inputs, layers, placed_rail=placed)
    p = sol.patches[0]
    assert abs(_vertical(sol) - inputs.vertical_load_N) / inputs.vertical_load_N < CONTINUOUS_BALANCE
    assert not p.normal.elastic and p.passes
    # the per-strip rail layer follows the table at the strip's rail coordinate
    on = p.normal.p_peak_MPa > 0
    res = residual_on_profiles(sol.patches)
    ys, up = res["rail"]
    assert up.max() > 0 and res["wheel"][1].max() > 0
    j = int(np.argmax(up))
    ch = rail_t.characteristic_at(ys[j])
    assert up[j] == pytest.approx(float(ch.residual_displacement(p.normal.p_peak_MPa[on].max())), rel=0.2)
    # deformed profiles: written in both formats and read back
    pts = deformed_profile(rail60, ys, up)
    dist, _ = rail60.signed_distance(pts)                 # moved into the rail (negative) by u_p along the normal
    assert -dist.min() == pytest.approx(up.max(), rel=1e-3)
    assert np.all(dist < 1e-9)
    for path, writer in ((tmp_path / "r.prr", lambda f: write_simpack(f, pts, body="rail")),
                         (tmp_path / "r.csv", lambda f: write_text(f, pts))):
        writer(path)
        back = read_profile(path) if path.suffix == ".prr" else read_profile(path, body="rail")
        assert np.max(np.abs(back.z(pts[:, 0]) - pts[:, 1])) < 1e-9


def test_combined_layer_is_softer(rail60, s1002, placed):
    inputs = WheelRailInputs(pose=WheelsetPose(2.0))
    elastic = solve_wheel(rail60, s1002, inputs, placed_rail=placed)
    soft = solve_wheel(rail60, s1002, inputs, LayerSources(combined=Characteristic.linear(2e4)), placed_rail=placed)
    assert soft.patches[0].normal.area_mm2 > elastic.patches[0].normal.area_mm2
    assert soft.patches[0].normal.p_max_MPa < elastic.patches[0].normal.p_max_MPa


def test_heavy_load_widens_the_layer(rail60, s1002, placed):
    # the virtual penetration exceeds the first layer cap (0.3 mm): solved again with a wider layer, still balanced
    soft = LayerSources(combined=Characteristic(np.array([0, 0.5, 3.0]), np.array([0, 200.0, 800.0])))
    inputs = WheelRailInputs(pose=WheelsetPose(3.0), load=WheelLoadSpec(vertical_load_N=150000.0),
                             method=WheelRailMethodSpec(normal="kik_piotrowski"))   # delta0: KP's virtual penetration
    sol = solve_wheel(rail60, s1002, inputs, soft, placed_rail=placed)
    p = sol.patches[0]
    assert p.normal.delta0_mm > 0.3
    assert abs(_vertical(sol) - 150000.0) / 150000.0 < CONTINUOUS_BALANCE


def test_patches_that_cannot_be_merged_are_a_clear_error(rail60, s1002, placed):
    # a very soft layer at 150 kN: the flange patch runs off its separation function even after merging candidates
    soft = LayerSources(combined=Characteristic(np.array([0, 0.01, 0.2]), np.array([0, 600.0, 1500.0])))
    with pytest.raises(PatchTruncated, match=r"wheel-rail case: a contact patch reaches the end of its separation "
                                         r"function .* even with candidates merged up to merge_mm = 0.5 mm"):
        solve_wheel(rail60, s1002, WheelRailInputs(pose=WheelsetPose(7.0), load=WheelLoadSpec(vertical_load_N=150000.0)), soft,
                    placed_rail=placed)


def test_patches_growing_into_each_other_are_merged_into_one(rail60, s1002, placed):
    # 100 kN at lateral 5 mm: tread and gauge-corner patches meet; solved as one patch with two regions
    sol = solve_wheel(rail60, s1002, WheelRailInputs(pose=WheelsetPose(5.0), load=WheelLoadSpec(vertical_load_N=100000.0)),
                      placed_rail=placed)
    assert sol.merge_mm > WheelRailInputs().search.merge_mm
    assert len(sol.patches) == 1 and len(sol.patches[0].normal.patches) == 2
    assert abs(_vertical(sol) - 100000.0) / 100000.0 < CONTINUOUS_BALANCE
    # at the default merge level the same case is two candidates whose patches run into the barrier
    assert solve_wheel(rail60, s1002, WheelRailInputs(pose=WheelsetPose(5.0), load=WheelLoadSpec(vertical_load_N=10000.0)),
                       placed_rail=placed).merge_mm == WheelRailInputs().search.merge_mm


def test_a_convergence_failure_names_the_case(rail60, s1002, placed):
    from wrlayer.errors import ConvergenceError

    # analytic profiles, 100 kN at 5.2 mm: the merged patch's regions merge and the KP force jumps past the target
    with pytest.raises(ConvergenceError, match=r"^my case: .*jumps across the target"):
        solve_wheel(rail60, s1002, WheelRailInputs(pose=WheelsetPose(5.2), load=WheelLoadSpec(vertical_load_N=100000.0)),
                    placed_rail=placed, case="my case")
