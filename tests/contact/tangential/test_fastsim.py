"""FASTSIM on strip patches: Kalker's linear theory, saturation, the analytic simplified-theory curve, symmetry,
bounds, energy balance, grid sampling and input errors."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from contact.tangential.fastsim import (
    Creepage,
    equivalent_ellipse,
    simplified_theory_fx_ratio,
    solve_tangential,
)
from contact.tangential.grid_sample import sample_on_grid
from contact.tangential.kalker_coefficients import creep_coefficients
from contact.normal.patch import Patch
from wrlayer.errors import InputError

E_MPa, NU, MU = 210000.0, 0.28, 0.3
G_MPa = E_MPa / (2 * (1 + NU))


def hertz_patch(a, b, normal_N, ny):
    """Elliptic patch on strips: x_l(y) = a sqrt(1 - y^2/b^2), p_peak(y) = p0 sqrt(1 - y^2/b^2)."""
    p0 = 3 * normal_N / (2 * np.pi * a * b)
    h = 2 * b / ny
    y = -b + (np.arange(ny) + 0.5) * h
    r = np.sqrt(1 - (y / b) ** 2)
    return Patch(h, y, a * r, p0 * r)


# round patch, and the paper's no-layer patch size (27.36 x 3.85 mm, a/b = 7.1) at 100 kN
PATCHES = {"a6_b4": (6.0, 4.0, 1.0e5), "paper_like": (13.68, 1.925, 1.0e5)}


@pytest.fixture(params=sorted(PATCHES), scope="module")
def ellipse(request):
    a, b, n = PATCHES[request.param]
    return a, b, hertz_patch(a, b, n, ny=41)


def analytic_simplified_theory(patch, vx, L1, mu):
    """Exact |Fx| / (mu N) of the continuum march (see simplified_theory_fx_ratio), for p_peak ~ x_l patches."""
    return simplified_theory_fx_ratio(vx * patch.x_lead_mm[0] / (L1 * mu * patch.p_peak_MPa[0]))


def test_simplified_theory_curve_limits():
    assert simplified_theory_fx_ratio(1e-6) == pytest.approx(4e-6 / np.pi, rel=1e-6)  # linear theory
    assert simplified_theory_fx_ratio(1e6) == pytest.approx(1.0, abs=1e-6)  # full slip
    # kappa = 1: xi* = 0, adhesion 1/2 + slip area pi/4 over pi/2
    assert simplified_theory_fx_ratio(1.0) == pytest.approx((0.5 + np.pi / 4) / (np.pi / 2))


def test_linear_theory_on_ellipses(ellipse):
    """Small creepage: Kalker's linear theory within 0.5 % (41 strips, nx = 60; measured <= 0.1 %)."""
    a, b, patch = ellipse
    c = creep_coefficients(a / b, NU)
    small = 1e-7  # far below saturation: no slip except the trailing-edge cell
    r = solve_tangential(patch, Creepage(vx=small), G_MPa, NU, MU, nx=60)
    assert r.Fx_N == pytest.approx(-G_MPa * a * b * c.C11 * small, rel=5e-3)
    r = solve_tangential(patch, Creepage(vy=small), G_MPa, NU, MU, nx=60)
    assert r.Fy_N == pytest.approx(-G_MPa * a * b * c.C22 * small, rel=5e-3)
    r = solve_tangential(patch, Creepage(phi_per_mm=small), G_MPa, NU, MU, nx=60)
    assert r.Fy_N == pytest.approx(-G_MPa * a * b * np.sqrt(a * b) * c.C23 * small, rel=5e-3)
    assert abs(r.Fx_N) < 1e-9 * abs(r.Fy_N)  # spin on a symmetric patch: no longitudinal force


def test_equivalent_ellipse_of_an_ellipse_is_itself(ellipse):
    a, b, patch = ellipse
    ell = equivalent_ellipse(patch, G_MPa, NU)
    assert ell.a_mm == pytest.approx(a, rel=2e-3) and ell.b_mm == pytest.approx(b, rel=2e-3)


@pytest.mark.parametrize("creep", [Creepage(vx=0.5), Creepage(vy=-0.3), Creepage(vx=0.3, vy=0.3, phi_per_mm=0.001)])
def test_large_creepage_saturates_at_mu_n(creep):
    patch = hertz_patch(13.68, 1.925, 1e5, ny=31)
    r = solve_tangential(patch, creep, G_MPa, NU, MU, nx=60)
    assert np.hypot(r.Fx_N, r.Fy_N) == pytest.approx(MU * patch.normal_force_N(), rel=1e-2)
    assert r.slip_area_mm2 > 0.98 * patch.area_mm2()


@pytest.mark.parametrize("vx", [5e-4, 1e-3, 2e-3, 4e-3])
def test_fx_curve_matches_the_analytic_simplified_theory_and_converges(ellipse, vx):
    _, _, patch = ellipse
    L1 = equivalent_ellipse(patch, G_MPa, NU).L1_mm_per_MPa
    exact = analytic_simplified_theory(patch, vx, L1, MU)
    errors = []
    for nx in (20, 80, 320):
        r = solve_tangential(patch, Creepage(vx=vx), G_MPa, NU, MU, nx=nx)
        errors.append(abs(-r.Fx_N / (MU * patch.normal_force_N()) / exact - 1))
    assert errors[-1] < 2e-3
    assert errors[-1] <= errors[0] + 1e-12


def test_fx_curve_close_to_vermeulen_johnson():
    """Sanity check against the Vermeulen-Johnson curve F/(mu N) = 1 - (1 - eps)^3, eps = G a b C11 vx/(3 mu N):
    the simplified theory is known to deviate by up to ~10 % in the transition (measured 7.6 % max)."""
    a, b, n = PATCHES["a6_b4"]
    patch = hertz_patch(a, b, n, ny=41)
    c11 = creep_coefficients(a / b, NU).C11
    for vx in np.linspace(2e-4, 5e-3, 8):
        eps = min(G_MPa * a * b * c11 * vx / (3 * MU * n), 1.0)
        vj = 1 - (1 - eps) ** 3
        r = solve_tangential(patch, Creepage(vx=vx), G_MPa, NU, MU, nx=100)
        assert -r.Fx_N / (MU * patch.normal_force_N()) == pytest.approx(vj, rel=0.10, abs=2e-3)


def test_symmetries():
    patch = hertz_patch(13.68, 1.925, 1e5, ny=31)
    base = solve_tangential(patch, Creepage(vx=0.002, vy=0.001, phi_per_mm=0.0012), G_MPa, NU, MU)
    # mirror y -> -y of the symmetric patch maps (vx, vy, phi) to (vx, -vy, -phi): Fx stays, Fy and Mz flip
    mirror = solve_tangential(patch, Creepage(vx=0.002, vy=-0.001, phi_per_mm=-0.0012), G_MPa, NU, MU)
    assert (mirror.Fx_N, mirror.Fy_N, mirror.Mz_Nmm) == pytest.approx(
        (base.Fx_N, -base.Fy_N, -base.Mz_Nmm), rel=1e-9)
    vx_back = solve_tangential(patch, Creepage(vx=-0.002), G_MPa, NU, MU)
    neg = solve_tangential(patch, Creepage(vx=-0.002, vy=-0.001, phi_per_mm=-0.0012), G_MPa, NU, MU)
    assert (neg.Fx_N, neg.Fy_N, neg.Mz_Nmm) == pytest.approx((-base.Fx_N, -base.Fy_N, -base.Mz_Nmm), rel=1e-9)
    vx_only = solve_tangential(patch, Creepage(vx=0.002), G_MPa, NU, MU)
    assert vx_only.Fx_N < 0 and abs(vx_only.Fy_N) < 1e-12 * abs(vx_only.Fx_N)
    assert vx_back.Fx_N == pytest.approx(-vx_only.Fx_N, rel=1e-12)
    spin_only = solve_tangential(patch, Creepage(phi_per_mm=0.0012), G_MPa, NU, MU)
    assert abs(spin_only.Fx_N) < 1e-9 * patch.normal_force_N() and spin_only.Fy_N < 0


def test_zero_creepage_is_zero_everywhere():
    patch = hertz_patch(6, 4, 1e5, ny=11)
    r = solve_tangential(patch, Creepage(), G_MPa, NU, MU)
    assert r.Fx_N == r.Fy_N == r.Mz_Nmm == 0.0
    assert not r.slip.any() and r.PT_max_W_per_mm2 == 0.0 and r.WT_max_N_per_mm == 0.0
    assert r.adhesion_area_mm2 == pytest.approx(patch.area_mm2())


@settings(max_examples=40, deadline=None)
@given(st.floats(-0.02, 0.02), st.floats(-0.02, 0.02), st.floats(-0.01, 0.01), st.floats(0.05, 0.6),
       st.integers(2, 40))
def test_bounds_and_signs(vx, vy, phi, mu, nx):
    patch = hertz_patch(13.68, 1.925, 1e5, ny=9)
    r = solve_tangential(patch, Creepage(vx=vx, vy=vy, phi_per_mm=phi), G_MPa, NU, mu, nx=nx)
    assert np.hypot(r.Fx_N, r.Fy_N) <= mu * patch.normal_force_N() * (1 + 1e-12)
    assert np.all(r.traction_MPa <= mu * r.pn_MPa * (1 + 1e-12) + 1e-12)
    assert np.all(r.PT_W_per_mm2 >= 0) and np.all(r.WT_N_per_mm >= 0) and np.all(np.diff(r.WT_field_N_per_mm) >= 0)
    assert r.slip_area_mm2 + r.adhesion_area_mm2 == pytest.approx(patch.area_mm2())
    # creep forces oppose the rigid slip: their power is never positive
    assert r.Fx_N * vx + r.Fy_N * vy + r.Mz_Nmm * phi <= 1e-9


def test_slip_area_grows_with_creepage():
    patch = hertz_patch(13.68, 1.925, 1e5, ny=21)
    areas = [solve_tangential(patch, Creepage(vx=v, phi_per_mm=0.6 * v), G_MPa, NU, MU).slip_area_mm2
             for v in (1e-4, 5e-4, 1e-3, 2e-3, 4e-3, 8e-3)]
    assert np.all(np.diff(areas) >= 0) and areas[-1] > areas[0]


@pytest.mark.parametrize("creep", [Creepage(vx=2e-3), Creepage(vx=1e-3, vy=-1e-3)])
def test_frictional_power_balances_creep_force_power(creep):
    """Without spin, sum of P_T dA = -(Fx vx + Fy vy) V (units: W = N mm/s * 1e-3); 1 % at nx = 60."""
    patch = hertz_patch(6, 4, 1e5, ny=41)
    r = solve_tangential(patch, creep, G_MPa, NU, MU, speed_mm_s=2000.0, nx=60)
    power_W = np.sum(r.PT_W_per_mm2 * r.dx_mm[:, None]) * patch.grid_mm
    assert power_W == pytest.approx(-(r.Fx_N * creep.vx + r.Fy_N * creep.vy) * 2000.0 * 1e-3, rel=1e-2)
    # W_T per strip is P_T integrated along the strip divided by V
    wt = np.sum(r.PT_W_per_mm2 * r.dx_mm[:, None], axis=1) / (2000.0 * 1e-3)
    np.testing.assert_allclose(r.WT_N_per_mm, wt, rtol=1e-12)
    assert r.WT_max_N_per_mm == pytest.approx(r.WT_N_per_mm.max())


@pytest.mark.parametrize("rule", ["single", "blended"])
def test_other_flexibility_rules_keep_the_single_creepage_linear_theory(rule):
    a, b, n = PATCHES["paper_like"]
    patch = hertz_patch(a, b, n, ny=41)
    c = creep_coefficients(a / b, NU)
    s = 1e-7
    fx = solve_tangential(patch, Creepage(vx=s), G_MPa, NU, MU, flexibility=rule).Fx_N
    fy = solve_tangential(patch, Creepage(phi_per_mm=s), G_MPa, NU, MU, flexibility=rule).Fy_N
    assert fx == pytest.approx(-G_MPa * a * b * c.C11 * s, rel=5e-3)
    assert fy == pytest.approx(-G_MPa * a * b * np.sqrt(a * b) * c.C23 * s, rel=5e-3)


def test_single_flexibility_balances_power_with_spin_and_blend_lies_between():
    patch = hertz_patch(13.68, 1.925, 1e5, ny=31)
    creep = Creepage(vx=0.002, phi_per_mm=0.0012)
    res = {rule: solve_tangential(patch, creep, G_MPa, NU, MU, nx=100, flexibility=rule)
           for rule in ("three", "single", "blended")}
    r = res["single"]
    assert r.L_mm_per_MPa[0] == r.L_mm_per_MPa[1] == r.L_mm_per_MPa[2]
    power_W = np.sum(r.PT_W_per_mm2 * r.dx_mm[:, None]) * patch.grid_mm
    creep_power_W = -(r.Fx_N * creep.vx + r.Mz_Nmm * creep.phi_per_mm) * r.speed_mm_s * 1e-3
    assert power_W == pytest.approx(creep_power_W, rel=1e-2)
    for i in range(3):  # the blend lies between the two rules, flexibility by flexibility
        lo, hi = sorted((res["three"].L_mm_per_MPa[i], res["single"].L_mm_per_MPa[i]))
        assert lo <= res["blended"].L_mm_per_MPa[i] <= hi


def test_speed_scales_power_not_forces_or_work():
    patch = hertz_patch(13.68, 1.925, 1e5, ny=15)
    creep = Creepage(vx=0.002, phi_per_mm=0.0012)
    slow, fast = (solve_tangential(patch, creep, G_MPa, NU, MU, speed_mm_s=v) for v in (1000.0, 3000.0))
    assert fast.Fx_N == slow.Fx_N and fast.WT_max_N_per_mm == pytest.approx(slow.WT_max_N_per_mm)
    assert fast.PT_max_W_per_mm2 == pytest.approx(3 * slow.PT_max_W_per_mm2)
    np.testing.assert_allclose(fast.slip_velocity_mm_s, 3 * slow.slip_velocity_mm_s)


def test_non_elliptic_patch_runs_and_uses_each_strip_length():
    # a flat-topped (non-elliptic) patch: constant length in the middle, short strips at the sides
    h = 0.2
    y = (np.arange(25) - 12) * h
    xl = np.where(np.abs(y) < 1.5, 8.0, 3.0)
    patch = Patch(h, y, xl, 1200.0 * xl / 8.0)
    r = solve_tangential(patch, Creepage(vx=1e-7), G_MPa, NU, MU)
    L1 = r.ellipse.L1_mm_per_MPa
    # linear regime: each strip carries 2 x_l^2 vx / L1 per unit width
    assert r.Fx_N == pytest.approx(-np.sum(2 * xl**2) * h * 1e-7 / L1, rel=1e-6)
    assert r.x_mm[0, 0] == pytest.approx(3.0 - 3.0 / 60) and r.x_mm[12, 0] == pytest.approx(8.0 - 8.0 / 60)


@pytest.mark.parametrize("vx", [3e-4, 1.5e-3, 5e-3])
def test_kik_piotrowski_patch_follows_the_analytic_curve(vx):
    """On any Kik-Piotrowski patch p_peak(y) is proportional to x_l(y) (eq. 11), so with one flexibility every strip
    is self-similar and the exact continuum curve of the ellipse holds for the non-elliptic patch as well."""
    h = 0.1
    y = (np.arange(60) - 29.5) * h
    xl = 9.0 * np.sqrt(np.clip(1 - (np.abs(y) / 3.2) ** 4, 0, None)) + 1.0  # flat-topped, two-sided
    patch = Patch(h, y, xl, 1500.0 * xl / xl.max())
    r = solve_tangential(patch, Creepage(vx=vx), G_MPa, NU, MU, nx=320)
    exact = analytic_simplified_theory(patch, vx, r.L_mm_per_MPa[0], MU)
    assert -r.Fx_N / (MU * patch.normal_force_N()) == pytest.approx(exact, rel=2e-3)


def test_sample_on_grid_matches_the_strips():
    patch = hertz_patch(13.68, 1.925, 1e5, ny=15)
    r = solve_tangential(patch, Creepage(vx=0.002, phi_per_mm=0.0012), G_MPa, NU, MU, nx=80)
    g = sample_on_grid(patch, r)
    assert g.tx_MPa.shape == g.mask.shape == (patch.n_strips, g.x_mm.size)
    assert np.all(np.isnan(g.tx_MPa[~g.mask])) and not g.slip[~g.mask].any()
    assert np.all(np.isfinite(g.tx_MPa[g.mask]))
    # slip area from the picture grid agrees with the FASTSIM cells to within a grid row per strip
    slip_area_grid = g.slip.sum() * patch.grid_mm**2
    assert slip_area_grid == pytest.approx(r.slip_area_mm2, abs=2 * patch.n_strips * patch.grid_mm**2)
    # force from the sampled tractions approximates the FASTSIM force
    fx_grid = np.nansum(g.tx_MPa) * patch.grid_mm**2
    assert fx_grid == pytest.approx(r.Fx_N, rel=0.05)


@pytest.mark.parametrize("kwargs, what", [
    ({"friction": -0.1}, "friction"), ({"friction": np.nan}, "friction"),
    ({"G_MPa": 0.0}, "G_MPa"), ({"G_MPa": -5.0}, "G_MPa"), ({"poisson": 0.7}, "poisson"),
    ({"speed_mm_s": 0.0}, "speed_mm_s"), ({"nx": 1}, "nx"), ({"nx": 10.5}, "nx"),
    ({"flexibility": "kalker"}, "flexibility"),
])
def test_bad_input_names_the_argument(kwargs, what):
    patch = hertz_patch(6, 4, 1e5, ny=5)
    args = {"G_MPa": G_MPa, "poisson": NU, "friction": MU, "speed_mm_s": 1000.0, "nx": 20} | kwargs
    with pytest.raises(InputError, match=what):
        solve_tangential(patch, Creepage(vx=0.001), **args)


@pytest.mark.parametrize("field", ["vx", "vy", "phi_per_mm"])
def test_non_finite_creepage_is_rejected(field):
    with pytest.raises(InputError, match=f"creepage.{field}"):
        Creepage(**{field: np.inf})
    with pytest.raises(InputError, match=f"creepage.{field}"):
        Creepage(**{field: np.nan})


def test_empty_patch_is_rejected():
    patch = Patch(0.5, np.array([0.0]), np.array([2.0]), np.array([0.0]))  # no pressure: no normal force
    with pytest.raises(InputError, match="patch"):
        solve_tangential(patch, Creepage(vx=0.001), G_MPa, NU, MU)


def test_shifted_strips_are_a_lateral_creepage_with_spin():
    """Strips shifted by s along x (the exact solver's rolling mode) see the spin slip phi (x + s): the same
    tractions as unshifted strips with vy' = vy + phi s L2/L3 (the march uses vy/L2 + phi x/L3), and Mz grows by
    s Fy; without spin the shift changes nothing but the cell coordinates."""
    a, b, n = PATCHES["a6_b4"]
    patch = hertz_patch(a, b, n, ny=31)
    s = 0.7
    shift = np.full(patch.n_strips, s)
    spin = Creepage(1e-3, 5e-4, 2e-4)
    moved = solve_tangential(patch, spin, G_MPa, NU, MU, nx=40, strip_centre_mm=shift)
    _, L2, L3 = moved.L_mm_per_MPa
    same = solve_tangential(patch, Creepage(1e-3, 5e-4 + 2e-4 * s * L2 / L3, 2e-4), G_MPa, NU, MU, nx=40)
    assert same.L_mm_per_MPa == moved.L_mm_per_MPa  # rule "three": flexibilities independent of the creepage
    np.testing.assert_allclose(moved.ty_MPa, same.ty_MPa, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(moved.tx_MPa, same.tx_MPa, rtol=1e-12, atol=1e-12)
    assert moved.Mz_Nmm != pytest.approx(solve_tangential(patch, spin, G_MPa, NU, MU, nx=40).Mz_Nmm, rel=1e-3)
    np.testing.assert_allclose(moved.x_mm - s, solve_tangential(patch, spin, G_MPa, NU, MU, nx=40).x_mm)
    no_spin = Creepage(1e-3, 5e-4, 0.0)
    a0 = solve_tangential(patch, no_spin, G_MPa, NU, MU, nx=40, strip_centre_mm=shift)
    b0 = solve_tangential(patch, no_spin, G_MPa, NU, MU, nx=40)
    np.testing.assert_array_equal(a0.ty_MPa, b0.ty_MPa)
    assert a0.Mz_Nmm == pytest.approx(b0.Mz_Nmm + s * b0.Fy_N, rel=1e-9)
    with pytest.raises(InputError, match="strip_centre_mm"):
        solve_tangential(patch, spin, G_MPa, NU, MU, nx=40, strip_centre_mm=np.zeros(3))
