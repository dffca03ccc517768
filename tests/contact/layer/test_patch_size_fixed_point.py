"""The fixed point over the patch sizes shared by scenes and wheel-rail scenes with ``scale_to_patch`` (mm)."""

import pytest

from contact.layer.patch_scaling import PATCH_SCALING_ITERATIONS, PATCH_SCALING_TOLERANCE, settle_patch_sizes
from wrlayer.errors import ConvergenceError


def contraction(target, rate):
    """solve_at whose patch moves a fraction ``rate`` of the way from the given sizes to ``target``."""
    calls = []

    def solve_at(sizes):
        calls.append(sizes)
        new = {k: tuple(s + (1 - rate) * (t - s) for s, t in zip(sizes[k], target[k])) for k in sizes}
        return ("solved at", sizes), new

    return solve_at, calls


def test_settles_on_the_fixed_point_and_returns_the_result_at_the_returned_sizes():
    target = {0: (6.0, 4.0), 3: (2.0, 1.5)}
    solve_at, calls = contraction(target, 0.1)
    result, sizes, solves = settle_patch_sizes(solve_at, {0: (5.0, 5.0), 3: (3.0, 1.0)}, "case")
    assert result == ("solved at", sizes) and solves == len(calls) and solves >= 2
    for k in target:
        for s, t in zip(sizes[k], target[k]):
            assert s == pytest.approx(t, rel=2 * PATCH_SCALING_TOLERANCE)


def test_a_patch_that_does_not_settle_is_a_convergence_error_naming_the_case():
    solve_at, calls = contraction({0: (6.0, 4.0)}, 0.9)  # slow: 10 % of the way per solve
    with pytest.raises(ConvergenceError, match="my scene: the patch sizes did not settle within"):
        settle_patch_sizes(solve_at, {0: (1.0, 1.0)}, "my scene")
    assert len(calls) == PATCH_SCALING_ITERATIONS


def test_a_change_of_the_loaded_patches_is_not_settled():
    seen = []

    def solve_at(sizes):  # the second patch appears after the first solve, then both stay put
        seen.append(dict(sizes))
        return None, {0: (1.0, 1.0), 1: (2.0, 2.0)}

    _, sizes, solves = settle_patch_sizes(solve_at, {0: (1.0, 1.0)}, "case")
    assert solves == 2 and sizes.keys() == {0, 1}
