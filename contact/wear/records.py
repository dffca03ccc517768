"""What the wear loop produces: one record per completed step and the run that collects them (units mm, MPa, s;
distances in km). The files of a run (:mod:`contact.wear.outputs`) and its pictures (:mod:`contact.wear.plots`) are
written from these.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from contact.wear.conicity import RadiusDifference
from contact.wear.layer_state import History
from contact.wear.profile_grid import ArcGrid
from contact.wear.quasi_static import WheelsetBalance
from contact.wear.scene import WearScene
from contact.wear.statistics import BodyStats
from contact.wheel_rail.patch_result import PatchResult
from meshes.profiles import Profile
from wrlayer.errors import WrLayerError
from wrlayer.json_io import Layout, Record
from wrlayer.short_repr import short_repr

#: profiles[side][body]: the profiles of the simulated sides ("right", "left"), bodies "wheel" and "rail".
Profiles = dict[str, dict[str, Profile]]


@dataclass(frozen=True)
class BodyStep:
    """One body on one side in one step: the grid of the profile BEFORE the step and the depths on its nodes.

    Attributes
    ----------
    grid : ArcGrid
        Nodes of the profile before the step (equal arc length).
    wear_mm : np.ndarray
        Smoothed wear depth of the step per node (mm).
    inelastic_mm : np.ndarray
        Smoothed inelastic depth of the step per node (mm).
    wear_raw_mm : np.ndarray
        Wear depth of the step per node before smoothing (mm).
    stats : BodyStats
        Largest depths, areas and mass loss (:mod:`contact.wear.statistics`).
    """

    grid: ArcGrid
    wear_mm: np.ndarray
    inelastic_mm: np.ndarray
    wear_raw_mm: np.ndarray
    stats: BodyStats

    __repr__ = short_repr  # the arrays by their shapes


#: A patch of ``steps[].conditions[].patches[]`` in result.json: contact point (first contact, mm), forces (N),
#: peak pressure (MPa), area (mm^2), creepages, passes, rolling radius (mm).
WEAR_PATCH_LAYOUT: Layout = (
    ("y_wheel_mm", "first_contact.y_wheel_mm"), ("y_rail_mm", "first_contact.y_rail_mm"),
    *((name, name) for name in ("normal_force_N", "p_max_MPa", "area_mm2", "Fx_N", "Fy_N", "creepage_x",
                                "creepage_y", "spin_per_mm")),
    ("passes", "n_passes"), ("wheel_radius_mm", "wheel_radius_mm"))


@dataclass(frozen=True, kw_only=True)
class ConditionSummary(Record):
    """One (condition, side) solution of a step as result.json records it (``steps[].conditions[]``).

    Attributes
    ----------
    condition : int
        Index of the condition in the collective (0-based).
    side : str
        ``"right"`` or ``"left"``.
    passes : tuple[int, ...]
        Passes run per loaded patch.
    shakedown : bool
        Every patch shook down within its passes.
    seconds : float
        Wall time of the solution (s).
    merge_mm : float
        Merge barrier of the contact search used (mm).
    patches : tuple[PatchResult, ...]
        The loaded patches (written in :data:`WEAR_PATCH_LAYOUT`).
    """

    condition: int
    side: str
    passes: tuple[int, ...]
    shakedown: bool
    seconds: float
    merge_mm: float
    patches: tuple[PatchResult, ...] = field(metadata={"layout": WEAR_PATCH_LAYOUT})


@dataclass(frozen=True)
class StepRecord:
    """A completed wear step.

    Attributes
    ----------
    index : int
        Step number (1-based).
    start_km : float
        Running distance at the start of the step (km).
    length_km : float
        Length of the step (km), after the step control.
    bodies : dict
        ``bodies[(side, body)]``: :class:`BodyStep`.
    conicity : RadiusDifference
        Rolling-radius difference of the profiles after the step.
    conditions : tuple
        :class:`ConditionSummary` per (condition, side).
    timings : dict
        Wall times (s): ``solve_s``, ``update_s``, ``conditions_s`` and, after a recalibration,
        ``recalibration_s``.
    profiles : dict
        ``profiles[side][body]``: the profiles after the step.
    notes : tuple
        Shortened step, large inelastic increment, recalibration.
    layer_state : dict
        Hardening mode: ``layer_state[(side, body)]`` = (profile y (mm), largest peak pressure so far (MPa)) after
        the step; empty otherwise.
    balances : tuple
        :class:`contact.wear.quasi_static.WheelsetBalance` of the conditions whose position was found from the
        quasi-static balance on the profiles before the step (result.json ``steps[].balance``).
    """

    index: int
    start_km: float
    length_km: float
    bodies: dict[tuple[str, str], BodyStep]
    conicity: RadiusDifference
    conditions: tuple[ConditionSummary, ...]
    timings: dict[str, float]
    profiles: Profiles
    notes: tuple[str, ...] = ()
    layer_state: History = field(default_factory=dict)
    balances: tuple[WheelsetBalance, ...] = ()

    __repr__ = short_repr  # the depths by their shapes

    @property
    def end_km(self) -> float:
        return self.start_km + self.length_km


@dataclass
class WearRun:
    """The loop's result, filled step by step (mutable: :func:`contact.wear.loop.wear_steps` appends each step as
    it completes).

    Attributes
    ----------
    scene : WearScene
        The scene run.
    initial_profiles : dict
        ``initial_profiles[side][body]``: the profiles before the first step.
    initial_conicity : RadiusDifference
        Rolling-radius difference of the initial profiles (result.json ``initial.conicity``).
    steps : list of StepRecord
        The completed steps.
    stopped : str or None
        Why the loop stopped early, naming the step (result.json ``status`` = "stopped: ..."); None: not stopped.
    """

    scene: WearScene
    initial_profiles: Profiles
    initial_conicity: RadiusDifference
    steps: list[StepRecord] = field(default_factory=list)
    stopped: str | None = None

    def __repr__(self) -> str:
        done_km = self.steps[-1].end_km if self.steps else 0.0
        return (f"WearRun({len(self.steps)} steps, {done_km:.6g} km"
                f"{', stopped: ' + self.stopped if self.stopped else ''})")


class WearStopped(WrLayerError):
    """The loop stopped at a step (the message names it); ``run`` holds the completed steps (exit code 5)."""

    exit_code = 5

    def __init__(self, message: str, run: WearRun):
        super().__init__(message)
        self.run = run


__all__ = ["WEAR_PATCH_LAYOUT", "BodyStep", "ConditionSummary", "Profiles", "StepRecord", "WearRun", "WearStopped"]
