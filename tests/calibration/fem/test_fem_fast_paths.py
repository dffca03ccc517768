"""The FEM engine's fast paths give the results of the plain ones: the blocked CSR pattern, single-precision
factorisations (refined / as CG preconditioner), the matrix-free tangent, adaptive CG tolerances and the elastic
predictor (elastic unloading without Newton iterations; Newton takes over when a point re-yields) and the
extrapolating predictor (quadratic in p0, carried across calls)."""

import numpy as np
import pytest
import skfem
from fem_cases import DIRICHLET_2D

from calibration.fem.assembly import _csr_pattern, _csr_pattern_blocked, discretise, field_element
from calibration.fem.elastoplastic_solver import SolverOptions, extrapolate, solve_load_path
from calibration.fem.linear_solvers import HAVE_PARDISO, Factoriser, preconditioned_cg
from calibration.fem.material import J2Material
from calibration.fem.boundary import dirichlet_dofs
from calibration.fem.problem import TangentProblem
from calibration.hertz.load import HertzLoad
from calibration.fem.return_mapping import radial_return

STEEL = J2Material(210000.0, 0.3, 500.0, H_iso_MPa=10000.0, H_kin_MPa=10000.0)
LOAD = HertzLoad(0.0, 1.0)
#: tight tolerances, so that two converged paths are compared, not two stopping points
TIGHT = dict(dirichlet=DIRICHLET_2D, rtol=1e-10, etol=1e-14)
needs_pardiso = pytest.mark.skipif(not HAVE_PARDISO, reason="pypardiso not installed")


@pytest.fixture(scope="module")
def disc_2d(block_2d_coarse):
    return discretise(block_2d_coarse)


@pytest.fixture(scope="module")
def first_yield(block_2d_coarse, disc_2d):
    return solve_load_path(block_2d_coarse, STEEL, LOAD, [1.0], options=SolverOptions(dirichlet=DIRICHLET_2D),
                           disc=disc_2d).first_yield_p0_MPa


@pytest.mark.parametrize("kind, order", [("tet", 1), ("tet", 2), ("tri", 1), ("tri", 2)])
def test_blocked_csr_pattern_equals_the_generic_one(kind, order):
    mesh = (skfem.MeshTet1.init_tensor(*[np.linspace(0, 1, 4)] * 3) if kind == "tet"
            else skfem.MeshTri1.init_symmetric().refined(2))
    basis = skfem.Basis(mesh, field_element(kind, order))
    edofs = np.ascontiguousarray(basis.element_dofs.T)
    fast = _csr_pattern_blocked(edofs, basis.N, mesh.dim())
    assert fast is not None
    for a, b in zip(_csr_pattern(edofs, basis.N), fast):
        np.testing.assert_array_equal(a, b)
    # a numbering that is not blocked falls back (None)
    assert _csr_pattern_blocked(edofs[:, ::-1].copy(), basis.N, mesh.dim()) is None


@needs_pardiso
def test_single_precision_factorisation_refines_to_double_accuracy(disc_2d):
    prob = TangentProblem(disc_2d, STEEL, dirichlet_dofs(disc_2d, DIRICHLET_2D), SolverOptions(dirichlet=DIRICHLET_2D))
    b = np.random.default_rng(1).standard_normal(disc_2d.n_dofs)
    b[prob.fixed] = 0.0
    single = Factoriser(disc_2d.csr_indptr, disc_2d.csr_indices, disc_2d.n_dofs, "pardiso", "single")
    single.factorise(prob.Ke_bc_data)
    raw = single.solve(b)
    rel = np.linalg.norm(prob.Ke.dot(raw) - b) / np.linalg.norm(b)
    assert 1e-12 < rel < 1e-4  # single precision: inexact, but a good preconditioner
    x = single.solve_refined(b, prob.Ke.dot, rtol=1e-12)
    assert np.linalg.norm(prob.Ke.dot(x) - b) <= 1e-12 * np.linalg.norm(b)
    y, iters = preconditioned_cg(prob.Ke.dot, b, single.solve, rtol=1e-12)
    assert iters <= 4 and np.linalg.norm(prob.Ke.dot(y) - b) <= 1e-12 * np.linalg.norm(b)
    assert tiny_rhs_is_solved(single, prob, b)


def tiny_rhs_is_solved(factor, prob, b):
    """A right-hand side below float32's range (a converged residual) is scaled, not flushed to zero."""
    x = factor.solve(1e-40 * b)
    return np.linalg.norm(prob.Ke.dot(x) - 1e-40 * b) <= 1e-4 * 1e-40 * np.linalg.norm(b)


def test_matrix_free_tangent_equals_the_assembled_one(block_2d_coarse, disc_2d, first_yield):
    res = solve_load_path(block_2d_coarse, STEEL, LOAD, [2 * first_yield], disc=disc_2d,
                          options=SolverOptions(dirichlet=DIRICHLET_2D, max_increment_MPa=0.5 * first_yield))
    prob = TangentProblem(disc_2d, STEEL, dirichlet_dofs(disc_2d, DIRICHLET_2D), SolverOptions(dirichlet=DIRICHLET_2D))
    st = res.state
    # strain a little beyond the converged state: plastic points with the consistent tangent
    u = 1.05 * st.u_mm
    rm = radial_return(STEEL, disc_2d.strain(u), st.plastic_strain, st.back_stress_MPa, st.eq_plastic_strain)
    plastic = np.nonzero(rm.plastic.any(axis=1))[0]
    assert plastic.size > 0
    K = disc_2d.csr_matrix(prob.tangent_data(rm.tangent_of(plastic), plastic))
    x = np.random.default_rng(2).standard_normal(disc_2d.n_dofs)
    np.testing.assert_allclose(prob.tangent_matvec(rm.tangent_of(plastic), plastic)(x), K.dot(x), rtol=1e-12,
                               atol=1e-12 * np.abs(K.dot(x)).max())


def _path(mesh, disc, levels, **kw):
    return solve_load_path(mesh, STEEL, LOAD, levels, disc=disc, options=SolverOptions(**{**TIGHT, **kw}))


def test_elastic_unloading_needs_no_newton_iteration_and_equals_newton(block_2d_coarse, disc_2d, first_yield):
    # 1.2 x first yield: a small plastic zone that unloads elastically
    levels = [1.2 * first_yield, 0.0]
    # the default tolerances (rtol 1e-8): the predictor's round-off residual (1e-12 here) is "nothing to do"
    fast = _path(block_2d_coarse, disc_2d, levels, elastic_predictor=True, rtol=1e-8, etol=1e-10)
    plain = _path(block_2d_coarse, disc_2d, levels, elastic_predictor=False)
    unl_fast, unl_plain = fast.history[-1], plain.history[-1]
    assert unl_fast.p0_MPa == 0.0 and unl_fast.n_yielded > 0  # a dent remains
    assert unl_fast.newton_iters == 0 and unl_fast.n_plastic == 0  # no Newton iteration, no point re-yields
    assert unl_plain.newton_iters >= 1
    scale = np.abs(plain.state.u_mm).max()
    assert np.abs(fast.state.u_mm - plain.state.u_mm).max() <= 1e-8 * scale
    assert unl_fast.u_centre_mm == pytest.approx(unl_plain.u_centre_mm, rel=1e-8)
    # the plastic strains are those of the loading increment (converged to rtol 1e-8 against 1e-10)
    peq = plain.state.eq_plastic_strain
    assert np.abs(fast.state.eq_plastic_strain - peq).max() <= 1e-5 * peq.max()


def test_re_yielding_unloading_falls_back_to_newton(block_2d_coarse, disc_2d, first_yield):
    # 2 x first yield: unloading re-yields (reverse plasticity), the predictor is only Newton's start
    levels = [2.0 * first_yield, 0.0]
    kw = dict(max_increment_MPa=0.5 * first_yield, max_unload_increment_MPa=2.0 * first_yield)
    fast = _path(block_2d_coarse, disc_2d, levels, elastic_predictor=True, **kw)
    plain = _path(block_2d_coarse, disc_2d, levels, elastic_predictor=False, **kw)
    unl_fast, unl_plain = fast.history[-1], plain.history[-1]
    assert unl_fast.n_plastic > 0 and unl_fast.newton_iters >= 1
    assert unl_fast.newton_iters < unl_plain.newton_iters  # the first (elastic) correction is the predictor
    assert unl_fast.u_centre_mm == pytest.approx(unl_plain.u_centre_mm, rel=1e-8)
    scale = np.abs(plain.state.u_mm).max()
    assert np.abs(fast.state.u_mm - plain.state.u_mm).max() <= 1e-8 * scale


@pytest.mark.parametrize("kw", [dict(cg_forcing="fixed"), dict(factor_precision="double")])
def test_adaptive_cg_and_single_precision_give_the_same_path(block_2d_coarse, disc_2d, first_yield, kw):
    levels = [1.5 * first_yield, 2.0 * first_yield, 0.0]
    ref = _path(block_2d_coarse, disc_2d, levels, max_increment_MPa=0.5 * first_yield, **kw)
    new = _path(block_2d_coarse, disc_2d, levels, max_increment_MPa=0.5 * first_yield)
    np.testing.assert_allclose([i.u_centre_mm for i in new.history], [i.u_centre_mm for i in ref.history],
                               rtol=1e-8)


def test_bad_fast_path_options_are_named(block_2d_coarse, disc_2d):
    from wrlayer.errors import InputError

    for kw, name in [(dict(cg_forcing="eager"), "cg_forcing"), (dict(factor_precision="half"), "factor_precision"),
                     (dict(cg_rtol=0.5, cg_rtol_max=0.1), "cg_rtol"),
                     (dict(cg_target_fraction=1.0), "cg_target_fraction")]:
        with pytest.raises(InputError, match=name):
            solve_load_path(block_2d_coarse, STEEL, LOAD, [1.0], disc=disc_2d,
                            options=SolverOptions(dirichlet=DIRICHLET_2D, **kw))


def test_extrapolation_is_exact_for_quadratic_and_linear_branches():
    u = lambda p: np.array([1.0 + 2.0 * p + 0.5 * p * p, -p * p])  # noqa: E731
    pts = [(p, u(p)) for p in (1.0, 1.5, 2.5)]
    np.testing.assert_allclose(extrapolate(pts, 3.2), u(3.2), rtol=1e-13)
    lin = [(p, np.array([3.0 - 2.0 * p])) for p in (2.0, 1.0)]  # a downward branch
    np.testing.assert_allclose(extrapolate(lin, 0.25), [2.5], rtol=1e-13)


def test_quadratic_predictor_carried_across_calls_saves_iterations_and_keeps_the_path(block_2d_coarse, disc_2d,
                                                                                       first_yield):
    """A load path split into stages (as the calibration's: load, unload, reload from the peak state) converges
    to the same states with fewer Newton iterations when the loading branch is handed on."""
    p_y, kw = first_yield, dict(max_increment_MPa=0.25 * first_yield, rtol=1e-8, etol=1e-10)
    first = _path(block_2d_coarse, disc_2d, [1.5 * p_y, 1.75 * p_y], **kw)
    assert len(first.branch_points) == 3 and first.branch_points[-1][0] == 1.75 * p_y
    levels = [2.0 * p_y, 2.25 * p_y]

    def stage(branch, order):  # a fresh discretisation each: the same (elastic) preconditioner on entry
        return solve_load_path(block_2d_coarse, STEEL, LOAD, levels, disc=discretise(block_2d_coarse),
                               options=SolverOptions(**{**TIGHT, **kw}, predictor_order=order),
                               initial_state=first.state, branch_points=branch)

    runs = {"plain": stage(None, 1), "linear": stage(first.branch_points, 1),
            "quadratic": stage(first.branch_points, 2),
            # a branch that does not end at the start level is ignored (the start state alone, as "plain")
            "stale": stage(first.branch_points[:-1], 1)}
    iters = {k: sum(h.newton_iters for h in r.history) for k, r in runs.items()}
    assert iters["quadratic"] < iters["plain"] and iters["linear"] < iters["plain"]
    scale = np.abs(runs["plain"].state.u_mm).max()
    assert iters["stale"] == iters["plain"]
    np.testing.assert_allclose(runs["stale"].state.u_mm, runs["plain"].state.u_mm, rtol=0, atol=1e-12 * scale)
    for name in ("linear", "quadratic"):
        assert np.abs(runs[name].state.u_mm - runs["plain"].state.u_mm).max() <= 1e-7 * scale
    with pytest.raises(Exception, match="predictor_order"):
        SolverOptions(predictor_order=3).validate()
