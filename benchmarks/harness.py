"""Timing, memory and machine facts for the benchmarks (units: seconds, MiB).

Timings are medians of repeated runs after warm-up, because this machine's speed drifts; comparisons between two
implementations should interleave their runs (see :func:`interleaved_medians`) and be reported as ratios.
"""

from __future__ import annotations

import contextlib
import os
import platform
import resource
import statistics
import subprocess
import sys
import tarfile
import tempfile
import time
import tracemalloc
from importlib import metadata
from pathlib import Path
from typing import Any, Callable


def median_time(fn: Callable[[], Any], repeat: int = 5, warmup: int = 1,
                clock: Callable[[], float] = time.perf_counter) -> tuple[float, list[float]]:
    """Median time of ``fn()`` in seconds over ``repeat`` runs after ``warmup`` untimed runs (wall time; CPU time
    with ``clock=time.process_time``)."""
    for _ in range(warmup):
        fn()
    times = []
    for _ in range(repeat):
        t0 = clock()
        fn()
        times.append(clock() - t0)
    return statistics.median(times), times


def interleaved_medians(fns: dict[str, Callable[[], Any]], repeat: int = 5,
                        warmup: int = 1) -> dict[str, float]:
    """Median wall time (s) of each callable, runs interleaved A, B, A, B, ... to cancel machine drift."""
    for _ in range(warmup):
        for fn in fns.values():
            fn()
    times: dict[str, list[float]] = {k: [] for k in fns}
    for _ in range(repeat):
        for k, fn in fns.items():
            t0 = time.perf_counter()
            fn()
            times[k].append(time.perf_counter() - t0)
    return {k: statistics.median(v) for k, v in times.items()}


def peak_memory_mb(fn: Callable[[], Any]) -> tuple[Any, float]:
    """Run ``fn()`` and return (result, peak Python-heap allocation in MiB, tracemalloc; numpy buffers included)."""
    tracemalloc.start()
    try:
        result = fn()
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    return result, peak / 2**20


def max_rss_mb() -> float:
    """Peak resident set size of this process so far (MiB), including native libraries' memory."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def _cpu_model() -> str:
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as fh:
            for line in fh:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def _git_version() -> str:
    try:
        return subprocess.run(["git", "describe", "--always", "--dirty"], capture_output=True, text=True,
                              check=True, cwd=os.path.dirname(__file__)).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


@contextlib.contextmanager
def revision_tree(revision: str):
    """The source tree of git ``revision`` of this repository, extracted (``git archive``) into a scratch folder
    that is removed afterwards: run another revision's code there (``PYTHONPATH`` = the yielded path)."""
    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    with tempfile.TemporaryDirectory() as tmp:
        tree = Path(tmp) / "tree"
        tree.mkdir()
        tar_path = Path(tmp) / "tree.tar"
        tar_path.write_bytes(subprocess.run(["git", "-C", repo, "archive", "--format=tar", revision], check=True,
                                            capture_output=True).stdout)
        with tarfile.open(tar_path) as tar:
            tar.extractall(tree, filter="data")
        tar_path.unlink()
        yield tree


def report_stamp(command: str) -> str:
    """The stamp every validation report carries under its title (docs/validation/README.md): the code revision,
    the command that regenerates the report and the machine's load, e.g.
    ``Revision 2172805; regenerate: `python -m benchmarks.bench_x --report F`; load average 1.2 on 2 cores.``"""
    return (f"Revision {_git_version()}; regenerate: `{command}`; load average {os.getloadavg()[0]:.1f} on "
            f"{os.cpu_count()} cores.")


def stamped_report(title: str, markdown: str, command: str) -> str:
    """A validation report: the title, :func:`report_stamp`, the units, then the benchmark's markdown."""
    return f"# {title}\n\n{report_stamp(command)} Units: mm, N, MPa, s.\n\n{markdown.rstrip()}\n"


def write_report(path: Path, title: str, markdown: str, command: str) -> Path:
    """Write the :func:`stamped_report` of ``markdown`` to ``path`` (its folder created); returns ``path``."""
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(stamped_report(title, markdown, command))
    return path


def publish(report: Path | None, title: str, markdown: str, program: str, argv: list[str] | None) -> None:
    """Print a benchmark's ``markdown``; with ``report`` also write it there as a :func:`stamped_report` whose
    command is ``program`` with ``argv`` (:func:`command_line`)."""
    if report is not None:
        write_report(report, title, markdown, command_line(program, argv))
    print(markdown)


def command_line(program: str, argv: list[str] | None) -> str:
    """The command that ran this benchmark: ``program`` and its arguments (``sys.argv[1:]`` when ``argv`` is None)."""
    return " ".join([program, *(sys.argv[1:] if argv is None else argv)])


def machine_info() -> dict[str, Any]:
    """Cores, CPU model, memory, Python and key package versions, and the code version (git)."""
    pkgs = {}
    for name in ("numpy", "scipy", "scikit-fem", "gmsh", "meshio", "pyvista", "numba", "pypardiso", "felupe"):
        try:
            pkgs[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            pkgs[name] = None
    try:
        mem_gib = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 2**30
    except (ValueError, OSError):
        mem_gib = float("nan")
    return {
        "cores": os.cpu_count(),
        "cpu_model": _cpu_model(),
        "memory_GiB": round(mem_gib, 1),
        "python": sys.version.split()[0],
        "platform": platform.platform(),
        "packages": pkgs,
        "code_version": _git_version(),
    }
