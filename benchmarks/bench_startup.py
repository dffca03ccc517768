"""Start-up time of the command line for a small scene: `wrlayer simulate scenes/hertz_check.toml`.

The whole process is timed from outside (wall time, median of repeated runs after one untimed warm-up, the same
interpreter as the benchmarks) and split into the interpreter's own start-up (`python -c pass`), the imports
(`python -X importtime`: every module the run imports beyond those of the bare interpreter, top-level cumulative
times summed, less those a library imports itself inside the solve; the flag itself adds a little) and the solve
(the scene's own `solver.total_s` in result.json); the rest is argument parsing, reading the scene, writing the
results and exit. The scene is also run twice in one process: the second solve is the solve proper, the
difference is the first call's cost (numba loading its cached machine code, lazy imports). CPU times (user +
system) are given beside the wall times: on a loaded machine they show the cost itself. Target: under 0.5 s for
a small scene. The floor of the Kik-Piotrowski path is measured on its own: the interpreter, numpy, numba and the
first call of one cached numba function (the Boussinesq sum every solve makes), in one process. The heaviest
imports are grouped by package (summed self times, so nothing is counted twice; our own packages one level
deeper, e.g. `contact.normal`) with the module through which the most expensive part of each is imported.
Units: seconds.
"""

from __future__ import annotations

import dataclasses
import json
import os
import pathlib
import resource
import statistics
import subprocess
import sys
import tempfile
import time

from benchmarks.importtime import (ImportGroup, ImportRecord, import_groups, import_seconds, lazy_library_seconds,
                                   module_level_importers, parse_importtime, third_party)

ROOT = pathlib.Path(__file__).resolve().parents[1]
SCENE = ROOT / "scenes" / "hertz_check.toml"
#: start-up target for a small scene, s
TARGET_S = 0.5
#: how many of the heaviest import groups the report lists
N_HEAVIEST = 10


@dataclasses.dataclass(frozen=True)
class StartupTiming:
    """The measured start-up of one small scene.

    Attributes
    ----------
    scene : str
        Scene file, relative to the repository.
    repeat : int
        Timed runs of each command (medians).
    wall_s : float
        Wall time of the whole ``python -m contact simulate`` process, median, s.
    wall_runs_s : list of float
        The timed runs, s.
    cpu_s : float
        CPU time (user + system) of the whole process, median, s: less sensitive to the machine's load.
    first_run_s : float
        The untimed warm-up run (cold file cache, numba cache check), s.
    interpreter_s : float
        Wall time of ``python -c pass``, median, s.
    interpreter_cpu_s : float
        CPU time of ``python -c pass``, median, s.
    main_import_s : float
        Wall time of ``python -c "import wrlayer.cli, contact.__main__"`` minus ``interpreter_s`` (the
        module-level imports of the command line), median, s.
    main_import_cpu_s : float
        The same in CPU time, median, s.
    run_import_s : float
        Imports of the whole run beyond the bare interpreter's (``-X importtime``, one run), s.
    lazy_import_s : float
        The part of ``run_import_s`` that a library imports itself when running (numba's typing and lowering
        registries at the first call of compiled code, inside the solve), s.
    solve_s : float
        The scene's own ``solver.total_s`` (result.json), median, s.
    solve_first_s : float
        ``solver.total_s`` of the first of two runs of the scene in one process, median, s.
    solve_warm_s : float
        ``solver.total_s`` of the second run in the same process (numba's compiled code loaded, modules imported):
        the solve proper, median, s.
    other_s : float
        ``wall_s - interpreter_s - (run_import_s - lazy_import_s) - solve_s``: parsing, reading, writing, exit, s.
    target_s : float
        Start-up target, s.
    target_met : bool
        Whether ``wall_s < target_s``.
    floor_numpy_s : float
        ``import numpy`` in a bare interpreter, median, s.
    floor_numba_s : float
        ``import numba`` after numpy, median, s.
    floor_first_call_s : float
        First call of the cached numba function of the Kik-Piotrowski solve (numba's type registries and the
        cached machine code loaded), median, s.
    floor_s : float
        ``interpreter_s + floor_numpy_s + floor_numba_s + floor_first_call_s``: what a Kik-Piotrowski run cannot
        go below while its solver is compiled by numba, s.
    floor_cpu_s : float
        The same in CPU time (interpreter, numpy, numba, first call), s.
    load_before : float
        One-minute load average of the machine before the runs (2 cores).
    load_after : float
        One-minute load average after the runs.
    """

    scene: str
    repeat: int
    wall_s: float
    wall_runs_s: list
    cpu_s: float
    first_run_s: float
    interpreter_s: float
    interpreter_cpu_s: float
    main_import_s: float
    main_import_cpu_s: float
    run_import_s: float
    lazy_import_s: float
    solve_s: float
    solve_first_s: float
    solve_warm_s: float
    other_s: float
    target_s: float
    target_met: bool
    floor_numpy_s: float
    floor_numba_s: float
    floor_first_call_s: float
    floor_s: float
    floor_cpu_s: float
    load_before: float
    load_after: float


def _env() -> dict[str, str]:
    """The benchmark's environment with this repository first on the path (the run measures this code)."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT)] + ([env["PYTHONPATH"]] if env.get("PYTHONPATH") else []))
    return env


def _children_cpu() -> float:
    ru = resource.getrusage(resource.RUSAGE_CHILDREN)
    return ru.ru_utime + ru.ru_stime


def _timed(args: list[str], env: dict[str, str]) -> tuple[float, float, subprocess.CompletedProcess]:
    """Wall time (s), CPU time (s) and the finished process of ``python ARGS``."""
    c0, t0 = _children_cpu(), time.perf_counter()
    proc = subprocess.run([sys.executable, *args], env=env, cwd=ROOT, capture_output=True, text=True, check=True)
    return time.perf_counter() - t0, _children_cpu() - c0, proc


#: what the ``wrlayer`` console script runs (pip's generated script: import, call, exit)
_CONSOLE = "import sys; from wrlayer.cli import main; sys.exit(main())"


def _simulate_args(out: pathlib.Path) -> list[str]:
    return ["-c", _CONSOLE, "simulate", str(SCENE), "--out", str(out)]


#: imports numpy and numba and calls the Boussinesq sum (numba, cached) once on a one-strip patch, printing the
#: three wall times and the three CPU times (s) as JSON
_FLOOR = ("import time, json\nc = lambda: (time.perf_counter(), time.process_time())\nt0 = c()\n"
          "import numpy as np\nt1 = c()\nimport numba\nt2 = c()\n"
          "from contact.normal.boussinesq import boussinesq_integral\nt3 = c()\n"
          "boussinesq_integral(np.ones(1), np.zeros(1, dtype=np.int64), 0.1)\nt4 = c()\n"
          "print(json.dumps([b[k] - a[k] for k in (0, 1) for a, b in ((t0, t1), (t1, t2), (t3, t4))]))")


def _floor(env: dict[str, str], repeat: int) -> list[float]:
    """Median wall times of importing numpy, numba after it and the first call of a cached numba function, then
    the same three in CPU time (s)."""
    runs = [json.loads(_timed(["-c", _FLOOR], env)[2].stdout) for _ in range(repeat)]
    return [statistics.median(r[i] for r in runs) for i in range(6)]


#: runs the scene twice in one process and prints the two ``solver.total_s`` (s) as JSON
_TWICE = ("import json, sys\nfrom contact.run_files import run_scene_file\n"
          "print(json.dumps([run_scene_file(sys.argv[1], sys.argv[2] + str(i))['solver']['total_s'] for i in (0, 1)]))")


def _solve_twice(env: dict[str, str], work: pathlib.Path, repeat: int) -> tuple[float, float]:
    """Median ``solver.total_s`` (s) of the first and of the second run of the scene in one process."""
    pairs = [json.loads(_timed(["-c", _TWICE, str(SCENE), str(work / f"twice{k}-")], env)[2].stdout)
             for k in range(repeat)]
    return statistics.median(p[0] for p in pairs), statistics.median(p[1] for p in pairs)


def measure(repeat: int, work: pathlib.Path) -> tuple[StartupTiming, list[ImportRecord], frozenset[str]]:
    """Time the command ``repeat`` times (interleaved with the bare interpreter and the import of the command
    line), then one ``-X importtime`` run; returns the timing, that run's import records and the bare set."""
    env = _env()
    load_before = os.getloadavg()[0]
    first = _timed(_simulate_args(work / "warm-up"), env)[0]
    runs: dict[str, list[tuple[float, float]]] = {"simulate": [], "pass": [], "main": []}
    solves = []
    for i in range(repeat):
        out = work / f"run{i}"
        runs["simulate"].append(_timed(_simulate_args(out), env)[:2])
        solves.append(json.loads((out / "result.json").read_text(encoding="utf-8"))["solver"]["total_s"])
        runs["pass"].append(_timed(["-c", "pass"], env)[:2])
        runs["main"].append(_timed(["-c", "import wrlayer.cli, contact.__main__"], env)[:2])
    bare_set = frozenset(r.name for r in parse_importtime(_timed(["-X", "importtime", "-c", "pass"], env)[2].stderr))
    records = parse_importtime(_timed(["-X", "importtime", *_simulate_args(work / "importtime")], env)[2].stderr)
    wall, cpu = (statistics.median(v) for v in zip(*runs["simulate"]))
    interp, interp_cpu = (statistics.median(v) for v in zip(*runs["pass"]))
    main, main_cpu = (statistics.median(v) for v in zip(*runs["main"]))
    solve = statistics.median(solves)
    solve_first, solve_warm = _solve_twice(env, work, max(1, repeat // 2))
    run_import = import_seconds(records, bare_set)
    lazy = lazy_library_seconds(records)
    floor = _floor(env, repeat)
    timing = StartupTiming(
        scene=str(SCENE.relative_to(ROOT)), repeat=repeat, wall_s=wall, wall_runs_s=[w for w, _ in runs["simulate"]],
        cpu_s=cpu, first_run_s=first, interpreter_s=interp, interpreter_cpu_s=interp_cpu, main_import_s=main - interp,
        main_import_cpu_s=main_cpu - interp_cpu, run_import_s=run_import, lazy_import_s=lazy, solve_s=solve,
        solve_first_s=solve_first, solve_warm_s=solve_warm, other_s=wall - interp - (run_import - lazy) - solve,
        target_s=TARGET_S, target_met=wall < TARGET_S, floor_numpy_s=floor[0], floor_numba_s=floor[1],
        floor_first_call_s=floor[2], floor_s=interp + sum(floor[:3]), floor_cpu_s=interp_cpu + sum(floor[3:]),
        load_before=load_before,
        load_after=os.getloadavg()[0])
    return timing, records, bare_set


def _markdown(t: StartupTiming, groups: list[ImportGroup], importers: dict[str, list[str]]) -> str:
    md = [__doc__.split("\n\n", 1)[1].strip(), "",
          f"Scene `{t.scene}`, {t.repeat} timed runs; load average {t.load_before:.2f} before, "
          f"{t.load_after:.2f} after (2 cores; the timings scale with it).", "",
          "| part | s |", "|---|---|",
          f"| whole process, median (runs {', '.join(f'{w:.2f}' for w in t.wall_runs_s)}) | {t.wall_s:.3f} |",
          f"| whole process, CPU time (user + system), median | {t.cpu_s:.3f} |",
          f"| first (warm-up) run | {t.first_run_s:.3f} |",
          f"| interpreter start-up (`python -c pass`; CPU {t.interpreter_cpu_s:.3f}) | {t.interpreter_s:.3f} |",
          "| module-level imports of the command line (`import wrlayer.cli, contact.__main__` minus the above; "
          f"CPU {t.main_import_cpu_s:.3f}) | {t.main_import_s:.3f} |",
          f"| all imports of the run (`-X importtime`) | {t.run_import_s:.3f} |",
          f"| ... of which libraries import while running (numba, inside the solve) | {t.lazy_import_s:.3f} |",
          f"| solve (result.json `solver.total_s`) | {t.solve_s:.3f} |",
          f"| solve, first run in a process / second run in the same process | {t.solve_first_s:.3f} / "
          f"{t.solve_warm_s:.3f} |",
          f"| other (parsing, reading, writing, exit) | {t.other_s:.3f} |", "",
          f"Target {t.target_s:g} s: **{'met' if t.target_met else 'not met'}**. Floor of a Kik-Piotrowski run "
          f"while its solver is compiled by numba: {t.floor_s:.3f} s = interpreter {t.interpreter_s:.3f} + numpy "
          f"{t.floor_numpy_s:.3f} + numba {t.floor_numba_s:.3f} + first call of a cached numba function "
          f"{t.floor_first_call_s:.3f} (CPU time {t.floor_cpu_s:.3f}).", "",
          f"The {N_HEAVIEST} heaviest import groups of the run (summed self times):", "",
          "| group | s | modules | mostly imported by | our module on that chain |", "|---|---|---|---|---|"]
    md += [f"| {g.group} | {g.self_s:.3f} | {g.modules} | {g.importer} | {g.project_importer or '—'} |"
           for g in groups[:N_HEAVIEST]]
    if importers:
        md += ["", "Our modules imported by this run that import those packages at module level (from the "
               "sources):", ""]
        md += [f"- {p}: " + (", ".join(f"`{m}`" for m in mods) if mods else "none")
               for p, mods in importers.items()]
    return "\n".join(md) + "\n"


def run(mode: str, out: pathlib.Path) -> dict:
    """Benchmark entry point (``python -m benchmarks --only startup``)."""
    repeat = 5 if mode == "quick" else 9
    with tempfile.TemporaryDirectory(prefix="bench-startup-") as tmp:
        timing, records, _ = measure(repeat, pathlib.Path(tmp))
    groups = import_groups(records)
    libraries = {g.group for g in groups[:N_HEAVIEST] if third_party(g.group)}
    importers = module_level_importers(ROOT, libraries, {r.name for r in records})
    return {"title": "Start-up of the command line (small scene)", "markdown": _markdown(timing, groups, importers),
            "figures": [],
            "data": {"timing": dataclasses.asdict(timing),
                     "heaviest_imports": [dataclasses.asdict(g) for g in groups[:N_HEAVIEST]],
                     "module_level_importers": importers}}
