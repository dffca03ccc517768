"""One rolling pass of the shipped half-space configuration (calibration/configs/rolling_halfspace.toml) at one
level: CPU seconds, Newton iterations, CG iterations, triangular solves and the groove, and the same pass computed
by the code of another git revision (units s, mm, MPa).

The set-up (mesh, elastic factorisation, the unit responses of every sub-step position, which all passes and
levels share) is counted apart from the pass. One BLAS/MKL thread; the CPU seconds are those of this process
(``time.process_time``), with the machine's 1-minute load average, because the machine is shared: compare the
counts, not the seconds, between runs on a loaded machine. Target: 15 s per pass on an idle 2-core machine.

``--against REV`` runs this file with the code of revision REV (``git archive`` into a scratch folder, a fresh
interpreter whose path starts there, so nothing of this revision's engine is imported) and reports both passes
and the largest groove difference relative to the deepest groove point::

    python -m benchmarks.bench_rolling_pass [--level 1.7] [--length 2.0] [--against 74239b4] [--report FILE]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from dataclasses import replace
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
CONFIG = "calibration/configs/rolling_halfspace.toml"
#: the acceptance of a change of the solver: the grooves of the same pass agree within this relative difference
SAME_GROOVE_RTOL = 5e-3


def one_pass(level_py: float = 1.7, length_factor: float | None = None, config: str = CONFIG,
             elements: float | None = None) -> dict:
    """The first pass at ``level_py`` x p_y of ``config`` (track half-length ``length_factor`` x a, elements per
    contact semi-axis ``elements``; default the configuration's): set-up and pass CPU seconds, counts and the
    groove profile (mm)."""
    from threadpoolctl import threadpool_limits

    from calibration.fem.solver_state import SolverState
    from calibration.rolling.config import load_rolling_config
    from calibration.rolling.passes import MovingLoadPass, roll
    from calibration.rolling.run import body_mesh, build_model
    from calibration.rolling.substeps import SubstepSolver, UnitResponses

    cfg = load_rolling_config(Path(config))
    if length_factor is not None:
        cfg = replace(cfg, track=replace(cfg.track, length_factor=float(length_factor)))
    if elements is not None:
        cfg = replace(cfg, mesh=replace(cfg.mesh, elements_per_semi_axis=float(elements)))
    with threadpool_limits(limits=1):
        load = [os.getloadavg()[0]]
        c0 = time.process_time()
        model = build_model(cfg, body_mesh(cfg))
        positions = [x * cfg.contact.a_mm for x in cfg.track.positions_over_a()]
        responses = UnitResponses(model.prob, model.forces)
        solver = SubstepSolver(model.prob, model.forces, level_py * model.p_y_MPa, cfg.track.substeps,
                               responses=responses)
        for a, b in zip(positions[:-1], positions[1:]):  # every sub-step position of the pass (shared by all)
            solver.elastic_path(solver_target(a, 1.0), solver_target(b, 1.0))
        setup_cpu, setup_solves = time.process_time() - c0, model.prob.factor.n_solves
        c1 = time.process_time()
        done = [r for r in roll(solver, SolverState.virgin(model.disc), positions, 1, cfg.track.ramp_steps)
                if isinstance(r, MovingLoadPass)][0]
        pass_cpu = time.process_time() - c1
        load.append(os.getloadavg()[0])
    groove = model.probe.profile(done.state)
    return {"config": str(config), "level_py": level_py, "length_factor": cfg.track.length_factor,
            "elements_per_semi_axis": cfg.mesh.elements_per_semi_axis, "substeps": cfg.track.substeps, "n_dofs": int(model.disc.n_dofs),
            "steps": done.n_steps, "setup_cpu_s": setup_cpu, "setup_solves": setup_solves, "pass_cpu_s": pass_cpu,
            "newton_iterations": done.newton_iters, "cg_iterations": done.cg_iters,
            "solves": model.prob.factor.n_solves - setup_solves,
            "factorisations": model.prob.factor.n_factorisations, "load_1min": load,
            "groove_mm": float(groove.groove_mm), "depth_along_mm": [float(x) for x in groove.depth_along_mm]}


def solver_target(x_mm: float, fraction: float):
    """A load target (centre x in mm, fraction of p0) of :mod:`calibration.rolling.passes`."""
    from calibration.rolling.passes import Target

    return Target(x_mm, fraction)


def revision_pass(revision: str, level_py: float, length_factor: float | None, config: str = CONFIG,
                  elements: float | None = None) -> dict:
    """:func:`one_pass` computed by the code of git ``revision`` (this file run inside its extracted tree)."""
    from benchmarks.harness import revision_tree

    with revision_tree(revision) as tree:
        dest = tree.parent / "pass.json"
        args = [sys.executable, str(Path(__file__).resolve()), "--level", str(level_py), "--json", str(dest),
                "--config", str(tree / config) if not Path(config).is_absolute() else config, "--child"]
        args += [] if length_factor is None else ["--length", str(length_factor)]
        args += [] if elements is None else ["--elements", str(elements)]
        subprocess.run(args, cwd=tree, env={**os.environ, "PYTHONPATH": str(tree)}, check=True)
        return json.loads(dest.read_text())


def groove_difference(reference: dict, other: dict) -> float:
    """Largest |depth difference| along the track relative to the reference's deepest point (-)."""
    a, b = reference["depth_along_mm"], other["depth_along_mm"]
    if len(a) != len(b):
        return float("inf")
    scale = max(abs(x) for x in a)
    return max(abs(x - y) for x, y in zip(a, b)) / scale if scale > 0 else 0.0


def markdown(rows: dict[str, dict], difference: float | None) -> str:
    first = next(iter(rows.values()))
    config = Path(first["config"])
    config = config.relative_to(REPO) if config.is_relative_to(REPO) else config.name
    lines = [f"One pass at {first['level_py']:g} p_y of `{config}` ({first['n_dofs']} dofs, "
             f"{first['elements_per_semi_axis']:g} elements per contact semi-axis, track half-length "
             f"{first['length_factor']:g} a, {first['steps']} steps of {first['substeps']} material sub-steps), one "
             "BLAS thread. CPU seconds of this process on a shared machine, with the load: compare the counts.", "",
             "| code | set-up CPU (s) | set-up solves | pass CPU (s) | load (1 min) | Newton iterations | CG iterations "
             "| triangular solves | factorisations | groove (mm) |", "|---" * 10 + "|"]
    for name, r in rows.items():
        lines.append(f"| {name} | {r['setup_cpu_s']:.1f} | {r['setup_solves']} | {r['pass_cpu_s']:.1f} | "
                     f"{r['load_1min'][0]:.1f}-{r['load_1min'][1]:.1f} | {r['newton_iterations']} | "
                     f"{r['cg_iterations']} | {r['solves']} | {r['factorisations']} | {r['groove_mm']:.6g} |")
    if difference is not None:
        lines += ["", f"Largest groove difference along the track: {difference:.1e} of the deepest point (limit "
                      f"{SAME_GROOVE_RTOL:.1e})."]
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.bench_rolling_pass", description=__doc__.splitlines()[0])
    ap.add_argument("--level", type=float, default=1.7, help="load level in p_y (default 1.7)")
    ap.add_argument("--length", type=float, default=None, help="track half-length in a (default: the config's)")
    ap.add_argument("--config", default=CONFIG, help=f"rolling configuration (default {CONFIG})")
    ap.add_argument("--elements", type=float, default=None, help="elements per contact semi-axis (default: the "
                                                                   "config's; 4 is the section at h = a/4)")
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--against", metavar="REVISION", help="git revision whose pass is computed too")
    ap.add_argument("--json", type=Path, help="write the measurements there")
    ap.add_argument("--report", type=Path, help="write a stamped markdown report there")
    args = ap.parse_args(argv)
    here = one_pass(args.level, args.length, args.config, args.elements)
    if args.child:  # a run of another revision's code for --against: its measurements only
        args.json.write_text(json.dumps(here))
        return 0
    rows, difference = {"this revision": here}, None
    if args.against:
        rows = {args.against: revision_pass(args.against, args.level, args.length, args.config, args.elements),
                **rows}
        difference = groove_difference(rows[args.against], here)
    text = markdown(rows, difference)
    if args.json:
        args.json.write_text(json.dumps(here if not args.against else {"runs": rows, "difference": difference},
                                        indent=1))
    if args.report:
        from benchmarks.harness import command_line, stamped_report

        title = "FEM: one rolling pass, counts and CPU seconds"
        args.report.write_text(stamped_report(title, text, command_line("python -m benchmarks.bench_rolling_pass",
                                                                         argv)))
    print(text)
    return 0 if difference is None or difference <= SAME_GROOVE_RTOL else 1


if __name__ == "__main__":
    sys.exit(main())
