"""bench_rolling_pass: the groove comparison of two passes and its table (no FEM run)."""

import pytest

from benchmarks.bench_rolling_pass import SAME_GROOVE_RTOL, groove_difference, markdown


def _run(depths, **over):
    return {"config": "calibration/configs/rolling_halfspace.toml", "level_py": 1.7, "length_factor": 2.0,
            "elements_per_semi_axis": 3.0, "substeps": 4, "n_dofs": 100, "steps": 37, "setup_cpu_s": 1.0,
            "setup_solves": 10, "pass_cpu_s": 2.0, "newton_iterations": 5, "cg_iterations": 20, "solves": 25,
            "factorisations": 1, "load_1min": [1.0, 1.2], "groove_mm": 0.005, "depth_along_mm": depths} | over


def test_groove_difference_is_relative_to_the_deepest_point():
    ref = _run([0.0, -0.004, -0.005, -0.001])
    assert groove_difference(ref, ref) == 0.0
    assert groove_difference(ref, _run([0.0, -0.004, -0.00501, -0.001])) == pytest.approx(2e-3)
    assert groove_difference(ref, _run([0.0, -0.004])) == float("inf")


def test_table_names_both_codes_and_the_limit():
    text = markdown({"abc1234": _run([0.0, -0.005]), "this revision": _run([0.0, -0.005], solves=20)}, 0.0)
    assert "| abc1234 |" in text and "| this revision |" in text and "| 20 |" in text
    assert f"{SAME_GROOVE_RTOL:.1e}" in text and "rolling_halfspace.toml" in text
