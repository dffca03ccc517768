"""Command line of the contact solver.

    wrlayer simulate SCENE --out DIR [--json] [--plots] [--no-vtk]
    wrlayer simulate-all SCENES_DIR --out OUT [--plots] [--no-vtk]
    wrlayer wear SCENE --out DIR [--no-plots] [--workers N] [--scheduler ADDRESS] [--quiet]
    wrlayer geometry --rail RAIL --wheel WHEEL --out DIR [...]   (contact.geometry.command)

Every command that reads profile files takes ``--accept-unusual-profile`` (:func:`wrlayer.cli.add_profile_check_option`).

Argument parsing only: the runs and their files are :mod:`contact.run_files`. ``simulate`` writes
``DIR/result.json``, the frictional CSVs, the VTK fields ``DIR/vtk/contact_fields.pvd`` (unless ``--no-vtk`` or
``output.vtk = false``) and pictures with ``--plots``, atomically: on any error nothing is written. A run whose
estimated cost exceeds the limit is refused up front unless ``--force`` (:mod:`contact.scenes.cost`).
``simulate-all`` runs every ``*.toml`` of the folder into ``OUT/<scene-stem>/``, then writes a table like the
paper's Table 1 to ``OUT/table.md`` and ``OUT/table.csv`` and prints a summary that fits 100 columns (one short
table per scene kind, :func:`contact.scenes.result_table.summary_text`); a failing scene is reported in one line,
the others still run, and the exit code is non-zero if any failed. ``simulate`` and each scene of ``simulate-all``
print the scene's key numbers (:func:`contact.scenes.result_table.scene_summary`). ``wear`` runs a wear scene
(:func:`contact.run_files.run_wear_file`: published step by step; a bad scene, a scheduler address of a wrong form
or a refused cost fails before anything is written) and prints one line per step.

Exit codes: 0 success; 1 some scenes of ``simulate-all`` failed (each reported in one line); 2 bad input (scene,
table or profile file, a refused cost, a busy ``--out``); 3 numerical failure (ConvergenceError); 4 some cases of a
wheel–rail sweep failed (each printed on stderr as case, wheel, reason; every result, the failed cases' errors
included, was written; ``simulate-all`` gives 4 when no scene but some case failed); 5 wear loop stopped at a step
(result.json says "stopped: step N: ..."; the completed steps were written); 130 interrupted; 143 terminated (a
wear run's published steps in ``DIR.partial`` are marked so).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from contact.geometry.command import add_parser as add_geometry_parser
from wrlayer import cli
from wrlayer.atomic_write import output_lock
from wrlayer.errors import InputError, cli_guard, record_kept

if TYPE_CHECKING:
    from contact.scenes.run_result import SceneResult
    from contact.wheel_rail.results import SweepResult


def report_failed_cases(name: str, result: SceneResult | SweepResult) -> int:
    """Print the failed cases of a sweep on stderr; the exit code: 4 when some failed (all results written), 0."""
    from contact.run_files import failed_cases

    lines = failed_cases(result)
    for line in lines:
        print(f"error: {name}: {line}", file=sys.stderr, flush=True)
    if lines:
        print(f"error: {name}: {len(lines)} of {len(result.cases)} cases failed (the others were written)",
              file=sys.stderr, flush=True)
    return 4 if lines else 0


def _simulate(args: argparse.Namespace) -> int:
    from contact.run_files import run_scene

    result = run_scene(args.scene, args.out, plots=args.plots, force=args.force, vtk=not args.no_vtk,
                       workers=args.workers, scheduler=args.scheduler,
                       accept_unusual_profile=args.accept_unusual_profile)
    if args.json:
        sys.stdout.write(result.to_json())
    else:
        from contact.scenes.result_table import scene_summary

        print("\n".join(scene_summary(Path(args.scene).name, result)))
        print(f"{Path(args.scene).name}: wrote {Path(args.out) / 'result.json'}")
    for line in result.warnings or ():
        print(line, file=sys.stderr)
    return report_failed_cases(Path(args.scene).name, result)


def _simulate_all(args: argparse.Namespace) -> int:
    folder = Path(args.scenes_dir)
    if not folder.is_dir():
        raise InputError(str(folder), "no such scenes folder")
    scenes = sorted(folder.glob("*.toml"))
    if not scenes:
        raise InputError(str(folder), "holds no *.toml scene files")
    out = Path(args.out)
    with output_lock(out):
        return _run_all(scenes, out, args)


def _run_all(scenes: list[Path], out: Path, args: argparse.Namespace) -> int:
    from contact.run_files import run_scene_folder, write_folder_tables
    from contact.scenes.result_table import scene_summary

    results: dict[str, SceneResult | SweepResult] = {}
    failed = []
    code = 0
    for path, result, error in run_scene_folder(scenes, out, plots=args.plots, force=args.force,
                                                vtk=not args.no_vtk,
                                                accept_unusual_profile=args.accept_unusual_profile):
        if result is None:
            failed.append(path.name)
            print(error, file=sys.stderr, flush=True)
            continue
        results[path.stem] = result
        for line in result.warnings or ():
            print(line, file=sys.stderr)
        record_kept(f"{len(results)} of {len(scenes)} scene outputs complete in {out}")  # the SIGTERM line
        print(f"{path.name}: ok -> {out / path.stem / 'result.json'}")
        print("\n".join("  " + line for line in scene_summary(path.stem, result)), flush=True)
        code = max(code, report_failed_cases(path.name, result))
    if results:
        summary = write_folder_tables(results, out)
        print()
        print(summary, flush=True)
    if failed:
        print(f"error: {len(failed)} of {len(scenes)} scenes failed: {', '.join(failed)}", file=sys.stderr)
        return 1
    return code


def _wear(args: argparse.Namespace) -> int:
    from contact.run_files import run_wear_into

    run, _ = run_wear_into(args.scene, args.out, plots=not args.no_plots, workers=args.workers,
                           scheduler=args.scheduler, show_progress=not args.quiet, force=args.force,
                           accept_unusual_profile=args.accept_unusual_profile)
    from contact.result_warnings import method_warnings
    from contact.scenes.result_table import wear_summary

    print("\n".join(wear_summary(Path(args.scene).name, run.steps, Path(args.out) / "result.json")))
    for line in method_warnings(Path(args.scene).name, run.scene.normal.name):
        print(line, file=sys.stderr)
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = cli.parser("python -m contact", "Kik–Piotrowski contact with the Prandtl-body layer, FASTSIM, passes to "
                        "shakedown, wheel-on-rail scenes (units mm, N, MPa, s).",
                        ["wrlayer simulate scenes/paper_with_layer.toml --out out/one --plots",
                         "wrlayer simulate-all scenes --out out/simulate",
                         "wrlayer wear scenes/wear/s1002_60e1.toml --out out/wear"])
    sub = parser.add_subparsers(dest="command", required=True)
    one = cli.subparser(sub, "simulate", "run one scene file",
                        ["wrlayer simulate scenes/calibrated_layers.toml --out out/one --plots"])
    one.add_argument("scene", help="scene TOML file")
    cli.add_run_options(one, "output folder (result.json, pictures)", quiet=False)
    one.add_argument("--json", action="store_true", help="also print the result JSON")
    one.add_argument("--plots", action="store_true", help="write PNG pictures")
    one.add_argument("--no-vtk", action="store_true", help="do not write the VTK fields for ParaView (vtk/)")
    cli.add_profile_check_option(one)
    cli.add_worker_options(one, "wheel-rail sweeps: local worker processes for the cases (overrides [run] workers)",
                           "wheel-rail sweeps: Dask scheduler address for the cases (overrides [run] scheduler)")
    one.set_defaults(func=_simulate)
    many = cli.subparser(sub, "simulate-all",
                         "run every *.toml in a folder and print a summary (full table in OUT/table.md)",
                         ["wrlayer simulate-all scenes --out out/simulate --plots"])
    many.add_argument("scenes_dir", help="folder of scene TOML files")
    cli.add_run_options(many, "output folder (one subfolder per scene, table.md, table.csv)", quiet=False)
    many.add_argument("--plots", action="store_true", help="write PNG pictures")
    many.add_argument("--no-vtk", action="store_true", help="do not write the VTK fields for ParaView (vtk/)")
    cli.add_profile_check_option(many)
    many.set_defaults(func=_simulate_all)
    wear = cli.subparser(sub, "wear", "run a wear scene (profiles evolving by wear and inelastic displacement)",
                         ["wrlayer wear scenes/wear/s1002_60e1.toml --out out/wear",
                          "wrlayer wear scenes/wear/s1002_60e1.toml --out out/wear --workers 2 --no-plots"])
    wear.add_argument("scene", help="wear scene TOML file")
    cli.add_run_options(wear, "output folder (profiles/, depth/, steps.csv, result.json, PNGs)")
    wear.add_argument("--no-plots", action="store_true", help="do not write PNG pictures")
    cli.add_profile_check_option(wear)
    cli.add_worker_options(wear, "local processes per step (default: the scene's)",
                           "Dask scheduler address (default: the scene's; none = local)")
    wear.set_defaults(func=_wear)
    add_geometry_parser(sub)
    return parser


@cli_guard
def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    return args.func(args)


if __name__ == "__main__":
    sys.exit(main())
