"""One parallel runner for independent, picklable tasks: in-process, local worker processes or a Dask cluster.

Used by the calibration (one task per profile position) and by the wear loop (one task per load condition)::

    with Runner(workers=2) as runner:                     # or Runner(scheduler="tcp://host:8786"), Runner(1)
        for index, result in runner.imap(solve, tasks, on_progress=bar.update):
            ...                                           # completion order; tasks[index] gave result

- **in-process** (``workers = 1``, or a single task): the tasks run one after the other in this process;
- **local processes** (``workers > 1``): a spawn pool created once per ``with`` block. Each worker ends with its
  parent (Linux ``PR_SET_PDEATHSIG`` plus a watchdog thread on every platform), so a killed run (``kill -9``)
  leaves no worker computing; the BLAS/MKL/OpenMP pools of each worker are limited to ``blas_threads`` (default:
  the machine's cores shared evenly, :func:`blas_threads_per_worker`): measured on 2 cores, one 3D calibration
  position takes 3-6x longer when the workers' BLAS threads oversubscribe the cores;
- **Dask** (``scheduler`` address): a client connected once per ``with`` block; one BLAS thread per task (a Dask
  worker runs as many tasks as it has threads).

A scheduler address is checked when the runner is made (:func:`check_scheduler_address`: ``tcp://``, ``tls://``,
``ucx://``, ``ws://``, ``wss://``, ``inproc://`` or a bare ``host:port``), without contacting the scheduler, so a
mistyped address fails before the first task, with one line naming the input.

A task reports progress inside itself with :func:`report_progress`; the runner forwards it to ``on_progress``
(in-process and local processes; on Dask, :attr:`Runner.streams_progress` is False and the caller counts whole
tasks). On an exception, ``KeyboardInterrupt`` or SIGTERM (:class:`wrlayer.errors.Terminated`, raised in the main
thread while a runner is open) the workers are ended at once, without waiting for their tasks.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import multiprocessing as mp
import numbers
import os
import signal
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from typing import Any, Self, TypeVar

from wrlayer.errors import InputError, Terminated

T = TypeVar("T")
R = TypeVar("R")

#: Environment variables of the BLAS/LAPACK/OpenMP thread pools (read when a library is loaded).
THREAD_VARIABLES = ("OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS", "NUMBA_NUM_THREADS")
#: Seconds between two looks at the local workers' progress queue while waiting for results.
POLL_S = 0.5
#: Seconds between two checks of a worker's watchdog that its parent is still alive.
WATCHDOG_S = 1.0


def blas_threads_per_worker(workers: int) -> int:
    """BLAS threads per worker process: the machine's cores shared evenly (at least 1)."""
    return max(1, (os.cpu_count() or 1) // max(1, int(workers)))


def limited_threads(n: int):
    """Context limiting the BLAS/MKL/OpenMP pools loaded in this process to ``n`` threads (threadpoolctl). A
    library loaded later is limited by :data:`THREAD_VARIABLES` only (set for the workers before they start)."""
    from threadpoolctl import threadpool_limits  # only where threads are limited: the wear scenes do not need it

    return threadpool_limits(limits=max(1, int(n)))


@contextlib.contextmanager
def thread_environment(n: int):
    """Set :data:`THREAD_VARIABLES` to ``n`` while worker processes are spawned (they read them before numpy/MKL
    load), then restore this process's environment."""
    old = {var: os.environ.get(var) for var in THREAD_VARIABLES}
    os.environ.update({var: str(max(1, int(n))) for var in THREAD_VARIABLES})
    try:
        yield
    finally:
        for var, value in old.items():
            if value is None:
                os.environ.pop(var, None)
            else:
                os.environ[var] = value


#: Where :func:`report_progress` sends its counts: the local worker's queue, the in-process callback, or None.
_progress_sink: Callable[[int], Any] | None = None


def report_progress(n: int = 1) -> None:
    """Called inside a task: ``n`` more steps of it are done (forwarded to the runner's ``on_progress``; a no-op
    where nobody listens, e.g. on Dask)."""
    if _progress_sink is not None:
        _progress_sink(n)


def worker_lifeline(parent_pid: int, progress_queue=None) -> None:
    """Initializer of a local worker process: the worker ends with its parent, and sends its progress to
    ``progress_queue``.

    On Linux the kernel sends SIGKILL to the worker when the parent dies (``prctl(PR_SET_PDEATHSIG)``); on every
    platform a daemon thread checks once a second that the parent is still there and exits the worker otherwise.
    So a killed run (``kill -9``) leaves no worker computing and holding the caller's pipes open."""
    global _progress_sink
    _progress_sink = None if progress_queue is None else progress_queue.put
    try:
        import ctypes  # Linux only; elsewhere the watchdog alone ends the worker

        libc = ctypes.CDLL("libc.so.6", use_errno=True)
        libc.prctl(1, int(signal.SIGKILL), 0, 0, 0)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass
    if os.getppid() != parent_pid:  # the parent died before the line above took effect
        os._exit(1)

    def watch():
        while True:
            time.sleep(WATCHDOG_S)
            if os.getppid() != parent_pid:
                os._exit(1)

    threading.Thread(target=watch, name="parent-watchdog", daemon=True).start()


def call_limited(fn: Callable[[T], R], task: T, blas_threads: int) -> R:
    """``fn(task)`` with the BLAS pools of this process limited to ``blas_threads`` (what a worker runs)."""
    with limited_threads(blas_threads):
        return fn(task)


#: Address schemes of the Dask communication layer.
SCHEDULER_SCHEMES = ("tcp", "tls", "ucx", "ws", "wss", "inproc")


def _host_port(rest: str, address: str, what: str) -> None:
    """InputError unless ``rest`` is ``host``, ``host:port`` or ``[ipv6]:port`` (port 1..65535)."""
    host, port = rest, ""
    if rest.startswith("["):
        host, _, tail = rest[1:].partition("]")
        if tail and not tail.startswith(":"):
            raise InputError(what, f"{address!r} is not a scheduler address ([ipv6]:port)")
        port = tail[1:]
    elif ":" in rest:
        host, _, port = rest.rpartition(":")
    if not host or any(c in host for c in "/?#@ ") or ":" in host and not rest.startswith("["):
        raise InputError(what, f"{address!r} is not a scheduler address (host:port, e.g. tcp://10.0.0.5:8786)")
    if port and not (port.isdigit() and 1 <= int(port) <= 65535):
        raise InputError(what, f"{address!r}: the port must be an integer 1..65535, got {port!r}")


def check_workers(workers: Any, what: str = "workers") -> int:
    """The number of worker processes ``workers`` (an integer >= 1; 1: in-process), InputError naming ``what``
    otherwise. The one rule for ``--workers`` and every ``workers`` key."""
    if isinstance(workers, bool) or not isinstance(workers, numbers.Integral) or workers < 1:
        raise InputError(what, f"must be >= 1, got {workers}")
    return int(workers)


def check_scheduler_address(address: Any, what: str = "scheduler") -> str:
    """The Dask scheduler ``address`` checked by its form only (no connection): "" (none), ``scheme://host:port``
    with a scheme of :data:`SCHEDULER_SCHEMES` (``inproc://`` takes any non-empty rest) or a bare ``host:port``.
    InputError naming ``what`` otherwise (also for a value that is not a string)."""
    if not isinstance(address, str):
        raise InputError(what, f"must be a Dask scheduler address (a string such as \"tcp://host:8786\"), got "
                               f"{type(address).__name__} {address!r}")
    address = address.strip()
    if not address:
        return ""
    if not address.isprintable() or any(c.isspace() for c in address):
        raise InputError(what, f"{address!r} is not a scheduler address (spaces or control characters)")
    scheme, sep, rest = address.partition("://")
    if not sep:
        scheme, rest = "", address
    elif scheme.lower() not in SCHEDULER_SCHEMES:
        raise InputError(what, f"{address!r}: unknown scheme {scheme!r}; use one of "
                               f"{', '.join(s + '://' for s in SCHEDULER_SCHEMES)} or host:port")
    if scheme.lower() == "inproc":
        if not rest:
            raise InputError(what, f"{address!r}: inproc:// needs the in-process address after it")
        return address
    _host_port(rest, address, what)
    return address


def _raise_terminated(signum, frame):
    raise Terminated()


class Runner:
    """Runs ``fn(task)`` for many tasks in-process, on local worker processes or on a Dask cluster (see the module
    docstring). Use as a context manager: the pool or the client lives for the ``with`` block and serves every
    :meth:`imap`/:meth:`map` inside it.

    Parameters
    ----------
    workers : int
        Local worker processes (1: in-process). Ignored with a scheduler.
    scheduler : str
        Dask scheduler address ("": local).
    blas_threads : int or None
        BLAS/MKL/OpenMP threads per task in-process and in the local workers (None: the cores shared evenly
        among the workers); one per task on Dask.
    what : str
        The input key named by an error about the scheduler (e.g. ``wear.scheduler``).
    """

    def __init__(self, workers: int = 1, scheduler: str = "", *, blas_threads: int | None = None,
                 what: str = "scheduler"):
        self.workers, self.what = check_workers(workers, "workers"), what
        self.scheduler = check_scheduler_address(scheduler or "", what)
        self.blas_threads = blas_threads_per_worker(self.workers) if blas_threads is None else int(blas_threads)
        self._pool: cf.ProcessPoolExecutor | None = None
        self._queue = None
        self._client = None
        self._previous_sigterm = None

    @property
    def mode(self) -> str:
        """'dask', 'processes' or 'in-process'."""
        return "dask" if self.scheduler else "processes" if self.workers > 1 else "in-process"

    @property
    def streams_progress(self) -> bool:
        """True when :func:`report_progress` inside the tasks reaches ``on_progress`` (not on Dask)."""
        return not self.scheduler

    def __enter__(self) -> Self:
        if self.scheduler:
            self._client = self._connect()
        elif self.workers > 1:
            ctx = mp.get_context("spawn")
            # handed to the workers at start (no Manager process that could outlive a run); a SimpleQueue writes each
            # count to the pipe before put() returns, so a task's counts are readable before its result arrives
            self._queue = ctx.SimpleQueue()
            self._pool = cf.ProcessPoolExecutor(max_workers=self.workers, mp_context=ctx,
                                                initializer=worker_lifeline, initargs=(os.getpid(), self._queue))
        if threading.current_thread() is threading.main_thread() and \
                signal.getsignal(signal.SIGTERM) is signal.SIG_DFL:  # a library caller: SIGTERM ends the workers too
            self._previous_sigterm = signal.signal(signal.SIGTERM, _raise_terminated)
        return self

    def _connect(self):
        try:
            from distributed import Client  # only with a scheduler: the optional 'cluster' dependency
        except ImportError:
            raise InputError(self.what, "needs the 'distributed' package (pip install dask[distributed])") from None
        try:
            return Client(self.scheduler, timeout="20s")
        except (OSError, TimeoutError, ValueError, TypeError) as err:  # TypeError: e.g. tls:// without security
            reason = " ".join(str(err).split()) or type(err).__name__
            raise InputError(self.what, f"cannot connect to the Dask scheduler {self.scheduler!r}: {reason}") from None

    def __exit__(self, exc_type, exc, tb) -> None:
        try:
            if self._pool is not None:
                if exc_type is None:
                    self._pool.shutdown(wait=True)
                else:
                    self.terminate()
            if self._queue is not None:
                self._queue.close()
            if self._client is not None:
                self._client.close()
        finally:
            self._pool = self._queue = self._client = None
            if self._previous_sigterm is not None:
                signal.signal(signal.SIGTERM, self._previous_sigterm)
                self._previous_sigterm = None

    def terminate(self) -> None:
        """End the local workers now (do not wait for their tasks) and cancel what is queued."""
        if self._pool is None:
            return
        for proc in list((self._pool._processes or {}).values()):  # the executor has no public way to kill them
            proc.terminate()
        self._pool.shutdown(wait=False, cancel_futures=True)

    def imap(self, fn: Callable[[T], R], tasks: Sequence[T], on_progress: Callable[[int], Any] | None = None
             ) -> Iterator[tuple[int, R]]:
        """(index, fn(tasks[index])) in completion order. The first exception of a task is raised here (the
        other workers are ended when it leaves the ``with`` block). ``fn`` must be picklable (a module-level
        function) for local processes and Dask."""
        tasks = list(tasks)
        if not tasks:
            return
        if self._client is not None:
            yield from self._imap_dask(fn, tasks)
        elif self._pool is not None and len(tasks) > 1:
            yield from self._imap_pool(fn, tasks, on_progress)
        else:
            yield from self._imap_here(fn, tasks, on_progress)

    def map(self, fn: Callable[[T], R], tasks: Sequence[T], on_done: Callable[[R], Any] | None = None) -> list[R]:
        """The results in task order; ``on_done(result)`` as each finishes."""
        done: dict[int, R] = {}
        for k, res in self.imap(fn, tasks):
            done[k] = res
            if on_done is not None:
                on_done(res)
        return [done[k] for k in range(len(done))]

    def _imap_here(self, fn, tasks, on_progress):
        global _progress_sink
        previous, _progress_sink = _progress_sink, on_progress
        try:
            for k, task in enumerate(tasks):
                yield k, call_limited(fn, task, self.blas_threads)
        finally:
            _progress_sink = previous

    def _imap_pool(self, fn, tasks, on_progress):
        try:
            with thread_environment(self.blas_threads):  # the workers start at the submits
                futures = {self._pool.submit(call_limited, fn, t, self.blas_threads): k for k, t in enumerate(tasks)}
            pending = set(futures)
            while pending:
                done, pending = cf.wait(pending, timeout=POLL_S, return_when=cf.FIRST_COMPLETED)
                self._drain(on_progress)
                for fut in done:
                    yield futures[fut], fut.result()
            self._drain(on_progress)
        except BaseException:  # an error, an interrupt or SIGTERM: end the workers now, not after their tasks
            self.terminate()
            raise

    def _drain(self, on_progress) -> None:
        while True:
            try:
                if self._queue.empty():
                    return
                n = self._queue.get()
            except (EOFError, OSError, ValueError):
                return
            if on_progress is not None:
                on_progress(n)

    def _imap_dask(self, fn, tasks):
        from distributed import as_completed  # only with a scheduler

        futures = {self._client.submit(call_limited, fn, t, 1, pure=False): k for k, t in enumerate(tasks)}
        for fut in as_completed(futures):
            yield futures[fut], fut.result()


__all__ = ["POLL_S", "SCHEDULER_SCHEMES", "THREAD_VARIABLES", "Runner", "blas_threads_per_worker", "call_limited",
           "check_scheduler_address", "check_workers", "limited_threads", "report_progress", "thread_environment", "worker_lifeline"]
