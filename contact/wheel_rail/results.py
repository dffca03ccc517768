"""The result records of a wheel_rail scene, as written to result.json: the whole sweep, its cases, each wheel
(units mm, N, MPa, s, rad; conventions: :data:`contact.wheel_rail.result_files.CONVENTIONS`, docs/wheel-rail.md).
Field names are the JSON keys; the patches: :mod:`contact.wheel_rail.patch_result`.

Built from the solver's solutions (:class:`contact.wheel_rail.solution.WheelRailSolution`) by the ``of``
constructors; converted to JSON only when written (:class:`contact.scenes.result_io.Record`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from contact.wheel_rail.patch_result import OMIT_NONE, PatchResult
from contact.wheel_rail.solution import WheelRailSolution
from wrlayer.json_io import Record


@dataclass(frozen=True, kw_only=True)
class UnloadedCandidate(Record):
    """A contact candidate that carries no load.

    Attributes
    ----------
    y_rail_mm : float
        Rail profile coordinate (mm).
    y_wheel_mm : float
        Wheel profile coordinate (mm).
    normal_gap_mm : float
        Normal gap at rigid contact (mm).
    contact_angle_rad : float
        Contact angle (rad).
    """

    y_rail_mm: float
    y_wheel_mm: float
    normal_gap_mm: float
    contact_angle_rad: float


@dataclass(frozen=True, kw_only=True)
class FlangeTip(Record):
    """The wheel's flange tip.

    Attributes
    ----------
    y_wheel_mm : float
        Wheel profile coordinate (mm).
    Y_side_mm : float
        Lateral position in the side frame (mm).
    """

    y_wheel_mm: float
    Y_side_mm: float


@dataclass(frozen=True, kw_only=True)
class WheelResult(Record):
    """One wheel of a case.

    Attributes
    ----------
    side : str
        "right" or "left" (-).
    wheel_height_mm : float
        Wheelset centre height at rigid contact (mm).
    approach_mm : float
        Vertical approach Delta beyond rigid contact (mm).
    vertical_balance_rel : float
        |sum F_Z - Q| / Q of the balanced quantity (-).
    balance : str
        "total" or "normal" (``method.balance``) (-).
    balance_iterations : int
        Patch solves of the balance (-).
    vertical_force_N : float
        Z component of the total contact force on the wheel (N).
    merge_mm : float | None
        The candidate merge level used (mm).
    normal_vertical_N : float
        Z component of the normal forces alone (N).
    force_on_wheel_track_N : tuple[float, float, float]
        Total contact force of the rail on the wheel, track frame (N).
    Y_over_Q : float
        Lateral over vertical force (-).
    n_patches : int
        Loaded patches (-).
    patches : tuple[PatchResult, ...]
        The loaded patches.
    unloaded_candidates : tuple[UnloadedCandidate, ...]
        The candidates carrying no load.
    flange_tip : FlangeTip
        The flange tip.
    """

    side: str
    wheel_height_mm: float
    approach_mm: float
    vertical_balance_rel: float
    balance: str
    balance_iterations: int
    vertical_force_N: float
    merge_mm: float | None
    normal_vertical_N: float
    force_on_wheel_track_N: tuple[float, float, float]
    Y_over_Q: float
    n_patches: int
    patches: tuple[PatchResult, ...]
    unloaded_candidates: tuple[UnloadedCandidate, ...]
    flange_tip: FlangeTip

    def __repr__(self) -> str:
        return (f"WheelResult({self.side}, Fz={self.vertical_force_N:.6g} N, Y/Q={self.Y_over_Q:.4g}, "
                f"patches={self.n_patches}, approach={self.approach_mm:.5g} mm)")

    @classmethod
    def of(cls, sol: WheelRailSolution) -> WheelResult:
        Q = sol.inputs.vertical_load_N
        force = sum((p.force_track_N() for p in sol.patches), np.zeros(3))
        tip_y_wheel_mm, tip_Y_side_mm = sol.search.flange_tip
        return cls(side=sol.inputs.side, wheel_height_mm=sol.search.wheel_height_mm, approach_mm=sol.approach_mm,
                   vertical_balance_rel=sol.vertical_balance_rel, balance=sol.inputs.balance,
                   balance_iterations=sol.balance_iterations, vertical_force_N=float(force[2]), merge_mm=sol.merge_mm,
                   normal_vertical_N=float(sum(p.normal_force_N * p.normal_track[2] for p in sol.patches)),
                   force_on_wheel_track_N=tuple(force.tolist()), Y_over_Q=float(force[1] / Q),
                   n_patches=len(sol.patches),
                   patches=tuple(PatchResult.of(p, p.vertical_N / float(force[2])) for p in sol.patches),
                   unloaded_candidates=tuple(
                       UnloadedCandidate(y_rail_mm=c.y_rail_mm, y_wheel_mm=c.y_wheel_mm, normal_gap_mm=c.normal_gap_mm,
                                         contact_angle_rad=c.contact_angle_rad) for c in sol.unloaded),
                   flange_tip=FlangeTip(y_wheel_mm=tip_y_wheel_mm, Y_side_mm=tip_Y_side_mm))


@dataclass(frozen=True, kw_only=True)
class DeformedProfileFile(Record):
    """A deformed profile written for a case.

    Attributes
    ----------
    file : str
        The file, relative to the output folder.
    body : str
        "rail" or "wheel" (-).
    side : str
        "right" or "left" (-).
    max_residual_mm : float
        Largest residual displacement applied (mm).
    read_back_max_error_mm : float
        Largest deviation of the file read back from the points written (mm).
    """

    file: str
    body: str
    side: str
    max_residual_mm: float
    read_back_max_error_mm: float


@dataclass(frozen=True, kw_only=True)
class CaseResult(Record):
    """One case of the scene: its pose, load and speed, and every wheel (or the error that stopped it).

    Attributes
    ----------
    lateral_mm : float
        Lateral wheelset displacement towards the right rail (mm).
    yaw_rad : float
        Yaw angle (rad).
    roll_rad : float
        Roll angle (rad; solved with ``roll_rad = "auto"``).
    pitch_rate_rad_s : float | None
        Pitch rate (rad/s).
    vertical_load_N : float
        Vertical load per wheel (N).
    speed_mm_s : float
        Rolling speed (mm/s).
    wheels : dict[str, WheelResult] | None
        Per side ("right", "left"); left out for a failed case.
    rolling_radius_difference_mm : float | None
        Rolling radius of the main patches, left - right (mm); both wheels only.
    deformed_profiles : tuple[DeformedProfileFile, ...] | None
        The deformed profiles written (with layers and ``output.deformed_profiles``).
    error : str | None
        Why the case failed; left out for a solved case.
    failed_wheel : str | None
        The wheel ("right" or "left") whose solution failed; left out for a solved case or a failure of the
        whole wheelset (the rigid roll).
    case : int
        Case number, 0-based (-).
    time_s : float
        Wall-clock time of the case (s).
    """

    lateral_mm: float
    yaw_rad: float
    roll_rad: float
    pitch_rate_rad_s: float | None
    vertical_load_N: float
    speed_mm_s: float
    wheels: dict[str, WheelResult] | None = field(default=None, metadata=OMIT_NONE)
    rolling_radius_difference_mm: float | None = field(default=None, metadata=OMIT_NONE)
    deformed_profiles: tuple[DeformedProfileFile, ...] | None = field(default=None, metadata=OMIT_NONE)
    error: str | None = field(default=None, metadata=OMIT_NONE)
    failed_wheel: str | None = field(default=None, metadata=OMIT_NONE)
    case: int = 0
    time_s: float = 0.0

    def __repr__(self) -> str:
        what = self.error if self.error is not None else ", ".join(repr(w) for w in (self.wheels or {}).values())
        return f"CaseResult({self.case}: lateral {self.lateral_mm:g} mm, yaw {self.yaw_rad:g} rad: {what})"


@dataclass(frozen=True, kw_only=True)
class RailPlacement(Record):
    """The rail placed in the side frame.

    Attributes
    ----------
    dy_mm : float
        Lateral shift of the profile (mm).
    dz_mm : float
        Vertical shift of the profile (mm).
    angle_rad : float
        Rotation (the inclination) (rad).
    gauge_point_Y_mm : float
        Lateral position of the gauge point (mm).
    gauge_point_Z_mm : float
        Height of the gauge point (mm).
    top_y_rail_mm : float
        Rail profile coordinate of the highest point (mm).
    """

    dy_mm: float
    dz_mm: float
    angle_rad: float
    gauge_point_Y_mm: float
    gauge_point_Z_mm: float
    top_y_rail_mm: float


@dataclass(frozen=True, kw_only=True)
class SweepResult(Record):
    """The result of a wheel_rail scene (result.json).

    Attributes
    ----------
    type : str
        "wheel_rail" (-).
    inputs : dict
        The resolved inputs (the scene's ``to_dict()``).
    code_version : str
        Version of the code that ran.
    units : dict
        Units of the result fields.
    conventions : dict
        Sign and frame conventions of the result fields.
    rail_placement : RailPlacement
        The rail placed in the track.
    cases : tuple[CaseResult, ...]
        Every case in order.
    n_failed : int
        Cases that failed (-).
    timings_s : dict
        Wall-clock times: "total" (s).
    frictional_outputs : tuple[str, ...]
        The wear-ready frictional CSV files written.
    cases_csv : str
        The per-patch table file ("cases.csv").
    pictures : tuple[str, ...] | None
        The pictures written (with ``--plots``).
    """

    type: str
    inputs: dict
    code_version: Any
    units: dict
    conventions: dict
    rail_placement: RailPlacement
    cases: tuple[CaseResult, ...]
    n_failed: int
    timings_s: dict
    frictional_outputs: tuple[str, ...] = ()
    cases_csv: str = "cases.csv"
    pictures: tuple[str, ...] | None = field(default=None, metadata=OMIT_NONE)
    warnings: tuple[str, ...] | None = field(default=None, metadata=OMIT_NONE)

    def __repr__(self) -> str:
        return f"SweepResult({len(self.cases)} cases, {self.n_failed} failed, {self.timings_s.get('total', 0):.3g} s)"


__all__ = ["CaseResult", "DeformedProfileFile", "FlangeTip", "RailPlacement", "SweepResult", "UnloadedCandidate",
           "WheelResult"]
