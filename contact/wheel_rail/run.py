"""Solve a wheel_rail scene: every case on every simulated wheel, the result record, the wear-ready frictional CSVs
and deformed profiles (units mm, N, MPa, s, rad); the other files (cases.csv, VTK, pictures, result.json):
:mod:`contact.run_files`.

Run by ``python -m contact simulate SCENE --out DIR`` (and ``simulate-all``) with the scene parsed once
(:func:`contact.wheel_rail.parse.parse_wheel_rail_scene`). A progress bar over the cases goes to stderr when it is a
terminal (:mod:`wrlayer.progress`; ``WRLAYER_PROGRESS=0/1`` overrides). Conventions: docs/wheel-rail.md.

The cases are solved one after the other in this process, or, with ``run.workers > 1`` or a ``run.scheduler``,
by :class:`wrlayer.runner.Runner` (local processes or a Dask cluster, one BLAS thread per worker) as independent
tasks (:func:`solve_one`) whose results come back to this process, which writes every file.

A case that fails (bad geometry: profiles that do not meet, the flange through the rail; or a solver failure) is
recorded with its error message in ``cases[k].error`` and the other cases are still computed; the scene itself
fails only when every case fails.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from contact.scenes.result_io import UNITS, code_version
from contact.tangential.frictional_outputs import write_wheel_rail
from contact.wheel_rail.result_files import CONVENTIONS
from contact.wheel_rail.results import CaseResult, DeformedProfileFile, RailPlacement, SweepResult, WheelResult
from contact.wheel_rail.scene import WheelRailScene
from contact.wheel_rail.sweep_spec import SWEEP_KEYS, CaseSpec
from contact.wheel_rail.deformed import deformed_profile, residual_on_profiles, rigid_roll
from contact.wheel_rail.solution import WheelRailSolution
from contact.wheel_rail.solve import solve_wheel
from contact.wheel_rail.track_geometry import PlacedRail, WheelsetPose, place_rail
from wrlayer.errors import ConvergenceError, InputError, check_terminated
from wrlayer.progress import progress


def solve_case(scene: WheelRailScene, case: CaseSpec, placed_rail: PlacedRail | None = None
               ) -> tuple[CaseResult, dict[str, WheelRailSolution]]:
    """One case of the scene: (its record, {side: WheelRailSolution}); raises InputError/ConvergenceError, with
    the failed wheel's side as the error's ``wheel`` attribute when one wheel failed."""
    layout, rail, wheel = scene.layout, scene.rail_profile, scene.wheel_profile
    placed_rail = placed_rail or place_rail(rail, layout)
    pose = WheelsetPose(case.lateral_mm, case.yaw_rad, 0.0 if scene.roll_auto else case.roll_rad)
    if scene.roll_auto:
        roll = rigid_roll(placed_rail, wheel, layout, pose, scene.method.search)
        pose = WheelsetPose(pose.lateral_mm, pose.yaw_rad, roll)
    sols = {}
    for side in scene.sides:
        try:
            sols[side] = solve_wheel(rail, wheel, scene.inputs(side, pose, case), scene.solver_layers, placed_rail,
                                     case=f"case lateral {pose.lateral_mm:g} mm, yaw {pose.yaw_rad:g} rad, {side} "
                                          "wheel")
        except (InputError, ConvergenceError) as err:
            err.wheel = side       # the failed wheel, for the case's record
            raise
    any_inputs = next(iter(sols.values())).inputs
    difference = None
    if len(sols) == 2:  # rolling radius difference of the main (largest normal force) patches, left - right
        r = {side: max(s.patches, key=lambda p: p.normal_force_N).candidate.wheel_radius_mm for side, s in sols.items()}
        difference = r["left"] - r["right"]
    record = CaseResult(lateral_mm=pose.lateral_mm, yaw_rad=pose.yaw_rad, roll_rad=pose.roll_rad,
                        pitch_rate_rad_s=any_inputs.omega_rad_s, vertical_load_N=any_inputs.vertical_load_N,
                        speed_mm_s=any_inputs.speed_mm_s, wheels={side: WheelResult.of(s) for side, s in sols.items()},
                        rolling_radius_difference_mm=difference)
    return record, sols


def write_deformed_profiles(scene: WheelRailScene, sols: dict[str, WheelRailSolution], out_dir: Path,
                            stem: str) -> tuple[DeformedProfileFile, ...]:
    """Deformed rail and wheel profiles of one case (every side), written as SIMPACK and CSV and read back."""
    from meshes.profiles.io import write_profile_files

    written = []
    profiles = {"rail": scene.rail_profile, "wheel": scene.wheel_profile}
    for side, sol in sols.items():
        for body, (ys, up) in residual_on_profiles(sol.patches).items():
            if not np.any(up > 1e-9):
                continue
            prof = profiles[body]
            pts = deformed_profile(prof, ys, up)
            paths, err = write_profile_files(out_dir / "deformed_profiles" / f"{stem}_{side}_{body}", pts, body,
                                             f"{prof.name} with residual displacements ({stem}, {side})")
            for path in paths:
                written.append(DeformedProfileFile(file=str(path.relative_to(out_dir)), body=body, side=side,
                                                   max_residual_mm=float(up.max()), read_back_max_error_mm=err))
    return tuple(written)


def failed_record(case: CaseSpec, k: int, err: InputError | ConvergenceError, time_s: float) -> CaseResult:
    """The record of case ``k`` that failed with ``err`` (its inputs, the error and the failed wheel)."""
    return CaseResult(**{key: getattr(case, key) for key in SWEEP_KEYS}, error=str(err),
                      failed_wheel=getattr(err, "wheel", None), case=k, time_s=time_s)


def solve_one(task: tuple[WheelRailScene, PlacedRail, int, bool]
              ) -> tuple[CaseResult, dict[str, WheelRailSolution] | None]:
    """Case k of the scene, ``task`` = (scene, placed rail, k, keep): its record and solutions ({} unless ``keep``:
    no file needs them, and a worker then sends back the record alone instead of about 1 MB), or its error's record
    and None. Writes no file: a task of the runner (:class:`wrlayer.runner.Runner`), also on a remote Dask worker."""
    scene, placed, k, keep = task
    case = scene.cases[k]
    t_case = time.perf_counter()
    try:
        record, sols = solve_case(scene, case, placed)
    except (InputError, ConvergenceError) as err:
        return failed_record(case, k, err, time.perf_counter() - t_case), None
    return dataclasses.replace(record, case=k, time_s=time.perf_counter() - t_case), sols if keep else {}


def with_deformed_profiles(scene: WheelRailScene, solved: tuple[CaseResult, dict[str, WheelRailSolution] | None],
                           out_dir: Path) -> tuple[CaseResult, dict[str, WheelRailSolution] | None]:
    """A solved case with its deformed profiles written into ``out_dir`` (with layers and
    ``output.deformed_profiles``; a profile that cannot be written fails the case)."""
    record, sols = solved
    if sols is None or scene.layers is None or not scene.output.deformed_profiles:
        return record, sols
    t0 = time.perf_counter()
    try:
        files = write_deformed_profiles(scene, sols, out_dir, f"case{record.case:03d}")
    except (InputError, ConvergenceError) as err:
        return failed_record(scene.cases[record.case], record.case, err,
                             record.time_s + time.perf_counter() - t0), None
    return dataclasses.replace(record, deformed_profiles=files, time_s=record.time_s + time.perf_counter() - t0), sols


def solve_parallel(scene: WheelRailScene, placed: PlacedRail, keep: bool = True
                   ) -> list[tuple[CaseResult, dict[str, WheelRailSolution] | None]]:
    """Every case through the runner (``run.workers`` local processes or the Dask cluster at ``run.scheduler``,
    one BLAS thread per worker), in case order (``keep``: :func:`solve_one`)."""
    from wrlayer.runner import Runner  # only for a parallel sweep: the runner imports multiprocessing

    tasks = [(scene, placed, k, keep) for k in range(len(scene.cases))]
    done = {}
    with Runner(scene.run.workers, scene.run.scheduler, blas_threads=1, what="run.scheduler") as runner:
        for k, solved in progress(runner.imap(solve_one, tasks), desc=scene.path.stem, total=len(tasks), unit="case",
                                  leave=False):
            done[k] = solved
    return [done[k] for k in range(len(tasks))]


def solve_cases(scene: WheelRailScene, placed: PlacedRail, out_dir: Path, keep: bool = True
                ) -> Iterator[tuple[CaseResult, dict[str, WheelRailSolution] | None]]:
    """Every case in order: (its record, its solutions ({} unless ``keep``) or None when it failed); deformed
    profiles written into ``out_dir``. One after the other in this process, or through the runner with
    ``run.workers > 1`` or a ``run.scheduler`` (the same numbers: every case is solved on its own)."""
    keep = keep or (scene.layers is not None and scene.output.deformed_profiles)
    if scene.run.parallel:
        solved = iter(solve_parallel(scene, placed, keep))
    else:
        solved = map(solve_one, progress([(scene, placed, k, keep) for k in range(len(scene.cases))],
                                         desc=scene.path.stem, total=len(scene.cases), unit="case", leave=False))
    for one in solved:
        # a SIGTERM that arrived inside a C callback (numba compiling a kernel on a first run) was dropped there:
        # its flag ends the sweep after the case, not after all of them
        check_terminated()
        yield with_deformed_profiles(scene, one, out_dir)


def solve_sweep(scene: WheelRailScene, out_dir: Path, keep: bool) -> tuple[SweepResult, list]:
    """Every case of the scene: the result record and the cases' solutions ({side: WheelRailSolution}, None for a
    failed case; {} unless ``keep`` or the deformed profiles need them); the deformed profiles and (with
    ``output.frictional_csv``) the wear-ready frictional CSVs go into ``out_dir``. InputError when every case
    failed. The other files: :func:`contact.run_files.write_sweep_files`."""
    t0 = time.perf_counter()
    out_dir = Path(out_dir)
    placed = place_rail(scene.rail_profile, scene.layout)
    solved = list(solve_cases(scene, placed, out_dir, keep=keep or scene.output.frictional_csv))
    records, all_sols = [r for r, _ in solved], [s for _, s in solved]
    if all(s is None for s in all_sols):
        raise InputError(scene.path.name, f"every case failed; first: {records[0].error}")
    result = SweepResult(
        type="wheel_rail", inputs=scene.to_dict(), code_version=code_version(),
        units={**UNITS, "angles": "rad (contact_angle_deg in degrees)",
               "Fx_N, Fy_N": "N (creep forces of the rail on the wheel, contact frame x = rolling direction, "
                             "y = contact-plane lateral axis with positive track-Y component)"},
        conventions=CONVENTIONS,
        rail_placement=RailPlacement(dy_mm=placed.dy_mm, dz_mm=placed.dz_mm, angle_rad=placed.angle_rad,
                                     gauge_point_Y_mm=placed.gauge_point[0], gauge_point_Z_mm=placed.gauge_point[1],
                                     top_y_rail_mm=placed.top_q_mm),
        cases=tuple(records), n_failed=sum(1 for r in records if r.error is not None),
        timings_s={"total": time.perf_counter() - t0},
        frictional_outputs=tuple(write_wheel_rail(all_sols, out_dir)) if scene.output.frictional_csv else ())
    return result, all_sols


__all__ = ["failed_record", "solve_case", "solve_cases", "solve_one", "solve_parallel", "solve_sweep",
           "with_deformed_profiles", "write_deformed_profiles"]
