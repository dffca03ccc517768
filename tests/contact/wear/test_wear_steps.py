"""The step loop's parts: step planning, body statistics, the layer state handed on, the generator of records."""

import dataclasses
import math

import numpy as np
import pytest

from contact.wear.condition import ConditionResult
from contact.wear.layer_state import raised_history, virgin_history
from contact.wear.loop import run_wear, start_run, wear_steps
from contact.wear.planning import (MAX_STEP_FACTOR, controlled_length, nominal_length_km, passes_per_km,
                                   wheelset_roll)
from contact.wear.profile_grid import ArcGrid
from contact.wear.records import StepRecord
from contact.wear.state import WearState
from contact.wear.statistics import body_stats
from contact.wheel_rail.deformed import rigid_roll
from contact.wheel_rail.track_geometry import WheelsetPose, place_rail
from meshes.profiles import S1002, Rail60E1
from wrlayer.errors import InputError


def test_passes_per_km(make_scene):
    per_km = passes_per_km(make_scene(wear={"rail_passes_per_wheel_pass": 2.5}))
    assert per_km["wheel"] == pytest.approx(1e6 / (2 * math.pi * 460.0), rel=1e-15)
    assert per_km["rail"] == pytest.approx(2.5 * per_km["wheel"], rel=1e-15)


def test_nominal_length_shares_the_remaining_distance(make_scene):
    col = make_scene(wear={"distance_km": 300.0, "steps": 3}).collective
    assert nominal_length_km(col, 0.0, 0) == 100.0
    assert nominal_length_km(col, 50.0, 1) == 125.0  # a shortened first step: the rest over two steps
    assert nominal_length_km(col, 290.0, 5) == pytest.approx(10.0)  # past the nominal steps: the rest at once
    with pytest.raises(InputError, match=rf"step {3 * MAX_STEP_FACTOR + 1}: the step control needs more"):
        nominal_length_km(col, 290.0, 3 * MAX_STEP_FACTOR)


def test_step_control():
    assert controlled_length(100.0, 1e-4, 0.0, 0.1) == (100.0, ())
    length, notes = controlled_length(100.0, 2e-3, 0.0, 0.1)
    assert length == pytest.approx(50.0) and "shortened from 100 km to 50 km (max wear depth 0.2 mm" in notes[0]
    length, notes = controlled_length(100.0, 1e-4, 0.3, 0.1)
    assert length == 100.0 and "inelastic increment 0.3 mm exceeds" in notes[0]


@pytest.mark.parametrize("body, around_mm, key", [("wheel", 2 * math.pi * 460.0, "mass_loss_g_per_km"),
                                                  ("rail", 1000.0, "mass_loss_g_per_m_rail_per_km")])
def test_body_stats_by_hand(body, around_mm, key):
    """A uniform depth d: area d x arc length, mass = area x (circumference or 1 m) x density, per km."""
    grid = ArcGrid.of(S1002() if body == "wheel" else Rail60E1(), 0.2)
    wear = np.full(grid.s_mm.size, 0.01)
    inel = np.zeros(grid.s_mm.size)
    inel[7] = 0.002
    st = body_stats(grid, wear, inel, 50.0, body, 460.0, 7850.0)
    length = grid.profile.length
    assert st.worn_area_mm2 == pytest.approx(0.01 * length, rel=1e-12)
    assert (st.wear_max_mm, st.inelastic_max_mm, st.inelastic_max_y_mm) == (0.01, 0.002, grid.y_mm[7])
    assert st.mass_loss == pytest.approx(0.01 * length * around_mm * 7850.0 * 1e-6 / 50.0, rel=1e-12)
    d = st.to_dict()
    assert list(d)[-1] == key and d[key] == st.mass_loss and "body" not in d


def test_wheelset_roll_is_the_rigid_roll(make_scene):
    """One side: rigid_roll itself; two sides with the same profiles: the same root."""
    scene = make_scene(wheel={"side": "both"}, wheelset={"roll_rad": "auto"})
    layout, search = scene.wheel_rail.layout, scene.wheel_rail.method.search
    pr = {"rail": scene.wheel_rail.rail_profile, "wheel": scene.wheel_rail.wheel_profile}
    pose = WheelsetPose(4.0, 0.001, 0.0)
    expected = rigid_roll(place_rail(pr["rail"], layout), pr["wheel"], layout, pose, search)
    assert expected != 0.0
    assert wheelset_roll(scene, {"right": pr}, pose) == expected
    assert wheelset_roll(scene, {"right": pr, "left": dict(pr)}, pose) == pytest.approx(expected, abs=1e-12)


def test_raised_history_keeps_the_largest_pressure_and_leaves_its_input():
    profiles = {"right": {"rail": Rail60E1(), "wheel": S1002()}}
    before = virgin_history(profiles, 0.5)
    res = ConditionResult(0, "right", 0.1,
                          peaks={"rail": [(np.array([2.0, -2.0, 0.0]), np.array([100.0, 300.0, 500.0]))]})
    after = raised_history(before, [res])
    y, p = after["right", "rail"]
    inside = (y >= -2.0) & (y <= 2.0)
    assert np.all(p[inside] > 0) and np.all(p[~inside] == 0) and p.max() <= 500.0
    assert np.all(before["right", "rail"][1] == 0) and np.all(after["right", "wheel"][1] == 0)
    again = raised_history(after, [dataclasses.replace(res, peaks={"rail": [(np.array([-1.0, 1.0]),
                                                                               np.array([50.0, 50.0]))]})])
    assert np.array_equal(again["right", "rail"][1], p)  # a lower load leaves the history


def test_the_loop_yields_each_step_as_it_completes(make_scene):
    scene = make_scene(layers=None, wear={"distance_km": 30.0, "steps": 3, "inelastic": False})
    run = start_run(scene)
    steps = wear_steps(run, show_progress=False)
    first = next(steps)
    assert isinstance(first, StepRecord) and first.index == 1 and run.steps == [first]
    with pytest.raises(dataclasses.FrozenInstanceError):
        first.length_km = 0.0
    rest = list(steps)
    assert [r.index for r in rest] == [2, 3] and run.steps == [first, *rest]
    assert [r.start_km for r in run.steps] == pytest.approx([0.0, 10.0, 20.0])
    assert run.steps[-1].end_km == pytest.approx(30.0) and run.stopped is None
    again = run_wear(scene, show_progress=False)
    for a, b in zip(run.steps, again.steps):
        assert np.array_equal(a.bodies["right", "wheel"].wear_mm, b.bodies["right", "wheel"].wear_mm)


def test_state_after_a_step(make_scene):
    scene = make_scene(layers=None, wear={"distance_km": 30.0, "steps": 3, "inelastic": False})
    run = start_run(scene)
    state = WearState.initial(scene, run.initial_profiles)
    record = next(wear_steps(run, show_progress=False))
    history = virgin_history(record.profiles, 0.2)
    after = state.after(record, history)
    assert (after.steps_done, after.done_km, after.profiles, after.history) == (1, 10.0, record.profiles, history)
    assert after.unfinished(scene) and not dataclasses.replace(after, done_km=30.0).unfinished(scene)
    assert record.layer_state == {}  # kept only in the hardening mode with the inelastic part
