"""Thick-walled cylinder under internal pressure, plane strain, elastic-perfectly plastic (Hill 1950)."""

import numpy as np
import pytest

from calibration.fem.elastoplastic_solver import SolverOptions, solve_load_path
from calibration.hertz.load import UniformPressure
from calibration.fem.material import J2Material
from calibration.fem.verification_meshes import quarter_annulus
from wrlayer.errors import ConvergenceError

A_MM, B_MM = 1.0, 2.0
MAT = J2Material(210000.0, 0.3, 240.0)


def first_yield_pressure(mat, a, b):
    """Lame solution, plane strain: sigma_vm(a)^2 = 3 B^2 / a^4 + (1 - 2 nu)^2 A^2 with A = p a^2 / (b^2 - a^2),
    B = p a^2 b^2 / (b^2 - a^2); first yield where sigma_vm(a) = Y."""
    A = a ** 2 / (b ** 2 - a ** 2)
    return mat.yield_MPa / (A * np.sqrt(3 * b ** 4 / a ** 4 + (1 - 2 * mat.poisson) ** 2))


def limit_pressure(mat, a, b):
    """Plane-strain limit pressure (2 / sqrt 3) Y ln(b / a)."""
    return 2 / np.sqrt(3) * mat.yield_MPa * np.log(b / a)


@pytest.fixture(scope="module")
def cylinder():
    mesh = quarter_annulus(A_MM, B_MM, 16, 16, order=2, grading=1.1)
    opts = SolverOptions(dirichlet={"sym_y": [0], "sym_z": [1]}, strategy="newton",
                         max_increment_MPa=0.05 * limit_pressure(MAT, A_MM, B_MM))
    return mesh, opts


def test_first_yield_and_converged_just_below_the_limit(cylinder):
    mesh, opts = cylinder
    p_lim = limit_pressure(MAT, A_MM, B_MM)
    res = solve_load_path(mesh, MAT, UniformPressure("inner", probe_mm=(A_MM, 0.0)), [0.99 * p_lim], options=opts)
    assert res.first_yield_p0_MPa == pytest.approx(first_yield_pressure(MAT, A_MM, B_MM), rel=0.01)
    first = [i for i in res.history if i.first_yield]
    assert len(first) == 1 and first[0].p0_MPa >= res.first_yield_p0_MPa
    assert res.history[-1].p0_MPa == pytest.approx(0.99 * p_lim)
    # elastic range: bore displacement matches Lame (plane strain) u(a) = (1+nu) p a / E [(1-2nu) a^2 + b^2]/(b^2-a^2)
    inc = res.history[0]
    nu, E = MAT.poisson, MAT.E_MPa
    u_exact = (1 + nu) * inc.p0_MPa * A_MM / E * ((1 - 2 * nu) * A_MM ** 2 + B_MM ** 2) / (B_MM ** 2 - A_MM ** 2)
    assert inc.u_centre_mm == pytest.approx(u_exact, rel=2e-3)  # the bore moves outwards = into the body
    # beyond the limit pressure there is no equilibrium: the solver must refuse, not return a result
    with pytest.raises(ConvergenceError, match="p0 ="):
        solve_load_path(mesh, MAT, UniformPressure("inner"), [1.01 * p_lim], options=opts,
                        initial_state=res.state)
