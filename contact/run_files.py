"""Run a scene file of any kind (contact, wheel–rail, wear) into an output folder: the one place where scenes are
run and their files written (the command line, :mod:`contact.__main__`, only parses arguments).

A contact or wheel–rail scene writes ``DIR/result.json``, the frictional CSVs, the VTK fields
``DIR/vtk/contact_fields.pvd`` (unless ``vtk=False`` or ``output.vtk = false``), contact_convention.csv (with
``output.convention = "contact"``), a wheel–rail sweep also ``cases.csv`` and the contact table, and pictures with
``plots``, atomically: on any error nothing is written; the folder is built beside DIR and replaces it as a whole
(:func:`wrlayer.atomic_write.replace_output_dir`: a lock refuses a second run into the same DIR, files of an earlier
run never survive beside the new ones). A run whose estimated cost exceeds the limit is refused up front unless
``force`` (:mod:`contact.scenes.cost`, :mod:`contact.wear.cost`). A wear scene's folder is published step by step
(:func:`run_wear_file`). ``workers`` and ``scheduler`` replace the scene's (``[run]``, ``[wear]``) by one rule
(:func:`run_overrides`); the numbers do not depend on them. Units: mm, N, MPa, s, rad.
"""

from __future__ import annotations

import contextlib
import dataclasses
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

from wrlayer.atomic_write import (StagedOutput, atomic_write_text, output_error, replace_output_dir,
                                  staged_output_dir)
from wrlayer.cost import guard
from wrlayer.errors import InputError, Terminated, WrLayerError, check_terminated
from wrlayer.jit import run_mode

if TYPE_CHECKING:  # the solver stack is imported only when a scene runs: `python -m contact --help` stays quick
    from contact.scenes.run_result import SceneResult
    from contact.scenes.simulation import SimulationRun
    from contact.wear.records import WearRun
    from contact.wear.scene import WearScene
    from contact.wheel_rail.results import SweepResult
    from contact.wheel_rail.scene import WheelRailScene

#: What a wear run writes in its folder (replaced by each run; other files of DIR, e.g. a user's notes, are kept).
WEAR_OWNED = ("result.json", "steps.csv", "*.png", "profiles/", "depth/", "layer_state/", "calibration/")


def run_overrides(workers: int | None, scheduler: str | None) -> dict[str, Any]:
    """The ``workers`` / ``scheduler`` given on the command line (None: the scene's), checked
    (:func:`wrlayer.runner.check_workers`, :func:`wrlayer.runner.check_scheduler_address`), as field changes of the
    scene's run settings."""
    changes: dict[str, Any] = {}
    if workers is not None or scheduler is not None:
        from wrlayer.runner import check_scheduler_address, check_workers  # the process pool's modules on demand

        if workers is not None:
            changes["workers"] = check_workers(workers, "--workers")
        if scheduler is not None:
            changes["scheduler"] = check_scheduler_address(scheduler, "--scheduler")
    return changes


def run_scene(scene_path: str | Path, out_dir: str | Path, plots: bool = False, force: bool = False,
              vtk: bool = True, workers: int | None = None, scheduler: str | None = None,
              accept_unusual_profile: bool = False) -> SceneResult | SweepResult:
    """Run one contact or wheel–rail scene file into ``out_dir`` (every file, atomically); returns the result
    record (result.json). The run's cost is estimated first; above :data:`wrlayer.cost.LIMIT_SECONDS` it is refused
    (CostError, exit 2) unless ``force``. ``workers``/``scheduler``: a wheel–rail scene's ``[run]`` replaced;
    ``accept_unusual_profile``: its profile files read without the plausibility checks."""
    from contact.scenes.scene import read_scene_data, scene_type

    scene_path, data = read_scene_data(scene_path)
    kind = scene_type(data, scene_path)
    changes = run_overrides(workers, scheduler)  # checked for every scene kind, used by a wheel–rail sweep
    out_dir = Path(out_dir)
    if out_dir.exists() and not out_dir.is_dir():
        raise InputError(f"--out {out_dir}", "exists and is not a folder")
    if kind == "wheel_rail":
        from contact.scenes.cost import wheel_rail_cost
        from contact.wheel_rail.parse import parse_wheel_rail_scene

        scene = parse_wheel_rail_scene(data, scene_path, accept_unusual_profile)
        if changes:
            scene = dataclasses.replace(scene, run=dataclasses.replace(scene.run, **changes))
        estimate = guard(wheel_rail_cost(scene), force)
        with run_mode(estimate.seconds), replace_output_dir(out_dir) as tmp:
            result = _write_result(tmp, run_wheel_rail_scene(scene, tmp, plots, vtk=vtk and scene.output.vtk))
        return result

    from contact.scenes.scene import parse_scene

    scene = parse_scene(data, scene_path)  # before importing the solvers: a bad scene fails fast
    from contact.scenes.cost import scene_cost

    estimate = guard(scene_cost(scene), force)
    from contact.scenes.simulation import simulate

    with run_mode(estimate.seconds):  # a small scene's kernels run as plain Python: no numba start-up
        run = simulate(scene)
    run.result.to_json()  # serialisable before anything is written (a failure leaves no file)
    with replace_output_dir(out_dir) as tmp:
        result = _write_result(tmp, write_scene_files(run, tmp, plots, vtk and scene.output.vtk))
    return result


def run_scene_file(scene_path: str | Path, out_dir: str | Path, plots: bool = False, force: bool = False,
                   vtk: bool = True, workers: int | None = None, scheduler: str | None = None) -> dict[str, Any]:
    """:func:`run_scene` returning the result.json data (a dictionary, [result keys](docs/result-keys.md))."""
    return run_scene(scene_path, out_dir, plots, force, vtk, workers, scheduler).to_dict()


def _write_result(out_dir: Path, result: SceneResult | SweepResult) -> SceneResult | SweepResult:
    """Write result.json with the warnings of implausible results (:mod:`contact.result_warnings`); returns the
    record written."""
    from contact.result_warnings import scene_warnings
    from contact.scenes.result_io import write_result

    name = Path(str(result.inputs.get("scene_file", "scene"))).name if isinstance(result.inputs, dict) else "scene"
    result = dataclasses.replace(result, warnings=scene_warnings(name, result) or None)
    write_result(out_dir, result)
    return result


def write_scene_files(run: SimulationRun, out_dir: Path, plots: bool, vtk: bool) -> SceneResult:
    """The files of a contact scene's run beside result.json: the wear-ready frictional CSVs, the VTK fields
    (``vtk``), contact_convention.csv (``output.convention = "contact"``), pictures (``plots``); returns the
    result record naming them."""
    from contact.tangential.frictional_outputs import write_scene_run

    result = dataclasses.replace(run.result, frictional_outputs=tuple(write_scene_run(run, out_dir)))
    if vtk:
        from contact.scenes.vtk_output import scene_items, write_series

        write_series(scene_items(run), out_dir)
    if run.scene.output.convention == "contact":
        from contact.scenes.contact_convention import write_contact_convention

        write_contact_convention(result, out_dir, run.scene.tangential)
    if plots:
        from contact.scenes.plots import write_scene_plots

        result = dataclasses.replace(result, pictures=tuple(p.name for p in write_scene_plots(run, out_dir)))
    return result


def run_wheel_rail_scene(scene: WheelRailScene, out_dir: Path, plots: bool, vtk: bool | None = None
                         ) -> SweepResult:
    """Run a wheel_rail scene (:func:`contact.wheel_rail.run.solve_sweep`); pictures, deformed profiles, CSV files
    and (``vtk``, default ``output.vtk``) the VTK fields go into ``out_dir`` (result.json is the caller's:
    ``result.to_json()``); with ``output.convention = "contact"`` also contact_convention.csv, with
    ``output.contact_table`` the contact table (:mod:`contact.wheel_rail.contact_table`)."""
    from contact.wheel_rail.run import solve_sweep

    out_dir = Path(out_dir)
    vtk = scene.output.vtk if vtk is None else vtk
    result, all_sols = solve_sweep(scene, out_dir, keep=plots or vtk)
    return write_sweep_files(scene, result, all_sols, out_dir, plots, vtk)


def write_sweep_files(scene: WheelRailScene, result: SweepResult, all_sols: list, out_dir: Path, plots: bool,
                      vtk: bool) -> SweepResult:
    """The files of a wheel–rail sweep beside result.json: cases.csv, the VTK fields (``vtk``),
    contact_convention.csv, the contact table, pictures (``plots``); returns the result record naming them."""
    from contact.scenes.contact_convention import write_contact_convention
    from contact.wheel_rail.contact_table import write_contact_table
    from contact.wheel_rail.result_files import cases_csv

    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / result.cases_csv).write_text(cases_csv(result), encoding="utf-8")
    if vtk and scene.output.vtk_frame == "local":
        from contact.scenes.vtk_output import sweep_items, write_series

        write_series(sweep_items(all_sols), out_dir)
    elif vtk:
        from contact.wheel_rail.track_vtk import write_track_series

        write_track_series(all_sols, out_dir)
    if scene.output.convention == "contact":
        write_contact_convention(result, out_dir)
    if scene.output.contact_table:
        write_contact_table(result, scene, out_dir)
    if plots:
        from contact.wheel_rail.plots import write_wheel_rail_plots  # matplotlib only when pictures are asked for

        pictures = write_wheel_rail_plots(result, all_sols, out_dir)
        result = dataclasses.replace(result, pictures=tuple(p.name for p in pictures))
    return result


def failed_cases(result: SceneResult | SweepResult) -> list[str]:
    """One line per failed case of a wheel–rail sweep result: case number, wheel and reason (empty otherwise)."""
    return [f"case {c.case}: {c.failed_wheel or 'wheelset'}: {c.error}"
            for c in getattr(result, "cases", ()) if c.error is not None]


def run_scene_folder(scenes: list[Path], out: Path, plots: bool = False, force: bool = False, vtk: bool = True,
                     accept_unusual_profile: bool = False
                     ) -> Iterator[tuple[Path, SceneResult | SweepResult | None, str | None]]:
    """Run every scene file of ``scenes`` into ``out/<stem>/``: (path, its result or None, None or the error line)
    per scene, as each ends (a failing scene does not stop the others)."""
    for path in scenes:
        try:
            yield path, run_scene(path, out / path.stem, plots=plots, force=force, vtk=vtk,
                                  accept_unusual_profile=accept_unusual_profile), None
        except WrLayerError as err:
            named = getattr(err, "what", "").split(":")[0].strip() in (path.name, str(path))
            yield path, None, f"error: {err}" if named else f"error: {path.name}: {err}"
        except Exception as err:  # noqa: BLE001 - a programming error in one scene must not stop the batch
            yield path, None, f"error: {path.name}: internal error {type(err).__name__}: {err}"


def write_folder_tables(results: dict[str, SceneResult | SweepResult], out: Path) -> str:
    """Write ``out/table.md`` and ``out/table.csv`` of a batch's results (:mod:`contact.scenes.result_table`);
    returns the console summary."""
    from contact.scenes.result_table import results_table, summary_text

    markdown, csv = results_table(results)
    atomic_write_text(out / "table.md", markdown)
    atomic_write_text(out / "table.csv", csv)
    return summary_text(results, out)


# --------------------------------------------------------------------------------------------------- wear
def run_wear_file(scene_path: str | Path, out_dir: str | Path, plots: bool = True, workers: int | None = None,
                  scheduler: str | None = None, show_progress: bool = True, force: bool = False,
                  accept_unusual_profile: bool = False) -> dict[str, Any]:
    """:func:`run_wear_into` returning the result.json data (a dictionary)."""
    return run_wear_into(scene_path, out_dir, plots, workers, scheduler, show_progress, force,
                         accept_unusual_profile)[1]


def run_wear_into(scene_path: str | Path, out_dir: str | Path, plots: bool = True, workers: int | None = None,
                  scheduler: str | None = None, show_progress: bool = True, force: bool = False,
                  accept_unusual_profile: bool = False) -> tuple[WearRun, dict[str, Any]]:
    """Run one wear scene into ``out_dir`` (files: :mod:`contact.wear.outputs`); returns the run's records and the
    result.json data (raises WearStopped after publishing the completed steps). Refused (CostError, exit 2) when
    the estimate exceeds the limit, unless ``force``. ``accept_unusual_profile``: the scene's profile files read
    without the plausibility checks.

    The run is built in a staging folder beside DIR (:func:`wrlayer.atomic_write.staged_output_dir`) and published
    as a whole after every completed step into ``DIR.partial`` beside DIR, with result.json saying "running: N
    steps completed"; DIR keeps its earlier content until the run ends, when the run replaces it and
    ``DIR.partial`` is removed. At the end result.json says "complete"; a failure during the loop stops it, result.json
    says "stopped: step N: ..." (this ended run replaces DIR too); SIGTERM or Ctrl-C marks the published steps in
    ``DIR.partial`` "terminated after step N" / "interrupted after step N"; a full disk or another failure to
    write marks them "stopped after step N: <path>: <reason>"."""
    from contact.scenes.scene import read_scene_data
    from contact.wear.cost import wear_cost
    from contact.wear.scene import parse_wear_scene

    scene_path, data = read_scene_data(scene_path)
    scene = parse_wear_scene(data, scene_path, accept_unusual_profile)
    changes = run_overrides(workers, scheduler)
    if changes:
        scene = dataclasses.replace(scene, settings=dataclasses.replace(scene.settings, **changes))
    guard(wear_cost(scene), force)
    out = Path(out_dir)
    with staged_output_dir(out, owned=WEAR_OWNED) as staged:  # a second run into DIR is refused (the lock)
        try:
            return _run_staged(scene, staged, plots, show_progress)
        except OSError as err:  # a full disk or a permission: the path named once
            raise output_error(err, out) from None


def _run_staged(scene: WearScene, staged: StagedOutput, plots: bool, show_progress: bool
                ) -> tuple[WearRun, dict[str, Any]]:
    """Run the loop in ``staged.dir``, publishing after every completed step (the caller holds DIR's lock)."""
    from contact.wear.loop import start_run, wear_steps
    from contact.wear.outputs import RunFiles, mark_published
    from contact.wear.records import WearStopped

    run = start_run(scene)
    files = RunFiles(staged.dir, run)
    try:  # the end too (final files, pictures): a SIGTERM there marks the published steps like one in a step
        try:
            for record in wear_steps(run, work_dir=staged.dir, show_progress=show_progress):
                files.step(record)
                staged.publish(staged.partial_kept(f"{len(run.steps)} completed step(s)"))
        except WearStopped as stop:
            files.finish(f"stopped: {stop.run.stopped}", _wear_pictures(run, staged.dir, plots))
            staged.finish(f"the stopped run's {len(run.steps)} completed step(s) are in {staged.path}")
            raise
        result = files.finish("complete", _wear_pictures(run, staged.dir, plots))
        check_terminated()  # a SIGTERM swallowed by a C callback (plots): the last published steps stay
        staged.finish(f"the complete run ({len(run.steps)} steps) is in {staged.path}")
        return run, result
    except (Terminated, KeyboardInterrupt, InputError, OSError) as err:
        if staged.where == staged.partial:  # the published steps say how the run ended (not an ended run in DIR)
            with contextlib.suppress(OSError, InputError):  # a full disk may refuse this too: "running" stays
                mark_published(staged.where, _end_status(err, staged.published, staged.where))
        raise


def _end_status(err: BaseException, steps: int, out: Path) -> str:
    """result.json's status for a run ended by ``err`` after ``steps`` published steps."""
    if isinstance(err, Terminated):
        return f"terminated (SIGTERM) after step {steps}"
    if isinstance(err, KeyboardInterrupt):
        return f"interrupted after step {steps}"
    return f"stopped after step {steps}: {output_error(err, out) if isinstance(err, OSError) else err}"


def _wear_pictures(run: WearRun, out: Path, plots: bool) -> list[Path]:
    if not (plots and run.steps):
        return []
    from contact.wear.plots import write_wear_plots  # matplotlib only when pictures are drawn

    return write_wear_plots(run, out)


__all__ = ["WEAR_OWNED", "failed_cases", "run_overrides", "run_scene", "run_scene_file", "run_scene_folder",
           "run_wear_file", "run_wear_into", "run_wheel_rail_scene", "write_folder_tables", "write_scene_files",
           "write_sweep_files"]
