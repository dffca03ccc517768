"""The exact half-space normal solver (contact.normal.exact) without and with a linear layer: Hertz, the Winkler
limit, prescribed approach, grid placement, several valleys and bad input. Units: mm, N, MPa."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from wrlayer.characteristic import Characteristic
from contact.layer.prandtl_layer import LayerPair, PrandtlLayer
from contact.normal.exact import ExactOptions, solve_exact
from contact.normal.halfspace import HalfSpace, compliance_factor, influence_coefficients
from contact.normal.kik_piotrowski import NormalProblem
from contact.normal.method import NormalMethod, solve_normal_with
from tests.contact.normal.hertz_reference import hertz
from wrlayer.errors import ConvergenceError, InputError

E, NU = 210000.0, 0.28


def _parabolic(N, Rx, Ry, h, half_width=None):
    H = hertz(N, Rx, Ry, E, NU)
    half = 2.5 * H["b_mm"] if half_width is None else half_width
    y = np.linspace(-half, half, 801)
    return NormalProblem(y, y * y / (2.0 * Ry), N, Rx, E, NU, grid_mm=h), H


def test_halfspace_convolution_equals_direct_sum():
    rng = np.random.default_rng(1)
    ny, nx, dy, dx = 7, 11, 0.1, 0.37
    p = rng.random((ny, nx))
    hs = HalfSpace(ny, nx, dy, dx, compliance_factor(E, NU))
    j, i = np.mgrid[0:ny, 0:nx]
    direct = np.array([[np.sum(p * influence_coefficients(i - a, j - b, dx, dy)) for a in range(nx)]
                       for b in range(ny)]) * compliance_factor(E, NU)
    np.testing.assert_allclose(hs.displacement(p), direct, rtol=1e-12, atol=1e-15)


def test_cells_displacement_equals_the_convolution():
    """The few-cell displacement the CG uses for clipped and added cells equals the FFT convolution."""
    hs = HalfSpace(9, 13, 0.1, 0.23, compliance_factor(E, NU))
    rows, cols, vals = np.array([0, 4, 8, 4]), np.array([12, 6, 0, 7]), np.array([1.0, -2.0, 0.5, 3.0])
    p = np.zeros((9, 13))
    p[rows, cols] = vals
    np.testing.assert_allclose(hs.cells_displacement(rows, cols, vals), hs.displacement(p), rtol=1e-12,
                               atol=1e-16)


def test_cg_with_few_cell_corrections_gives_the_same_pressure():
    """One convolution per CG step (few-cell corrections) or two: the same pressure to round-off."""
    from contact.normal.constrained_cg import constrained_cg
    ny, nx, dy, dx = 31, 41, 0.1, 0.12
    hs = HalfSpace(ny, nx, dy, dx, compliance_factor(E, NU))
    y, x = (np.arange(ny) - 15) * dy, (np.arange(nx) - 20) * dx
    f = (x * x)[None, :] / 200.0 + (y * y)[:, None] / 60.0
    start = np.where(f < 0.002, 1.0, 0.0)
    kw = dict(force_N=2000.0, tol=1e-10, max_iter=500)
    plain = constrained_cg(hs.displacement, f, 0.0, 0.0, dx * dy, start, **kw)
    n_plain = hs.evaluations
    local = constrained_cg(hs.displacement, f, 0.0, 0.0, dx * dy, start, cells_displacement=hs.cells_displacement,
                           **kw)
    np.testing.assert_allclose(local.p_MPa, plain.p_MPa, rtol=1e-9, atol=1e-9 * plain.p_MPa.max())
    assert local.delta_mm == pytest.approx(plain.delta_mm, rel=1e-12)
    assert local.iterations == plain.iterations
    assert hs.evaluations - n_plain < n_plain - 1              # fewer convolutions with the corrections


# a/b from 1 to 10 in both orientations (long axis along x or along y)
@pytest.mark.parametrize("Rx,Ry", [(100.0, 100.0), (300.0, 80.0), (1600.0, 31.7), (1000.0, 10.0), (80.0, 300.0),
                                   (10.0, 1000.0)])
def test_hertz_within_one_percent_at_default_cells(Rx, Ry):
    H = hertz(1.0e4, Rx, Ry, E, NU)
    prob, H = _parabolic(1.0e4, Rx, Ry, H["b_mm"] / 15.3)   # lines: 15 per semi-axis b; x cells: the default
    sol = solve_exact(prob)
    assert sol.p_max_MPa == pytest.approx(H["p0_MPa"], rel=0.01)
    assert sol.area_mm2 == pytest.approx(H["area_mm2"], rel=0.01)
    assert sol.delta_mm == pytest.approx(H["delta_mm"], rel=0.01)
    assert sol.length_mm / 2 == pytest.approx(H["a_mm"], rel=0.01)
    assert sol.width_mm / 2 == pytest.approx(H["b_mm"], rel=0.01)
    assert sol.normal_force_N == pytest.approx(1.0e4, rel=1e-9)
    assert sol.method == "exact" and len(sol.patches) == 1
    assert sol.iterations["gap_error_mm"] < 1e-5 * sol.delta_mm          # CG tolerance, far below the grid error


def test_prescribed_approach_gives_the_hertz_force():
    prob, H = _parabolic(2.0e4, 300.0, 80.0, 0.1)
    sol = solve_exact(prob, options=ExactOptions(approach_mm=H["delta_mm"]))
    assert sol.normal_force_N == pytest.approx(2.0e4, rel=0.01)
    assert sol.delta_mm == H["delta_mm"]


def test_winkler_limit_of_a_very_soft_layer():
    """S = 50 N/mm^3: the layer's compliance dwarfs the half-space's, p -> (delta - f) S cell by cell."""
    y = np.linspace(-8.0, 8.0, 641)
    prob = NormalProblem(y, y * y / (2 * 31.7), 1.0e4, 1600.0, E, NU, grid_mm=0.1)
    layer = LayerPair(combined=PrandtlLayer.uniform(Characteristic.linear(50.0, 10.0), prob.strip_y_mm))
    sol = solve_exact(prob, layer)
    fld = sol.field
    winkler = np.maximum(sol.delta_mm - fld.separation_mm, 0.0) * 50.0
    assert np.max(np.abs(fld.p_MPa - winkler)) < 0.01 * winkler.max()
    # and the contact condition holds cell by cell with the computed elastic part (solver identity)
    u_e = HalfSpace(fld.p_MPa.shape[0], fld.p_MPa.shape[1], fld.dy_mm, fld.dx_mm,
                    compliance_factor(E, NU)).displacement(fld.p_MPa)
    on = fld.p_MPa > 0
    gap = fld.separation_mm + u_e + fld.p_MPa / 50.0 - sol.delta_mm
    assert np.max(np.abs(gap[on])) < 1e-7 and np.min(gap[~on]) > -1e-7


def test_grid_grows_when_the_kp_patch_is_too_small():
    prob, _ = _parabolic(1.0e5, 1600.0, 31.7, 0.1, half_width=8.0)     # exact patch is longer than KP's
    tight = solve_exact(prob, options=ExactOptions(margin=0.0))
    wide = solve_exact(prob, options=ExactOptions(margin=0.8))
    assert tight.iterations["grid_changes"] >= 1 and wide.iterations["grid_changes"] == 0
    assert tight.p_max_MPa == pytest.approx(wide.p_max_MPa, rel=1e-5)
    assert tight.area_mm2 == pytest.approx(wide.area_mm2, rel=1e-5)
    p = tight.field.p_MPa
    assert not (np.any(p[:, 0] > 0) or np.any(p[:, -1] > 0) or np.any(p[0] > 0) or np.any(p[-1] > 0))


def test_two_equal_valleys_share_the_load_on_one_grid():
    y = np.arange(-8.0, 20.0 + 1e-9, 0.05)
    f = np.minimum(y * y / 50.0, (y - 12.0) ** 2 / 50.0)
    prob = NormalProblem(y, f, 4.0e4, 500.0, E, NU, grid_mm=0.1)
    sol = solve_exact(prob)
    assert len(sol.patches) == 2
    forces = [r.normal_force_N for r in sol.regions]
    assert forces[0] == pytest.approx(forces[1], rel=2e-3)
    assert sum(forces) == pytest.approx(4.0e4, rel=1e-9)
    assert sol.regions[0].p0_MPa == pytest.approx(sol.regions[1].p0_MPa, rel=5e-3)


def test_method_dispatch_and_the_accurate_default():
    """The default ("auto") is the exact solver in either layer mode."""
    prob, _ = _parabolic(1.0e4, 300.0, 80.0, 0.1)
    kp = solve_normal_with(prob, method=NormalMethod("kik_piotrowski"))
    ex = solve_normal_with(prob, method=NormalMethod("exact", exact_cells=32))
    assert kp.method == "kik_piotrowski" and ex.method == "exact"
    assert solve_normal_with(prob).method == solve_normal_with(prob, method="auto").method == "exact"
    assert NormalMethod(layer_mode="rolling").name == NormalMethod().name == "exact"
    assert ex.iterations["grid_cells"][1] >= 32
    assert ex.p_peak_MPa.shape == kp.p_peak_MPa.shape == prob.strip_y_mm.shape


@pytest.mark.parametrize("kwargs,key", [({"exact_cells": 4}, "method.exact_cells"),
                                        ({"exact_cells": 5000}, "method.exact_cells"),
                                        ({"layer_mode": "sideways"}, "method.layer_mode")])
def test_bad_options_name_the_key(kwargs, key):
    with pytest.raises(InputError) as err:
        NormalMethod("exact", **kwargs)
    assert err.value.what == key


def test_layer_not_covering_the_patch_is_an_input_error():
    prob, _ = _parabolic(1.0e4, 300.0, 80.0, 0.1)
    y = prob.strip_y_mm
    half = y[y >= 0.0]                                  # elements only on one side of the patch
    layer = LayerPair(combined=PrandtlLayer.uniform(Characteristic.linear(5.0e4, 1.0), half, name="half layer"))
    with pytest.raises(InputError, match="half layer"):
        solve_exact(prob, layer)


def test_patch_beyond_the_separation_table_is_an_input_error():
    prob, _ = _parabolic(1.0e5, 1600.0, 31.7, 0.1, half_width=1.3)
    with pytest.raises(InputError) as err:
        solve_exact(prob)
    assert err.value.what == "separation.y_mm"


def test_non_convergence_is_a_convergence_error():
    prob, _ = _parabolic(1.0e4, 300.0, 80.0, 0.1)
    with pytest.raises(ConvergenceError):
        solve_exact(prob, options=ExactOptions(cg_max_iter=2))
    layer = LayerPair(combined=PrandtlLayer.uniform(Characteristic.from_dict(
        {"u_mm": [0.0, 0.02, 0.03, 0.06], "p_MPa": [0.0, 1190.0, 1456.0, 1900.0]}), prob.strip_y_mm))
    with pytest.raises(ConvergenceError):
        solve_exact(dataclasses.replace(prob, normal_force_N=5.0e4), layer,
                    options=ExactOptions(layer_max_iter=1))


def test_fastsim_gets_the_exact_pressure_shape_and_force():
    from contact.normal.exact import fastsim_pressure
    from contact.tangential.fastsim import Creepage, _semi_ellipse_cell_means, solve_tangential

    h = hertz(1.0e4, 300.0, 80.0, E, NU)["b_mm"] / 15.3
    prob, H = _parabolic(1.0e4, 300.0, 80.0, h)
    sol = solve_exact(prob)
    pt = sol.patches[0]
    nx = 40
    pn = fastsim_pressure(sol, 0, nx)
    strip_force = pn.sum(axis=1) * (2.0 * pt.x_lead_mm / nx) * h
    np.testing.assert_allclose(strip_force.sum(), 1.0e4, rtol=1e-9)
    ellipse = pt.p_peak_MPa[:, None] * _semi_ellipse_cell_means(nx)[None, :]
    assert np.max(np.abs(pn - ellipse)) < 0.05 * H["p0_MPa"]          # Hertz: the exact shape is semi-elliptic
    cr = Creepage(0.001, 0.0, 0.0)
    G = E / (2 * (1 + NU))
    same = solve_tangential(pt, cr, G, NU, 0.3, nx=nx, pressure_cells_MPa=ellipse)
    default = solve_tangential(pt, cr, G, NU, 0.3, nx=nx)
    assert same.Fx_N == default.Fx_N
    shaped = solve_tangential(pt, cr, G, NU, 0.3, nx=nx, pressure_cells_MPa=pn)
    assert shaped.Fx_N == pytest.approx(default.Fx_N, rel=0.02)
    with pytest.raises(InputError):
        solve_tangential(pt, cr, G, NU, 0.3, nx=nx, pressure_cells_MPa=pn[:, :-1])


def _fastsim_pressure_line_by_line(sol, region, nx):
    """fastsim_pressure as it was written with np.interp, line by line (the compiled loop's reference)."""
    fld = sol.field
    rows = np.searchsorted(fld.lines, sol.regions[region].strips)
    out = np.empty((rows.size, nx))
    frac = (np.arange(nx) + 0.5) / nx
    for k, r in enumerate(rows):
        lo, hi = fld.x_extent_mm[r]
        on = np.flatnonzero(fld.p_MPa[r] > 0)
        xs = np.concatenate([[lo], fld.x_mm[on], [hi]])
        ps = np.concatenate([[0.0], fld.p_MPa[r, on], [0.0]])
        order = np.argsort(xs, kind="stable")
        pc = np.interp(hi - frac * (hi - lo), xs[order], ps[order])
        total = pc.sum() * (hi - lo) / nx
        out[k] = pc * (fld.p_MPa[r].sum() * fld.dx_mm / total) if total > 0 else 0.0
    return out


@pytest.mark.parametrize("nx", [7, 40, 60])
def test_fastsim_pressure_is_np_interp_line_by_line_bit_for_bit(nx):
    from contact.normal.exact import fastsim_pressure

    prob, _ = _parabolic(1.0e4, 300.0, 80.0, 0.1)
    sol = solve_exact(prob)
    assert np.array_equal(fastsim_pressure(sol, 0, nx), _fastsim_pressure_line_by_line(sol, 0, nx))
    fld = sol.field                         # extents inside the outer loaded cells (the sort puts them in order)
    ext = fld.x_extent_mm.copy()
    ext[:, 0] += 1.5 * fld.dx_mm
    ext[:, 1] -= 0.25 * fld.dx_mm
    moved = dataclasses.replace(sol, field=dataclasses.replace(fld, x_extent_mm=ext))
    assert np.array_equal(fastsim_pressure(moved, 0, nx), _fastsim_pressure_line_by_line(moved, 0, nx))


def test_offgrid_check_finds_a_second_valley_the_grid_misses():
    """The grid-placement check: a grid over the first valley only, with the converged pressure there, reports
    the strips of the second (equal) valley, where f + u_E(0, y) < delta."""
    from contact.normal.exact import _Grid, _offgrid_contact

    y = np.arange(-8.0, 20.0 + 1e-9, 0.05)
    f = np.minimum(y * y / 50.0, (y - 12.0) ** 2 / 50.0)
    prob = NormalProblem(y, f, 4.0e4, 500.0, E, NU, grid_mm=0.1)
    sol = solve_exact(prob)
    fld = sol.field
    first = fld.y_mm < 6.0
    rows = np.flatnonzero(first)
    grid = _Grid(int(fld.lines[rows[0]]), rows.size, fld.x_mm.size, fld.dx_mm)
    hits = _offgrid_contact(prob, prob.separation_on_grid_mm, grid, fld.p_MPa[first], sol.delta_mm,
                            compliance_factor(E, NU))
    second = sol.regions[1].strips
    assert hits.size > 0 and set(second) <= set(hits) and prob.strip_y_mm[hits].min() > 6.0
    # with the full grid nothing is missed
    full = _Grid(int(fld.lines[0]), fld.lines.size, fld.x_mm.size, fld.dx_mm)
    assert _offgrid_contact(prob, prob.separation_on_grid_mm, full, fld.p_MPa, sol.delta_mm,
                            compliance_factor(E, NU)).size == 0
