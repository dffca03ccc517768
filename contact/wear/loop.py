"""The wear loop: solve the load collective on the current profiles, turn it into wear and inelastic depths,
update the profiles, repeat (units mm, N, MPa, s; distances in km).

Per step
--------
1. Every condition c of the collective is solved on every simulated side (:mod:`contact.wear.condition`), on local
   processes or a Dask cluster (:mod:`contact.wear.runner`). Each condition runs min(passes cap, its passes in the step)
   passes of the layer machinery (:mod:`contact.passes.passes`).
2. Abrasive wear is linear in distance for a fixed profile: a wheel point passes the contact once per revolution,
   n_w = 1e6 / (2 pi r0) passes per km (r0: the nominal rolling radius); a rail section sees
   ``rail_passes_per_wheel_pass`` times as many. The wear depth rate (mm/km) of each body and side is
   sum_c weight_c * passes_per_km * (strip depth per pass of c), deposited conservatively on the profile's
   arc-length grid (:class:`contact.wear.profile_grid.ArcGrid`).
3. Inelastic displacement: the residual displacement after a condition's passes is where that condition's
   contact shook down (or the cap was reached). All conditions of a step act on the same profile, so the step's
   inelastic increment is the pointwise envelope (maximum) over the conditions, NOT their sum: each condition's
   dent is already the state at which its own passes stop adding. Between steps the dent is moved into the
   profile, and the layer state is kept per profile position (``layer_state = "hardening"``, the default): every
   position remembers the largest peak pressure it has carried and its element is hardened to it
   (:mod:`contact.wear.layer_state`), so a later step adds a residual only where the load exceeds that. With
   ``layer_state = "virgin"`` the elements start virgin on the dented profile every step (the paper's mode for its
   19 passes). ``passes.hardening`` applies within a step's passes. Either way the inelastic part saturates
   while wear goes on.
4. Step control: the nominal step is (remaining distance) / (remaining nominal steps). If the largest smoothed wear
   depth of that step exceeds ``max_depth_per_step_mm``, the step is shortened in proportion (wear is linear in
   distance on a fixed profile); the inelastic increment does not scale with the step (it saturates within a few
   passes) and is reported.
5. Both depth distributions are smoothed (Gaussian, ``smoothing_mm``) and the profiles are moved along their
   normals; the new profiles, a row of the step table and the condition summaries are written at once, so a later
   failure keeps every completed step.

A condition without contact, a solver failure or a profile that folds stops the loop with an error naming the step;
:class:`WearStopped` carries the completed steps.
"""

from __future__ import annotations

import dataclasses
import math
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from contact.passes.passes import PassesOptions
from contact.wear.condition import BODIES, ConditionResult, ConditionTask
from contact.wear.conicity import radius_difference
from contact.wear.layer_state import HardenedTable
from contact.wear.profile_grid import ArcGrid
from contact.wear.runner import TaskRunner, map_tasks
from contact.wear.scene import WearScene
from contact.wheel_rail.contact_search import raw_min_gap
from contact.wheel_rail.deformed import rigid_roll
from contact.wheel_rail.inputs import WheelRailLayers
from contact.wheel_rail.track_geometry import WheelsetPose, place_rail
from wrlayer.errors import ConvergenceError, InputError, WrLayerError

MAX_STEP_FACTOR = 50  # at most this many times the nominal number of steps (step control guard)


@dataclass
class BodyStep:
    """One body on one side in one step: grid of the profile BEFORE the step, depths (mm) on its nodes."""

    grid: ArcGrid
    wear_mm: np.ndarray
    inelastic_mm: np.ndarray
    wear_raw_mm: np.ndarray
    stats: dict = field(default_factory=dict)


@dataclass
class StepRecord:
    """A completed step: index (1-based), start and length (km), bodies[(side, body)], conicity after the step,
    condition summaries, timings (s); ``layer_state[(side, body)]`` = (profile y, largest peak pressure so far, MPa)
    after the step (hardening mode)."""

    index: int
    start_km: float
    length_km: float
    bodies: dict
    conicity: dict
    conditions: list
    timings: dict
    profiles: dict
    notes: list = field(default_factory=list)
    layer_state: dict = field(default_factory=dict)

    @property
    def end_km(self) -> float:
        return self.start_km + self.length_km


@dataclass
class WearRun:
    """The loop's result: initial profiles and conicity, the completed steps, and the stop reason if any."""

    scene: WearScene
    initial_profiles: dict
    initial_conicity: dict
    steps: list[StepRecord]
    stopped: str | None = None


class WearStopped(WrLayerError):
    """The loop stopped at a step (the message names it); ``run`` holds the completed steps (exit code 5)."""

    exit_code = 5

    def __init__(self, message: str, run: WearRun):
        super().__init__(message)
        self.run = run


def passes_per_km(scene: WearScene) -> dict:
    """Passes per km of wheel running distance: {"wheel": 1e6/(2 pi r0), "rail": that * rail_passes_per_wheel_pass}."""
    r0 = scene.parsed.layout.nominal_radius_mm
    n = 1e6 / (2.0 * math.pi * r0)
    return {"wheel": n, "rail": n * scene.settings.rail_passes_per_wheel_pass}


def _roll(scene: WearScene, profiles: dict, pose: WheelsetPose) -> float:
    """Roll of the rigid wheelset at which both wheels touch (both sides' own profiles when both are simulated)."""
    parsed = scene.parsed
    layout, settings = parsed.layout, parsed.method.search
    if len(profiles) == 1:
        (_side, pr), = profiles.items()
        return rigid_roll(place_rail(pr["rail"], layout), pr["wheel"], layout, pose, settings)
    placed = {s: place_rail(p["rail"], layout) for s, p in profiles.items()}

    def difference(roll: float) -> float:
        p = WheelsetPose(pose.lateral_mm, pose.yaw_rad, roll)
        return (raw_min_gap(placed["right"], profiles["right"]["wheel"], layout, p.for_side("right"), settings)
                - raw_min_gap(placed["left"], profiles["left"]["wheel"], layout, p.for_side("left"), settings))

    try:
        return float(brentq(difference, -0.05, 0.05, xtol=1e-12, rtol=1e-12, maxiter=100))
    except ValueError:
        raise ConvergenceError(f"rigid wheelset roll at lateral {pose.lateral_mm:g} mm: both wheels cannot touch") \
            from None


def side_layers(scene: WearScene, state: dict | None, side: str, recalibrated: dict | None = None
                ) -> WheelRailLayers | None:
    """The layers of one side: the scene's (or the tables recalibrated on the worn profiles,
    ``recalibrated[(side, body)]``), with every table position hardened to its largest peak pressure so far
    (``state[(side, body)] = (y, p_hist)``) in the hardening mode."""
    layers = scene.parsed.solver_layers
    if not scene.settings.inelastic or layers is None:
        return None
    if layers.combined is not None:
        return layers
    recalibrated = recalibrated or {}
    hardening = scene.settings.layer_state == "hardening" and state
    tables = {}
    for body in BODIES:
        table = recalibrated.get((side, body), getattr(layers, body))
        if hardening and table is not None and (side, body) in state:
            y, p = state[side, body]
            table = HardenedTable(table, y, p)
        tables[body] = table
    names = {**layers.names, **{b: f"recalibrated {b} table" for (s, b) in recalibrated if s == side}}
    return WheelRailLayers(rail=tables["rail"], wheel=tables["wheel"], names=names,
                           scale_to_patch=layers.scale_to_patch)


def _recalibrate(scene: WearScene, profiles: dict, step: int, work_dir: Path | None, recalibrated: dict) -> None:
    """Recalibrate the tables of every side on its current profiles (contact.wear.recalibrate)."""
    import tempfile

    from contact.wear.recalibrate import recalibrate_side

    base = Path(work_dir) if work_dir is not None else Path(tempfile.mkdtemp(prefix="wrlayer-recal-"))
    for side, prof in profiles.items():
        tables = recalibrate_side(scene.settings.recalibrate_template, prof,
                                  base / "calibration" / f"step_{step:03d}_{side}", scene.settings.scheduler,
                                  what=f"step {step}: wear.recalibrate ({side} side)")
        for body, table in tables.items():
            recalibrated[side, body] = table


def update_state(state: dict, results: list[ConditionResult]) -> None:
    """p_hist = max(p_hist, this step's peak pressures) on each (side, body) grid of profile coordinates."""
    for r in results:
        for body, patches in r.peaks.items():
            if (r.side, body) not in state:
                continue
            y, p = state[r.side, body]
            for ys, pk in patches:
                order = np.argsort(ys)
                ys, pk = ys[order], pk[order]
                inside = (y >= ys[0]) & (y <= ys[-1])
                p[inside] = np.maximum(p[inside], np.interp(y[inside], ys, pk))


def build_tasks(scene: WearScene, profiles: dict, step: int, step_km: float, state: dict | None = None,
                recalibrated: dict | None = None) -> list[ConditionTask]:
    """The (condition, side) tasks of a step on the current profiles (``state``: the layer state, see
    :func:`side_layers`)."""
    parsed = scene.parsed
    cap = parsed.passes.max
    n_km = passes_per_km(scene)["wheel"]
    tasks = []
    for k, c in enumerate(scene.collective.conditions):
        pose = WheelsetPose(c.lateral_mm, c.yaw_rad, 0.0)
        if parsed.roll_auto:
            try:
                pose = WheelsetPose(c.lateral_mm, c.yaw_rad, _roll(scene, profiles, pose))
            except (InputError, ConvergenceError) as err:
                raise InputError(f"step {step}, condition {k} ({c.describe()})", f"no rigid contact: {err}") from None
        n_pass = int(max(1, min(cap, math.ceil(c.weight * step_km * n_km))))
        opts = parsed.passes
        for side in profiles:
            pitch = parsed.wheelset.pitch_rate_rad_s if c.pitch_rate_rad_s is None else c.pitch_rate_rad_s
            inputs = dataclasses.replace(parsed.inputs(side, pose), pitch_rate_rad_s=pitch,
                                         vertical_load_N=c.vertical_load_N, speed_mm_s=c.speed_mm_s,
                                         normal_method=scene.normal,
                                         passes=PassesOptions(n_pass, opts.tolerance_mm, opts.hardening))
            tasks.append(ConditionTask(k, side, c, profiles[side]["rail"], profiles[side]["wheel"], inputs,
                                       side_layers(scene, state, side, recalibrated), scene.law, scene.normal,
                                       step))
    return tasks


def _depth_rates(scene: WearScene, grids: dict, results: list[ConditionResult]) -> tuple[dict, dict]:
    """(wear depth rate per km, inelastic envelope) on each (side, body) grid."""
    per_km = passes_per_km(scene)
    conds = scene.collective.conditions
    rate = {key: np.zeros_like(g.s_mm) for key, g in grids.items()}
    inel = {key: np.zeros_like(g.s_mm) for key, g in grids.items()}
    for r in results:
        w = conds[r.index].weight
        for b in BODIES:
            g = grids[r.side, b]
            rate[r.side, b] += w * per_km[b] * g.deposit(r.y_mm[b], r.wear_mm[b], r.strip_mm)
            if scene.settings.inelastic and r.inelastic_mm[b].size:
                inel[r.side, b] = np.maximum(inel[r.side, b], g.deposit(r.inelastic_y_mm[b], r.inelastic_mm[b],
                                                                         r.strip_mm))
    return rate, inel


def _stats(grid: ArcGrid, wear: np.ndarray, inel: np.ndarray, length_km: float, body: str, r0: float,
           density: float) -> dict:
    """Max, location, worn area (mm^2), mass loss: wheel g per km (area x 2 pi r0), rail g per m of rail per km."""
    area = grid.area_mm2(wear)
    iw, ii = int(np.argmax(wear)), int(np.argmax(inel))
    mass_g = area * (2.0 * math.pi * r0 if body == "wheel" else 1000.0) * density * 1e-9 * 1e3
    return {"wear_max_mm": float(wear[iw]), "wear_max_y_mm": float(grid.y_mm[iw]), "worn_area_mm2": area,
            "inelastic_max_mm": float(inel[ii]), "inelastic_max_y_mm": float(grid.y_mm[ii]),
            "inelastic_area_mm2": grid.area_mm2(inel),
            ("mass_loss_g_per_km" if body == "wheel" else "mass_loss_g_per_m_rail_per_km"):
                mass_g / length_km if length_km > 0 else 0.0}


def run_wear(scene: WearScene, on_step: Callable[[StepRecord, WearRun], None] | None = None,
             show_progress: bool = True, work_dir: Path | None = None) -> WearRun:
    """Run the loop (see the module docstring). ``on_step(record, run)`` is called after every completed step
    (the CLI writes the step's files there). Raises :class:`WearStopped` naming the step on a failure.
    ``work_dir``: where recalibrations ([wear.recalibrate]) put their files (default: a temporary folder)."""
    from tqdm import tqdm

    from wrlayer.progress import progress_enabled

    show_progress = progress_enabled(not show_progress)
    parsed, settings, col = scene.parsed, scene.settings, scene.collective
    layout = parsed.layout
    profiles = {side: {"rail": parsed.rail_profile, "wheel": parsed.wheel_profile} for side in parsed.sides}
    run = WearRun(scene, {s: dict(p) for s, p in profiles.items()},
                  radius_difference(profiles, layout, settings.conicity_amplitude_mm, parsed.method.search), [])
    done_km, step = 0.0, 0
    state = {}  # (side, body) -> (profile coordinates y, largest peak pressure so far p_hist) for the layer state
    for s, p in profiles.items():
        for b in BODIES:
            y_nodes = ArcGrid.of(p[b], settings.grid_mm).y_mm
            state[s, b] = (y_nodes, np.zeros(y_nodes.size))
    recalibrated: dict = {}
    n_tasks = len(col.conditions) * len(profiles)
    runner = TaskRunner(settings.workers, settings.scheduler).__enter__()  # a bad scheduler fails before step 1
    bar_steps = tqdm(total=col.steps, desc="wear steps", unit="step", disable=not show_progress, position=0,
                     file=sys.stderr)
    bar_cond = tqdm(total=n_tasks, desc="conditions", unit="cond", disable=not show_progress, position=1,
                    file=sys.stderr, leave=False)
    try:
        while done_km < col.distance_km * (1.0 - 1e-12):
            step += 1
            if step > MAX_STEP_FACTOR * col.steps:
                raise InputError(f"step {step}", f"the step control needs more than {MAX_STEP_FACTOR} x steps; "
                                 "raise max_depth_per_step_mm or steps")
            remaining_steps = max(1, col.steps - len(run.steps))
            nominal_km = (col.distance_km - done_km) / remaining_steps
            t0 = time.perf_counter()
            tasks = build_tasks(scene, profiles, step, nominal_km, state, recalibrated)
            bar_cond.reset(total=len(tasks))
            results = runner.map(tasks, on_done=lambda r: bar_cond.update(1))
            t_solve = time.perf_counter() - t0
            update_state(state, results)
            t1 = time.perf_counter()
            grids = {(s, b): ArcGrid.of(profiles[s][b], settings.grid_mm) for s in profiles for b in BODIES}
            rate, inel = _depth_rates(scene, grids, results)
            smooth_rate = {k: grids[k].smooth(v, settings.smoothing_mm) for k, v in rate.items()}
            smooth_inel = {k: grids[k].smooth(v, settings.smoothing_mm) for k, v in inel.items()}
            max_rate = max(float(np.max(v)) for v in smooth_rate.values())
            length = nominal_km
            notes = []
            if max_rate * length > settings.max_depth_per_step_mm:
                length = settings.max_depth_per_step_mm / max_rate
                notes.append(f"step shortened from {nominal_km:.6g} km to {length:.6g} km (max wear depth "
                             f"{max_rate * nominal_km:.4g} mm > {settings.max_depth_per_step_mm:g} mm)")
            max_inel = max(float(np.max(v)) for v in smooth_inel.values())
            if max_inel > settings.max_depth_per_step_mm:
                notes.append(f"inelastic increment {max_inel:.4g} mm exceeds max_depth_per_step_mm (it saturates "
                             "within the step's passes and does not scale with the step length)")
            bodies, new_profiles = {}, {s: {} for s in profiles}
            for (s, b), g in grids.items():
                wear = smooth_rate[s, b] * length
                total = wear + smooth_inel[s, b]
                name = f"{run.initial_profiles[s][b].name} {s} after step {step}"
                new_profiles[s][b] = g.updated(total, name, f"step {step}: {s} {b} profile")
                bodies[s, b] = BodyStep(g, wear, smooth_inel[s, b], rate[s, b] * length,
                                        _stats(g, wear, smooth_inel[s, b], length, b, layout.nominal_radius_mm,
                                               scene.law.density_kg_m3))
            t_update = time.perf_counter() - t1
            conic = radius_difference(new_profiles, layout, settings.conicity_amplitude_mm,
                                      parsed.method.search)
            rec = StepRecord(step, done_km, length, bodies, conic,
                             [{"condition": r.index, "side": r.side, "passes": r.passes, "shakedown": r.shakedown,
                               "seconds": r.seconds, "merge_mm": r.merge_mm, "patches": r.summary} for r in results],
                             {"solve_s": t_solve, "update_s": t_update,
                              "conditions_s": sum(r.seconds for r in results)},
                             new_profiles, notes)
            if settings.inelastic and settings.layer_state == "hardening":
                rec.layer_state = {k: (y.copy(), p.copy()) for k, (y, p) in state.items()}
            profiles = new_profiles
            done_km += length
            run.steps.append(rec)
            if (settings.recalibrate_every and step % settings.recalibrate_every == 0
                    and done_km < col.distance_km * (1.0 - 1e-12)):
                t2 = time.perf_counter()
                _recalibrate(scene, profiles, step, work_dir, recalibrated)
                rec.timings["recalibration_s"] = time.perf_counter() - t2
                rec.notes.append(f"layer tables recalibrated on the profiles after step {step} "
                                 f"({', '.join(sorted({f'{s} {b}' for s, b in recalibrated}))})")
            if on_step is not None:
                on_step(rec, run)
            bar_steps.total = max(bar_steps.total, len(run.steps) + (1 if done_km < col.distance_km else 0))
            bar_steps.update(1)
    except (InputError, ConvergenceError) as err:
        run.stopped = f"step {step}: {err}"
        raise WearStopped(f"wear loop stopped at step {step} after {done_km:.6g} km ({len(run.steps)} completed steps "
                          f"kept): {err}", run) from None
    finally:
        runner.__exit__(None, None, None)
        bar_cond.close()
        bar_steps.close()
    return run


__all__ = ["BodyStep", "StepRecord", "TaskRunner", "WearRun", "WearStopped", "build_tasks", "map_tasks",
           "passes_per_km", "run_wear"]
