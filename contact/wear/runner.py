"""Where the conditions of a step are solved: in-process, on a pool of local processes or on a Dask cluster.

The tasks (:class:`contact.wear.condition.ConditionTask`) are picklable and independent; results come back in task
order. The pool or the Dask client is created once and kept for all steps of a run.
"""

from __future__ import annotations

import concurrent.futures as cf
from collections.abc import Callable
from typing import Self

from contact.wear import condition as _condition
from contact.wear.condition import ConditionResult, ConditionTask
from wrlayer.errors import InputError


def solve_condition(task: ConditionTask) -> ConditionResult:
    """:func:`contact.wear.condition.solve_condition` (looked up at call time, so tests can replace it)."""
    return _condition.solve_condition(task)


class TaskRunner:
    """Runs condition tasks in-process (workers = 1), on a pool of local processes (spawn; kept for all steps) or
    on a Dask cluster (``scheduler`` address, the same option as calibration; one thread per worker is the
    cluster's setting; the client is kept for all steps). Use as a context manager."""

    def __init__(self, workers: int = 1, scheduler: str = ""):
        self.workers, self.scheduler = int(workers), scheduler
        self._pool = self._client = None

    def __enter__(self) -> Self:
        if self.scheduler:
            try:
                from distributed import Client
            except ImportError:
                raise InputError("wear.scheduler", "needs the 'distributed' package (pip install "
                                 "dask[distributed])") from None
            try:
                self._client = Client(self.scheduler, timeout="20s")
            except (OSError, TimeoutError, ValueError) as err:
                raise InputError("wear.scheduler", f"cannot connect to the Dask scheduler {self.scheduler!r}: "
                                 f"{err}") from None
        elif self.workers > 1:
            import multiprocessing as mp

            self._pool = cf.ProcessPoolExecutor(max_workers=self.workers, mp_context=mp.get_context("spawn"))
        return self

    def __exit__(self, *exc) -> None:
        if self._client is not None:
            self._client.close()
        if self._pool is not None:
            self._pool.shutdown(cancel_futures=True)

    def map(self, tasks: list[ConditionTask], on_done: Callable[[ConditionResult], None] | None = None
            ) -> list[ConditionResult]:
        """Results in task order; the first failure is re-raised."""
        done: dict[int, ConditionResult] = {}
        id_of = {(t.index, t.side): k for k, t in enumerate(tasks)}

        def finish(res: ConditionResult):
            done[id_of[res.index, res.side]] = res
            if on_done is not None:
                on_done(res)

        if self._client is not None:
            from distributed import as_completed

            for fut in as_completed([self._client.submit(solve_condition, t, pure=False) for t in tasks]):
                finish(fut.result())
        elif self._pool is not None and len(tasks) > 1:
            for fut in cf.as_completed([self._pool.submit(solve_condition, t) for t in tasks]):
                finish(fut.result())
        else:
            for t in tasks:
                finish(solve_condition(t))
        return [done[k] for k in range(len(tasks))]


def map_tasks(tasks: list[ConditionTask], workers: int = 1, scheduler: str = "",
              on_done: Callable[[ConditionResult], None] | None = None) -> list[ConditionResult]:
    """Solve the tasks once (see :class:`TaskRunner`)."""
    with TaskRunner(workers, scheduler) as runner:
        return runner.map(tasks, on_done)


__all__ = ["TaskRunner", "map_tasks", "solve_condition"]
