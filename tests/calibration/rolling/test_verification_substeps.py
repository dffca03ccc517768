"""Material sub-steps along the load's path (calibration.rolling.substeps): on a tiny 2D line contact above the
shakedown limit (p0 = 4.35 k) they bring a coarse step closer to the fine-step groove than plain steps of the
same length; a step that stays elastic is the same with and without them; bad sub-step counts are input errors."""

import numpy as np
import pytest

from calibration.fem.solver_state import SolverState
from calibration.rolling.config import ContactSettings, RollingConfig, RollingRunSettings, TrackMeshSettings, \
    TrackSettings
from calibration.rolling.passes import MovingLoadPass, roll
from calibration.rolling.run import build_model, level_pressures
from calibration.rolling.substeps import SubstepSolver, UnitResponses
from calibration.rolling.track_mesh import track_mesh
from wrlayer.errors import InputError


def config(level: float) -> RollingConfig:
    return RollingConfig(contact=ContactSettings(a_mm=1.0, levels=(level,), model="2d", level_unit="k"),
                         track=TrackSettings(length_factor=1.0, step_factor=0.5, n_passes=1, ramp_steps=2),
                         mesh=TrackMeshSettings(elements_per_semi_axis=3.0, size_factor=5.0),
                         run=RollingRunSettings(plots=False, linear_solver="scipy"))


@pytest.fixture(scope="module")
def block():
    cfg = config(4.35)
    model = build_model(cfg, track_mesh(cfg.contact, cfg.track, cfg.mesh))
    return cfg, model, UnitResponses(model.prob, model.forces)


def one_pass(block, p0: float, step: float, substeps: int):
    """(groove (mm), final state) of one pass at p0 (MPa) with steps of ``step`` a."""
    cfg, model, responses = block
    n = int(round(2.0 / step))
    positions = [-1.0 + 2.0 * i / n for i in range(n + 1)]
    solver = SubstepSolver(model.prob, model.forces, p0, substeps, responses=responses)
    state = [r for r in roll(solver, SolverState.virgin(model.disc), positions, 1, 2)
             if isinstance(r, MovingLoadPass)][0].state
    model.prob.reset_to_elastic()
    return model.probe.profile(state).groove_mm, state


def test_substeps_converge_faster_than_plain_steps(block):
    cfg, model, _ = block
    p0 = level_pressures(cfg, model.p_y_MPa)[0]
    fine, _ = one_pass(block, p0, 1 / 16, 1)
    plain, _ = one_pass(block, p0, 1 / 2, 1)
    sub, _ = one_pass(block, p0, 1 / 2, 4)
    assert plain < fine  # the plain step cuts the stress path short: too little plastic flow
    assert abs(sub - fine) < 0.5 * abs(plain - fine)


def test_elastic_step_is_the_same_with_substeps(block):
    cfg, model, _ = block
    _, plain = one_pass(block, 0.9 * model.p_y_MPa, 1 / 2, 1)
    _, sub = one_pass(block, 0.9 * model.p_y_MPa, 1 / 2, 4)
    assert not plain.eq_plastic_strain.any() and not sub.eq_plastic_strain.any()
    assert np.allclose(sub.u_mm, plain.u_mm, rtol=0, atol=1e-9 * np.abs(plain.u_mm).max() + 1e-15)


@pytest.mark.parametrize("bad", [0, 65, 2.5])
def test_bad_substeps_are_input_errors(block, bad):
    _, model, _ = block
    with pytest.raises(InputError, match="substeps"):
        SubstepSolver(model.prob, model.forces, 1000.0, bad)
