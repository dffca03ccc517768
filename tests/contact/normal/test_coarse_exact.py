"""The coarse-grid exact normal solver (contact.normal.coarse_exact): Hertz, the exact solver, the layer, errors."""

from __future__ import annotations

import numpy as np
import pytest

from contact.layer.prandtl_layer import LayerPair, PrandtlLayer
from contact.normal.coarse_exact import CoarseOptions, solve_coarse_exact
from contact.normal.exact import ExactOptions, solve_exact
from contact.normal.kik_piotrowski import NormalProblem
from contact.normal.method import NormalMethod, solve_normal_with
from contact.scenes.paper_example import paper_characteristic
from tests.contact.normal.hertz_reference import hertz
from wrlayer.errors import InputError

E, NU, RX = 210000.0, 0.3, 460.0


def parabolic(r_y: float, n: float, half: float = 12.0, grid_mm: float = 0.1) -> NormalProblem:
    y = np.linspace(-half, half, 961)
    return NormalProblem(y, y * y / (2 * r_y), n, RX, E, NU, grid_mm=grid_mm)


def flat_topped(n: float = 2e4) -> NormalProblem:
    y = np.linspace(-12.0, 12.0, 961)
    return NormalProblem(y, np.maximum(np.abs(y) - 1.5, 0.0) ** 2 / 80.0, n, RX, E, NU)


def paper_layer(prob: NormalProblem) -> LayerPair:
    return LayerPair(combined=PrandtlLayer.uniform(paper_characteristic(), prob.strip_y_mm, name="paper layer"))


@pytest.mark.parametrize("r_y, n", [(460.0, 1e4), (40.0, 8e4), (3000.0, 1e4)])
def test_hertz_closed_form(r_y, n):
    """Circle, a/b = 3 and a/b = 0.4: p_max and approach within 2 %, area and semi-axes within 3 % of Hertz's
    elliptic-integral solution (the edges lie within cells of 1/13 of the patch; a wrong influence coefficient,
    force or box would be off by far more)."""
    ref = hertz(n, RX, r_y, E, NU)
    sol = solve_coarse_exact(parabolic(r_y, n))
    assert sol.p_max_MPa == pytest.approx(ref["p0_MPa"], rel=0.02)
    assert sol.area_mm2 == pytest.approx(ref["area_mm2"], rel=0.03)
    assert sol.delta_mm == pytest.approx(ref["delta_mm"], rel=0.02)
    assert sol.length_mm == pytest.approx(2 * ref["a_mm"], rel=0.03)
    assert sol.width_mm == pytest.approx(2 * ref["b_mm"], rel=0.03)
    assert sol.method == "coarse_exact"


def test_force_is_carried_by_the_strips():
    sol = solve_coarse_exact(parabolic(100.0, 3e4))
    assert sum(p.normal_force_N() for p in sol.patches) == pytest.approx(3e4, rel=1e-9)
    assert sol.normal_force_N == pytest.approx(3e4, rel=1e-6)
    # the strips' peak pressure is the lines' peak pressure interpolated: its maximum near p_max
    assert sol.p_peak_MPa.max() == pytest.approx(sol.p_max_MPa, rel=0.02)


def test_non_hertzian_against_the_exact_solver():
    """Flat-topped separation (pressure peaks at the ends of the flat part): within 5 % of the exact solver on a
    fine grid; Kik-Piotrowski is 15-50 % off here."""
    prob = flat_topped()
    ref = solve_exact(prob, None, ExactOptions(cells=64))
    sol = solve_coarse_exact(prob, None, CoarseOptions(cells=24))
    for key in ("p_max_MPa", "area_mm2", "delta_mm", "width_mm"):
        assert getattr(sol, key) == pytest.approx(getattr(ref, key), rel=0.05), key


def test_with_the_layer_against_the_exact_solver():
    """The paper's layer in series (it yields at this load): peak pressure and approach within 2 %, area 5 %."""
    prob = parabolic(31.7, 1e5, half=8.0)
    ref = solve_exact(prob, paper_layer(prob), ExactOptions(cells=64))
    sol = solve_coarse_exact(prob, paper_layer(prob))
    assert not sol.elastic and not ref.elastic
    assert sol.p_max_MPa == pytest.approx(ref.p_max_MPa, rel=0.02)
    assert sol.delta_mm == pytest.approx(ref.delta_mm, rel=0.02)
    assert sol.area_mm2 == pytest.approx(ref.area_mm2, rel=0.05)
    assert sol.p_max_MPa < 0.8 * solve_coarse_exact(prob).p_max_MPa      # the layer lowers the peak


def test_extrapolation_option_changes_little_on_hertz():
    prob = parabolic(460.0, 1e4)
    plain = solve_coarse_exact(prob)
    extra = solve_coarse_exact(prob, None, CoarseOptions(extrapolate=True))
    assert extra.iterations["extrapolated"]
    assert extra.p_max_MPa == pytest.approx(plain.p_max_MPa, rel=0.02)


def test_an_approach_guess_places_the_grid_without_a_locating_solve():
    """With a nearby solve's approach (the wheel-rail balance) the first grid covers {f < delta / 2}: fewer grid
    solves, the same solution within the grid's discretisation (a few %)."""
    prob = flat_topped()
    cold = solve_coarse_exact(prob)
    warm = solve_coarse_exact(prob, delta_guess_mm=1.05 * cold.delta_mm)
    assert warm.iterations["boxes"] < cold.iterations["boxes"]
    for key in ("p_max_MPa", "area_mm2", "delta_mm"):
        assert getattr(warm, key) == pytest.approx(getattr(cold, key), rel=0.03), key


def test_registry_and_errors():
    prob = parabolic(460.0, 1e4)
    sol = solve_normal_with(prob, method="coarse_exact")
    assert sol.method == "coarse_exact"
    with pytest.raises(InputError, match="method.layer_mode"):
        NormalMethod("coarse_exact", layer_mode="rolling")
    with pytest.raises(InputError, match="coarse_cells"):
        CoarseOptions(cells=7)
    short = parabolic(460.0, 1e4, half=2.0)            # the patch (b = 3.1 mm) is wider than the table
    with pytest.raises(InputError, match="end of the separation table"):
        solve_coarse_exact(short)


def test_a_warm_start_keeps_the_grid_of_the_last_solve_at_another_force():
    """The balance's warm start (CoarseWarmStart): the next force of the same separation is solved on the kept grid
    from the kept pressure, in one grid solve and fewer CG steps than a cold solve; the solution is the grid's,
    within the grid's discretisation (a fraction of a cell) of the cold solve at that force; another separation
    does not use it."""
    from contact.normal.coarse_exact import CoarseWarmStart

    warm = CoarseWarmStart()
    prob = flat_topped(2e4)
    first = solve_coarse_exact(prob, warm=warm)
    assert warm.solves == 0 and warm.state is not None
    nearby = prob.with_force(2.06e4)
    again = solve_coarse_exact(nearby, warm=warm)
    cold = solve_coarse_exact(nearby)
    assert (warm.solves, warm.kept) == (1, 1)
    assert again.iterations["boxes"] == 1 < cold.iterations["boxes"]
    assert again.iterations["cg_iterations"] < cold.iterations["cg_iterations"]
    assert again.iterations["grid_cells"] == first.iterations["grid_cells"]
    assert again.normal_force_N == pytest.approx(2.06e4, rel=1e-6)
    for key in ("p_max_MPa", "area_mm2", "delta_mm"):
        assert getattr(again, key) == pytest.approx(getattr(cold, key), rel=0.02), key
    # on the kept grid the start stays the pressure it was fitted with: the same force gives the same solution
    assert solve_coarse_exact(nearby, warm=warm).delta_mm == again.delta_mm
    solve_coarse_exact(parabolic(300.0, 2e4), warm=warm)              # another separation: a cold solve
    assert warm.solves == 2


def test_a_warm_start_keeps_its_grid_within_the_slack_where_a_cold_fit_would_move():
    """The benchmark set's Hertz patch a/b = 10 (R_y 12.59 mm, 10 kN) at +2 % force: one more loaded line moves the
    fit's ends by more than a cell but less than :data:`WARM_KEEP_CELLS`; the warm solve keeps the grid (one grid
    solve), within the grid's discretisation of the cold solve; with a slack of one cell it refits."""
    from benchmarks.fast_normal_cases import hertz_patches
    from contact.normal import coarse_exact
    from contact.normal.coarse_exact import CoarseWarmStart

    prob = next(p.problem for p in hertz_patches() if p.name == "a/b 10").with_force(0.98e4)
    for slack, kept in ((coarse_exact.WARM_KEEP_CELLS, 1), (1.0, 0)):
        warm = CoarseWarmStart()
        solve_coarse_exact(prob, warm=warm)
        with pytest.MonkeyPatch.context() as mp:
            mp.setattr(coarse_exact, "WARM_KEEP_CELLS", slack)
            again = solve_coarse_exact(prob.with_force(1e4), warm=warm)
        assert (warm.solves, warm.kept) == (1, kept), slack
        assert (again.iterations["boxes"] == 1) == bool(kept)
        cold = solve_coarse_exact(prob.with_force(1e4))
        for key in ("p_max_MPa", "area_mm2", "delta_mm"):
            assert getattr(again, key) == pytest.approx(getattr(cold, key), rel=0.02), key


def test_a_warm_start_refits_when_the_patch_outgrows_the_kept_grid():
    from contact.normal.coarse_exact import CoarseWarmStart

    warm = CoarseWarmStart()
    prob = parabolic(100.0, 1e4)
    solve_coarse_exact(prob, warm=warm)
    big = solve_coarse_exact(prob.with_force(3e4), warm=warm)
    cold = solve_coarse_exact(prob.with_force(3e4))
    assert (warm.solves, warm.kept) == (1, 0)
    for key in ("p_max_MPa", "area_mm2", "delta_mm"):
        assert getattr(big, key) == pytest.approx(getattr(cold, key), rel=0.02), key


def test_a_rough_solve_stops_on_the_fitted_grid_and_a_warm_solve_finishes_it():
    """``rough`` (the balance's first point): the same fitted grid as the full solve, without the last solve to the
    tolerance (fewer CG steps, p_max within the placing tolerance); a warm solve started from it at the same
    force gives the full solve's solution within the CG tolerance."""
    from contact.normal.coarse_exact import CoarseWarmStart

    prob = flat_topped()
    full = solve_coarse_exact(prob)
    warm = CoarseWarmStart()
    rough = solve_coarse_exact(prob, warm=warm, rough=True)
    assert rough.iterations["grid_cells"] == full.iterations["grid_cells"]
    assert rough.iterations["cg_iterations"] < full.iterations["cg_iterations"]
    assert rough.p_max_MPa == pytest.approx(full.p_max_MPa, rel=1e-2)
    again = solve_coarse_exact(prob, warm=warm)
    assert (warm.solves, warm.kept) == (1, 1)
    for key in ("p_max_MPa", "area_mm2", "delta_mm"):
        assert getattr(again, key) == pytest.approx(getattr(full, key), rel=1e-4), key


def test_expanded_columns_are_the_tables_columns():
    """The influence matrix expanded for the CG (lines on a lattice with a gap) holds exactly the table's columns."""
    from contact.normal.coarse_cg import _add_column, influence_columns
    from contact.normal.coarse_grid import CoarseGrid, influence_table

    rows = np.array([0, 1, 2, 5, 6])
    grid = CoarseGrid(0.2 * rows, rows, 0.5 * np.arange(4), 0.2, 0.5, 0.1)
    k = influence_table(grid, 1e-5)
    cols = influence_columns(k, rows)
    for j in range(rows.size * 4):
        expected = np.zeros(rows.size * 4)
        _add_column(k, rows, 4, j, 1.0, expected)
        np.testing.assert_array_equal(cols[j], expected)


def test_resampling_is_numpys_interpolation_row_by_row():
    """The compiled resampling of a pressure between grids gives np.interp's values (0 outside) bit for bit."""
    from contact.normal.coarse_grid import _interp_rows

    rng = np.random.default_rng(7)
    for _ in range(50):
        xp = np.unique(rng.uniform(-3.0, 3.0, int(rng.integers(2, 30))))
        x = np.sort(np.concatenate([rng.uniform(-4.0, 4.0, int(rng.integers(1, 30))), xp[[0, -1]]]))
        fp = rng.uniform(0.0, 5.0, (int(rng.integers(1, 20)), xp.size))
        expected = np.array([np.interp(x, xp, row, left=0.0, right=0.0) for row in fp])
        np.testing.assert_array_equal(_interp_rows(x, xp, fp), expected)


def test_line_curves_follow_each_elements_state_and_its_reverse_threshold():
    """The coarse solver's line curves: strips in one element state share a curve (also across solves), a strip
    whose element differs (another slider threshold, or another reverse threshold factor) gets its own, equal to the
    element's own loading curve; the compiled linearisation is the piecewise-linear curve."""
    from contact.normal.coarse_layer import LineLayers

    prob = parabolic(460.0, 2e4)
    base = PrandtlLayer.uniform(paper_characteristic(), prob.strip_y_mm, name="paper layer")
    slipped, other_rho = 100, 150          # another slider threshold, another reverse threshold factor
    half_width = base.half_width_mm.copy()
    half_width[slipped] *= 1.2
    rho = np.ones(base.n_points)
    rho[other_rho] = 0.5
    lay = PrandtlLayer(base.y_mm, base.k_N_per_mm3, half_width, base.k_last_N_per_mm3, name="layer",
                       reverse_factor=rho)
    lines = LineLayers(LayerPair(combined=lay), prob)
    y = prob.strip_y_mm[[0, 50, slipped, other_rho, 200]]
    lines.on_lines(y)
    curves = [lines._curve(int(j)) for j in lines.strips(y)]
    assert curves[0] is curves[1] is curves[4] and curves[2] is not curves[0] and curves[3] is not curves[0]
    assert LineLayers(LayerPair(combined=lay), prob)._curve(0) is curves[0]          # kept across solves
    for curve, j in ((curves[2], slipped), (curves[3], other_rho)):
        p, u, _ = lay.loading_curve(j)
        np.testing.assert_allclose(np.interp(p, curve.p, curve.u), u - u[0], rtol=1e-12, atol=1e-15)
    knots, disp, slope = lines.on_lines(y)
    pressure = np.linspace(0.0, 1.2 * knots[0, -1], 7)[None, :].repeat(y.size, axis=0)
    u_l, c = lines.linearise(pressure, (knots, disp, slope))
    np.testing.assert_allclose(u_l[0, :-1], np.interp(pressure[0, :-1], curves[0].p, curves[0].u), rtol=1e-12)
