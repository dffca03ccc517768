"""Validation against an independent reference: onset of plasticity under a circular Hertz pressure.

Reference: the closed-form Hertz stresses on the load axis (Johnson, Contact Mechanics, 1985, eq. 3.45) put the
first yield of a von Mises half-space (nu = 0.3) at p0 = 1.613 Y, depth 0.481 a
(:func:`calibration.fem.verification_meshes.hertz_axis_first_yield`). The 3D elastoplastic FEM (P2 tetrahedra,
coarse quarter block, the mesh of ``benchmarks/bench_fem_validation.py`` with h = 0.5 mm) must reproduce it.

Tolerance (2 %): in the convergence study (``python -m benchmarks --full --only fem_validation``,
docs/calibration.md) the first yield is 1.6006, 1.6087, 1.6120, 1.6124 Y at h = 0.5, 0.25, 0.18, 0.13 mm, i.e. this
coarse mesh is 0.76 % below the reference and the error falls with h; the maximum is sampled at quadrature points,
not on the axis, so the FEM value approaches the reference from below. 2 % is that coarse-mesh deviation with a
margin of about 2.5x for meshes of other gmsh versions; the load levels 0.97 and 1.03 x the reference bracket
it (1.5 x the tolerance).
"""

import numpy as np
import pytest

from calibration.fem.assembly import discretise
from calibration.fem.elastoplastic_solver import SolverOptions, solve_load_path
from calibration.fem.verification_meshes import hertz_axis_first_yield, hertz_block_gmsh
from calibration.hertz.load import HertzLoad
from fem_cases import DIRICHLET_3D, STEEL
from wrlayer.errors import InputError

TOL = 0.02
A_MM = 1.0


@pytest.fixture(scope="module")
def coarse():
    mesh = hertz_block_gmsh(0.5, 1.5, 20.0, order=2, dim=3)
    return mesh, discretise(mesh)


def test_reference_value_is_the_closed_form_maximum():
    p_y, depth = hertz_axis_first_yield(0.3)
    # Johnson (1985) quotes 1.60 Y at 0.48 a (two digits) for nu = 0.3
    assert p_y == pytest.approx(1.60, abs=0.015)
    assert depth == pytest.approx(0.48, abs=0.005)
    # incompressible limit: larger first-yield pressure, deeper point (the formula depends on nu)
    p_half, d_half = hertz_axis_first_yield(0.499)
    assert p_half > p_y and d_half > depth


def test_reference_rejects_bad_poisson_ratio():
    with pytest.raises(InputError, match="poisson"):
        hertz_axis_first_yield(0.5)
    with pytest.raises(InputError, match="poisson"):
        hertz_axis_first_yield(float("nan"))


def test_onset_of_plasticity_matches_hertz_first_yield(coarse):
    mesh, disc = coarse
    p_ref, depth_ref = hertz_axis_first_yield(STEEL.poisson)
    load = HertzLoad(0.0, A_MM, a_mm=A_MM)
    opts = SolverOptions(dirichlet=DIRICHLET_3D)
    below = solve_load_path(mesh, STEEL, load, [(1 - 1.5 * TOL) * p_ref * STEEL.yield_MPa], options=opts, disc=disc)
    # the solver's first-yield pressure (elastic solution, largest quadrature-point von Mises stress)
    assert below.first_yield_p0_MPa / STEEL.yield_MPa == pytest.approx(p_ref, rel=TOL)
    assert below.history[-1].n_yielded == 0
    above = solve_load_path(mesh, STEEL, load, [(1 + 1.5 * TOL) * p_ref * STEEL.yield_MPa], options=opts,
                            disc=disc, initial_state=below.state)
    yielded = above.state.eq_plastic_strain > 0
    assert yielded.any()
    x = disc.qp_coordinates()
    depth, r = -x[2][yielded] / A_MM, np.hypot(x[0][yielded], x[1][yielded]) / A_MM
    # the first plastic points sit below the centre around the published depth (0.48 a), within one element
    h = 0.5 / A_MM
    assert np.all(np.abs(depth - depth_ref) < h) and np.all(r < h)


@pytest.mark.slow
def test_mixed_hardening_equals_isotropic_hardening_of_the_summed_modulus_under_the_hertz_path(coarse):
    """The reason the benchmark may compare the calibration's mixed law (H_iso = H_kin = 10 GPa) with Tamaas'
    isotropic hardening of 20 GPa (Tamaas has no kinematic hardening): on a proportional stress path both laws
    give the uniaxial slope H_iso + H_kin, and the Hertz loading stays close to proportional. Measured on the
    benchmark's finer meshes: 0.2 % in u_pl at 3 Y; here (h = 0.5 mm, 2.8 Y) it must stay within 1 %, while the
    isotropic half (10 GPa) differs by several times that."""
    from calibration.fem.material import J2Material

    mesh, disc = coarse
    load = HertzLoad(0.0, A_MM, a_mm=A_MM)
    opts = SolverOptions(dirichlet=DIRICHLET_3D, max_increment_MPa=0.2 * STEEL.yield_MPa)
    p0 = 2.8 * STEEL.yield_MPa
    c_el = solve_load_path(mesh, STEEL, load, [1.0], options=opts, disc=disc).history[-1].u_centre_mm

    def inelastic(h_iso, h_kin):
        mat = J2Material(STEEL.E_MPa, STEEL.poisson, STEEL.yield_MPa, h_iso, h_kin)
        res = solve_load_path(mesh, mat, load, [p0, 0.0], options=opts, disc=disc)
        loaded, dent = (h.u_centre_mm for h in res.history if h.requested)
        return loaded - c_el * p0, dent

    mixed, iso_sum, iso_half = inelastic(1e4, 1e4), inelastic(2e4, 0.0), inelastic(1e4, 0.0)
    for k in range(2):  # u_pl under load, residual dent
        assert mixed[k] > 0
        assert mixed[k] == pytest.approx(iso_sum[k], rel=0.01)
        assert abs(iso_half[k] / mixed[k] - 1) > 5 * abs(iso_sum[k] / mixed[k] - 1) + 0.02
