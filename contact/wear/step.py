"""One wear step: solve the load collective on the current profiles, turn it into wear and inelastic depths and
move the profiles (units mm, N, MPa, s; distances in km).

1. Every condition c of the collective is solved on every simulated side (:mod:`contact.wear.condition`; the tasks
   and their passes: :mod:`contact.wear.planning`) by the loop's runner (in-process, local processes or Dask).
2. The wear depth rate (mm/km) of each body and side is sum_c weight_c * passes_per_km * (strip depth per pass of
   c), deposited conservatively on the profile's arc-length grid (:class:`contact.wear.profile_grid.ArcGrid`).
3. Inelastic displacement: the residual displacement after a condition's passes is where that condition's
   contact shook down (or the cap was reached). All conditions of a step act on the same profile, so the step's
   inelastic increment is the pointwise envelope (maximum) over the conditions, NOT their sum: each condition's
   dent is already the state at which its own passes stop adding.
4. Both depth distributions are smoothed (Gaussian, ``smoothing_mm``), the step length is set by the step control
   (:func:`contact.wear.planning.controlled_length`) and the profiles are moved along their normals by wear x length
   + inelastic increment. The rolling-radius difference of the new profiles closes the step.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from contact.wear.condition import BODIES, ConditionResult
from contact.wear.conicity import radius_difference
from contact.wear.layer_state import History, raised_history
from contact.wear.planning import balanced_positions, build_tasks, controlled_length, nominal_length_km, passes_per_km
from contact.wear.profile_grid import ArcGrid
from contact.wear.records import BodyStep, ConditionSummary, StepRecord
from contact.wear.scene import WearScene
from contact.wear.state import WearState
from contact.wear.statistics import body_stats

Grids = dict[tuple[str, str], ArcGrid]


def depth_rates(scene: WearScene, grids: Grids, results: list[ConditionResult]
                ) -> tuple[dict[tuple[str, str], np.ndarray], dict[tuple[str, str], np.ndarray]]:
    """(wear depth rate per km, inelastic envelope) on each (side, body) grid (mm/km, mm)."""
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


def summary_of(r: ConditionResult) -> ConditionSummary:
    return ConditionSummary(condition=r.index, side=r.side, passes=r.passes, shakedown=r.shakedown, seconds=r.seconds,
                            merge_mm=r.merge_mm, patches=r.patches)


def wear_step(scene: WearScene, state: WearState, solve: Callable[[list], list[ConditionResult]]
              ) -> tuple[StepRecord, History]:
    """The step after ``state`` (its record and the layer state after it); ``solve(tasks)`` returns the results
    in task order."""
    settings, step = scene.settings, state.steps_done + 1
    nominal_km = nominal_length_km(scene.collective, state.done_km, state.steps_done)
    t0 = time.perf_counter()
    balances = balanced_positions(scene, state.profiles, step)
    results = solve(build_tasks(scene, state.profiles, step, nominal_km, state.history, state.tables, balances))
    t_solve = time.perf_counter() - t0
    history = raised_history(state.history, results)
    t1 = time.perf_counter()
    grids = {(s, b): ArcGrid.of(state.profiles[s][b], settings.grid_mm) for s in state.profiles for b in BODIES}
    rate, inel = depth_rates(scene, grids, results)
    smooth_rate = {k: grids[k].smooth(v, settings.smoothing_mm) for k, v in rate.items()}
    smooth_inel = {k: grids[k].smooth(v, settings.smoothing_mm) for k, v in inel.items()}
    length, notes = controlled_length(nominal_km, max(float(np.max(v)) for v in smooth_rate.values()),
                                      max(float(np.max(v)) for v in smooth_inel.values()),
                                      settings.max_depth_per_step_mm)
    r0, initial = scene.wheel_rail.wheel.nominal_radius_mm, scene.initial_profiles
    bodies, profiles = {}, {s: {} for s in state.profiles}
    for (s, b), g in grids.items():
        wear = smooth_rate[s, b] * length
        name = f"{initial[s][b].name} {s} after step {step}"
        profiles[s][b] = g.updated(wear + smooth_inel[s, b], name, f"step {step}: {s} {b} profile")
        bodies[s, b] = BodyStep(grid=g, wear_mm=wear, inelastic_mm=smooth_inel[s, b], wear_raw_mm=rate[s, b] * length,
                                stats=body_stats(g, wear, smooth_inel[s, b], length, b, r0, scene.law.density_kg_m3))
    t_update = time.perf_counter() - t1
    conicity = radius_difference(profiles, scene.wheel_rail.layout, settings.conicity_amplitude_mm,
                                 scene.wheel_rail.method.search)
    keep_state = settings.inelastic and settings.layer_state == "hardening"
    record = StepRecord(index=step, start_km=state.done_km, length_km=length, bodies=bodies, conicity=conicity,
                        conditions=tuple(summary_of(r) for r in results),
                        timings={"solve_s": t_solve, "update_s": t_update,
                                 "conditions_s": sum(r.seconds for r in results)},
                        profiles=profiles, notes=notes, layer_state=dict(history) if keep_state else {},
                        balances=tuple(balances.values()))
    return record, history


__all__ = ["depth_rates", "summary_of", "wear_step"]
