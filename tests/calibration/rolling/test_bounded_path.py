"""The sub-stepped rolling material evaluated only where it can be plastic (calibration.fem.bounded_material, from
calibration.rolling.substeps): on a tiny 2D line contact above the shakedown limit, an iterate near the reference is
return-mapped on a small part of the block and gives the same internal forces, plastic points, tangent and
converged result as the evaluation at every point; an iterate far from it is evaluated everywhere; a pass gives the
same groove with and without the bound."""

import numpy as np
import pytest

from calibration.fem import bounded_material
from calibration.fem.return_mapping import tangent_of_elements
from calibration.fem.solver_state import SolverState
from calibration.rolling.passes import MovingLoadPass, Target, roll
from calibration.rolling.run import build_model, level_pressures
from calibration.rolling.substeps import SubstepSolver, UnitResponses
from calibration.rolling.track_mesh import track_mesh
from tests.calibration.rolling.test_verification_substeps import config


@pytest.fixture(scope="module")
def loaded():
    """(model, solver, a plastic state under the load at x = -0.5 mm, the next step's targets)."""
    cfg = config(4.35)
    model = build_model(cfg, track_mesh(cfg.contact, cfg.track, cfg.mesh))
    p0 = level_pressures(cfg, model.p_y_MPa)[0]
    solver = SubstepSolver(model.prob, model.forces, p0, 4, responses=UnitResponses(model.prob, model.forces))
    state = SolverState.virgin(model.disc)
    for a, b in [(Target(-1.0, 0.0), Target(-1.0, 0.5)), (Target(-1.0, 0.5), Target(-1.0, 1.0)),
                 (Target(-1.0, 1.0), Target(-0.5, 1.0))]:
        state, _ = solver.step(state, a, b)
    assert state.eq_plastic_strain.any()
    return model, solver, state, Target(-0.5, 1.0), Target(0.0, 1.0)


def test_restricted_iterate_is_the_full_one(loaded):
    model, solver, state, a, b = loaded
    u0, _, path = solver.start(state, a, b)
    path(u0)  # the reference: every point
    rng = np.random.default_rng(1)
    u = u0 + 1e-3 * np.abs(u0).max() * rng.standard_normal(u0.size) * ~model.prob.fixed
    restricted = path(u)
    assert restricted.result is None and path.evaluated < 1.5 * model.disc.n_elements
    disc = model.disc
    eps_path = [disc.strain(d) for d in solver.elastic_path(a, b)]
    r, yielded, tangent, elastic = solver.material_path(state, disc.strain(state.u_mm), eps_path, u)
    assert restricted.plastic.any() and np.array_equal(restricted.plastic, yielded)
    f_full = disc.internal_force(r.stress_MPa)
    free = ~model.prob.fixed
    assert np.abs(restricted.f_int - f_full)[free].max() <= 1e-9 * np.abs(f_full[free]).max()
    elems = np.flatnonzero(yielded.any(axis=1))
    assert np.allclose(restricted.tangent_of(elems), tangent_of_elements(elems, yielded, tangent, elastic),
                       rtol=1e-12, atol=1e-9)
    done = restricted.full_result()
    for name in ("stress_MPa", "plastic_strain", "back_stress_MPa", "eq_plastic_strain"):
        full = getattr(r, name)
        assert np.allclose(getattr(done, name), full, rtol=0, atol=1e-10 * max(np.abs(full).max(), 1e-300)), name
    assert np.array_equal(done.plastic, r.plastic)


def test_far_iterate_is_evaluated_everywhere(loaded):
    model, solver, state, a, b = loaded
    u0, _, path = solver.start(state, a, b)
    path(u0)
    response = path(2.0 * u0)  # far beyond the bound at most points
    assert response.result is not None and path.evaluated == 2 * model.disc.n_elements


def test_pass_groove_is_the_same_with_and_without_the_bound(loaded, monkeypatch):
    model, solver, _, _, _ = loaded
    positions = [-1.0, -0.5, 0.0, 0.5, 1.0]

    def groove():
        st = [r for r in roll(solver, SolverState.virgin(model.disc), positions, 1, 2)
              if isinstance(r, MovingLoadPass)][0].state
        model.prob.reset_to_elastic()
        return model.probe.profile(st).groove_mm

    bounded = groove()
    monkeypatch.setattr(bounded_material, "FULL_FRACTION", -1.0)  # every iterate evaluated everywhere
    everywhere = groove()
    # the internal forces differ by round-off, so the Newton iterations stop at slightly different iterates:
    # the grooves agree to about the Newton tolerance (rtol 1e-8; measured 3.6e-8), not to round-off
    assert bounded > 0 and abs(bounded - everywhere) <= 1e-6 * bounded
