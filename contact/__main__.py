"""Command line of the contact solver.

    wrlayer simulate SCENE --out DIR [--json] [--plots] [--no-vtk]
    wrlayer simulate-all SCENES_DIR --out OUT [--plots] [--no-vtk]
    wrlayer wear SCENE --out DIR [--no-plots] [--workers N] [--scheduler ADDRESS]   (contact.wear.cli)

``simulate`` writes ``DIR/result.json``, the frictional CSVs, the VTK fields ``DIR/vtk/contact_fields.pvd`` (unless
``--no-vtk`` or ``output.vtk = false``) and pictures with ``--plots``, atomically: on any error nothing is
written; the folder is built beside DIR and replaces it as a whole (:func:`wrlayer.atomic_write.replace_output_dir`:
a lock refuses a second run into the same DIR, files of an earlier run never survive beside the new ones). A run
whose estimated cost exceeds the limit is refused up front unless ``--force`` (:mod:`contact.scenes.cost`).
``simulate-all`` runs every ``*.toml`` of the folder into ``OUT/<scene-stem>/``, then writes a table like the
paper's Table 1 to ``OUT/table.md`` and ``OUT/table.csv`` and prints a summary that fits 100 columns (one short
table per scene kind, :func:`contact.scenes.result_table.summary_text`); a failing scene is reported in one line,
the others still run, and the exit code is non-zero if any failed.

Exit codes: 0 success; 1 some scenes of ``simulate-all`` failed (each reported in one line); 2 bad input (scene,
table or profile file, a refused cost, a busy ``--out``); 3 numerical failure (ConvergenceError); 4 some cases of a
wheel–rail sweep failed (each printed on stderr as case, wheel, reason; every result, the failed cases' errors
included, was written; ``simulate-all`` gives 4 when no scene but some case failed); 5 wear loop stopped at a step
(see :mod:`contact.wear.cli`); 130 interrupted; 143 terminated.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from wrlayer import cli
from wrlayer.atomic_write import atomic_write_text, output_lock, replace_output_dir
from wrlayer.cost import guard
from wrlayer.errors import InputError, WrLayerError, cli_guard, record_kept
from wrlayer.jit import run_mode


def run_scene_file(scene_path: str | Path, out_dir: str | Path, plots: bool = False,
                   force: bool = False, vtk: bool = True, run: Any = None) -> dict[str, Any]:
    """Run one scene file into ``out_dir`` (result.json + pictures, atomically); returns the result dict.

    The run's cost is estimated first (:mod:`contact.scenes.cost`); above :data:`wrlayer.cost.LIMIT_SECONDS` it is
    refused (CostError, exit 2) unless ``force``. VTK fields (:mod:`contact.scenes.vtk_output`) are written when the
    scene's ``output.vtk`` and ``vtk`` (False: ``--no-vtk``) are both true; contact_convention.csv with
    ``output.convention = "contact"`` (:mod:`contact.scenes.contact_convention`). ``run``: a
    :class:`contact.wheel_rail.scene.RunSpec` in place of a wheel–rail scene's ``[run]`` (``--workers``,
    ``--scheduler``; the numbers do not depend on it)."""
    from contact.scenes.scene import read_scene_data, scene_type

    scene_path, data = read_scene_data(scene_path)
    kind = scene_type(data, scene_path)
    out_dir = Path(out_dir)
    if out_dir.exists() and not out_dir.is_dir():
        raise InputError(f"--out {out_dir}", "exists and is not a folder")
    if kind == "wheel_rail":
        from contact.scenes.cost import wheel_rail_cost
        from contact.wheel_rail.parse import parse_wheel_rail_scene
        from contact.wheel_rail.run import run_wheel_rail_scene

        scene = parse_wheel_rail_scene(data, scene_path)
        if run is not None:
            scene = dataclasses.replace(scene, run=run)
        estimate = guard(wheel_rail_cost(scene), force)
        with run_mode(estimate.seconds), replace_output_dir(out_dir) as tmp:
            result = run_wheel_rail_scene(scene, tmp, plots, vtk=vtk and scene.output.vtk)
            (tmp / "result.json").write_text(result.to_json(), encoding="utf-8")
        return result.to_dict()

    from contact.scenes.scene import parse_scene

    scene = parse_scene(data, scene_path)  # before importing the solvers: a bad scene fails fast
    from contact.scenes.cost import scene_cost

    estimate = guard(scene_cost(scene), force)
    from contact.scenes.simulation import simulate

    with run_mode(estimate.seconds):  # a small scene's kernels run as plain Python: no numba start-up
        run = simulate(scene)
    result = run.result
    result.to_json()  # serialisable before anything is written (a failure leaves no file)
    with replace_output_dir(out_dir) as tmp:
        from contact.tangential.frictional_outputs import write_scene_run

        # wear-ready CSVs beside result.json
        result = dataclasses.replace(result, frictional_outputs=tuple(write_scene_run(run, tmp)))
        if vtk and scene.output.vtk:
            from contact.scenes.vtk_output import scene_items, write_series

            write_series(scene_items(run), tmp)
        if scene.output.convention == "contact":
            from contact.scenes.contact_convention import write_contact_convention

            write_contact_convention(result.to_dict(), tmp)
        if plots:
            from contact.scenes.plots import write_scene_plots

            result = dataclasses.replace(result, pictures=tuple(p.name for p in write_scene_plots(run, tmp)))
        (tmp / "result.json").write_text(result.to_json(), encoding="utf-8")
    return result.to_dict()


def failed_cases(result: dict[str, Any]) -> list[str]:
    """One line per failed case of a wheel–rail sweep result: case number, wheel and reason (empty otherwise)."""
    return [f"case {c.get('case', k)}: {c.get('failed_wheel') or 'wheelset'}: {c['error']}"
            for k, c in enumerate(result.get("cases") or []) if c.get("error") is not None]


def report_failed_cases(name: str, result: dict[str, Any]) -> int:
    """Print the failed cases of a sweep on stderr; the exit code: 4 when some failed (all results written), 0."""
    lines = failed_cases(result)
    for line in lines:
        print(f"error: {name}: {line}", file=sys.stderr, flush=True)
    if lines:
        print(f"error: {name}: {len(lines)} of {len(result['cases'])} cases failed (the others were written)",
              file=sys.stderr, flush=True)
    return 4 if lines else 0


def _simulate(args: argparse.Namespace) -> int:
    run = None
    if args.workers is not None or args.scheduler is not None:
        from contact.wheel_rail.scene import RunSpec

        if args.workers is not None and args.workers < 1:
            raise InputError("--workers", f"must be >= 1, got {args.workers}")
        run = RunSpec(workers=args.workers or 1, scheduler=args.scheduler or "")
    result = run_scene_file(args.scene, args.out, plots=args.plots, force=args.force, vtk=not args.no_vtk, run=run)
    if args.json:
        from contact.scenes.result_io import result_text

        sys.stdout.write(result_text(result))
    else:
        print(f"{Path(args.scene).name}: wrote {Path(args.out) / 'result.json'}")
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
    from contact.scenes.result_table import results_table, summary_text

    results: dict[str, dict[str, Any]] = {}
    failed = []
    code = 0
    for path in scenes:
        try:
            results[path.stem] = run_scene_file(path, out / path.stem, plots=args.plots, force=args.force,
                                                vtk=not args.no_vtk)
            record_kept(f"{len(results)} of {len(scenes)} scene outputs complete in {out}")  # the SIGTERM line
            print(f"{path.name}: ok -> {out / path.stem / 'result.json'}", flush=True)
            code = max(code, report_failed_cases(path.name, results[path.stem]))
        except WrLayerError as err:
            failed.append(path.name)
            named = getattr(err, "what", "").split(":")[0].strip() in (path.name, str(path))
            print(f"error: {err}" if named else f"error: {path.name}: {err}", file=sys.stderr, flush=True)
        except Exception as err:  # noqa: BLE001 - a programming error in one scene must not stop the batch
            failed.append(path.name)
            print(f"error: {path.name}: internal error {type(err).__name__}: {err}", file=sys.stderr, flush=True)
    if results:
        markdown, csv = results_table(results)
        atomic_write_text(out / "table.md", markdown)
        atomic_write_text(out / "table.csv", csv)
        print()
        print(summary_text(results, out), flush=True)
    if failed:
        print(f"error: {len(failed)} of {len(scenes)} scenes failed: {', '.join(failed)}", file=sys.stderr)
        return 1
    return code


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
    one.add_argument("--workers", type=int, default=None,
                     help="wheel-rail sweeps: local worker processes for the cases (overrides [run] workers)")
    one.add_argument("--scheduler", default=None, metavar="ADDRESS",
                     help="wheel-rail sweeps: Dask scheduler address for the cases (overrides [run] scheduler)")
    one.set_defaults(func=_simulate)
    many = cli.subparser(sub, "simulate-all",
                         "run every *.toml in a folder and print a summary (full table in OUT/table.md)",
                         ["wrlayer simulate-all scenes --out out/simulate --plots"])
    many.add_argument("scenes_dir", help="folder of scene TOML files")
    cli.add_run_options(many, "output folder (one subfolder per scene, table.md, table.csv)", quiet=False)
    many.add_argument("--plots", action="store_true", help="write PNG pictures")
    many.add_argument("--no-vtk", action="store_true", help="do not write the VTK fields for ParaView (vtk/)")
    many.set_defaults(func=_simulate_all)
    from contact.wear.cli import add_parser as add_wear_parser

    add_wear_parser(sub)
    return parser


@cli_guard
def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    return args.func(args)


if __name__ == "__main__":
    sys.exit(main())
