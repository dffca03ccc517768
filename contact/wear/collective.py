"""Load collective of a wear simulation: running conditions, each with its share of the distance (units mm, N,
mm/s, rad; distance in km).

A condition is one quasi-static state of the wheelset: lateral displacement (towards the right rail), yaw,
vertical load per wheel (or per side), speed, the track curvature (0 on straight track; a steady curve's terms in
the creepages, :mod:`contact.wear.curving`), and its weight = the share of the running distance spent in it. The
weights must sum to one (within 1e-9).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from contact.wear.curving import CurvingBalance
from wrlayer.errors import InputError
from wrlayer.section_keys import NOT_A_KEY

WEIGHT_SUM_TOL = 1e-9
#: Condition fields written to result.json only when set (runs without them keep their records).
OPTIONAL_RECORDS = ("balance", "creepages_right", "creepages_left")


#: Largest number of running conditions of a collective (each is solved on every side in every step).
MAX_CONDITIONS = 10_000
#: Largest track curvature (1/m): radius 50 m, below the tightest tramway curves of standard-gauge vehicles.
MAX_CURVATURE_1_PER_M = 0.02

@dataclass(frozen=True)
class Condition:
    """One running condition and its weight: a ``[[collective.condition]]`` table (or one entry of a sweep).

    Attributes
    ----------
    lateral_mm : float
        Lateral displacement of the wheelset towards the right rail (mm).
    yaw_rad : float
        Yaw angle of the wheelset (rad), |yaw| < 0.2.
    vertical_load_N : float
        Vertical load per wheel (N); default the scene's ``[load]``.
    speed_mm_s : float
        Running speed (mm/s); default the scene's ``[load]``.
    weight : float
        Share of the running distance spent in this condition (0..1]; the weights sum to 1.
    label : str
        Name in messages and results (default: the numbers).
    pitch_rate_rad_s : float or None
        Angular velocity of the wheelset (rad/s); None = the scene's (default: pure rolling at the nominal radius,
        V / r0). A value different from V / r0 adds a longitudinal creepage (traction or braking).
    vertical_load_right_N : float or None
        Vertical load of the right wheel (N); None = ``vertical_load_N``.
    vertical_load_left_N : float or None
        Vertical load of the left wheel (N); None = ``vertical_load_N``.
    curvature_1_per_m : float
        Track curvature 1/R (1/m), positive for a curve to the left (the right rail is the outer, high rail);
        0 = straight track. Gives the wheelset's yaw rate -V / R (:mod:`contact.wear.curving`).
    balance : CurvingBalance or None
        A curve whose wheelset position is found from the quasi-static balance in every step
        (:mod:`contact.wear.quasi_static`; ``lateral_mm`` and ``yaw_rad`` are then unused); None: given.
    creepages_right : tuple or None
        Creepages (vx, vy, phi (1/mm)) of the right wheel from a multibody export, used instead of the kinematic
        ones (:mod:`contact.wear.mbs_collective`); None: from the kinematics.
    creepages_left : tuple or None
        The same for the left wheel.
    """

    lateral_mm: float
    yaw_rad: float
    vertical_load_N: float
    speed_mm_s: float
    weight: float
    label: str = ""
    pitch_rate_rad_s: float | None = None
    vertical_load_right_N: float | None = None
    vertical_load_left_N: float | None = None
    curvature_1_per_m: float = 0.0
    balance: CurvingBalance | None = field(default=None, metadata={NOT_A_KEY: True})
    creepages_right: tuple[float, float, float] | None = field(default=None, metadata={NOT_A_KEY: True})
    creepages_left: tuple[float, float, float] | None = field(default=None, metadata={NOT_A_KEY: True})

    def to_dict(self) -> dict[str, Any]:
        """The condition as result.json records it (the balance and the given creepages only where present)."""
        out = {k: v for k, v in vars(self).items() if v is not None or k not in OPTIONAL_RECORDS}
        return out if self.balance is None else {**out, "balance": vars(self.balance)}

    def creepages_on(self, side: str) -> tuple[float, float, float] | None:
        """The given creepages (vx, vy, phi (1/mm)) of the ``side`` wheel; None: from the kinematics."""
        return self.creepages_right if side == "right" else self.creepages_left

    def describe(self) -> str:
        position = "position from the balance" if self.balance else \
            f"lateral {self.lateral_mm:g} mm, yaw {self.yaw_rad:g} rad"
        return (self.label or f"{position}, "
                f"{self.vertical_load_N:g} N, {self.speed_mm_s:g} mm/s"
                + (f", curve 1/R = {self.curvature_1_per_m:g} 1/m" if self.curvature_1_per_m else ""))

    def load_on(self, side: str) -> float:
        """Vertical load (N) of the ``side`` wheel."""
        load = self.vertical_load_right_N if side == "right" else self.vertical_load_left_N
        return self.vertical_load_N if load is None else load

    @property
    def yaw_rate_rad_s(self) -> float:
        """The wheelset's yaw rate psi' = -V kappa (rad/s) of a steady curve (0 on straight track)."""
        return -self.speed_mm_s * self.curvature_1_per_m * 1e-3


@dataclass(frozen=True)
class LoadCollective:
    """The ``[collective]`` with the distance and the nominal steps of ``[wear]``.

    Attributes
    ----------
    conditions : tuple of Condition
        The running conditions (``[[collective.condition]]`` or a sweep).
    distance_km : float
        Total running distance of the wheel (km), ``wear.distance_km``.
    steps : int
        Nominal number of profile-update steps, ``wear.steps`` (the step control may add some).
    where : str
        The input named in error messages (not a scene key).
    source_file : str
        The multibody export the conditions were merged from (``[collective] csv``); empty otherwise.
    source_sha256 : str
        SHA-256 of that file's bytes; empty otherwise.
    """

    conditions: tuple[Condition, ...]
    distance_km: float
    steps: int
    where: str = "collective"
    source_file: str = ""
    source_sha256: str = ""

    def __post_init__(self):
        if not self.conditions:
            raise InputError(f"{self.where}.conditions", "needs at least one running condition")
        if len(self.conditions) > MAX_CONDITIONS:
            raise InputError(f"{self.where}.conditions", f"at most {MAX_CONDITIONS} conditions, got "
                                                         f"{len(self.conditions)}")
        for k, c in enumerate(self.conditions):
            if not (math.isfinite(c.weight) and c.weight > 0):
                raise InputError(f"{self.where}.conditions[{k}].weight", f"must be > 0, got {c.weight!r}")
            for key in ("vertical_load_N", "vertical_load_right_N", "vertical_load_left_N"):
                q = getattr(c, key)
                if q is not None and not (math.isfinite(q) and q > 0):
                    raise InputError(f"{self.where}.conditions[{k}].{key}", f"must be > 0, got {q!r}")
            if not (math.isfinite(c.curvature_1_per_m) and abs(c.curvature_1_per_m) <= MAX_CURVATURE_1_PER_M):
                raise InputError(f"{self.where}.conditions[{k}].curvature_1_per_m", "must be finite with |1/R| <= "
                                 f"{MAX_CURVATURE_1_PER_M:g} 1/m (R >= {1 / MAX_CURVATURE_1_PER_M:g} m), got "
                                 f"{c.curvature_1_per_m!r}")
            if not (math.isfinite(c.speed_mm_s) and c.speed_mm_s > 0):
                raise InputError(f"{self.where}.conditions[{k}].speed_mm_s", "must be > 0")
            if not abs(c.yaw_rad) < 0.2:
                raise InputError(f"{self.where}.conditions[{k}].yaw_rad", f"|yaw| must be < 0.2 rad, got {c.yaw_rad}")
        total = sum(c.weight for c in self.conditions)
        if abs(total - 1.0) > WEIGHT_SUM_TOL:
            raise InputError(f"{self.where}.weights", f"must sum to 1, they sum to {total:.12g}")
        if not (math.isfinite(self.distance_km) and self.distance_km > 0):
            raise InputError("wear.distance_km", f"must be a positive distance, got {self.distance_km!r}")
        if not (isinstance(self.steps, int) and self.steps >= 1):
            raise InputError("wear.steps", f"must be an integer >= 1, got {self.steps!r}")

    @property
    def creepages_given(self) -> bool:
        """The conditions' creepages come from the multibody export (not from the kinematics)."""
        return any(c.creepages_right is not None for c in self.conditions)

    @property
    def nominal_step_km(self) -> float:
        return self.distance_km / self.steps


__all__ = ["MAX_CONDITIONS", "MAX_CURVATURE_1_PER_M", "WEIGHT_SUM_TOL", "Condition", "LoadCollective"]
