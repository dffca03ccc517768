"""Load collective: weights, validation of every condition, the nominal step."""

import math

import pytest

from contact.wear.collective import WEIGHT_SUM_TOL, Condition, LoadCollective
from wrlayer.errors import InputError


def _cond(**over):
    kw = {"lateral_mm": 0.0, "yaw_rad": 0.0, "vertical_load_N": 60000.0, "speed_mm_s": 2000.0, "weight": 1.0}
    return Condition(**{**kw, **over})


def test_weights_summing_to_one_within_the_tolerance_are_accepted():
    conds = tuple(_cond(lateral_mm=y, weight=w) for y, w in ((-3.0, 0.15), (0.0, 0.7), (3.0, 0.15)))
    col = LoadCollective(conds, 3000.0, 3)
    assert col.nominal_step_km == pytest.approx(1000.0)
    assert sum(c.weight for c in col.conditions) == pytest.approx(1.0)
    third = LoadCollective(tuple(_cond(weight=1.0 / 3.0) for _ in range(3)), 10.0, 1)  # 1/3 x 3 rounds off
    assert len(third.conditions) == 3
    nudged = (_cond(weight=0.5), _cond(weight=0.5 + 0.5 * WEIGHT_SUM_TOL))
    assert LoadCollective(nudged, 1.0, 1).steps == 1


@pytest.mark.parametrize("conds, match", [
    ((), r"collective.conditions: needs at least one"),
    ((_cond(weight=0.5), _cond(weight=0.6)), r"collective.weights: must sum to 1, they sum to 1.1"),
    ((_cond(weight=0.5), _cond(weight=0.5 + 3 * WEIGHT_SUM_TOL)), r"must sum to 1"),
    ((_cond(weight=0.0), _cond(weight=1.0)), r"conditions\[0\].weight: must be > 0"),
    ((_cond(weight=math.nan),), r"conditions\[0\].weight"),
    ((_cond(vertical_load_N=0.0),), r"conditions\[0\].vertical_load_N: must be > 0"),
    ((_cond(speed_mm_s=-1.0),), r"conditions\[0\].speed_mm_s: must be > 0"),
    ((_cond(yaw_rad=0.25),), r"conditions\[0\].yaw_rad: \|yaw\| must be < 0.2 rad"),
])
def test_bad_conditions_name_the_condition(conds, match):
    with pytest.raises(InputError, match=match):
        LoadCollective(conds, 100.0, 1)


@pytest.mark.parametrize("distance, steps, match", [
    (0.0, 1, r"wear.distance_km: must be a positive distance"),
    (math.inf, 1, r"wear.distance_km"),
    (100.0, 0, r"wear.steps: must be an integer >= 1"),
    (100.0, 2.0, r"wear.steps"),
])
def test_bad_distance_or_steps(distance, steps, match):
    with pytest.raises(InputError, match=match):
        LoadCollective((_cond(),), distance, steps)


def test_condition_describes_itself():
    assert _cond(label="curve").describe() == "curve"
    assert _cond(lateral_mm=2.0, yaw_rad=0.002).describe() == "lateral 2 mm, yaw 0.002 rad, 60000 N, 2000 mm/s"


def test_scene_sweep_weights(make_scene):
    """A sweep collective: "uniform" weights, the scene's load and speed for every condition."""
    col = make_scene(collective={"lateral_mm": {"start": -2.0, "stop": 2.0, "step": 1.0}, "yaw_rad": 0.001,
                                 "weights": "uniform"}).collective
    assert [c.lateral_mm for c in col.conditions] == [-2.0, -1.0, 0.0, 1.0, 2.0]
    assert all(c.weight == pytest.approx(0.2) and c.yaw_rad == 0.001 for c in col.conditions)
    assert all(c.vertical_load_N == 40000.0 and c.speed_mm_s == 2000.0 for c in col.conditions)
