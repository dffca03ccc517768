"""Rolling-radius difference and equivalent conicity (EN 15302): conical wheels on a round rail head, computed by
hand, and the wear run's columns."""

import csv
import json

import numpy as np
import pytest

from contact.__main__ import main
from contact.wear.conicity import radius_difference, rolling_radius
from contact.wheel_rail.track_geometry import TrackLayout
from meshes.profiles import S1002, Rail60E1, SplineProfile


def _cone(slope):
    """A conical tread z = slope * y (wheel frame: the radius r = r0 - z falls towards the field side)."""
    y = np.linspace(-40.0, 40.0, 81)
    return SplineProfile(y, slope * y, name=f"cone {slope:g}", body="wheel")


@pytest.mark.parametrize("slope", [0.025, 1.0 / 15.0])
@pytest.mark.parametrize("amplitude", [1.0, 3.0])
def test_cone_on_a_round_head_gives_its_slope(slope, amplitude):
    """By hand: on the rail's crown arc the contact stays where the rail's slope equals the cone's, so the wheel's
    contact point moves by the lateral displacement a and the rolling radius by slope x a, towards the flange on
    the wheel the wheelset moves towards: r_right(a) - r_left(a) = 2 slope a, quasi-conicity = slope."""
    wheel, rail, layout = _cone(slope), Rail60E1(), TrackLayout()
    got = radius_difference({"right": {"rail": rail, "wheel": wheel}}, layout, amplitude)
    assert got.delta_r_mm == pytest.approx(2.0 * slope * amplitude, rel=1e-7)
    assert got.quasi_conicity == pytest.approx(slope, rel=1e-7)
    centre = rolling_radius(rail, wheel, layout, "right", 0.0)
    assert got.r_right_mm - centre == pytest.approx(slope * amplitude, rel=1e-7)
    assert centre - got.r_left_mm == pytest.approx(slope * amplitude, rel=1e-7)


def test_one_side_stands_for_both_and_the_sides_are_used_as_given():
    """A side not simulated takes the other's profiles (mirror-symmetric wheelset); two sides: each its own."""
    layout = TrackLayout()
    s1002 = {"rail": Rail60E1(), "wheel": S1002()}
    right_only = radius_difference({"right": s1002}, layout, 3.0)
    both = radius_difference({"right": s1002, "left": dict(s1002)}, layout, 3.0)
    left_only = radius_difference({"left": s1002}, layout, 3.0)
    assert right_only == both == left_only
    assert right_only.delta_r_mm > 0  # S1002: the radius grows towards the flange
    cone = radius_difference({"right": s1002, "left": {"rail": Rail60E1(), "wheel": _cone(0.025)}}, layout, 3.0)
    assert cone.r_right_mm == right_only.r_right_mm
    assert cone.r_left_mm == pytest.approx(rolling_radius(Rail60E1(), _cone(0.025), layout, "left", 3.0))


@pytest.mark.parametrize("slope", [0.025, 1.0 / 15.0])
def test_equivalent_conicity_of_a_cone_is_its_slope(slope):
    """By hand: within the rail's crown arc Delta r(y) = 2 slope y exactly (test above), and the harmonic
    linearisation of a linear Delta r = 2 gamma y is gamma: (1/(2 pi A)) int 2 gamma A sin^2 = gamma."""
    got = radius_difference({"right": {"rail": Rail60E1(), "wheel": _cone(slope)}}, TrackLayout(), 3.0)
    assert got.equivalent_conicity == pytest.approx(slope, rel=1e-7)
    assert got.amplitude_mm == 3.0


def test_equivalent_conicity_of_two_different_cones_drops_the_offset():
    """By hand: right cone s1, left cone s2: r_right = c1 + s1 y, r_left = c2 - s2 y, so Delta r = (c1 - c2) +
    (s1 + s2) y. The harmonic linearisation drops the constant: gamma_e = (s1 + s2) / 2, while the
    quasi-conicity Delta r(A) / (2 A) keeps the offset (c1 - c2) / (2 A)."""
    s1, s2, layout = 0.025, 0.05, TrackLayout()
    profiles = {"right": {"rail": Rail60E1(), "wheel": _cone(s1)}, "left": {"rail": Rail60E1(), "wheel": _cone(s2)}}
    got = radius_difference(profiles, layout, 2.0)
    assert got.equivalent_conicity == pytest.approx(0.5 * (s1 + s2), rel=1e-7)
    offset = rolling_radius(Rail60E1(), _cone(s1), layout, "right", 0.0) - \
        rolling_radius(Rail60E1(), _cone(s2), layout, "left", 0.0)
    assert abs(offset) > 1e-3  # the two cones touch their rails at different radii
    assert got.quasi_conicity == pytest.approx(0.5 * (s1 + s2) + offset / 4.0, rel=1e-7)


def test_equivalent_conicity_of_s1002_is_the_harmonic_mean_of_its_delta_r():
    """S1002 on 60E1 1:40, gauge 1435: the wired value equals the harmonic linearisation of the same Delta r
    sampled by hand (the mirrored wheelset: Delta r(y) = r_right(y) - r_right(-y) on 0.1 mm samples, linear between
    them, 720 points in phi), and lies in the range published for this pair at 3 mm (0.1 ... 0.3)."""
    layout = TrackLayout()
    s1002 = {"right": {"rail": Rail60E1(), "wheel": S1002()}}
    got = radius_difference(s1002, layout, 3.0)
    y = np.linspace(-3.0, 3.0, 61)
    r = np.array([rolling_radius(Rail60E1(), S1002(), layout, "right", a) for a in y])
    dr = r - r[::-1]
    phi = np.linspace(0.0, 2.0 * np.pi, 721)[:-1]
    by_hand = np.mean(np.interp(3.0 * np.sin(phi), y, dr) * np.sin(phi)) / 3.0
    assert got.equivalent_conicity == pytest.approx(by_hand, abs=1e-3)  # measured 9e-5
    assert 0.1 < got.equivalent_conicity < 0.3


def test_wear_run_reports_equivalent_conicity_per_step(tmp_path, wear_dict, write_scene):
    """steps.csv keeps its columns and adds equivalent_conicity and conicity_amplitude_mm; result.json carries the
    same numbers per step and for the initial profiles (S1002/60E1: the value of the direct call)."""
    data = wear_dict(layers=None, wear={"distance_km": 20.0, "steps": 1, "inelastic": False,
                                        "conicity_amplitude_mm": 2.5})
    out = tmp_path / "out"
    assert main(["wear", str(write_scene(data)), "--out", str(out), "--quiet"]) == 0
    rows = list(csv.DictReader((out / "steps.csv").open()))
    assert list(rows[0])[-4:] == ["delta_r_mm", "quasi_conicity", "equivalent_conicity", "conicity_amplitude_mm"]
    res = json.loads((out / "result.json").read_text())
    step = res["steps"][0]["conicity"]
    assert float(rows[0]["equivalent_conicity"]) == pytest.approx(step["equivalent_conicity"], rel=1e-8)
    assert float(rows[0]["conicity_amplitude_mm"]) == step["amplitude_mm"] == 2.5
    initial = radius_difference({"right": {"rail": Rail60E1(), "wheel": S1002()}}, TrackLayout(), 2.5)
    assert res["initial"]["conicity"]["equivalent_conicity"] == pytest.approx(initial.equivalent_conicity, rel=1e-12)
    assert 0.1 < step["equivalent_conicity"] < 0.3
