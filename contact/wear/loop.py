"""The wear loop: steps until the collective's distance is run (units mm, N, MPa, s; distances in km).

:func:`wear_steps` is a generator of :class:`~contact.wear.records.StepRecord`: each step is planned
(:mod:`contact.wear.planning`), solved and applied to the profiles (:mod:`contact.wear.step`), the state handed to
the next step (:mod:`contact.wear.state`), the layer tables recalibrated on the worn profiles when the scene asks
for it (:mod:`contact.wear.recalibrate`), and the record yielded at once, so that a consumer can write each step
as it completes (:func:`contact.run_files.run_wear_file` does) and a later failure keeps every completed step.
:func:`run_wear` runs the loop to its end.

A condition without contact, a solver failure, a profile that folds or a failed recalibration stops the loop with
an error naming the step; :class:`~contact.wear.records.WearStopped` carries the completed steps.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable, Iterator
from functools import partial
from pathlib import Path


from contact.wear.conicity import radius_difference
from contact.wear.recalibrate import recalibrate_sides
from contact.wear.records import StepRecord, WearRun, WearStopped
from contact.wear.runner import TaskRunner
from contact.wear.scene import MAX_STEPS, WearScene
from contact.wear.state import WearState
from contact.wear.step import wear_step
from wrlayer.errors import ConvergenceError, InputError, check_terminated
from wrlayer.progress import ProgressBar


class StepBars:
    """Progress bars on stderr: the steps of the run and the conditions of the current step."""

    def __init__(self, steps: int, tasks: int, quiet: bool):
        self.steps = ProgressBar(steps, "wear steps", "step", quiet, position=0)
        self.conditions = ProgressBar(tasks, "conditions", "cond", quiet, position=1, lines=False, leave=False)

    def step_started(self) -> None:
        self.conditions.reset()

    def condition_done(self, _result) -> None:
        check_terminated()  # a SIGTERM swallowed inside a condition's solver ends the run here
        self.conditions.update(1)

    def step_done(self, steps_done: int, more: bool) -> None:
        self.steps.grow_total(steps_done + (1 if more else 0))
        self.steps.update(1)

    def close(self) -> None:
        self.conditions.close()
        self.steps.close()


def start_run(scene: WearScene) -> WearRun:
    """A run before its first step: the scene's profiles on every simulated side and their rolling-radius
    difference."""
    profiles = scene.initial_profiles
    return WearRun(scene, profiles, radius_difference(profiles, scene.wheel_rail.layout,
                                                      scene.settings.conicity_amplitude_mm,
                                                      scene.wheel_rail.method.search))


def recalibrated(scene: WearScene, state: WearState, record: StepRecord, work_dir: Path | None
                 ) -> tuple[WearState, StepRecord]:
    """The state with the tables recalibrated on the profiles after ``record`` and the record noting it."""
    t0 = time.perf_counter()
    found, anchors = recalibrate_sides(scene.settings.recalibrate, state.profiles, record.index, work_dir,
                                       scene.settings.scheduler, state.anchors)
    tables = {**state.tables, **found}
    note = (f"layer tables recalibrated on the profiles after step {record.index} "
            f"({', '.join(sorted({f'{s} {b}' for s, b in tables}))})")
    record = dataclasses.replace(record, timings={**record.timings, "recalibration_s": time.perf_counter() - t0},
                                 notes=record.notes + (note,))
    return dataclasses.replace(state, tables=tables, anchors=anchors), record


def wear_steps(run: WearRun, work_dir: Path | None = None, show_progress: bool = True) -> Iterator[StepRecord]:
    """Run the loop of ``run.scene`` from ``run``'s initial profiles, appending each completed step to
    ``run.steps`` and yielding it. A recalibration ([wear.recalibrate]) due after a step runs when the next
    record is asked for (so a consumer has written the step before), and the step's record in ``run.steps`` is
    replaced by one that notes it. Raises :class:`WearStopped` naming the step on a failure (``run.stopped`` says
    why). ``work_dir``: where recalibrations put their files (default: a temporary folder)."""
    scene = run.scene
    recal = scene.settings.recalibrate
    state = WearState.initial(scene, run.initial_profiles)
    n_tasks = len(scene.collective.conditions) * len(state.profiles)
    with TaskRunner(scene.settings.workers, scene.settings.scheduler) as runner:  # a bad scheduler: before step 1
        bars = StepBars(scene.collective.steps, n_tasks, quiet=not show_progress)
        step = 1
        try:
            while state.unfinished(scene):
                check_terminated()
                step = state.steps_done + 1
                if step > MAX_STEPS:
                    raise InputError("wear.max_depth_per_step_mm", f"the step control needs more than {MAX_STEPS} "
                                     "steps for the distance (raise it, or shorten distance_km)")
                bars.step_started()
                record, history = wear_step(scene, state, partial(runner.map, on_done=bars.condition_done))
                state = state.after(record, history)
                run.steps.append(record)
                bars.step_done(len(run.steps), state.unfinished(scene))
                yield record
                if recal is not None and recal.due(step) and state.unfinished(scene):
                    state, run.steps[-1] = recalibrated(scene, state, record, work_dir)
        except (InputError, ConvergenceError) as err:
            run.stopped = f"step {step}: {err}"
            raise WearStopped(f"wear loop stopped at step {step} after {state.done_km:.6g} km ({len(run.steps)} "
                              f"completed steps kept): {err}", run) from None
        finally:
            bars.close()


def run_wear(scene: WearScene, on_step: Callable[[StepRecord, WearRun], None] | None = None,
             show_progress: bool = True, work_dir: Path | None = None) -> WearRun:
    """Run the loop to its end (see :func:`wear_steps`); ``on_step(record, run)`` is called after every completed
    step. Raises :class:`WearStopped` naming the step on a failure."""
    run = start_run(scene)
    for record in wear_steps(run, work_dir, show_progress):
        if on_step is not None:
            on_step(record, run)
    return run


__all__ = ["StepBars", "recalibrated", "run_wear", "start_run", "wear_steps"]
