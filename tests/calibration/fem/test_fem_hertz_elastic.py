"""Elastic Hertz pressure against the analytic half-space: surface displacements and first yield (Johnson 1985)."""

import numpy as np
import pytest
from fem_cases import DIRICHLET_2D, DIRICHLET_3D, STEEL

from calibration.fem.elastoplastic_solver import SolverOptions, solve_load_path
from calibration.fem.assembly import discretise
from calibration.hertz.load import HertzLoad
from calibration.fem.verification_meshes import hertz_block_gmsh


def hertz_surface_w(r, a, p0, E, nu):
    """Normal surface displacement of a half-space under p0 sqrt(1 - r^2/a^2) (Johnson 1985, eq. 3.41/3.42)."""
    r = np.asarray(r, dtype=float)
    inside = (1 - nu ** 2) / E * np.pi * p0 / (4 * a) * (2 * a ** 2 - r ** 2)
    with np.errstate(invalid="ignore", divide="ignore"):
        outside = (1 - nu ** 2) / E * p0 / (2 * a) * ((2 * a ** 2 - r ** 2) * np.arcsin(np.minimum(a / r, 1))
                                                    + a * np.sqrt(np.maximum(r ** 2 - a ** 2, 0)))
    return np.where(r <= a, inside, outside)


@pytest.fixture(scope="module")
def elastic_3d():
    """Quarter block, P2 tets, 0.15 mm elements within 1.2 mm of the load (a = 1 mm), 20 mm block, far faces
    clamped (unstructured gmsh mesh graded away from the load)."""
    mesh = hertz_block_gmsh(0.15, 1.2, 20.0, order=2, dim=3)
    disc = discretise(mesh)
    res = solve_load_path(mesh, STEEL, HertzLoad(0.0, 1.0, a_mm=1.0), [100.0],
                          options=SolverOptions(dirichlet=DIRICHLET_3D), disc=disc)
    return disc, res


def test_3d_surface_displacement_profile_matches_half_space(elastic_3d):
    """w(0) - w(r) on the surface within 2 % (the difference removes the rigid offset of the truncated block;
    the absolute w(0) against the half-space is checked in benchmarks/bench_fem.py on larger blocks)."""
    disc, res = elastic_3d
    u = res.state.u_mm
    r_probe = [0.6, 1.0, 2.0]
    w = {r: HertzLoad(r, 1.0, a_mm=1.0).centre_only(disc.basis).centre_displacement_mm(u) for r in [0.0] + r_probe}
    assert res.history[-1].u_centre_mm == pytest.approx(w[0.0], rel=1e-12)
    for r in r_probe:
        exact = hertz_surface_w(0.0, 1.0, 100.0, STEEL.E_MPa, STEEL.poisson) - \
            hertz_surface_w(r, 1.0, 100.0, STEEL.E_MPa, STEEL.poisson)
        assert w[0.0] - w[r] == pytest.approx(float(exact), rel=0.02), r


def test_3d_first_yield_is_1_61_Y_at_depth_0_48_a(elastic_3d):
    disc, res = elastic_3d
    assert res.first_yield_p0_MPa / STEEL.yield_MPa == pytest.approx(1.61, rel=0.02)
    from calibration.fem.material import von_mises_MPa
    vm = von_mises_MPa(res.state.stress_MPa)
    k = np.unravel_index(np.argmax(vm), vm.shape)
    depth = -disc.qp_coordinates()[2][k]
    assert depth == pytest.approx(0.48, abs=0.1)  # qp spacing ~0.1 mm near the load


def test_2d_first_yield_is_1_79_Y_at_depth_0_70_b(block_2d):
    disc = discretise(block_2d)
    res = solve_load_path(block_2d, STEEL, HertzLoad(0.0, 1.0), [50.0],
                          options=SolverOptions(dirichlet=DIRICHLET_2D), disc=disc)
    assert res.first_yield_p0_MPa / STEEL.yield_MPa == pytest.approx(1.79, rel=0.02)
    from calibration.fem.material import von_mises_MPa
    vm = von_mises_MPa(res.state.stress_MPa)
    k = np.unravel_index(np.argmax(vm), vm.shape)
    assert -disc.qp_coordinates()[1][k] == pytest.approx(0.70, abs=0.05)
    assert res.history[-1].n_plastic == 0
