"""Elastoplastic Hertz load path (plane strain): Newton convergence, strategies and backends agree, unloading
leaves self-equilibrated residual stresses, step cutting, restart, output files and input errors."""

import numpy as np
import pytest
import skfem
from fem_cases import DIRICHLET_2D

from calibration.fem.elastoplastic_solver import (LoadPath, SolverOptions, SolverState, load_state, save_state,
                                                  solve_load_path)
from calibration.fem.assembly import discretise
from calibration.hertz.load import HertzLoad
from calibration.fem.linear_solvers import HAVE_PARDISO
from calibration.fem.material import J2Material
from wrlayer.errors import ConvergenceError, InputError

#: combined hardening (p0 = 2 x first yield is near the plane-strain collapse load for perfect plasticity)
STEEL = J2Material(210000.0, 0.3, 500.0, H_iso_MPa=10000.0, H_kin_MPa=10000.0)
LOAD = HertzLoad(0.0, 1.0)


@pytest.fixture(scope="module")
def disc_2d(block_2d_coarse):
    return discretise(block_2d_coarse)


@pytest.fixture(scope="module")
def path_newton(block_2d_coarse, disc_2d):
    """Load to 2x first yield in 4 steps and unload, full Newton."""
    fy = solve_load_path(block_2d_coarse, STEEL, LOAD, [1.0], options=SolverOptions(dirichlet=DIRICHLET_2D),
                         disc=disc_2d).first_yield_p0_MPa
    opts = SolverOptions(dirichlet=DIRICHLET_2D, strategy="newton", max_increment_MPa=0.5 * fy)
    return fy, solve_load_path(block_2d_coarse, STEEL, LOAD, [2 * fy, 0.0], options=opts, disc=disc_2d)


def test_quadratic_convergence_in_plastic_increments(path_newton):
    fy, res = path_newton
    plastic = [i for i in res.history if i.n_plastic > 0 and i.p0_MPa > fy]
    assert plastic
    for inc in plastic:
        r = inc.residuals
        assert r[-1] <= 1e-8
        # the error exponent log(r_k+1)/log(r_k) approaches 2 once in the asymptotic range
        orders = [np.log(r[k + 1]) / np.log(r[k]) for k in range(len(r) - 1) if r[k] < 1e-2]
        assert max(orders) > 1.7, r


def test_unloading_leaves_a_dent_and_self_equilibrated_residual_stress(path_newton, disc_2d):
    fy, res = path_newton
    peak = max(res.history, key=lambda i: i.p0_MPa)
    final = res.history[-1]
    assert final.p0_MPa == 0.0 and peak.p0_MPa == pytest.approx(2 * fy)
    assert final.u_centre_mm > 0.02 * peak.u_centre_mm  # a permanent dent into the body
    assert final.n_yielded > 0
    f_int = disc_2d.internal_force(res.state.stress_MPa)
    free = np.ones(disc_2d.n_dofs, dtype=bool)
    free[disc_2d.basis.get_dofs("fixed").all()] = False
    free[disc_2d.basis.get_dofs("side").all()] = False
    free[disc_2d.basis.get_dofs("sym_y").all("u^1")] = False
    f_peak = peak.p0_MPa * np.abs(LOAD.prepare(disc_2d.basis).force_per_MPa).sum()
    assert np.abs(f_int[free]).max() < 1e-7 * f_peak
    assert np.abs(res.state.stress_MPa).max() > 0.1 * STEEL.yield_MPa  # residual stresses are not zero


@pytest.mark.parametrize("strategy, backend", [("pcg", "auto"), ("modified", "auto"), ("newton", "scipy")])
def test_strategies_and_backends_agree(path_newton, block_2d_coarse, disc_2d, strategy, backend):
    fy, ref = path_newton
    opts = SolverOptions(dirichlet=DIRICHLET_2D, strategy=strategy, linear_solver=backend, max_increment_MPa=0.5 * fy)
    res = solve_load_path(block_2d_coarse, STEEL, LOAD, [2 * fy, 0.0], options=opts, disc=disc_2d)
    assert [i.p0_MPa for i in res.history] == pytest.approx([i.p0_MPa for i in ref.history])
    np.testing.assert_allclose([i.u_centre_mm for i in res.history], [i.u_centre_mm for i in ref.history],
                               rtol=1e-6)


def test_pardiso_is_the_default_backend_when_installed():
    from calibration.fem.linear_solvers import resolve_backend
    assert resolve_backend("auto") == ("pardiso" if HAVE_PARDISO else "scipy")


def test_restart_from_saved_state_continues_identically(tmp_path, path_newton, block_2d_coarse, disc_2d):
    fy, ref = path_newton
    opts = SolverOptions(dirichlet=DIRICHLET_2D, strategy="newton", max_increment_MPa=0.5 * fy)
    first = solve_load_path(block_2d_coarse, STEEL, LOAD, [2 * fy], options=opts, disc=disc_2d)
    path = save_state(first.state, tmp_path / "state.npz")
    restored = load_state(path)
    assert isinstance(restored, SolverState) and restored.p0_MPa == pytest.approx(2 * fy)
    second = solve_load_path(block_2d_coarse, STEEL, LOAD, [0.0], options=opts, disc=disc_2d,
                             initial_state=restored)
    assert second.history[-1].u_centre_mm == pytest.approx(ref.history[-1].u_centre_mm, rel=1e-9)
    with pytest.raises(InputError, match="state"):
        load_state(tmp_path / "missing.npz")


def test_huge_increment_recovers_by_cutting_and_floor_raises(path_newton, block_2d_coarse, disc_2d):
    fy, _ = path_newton
    # without the elastic predictor (which starts this one step at the elastic solution and then converges in 5
    # iterations, so that nothing is cut): the subject here is the cutting of a step that fails
    opts = SolverOptions(dirichlet=DIRICHLET_2D, strategy="newton", max_newton=5, elastic_predictor=False)
    res = solve_load_path(block_2d_coarse, STEEL, LOAD, [2.5 * fy], options=opts, disc=disc_2d)
    assert any(not i.requested for i in res.history)  # sub-steps were needed
    assert res.history[-1].p0_MPa == pytest.approx(2.5 * fy) and res.history[-1].requested
    tight = SolverOptions(dirichlet=DIRICHLET_2D, strategy="newton", max_newton=2, min_increment_fraction=0.5)
    with pytest.raises(ConvergenceError, match=r"p0 = .*relative residuals"):
        solve_load_path(block_2d_coarse, STEEL, LOAD, [2.5 * fy], options=tight, disc=disc_2d)


def test_vtk_and_png_output(tmp_path, path_newton, block_2d_coarse, disc_2d):
    import meshio
    fy, _ = path_newton
    opts = SolverOptions(dirichlet=DIRICHLET_2D, max_increment_MPa=fy)
    res = solve_load_path(block_2d_coarse, STEEL, LOAD, [2 * fy], options=opts, disc=disc_2d, vtk_at=[0],
                          out_dir=tmp_path)
    vtu = [f for f in res.files if f.suffix == ".vtu"]
    pngs = [f for f in res.files if f.suffix == ".png"]
    assert len(vtu) == 1 and len(pngs) == 2 and all(p.stat().st_size > 1000 for p in pngs)
    assert res.output_seconds > 0  # reported apart (FemResult.output_seconds)
    m = meshio.read(vtu[0])
    for key in ("stress_MPa", "von_mises_MPa", "eq_plastic_strain", "plastic"):
        assert key in m.cell_data
    assert m.cell_data["plastic"][0].sum() > 0
    assert m.point_data["displacement_mm"].shape[1] == 3


def test_bad_solver_inputs_are_named(block_2d_coarse, disc_2d):
    def run(levels=(1.0,), mesh=block_2d_coarse, **kw):
        init = kw.pop("initial_state", None)
        return solve_load_path(mesh, STEEL, LOAD, list(levels), options=SolverOptions(**kw), initial_state=init)

    with pytest.raises(InputError, match="dirichlet"):
        run(dirichlet={"nowhere": [0]})
    with pytest.raises(InputError, match="dirichlet"):
        run(dirichlet={"fixed": [2]})
    with pytest.raises(InputError, match="p0_levels_MPa"):
        run(levels=(-1.0,), dirichlet=DIRICHLET_2D)
    with pytest.raises(InputError, match="strategy"):
        run(strategy="magic")
    with pytest.raises(InputError, match="linear_solver"):
        run(linear_solver="cholmod")
    with pytest.raises(InputError, match="rtol"):
        run(rtol=0.0)
    bare = skfem.MeshTri1.init_tensor(np.linspace(0, 1, 3), np.linspace(-1, 0, 3)).with_boundaries(
        {"surface": lambda x: x[1] > -1e-9})
    with pytest.raises(InputError, match="fixed"):
        run(mesh=bare)
    with pytest.raises(InputError, match="mesh"):
        run(mesh=skfem.MeshQuad())
    with pytest.raises(InputError, match="initial_state"):
        run(dirichlet=DIRICHLET_2D, initial_state=SolverState(np.zeros(3), np.zeros((1, 1, 6)),
                                                              np.zeros((1, 1, 6)), np.zeros((1, 1))))


def test_unloading_to_zero_in_many_uneven_steps(path_newton, block_2d_coarse, disc_2d):
    """Sub-steps that do not sum exactly to the target (round-off) end exactly on it, and the last ones of an
    unloading to zero converge (measured against the level's load, not against zero load)."""
    fy, _ = path_newton
    opts = SolverOptions(dirichlet=DIRICHLET_2D, strategy="newton", max_increment_MPa=fy / 43.7)
    res = solve_load_path(block_2d_coarse, STEEL, LOAD, [1.9 * fy, 0.0], options=opts, disc=disc_2d)
    assert res.history[-1].p0_MPa == 0.0
    assert min(abs(i.p0_MPa) for i in res.history[:-1]) > 1e-6 * fy  # no round-off residue step
    assert all(i.residuals[-1] <= 1e-8 for i in res.history)


def test_increments_are_a_generator_the_caller_can_stop_and_resume(path_newton, block_2d_coarse, disc_2d):
    """LoadPath.increments yields each converged increment with the path's state at it: a caller that stops after
    the first and resumes from its state reaches the same peak as the whole path in one call."""
    fy, res = path_newton
    opts = SolverOptions(dirichlet=DIRICHLET_2D, strategy="newton", max_increment_MPa=0.5 * fy)
    path = LoadPath(block_2d_coarse, STEEL, LOAD, [2 * fy], options=opts, disc=disc_2d)
    steps = path.increments(2 * fy)
    first = next(steps)
    assert first.p0_MPa == pytest.approx(0.5 * fy) and path.state.p0_MPa == first.p0_MPa
    steps.close()  # stop here, keep the state, resume from it
    resumed = LoadPath(block_2d_coarse, STEEL, LOAD, [2 * fy], options=opts, disc=disc_2d,
                       initial_state=path.state, branch_points=path.branch)
    rest = list(resumed.increments(2 * fy))
    whole = [h for h in res.history if h.p0_MPa <= 2 * fy * (1 + 1e-12)][:1 + len(rest)]
    assert [h.p0_MPa for h in [first] + rest] == pytest.approx([h.p0_MPa for h in whole])
    assert rest[-1].u_centre_mm == pytest.approx(whole[-1].u_centre_mm, rel=1e-6)  # Newton tolerance


def test_load_levels_merge_a_step_and_a_peak_equal_up_to_round_off():
    from calibration.indentation import load_levels
    from calibration.settings import LoadSettings

    p_y = 700.0  # 1.7 from the steps (1 + 14 x 0.05) and from the peaks differ by 2e-13 MPa
    levels = load_levels(p_y, LoadSettings(n_levels=40, unload_factors=(1.15, 1.4, 1.7, 2.2)))
    assert np.all(np.diff(levels) > 1e-6 * p_y)
    assert min(abs(np.array(levels) - 1.7 * p_y)) < 1e-9 * p_y and levels[-1] == pytest.approx(3.0 * p_y)
