"""Where the conditions of a step are solved: the shared runner (:mod:`wrlayer.runner`) applied to the wear's
condition tasks: in-process, on local worker processes or on a Dask cluster.

The tasks (:class:`contact.wear.condition.ConditionTask`) are picklable and independent; results come back in task
order. The pool or the Dask client is created once and kept for all steps of a run.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Self

from contact.wear import condition as condition_module
from contact.wear.condition import ConditionResult, ConditionTask
from wrlayer.runner import Runner


def solve_condition(task: ConditionTask) -> ConditionResult:
    """:func:`contact.wear.condition.solve_condition` (looked up at call time, so tests can replace it)."""
    return condition_module.solve_condition(task)


class TaskRunner:
    """Runs condition tasks with :class:`wrlayer.runner.Runner` (in-process for workers = 1, local processes that
    end with their parent and share the cores' BLAS threads, or the Dask cluster of ``scheduler``, the same option
    as calibration's). Use as a context manager: the pool or client is kept for all steps of a run."""

    def __init__(self, workers: int = 1, scheduler: str = ""):
        self.workers, self.scheduler = int(workers), scheduler
        self._runner = Runner(workers, scheduler, what="wear.scheduler")

    def __enter__(self) -> Self:
        self._runner.__enter__()
        return self

    def __exit__(self, *exc) -> None:
        self._runner.__exit__(*exc)

    def map(self, tasks: list[ConditionTask], on_done: Callable[[ConditionResult], None] | None = None
            ) -> list[ConditionResult]:
        """Results in task order; the first failure is re-raised."""
        return self._runner.map(solve_condition, tasks, on_done)


def map_tasks(tasks: list[ConditionTask], workers: int = 1, scheduler: str = "",
              on_done: Callable[[ConditionResult], None] | None = None) -> list[ConditionResult]:
    """Solve the tasks once (see :class:`TaskRunner`)."""
    with TaskRunner(workers, scheduler) as runner:
        return runner.map(tasks, on_done)


__all__ = ["TaskRunner", "map_tasks", "solve_condition"]
