"""The shared parallel runner (wrlayer.runner): in-process and on two local processes, progress from inside the
tasks, BLAS limits in the workers, an error raised to the caller, workers that die with their parent."""

import math
import os
import subprocess
import sys
import textwrap
import time

import pytest

from wrlayer.cost import CostError
from wrlayer.errors import InputError
from wrlayer.runner import (THREAD_VARIABLES, Runner, blas_threads_per_worker, check_scheduler_address, check_workers,
                            report_progress)

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def steps(n: int) -> int:
    """A task reporting ``n`` progress steps; returns n squared."""
    for _ in range(n):
        report_progress(1)
    return n * n


def fail_on_three(n: int) -> int:
    if n == 3:
        raise ValueError("three")
    return n


def bad_input_on_three(n: int) -> int:
    if n == 3:
        raise CostError("task 3", "refused")  # an InputError subclass: (what, problem) cross the process boundary
    return n


def test_in_process_results_and_progress():
    seen = []
    with Runner(1) as runner:
        assert runner.mode == "in-process" and runner.streams_progress
        out = list(runner.imap(steps, [1, 2, 3], on_progress=seen.append))
        assert runner.map(math.sqrt, [4.0, 9.0]) == [2.0, 3.0]
    assert out == [(0, 1), (1, 4), (2, 9)]
    assert sum(seen) == 6


def test_two_local_processes():
    seen = []
    with Runner(2) as runner:
        assert runner.mode == "processes"
        out = dict(runner.imap(steps, [1, 2, 3, 4], on_progress=seen.append))
        pids = set(runner.map(worker_pid, [0, 1, 2, 3]))
    assert out == {0: 1, 1: 4, 2: 9, 3: 16}
    assert sum(seen) == 10  # every step reported by the workers reached the caller
    assert os.getpid() not in pids


def worker_pid(_task) -> int:
    return os.getpid()


def test_blas_threads_set_in_workers():
    n = blas_threads_per_worker(2)
    with Runner(2) as runner:
        values = runner.map(os.getenv, list(THREAD_VARIABLES))
    assert values == [str(n)] * len(THREAD_VARIABLES)
    assert all(os.environ.get(v) != "sentinel" for v in THREAD_VARIABLES)  # the parent's environment restored


def test_task_error_reaches_the_caller():
    """The first failing task's exception reaches the caller (in-process and from the workers), the workers are
    ended and the caller goes on. Run in a fresh interpreter: the pool is started from a process whose signal
    handlers no other test has touched."""
    code = textwrap.dedent("""
        import sys
        from wrlayer.runner import Runner
        sys.path.insert(0, sys.argv[1])
        from test_runner import bad_input_on_three, fail_on_three
        for task in (fail_on_three, bad_input_on_three):
            for workers, tasks in ((2, [1, 2, 3, 4]), (1, [3])):
                try:
                    with Runner(workers) as runner:
                        runner.map(task, tasks)
                except ValueError as err:
                    print(workers, type(err).__name__, err, getattr(err, "problem", ""))
        print("done")
    """)
    done = subprocess.run([sys.executable, "-c", code, os.path.dirname(__file__)], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split("\n")[:5] == ["2 ValueError three ", "1 ValueError three ",
                                           "2 CostError task 3: refused refused", "1 CostError task 3: refused refused",
                                           "done"], done.stdout


PARENT = textwrap.dedent("""
    import threading, time
    from wrlayer.runner import Runner
    with Runner(2) as runner:
        results = runner.imap(time.sleep, [60.0, 60.0])
        threading.Thread(target=next, args=(results, None), daemon=True).start()  # submits, then waits
        time.sleep(3.0)
        print(" ".join(str(p) for p in runner._pool._processes), flush=True)
        time.sleep(120)
""")


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().split()[2] != "Z"
    except OSError:
        return False


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_workers_die_with_their_parent():
    env = dict(os.environ, PYTHONPATH=ROOT)
    parent = subprocess.Popen([sys.executable, "-c", PARENT], stdout=subprocess.PIPE, text=True, env=env, cwd=ROOT)
    try:
        pids = [int(p) for p in parent.stdout.readline().split()]
        assert len(pids) == 2 and all(_alive(p) for p in pids)
        parent.kill()  # SIGKILL: no cleanup in the parent at all
        parent.wait(10)
        deadline = time.monotonic() + 10
        while any(_alive(p) for p in pids) and time.monotonic() < deadline:
            time.sleep(0.1)
        assert not any(_alive(p) for p in pids)
    finally:
        if parent.poll() is None:
            parent.kill()


TERMINATED = textwrap.dedent("""
    import time
    from wrlayer.errors import Terminated
    from wrlayer.runner import Runner
    try:
        with Runner(2) as runner:
            results = runner.imap(time.sleep, [60.0, 60.0])
            print("running", flush=True)
            list(results)
    except Terminated:
        print("terminated", runner._pool is None, flush=True)
""")


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_sigterm_ends_the_workers_and_unwinds_the_caller():
    """SIGTERM to a library caller (no handler of its own): the runner's handler raises Terminated, the workers
    are ended and the caller's except/finally blocks run."""
    env = dict(os.environ, PYTHONPATH=ROOT)
    parent = subprocess.Popen([sys.executable, "-c", TERMINATED], stdout=subprocess.PIPE, text=True, env=env,
                              cwd=ROOT)
    try:
        assert parent.stdout.readline().strip() == "running"
        time.sleep(3.0)  # the workers are spawned and sleeping
        kids = [int(k) for t in os.listdir(f"/proc/{parent.pid}/task")
                for k in open(f"/proc/{parent.pid}/task/{t}/children").read().split()]
        parent.terminate()
        out, _ = parent.communicate(timeout=30)
        assert out.strip() == "terminated True"
        deadline = time.monotonic() + 10
        while any(_alive(k) for k in kids) and time.monotonic() < deadline:
            time.sleep(0.1)
        assert kids and not any(_alive(k) for k in kids)
    finally:
        if parent.poll() is None:
            parent.kill()


@pytest.mark.parametrize("address", ["tcp://10.0.0.5:8786", "tls://scheduler.example:8786", "ucx://h:13337",
                                     "ws://h:8786", "wss://h", "inproc://10.0.0.5/123/4", "h:8786",
                                     "[::1]:8786", "tcp://[::1]:8786", "", "  "])
def test_scheduler_addresses_of_every_scheme_accepted_without_a_scheduler(address):
    assert check_scheduler_address(address, "x") == address.strip()
    assert Runner(1, address).scheduler == address.strip()  # no connection until the block is entered


@pytest.mark.parametrize("address, fragment", [
    ("tls://", "is not a scheduler address"), ("http://h:1", "unknown scheme 'http'"),
    ("tcp://h:70000", "the port must be an integer 1..65535"), ("inproc://", "needs the in-process address"),
    ("tcp://h 1", "spaces or control characters"), (True, "got bool True"), (8786, "got int 8786"),
    ("tcp://a:b:c", "is not a scheduler address"),
])
def test_bad_scheduler_address_is_one_input_error(address, fragment):
    with pytest.raises(InputError, match=r"^wear\.scheduler: ") as err:
        check_scheduler_address(address, "wear.scheduler")
    assert fragment in str(err.value) and "\n" not in str(err.value)
    with pytest.raises(InputError):
        Runner(1, address, what="wear.scheduler")


@pytest.mark.parametrize("workers", [0, -1, True, 1.5, "2"])
def test_workers_rule_refuses_what_is_not_a_count_of_one_or_more(workers):
    """One rule for --workers and every workers key: an integer >= 1, the error naming the option."""
    with pytest.raises(InputError, match="--workers: must be >= 1"):
        check_workers(workers, "--workers")
    with pytest.raises(InputError, match="workers"):
        Runner(workers)


def test_workers_rule_keeps_a_count():
    assert check_workers(3) == 3 and Runner(2).workers == 2
