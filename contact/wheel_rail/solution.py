"""The solution of one wheel on its rail: every loaded patch with its normal and tangential solution, passes and
layer look-up, in the track frame (units mm, N, MPa, s, rad)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from contact.normal.kik_piotrowski import NormalProblem, NormalSolution
from contact.passes.passes import PassRecord
from contact.tangential.fastsim import TangentialResult
from contact.wheel_rail.balance import patch_tangential
from contact.wheel_rail.contact_search import ContactCandidate, SearchResult
from contact.wheel_rail.inputs import WheelRailInputs
from contact.wheel_rail.kinematics import PatchKinematics
from contact.wheel_rail.reference_point import ReferencePoint
from contact.wheel_rail.track_geometry import PlacedRail
from meshes.profiles import Profile


@dataclass(eq=False)
class PatchSolution:
    """One loaded contact candidate: geometry (side frame), track-frame vectors, normal and tangential solutions.

    ``strip_sign`` is +1 (right) or -1 (left): the problem's strip coordinate (track orientation) is
    strip_sign * eta of the candidate. ``rail_y_of_strip``/``wheel_y_of_strip``: profile coordinates (mm) of the
    strips on each body; ``residual_mm``: accumulated residual displacement per layer after the last pass (mm);
    ``pass_normals``: the normal solution of every pass; ``layer_patch_mm``: (a, b) (mm) the table layers were
    scaled to (``scale_to_patch``), ``layer_scaling_solves``: balances solved with scaled layers (0: not scaled).
    """

    candidate: ContactCandidate
    side: str
    strip_sign: int
    problem: NormalProblem
    normal: NormalSolution
    normal_force_N: float
    point_track: np.ndarray
    normal_track: np.ndarray
    lateral_track: np.ndarray
    kinematics: PatchKinematics
    tangential: list[TangentialResult]
    passes: list[PassRecord] = field(default_factory=list)
    rail_y_of_strip: np.ndarray | None = None
    wheel_y_of_strip: np.ndarray | None = None
    residual_mm: dict = field(default_factory=dict)
    reference: ReferencePoint | None = None
    pass_normals: list = field(default_factory=list)
    layer_patch_mm: tuple[float, float] | None = None
    layer_scaling_solves: int = 0

    def __repr__(self) -> str:
        return (f"PatchSolution({self.side}, y_rail={self.candidate.y_rail_mm:.4g} mm, N={self.normal_force_N:.6g} N, "
                f"Fx={self.Fx_N:.6g} N, Fy={self.Fy_N:.6g} N, p_max={self.normal.p_max_MPa:.5g} MPa, "
                f"passes={len(self.passes)})")

    @property
    def eta_ref_mm(self) -> float:
        """The reference point in the problem's strip coordinate (mm): the tangential results' strip origin."""
        return self.strip_sign * self.reference.eta_mm if self.reference is not None else 0.0

    @property
    def vertical_N(self) -> float:
        """Z component of the contact force on the wheel (track frame): N cos(gamma) + F_s sin(gamma) (N)."""
        return float(self.force_track_N()[2])

    @property
    def Fx_N(self) -> float:
        return float(sum(t.Fx_N for t in self.tangential))

    @property
    def Fy_N(self) -> float:
        return float(sum(t.Fy_N for t in self.tangential))

    @property
    def Mz_Nmm(self) -> float:
        return float(sum(t.Mz_Nmm for t in self.tangential))

    def force_track_N(self) -> np.ndarray:
        """Force of the rail on the wheel in the track frame (N): N n + Fx e_X + Fy t."""
        return (self.normal_force_N * self.normal_track + self.Fx_N * np.array([1.0, 0.0, 0.0])
                + self.Fy_N * self.lateral_track)


@dataclass(eq=False)
class WheelRailSolution:
    """All loaded patches of one wheel; ``approach_mm`` = Delta (mm, vertical, beyond rigid contact; every wheel, one
    patch or several); ``vertical_balance_rel``: |sum F_Z - Q| / Q of the balanced quantity (balance "total": the
    vertical component of normal + tangential forces; "normal": of the normal forces); ``balance_iterations``:
    patch solves of the balance; ``merge_mm``: the candidate merge level that was used
    (:func:`contact.wheel_rail.solve.solve_wheel`)."""

    inputs: WheelRailInputs
    search: SearchResult
    rail: PlacedRail
    patches: list[PatchSolution]
    approach_mm: float
    vertical_balance_rel: float
    unloaded: list[ContactCandidate]
    wheel: Profile
    balance_iterations: int = 0
    merge_mm: float | None = None

    def __repr__(self) -> str:
        return (f"WheelRailSolution({self.inputs.side}, Q={self.inputs.vertical_load_N:.6g} N, "
                f"patches={len(self.patches)}, approach={self.approach_mm:.6g} mm, "
                f"vertical_balance_rel={self.vertical_balance_rel:.3g}, merge_mm={self.merge_mm})")

    @property
    def vertical_force_N(self) -> float:
        """Z component of the total contact force on the wheel (N)."""
        return float(sum(p.vertical_N for p in self.patches))

    def pass_tangential(self, patch: PatchSolution, normal: NormalSolution) -> list[TangentialResult]:
        """FASTSIM on another pass's normal solution of ``patch``, exactly as the balance solved its first pass (the
        same creepages, reference point and, with the exact solver, pressures)."""
        return patch_tangential(normal, patch.kinematics, self.inputs, patch.eta_ref_mm)


__all__ = ["PatchSolution", "WheelRailSolution"]
