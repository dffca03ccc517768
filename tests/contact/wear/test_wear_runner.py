"""Where a step's conditions run: in-process results in task order, progress per task, the first failure."""

from types import SimpleNamespace

import numpy as np
import pytest

from contact.wear import condition as condition_mod
from contact.wear.condition import ConditionResult
from contact.wear.planning import build_tasks
from contact.wear.runner import TaskRunner, map_tasks
from wrlayer.errors import InputError


def _fake_solve(task):
    if task.index == 99:
        raise InputError(f"step {task.step}, condition {task.index}", "synthetic failure")
    return ConditionResult(task.index, task.side, 0.1, seconds=float(task.index))


def _tasks(*indices):
    return [SimpleNamespace(index=k, side=side, step=1) for k in indices for side in ("right", "left")]


def test_in_process_results_come_in_task_order(monkeypatch):
    monkeypatch.setattr(condition_mod, "solve_condition", _fake_solve)
    done = []
    results = map_tasks(_tasks(2, 0, 1), on_done=done.append)
    assert [(r.index, r.side) for r in results] == [(k, s) for k in (2, 0, 1) for s in ("right", "left")]
    assert [(r.index, r.side) for r in done] == [(r.index, r.side) for r in results]


def test_one_task_on_a_pool_runs_in_process(monkeypatch):
    """workers > 1 with a single task: no process is started for it (the monkeypatched solver is used)."""
    monkeypatch.setattr(condition_mod, "solve_condition", _fake_solve)
    with TaskRunner(workers=2) as runner:
        (res,) = runner.map([SimpleNamespace(index=4, side="right", step=1)])
    assert res.seconds == 4.0


def test_the_first_failure_is_raised(monkeypatch):
    monkeypatch.setattr(condition_mod, "solve_condition", _fake_solve)
    with pytest.raises(InputError, match="condition 99: synthetic failure"):
        map_tasks(_tasks(0, 99, 1))


def test_real_conditions_in_process(make_scene):
    """Two real conditions on one side: a wear depth per strip for both bodies, strips on the profiles."""
    scene = make_scene(layers=None, wear={"inelastic": False},
                       collective={"lateral_mm": [1.0, 3.0], "weights": "uniform"})
    profiles = {"right": {"rail": scene.wheel_rail.rail_profile, "wheel": scene.wheel_rail.wheel_profile}}
    results = map_tasks(build_tasks(scene, profiles, 1, 10.0))
    assert [r.index for r in results] == [0, 1]
    for r in results:
        for body in ("wheel", "rail"):
            assert r.wear_mm[body].size == r.y_mm[body].size > 0 and np.max(r.wear_mm[body]) > 0
            prof = profiles["right"][body]
            assert np.all((r.y_mm[body] >= prof.y_min) & (r.y_mm[body] <= prof.y_max))
