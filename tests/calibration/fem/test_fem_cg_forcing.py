"""The inner CG tolerances of the Newton iterations (calibration.fem.newton.cg_tolerance): the 'mismatch' forcing
(Eisenstat-Walker choice 1) with the Newton-tolerance floor converges to the same state as the quadratic 'adaptive'
forcing without the floor (the plain iteration) in fewer triangular solves, counted on a small rolling pass with
material sub-steps (inexact tangent: Newton converges linearly); the tolerance formulas themselves."""

import dataclasses

import numpy as np
import pytest

from calibration.fem.newton import cg_tolerance
from calibration.fem.solver_state import SolverOptions, SolverState
from calibration.rolling.config import ContactSettings, RollingConfig, RollingRunSettings, TrackMeshSettings, \
    TrackSettings
from calibration.rolling.passes import MovingLoadPass, roll
from calibration.rolling.run import build_model, level_pressures
from calibration.rolling.substeps import SubstepSolver, UnitResponses
from calibration.rolling.track_mesh import track_mesh

PLAIN = dict(cg_forcing="adaptive", cg_target_fraction=0.0)
#: tight tolerances, so that two converged passes are compared, not two stopping points
TIGHT = dict(rtol=1e-10, etol=1e-14)


@pytest.fixture(scope="module")
def line_contact():
    """A 2D line contact above the shakedown limit (p0 = 4.35 k), steps of a/4 with 4 sub-steps (1,394 dofs)."""
    cfg = RollingConfig(contact=ContactSettings(a_mm=1.0, levels=(4.35,), model="2d", level_unit="k"),
                        track=TrackSettings(length_factor=1.0, step_factor=0.25, n_passes=1, ramp_steps=2),
                        mesh=TrackMeshSettings(elements_per_semi_axis=3.0, size_factor=5.0),
                        run=RollingRunSettings(plots=False, linear_solver="scipy"))
    model = build_model(cfg, track_mesh(cfg.contact, cfg.track, cfg.mesh))
    responses = UnitResponses(model.prob, model.forces)
    p0 = level_pressures(cfg, model.p_y_MPa)[0]
    positions = [-1.0 + 0.25 * i for i in range(9)]
    for x in positions:  # the kept unit responses first, so that the passes count their own solves only
        responses(x)
    return model, responses, p0, positions


def one_pass(line_contact, **options):
    """(final state, Newton iterations, triangular solves) of one pass with ``options``."""
    model, responses, p0, positions = line_contact
    model.prob.opts = dataclasses.replace(model.opts, **TIGHT, **options)
    model.prob.opts.validate()
    solver = SubstepSolver(model.prob, model.forces, p0, 4, responses=responses)
    before = model.prob.factor.n_solves
    done = [r for r in roll(solver, SolverState.virgin(model.disc), positions, 1, 2) if isinstance(r, MovingLoadPass)]
    model.prob.reset_to_elastic()
    return done[0].state, done[0].newton_iters, model.prob.factor.n_solves - before


def test_mismatch_forcing_gives_the_plain_pass_in_fewer_solves(line_contact):
    plain, plain_newton, plain_solves = one_pass(line_contact, **PLAIN)
    fast, fast_newton, fast_solves = one_pass(line_contact)
    assert fast_solves < 0.9 * plain_solves  # measured: 634 against 807
    assert fast_newton <= 1.1 * plain_newton
    peq = plain.eq_plastic_strain
    assert peq.max() > 0  # a plastic pass
    assert np.abs(fast.u_mm - plain.u_mm).max() <= 1e-8 * np.abs(plain.u_mm).max()
    assert np.abs(fast.eq_plastic_strain - peq).max() <= 1e-8 * peq.max()
    model = line_contact[0]
    assert model.probe.profile(fast).groove_mm == pytest.approx(model.probe.profile(plain).groove_mm, rel=1e-8)


def test_cg_tolerance_formulas():
    opts = SolverOptions(rtol=1e-6)
    # first iteration: the loosest tolerance
    assert cg_tolerance(opts, 0, 1e-2, [1e-2]) == opts.cg_rtol_max
    # a residual 10x smaller than the last, the linear model far off (inexact tangent): the mismatch, 0.1 - 1e-4
    assert cg_tolerance(opts, 1, 1e-3, [1e-2, 1e-3], linear=1e-6) == pytest.approx(0.0999)
    # ... where choice 2 asks for 0.9 (1e-3 / 1e-2)^2 = 9e-3
    adaptive = dataclasses.replace(opts, cg_forcing="adaptive")
    assert cg_tolerance(adaptive, 1, 1e-3, [1e-2, 1e-3], linear=1e-6) == pytest.approx(9e-3)
    # the linear model right (exact tangent): as tight as allowed
    assert cg_tolerance(opts, 1, 1e-3, [1e-2, 1e-3], linear=1e-3) == opts.cg_rtol
    # two times the Newton tolerance: no tighter than 0.3 rtol / |r| = 0.15 (capped at cg_rtol_max)
    assert cg_tolerance(opts, 2, 2e-6, [1e-3, 2e-6], linear=2e-6) == opts.cg_rtol_max
    assert cg_tolerance(opts, 2, 6e-6, [1e-3, 6e-6], linear=6e-6) == pytest.approx(0.05)
    no_floor = dataclasses.replace(opts, cg_target_fraction=0.0)
    assert cg_tolerance(no_floor, 2, 6e-6, [1e-3, 6e-6], linear=6e-6) == opts.cg_rtol
    # no linear residual known (a direct solve): choice 2
    assert cg_tolerance(no_floor, 1, 1e-3, [1e-2, 1e-3]) == pytest.approx(9e-3)
    fixed = dataclasses.replace(opts, cg_forcing="fixed")
    assert cg_tolerance(fixed, 3, 1e-3, [1e-2, 1e-3], linear=1e-6) == opts.cg_rtol
