"""``wrlayer wear SCENE --out DIR [--no-plots] [--workers N] [--scheduler ADDRESS] [--quiet] [--force]``.

Runs a wear scene (:mod:`contact.wear.scene`) into DIR (files: :mod:`contact.wear.outputs`). A bad scene, a
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

import contextlib
import dataclasses
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from wrlayer import cli
from wrlayer.atomic_write import StagedOutput, output_error, staged_output_dir
from wrlayer.cost import guard
from wrlayer.errors import InputError, Terminated, check_terminated

if TYPE_CHECKING:
    from contact.wear.records import WearRun
    from contact.wear.scene import WearScene

#: What a wear run writes in its folder (replaced by each run; other files of DIR, e.g. a user's notes, are kept).
WEAR_OWNED = ("result.json", "steps.csv", "*.png", "profiles/", "depth/", "layer_state/", "calibration/")


def run_wear_file(scene_path: str | Path, out_dir: str | Path, plots: bool = True, workers: int | None = None,
                  scheduler: str | None = None, show_progress: bool = True, force: bool = False) -> dict[str, Any]:
    """Run one wear scene into ``out_dir``; returns the result dict (raises WearStopped after publishing the
    completed steps). Refused (CostError, exit 2) when the estimate exceeds the limit, unless ``force``."""
    # the solver stack (numpy, scipy, calibration) only when a scene runs: `python -m contact --help` stays quick
    from contact.scenes.scene import read_scene_data
    from contact.wear.cost import wear_cost
    from contact.wear.scene import parse_wear_scene
    from wrlayer.runner import check_scheduler_address  # here: the process pool's modules only for a wear run

    scene_path, data = read_scene_data(scene_path)
    scene = parse_wear_scene(data, scene_path)
    changes = {}
    if workers is not None:
        if workers < 1:
            raise InputError("--workers", f"must be >= 1, got {workers}")
        changes["workers"] = workers
    if scheduler is not None:
        changes["scheduler"] = check_scheduler_address(scheduler, "--scheduler")
    if changes:
        scene = dataclasses.replace(scene, settings=dataclasses.replace(scene.settings, **changes))
    guard(wear_cost(scene), force)
    out = Path(out_dir)
    with staged_output_dir(out, owned=WEAR_OWNED) as staged:  # a second run into DIR is refused (the lock)
        try:
            return _run_staged(scene, staged, plots, show_progress)
        except OSError as err:  # a full disk or a permission: the path named once
            raise output_error(err, out) from None


def _run_staged(scene: WearScene, staged: StagedOutput, plots: bool, show_progress: bool) -> dict[str, Any]:
    """Run the loop in ``staged.dir``, publishing after every completed step (the caller holds DIR's lock)."""
    # imported here for the same reason as in run_wear_file
    from contact.wear.loop import start_run, wear_steps
    from contact.wear.outputs import RunFiles, mark_published
    from contact.wear.records import WearStopped

    run = start_run(scene)
    files = RunFiles(staged.dir, run)
    try:  # the end too (final files, pictures): a SIGTERM there marks the published steps like one in a step
        try:
            for record in wear_steps(run, work_dir=staged.dir, show_progress=show_progress):
                files.step(record)
                staged.publish(_kept(staged, len(run.steps)))
        except WearStopped as stop:
            files.finish(f"stopped: {stop.run.stopped}", _pictures(run, staged.dir, plots))
            staged.finish(f"the stopped run's {len(run.steps)} completed step(s) are in {staged.path}")
            raise
        result = files.finish("complete", _pictures(run, staged.dir, plots))
        check_terminated()  # a SIGTERM swallowed by a C callback (plots): the last published steps stay
        staged.finish(f"the complete run ({len(run.steps)} steps) is in {staged.path}")
        return result
    except (Terminated, KeyboardInterrupt, InputError, OSError) as err:
        if staged.where == staged.partial:  # the published steps say how the run ended (not an ended run in DIR)
            with contextlib.suppress(OSError, InputError):  # a full disk may refuse this too: "running" stays
                mark_published(staged.where, _end_status(err, staged.published, staged.where))
        raise


def _kept(staged: StagedOutput, steps: int) -> str:
    """What the SIGTERM line says once ``steps`` completed steps are published in the partial folder."""
    earlier = (staged.path / "result.json").is_file()
    return (f"{steps} completed step(s) kept in {staged.partial}; {staged.path} "
            + ("keeps the earlier output" if earlier else "was not written"))


def _end_status(err: BaseException, steps: int, out: Path) -> str:
    """result.json's status for a run ended by ``err`` after ``steps`` published steps."""
    if isinstance(err, Terminated):
        return f"terminated (SIGTERM) after step {steps}"
    if isinstance(err, KeyboardInterrupt):
        return f"interrupted after step {steps}"
    return f"stopped after step {steps}: {output_error(err, out) if isinstance(err, OSError) else err}"


def _pictures(run: WearRun, out: Path, plots: bool) -> list[Path]:
    if not (plots and run.steps):
        return []
    from contact.wear.plots import write_wear_plots  # matplotlib only when pictures are drawn

    return write_wear_plots(run, out)


def wear_command(args) -> int:
    result = run_wear_file(args.scene, args.out, plots=not args.no_plots, workers=args.workers,
                           scheduler=args.scheduler, show_progress=not args.quiet, force=args.force)
    steps = result["steps"]
    print(f"{Path(args.scene).name}: {len(steps)} steps, {result['distance_done_km']:.6g} km -> "
          f"{Path(args.out) / 'result.json'}, steps.csv, profiles/")
    for row in steps:
        worst = max(row["bodies"], key=lambda r: r["wear_max_mm"])
        print(f"  step {row['step']}: {row['start_km']:.6g}..{row['end_km']:.6g} km, max wear "
              f"{worst['wear_max_mm'] * 1e3:.2f} µm ({worst['side']} {worst['body']} at y = "
              f"{worst['wear_max_y_mm']:.2f} mm), dr = {row['conicity']['delta_r_mm']:.4f} mm", file=sys.stdout)
    return 0


def add_parser(sub) -> None:
    p = cli.subparser(sub, "wear", "run a wear scene (profiles evolving by wear and inelastic displacement)",
                      ["wrlayer wear scenes/wear/s1002_60e1.toml --out out/wear",
                       "wrlayer wear scenes/wear/s1002_60e1.toml --out out/wear --workers 2 --no-plots"])
    p.add_argument("scene", help="wear scene TOML file")
    cli.add_run_options(p, "output folder (profiles/, depth/, steps.csv, result.json, PNGs)")
    p.add_argument("--no-plots", action="store_true", help="do not write PNG pictures")
    p.add_argument("--workers", type=int, default=None, help="local processes per step (default: the scene's)")
    p.add_argument("--scheduler", default=None, help="Dask scheduler address (default: the scene's; none = local)")
    p.set_defaults(func=wear_command)


__all__ = ["WEAR_OWNED", "add_parser", "run_wear_file", "wear_command"]
