"""One running condition on one side, solved on the current profiles and turned into depths per pass (units mm,
N, MPa, s, rad).

The wheel-rail solver (:func:`contact.wheel_rail.solve.solve_wheel`: contact search, vertical load balance,
Kik–Piotrowski normal problem with the layers, passes, FASTSIM) gives every loaded patch. For each FASTSIM region
the wear law (:mod:`contact.wear.laws`) gives the wear depth per pass per strip of both bodies; the strips are
located on the profiles by the solver's strip-to-profile maps (``rail_y_of_strip``, ``wheel_y_of_strip``). The
inelastic displacement is the solver's accumulated residual displacement after the passes of this condition
(``PatchSolution.residual_mm``; a ``combined`` layer is split equally between the bodies, as the solver does).
Everything returned is plain arrays, so a task can run in another process or on a Dask worker.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace

import numpy as np

from contact.wear.collective import Condition
from contact.wear.laws import WearLaw, wear_of
from contact.wheel_rail.inputs import WheelRailInputs, WheelRailLayers
from contact.wheel_rail.solve import solve_wheel
from contact.wheel_rail.track_geometry import place_rail
from meshes.profiles import Profile
from wrlayer.errors import ConvergenceError, InputError

BODIES = ("wheel", "rail")
#: Worn profiles become conformal: two gap minima close together whose patches meet. The contact search then
#: treats them as one candidate (separation with two humps, split by the normal solver) by raising the search's
#: merge barrier (mm) step by step; the value used is reported per condition (``merge_mm``).
MERGE_RETRY_MM = (0.02, 0.1, 0.5)


@dataclass(frozen=True)
class ConditionTask:
    """Everything one worker needs (picklable)."""

    index: int
    side: str
    condition: Condition
    rail: Profile
    wheel: Profile
    inputs: WheelRailInputs
    layers: WheelRailLayers | None
    law: WearLaw
    step: int


@dataclass
class ConditionResult:
    """Per body: strip profile coordinates ``y_mm``, wear depth per pass ``wear_mm`` and accumulated residual
    ``inelastic_mm`` (same strips; mm); ``strip_mm``: strip width. ``passes``: passes run per patch;
    ``shakedown``: every patch shook down; ``summary``: scalars per patch; ``seconds``: wall time; ``peaks[body]``:
    per patch (profile coordinates of the strips, largest peak pressure p(0, y) over the passes in MPa)."""

    index: int
    side: str
    strip_mm: float
    y_mm: dict = field(default_factory=dict)
    wear_mm: dict = field(default_factory=dict)
    inelastic_y_mm: dict = field(default_factory=dict)
    inelastic_mm: dict = field(default_factory=dict)
    passes: list = field(default_factory=list)
    shakedown: bool = True
    summary: list = field(default_factory=list)
    seconds: float = 0.0
    merge_mm: float = 0.0
    peaks: dict = field(default_factory=dict)


def solve_condition(task: ConditionTask) -> ConditionResult:
    """Solve the task; a condition without contact or a solver failure is an InputError/ConvergenceError naming
    the step and the condition."""
    t0 = time.perf_counter()
    where = f"step {task.step}, condition {task.index} ({task.condition.describe()}), {task.side} wheel"
    placed = place_rail(task.rail, task.inputs.layout)
    inputs, merged = task.inputs, None
    for merge in (None,) + MERGE_RETRY_MM:
        if merge is not None:
            if merge <= inputs.search.merge_mm:
                continue
            inputs = replace(task.inputs, search=replace(task.inputs.search, merge_mm=merge))
        try:
            sol = solve_wheel(task.rail, task.wheel, inputs, task.layers, placed, case=where)
            merged = merge
            break
        except InputError as err:
            if "patches would merge" in err.problem and merge != MERGE_RETRY_MM[-1]:
                continue  # worn, conformal profiles: two close minima whose patches meet -> one candidate
            raise (err if where in err.what else InputError(f"{where}: {err.what}", err.problem)) from None
        except ConvergenceError as err:
            raise (err if where in str(err) else ConvergenceError(f"{where}: {err}")) from None
    if not sol.patches:
        raise InputError(where, "no contact (no loaded patch)")
    h = float(task.inputs.grid_mm)
    out = ConditionResult(task.index, task.side, h)
    ys = {b: [] for b in BODIES}
    wear = {b: [] for b in BODIES}
    iys = {b: [] for b in BODIES}
    ins = {b: [] for b in BODIES}
    for p in sol.patches:
        grid = p.problem.strip_y_mm
        coords = {"rail": p.rail_y_of_strip, "wheel": p.wheel_y_of_strip}
        for region, t in zip(p.normal.patches, p.tangential):
            cw = wear_of(t, task.law)  # strips as the region's (FASTSIM's y may be shifted to the reference point)
            for b in BODIES:
                ys[b].append(np.interp(region.y_mm, grid, coords[b]))
                wear[b].append(cw.strip_depth_mm[b])
        for b in BODIES:
            if b in p.residual_mm:
                u = np.asarray(p.residual_mm[b])
            elif "combined" in p.residual_mm:
                u = 0.5 * np.asarray(p.residual_mm["combined"])
            else:
                continue
            iys[b].append(coords[b])
            ins[b].append(u)
        peak = np.max([r.p_peak_MPa for r in p.passes], axis=0) if p.passes else np.asarray(p.normal.p_peak_MPa)
        for b in BODIES:  # largest peak pressure of every strip over the passes, at the profile coordinates
            out.peaks.setdefault(b, []).append((np.asarray(coords[b], float), np.asarray(peak, float)))
        out.passes.append(len(p.passes))
        if p.passes and not p.passes[-1].shakedown:
            out.shakedown = False
        out.summary.append({"y_wheel_mm": p.candidate.y_wheel_mm, "y_rail_mm": p.candidate.y_rail_mm,
                            "normal_force_N": p.normal_force_N, "p_max_MPa": p.normal.p_max_MPa,
                            "area_mm2": p.normal.area_mm2, "Fx_N": p.Fx_N, "Fy_N": p.Fy_N,
                            "creepage_x": p.kinematics.vx, "creepage_y": p.kinematics.vy,
                            "spin_per_mm": p.kinematics.phi_per_mm, "passes": len(p.passes),
                            "wheel_radius_mm": p.candidate.wheel_radius_mm})
    for b in BODIES:
        out.y_mm[b] = np.concatenate(ys[b]) if ys[b] else np.zeros(0)
        out.wear_mm[b] = np.concatenate(wear[b]) if wear[b] else np.zeros(0)
        out.inelastic_y_mm[b] = np.concatenate(iys[b]) if iys[b] else np.zeros(0)
        out.inelastic_mm[b] = np.concatenate(ins[b]) if ins[b] else np.zeros(0)
    out.merge_mm = merged if merged is not None else task.inputs.search.merge_mm
    out.seconds = time.perf_counter() - t0
    return out


__all__ = ["ConditionResult", "ConditionTask", "solve_condition"]
