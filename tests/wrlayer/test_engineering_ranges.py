"""wrlayer.plausibility: unit slips are named, the override passes them, result warnings name value and range."""

import math

import pytest

from wrlayer.errors import InputError
from wrlayer.plausibility import INPUT_RANGES, ImplausibleInput, check_input, result_warnings


@pytest.mark.parametrize("key, value, quantity, slip", [
    ("material.E_MPa", 210.0, "E_MPa", "GPa typed as MPa"),
    ("material.G_MPa", 82.0, "G_MPa", "GPa typed as MPa"),
    ("separation.lateral_radius_mm", 0.08, "profile_radius_mm", "metres typed as millimetres"),
    ("wheel.nominal_radius_mm", 0.46, "wheel_radius_mm", "metres typed as millimetres"),
    ("load.normal_force_N", 100.0e6, "normal_force_N", "a factor 1000 too large"),
    ("load.normal_force_N", 50.0, "normal_force_N", "kN typed as N"),
    ("run.speed_mm_s", 30.0e6, "speed_mm_s", None),
])
def test_slips_are_refused_naming_key_value_range_and_slip(key, value, quantity, slip):
    with pytest.raises(ImplausibleInput) as err:
        check_input(key, value, quantity)
    text = str(err.value)
    assert isinstance(err.value, InputError) and text.startswith(f"{key}: {value:g} ")
    rng = INPUT_RANGES[quantity]
    assert f"{rng.low:g}..{rng.high:g} {rng.unit}" in text and "\n" not in text
    if slip is not None:
        assert slip in text
    else:
        assert "accept_implausible" in text


def test_plausible_values_and_the_override_pass():
    assert check_input("material.E_MPa", 210000.0, "E_MPa") == 210000.0
    assert check_input("separation.lateral_radius_mm", -31.7, "profile_radius_mm") == -31.7   # concave: magnitude
    assert check_input("material.E_MPa", 3000.0, "E_MPa", accept=True) == 3000.0
    with pytest.raises(ImplausibleInput):
        check_input("material.poisson", math.nan, "poisson")


def test_result_warnings_name_where_value_and_range():
    assert result_warnings("paper_with_layer", {"p_max_MPa": 1517.0, "approach_mm": 0.12}) == []
    lines = result_warnings("scene x, pass 1", {"p_max_MPa": 16.6, "approach_mm": 8.4, "semi_axis_mm": 5.0})
    assert len(lines) == 2 and all(line.startswith("warning: scene x, pass 1: ") for line in lines)
    assert "p_max_MPa = 16.6 MPa" in lines[0] and "50..6000 MPa" in lines[0]
