"""Several contact regions in the Kik–Piotrowski solver: elastic interaction, local virtual penetration, lift-off.

Geometry: a main valley y^2/(2*25) and a second valley (y - 12)^2/(2*40) + level (mm), N = 60 kN, R = 460 mm.
"""

import dataclasses

import numpy as np
import pytest

import contact.normal.regions as kp
from contact.normal.boussinesq import boussinesq_integral
from contact.normal.kik_piotrowski import NormalForceEvaluator, NormalProblem, solve_normal
from contact.scenes.paper_example import paper_layers, paper_problem
from wrlayer.errors import ConvergenceError

E, NU, N, R = 2.1e5, 0.3, 6e4, 460.0
Y = np.linspace(-8.0, 20.0, 1401)


def two_valleys(level, interaction=True, **kw):
    f = np.minimum(Y ** 2 / 50.0, (Y - 12.0) ** 2 / 80.0 + level)
    return NormalProblem(Y, f, kw.pop("n", N), R, E, NU, region_interaction=interaction, **kw)


def by_y(sol):
    return sorted(sol.regions, key=lambda r: sol.strip_y_mm[r.reference])


@pytest.fixture(scope="module")
def main_only():
    return solve_normal(two_valleys(1.0))                # second valley far above: one region


def test_single_region_is_unchanged_by_the_option():
    prob = paper_problem()
    for layers in (None, paper_layers(prob)):
        new = solve_normal(prob, layers)
        old = solve_normal(dataclasses.replace(prob, region_interaction=False), layers)
        assert new.delta_mm == old.delta_mm and new.p_max_MPa == old.p_max_MPa
        np.testing.assert_array_equal(new.p_peak_MPa, old.p_peak_MPa)
        assert new.regions[0].interaction_mm == 0.0 and new.regions[0].approach_mm == new.delta_mm


def test_contact_conditions_with_interaction_hold_at_every_reference_point():
    """delta - f(y_j) = u_layer_j + sum_k C_jk p0_k, C_jk from the Boussinesq integral of region k about y_j."""
    prob = two_valleys(0.03)
    sol = solve_normal(prob, paper_layers(prob))
    assert len(sol.regions) == 2
    f = prob.separation_on_grid_mm
    c = prob.elastic_compliance_factor
    for j in sol.regions:
        total = j.u_layer_mm
        for k in sol.regions:
            xl0 = k.x_lead_mm[np.flatnonzero(k.strips == k.reference)[0]]
            total += c * boussinesq_integral(k.x_lead_mm, k.strips - j.reference, prob.grid_mm) / xl0 * k.p0_MPa
        assert total == pytest.approx(sol.delta_mm - f[j.reference], rel=1e-11)
        # the region's virtual penetration is alpha times its local approach at its reference strip
        xl0 = j.x_lead_mm[np.flatnonzero(j.strips == j.reference)[0]]
        assert xl0 ** 2 / (2 * R) == pytest.approx(prob.alpha * j.approach_mm, rel=1e-12)
        assert j.approach_mm + j.interaction_mm == pytest.approx(sol.delta_mm - f[j.reference], rel=1e-12)
    assert sum(r.normal_force_N for r in sol.regions) == pytest.approx(N, rel=1e-9)


def test_two_equal_valleys_share_the_load_and_raise_the_approach_by_the_interaction():
    y = np.linspace(-15, 15, 601)
    f = np.minimum((y + 6) ** 2 / 60.0, (y - 6) ** 2 / 60.0)
    sol = solve_normal(NormalProblem(y, f, N, R, E, NU))
    a, b = by_y(sol)
    assert a.normal_force_N == pytest.approx(N / 2, rel=1e-9) and b.p0_MPa == pytest.approx(a.p0_MPa, rel=1e-9)
    alone = solve_normal(NormalProblem(y, (y + 6) ** 2 / 60.0, N / 2, R, E, NU))
    assert a.interaction_mm > 0.01 * sol.delta_mm
    assert sol.delta_mm == pytest.approx(alone.delta_mm + a.interaction_mm, rel=1e-8)
    np.testing.assert_allclose(a.x_lead_mm, alone.regions[0].x_lead_mm, rtol=1e-8)
    old = solve_normal(NormalProblem(y, f, N, R, E, NU, region_interaction=False))
    assert old.delta_mm == pytest.approx(alone.delta_mm, rel=1e-8)          # independent regions: no interaction


def test_no_jump_when_the_second_valley_crosses_the_virtual_penetration(main_only):
    """Old solver: the second region appears at level = delta_0 with a finite load (p_0 of tens of GPa)."""
    d0 = main_only.delta0_mm
    below, above = (solve_normal(two_valleys(s * d0)) for s in (0.999, 1.001))
    fb, fa = (by_y(s)[1].normal_force_N for s in (below, above))
    assert abs(fb - fa) < 0.01 * N and fa > 0.05 * N
    assert abs(below.p_max_MPa - above.p_max_MPa) < 5.0
    for s in (below, above):
        assert s.p_max_MPa == pytest.approx(by_y(s)[0].p0_MPa)
    old = solve_normal(two_valleys(0.99 * d0, interaction=False))
    assert old.p_max_MPa > 10 * main_only.p_max_MPa                        # the discontinuity that was fixed


def test_second_region_load_goes_continuously_to_zero_at_lift_off(main_only):
    """Lift-off where the deformed surfaces separate: level* = delta - w(y = 12 mm) of the main region alone."""
    ev = NormalForceEvaluator(two_valleys(1.0), None)
    ev.force_at(main_only.delta_mm)
    region = ev.last[2][0]
    ref12 = int(np.flatnonzero(np.isclose(ev.y, 12.0))[0])
    level_star = main_only.delta_mm - ev.displacement_at(region, ref12)
    forces, pmax = [], []
    for eps in (3e-4, 1e-4, 3e-5, 1e-5):
        sol = solve_normal(two_valleys(level_star - eps))
        assert len(sol.regions) == 2
        second = by_y(sol)[1]
        forces.append(second.normal_force_N)
        pmax.append(sol.p_max_MPa)
        assert sol.p_max_MPa == pytest.approx(by_y(sol)[0].p0_MPa, rel=1e-12)
        assert sol.p_max_MPa > 5 * second.p0_MPa
    assert np.all(np.diff(forces) < 0) and forces[-1] < 2e-4 * N                # ~ eps^1.5 -> 0
    after = solve_normal(two_valleys(level_star + 1e-5))
    assert len(after.regions) == 1 and after.p_max_MPa == pytest.approx(main_only.p_max_MPa, rel=1e-12)
    assert pmax[-1] == pytest.approx(main_only.p_max_MPa, rel=1e-4)


def test_force_is_continuous_in_delta_across_lift_off():
    ev = NormalForceEvaluator(two_valleys(0.07), None)
    deltas = np.linspace(0.06, 0.11, 200)
    n = np.array([ev.force_at(d) for d in deltas])
    ev.force_at(0.06)
    assert len(ev.last[2]) == 1
    ev.force_at(0.11)
    assert len(ev.last[2]) == 2                                    # the second valley came into contact
    assert np.all(np.diff(n) > 0)
    step = np.diff(n) / n[1:]
    assert step.max() < 3 * np.median(step)                       # no jump: increments stay of one size


def test_cycling_interaction_raises_convergence_error(monkeypatch):
    monkeypatch.setattr(kp, "_MAX_INTERACTION_ITERATIONS", 1)
    with pytest.raises(ConvergenceError, match="interaction between regions"):
        solve_normal(two_valleys(0.03))


def test_candidate_reference_points_are_the_local_minima_of_f():
    f = np.array([3.0, 2.0, 2.0, 3.0, 1.0, 1.0, 1.0, 4.0, 0.0])
    np.testing.assert_array_equal(kp._local_minima(f), [8, 4, 1])          # ascending f, flat bottom: first strip
    assert not kp._single_valley(f)
    assert kp._single_valley(np.array([2.0, 1.0, 1.0, 0.0, 0.0, 3.0])) and kp._single_valley(np.array([1.0, 2.0]))


def test_a_valley_next_to_a_clipped_region_gets_its_own_strips():
    """Regression (stress seed 89): region r, clipped at the ridge, starts right next to a later candidate m."""
    f = np.array([2.5, 1.6, 0.9, 0.4, 0.1, 0.0, 0.1, 0.4, 0.7, 0.9, 0.95, 1.0, 1.0, 0.9, 1.2,
                  1.0, 0.8, 0.5, 0.3, 0.15, 0.1, 0.15, 0.3, 0.5, 0.8, 1.2, 1.6, 2.0, 2.5, 3.0, 3.5])
    prob = NormalProblem(np.arange(f.size) * 0.1, f, N, R, E, NU)
    ev = NormalForceEvaluator(prob, None)
    cand = [int(m) for m in ev.minima]
    assert cand == [5, 20, 13]
    w = np.array([2.0, 0.0, 0.0])                       # valley 5 pushed away by a large displacement
    runs = ev._local_penetrations(3.0, cand, w)
    strips = [r[0] for r in runs]
    assert [r[2] for r in runs] == [5, 13, 20]
    np.testing.assert_array_equal(strips[1], [11, 12, 13])   # from the ridge (first max) to the next region
    assert strips[2][0] == 14 and strips[0][-1] < 11     # region 20 was clipped at the ridge 14, next to 13
    assert all(np.all(r[1] > 0) for r in runs)
