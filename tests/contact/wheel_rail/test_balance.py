"""The wheel's vertical balance with the tangential forces (Manchester A-2.2 definition), the reported approach and
the contact reference point (units mm, N, rad)."""

import math

import numpy as np
import pytest

from contact.wheel_rail.kinematics import creepages
from contact.wheel_rail.reference_point import weighted_centre_eta
from contact.scenes.sections import PassesSpec, TangentialSpec
from contact.wheel_rail.inputs import WheelRailInputs
from contact.wheel_rail.sections import WheelLoadSpec, WheelRailMethodSpec
from contact.wheel_rail.solve import solve_wheel
from contact.wheel_rail.track_geometry import WheelsetPose, axle_direction

Q = 10000.0


def _solve(rail, wheel, placed, lateral, side="right", yaw=0.0, friction=0.3, **method):
    """The wheel's solution with the [method] keys ``method``."""
    pose = WheelsetPose(lateral, yaw, 0.0)
    inputs = WheelRailInputs(pose=pose, side=side, load=WheelLoadSpec(vertical_load_N=Q),
                             tangential=TangentialSpec(friction), method=WheelRailMethodSpec(**method))
    return solve_wheel(rail, wheel, inputs, placed_rail=placed)


def _normal_vertical(sol):
    return sum(p.normal_force_N * math.cos(p.candidate.contact_angle_rad) for p in sol.patches)


@pytest.mark.parametrize("side", ["right", "left"])
@pytest.mark.parametrize("lateral, n_patches", [(0.5, 1), (5.2, 2), (7.0, 1)])
@pytest.mark.parametrize("point", ["first_contact", "weighted_centre"])
def test_vertical_component_of_the_total_contact_force_equals_the_load(rail60, s1002, placed, side, lateral,
                                                                      n_patches, point):
    d = lateral if side == "right" else -lateral          # the flange of the wheel named by ``side`` approaches
    sol = _solve(rail60, s1002, placed, d, side=side, yaw=0.012 * np.sign(d), contact_point=point)
    assert len(sol.patches) == n_patches
    total = sum(p.force_track_N() for p in sol.patches)
    assert abs(total[2] - Q) / Q < 1e-6
    assert sol.vertical_balance_rel < 1e-6
    assert sol.vertical_force_N == pytest.approx(total[2], rel=1e-12)
    # the tangential forces matter: the normal forces alone do not carry Q (on the flange by far)
    off = abs(_normal_vertical(sol) - Q) / Q
    assert off > (0.2 if lateral == 7.0 else 1e-3)


def test_normal_only_balance_is_still_available_and_differs(rail60, s1002, placed):
    old = _solve(rail60, s1002, placed, 7.0, yaw=0.0168, balance="normal")
    new = _solve(rail60, s1002, placed, 7.0, yaw=0.0168)
    assert _normal_vertical(old) == pytest.approx(Q, rel=1e-6)
    assert old.vertical_force_N > 1.2 * Q                  # the 13-15 kN on the flange
    assert new.patches[0].normal_force_N < 0.85 * old.patches[0].normal_force_N


@pytest.mark.parametrize("lateral", [0.0, 3.0, 5.2, 8.0])
def test_approach_is_reported_for_every_case(rail60, s1002, placed, lateral):
    sol = _solve(rail60, s1002, placed, lateral)
    assert sol.approach_mm > 0.005
    for p in sol.patches:
        c = p.candidate
        assert p.normal.delta_mm == pytest.approx(sol.approach_mm * math.cos(c.contact_angle_rad) - c.normal_gap_mm,
                                                  rel=1e-6, abs=1e-9)


def test_weighted_centre_is_the_depth_squared_weighted_centre_of_the_interpenetration(rail60, s1002, placed):
    sol = _solve(rail60, s1002, placed, 0.0)
    c, delta = sol.patches[0].candidate, sol.patches[0].normal.delta_mm
    R = c.rolling_radius_kp_mm
    # brute force over (x, eta): h = delta - f(eta) - x^2 / (2 R) > 0
    eta = np.linspace(c.eta_mm[0], c.eta_mm[-1], 4001)
    f = np.interp(eta, c.eta_mm, c.f_mm - c.f_mm.min())
    x = np.linspace(-15.0, 15.0, 3001)
    h = np.maximum(delta - f[:, None] - x[None, :] ** 2 / (2 * R), 0.0)
    ref = float(np.sum(eta[:, None] * h ** 2) / np.sum(h ** 2))      # depth^2 weighting over the area
    assert weighted_centre_eta(c, delta) == pytest.approx(ref, abs=2e-3)


def test_creepages_and_spin_are_evaluated_at_the_chosen_point(rail60, s1002, placed):
    sols = {k: _solve(rail60, s1002, placed, 0.0, contact_point=k) for k in ("first_contact", "weighted_centre")}
    wc = sols["weighted_centre"].patches[0]
    fc = sols["first_contact"].patches[0]
    assert abs(wc.reference.eta_mm) > 0.3                  # the two points differ on this tread contact
    assert fc.reference.eta_mm == 0.0
    for sol in sols.values():
        p = sol.patches[0]
        inp = sol.inputs
        centre = np.array([0.0, inp.pose.lateral_mm, sol.search.wheel_height_mm])
        kin = creepages(p.point_track, p.normal_track, centre, axle_direction(inp.pose), inp.speed_mm_s,
                        inp.omega_rad_s)
        assert (p.kinematics.vx, p.kinematics.vy, p.kinematics.phi_per_mm) == pytest.approx(
            (kin.vx, kin.vy, kin.phi_per_mm), abs=1e-15)
        # FASTSIM's strips are about the reference point
        assert p.tangential[0].y_mm == pytest.approx(p.normal.patches[0].y_mm - p.strip_sign * p.reference.eta_mm)
    # a conical tread: the longitudinal creepage follows the rolling radius at the point
    assert wc.kinematics.vx != pytest.approx(fc.kinematics.vx, abs=1e-6)


def test_flange_climbing_limit_is_a_convergence_error(rail60, s1002, placed):
    from wrlayer.errors import ConvergenceError

    with pytest.raises(ConvergenceError, match="flange climbing limit"):
        _solve(rail60, s1002, placed, 7.0, yaw=0.0168, friction=0.5)


def _exact_available() -> bool:
    from contact.normal.kik_piotrowski import NormalProblem
    from contact.normal.method import NormalMethod, solve_normal_with
    from wrlayer.errors import InputError

    y = np.linspace(-5.0, 5.0, 101)
    prob = NormalProblem(y, y ** 2 / 60.0, 5000.0, 460.0, 210000.0, 0.28, grid_mm=0.2)
    try:
        solve_normal_with(prob, method=NormalMethod("exact"))
    except InputError as err:
        if "not available" in str(err):
            return False
        raise
    return True


@pytest.mark.skipif(not _exact_available(), reason="method.normal = 'exact' raises 'not available in this build' "
                    "until the exact half-space solver lands on main")
@pytest.mark.parametrize("lateral, n_patches", [(0.5, 1), (5.2, 2), (7.0, 1)])
def test_balance_and_approach_with_the_exact_normal_solver(rail60, s1002, placed, lateral, n_patches):
    sol = _solve(rail60, s1002, placed, lateral, normal="exact",
                 contact_point="weighted_centre")
    assert len(sol.patches) == n_patches
    assert abs(sol.vertical_force_N - Q) / Q < 1e-6
    for p in sol.patches:
        c = p.candidate
        assert p.normal.delta_mm == pytest.approx(sol.approach_mm * math.cos(c.contact_angle_rad) - c.normal_gap_mm,
                                                  rel=1e-5, abs=1e-8)


def test_weighted_centre_plane_is_the_weighted_mean_angle_and_carries_the_forces(rail60, s1002, placed):
    sol = _solve(rail60, s1002, placed, 0.5, contact_point="weighted_centre", normal="kik_piotrowski")  # to 1e-9
    p = sol.patches[0]
    c, delta = p.candidate, p.normal.delta_mm
    eta = np.linspace(c.eta_mm[0], c.eta_mm[-1], 4001)
    f = np.interp(eta, c.eta_mm, c.f_mm - c.f_mm.min())
    g = np.maximum(delta - f, 0.0)
    q = c.rail_coordinate(eta)
    n2 = placed.normal(q)
    gamma = np.arctan2(-n2[:, 0], n2[:, 1])
    expected = float(np.sum(gamma * g ** 2.5) / np.sum(g ** 2.5))
    assert p.reference.angle_rad == pytest.approx(expected, abs=2e-4)
    assert abs(p.reference.angle_rad - c.contact_angle_rad) > 1e-3       # differs from the first-contact plane
    assert p.normal_track[2] == pytest.approx(math.cos(p.reference.angle_rad), abs=1e-12)
    # the balance uses that plane: N cos(gamma_ref) + Fs sin(gamma_ref) = Q
    assert (p.normal_force_N * math.cos(p.reference.angle_rad) + p.Fy_N * math.sin(p.reference.angle_rad)
            == pytest.approx(Q, rel=1e-9))


@pytest.mark.skipif(not _exact_available(), reason="method.normal = 'exact' raises 'not available in this build' "
                    "until the exact half-space solver lands on main")
def test_close_patches_merged_and_solved_on_one_exact_grid(rail60, s1002, placed):
    pose = WheelsetPose(5.0)
    sol = solve_wheel(rail60, s1002, WheelRailInputs(pose=pose, load=WheelLoadSpec(vertical_load_N=100000.0),
                                                     method=WheelRailMethodSpec(normal="exact")), placed_rail=placed)
    assert sol.merge_mm > WheelRailInputs().search.merge_mm
    assert len(sol.patches) == 1 and len(sol.patches[0].normal.patches) == 2
    assert abs(sol.vertical_force_N - 100000.0) / 100000.0 < 1e-6


@pytest.mark.parametrize("method", ["kik_piotrowski", "exact", "coarse_exact"])
def test_layered_wheel_with_either_normal_method(rail60, s1002, placed, method):
    from wrlayer.characteristic import Characteristic
    from contact.scenes.layers import LayerSources

    layers = LayerSources(combined=Characteristic(np.array([0, 0.01, 0.05]), np.array([0, 300.0, 900.0])))
    sol = solve_wheel(rail60, s1002, WheelRailInputs(pose=WheelsetPose(2.0), method=WheelRailMethodSpec(normal=method)),
                      layers, placed_rail=placed)
    p = sol.patches[0]
    assert not p.normal.elastic and p.passes and p.passes[0].max_residual_mm > 0
    assert abs(sol.vertical_force_N - Q) / Q < 1e-6


def test_every_pass_is_kept(rail60, s1002, placed):
    from wrlayer.characteristic import Characteristic
    from contact.scenes.layers import LayerSources

    layers = LayerSources(combined=Characteristic(np.array([0, 0.01, 0.05]), np.array([0, 300.0, 900.0])))
    sol = solve_wheel(rail60, s1002, WheelRailInputs(pose=WheelsetPose(2.0), passes=PassesSpec(max=3)),
                      layers, placed_rail=placed)
    p = sol.patches[0]
    assert len(p.pass_normals) == len(p.passes) == 3


def assert_same_patch(warm, cold, force_rel: float, creep_abs: float, p_max_rel: float) -> None:
    """A warm-started balance's patch against the cold one: normal force (relative), creep forces F_x, F_y
    (absolute, in units of mu N = 0.3 N) and p_max (relative)."""
    scale = 0.3 * cold.normal_force_N
    assert warm.normal_force_N == pytest.approx(cold.normal_force_N, rel=force_rel)
    for key in ("Fx_N", "Fy_N"):
        assert sum(getattr(t, key) for t in warm.tangential) == pytest.approx(
            sum(getattr(t, key) for t in cold.tangential), abs=creep_abs * scale)
    assert warm.normal.p_max_MPa == pytest.approx(cold.normal.p_max_MPa, rel=p_max_rel)


def test_warm_started_exact_balance_gives_the_cold_forces(rail60, s1002, placed, monkeypatch):
    """The exact/exact balance with its warm starts and rough first point gives the forces of cold solves to full
    tolerance everywhere, within the solvers' tolerances."""
    from contact.wheel_rail import balance

    inputs = WheelRailInputs(pose=WheelsetPose(2.0, yaw_rad=0.002),
                             method=WheelRailMethodSpec(normal="exact", tangential="exact"))
    warm = solve_wheel(rail60, s1002, inputs, placed_rail=placed).patches[0]
    monkeypatch.setattr(balance.BalanceCandidate, "normal_start",
                        lambda self, method, rough=False: {"delta_guess_mm": self.delta_guess})
    cold = solve_wheel(rail60, s1002, inputs, placed_rail=placed).patches[0]
    assert_same_patch(warm, cold, force_rel=1e-7, creep_abs=1e-5, p_max_rel=1e-4)


def test_warm_started_coarse_and_fastrip_balance(rail60, s1002, placed, monkeypatch):
    """coarse_exact/fastrip: the balance's solves start from the candidate's last (the coarse grid kept, FaStrip's
    strips from their tractions; both counted) and give the cold solves' forces within the coarse grid's
    discretisation (the kept grid differs from a cold fit by a fraction of a cell)."""
    from contact.normal import coarse_exact
    from contact.tangential import fastrip
    from contact.wheel_rail import balance

    used = {"grid": 0, "strips": 0}
    start_for, solve = coarse_exact.CoarseWarmStart.start_for, fastrip.solve_fastrip

    def counted_start(self, *args):
        out = start_for(self, *args)
        used["grid"] += out is not None
        return out

    def counted_solve(*args, start=None, **kw):
        used["strips"] += start is not None
        return solve(*args, start=start, **kw)

    monkeypatch.setattr(coarse_exact.CoarseWarmStart, "start_for", counted_start)
    monkeypatch.setattr("contact.tangential.method.solve_fastrip", counted_solve)
    inputs = WheelRailInputs(pose=WheelsetPose(2.0, yaw_rad=0.002),
                             method=WheelRailMethodSpec(normal="coarse_exact", tangential="fastrip"))
    warm = solve_wheel(rail60, s1002, inputs, placed_rail=placed).patches[0]
    assert used["grid"] >= 2 and used["strips"] >= 2
    monkeypatch.setattr(balance.BalanceCandidate, "normal_start",
                        lambda self, method, rough=False: {"delta_guess_mm": self.delta_guess})
    tangential = balance.patch_tangential
    monkeypatch.setattr(balance, "patch_tangential", lambda *args: tangential(*args[:4]))
    cold = solve_wheel(rail60, s1002, inputs, placed_rail=placed).patches[0]
    assert_same_patch(warm, cold, force_rel=1e-4, creep_abs=2e-3, p_max_rel=5e-3)


def test_rail_angles_are_evaluated_once_per_candidate(rail60, s1002, placed, monkeypatch):
    """The weighted centre's angle reads the rail's local angles of a candidate from its kept table: the same
    numbers as evaluating the rail's normals at every load, and the rail evaluated once per candidate."""
    from contact.wheel_rail import reference_point as rp

    sol = _solve(rail60, s1002, placed, 0.5, contact_point="weighted_centre", normal="kik_piotrowski")
    c, delta = sol.patches[0].candidate, sol.patches[0].normal.delta_mm
    n2 = placed.normal(c.rail_coordinate(c.eta_mm))
    gamma = np.arctan2(-n2[:, 0], n2[:, 1])
    w = np.maximum(delta - (c.f_mm - c.f_mm.min()), 0.0) ** 2.5
    assert rp.weighted_angle(c, delta, placed) == float(np.sum(gamma * w) / w.sum())   # bit for bit
    calls = []
    monkeypatch.setattr(rp, "_RAIL_ANGLES", [])
    real = type(placed).normal
    monkeypatch.setattr(type(placed), "normal", lambda self, q: calls.append(1) or real(self, q))
    first = [rp.weighted_angle(c, d, placed) for d in (0.5 * delta, delta, 1.5 * delta)]
    assert len(calls) == 1 and first[1] == rp.weighted_angle(c, delta, placed)
    assert np.array_equal(rp.rail_angles(c, placed), gamma)


def test_balance_tolerance_per_normal_method():
    """The coarse-grid solver's balance stops at 5e-7 Q (above the jumps of its force where a solve refits its grid),
    the others at 1e-8 Q; both below the accepted 1e-5 (a jump of F_Z across Q)."""
    from contact.wheel_rail.balance import JUMP_BALANCE_RTOL, balance_rtol
    from contact.wheel_rail.solve import BALANCE_RTOL

    assert balance_rtol("coarse_exact") == 5e-7 < BALANCE_RTOL == JUMP_BALANCE_RTOL == 1e-5
    assert balance_rtol("exact") == balance_rtol("kik_piotrowski") == 1e-8
