"""One direct 3D calibration position (default configuration, 60E1 rail crown, one worker): run time split,
machine-independent counts, peak memory and the check that a code change left its result unchanged (units s,
MiB, mm, MPa).

Split (cProfile with the process CPU clock, so that the other users of a shared machine do not inflate it;
cumulative CPU time of each phase's functions): meshing (``build_mesh``: gmsh and conversion),
discretisation (``discretise``: basis, B-matrices, CSR pattern), assembly (the elastic stiffness and the load
vector), factorisation (PARDISO analysis and numerical factorisations), Newton (the increments: return mappings,
tangent products, CG; ``of which solves``: the triangular solves), output (VTK/PNG fields, only with plots) and
the rest. Counts: Newton iterations, triangular solves, factorisations, return-mapping calls and the quadrature
points they evaluated. Every time is given with the 1-minute load average of the machine (``os.getloadavg``) and
the process CPU time, because this machine is shared. One BLAS/MKL thread (as a worker of a two-worker
calibration): with two, the waiting OpenMP thread of PARDISO's solves counts as CPU time, and on a loaded machine
that tripled the CPU seconds (measured: 50 s against 14 s at load 8).

Same result: :func:`revision_result` computes the same position with the code of another git revision (extracted
with ``git archive`` into a scratch folder and run there by a fresh interpreter, so nothing of this revision is
imported) and :func:`max_relative_difference` compares every numeric field of the two IndentationResults relative
to that field's largest magnitude (``reverse_plasticity_mm``, a difference of two nearly equal displacements, is
compared relative to the residual dents). The code of the position's result must agree within
``SAME_RESULT_RTOL``::

    python -m benchmarks.bench_fem_position --against <revision>   # prints the split and the differences
"""

from __future__ import annotations

import argparse
import cProfile
import json
import os
import pstats
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
CONFIG = "calibration/configs/default.toml"
#: a code change must leave the position's result within this relative difference (-)
SAME_RESULT_RTOL = 1e-6
#: fields of an IndentationResult that are not results (times, files, cost counts)
NOT_RESULTS = {"seconds", "output_seconds", "files", "newton_iterations", "linear_solves", "factorisations"}
#: phases of the split: name -> the functions ("module:qualified name") whose cumulative times are summed
PHASES = {
    "meshing": ["calibration.indentation:build_mesh"],
    "discretisation": ["calibration.fem.assembly:discretise"],
    "assembly": ["calibration.fem.problem:TangentProblem.__init__", "calibration.hertz.load:HertzLoad.prepare"],
    "factorisation": ["calibration.fem.linear_solvers:Factoriser.factorise"],
    "Newton": ["calibration.fem.newton:newton_increment"],
    "of which solves": ["calibration.fem.linear_solvers:Factoriser.solve"],
    "output": ["calibration.fem.output:FieldSeries.__call__", "calibration.fem.output:write_increment_output",
               "calibration.fem.output:FieldSeries.write_pvd"],
}
#: the return mapping (calls are counted)
RETURN_MAPPING = "calibration.fem.return_mapping:radial_return"
#: snippet run by a fresh interpreter inside another revision's tree: the position's IndentationResult as JSON
_SNIPPET = """
import json, sys
from pathlib import Path
from calibration.config import load_config
from calibration.tasks import make_tasks, run_position
cfg = load_config({config!r})
tasks, _, _ = make_tasks(cfg, Path({out!r}), plots=False)
task = [t for t in tasks if t.body == {body!r} and t.y_mm == {y!r}][0]
out = run_position(task)
if out.error:
    sys.exit(out.error)
Path({dest!r}).write_text(json.dumps(out.indentation.to_dict()))
"""


def position_task(body: str = "rail", y_mm: float = 0.0, plots: bool = False, out_dir: Path | None = None):
    """The task of one position of the default configuration (fields into ``out_dir`` with plots)."""
    from calibration.config import load_config
    from calibration.tasks import make_tasks

    cfg = load_config(REPO / CONFIG)
    tasks, _, _ = make_tasks(cfg, Path(out_dir or tempfile.mkdtemp()), plots=plots)
    return next(t for t in tasks if t.body == body and t.y_mm == y_mm)


def _code_key(name: str) -> tuple[str, int, str]:
    """cProfile's key (file, first line, function name) of ``module:qualified.name``."""
    import importlib

    module, qualname = name.split(":")
    obj = importlib.import_module(module)
    for part in qualname.split("."):
        obj = getattr(obj, part)
    code = obj.__code__
    return code.co_filename, code.co_firstlineno, code.co_name


def _phase_seconds(stats: pstats.Stats, wanted: list[str]) -> tuple[float, int]:
    """Cumulative time (s) and calls of the functions ``wanted``."""
    total, calls = 0.0, 0
    for key in map(_code_key, wanted):
        if key in stats.stats:
            _, n_calls, _, cum, _ = stats.stats[key]
            total, calls = total + cum, calls + n_calls
    return total, calls


def timed_position(body: str = "rail", y_mm: float = 0.0, plots: bool = False) -> dict:
    """Run one position under cProfile: wall and CPU time, load average, the CPU split and the counts."""
    from benchmarks.bench_fem_memory import peak_rss_mb, reset_peak
    from calibration.tasks import run_position
    from wrlayer.runner import limited_threads

    with tempfile.TemporaryDirectory() as tmp, limited_threads(1):
        task = position_task(body, y_mm, plots, Path(tmp))
        load_before = os.getloadavg()[0]
        reset_peak()
        prof = cProfile.Profile(time.process_time)  # CPU seconds: robust to the machine's other load
        cpu0, t0 = time.process_time(), time.perf_counter()
        prof.enable()
        out = run_position(task)
        prof.disable()
        wall, cpu = time.perf_counter() - t0, time.process_time() - cpu0
    if out.error:
        raise RuntimeError(out.error)
    res = out.indentation
    stats = pstats.Stats(prof)
    split = {name: _phase_seconds(stats, fns)[0] for name, fns in PHASES.items()}
    # the assembly's own factorisation is counted under factorisation
    split["assembly"] = max(0.0, split["assembly"] - _first_factorisation(stats))
    split["rest"] = cpu - sum(v for k, v in split.items() if k != "of which solves")
    rm_s, rm_calls = _phase_seconds(stats, [RETURN_MAPPING])
    return {"body": body, "y_mm": y_mm, "plots": plots, "wall_s": wall, "cpu_s": cpu,
            "load_1min": [load_before, os.getloadavg()[0]], "split_s": split, "peak_memory_MiB": peak_rss_mb(),
            "counts": {"newton_iterations": res.newton_iterations, "linear_solves": res.linear_solves,
                       "factorisations": res.factorisations, "return_mapping_calls": rm_calls,
                       "return_mapping_s": rm_s, "n_dofs": res.n_dofs, "n_elements": res.n_elements},
            "result": res.to_dict()}


def _first_factorisation(stats: pstats.Stats) -> float:
    """Time (s) of the factorisations called from the assembly (TangentProblem.__init__)."""
    entry = stats.stats.get(_code_key(PHASES["factorisation"][0]))
    caller = entry[4].get(_code_key(PHASES["assembly"][0])) if entry else None
    return caller[3] if caller else 0.0


def revision_result(revision: str, body: str = "rail", y_mm: float = 0.0) -> dict:
    """The position's IndentationResult (dict) computed by the code of git ``revision`` (no plots)."""
    from benchmarks.harness import revision_tree

    with revision_tree(revision) as tree:
        dest = tree.parent / "result.json"
        code = _SNIPPET.format(config=CONFIG, out=str(tree.parent / "out"), body=body, y=float(y_mm),
                               dest=str(dest))
        env = {**os.environ, "PYTHONPATH": str(tree)}
        subprocess.run([sys.executable, "-c", code], cwd=tree, env=env, check=True)
        return json.loads(dest.read_text())


def max_relative_difference(reference: dict, other: dict) -> dict[str, float]:
    """Per numeric field: max |a - b| / max |a| (reverse_plasticity_mm: relative to the largest residual dent)."""
    out = {}
    for key, a in reference.items():
        if key in NOT_RESULTS or isinstance(a, bool) or a is None:
            continue
        b = other[key]
        if isinstance(a, dict):
            for sub, values in a.items():
                out[f"{key}.{sub}"] = _rel(values, b[sub], values)
        elif isinstance(a, (int, float)) or (isinstance(a, list) and (not a or isinstance(a[0], (int, float)))):
            scale = reference["residual_fem_mm"] if key == "reverse_plasticity_mm" else a
            out[key] = _rel(a, b, scale)
    return out


def _rel(a, b, scale) -> float:
    a, b = np.atleast_1d(np.asarray(a, dtype=float)), np.atleast_1d(np.asarray(b, dtype=float))
    if a.shape != b.shape:
        return float("inf")
    if a.size == 0:
        return 0.0
    ref = float(np.max(np.abs(np.asarray(scale, dtype=float))))
    return float(np.max(np.abs(a - b)) / ref) if ref > 0 else float(np.max(np.abs(a - b)))


def _markdown(rows: list[dict], check: dict | None) -> str:
    lines = ["| run | wall (s) | CPU (s) | load (1 min) | peak memory (MiB) | " + " | ".join(PHASES) + " | rest |",
             "|---" * (6 + len(PHASES)) + "|"]
    for r in rows:
        s = r["split_s"]
        lines.append(f"| {'with plots' if r['plots'] else 'no plots'} | {r['wall_s']:.2f} | {r['cpu_s']:.2f} | "
                     f"{r['load_1min'][0]:.1f}-{r['load_1min'][1]:.1f} | {r['peak_memory_MiB']:.0f} | "
                     + " | ".join(f"{s[k]:.2f}" for k in PHASES) + f" | {s['rest']:.2f} |")
    c = rows[0]["counts"]
    text = ("Direct 3D calibration of the 60E1 rail crown (y = 0), default configuration, one worker, times in s "
            "(the phases: CPU seconds, cProfile). Target: 3 s per position on an idle 2-core machine.\n\n" + "\n".join(lines)
            + f"\n\nCounts: {c['n_dofs']} dofs, {c['newton_iterations']} Newton iterations, {c['linear_solves']} "
            f"triangular solves, {c['factorisations']} factorisations, {c['return_mapping_calls']} return mappings.\n")
    if check is not None:
        worst = max(check["differences"].values())
        ref = check["counts"]
        text += (f"\nRevision {check['revision']}: {ref['newton_iterations']} Newton iterations, "
                 f"{ref['linear_solves']} triangular solves, {ref['factorisations']} factorisations. Same result: "
                 f"largest relative difference {worst:.1e} (limit {SAME_RESULT_RTOL:.0e}).\n")
    return text


def run(mode: str, out: Path) -> dict:
    rows = [timed_position(plots=False)]
    if mode != "quick":
        rows.append(timed_position(plots=True))
    for r in rows:
        r.pop("result")
    return {"title": "FEM: one direct 3D calibration position, split and counts", "markdown": _markdown(rows, None),
            "figures": [], "data": {"runs": rows}}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.bench_fem_position", description=__doc__.splitlines()[0])
    ap.add_argument("--against", metavar="REVISION", help="git revision whose result must be the same")
    ap.add_argument("--plots", action="store_true", help="also time the run with the VTK/PNG fields")
    ap.add_argument("--json", type=Path, help="write the measurements there")
    ap.add_argument("--report", type=Path, help="write a stamped markdown report there")
    args = ap.parse_args(argv)
    rows = [timed_position(plots=False)] + ([timed_position(plots=True)] if args.plots else [])
    check = None
    if args.against:
        ref = revision_result(args.against)
        check = {"revision": args.against, "differences": max_relative_difference(ref, rows[0]["result"]),
                 "counts": {k: ref[k] for k in ("newton_iterations", "linear_solves", "factorisations")}}
    text = _markdown(rows, check)
    print(text)
    if args.report:
        from benchmarks.harness import command_line, stamped_report

        args.report.write_text(stamped_report("FEM: one direct 3D calibration position, split and counts", text,
                                              command_line("python -m benchmarks.bench_fem_position", argv)))
    if check:
        for key, d in sorted(check["differences"].items(), key=lambda kv: -kv[1]):
            print(f"  {key:40s} {d:.2e}")
    if args.json:
        args.json.write_text(json.dumps({"runs": rows, "check": check}, indent=1))
    return 0 if check is None or max(check["differences"].values()) <= SAME_RESULT_RTOL else 1


if __name__ == "__main__":
    sys.exit(main())
