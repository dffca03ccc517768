"""Load collective of a wear simulation: running conditions, each with its share of the distance (units mm, N,
mm/s, rad; distance in km).

A condition is one quasi-static state of the wheelset on straight track: lateral displacement (towards the right
rail), yaw, vertical load per wheel, speed, and its weight = the share of the running distance spent in it. The
weights must sum to one (within 1e-9).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from wrlayer.errors import InputError

WEIGHT_SUM_TOL = 1e-9


#: Largest number of running conditions of a collective (each is solved on every side in every step).
MAX_CONDITIONS = 10_000

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
    """

    lateral_mm: float
    yaw_rad: float
    vertical_load_N: float
    speed_mm_s: float
    weight: float
    label: str = ""
    pitch_rate_rad_s: float | None = None

    def describe(self) -> str:
        return (self.label or f"lateral {self.lateral_mm:g} mm, yaw {self.yaw_rad:g} rad, "
                f"{self.vertical_load_N:g} N, {self.speed_mm_s:g} mm/s")


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
    """

    conditions: tuple[Condition, ...]
    distance_km: float
    steps: int
    where: str = "collective"

    def __post_init__(self):
        if not self.conditions:
            raise InputError(f"{self.where}.conditions", "needs at least one running condition")
        if len(self.conditions) > MAX_CONDITIONS:
            raise InputError(f"{self.where}.conditions", f"at most {MAX_CONDITIONS} conditions, got "
                                                         f"{len(self.conditions)}")
        for k, c in enumerate(self.conditions):
            if not (math.isfinite(c.weight) and c.weight > 0):
                raise InputError(f"{self.where}.conditions[{k}].weight", f"must be > 0, got {c.weight!r}")
            if not (math.isfinite(c.vertical_load_N) and c.vertical_load_N > 0):
                raise InputError(f"{self.where}.conditions[{k}].vertical_load_N", "must be > 0")
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
    def nominal_step_km(self) -> float:
        return self.distance_km / self.steps


__all__ = ["MAX_CONDITIONS", "WEIGHT_SUM_TOL", "Condition", "LoadCollective"]
