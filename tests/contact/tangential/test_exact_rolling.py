"""Kalker's exact steady rolling on a grid: Cerruti coefficients, Kalker's linear theory, full sliding, Carter's
2-D solution on a long strip, grid convergence and errors (units mm, N, MPa)."""

import numpy as np
import pytest
from scipy.integrate import dblquad

from contact.tangential.exact_influence import cerruti_coefficients
from contact.tangential.exact_rolling import RollingOptions, solve_rolling
from contact.tangential.fastsim import Creepage
from contact.tangential.kalker_coefficients import creep_coefficients
from contact.tangential.method import PressureGrid, solve_on_grid
from tests.contact.tangential.ellipse_grid import effective_axes, hertz_grid
from wrlayer.errors import ConvergenceError, InputError

NU, G_MPa, MU = 0.25, 80000.0, 0.3


def test_cerruti_coefficients_match_quadrature():
    """The closed forms equal a numerical integral of Johnson's point-force kernels over an off-centre cell."""
    nu, dx, dy, di, dj = 0.3, 0.4, 0.25, 2, -1
    xs, ys = di * dx, dj * dy                # field minus source centre

    def integral(kernel):
        return dblquad(lambda t, s: kernel(xs - s, ys - t), -dx / 2, dx / 2, -dy / 2, dy / 2, epsabs=1e-12)[0]

    r = lambda x, y: np.hypot(x, y)          # noqa: E731
    want = (integral(lambda x, y: (1 - nu) / r(x, y) + nu * x * x / r(x, y) ** 3),
            integral(lambda x, y: nu * x * y / r(x, y) ** 3),
            integral(lambda x, y: (1 - nu) / r(x, y) + nu * y * y / r(x, y) ** 3))
    got = cerruti_coefficients(di, dj, dx, dy, nu)
    np.testing.assert_allclose(np.array(got, float), want, rtol=1e-8)


def test_cerruti_symmetries():
    """A_xx and A_yy swap with x <-> y on square cells; A_xy is odd in each offset and zero on a cell's own line."""
    di, dj = np.meshgrid(np.arange(-3, 4), np.arange(-3, 4))
    axx, axy, ayy = cerruti_coefficients(di, dj, 0.2, 0.2, 0.28)
    np.testing.assert_allclose(axx, ayy.T, rtol=1e-12)
    np.testing.assert_allclose(axy, -axy[:, ::-1], atol=1e-14)
    np.testing.assert_allclose(axy[3], 0.0, atol=1e-14)
    assert axx[3, 3] > axx[3, 4] > 0 and ayy[3, 3] > ayy[4, 3] > 0


def _coefficients(a, b, nx, ny):
    """Kalker's C11, C22, C23 from the exact solver at small creepage in full adhesion (mu large), normalised by
    the ellipse of the loaded cells' area."""
    grid = hertz_grid(a, b, nx, ny=ny)
    ae, be = effective_axes(grid, a, b)
    out = []
    for creep, comp, scale in (((1e-4, 0, 0), "Fx_N", 1e-4 * ae * be), ((0, 1e-4, 0), "Fy_N", 1e-4 * ae * be),
                               ((0, 0, 1e-5), "Fy_N", 1e-5 * (ae * be) ** 1.5)):
        res = solve_on_grid(grid, Creepage(*creep), 1e3, G_MPa, NU, "exact")[0]
        out.append(-getattr(res, comp) / (G_MPa * scale))
    return np.array(out)


# (a/b, cells along x, lines along y of the coarse grid; the fine grid has twice as many): square cells, a = 3 mm,
# 24 cells across the short axis on the coarse grid. Ratios at Table E3's nodes (no interpolation). With 12 cells
# across the short axis the sampled ellipse edge makes the error erratic rather than first order (a/b = 5: C23
# -3.2 % at 12, -2.4 % at 16, -0.9 % at 24, -0.9 % at 32, -0.4 % at 48 cells), so an extrapolation from 12 and 24
# cells landed 1.0-1.3 % above the table; from 24 and 48 cells the extrapolated coefficients agree within 0.6 %
# (a/b = 0.2, 0.5, 1, 5) and 0.94 % (C23 at a/b = 2).
LINEAR_CASES = [(0.2, 24, 120), (0.5, 24, 48), (1.0, 24, 24), (2.0, 48, 24), (5.0, 120, 24)]


@pytest.mark.parametrize("ab, nx, ny", LINEAR_CASES)
def test_linear_theory_matches_kalkers_table(ab, nx, ny):
    """C11, C22, C23 of Kalker's Table E3 within 1 % (nu = 0.25: a column of the table, a/b at its rows: no
    interpolation) from two grids, extrapolated to zero cell size (first order: the upwind slip and the sampled
    ellipse edge)."""
    coarse = _coefficients(3.0, 3.0 / ab, nx, ny)
    fine = _coefficients(3.0, 3.0 / ab, 2 * nx, 2 * ny)
    k = creep_coefficients(ab, NU)
    np.testing.assert_allclose(2 * fine - coarse, [k.C11, k.C22, k.C23], rtol=0.01)
    np.testing.assert_allclose(fine, [k.C11, k.C22, k.C23], rtol=0.02)


@pytest.mark.slow
@pytest.mark.parametrize("ab, nx, ny", [(3.0, 72, 24), (1 / 0.15, 160, 24)])
def test_interpolated_coefficients_between_the_rows_match_the_exact_theory(ab, nx, ny):
    """Between Table E3's rows (a/b = 3: g = 1/3; a/b = 6.67: g = 0.15, the wheel/rail patches) the interpolated
    C11, C22, C23 (g C11, g C22, g^1.5 C23 linear in g) within 2 % of the exact theory, extrapolated as above; the
    coefficients interpolated linearly themselves were 6 %, 6 % and 16 % high at a/b = 6.67."""
    coarse = _coefficients(3.0, 3.0 / ab, nx, ny)
    fine = _coefficients(3.0, 3.0 / ab, 2 * nx, 2 * ny)
    k = creep_coefficients(ab, NU)
    np.testing.assert_allclose([k.C11, k.C22, k.C23], 2 * fine - coarse, rtol=0.02)


def test_full_sliding_gives_mu_N():
    """At a creepage far beyond saturation every loaded cell slips and |F| = mu N, opposite to the creepage."""
    grid = hertz_grid(4.0, 3.0, 24)
    normal = grid.p_MPa.sum() * grid.dx_mm * grid.dy_mm
    res = solve_on_grid(grid, Creepage(0.3, 0.4, 0.0), MU, G_MPa, NU, "exact")[0]
    assert np.hypot(res.Fx_N, res.Fy_N) == pytest.approx(MU * normal, rel=2e-3)
    assert res.Fx_N / res.Fy_N == pytest.approx(0.75, rel=2e-3)
    assert res.Fx_N < 0 and res.adhesion_area_mm2 < 0.02 * res.slip_area_mm2


def test_carter_on_a_long_strip():
    """A patch long in y (2-D Hertz pressure on |y| < 12 a): on the middle line the force per unit length follows
    Carter's F / (mu P) = 1 - (1 - eps)^2, eps = vx E* / (2 mu p0), E* = E / (2 (1 - nu^2)) (both bodies)."""
    a, p0, eps = 1.0, 1000.0, 0.5
    nx, dy = 40, 0.25
    dx = 2 * a / nx
    x = (np.arange(-nx // 2 - 2, nx // 2 + 2) + 0.5) * dx
    y = (np.arange(-48, 48) + 0.5) * dy
    p = np.broadcast_to(p0 * np.sqrt(np.clip(1 - (x / a) ** 2, 0, None)), (y.size, x.size))
    e_star = 2 * G_MPa * (1 + NU) / (2 * (1 - NU ** 2))
    vx = eps * 2 * MU * p0 / e_star
    res = solve_on_grid(PressureGrid(x, y, p), Creepage(vx, 0, 0), MU, G_MPa, NU, "exact")[0]
    mid = y.size // 2
    ratio = res.tx_MPa[mid].sum() / (MU * p[mid].sum())
    assert -ratio == pytest.approx(1 - (1 - eps) ** 2, abs=0.01)


def test_grid_convergence():
    """The longitudinal force at a creepage with partial slip converges as the cells shrink."""
    forces = [solve_on_grid(hertz_grid(4.0, 3.0, n), Creepage(0.001, 0, 0.0005), MU, G_MPa, NU, "exact")[0].Fx_N
              for n in (12, 24, 48)]
    assert abs(forces[2] - forces[1]) < 0.6 * abs(forces[1] - forces[0])
    assert abs(forces[2] - forces[1]) < 0.01 * abs(forces[2])


def test_anderson_accelerates_a_slow_linear_iteration():
    """Anderson mixing turns a slowly converging (rate 0.99) linear fixed-point iteration into a fast one."""
    from contact.tangential.anderson import Anderson
    rng = np.random.default_rng(3)
    q, _ = np.linalg.qr(rng.normal(size=(40, 40)))
    m = q @ np.diag(np.linspace(0.0, 0.99, 40)) @ q.T          # G(x) = m x + c, fixed point (1 - m)^-1 c
    c = rng.normal(size=40)
    want = np.linalg.solve(np.eye(40) - m, c)
    x, mixer = np.zeros(40), Anderson(40, 20)
    for _ in range(60):
        x = mixer.mix(x, m @ x + c)
    assert np.abs(x - want).max() < 1e-8 * np.abs(want).max()
    plain = np.zeros(40)
    for _ in range(60):
        plain = m @ plain + c
    assert np.abs(plain - want).max() > 0.1 * np.abs(want).max()


@pytest.mark.parametrize("memory", [RollingOptions().memory, 20])
def test_accelerated_sweeps_equal_plain_gauss_seidel(memory):
    """The accelerated iteration (Jacobi between line blocks, Anderson mixing of the default depth and of 20) and
    the exact block Gauss–Seidel (memory 0) give the same partial-slip solution to the tolerance, the accelerated
    one in fewer FFT pairs."""
    grid = hertz_grid(4.0, 3.0, 24)
    X, Y = np.meshgrid(grid.x_mm, grid.y_mm)
    args = (grid.x_mm, grid.y_mm, grid.p_MPa, 0.001 - 0.0005 * Y, 0.0005 + 0.0005 * X, MU, G_MPa, NU)
    fast = solve_rolling(*args, RollingOptions(tol=1e-10, memory=memory))
    plain = solve_rolling(*args, RollingOptions(tol=1e-10, memory=0))
    scale = MU * grid.p_MPa.max()
    assert np.abs(fast.tx_MPa - plain.tx_MPa).max() < 1e-6 * scale
    assert np.abs(fast.ty_MPa - plain.ty_MPa).max() < 1e-6 * scale
    assert np.array_equal(fast.slip, plain.slip) and 0 < fast.slip.sum() < (grid.p_MPa > 0).sum()
    assert fast.fft_evaluations < plain.fft_evaluations


@pytest.mark.parametrize("a, b, vx, vy, phi", [(4.0, 3.0, 0.001, 0.0005, 0.0005), (8.0, 1.5, 0.002, 0.0, 0.0012)])
def test_default_tolerance_error_is_below_the_normal_solves(a, b, vx, vy, phi):
    """At the default tolerance the tractions are within 2e-4 of mu max(p) of a solve to 1e-12 (the exact normal
    solve's pressure error at its default CG tolerance, 1e-4 to 2e-4 of max(p)) and the force within 1e-6 of
    mu F_N (the grid's discretisation error is about 1e-3 of mu F_N): partial slip and a long, spin-dominated
    nearly full-slip patch."""
    grid = hertz_grid(a, b, 24, ny=max(8, 2 * round(12 * b / a)))
    X, Y = np.meshgrid(grid.x_mm, grid.y_mm)
    args = (grid.x_mm, grid.y_mm, grid.p_MPa, vx - phi * Y, vy + phi * X, MU, G_MPa, NU)
    default = solve_rolling(*args)
    tight = solve_rolling(*args, RollingOptions(tol=1e-12))
    scale = MU * grid.p_MPa.max()
    assert np.hypot(default.tx_MPa - tight.tx_MPa, default.ty_MPa - tight.ty_MPa).max() < 2e-4 * scale
    force = np.array([(default.tx_MPa - tight.tx_MPa).sum(), (default.ty_MPa - tight.ty_MPa).sum()])
    assert np.hypot(*force) < 1e-6 * MU * grid.p_MPa.sum()
    assert default.iterations < tight.iterations and tight.slip.any()


def test_zero_creepage_and_no_convergence():
    grid = hertz_grid(4.0, 3.0, 12)
    res = solve_on_grid(grid, Creepage(0, 0, 0), MU, G_MPa, NU, "exact")[0]
    assert res.Fx_N == 0 and res.Fy_N == 0 and not res.slip.any()
    X, Y = np.meshgrid(grid.x_mm, grid.y_mm)
    with pytest.raises(ConvergenceError):
        solve_rolling(grid.x_mm, grid.y_mm, grid.p_MPa, 0.001 + 0 * X, 0 * Y, MU, G_MPa, NU,
                      RollingOptions(max_sweeps=2))


def test_pressure_grid_rejects_bad_input():
    with pytest.raises(InputError):
        PressureGrid(np.array([0.0, 1.0, 3.0]), np.array([0.0]), np.ones((1, 3)))
    with pytest.raises(InputError):
        PressureGrid(np.array([0.0, 1.0]), np.array([0.0]), -np.ones((1, 2)))
