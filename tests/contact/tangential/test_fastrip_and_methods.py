"""FaStrip (linear theory, Carter's strips, full sliding), the spin centre (creepages about a point, FASTSIM about
the force centroid) and the three methods side by side on one grid (units mm, N, MPa)."""

import numpy as np
import pytest

from contact.normal.exact import fastsim_pressure, strip_centres
from contact.normal.patch import Patch
from contact.scenes.scene import parse_scene
from contact.scenes.simulation import simulate
from contact.tangential.exact_rolling import RollingOptions
from contact.tangential.fastrip import solve_fastrip
from contact.tangential.fastsim import Creepage, solve_tangential
from contact.tangential.kalker_coefficients import creep_coefficients
from contact.tangential.method import TANGENTIAL_METHODS, PressureGrid, solve_for_normal_solution, solve_on_grid
from contact.tangential.spin_centre import force_centroid_mm, moment_about, solve_about_centroid
from tests.contact.tangential.ellipse_grid import hertz_grid
from wrlayer.errors import InputError

E_MPa, NU, MU = 210000.0, 0.28, 0.3
G_MPa = E_MPa / (2 * (1 + NU))


def hertz_patch(a, b, normal_N, ny, y0=0.0):
    p0 = 3 * normal_N / (2 * np.pi * a * b)
    h = 2 * b / ny
    y = -b + (np.arange(ny) + 0.5) * h
    r = np.sqrt(1 - (y / b) ** 2)
    return Patch(h, y + y0, a * r, p0 * r)


@pytest.mark.parametrize("a, b", [(6.0, 4.0), (13.68, 1.925), (2.0, 8.0)])
def test_fastrip_linear_theory(a, b):
    """Small creepages: Kalker's C11, C22, C23 within 0.5 % (the calibration on the equivalent ellipse)."""
    patch = hertz_patch(a, b, 1e5, 81)
    k = creep_coefficients(a / b, NU)
    fx = solve_fastrip(patch, Creepage(1e-5, 0, 0), G_MPa, NU, MU).Fx_N
    fy = solve_fastrip(patch, Creepage(0, 1e-5, 0), G_MPa, NU, MU).Fy_N
    fs = solve_fastrip(patch, Creepage(0, 0, 1e-6), G_MPa, NU, MU).Fy_N
    assert -fx / (G_MPa * a * b * 1e-5) == pytest.approx(k.C11, rel=5e-3)
    assert -fy / (G_MPa * a * b * 1e-5) == pytest.approx(k.C22, rel=5e-3)
    assert -fs / (G_MPa * (a * b) ** 1.5 * 1e-6) == pytest.approx(k.C23, rel=5e-3)


@pytest.mark.parametrize("creep", [(0.002, 0, 0), (0, 0.002, 0)])
def test_fastrip_follows_the_exact_theory_on_a_round_patch(creep):
    """Partial slip, pure creepage, on a Hertzian 6 x 4 mm patch (p0 = 1 GPa): FaStrip's force within 1 % of
    Kalker's exact theory on the same grid (32 cells across, one strip per line)."""
    grid = hertz_grid(6.0, 4.0, 32)
    fast, exact = (solve_on_grid(grid, Creepage(*creep), MU, G_MPa, NU, m)[0] for m in ("fastrip", "exact"))
    assert np.hypot(fast.Fx_N - exact.Fx_N, fast.Fy_N - exact.Fy_N) < 0.01 * np.hypot(exact.Fx_N, exact.Fy_N)


def test_fastrip_full_sliding_and_zero():
    patch = hertz_patch(6.0, 4.0, 1e5, 41)
    res = solve_fastrip(patch, Creepage(0.2, 0.0, 0.0), G_MPa, NU, MU)
    assert -res.Fx_N == pytest.approx(MU * patch.normal_force_N(), rel=1e-3)
    zero = solve_fastrip(patch, Creepage(0, 0, 0), G_MPa, NU, MU)
    assert zero.Fx_N == 0 and zero.Fy_N == 0 and zero.PT_max_W_per_mm2 == 0


def test_creepage_about_a_point_and_moments():
    c = Creepage(0.002, 0.001, 0.0012).about(x_mm=1.0, y_mm=-5.0)
    assert (c.vx, c.vy, c.phi_per_mm) == pytest.approx((0.002 + 0.006, 0.001 + 0.0012, 0.0012))
    assert moment_about(10.0, Fx_N=2.0, Fy_N=3.0, x_mm=1.0, y_mm=-5.0) == pytest.approx(10 + 3 + 10)


def test_fastsim_about_centroid_does_not_depend_on_the_frame():
    """The same patch placed at y0 in a frame whose creepages are about its origin: the forces are those of the
    patch at the origin with the creepages moved to y0; Mz moves by -y0 Fx."""
    cr = Creepage(0.002, 0.0, 0.0012)
    home = solve_about_centroid(hertz_patch(6.0, 4.0, 1e5, 41), cr, G_MPa, NU, MU)
    for y0 in (-5.0, 2.5):
        away = solve_about_centroid(hertz_patch(6.0, 4.0, 1e5, 41, y0), cr, G_MPa, NU, MU)
        ref = solve_tangential(hertz_patch(6.0, 4.0, 1e5, 41), cr.about(0.0, y0), G_MPa, NU, MU)
        assert force_centroid_mm(hertz_patch(6.0, 4.0, 1e5, 41, y0)) == pytest.approx(y0)
        assert (away.Fx_N, away.Fy_N) == pytest.approx((ref.Fx_N, ref.Fy_N), rel=1e-9)
        assert away.Mz_Nmm == pytest.approx(ref.Mz_Nmm - y0 * ref.Fx_N, rel=1e-9)
    assert home.Fx_N == solve_tangential(hertz_patch(6.0, 4.0, 1e5, 41), cr, G_MPa, NU, MU).Fx_N


def test_three_methods_side_by_side():
    """On a Hertzian grid with spin: FaStrip's Fx (the spin's longitudinal part) is within 3 % of the exact
    theory and closer than FASTSIM's (12 % off); Fy: FASTSIM 1-2 %, FaStrip 6-7 % off (measured)."""
    grid = hertz_grid(6.0, 4.0, 32)
    cr = Creepage(0.002, 0.0, 0.0012)
    res = {m: solve_on_grid(grid, cr, MU, G_MPa, NU, m)[0] for m in ("fastsim", "fastrip", "exact")}
    ex = res["exact"]
    assert abs(res["fastrip"].Fx_N - ex.Fx_N) < min(0.03 * abs(ex.Fx_N), abs(res["fastsim"].Fx_N - ex.Fx_N))
    assert res["fastsim"].Fy_N == pytest.approx(ex.Fy_N, rel=0.03)
    assert res["fastrip"].Fy_N == pytest.approx(ex.Fy_N, rel=0.08)
    assert ex.method == "exact" and ex.iterations > 0 and ex.residual < RollingOptions().tol
    assert {r.method for r in res.values()} == {"fastsim", "fastrip", "exact"}
    for r in res.values():            # one loaded region, forces within the Coulomb bound
        assert np.hypot(r.Fx_N, r.Fy_N) <= MU * r.normal_force_N * (1 + 1e-9)


def test_two_regions_on_one_grid():
    """Two separate patches: one result per region; the exact solve includes their interaction; Mz about the grid
    origin adds up."""
    g = hertz_grid(3.0, 2.0, 16)
    p = np.zeros((2 * g.y_mm.size + 4, g.x_mm.size))
    p[: g.y_mm.size], p[-g.y_mm.size:] = g.p_MPa, g.p_MPa
    y = (np.arange(p.shape[0]) - 0.5 * (p.shape[0] - 1)) * g.dy_mm
    grid = PressureGrid(g.x_mm, y, p)
    assert len(grid.regions()) == 2
    for method in ("fastsim", "fastrip", "exact"):
        lo, hi = solve_on_grid(grid, Creepage(0.001, 0, 0.0001), MU, G_MPa, NU, method)
        assert lo.Fx_N < hi.Fx_N < 0        # the spin adds longitudinal creepage at y < 0


def test_method_name_is_checked():
    with pytest.raises(InputError):
        solve_on_grid(hertz_grid(3.0, 2.0, 8), Creepage(0.001, 0, 0), MU, G_MPa, NU, "contact")


def test_grid_from_patch_keeps_the_force():
    patch = hertz_patch(6.0, 4.0, 1e5, 41)
    grid = PressureGrid.from_patch(patch, 48)
    assert grid.p_MPa.sum() * grid.dx_mm * grid.dy_mm == pytest.approx(patch.normal_force_N(), rel=1e-12)


def test_spin_centre_defects_and_fix():
    """Two patches at y = -5 and +5 mm (scene creepages vx = 0.002, phi = 0.0012 1/mm about the scene origin; exact
    normal solver): FASTSIM with the spin about each patch's own reference strip gave about 4 x the full theory's Fx
    and 2.2 x its Fy; the scene runner moves the creepages to each patch and takes the spin about its centroid:
    within 5 % in Fx and Fy."""
    y = np.round(np.arange(-14.0, 14.0001, 0.05), 4)
    f = np.minimum((y + 5) ** 2 / 80, 0.005 + (y - 5) ** 2 / 80)
    scene = parse_scene({"load": {"normal_force_N": 6e4, "rolling_radius_mm": 460.0},
                         "material": {"E_MPa": E_MPa, "poisson": NU}, "separation": {"y_mm": list(y), "f_mm": list(f)},
                         "tangential": {"creepage_x": 0.002, "creepage_y": 0.0, "spin_per_mm": 0.0012, "friction": MU},
                         "method": {"normal": "exact", "exact_cells": 24}}, "two_patches.toml")
    snap = simulate(scene).first
    sol, cr = snap.solution, Creepage(0.002, 0.0, 0.0012)
    exact = solve_on_grid(PressureGrid.from_exact(sol), cr, MU, G_MPa, NU, "exact")
    fx, fy = sum(r.Fx_N for r in exact), sum(r.Fy_N for r in exact)
    assert sum(t.Fx_N for t in snap.tangential) == pytest.approx(fx, rel=0.05)
    assert sum(t.Fy_N for t in snap.tangential) == pytest.approx(fy, rel=0.05)
    fixed = [solve_about_centroid(Patch(lp.grid_mm, lp.y_mm + yr, lp.x_lead_mm, lp.p_peak_MPa), cr, G_MPa, NU, MU,
                                  pressure_cells_MPa=fastsim_pressure(sol, i, 60),
                                  strip_centre_mm=strip_centres(sol, i))
             for i, (lp, yr) in enumerate(zip(snap.local_patches, snap.y_ref_mm))]
    assert sum(t.Fx_N for t in fixed) == pytest.approx(fx, rel=0.05)
    assert sum(t.Fy_N for t in fixed) == pytest.approx(fy, rel=0.05)
    for method in TANGENTIAL_METHODS:      # the one call for a normal solution: every method near the exact theory
        res = solve_for_normal_solution(sol, cr, MU, G_MPa, NU, method)
        assert len(res) == len(sol.patches) == 2
        assert sum(r.Fx_N for r in res) == pytest.approx(fx, rel=0.05)
        assert sum(r.Fy_N for r in res) == pytest.approx(fy, rel=0.07)


def test_fastrip_warm_start_from_the_last_balance_step():
    """Started from an earlier FaStrip solution (the balance's last step): its own solution is converged at once;
    a nearby patch (1 % longer and more loaded, one strip more) converges to the cold solve's forces within the
    strips' tolerance, in fewer sweeps; another cell count or method is no start."""
    from contact.tangential.fastrip import start_tractions

    creep = Creepage(1e-3, 5e-4, 4e-4)
    patch = hertz_patch(5.0, 3.0, 1e4, 21)
    cold = solve_fastrip(patch, creep, G_MPa, NU, MU)
    assert solve_fastrip(patch, creep, G_MPa, NU, MU, start=cold).iterations <= 2 < cold.iterations
    nearby = hertz_patch(5.05, 3.0, 1.02e4, 22)
    cold2 = solve_fastrip(nearby, creep, G_MPa, NU, MU)
    warm2 = solve_fastrip(nearby, creep, G_MPa, NU, MU, start=cold)
    assert warm2.iterations < cold2.iterations
    for key in ("Fx_N", "Fy_N", "Mz_Nmm"):
        assert getattr(warm2, key) == pytest.approx(getattr(cold2, key), rel=1e-6), key
    assert not start_tractions(cold, 21, 40)[2].any()
    assert not start_tractions(solve_tangential(patch, creep, G_MPa, NU, MU), 21, 60)[2].any()


def test_fastrip_model_coefficients_interpolated_between_nodes():
    """The strip model's full-adhesion coefficients, interpolated between the nodes a/b = 10^(k/32), within 1e-7 of
    the direct solve (a/b from 0.08 to 12 and at a node itself), whatever was solved before."""
    from contact.tangential import fastrip

    rng = np.random.default_rng(7)
    for r in [*np.exp(rng.uniform(np.log(0.08), np.log(12.0), 6)), 10.0 ** (5 / fastrip.NODES_PER_DECADE)]:
        direct = fastrip.solve_model_coefficients(float(r), 24)
        fastrip.clear_node_cache()
        first = fastrip.model_coefficients(float(r), 24)
        assert np.allclose(first, direct, rtol=1e-7, atol=0.0)
        fastrip.model_coefficients(float(r) * 1.3, 24)                    # other nodes in the cache
        assert fastrip.model_coefficients(float(r), 24) == first


def test_exact_theory_on_the_coarse_grid_of_a_coarse_solution():
    """A coarse-grid normal solution (coarse_exact) is solved by the exact theory on the coarse grid itself (its
    lines, not the strips; its pressure, not a raster of the strips): the rows are the grid's loaded lines, and the
    creep forces are within 3 % of mu N of the exact theory on the exact normal solution (0.1 mm strips, 48 cells;
    each of the grid's 12 cells along x cut into four for the rolling slip); two separated regions of a coarse grid
    (no lines in the gap) give one result each."""
    from contact.normal.coarse_exact import solve_coarse_exact
    from contact.normal.exact import solve_exact
    from contact.normal.kik_piotrowski import NormalProblem

    y = np.linspace(-12.0, 12.0, 961)
    prob = NormalProblem(y, y * y / 600.0, 2e4, 460.0, E_MPa, NU)
    coarse, exact = solve_coarse_exact(prob), solve_exact(prob)
    on = coarse.grid_pressure
    assert float(on.p_MPa.sum() * (on.x_mm[1] - on.x_mm[0]) * (on.y_mm[1] - on.y_mm[0])) == pytest.approx(2e4,
                                                                                                          rel=1e-9)
    cr = Creepage(0.001, -0.0008, 0.0003)
    fast = solve_for_normal_solution(coarse, cr, MU, G_MPa, NU, "exact")
    ref = solve_for_normal_solution(exact, cr, MU, G_MPa, NU, "exact")
    assert len(fast) == len(ref) == 1
    from contact.normal.coarse_tangential import tangential_grid

    lines = tangential_grid(on)  # the grid the exact theory solves on: the coarse cells refined along x
    assert float(lines.p_MPa.sum() * (lines.x_mm[1] - lines.x_mm[0]) * (lines.y_mm[1] - lines.y_mm[0])) == \
        pytest.approx(2e4, rel=1e-9)
    assert np.diff(fast[0].y_mm) == pytest.approx(lines.y_mm[1] - lines.y_mm[0])
    assert fast[0].y_mm.size == int(np.count_nonzero(lines.p_MPa.max(axis=1) > 0)) < prob.strip_y_mm.size
    for key in ("Fx_N", "Fy_N"):
        assert getattr(fast[0], key) == pytest.approx(getattr(ref[0], key), abs=0.03 * MU * 2e4), key
    # for the writers: one row per strip, each the nearest line's, the totals the solve's
    from contact.tangential.method import strip_rows

    rows = strip_rows(fast, coarse)[0]
    strips = coarse.patches[0].y_mm
    assert rows.tx_MPa.shape[0] == rows.WT_N_per_mm.size == strips.size and rows.Fx_N == fast[0].Fx_N
    k = np.abs(fast[0].y_mm[None, :] - strips[:, None]).argmin(axis=1)
    np.testing.assert_array_equal(rows.tx_MPa, fast[0].tx_MPa[k])
    assert strip_rows(ref, exact)[0] is ref[0]                  # the exact solution's lines are its strips
    two = NormalProblem(y, np.minimum((y - 4.0) ** 2, (y + 4.0) ** 2) / 600.0, 2e4, 460.0, E_MPa, NU)
    sol = solve_coarse_exact(two)
    assert len(sol.patches) == 2 == len(solve_for_normal_solution(sol, cr, MU, G_MPa, NU, "exact"))


def test_exact_theory_on_a_coarse_solution_resolves_the_spin_of_a_narrow_patch(monkeypatch):
    """A narrow, long patch (lateral radius 5 mm, 5 kN: 9 strips of 0.05 mm across, 7.9 mm long) under spin alone:
    the exact theory on the coarse solution's grid, each cell cut into four along x, is within 5 % of the exact
    theory on the exact normal solution (F_y / (mu N), M_z / (mu N a); measured 0.0 % and -2.7 %, the reference
    within 0.8 % of its own on 0.025 mm strips); on the normal grid's 12 cells along x it was 14 % and -20 %."""
    import contact.normal.coarse_exact as coarse_exact
    import contact.normal.coarse_tangential as coarse_tangential
    from contact.normal.exact import solve_exact
    from contact.normal.kik_piotrowski import NormalProblem

    y = np.linspace(-4.0, 4.0, 801)
    prob = NormalProblem(y, y * y / 10.0, 5e3, 460.0, E_MPa, NU, grid_mm=0.05)
    exact = solve_exact(prob)
    spin = Creepage(0.0, 0.0, 0.0005)
    ref = solve_for_normal_solution(exact, spin, MU, G_MPa, NU, "exact")[0]
    a = np.sqrt(exact.area_mm2 / np.pi)

    def errors():
        fast = solve_for_normal_solution(coarse_exact.solve_coarse_exact(prob), spin, MU, G_MPa, NU, "exact")[0]
        return (fast.Fy_N - ref.Fy_N) / (MU * 5e3), (fast.Mz_Nmm - ref.Mz_Nmm) / (MU * 5e3 * a)

    fy, mz = errors()
    assert abs(fy) < 0.05 and abs(mz) < 0.05
    monkeypatch.setattr(coarse_tangential, "TANGENTIAL_X_REFINE", 1)
    assert max(map(abs, errors())) > 0.1


def test_the_shipped_node_table_is_what_the_model_solves():
    """FaStrip's node coefficients come from the shipped table where it holds them (a new process solves none of
    the default cells' nodes): each equal to a fresh solve, and a node beyond the table or another cell count
    solved."""
    from contact.tangential import fastrip
    from contact.tangential.fastrip_nodes import TABLE_CELLS, TABLE_HALF_RANGE, table_node

    for k in (-TABLE_HALF_RANGE, -17, 0, 5, TABLE_HALF_RANGE):
        tabled = table_node(k, TABLE_CELLS, fastrip.NODES_PER_DECADE)
        fresh = fastrip.solve_model_coefficients(10.0 ** (k / fastrip.NODES_PER_DECADE), TABLE_CELLS)
        assert tabled == pytest.approx(fresh, rel=1e-12), k
    assert table_node(TABLE_HALF_RANGE + 1, TABLE_CELLS, fastrip.NODES_PER_DECADE) is None
    assert table_node(0, TABLE_CELLS + 2, fastrip.NODES_PER_DECADE) is None
    assert table_node(0, TABLE_CELLS, fastrip.NODES_PER_DECADE + 1) is None
    fastrip.clear_node_cache()
    far = fastrip._node_coefficients(TABLE_HALF_RANGE + 3, TABLE_CELLS)
    assert far == pytest.approx(fastrip.solve_model_coefficients(10.0 ** ((TABLE_HALF_RANGE + 3) / 32), TABLE_CELLS))
