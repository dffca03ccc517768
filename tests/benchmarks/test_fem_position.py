"""bench_fem_position: the old-against-new comparison of an IndentationResult and the profiled phases exist."""

import pytest

from benchmarks.bench_fem_position import PHASES, RETURN_MAPPING, _code_key, max_relative_difference


def _result(**over):
    base = {"model": "3d", "p_MPa": [0.0, 100.0, 200.0], "u_fem_mm": [0.0, 0.01, 0.03],
            "u_pl_mm": [0.0, 0.0, 0.002], "residual_fem_mm": [0.001, 0.004],
            "reverse_plasticity_mm": [1e-18, -2e-18], "n_dofs": 100, "seconds": 3.0, "files": [],
            "linear_solves": 10, "u_pl_depth_mm": {"1": [0.0, 0.0, 0.001]}, "reference_depth_mm": None}
    return base | over


def test_identical_results_differ_by_nothing():
    assert max(max_relative_difference(_result(), _result()).values()) == 0.0


def test_a_change_is_relative_to_the_fields_largest_value():
    d = max_relative_difference(_result(), _result(u_pl_mm=[0.0, 0.0, 0.002 * (1 + 2e-6)]))
    assert d["u_pl_mm"] == pytest.approx(2e-6, rel=1e-6)
    d = max_relative_difference(_result(), _result(u_pl_depth_mm={"1": [0.0, 0.0, 0.0011]}))
    assert d["u_pl_depth_mm.1"] == pytest.approx(0.1)


def test_times_and_costs_are_not_compared_and_reverse_plasticity_is_relative_to_the_dents():
    d = max_relative_difference(_result(), _result(seconds=9.0, linear_solves=3,
                                                   reverse_plasticity_mm=[5e-18, 1e-17]))
    assert "seconds" not in d and "linear_solves" not in d
    assert d["reverse_plasticity_mm"] < 1e-13  # round-off against 4 um dents, not a 1000 % change


def test_a_missing_point_is_an_infinite_difference():
    assert max_relative_difference(_result(), _result(p_MPa=[0.0, 100.0]))["p_MPa"] == float("inf")


def test_every_profiled_phase_names_an_existing_function():
    for names in list(PHASES.values()) + [[RETURN_MAPPING]]:
        for name in names:
            path, line, fn = _code_key(name)
            assert path.endswith(".py") and line > 0 and fn == name.rsplit(".", 1)[-1].split(":")[-1]
