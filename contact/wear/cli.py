"""``python -m contact wear SCENE --out DIR [--no-plots] [--workers N] [--scheduler ADDRESS] [--quiet]``.

Runs a wear scene (:mod:`contact.wear.scene`) into DIR (files: :mod:`contact.wear.outputs`). A bad scene fails
before anything is written. A failure during the loop stops it with one line naming the step; every completed
step's profiles and the table stay in DIR, result.json says "stopped: ..." and the exit code is non-zero.
"""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from wrlayer import cli
from wrlayer.atomic_write import output_lock
from wrlayer.errors import InputError

if TYPE_CHECKING:
    from contact.wear.records import WearRun
    from contact.wear.scene import WearScene


def run_wear_file(scene_path: str | Path, out_dir: str | Path, plots: bool = True, workers: int | None = None,
                  scheduler: str | None = None, show_progress: bool = True) -> dict[str, Any]:
    """Run one wear scene; returns the result dict (raises WearStopped after writing the completed steps)."""
    # the solver stack (numpy, scipy, calibration) only when a scene runs: `python -m contact --help` stays quick
    from contact.scenes.scene import read_scene_data
    from contact.wear.scene import parse_wear_scene

    scene_path, data = read_scene_data(scene_path)
    scene = parse_wear_scene(data, scene_path)
    changes = {}
    if workers is not None:
        if workers < 1:
            raise InputError("--workers", f"must be >= 1, got {workers}")
        changes["workers"] = workers
    if scheduler is not None:
        changes["scheduler"] = scheduler
    if changes:
        scene = dataclasses.replace(scene, settings=dataclasses.replace(scene.settings, **changes))
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise InputError(f"--out {out}", "exists and is not a folder")
    with output_lock(out):  # a second wear run into the same folder is refused (its steps would mix)
        return _run_locked(scene, out, plots, show_progress)


def _run_locked(scene: WearScene, out: Path, plots: bool, show_progress: bool) -> dict[str, Any]:
    """Run the loop into ``out``, writing every step as it completes (the caller holds the folder's lock)."""
    # imported here for the same reason as in run_wear_file
    from contact.wear.loop import start_run, wear_steps
    from contact.wear.outputs import RunFiles
    from contact.wear.records import WearStopped

    out.mkdir(parents=True, exist_ok=True)
    for stale in list(out.glob("profiles/step_*")) + list(out.glob("depth/step_*")) + \
            list(out.glob("layer_state/step_*")) + \
            [p for p in out.glob("calibration/step_*/**/*") if p.is_file()]:
        stale.unlink()  # an earlier run's steps would be mistaken for this run's
    run = start_run(scene)
    files = RunFiles(out, run)
    try:
        for record in wear_steps(run, work_dir=out, show_progress=show_progress):
            files.step(record)
    except WearStopped as stop:
        files.finish(f"stopped: {stop.run.stopped}", _pictures(run, out, plots))
        raise
    return files.finish("complete", _pictures(run, out, plots))


def _pictures(run: WearRun, out: Path, plots: bool) -> list[Path]:
    if not (plots and run.steps):
        return []
    from contact.wear.plots import write_wear_plots  # matplotlib only when pictures are drawn

    return write_wear_plots(run, out)


def wear_command(args) -> int:
    result = run_wear_file(args.scene, args.out, plots=not args.no_plots, workers=args.workers,
                           scheduler=args.scheduler, show_progress=not args.quiet)
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
                      ["python -m contact wear scenes/wear/s1002_60e1.toml --out out/wear",
                       "python -m contact wear scenes/wear/s1002_60e1.toml --out out/wear --workers 2 --no-plots"])
    p.add_argument("scene", help="wear scene TOML file")
    p.add_argument("--out", required=True, help="output folder (profiles/, depth/, steps.csv, result.json, PNGs)")
    p.add_argument("--no-plots", action="store_true", help="do not write PNG pictures")
    p.add_argument("--workers", type=int, default=None, help="local processes per step (default: the scene's)")
    p.add_argument("--scheduler", default=None, help="Dask scheduler address (default: the scene's; none = local)")
    p.add_argument("--quiet", action="store_true", help="no progress bars")
    p.set_defaults(func=wear_command)


__all__ = ["add_parser", "run_wear_file", "wear_command"]
