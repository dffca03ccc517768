"""``wrlayer wear SCENE --out DIR [--no-plots] [--workers N] [--scheduler ADDRESS] [--quiet] [--force]``.

Argument parsing only: runs a wear scene (:mod:`contact.wear.scene`) into DIR with
:func:`contact.run_files.run_wear_file` (files: :mod:`contact.wear.outputs`). A bad scene, a
scheduler address of a wrong form or a run whose estimated cost exceeds the limit (:mod:`contact.wear.cost`,
unless ``--force``) fails before anything is written.

The run is built in a staging folder beside DIR (:func:`wrlayer.atomic_write.staged_output_dir`) and published
as a whole after every completed step into ``DIR.partial`` beside DIR, with result.json saying "running: N steps
completed"; DIR keeps its earlier content until the run ends, when the run replaces it and ``DIR.partial`` is
removed. So a kill at any moment (even ``kill -9``) leaves DIR as it was (or the ended run) and the completed
steps of the killed run in ``DIR.partial`` with a result.json that matches them. At the end result.json says
"complete"; a failure during the loop stops it with one line naming the step, result.json says "stopped: step
N: ..." and the exit code is 5 (this ended run replaces DIR too); SIGTERM or Ctrl-C marks the published steps in
``DIR.partial`` "terminated after step N" / "interrupted after step N", says where they are and removes the
staging folder (exit 143 / 130); a full disk or another failure to write marks them "stopped after step N:
<path>: <reason>" (exit 2).
"""

from __future__ import annotations

import sys
from pathlib import Path

from wrlayer import cli


def wear_command(args) -> int:
    from contact.run_files import run_wear

    run, _ = run_wear(args.scene, args.out, plots=not args.no_plots, workers=args.workers, scheduler=args.scheduler,
                      show_progress=not args.quiet, force=args.force)
    done_km = run.steps[-1].end_km if run.steps else 0.0
    print(f"{Path(args.scene).name}: {len(run.steps)} steps, {done_km:.6g} km -> "
          f"{Path(args.out) / 'result.json'}, steps.csv, profiles/")
    for rec in run.steps:
        (side, body), worst = max(rec.bodies.items(), key=lambda item: item[1].stats.wear_max_mm)
        print(f"  step {rec.index}: {rec.start_km:.6g}..{rec.end_km:.6g} km, max wear "
              f"{worst.stats.wear_max_mm * 1e3:.2f} µm ({side} {body} at y = "
              f"{worst.stats.wear_max_y_mm:.2f} mm), dr = {rec.conicity.delta_r_mm:.4f} mm", file=sys.stdout)
    return 0


def add_parser(sub) -> None:
    p = cli.subparser(sub, "wear", "run a wear scene (profiles evolving by wear and inelastic displacement)",
                      ["wrlayer wear scenes/wear/s1002_60e1.toml --out out/wear",
                       "wrlayer wear scenes/wear/s1002_60e1.toml --out out/wear --workers 2 --no-plots"])
    p.add_argument("scene", help="wear scene TOML file")
    cli.add_run_options(p, "output folder (profiles/, depth/, steps.csv, result.json, PNGs)")
    p.add_argument("--no-plots", action="store_true", help="do not write PNG pictures")
    cli.add_worker_options(p, "local processes per step (default: the scene's)",
                           "Dask scheduler address (default: the scene's; none = local)")
    p.set_defaults(func=wear_command)


__all__ = ["add_parser", "wear_command"]
