"""Start-up time of the command line for a small scene: `python -m contact simulate scenes/hertz_check.toml`.

The whole process is timed from outside (wall time, median of repeated runs after one untimed warm-up, the same
interpreter as the benchmarks) and split into the interpreter's own start-up (`python -c pass`), the imports
(`python -X importtime`: every module the run imports beyond those of the bare interpreter, top-level cumulative
times summed; the flag itself adds a little) and the solve (the scene's own `solver.total_s` in result.json); the
rest is argument parsing, reading the scene, writing the results and exit. Target: under 0.5 s for a small scene.
The heaviest imports are grouped by package (summed self times, so nothing is counted twice; our own packages
one level deeper, e.g. `contact.normal`) with the module through which each is first imported. Units: seconds.
"""

from __future__ import annotations

import ast
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

ROOT = pathlib.Path(__file__).resolve().parents[1]
SCENE = ROOT / "scenes" / "hertz_check.toml"
#: start-up target for a small scene, s
TARGET_S = 0.5
#: our packages: grouped one level deeper, and the ones whose module-level imports are listed
PROJECT_PACKAGES = ("wrlayer", "meshes", "calibration", "contact")
#: how many of the heaviest import groups the report lists
N_HEAVIEST = 10


@dataclasses.dataclass(frozen=True)
class ImportRecord:
    """One line of ``python -X importtime`` output.

    Attributes
    ----------
    name : str
        Module name.
    self_us : int
        Time spent in the module's own body, µs.
    cumulative_us : int
        Time including the modules it imported first, µs.
    depth : int
        Nesting level (0: imported by the running code, not by another module's import).
    parent : int
        Index of the module whose import pulled this one in, -1 at depth 0.
    """

    name: str
    self_us: int
    cumulative_us: int
    depth: int
    parent: int


@dataclasses.dataclass(frozen=True)
class ImportGroup:
    """The import cost of one package (or, for our packages, one sub-package).

    Attributes
    ----------
    group : str
        Package name (``numba``) or our sub-package (``contact.normal``).
    self_s : float
        Summed self time of its modules, s.
    modules : int
        Number of its modules imported.
    importer : str
        Module whose import first pulled the group in; ``(run time)`` when it was imported by running code.
    project_importer : str
        Nearest module of our packages on that import chain (the one that imports it at module level), or "".
    """

    group: str
    self_s: float
    modules: int
    importer: str
    project_importer: str


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
        Wall time of ``python -c "import contact.__main__"`` minus ``interpreter_s`` (the module-level imports of
        the command line), median, s.
    main_import_cpu_s : float
        The same in CPU time, median, s.
    run_import_s : float
        Imports of the whole run beyond the bare interpreter's (``-X importtime``, one run), s.
    solve_s : float
        The scene's own ``solver.total_s`` (result.json), median, s.
    other_s : float
        ``wall_s - interpreter_s - run_import_s - solve_s``: parsing, reading, writing, exit, s.
    target_s : float
        Start-up target, s.
    target_met : bool
        Whether ``wall_s < target_s``.
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
    solve_s: float
    other_s: float
    target_s: float
    target_met: bool
    load_before: float
    load_after: float


def parse_importtime(text: str) -> list[ImportRecord]:
    """The records of ``-X importtime`` stderr, in output order (a module is printed after those it imported).

    Lines that are not ``import time: <self> | <cumulative> | <indent><name>`` (the header, other output) are
    skipped; the nesting depth is the indentation of the name in steps of two spaces."""
    rows: list[tuple[str, int, int, int]] = []
    for line in text.splitlines():
        if not line.startswith("import time:"):
            continue
        parts = line[len("import time:"):].split("|")
        if len(parts) != 3 or not parts[0].strip().isdigit():
            continue
        label = parts[2][1:] if parts[2].startswith(" ") else parts[2]
        depth = (len(label) - len(label.lstrip(" "))) // 2
        rows.append((label.strip(), int(parts[0]), int(parts[1]), depth))
    parents = [-1] * len(rows)
    waiting: dict[int, list[int]] = {}  # depth -> records still looking for their importer
    for i, (_, _, _, depth) in enumerate(rows):
        for child in waiting.pop(depth + 1, []):
            parents[child] = i
        waiting.setdefault(depth, []).append(i)
    return [ImportRecord(n, s, c, d, p) for (n, s, c, d), p in zip(rows, parents)]


def import_seconds(records: list[ImportRecord], exclude: frozenset[str] = frozenset()) -> float:
    """Summed cumulative time (s) of the top-level imports, leaving out the modules in ``exclude`` (e.g. those the
    bare interpreter imports)."""
    return sum(r.cumulative_us for r in records if r.depth == 0 and r.name not in exclude) / 1e6


def group_of(name: str) -> str:
    """The group a module's cost is counted in: its top-level package, or for our packages the sub-package."""
    parts = name.split(".")
    return ".".join(parts[:2]) if parts[0] in PROJECT_PACKAGES else parts[0]


def import_groups(records: list[ImportRecord]) -> list[ImportGroup]:
    """Import cost per group, heaviest first, with the module that first pulled each group in."""
    self_us: dict[str, int] = {}
    count: dict[str, int] = {}
    entry: dict[str, int] = {}  # group -> first record whose importer is outside the group
    for i, r in enumerate(records):
        g = group_of(r.name)
        self_us[g] = self_us.get(g, 0) + r.self_us
        count[g] = count.get(g, 0) + 1
        if g not in entry and (r.parent < 0 or group_of(records[r.parent].name) != g):
            entry[g] = i
    out = []
    for g in sorted(self_us, key=self_us.get, reverse=True):
        first = records[entry[g]] if g in entry else None
        importer = records[first.parent].name if first is not None and first.parent >= 0 else "(run time)"
        out.append(ImportGroup(g, self_us[g] / 1e6, count[g], importer, _project_ancestor(records, entry.get(g))))
    return out


def _project_ancestor(records: list[ImportRecord], index: int | None) -> str:
    while index is not None and index >= 0:
        index = records[index].parent
        if index >= 0 and records[index].name.split(".")[0] in PROJECT_PACKAGES:
            return records[index].name
    return ""


def module_level_importers(root: pathlib.Path, packages: set[str],
                           modules: set[str] | None = None) -> dict[str, list[str]]:
    """Our modules (of ``modules`` when given) that import one of ``packages`` at module level (statements in the
    module body, also inside a top-level ``if``/``try``), by package. Read from the sources: every such module is
    found, not only the first one an import chain meets."""
    found: dict[str, list[str]] = {p: [] for p in sorted(packages)}
    for pkg in PROJECT_PACKAGES:
        for path in sorted((root / pkg).rglob("*.py")):
            module = ".".join(path.relative_to(root).with_suffix("").parts).removesuffix(".__init__")
            if modules is not None and module not in modules:
                continue
            for p in sorted(_top_imports(ast.parse(path.read_text(encoding="utf-8"))) & packages):
                found[p].append(module)
    return found


def _top_imports(tree: ast.Module) -> set[str]:
    names: set[str] = set()
    stack = list(tree.body)
    while stack:
        node = stack.pop()
        if isinstance(node, ast.Import):
            names.update(a.name.split(".")[0] for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names.add(node.module.split(".")[0])
        elif isinstance(node, (ast.If, ast.Try)):
            stack += node.body + node.orelse + getattr(node, "finalbody", [])
            stack += [s for h in getattr(node, "handlers", []) for s in h.body]
    return names


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


def _simulate_args(out: pathlib.Path) -> list[str]:
    return ["-m", "contact", "simulate", str(SCENE), "--out", str(out)]


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
        runs["main"].append(_timed(["-c", "import contact.__main__"], env)[:2])
    bare_set = frozenset(r.name for r in parse_importtime(_timed(["-X", "importtime", "-c", "pass"], env)[2].stderr))
    records = parse_importtime(_timed(["-X", "importtime", *_simulate_args(work / "importtime")], env)[2].stderr)
    wall, cpu = (statistics.median(v) for v in zip(*runs["simulate"]))
    interp, interp_cpu = (statistics.median(v) for v in zip(*runs["pass"]))
    main, main_cpu = (statistics.median(v) for v in zip(*runs["main"]))
    solve = statistics.median(solves)
    run_import = import_seconds(records, bare_set)
    timing = StartupTiming(str(SCENE.relative_to(ROOT)), repeat, wall, [w for w, _ in runs["simulate"]], cpu, first,
                           interp, interp_cpu, main - interp, main_cpu - interp_cpu, run_import, solve,
                           wall - interp - run_import - solve, TARGET_S, wall < TARGET_S, load_before,
                           os.getloadavg()[0])
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
          "| module-level imports of the command line (`import contact.__main__` minus the above; "
          f"CPU {t.main_import_cpu_s:.3f}) | {t.main_import_s:.3f} |",
          f"| all imports of the run (`-X importtime`) | {t.run_import_s:.3f} |",
          f"| solve (result.json `solver.total_s`) | {t.solve_s:.3f} |",
          f"| other (parsing, reading, writing, exit) | {t.other_s:.3f} |", "",
          f"Target {t.target_s:g} s: **{'met' if t.target_met else 'not met'}**.", "",
          f"The {N_HEAVIEST} heaviest import groups of the run (summed self times):", "",
          "| group | s | modules | first imported by | our module on that chain |", "|---|---|---|---|---|"]
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
    third_party = {g.group for g in groups[:N_HEAVIEST]
                   if g.group.split(".")[0] not in PROJECT_PACKAGES and g.group not in sys.stdlib_module_names}
    importers = module_level_importers(ROOT, third_party, {r.name for r in records})
    return {"title": "Start-up of the command line (small scene)", "markdown": _markdown(timing, groups, importers),
            "figures": [],
            "data": {"timing": dataclasses.asdict(timing),
                     "heaviest_imports": [dataclasses.asdict(g) for g in groups[:N_HEAVIEST]],
                     "module_level_importers": importers}}
