"""Profiles read from files are checked for plausibility: units, orientation, spikes and steps."""

import numpy as np
import pytest

from meshes.profiles import get_profile
from meshes.profiles.plausibility import ImplausibleProfile, check_profile_points
from wrlayer.errors import InputError


def points(name: str, ds: float = 0.5):
    p = get_profile(name)
    y, z = p.sample(ds)
    return np.asarray(y), np.asarray(z), p.body


@pytest.mark.parametrize("name", ["S1002", "60E1", "54E1"])
def test_standard_sections_pass(name):
    check_profile_points(*points(name), what=name)


def test_reference_files_pass(reference_dir):
    for f in ("MBench_UIC60_v3.prr", "MBench_S1002_v3.prw"):
        p = get_profile(str(reference_dir / "profiles" / f))
        check_profile_points(p.points[:, 0], p.points[:, 1], p.body, f)


def test_metres_refused():
    y, z, body = points("60E1")
    with pytest.raises(ImplausibleProfile, match="spans only 0.072 mm.*metres"):
        check_profile_points(y / 1000.0, z / 1000.0, body, "rail.txt")


def test_micrometres_refused():
    y, z, body = points("S1002")
    with pytest.raises(ImplausibleProfile, match="micrometres"):
        check_profile_points(y * 1000.0, z * 1000.0, body, "wheel.txt")


def test_upside_down_rail_and_wheel_refused():
    y, z, body = points("60E1")
    with pytest.raises(ImplausibleProfile, match="upside down"):
        check_profile_points(y, -z, body, "rail.txt")
    y, z, body = points("S1002")
    with pytest.raises(ImplausibleProfile, match="upside down"):
        check_profile_points(y, -z, body, "wheel.txt")


def test_mirrored_wheel_refused():
    y, z, body = points("S1002")
    with pytest.raises(ImplausibleProfile, match=r"flange .* on the \+y side"):
        check_profile_points(-y[::-1], z[::-1], body, "wheel.txt")


def test_one_metre_spike_refused():
    y, z, body = points("60E1")
    z = z.copy()
    z[40] += 1000.0
    with pytest.raises(ImplausibleProfile, match="spike"):
        check_profile_points(y, z, body, "rail.txt")


def test_near_vertical_step_refused():
    y = np.concatenate([np.linspace(-35.0, 0.0, 351), np.linspace(0.001, 35.0, 350)])
    z = -(y ** 2) / 100.0 - np.where(y > 0.0005, 0.5, 0.0)
    with pytest.raises(ImplausibleProfile, match=r"turns by \d+ degrees at point 351 .* a step"):
        check_profile_points(y, z, "rail", "rail.txt")


def test_message_names_file_and_switch():
    y, z, body = points("60E1")
    with pytest.raises(InputError) as err:
        check_profile_points(y, -z, body, "rail.txt")
    assert str(err.value).startswith("rail.txt: ")
    assert "accept_unusual_profile" in str(err.value)
