"""Every script in examples/ runs (in-process, output into a temporary folder) and its key number agrees with a
value found independently of the code that computed it: the paper's Table 1, Hertz's closed form, CONTACT, Johnson's
first-yield load, the written depth file, the README's worked example."""

from __future__ import annotations

import csv
import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.special import ellipe, ellipk

REPO = Path(__file__).resolve().parents[1]
EXAMPLES = REPO / "examples"


def load_example(name: str):
    """The example module ``examples/<name>.py``, imported under its own name (not run as __main__)."""
    spec = importlib.util.spec_from_file_location(f"examples_{name}", EXAMPLES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def hertz_peak_pressure_MPa(R_x_mm: float, R_y_mm: float, N: float, E_MPa: float, poisson: float) -> float:
    """Hertz's p_0 for the gap x^2/(2 R_x) + y^2/(2 R_y) between two bodies of one material (Johnson 1985,
    sec. 4.2): e from (B/A) = ((a/b)^2 E(e) - K(e)) / (K(e) - E(e)), then a^3 = 3 N (K - E) / (2 pi E* e^2 A)."""
    A, B = 1.0 / (2.0 * max(R_x_mm, R_y_mm)), 1.0 / (2.0 * min(R_x_mm, R_y_mm))
    e_star = E_MPa / (2.0 * (1.0 - poisson ** 2))

    def ratio_error(k):                                    # k = b / a, m = e^2 = 1 - k^2
        m = 1.0 - k * k
        return (ellipe(m) / (k * k) - ellipk(m)) / (ellipk(m) - ellipe(m)) - B / A

    k = brentq(ratio_error, 1e-3, 1.0 - 1e-9, xtol=1e-14)
    m = 1.0 - k * k
    a = (3.0 * N * (ellipk(m) - ellipe(m)) / (2.0 * math.pi * e_star * m * A)) ** (1.0 / 3.0)
    return 3.0 * N / (2.0 * math.pi * a * (k * a))


def test_ex01_paper_table1_approach_within_1_percent_of_the_paper(tmp_path):
    delta = load_example("ex01_paper_table1").main(tmp_path)
    assert delta == pytest.approx(0.127601, rel=0.01)               # paper, Table 1, "with Prandtl body"


def test_ex02_exact_solver_peak_pressure_is_hertz(tmp_path):
    p_max = load_example("ex02_hertz_check").main(tmp_path)
    hertz = hertz_peak_pressure_MPa(300.0, 80.0, 50e3, 210e3, 0.28)  # scenes/hertz_check.toml
    assert hertz == pytest.approx(1818.5, abs=0.1)                   # the scene's [reference]
    assert p_max == pytest.approx(hertz, rel=0.01)


def test_ex03_wheel_on_rail_peak_pressure_is_contacts(tmp_path):
    p_max = load_example("ex03_wheel_on_rail").main(tmp_path)
    with (REPO / "benchmarks" / "data" / "contact_mbench_a22.csv").open(encoding="utf-8") as fh:
        rows = list(csv.reader(line for line in fh if not line.startswith("#")))
    header = rows[0]
    case3 = next(r for r in rows[1:] if r[0] == "right" and r[1] == "3")
    assert p_max == pytest.approx(float(case3[header.index("pmax_MPa")]), rel=0.01)


@pytest.mark.slow
def test_ex04_calibration_first_yield_is_johnsons(tmp_path):
    p2 = load_example("ex04_calibration_position").main(tmp_path)
    # first yield (von Mises, nu = 0.3) of an axisymmetric Hertz contact: p_0 = 1.61 Y (Johnson 1985, eq. 3.45 /
    # Fig. 6.1); Y = 500 MPa; the crown's patch is nearly round (a/b = 1.3) and the mesh the coarsest
    assert p2 / 500.0 == pytest.approx(1.61, rel=0.03)
    assert (tmp_path / "calibration" / "rail_layer_table.json").is_file()


def test_ex05_worn_area_is_the_integral_of_the_written_depths(tmp_path):
    area = load_example("ex05_wear_step").main(tmp_path)
    data = np.genfromtxt(tmp_path / "wear" / "depth" / "step_001_right_wheel.csv", delimiter=",", names=True)
    integral = float(np.sum(0.5 * (data["wear_mm"][1:] + data["wear_mm"][:-1]) * np.diff(data["s_mm"])))
    assert area > 0.0 and area == pytest.approx(integral, rel=0.02)


def test_ex06_result_json_gives_the_readmes_peak_pressure(tmp_path):
    example = load_example("ex06_results_pandas")
    p_max = example.main(tmp_path)
    assert abs(p_max - 1517.0) <= 0.5                                # README, worked example: p_max 1517 MPa
    with_pandas = example.largest_p_max_per_side(tmp_path / "sweep" / "cases.csv")
    example.pd = None                                                # the standard-library path gives the same
    assert example.largest_p_max_per_side(tmp_path / "sweep" / "cases.csv") == pytest.approx(with_pandas)
    assert float(example.passes_table(tmp_path / "paper" / "result.json")[0]["p_max_MPa"]) == p_max
