"""2D plane-strain line contact, frictionless, elastic-perfectly plastic (Bhargava, Hahn & Wert 1985; Johnson's
shakedown limit p0 = 4 k): below it (3.5 k) the net plastic strain change of a pass dies out after the first
pass (shakedown); above it (5.0 k) every pass adds about the same net plastic strain (ratcheting). A tiny block,
with material sub-steps (calibration.rolling.substeps)."""

import numpy as np
import pytest

from calibration.fem.solver_state import SolverState
from calibration.rolling.config import ContactSettings, RollingConfig, RollingRunSettings, TrackMeshSettings, \
    TrackSettings
from calibration.rolling.passes import MovingLoadPass, roll
from calibration.rolling.run import build_model, level_pressures
from calibration.rolling.substeps import SubstepSolver, UnitResponses
from calibration.rolling.track_mesh import track_mesh


@pytest.fixture(scope="module")
def net_increments():
    """{p0 / k: the largest net plastic strain change below |x| <= a of passes 1..3 (-)}."""
    cfg = RollingConfig(contact=ContactSettings(a_mm=1.0, levels=(3.5, 5.0), model="2d", level_unit="k"),
                        track=TrackSettings(length_factor=1.0, step_factor=0.5, n_passes=3, ramp_steps=2),
                        mesh=TrackMeshSettings(elements_per_semi_axis=3.0, size_factor=8.0),
                        run=RollingRunSettings(plots=False, linear_solver="scipy"))
    model = build_model(cfg, track_mesh(cfg.contact, cfg.track, cfg.mesh))
    responses = UnitResponses(model.prob, model.forces)
    out = {}
    for level, p0 in zip(cfg.contact.levels, level_pressures(cfg, model.p_y_MPa)):
        solver = SubstepSolver(model.prob, model.forces, p0, 2, responses=responses)
        previous = np.zeros((np.count_nonzero(model.probe.below), 6))
        incs = []
        for rec in roll(solver, SolverState.virgin(model.disc), [-1.0, -0.5, 0.0, 0.5, 1.0], 3, 2):
            if isinstance(rec, MovingLoadPass):
                now = rec.state.plastic_strain[model.probe.below]
                incs.append(float(np.sqrt(2.0 / 3.0 * ((now - previous) ** 2).sum(axis=-1)).max()))
                previous = now
        model.prob.reset_to_elastic()
        out[level] = incs
    return out


def test_shakedown_below_the_limit(net_increments):
    first, second, third = net_increments[3.5]
    assert first > 1e-4                      # it yields in the first pass (p_y about 3 k) ...
    assert second < 0.2 * first and third < 0.2 * second  # ... and the change dies out pass by pass: shakedown


def test_ratcheting_above_the_limit(net_increments):
    first, second, third = net_increments[5.0]
    assert second > 0.2 * first and third > 0.6 * second  # a net plastic strain change every pass, nearly
    assert third > 100 * net_increments[3.5][2]           # steady: ratcheting
