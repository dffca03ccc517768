"""One running condition on one side, solved on the current profiles and turned into depths per pass (units mm,
N, MPa, s, rad).

The wheel-rail solver (:func:`contact.wheel_rail.solve.solve_wheel`: contact search, vertical load balance,
Kik–Piotrowski normal problem with the layers, passes, FASTSIM) gives every loaded patch. For each FASTSIM region
the wear law (:mod:`contact.wear.laws`) gives the wear depth per pass per strip of both bodies; the strips are
located on the profiles by the solver's strip-to-profile maps (``rail_y_of_strip``, ``wheel_y_of_strip``). The
inelastic displacement is the solver's accumulated residual displacement after the passes of this condition
(``PatchSolution.residual_mm``; a ``combined`` layer is split equally between the bodies, as the solver does).
Worn, conformal profiles give gap minima whose patches meet; the solver merges them into one candidate by raising
the search's merge barrier itself, and the value it used is reported per condition (``merge_mm``). Everything
returned is plain arrays, so a task can run in another process or on a Dask worker.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass, field

import numpy as np

from contact.wear.collective import Condition
from contact.wear.laws import WearLaw, wear_of
from contact.scenes.layers import LayerSources
from contact.wheel_rail.inputs import WheelRailInputs
from contact.wheel_rail.results import WheelResult
from contact.wheel_rail.solution import WheelRailSolution
from contact.wheel_rail.solve import solve_wheel
from contact.wheel_rail.track_geometry import place_rail
from meshes.profiles import Profile
from wrlayer.errors import ConvergenceError, InputError

BODIES = ("wheel", "rail")


@dataclass(frozen=True)
class ConditionTask:
    """Everything one worker needs (picklable)."""

    index: int
    side: str
    condition: Condition
    rail: Profile
    wheel: Profile
    inputs: WheelRailInputs
    layers: LayerSources | None
    law: WearLaw
    step: int


@dataclass(frozen=True)
class ConditionResult:
    """One (condition, side) solved: depths per pass on the profiles' strips (mm) and the solution's scalars.

    Attributes
    ----------
    index : int
        Index of the condition in the collective (0-based).
    side : str
        ``"right"`` or ``"left"``.
    strip_mm : float
        Strip width of the normal problem (mm).
    y_mm : dict
        ``y_mm[body]``: profile coordinates of the wear strips (mm).
    wear_mm : dict
        ``wear_mm[body]``: wear depth per pass on those strips (mm).
    inelastic_y_mm : dict
        ``inelastic_y_mm[body]``: profile coordinates of the residual strips (mm).
    inelastic_mm : dict
        ``inelastic_mm[body]``: accumulated residual displacement after the condition's passes (mm).
    passes : tuple
        Passes run per loaded patch.
    shakedown : bool
        Every patch shook down within its passes.
    patches : tuple
        The loaded patches' records (:class:`contact.wheel_rail.patch_result.PatchResult`).
    seconds : float
        Wall time of the solution (s).
    merge_mm : float
        Merge barrier of the contact search the solver used (mm; raised by the solver where patches meet).
    peaks : dict
        ``peaks[body]``: per patch (profile coordinates of the strips (mm), largest peak pressure p(0, y) over the
        passes (MPa)).
    """

    index: int
    side: str
    strip_mm: float
    y_mm: dict = field(default_factory=dict)
    wear_mm: dict = field(default_factory=dict)
    inelastic_y_mm: dict = field(default_factory=dict)
    inelastic_mm: dict = field(default_factory=dict)
    passes: tuple = ()
    shakedown: bool = True
    patches: tuple = ()
    seconds: float = 0.0
    merge_mm: float = 0.0
    peaks: dict = field(default_factory=dict)


def side_inputs(task: ConditionTask) -> WheelRailInputs:
    """The task's inputs with the condition's values of its side: the vertical load of this wheel
    (:meth:`Condition.load_on`; a curve loads the outer wheel more) and the wheelset's yaw rate in a curve
    (:mod:`contact.wear.curving`) and the creepages a multibody export gives for this wheel."""
    c = task.condition
    load = dataclasses.replace(task.inputs.load, vertical_load_N=c.load_on(task.side))
    return dataclasses.replace(task.inputs, load=load, yaw_rate_rad_s=c.yaw_rate_rad_s,
                               creepages=c.creepages_on(task.side))


def solve_condition(task: ConditionTask) -> ConditionResult:
    """Solve the task; a condition without contact or a solver failure is an InputError/ConvergenceError naming
    the step and the condition."""
    t0 = time.perf_counter()
    where = f"step {task.step}, condition {task.index} ({task.condition.describe()}), {task.side} wheel"
    placed = place_rail(task.rail, task.inputs.layout)
    try:
        sol = solve_wheel(task.rail, task.wheel, side_inputs(task), task.layers, placed, case=where)
    except InputError as err:
        raise (err if where in err.what else InputError(f"{where}: {err.what}", err.problem)) from None
    except ConvergenceError as err:
        raise (err if where in str(err) else ConvergenceError(f"{where}: {err}")) from None
    if not sol.patches:
        raise InputError(where, "no contact (no loaded patch)")
    return _result(task, sol, t0)


def _concat(parts: list) -> np.ndarray:
    return np.concatenate(parts) if parts else np.zeros(0)


def _result(task: ConditionTask, sol: WheelRailSolution, t0: float) -> ConditionResult:
    """The depths of every patch of ``sol`` on the profiles' strips (see the module docstring)."""
    ys, wear, iys, ins, peaks = ({b: [] for b in BODIES} for _ in range(5))
    passes = []
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
            peaks[b].append((np.asarray(coords[b], float), np.asarray(peak, float)))
        passes.append(len(p.passes))
    shakedown = all(p.passes[-1].shakedown for p in sol.patches if p.passes)
    return ConditionResult(index=task.index, side=task.side, strip_mm=float(task.inputs.grid_mm),
                           y_mm={b: _concat(ys[b]) for b in BODIES}, wear_mm={b: _concat(wear[b]) for b in BODIES},
                           inelastic_y_mm={b: _concat(iys[b]) for b in BODIES},
                           inelastic_mm={b: _concat(ins[b]) for b in BODIES}, passes=tuple(passes),
                           shakedown=shakedown, patches=WheelResult.of(sol).patches,
                           seconds=time.perf_counter() - t0, merge_mm=sol.merge_mm, peaks=peaks)


__all__ = ["BODIES", "ConditionResult", "ConditionTask", "side_inputs", "solve_condition"]
