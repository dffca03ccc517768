"""Warm starts of the exact normal solver and its FFTs: the same solution as a cold solve within the CG tolerance."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from contact.normal.exact import ExactOptions, solve_exact
from contact.normal.halfspace import cropped_irfft2, fft_module, padded_rfft2
from contact.normal.kik_piotrowski import NormalProblem

E, NU = 210000.0, 0.28


def _problem(N: float, Ry: float = 31.7, half: float = 8.0) -> NormalProblem:
    y = np.linspace(-half, half, 801)
    return NormalProblem(y, y * y / (2.0 * Ry), N, 1600.0, E, NU, grid_mm=0.1)


def test_axis_by_axis_transforms_equal_the_padded_2d_ones():
    sfft = fft_module()
    a = np.random.default_rng(3).random((2, 7, 11))
    shape = (16, 25)
    np.testing.assert_allclose(padded_rfft2(a, shape), sfft.rfft2(a, s=shape), rtol=1e-12, atol=1e-12)
    spec = sfft.rfft2(np.random.default_rng(4).random((2, *shape)))
    np.testing.assert_allclose(cropped_irfft2(spec, shape, 7, 11), sfft.irfft2(spec, s=shape)[:, :7, :11],
                               rtol=1e-12, atol=1e-12)


def _same_solution(warm, cold, rel=1e-3):
    """Same grid, cell pressures within ``rel`` p_max (the CG stops on a relative change of 1e-5 per step: the cells
    of two runs from different starts differ by a few 1e-4), approach and area to the CG tolerance."""
    assert warm.iterations["grid_cells"] == cold.iterations["grid_cells"]
    assert warm.field.dx_mm == pytest.approx(cold.field.dx_mm, rel=1e-9)
    scale = cold.p_max_MPa
    assert np.max(np.abs(warm.field.p_MPa - cold.field.p_MPa)) < rel * scale
    assert warm.delta_mm == pytest.approx(cold.delta_mm, rel=1e-6)
    assert warm.area_mm2 == pytest.approx(cold.area_mm2, rel=1e-4)


def test_warm_start_from_a_nearby_load_gives_the_cold_solution_in_fewer_iterations():
    first = solve_exact(_problem(1.0e5))
    prob = _problem(1.02e5)
    cold = solve_exact(prob)
    warm = solve_exact(prob, start=first.field)
    _same_solution(warm, cold)
    assert warm.iterations["cg_iterations"] < cold.iterations["cg_iterations"]
    again = solve_exact(prob, start=cold.field)          # started at the solution itself: a step or two
    _same_solution(again, cold)
    assert again.iterations["cg_iterations"] <= 3


def test_warm_and_cold_converge_to_one_solution_with_a_tight_tolerance():
    opts = ExactOptions(cg_tol=1e-9)
    first = solve_exact(_problem(1.0e5), options=opts)
    prob = _problem(1.05e5)
    _same_solution(solve_exact(prob, options=opts, start=first.field), solve_exact(prob, options=opts), rel=1e-7)


def test_warm_start_grows_the_grid_as_the_cold_solve_does():
    opts = ExactOptions(margin=0.0)                       # KP's grid is too short: the cold solve grows it
    first = solve_exact(_problem(1.0e5), options=opts)
    prob = _problem(1.001e5)
    cold = solve_exact(prob, options=opts)
    assert cold.iterations["grid_changes"] >= 1
    warm = solve_exact(prob, options=opts, start=first.field)
    _same_solution(warm, cold)
    # the start's extent grows the grid before the first CG: one CG solve instead of one per grid
    assert warm.iterations["cg_iterations"] < cold.iterations["cg_iterations"]


def test_a_start_without_common_lines_falls_back_to_kp():
    prob = _problem(1.0e5)
    cold = solve_exact(prob)
    far = dataclasses.replace(cold.field, lines=cold.field.lines + 5000)
    warm = solve_exact(prob, start=far)
    _same_solution(warm, cold, rel=1e-12)
    assert warm.iterations["cg_iterations"] == cold.iterations["cg_iterations"]
