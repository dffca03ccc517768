"""A steady curve as a running condition: quasi-static curving (units mm, N, s, rad; curve radius in m).

Model (quasi-static curving of one wheelset, Iwnicki (ed.), Handbook of Railway Vehicle Dynamics, 2006, ch. 9;
Wickens, Fundamentals of Rail Vehicle Dynamics, 2003, ch. 7; cant and unbalanced acceleration after Esveld, Modern
Railway Track, 2001, ch. 2 and EN 13803):

- The curve has the signed curvature kappa = 1 / R (``curvature_1_per_m`` of the condition, positive for a curve to
  the LEFT, so that the right rail is the outer, high rail; negative for a curve to the right).
- Unbalanced lateral acceleration in the track plane, towards the outer rail::

      a_u = V^2 |kappa| - g h_t / s0        (cant h_t, ``cant_mm``)
      a_u = g I / s0                        (cant deficiency I, ``cant_deficiency_mm``)

  with g = 9810 mm/s^2 and s0 = gauge + 65 mm the distance of the rail-head centres (1500 mm for 1435 mm gauge,
  EN 13803).
- Load transfer (moment balance of the rigid vehicle about the track centre, roll of the suspension neglected):
  the lateral force 2 Q a_u / g acting at the height h (``cg_height_mm``) over the half distance e0 of the contact
  points gives Q_outer,inner = Q (1 +- a_u h / (g e0)), Q the mean vertical wheel load; h = 0 keeps both at Q.
- Kinematics: the wheelset's yaw rate is psi' = -V kappa (:attr:`contact.wear.collective.Condition.yaw_rate_rad_s`);
  the creepages at every contact point follow from it with the rolling-radius difference, the attack angle (the
  wheelset yaw ``yaw_rad`` relative to the track tangent) and the contact angle
  (:func:`contact.wheel_rail.kinematics.creepages`), to first order the linear curving creepages
  vx = +-(e0 / R - y gamma / r0), vy = -psi, phi = -+gamma / r0 - kappa.
- Position: the lateral displacement ``lateral_mm`` and the attack angle ``yaw_rad`` are given (from a multibody
  run, or e.g. the flange-contact position with the attack angle a / R of a bogie's leading wheelset of
  semi-wheelbase a). The lateral balance (the contact forces carrying 2 Q a_u / g) is not solved here; the
  force the contacts carry is in each condition's summary (``Fy_N``) to check it against.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from wrlayer.errors import InputError
from wrlayer.section_keys import key

#: Gravitational acceleration (mm/s^2).
G_MM_S2 = 9810.0
#: Distance of the rail-head centres minus the track gauge (mm): s0 = 1500 mm for 1435 mm gauge (EN 13803).
HEAD_CENTRES_OVER_GAUGE_MM = 65.0
#: Values of ``wheelset_position``: the condition's lateral_mm and yaw_rad, or found from the balance.
WHEELSET_POSITIONS = ("given", "balance")
#: Keys of the balance's suspension (only with ``wheelset_position = "balance"``).
SUSPENSION_KEYS = ("lateral_stiffness_N_per_mm", "yaw_stiffness_Nmm_per_rad", "frame_yaw_rad")


@dataclass(frozen=True)
class CurveSpec:
    """The cant and load transfer of a curved ``[[collective.condition]]`` (one with ``curvature_1_per_m`` != 0).

    Attributes
    ----------
    cant_mm : float or None
        Cant (superelevation) h_t of the outer rail (mm); None: 0, or the curve is given by ``cant_deficiency_mm``.
    cant_deficiency_mm : float or None
        Cant deficiency I (mm), instead of ``cant_mm``: a_u = g I / s0.
    cg_height_mm : float
        Height h of the vehicle's centre of gravity above the rail tops (mm) for the load transfer; 0: none.
    wheelset_position : str
        ``"given"``: the condition's lateral_mm and yaw_rad; ``"balance"``: found from the quasi-static balance of
        lateral forces and yaw moments in every step (then lateral_mm and yaw_rad are not given).
    lateral_stiffness_N_per_mm : float
        Balance: lateral stiffness k_y of the primary suspension to a frame on the track centre line (N/mm).
    yaw_stiffness_Nmm_per_rad : float
        Balance: yaw stiffness k_psi of the primary suspension to the frame (N mm/rad); 0 with k_y = 0: a free
        wheelset.
    frame_yaw_rad : float
        Balance: the frame's yaw relative to the track tangent (rad); 0: a radial frame.
    """

    cant_mm: float | None = key(None, "mm")
    cant_deficiency_mm: float | None = key(None, "mm")
    cg_height_mm: float = key(0.0, "mm", ge=0.0, le=5000.0)
    wheelset_position: str = key("given", choices=WHEELSET_POSITIONS)
    lateral_stiffness_N_per_mm: float = key(0.0, "N/mm", ge=0.0)
    yaw_stiffness_Nmm_per_rad: float = key(0.0, "N mm/rad", ge=0.0)
    frame_yaw_rad: float = key(0.0, "rad", ge=-0.05, le=0.05)

    def __post_init__(self):
        if self.cant_mm is not None and self.cant_deficiency_mm is not None:
            raise InputError("cant_deficiency_mm", "give cant_mm or cant_deficiency_mm, not both")
        for key in ("cant_mm", "cant_deficiency_mm"):
            v = getattr(self, key)
            if v is not None and not (math.isfinite(v) and abs(v) <= 300.0):
                raise InputError(key, f"must lie within +-300 mm, got {v!r}")
        if not (math.isfinite(self.cg_height_mm) and 0.0 <= self.cg_height_mm <= 5000.0):
            raise InputError("cg_height_mm", f"must lie in [0, 5000] mm, got {self.cg_height_mm!r}")
        if self.wheelset_position not in WHEELSET_POSITIONS:
            raise InputError("wheelset_position", f"must be one of {', '.join(WHEELSET_POSITIONS)}, got "
                             f"{self.wheelset_position!r}")
        for key in SUSPENSION_KEYS:
            v = getattr(self, key)
            if self.wheelset_position == "given" and v != 0.0:
                raise InputError(key, 'needs wheelset_position = "balance" (a given position has no suspension)')
            if not (math.isfinite(v) and (v >= 0.0 or key == "frame_yaw_rad")):
                raise InputError(key, f"must be a finite number >= 0, got {v!r}")

    def unbalanced_acceleration_mm_s2(self, curvature_1_per_m: float, speed_mm_s: float, gauge_mm: float) -> float:
        """a_u (mm/s^2) towards the outer rail (negative: cant excess), see the module docstring."""
        s0 = gauge_mm + HEAD_CENTRES_OVER_GAUGE_MM
        if self.cant_deficiency_mm is not None:
            return G_MM_S2 * self.cant_deficiency_mm / s0
        cant = 0.0 if self.cant_mm is None else self.cant_mm
        return speed_mm_s ** 2 * abs(curvature_1_per_m) * 1e-3 - G_MM_S2 * cant / s0

    def side_loads(self, curvature_1_per_m: float, load_N: float, speed_mm_s: float, gauge_mm: float,
                   e0_mm: float) -> tuple[float, float]:
        """(right, left) vertical wheel loads (N) for the mean wheel load ``load_N``; InputError when the inner
        wheel unloads completely."""
        a_u = self.unbalanced_acceleration_mm_s2(curvature_1_per_m, speed_mm_s, gauge_mm)
        shift = a_u * self.cg_height_mm / (G_MM_S2 * e0_mm)
        if not abs(shift) < 1.0:
            raise InputError("cg_height_mm", f"the load transfer a_u h / (g e0) = {shift:.3g} unloads a wheel "
                             "completely (overturning)")
        outer, inner = load_N * (1.0 + shift), load_N * (1.0 - shift)
        return (outer, inner) if curvature_1_per_m > 0 else (inner, outer)


    def balance(self, curvature_1_per_m: float, speed_mm_s: float, gauge_mm: float) -> CurvingBalance | None:
        """What the quasi-static balance needs (None for a given position)."""
        if self.wheelset_position != "balance":
            return None
        return CurvingBalance(self.unbalanced_acceleration_mm_s2(curvature_1_per_m, speed_mm_s, gauge_mm),
                              self.lateral_stiffness_N_per_mm, self.yaw_stiffness_Nmm_per_rad, self.frame_yaw_rad)


@dataclass(frozen=True)
class CurvingBalance:
    """What the quasi-static balance of a condition needs besides the wheel-rail inputs (mm, N, s, rad;
    :mod:`contact.wear.quasi_static`).

    Attributes
    ----------
    unbalanced_acceleration_mm_s2 : float
        a_u (mm/s^2) towards the outer rail (negative: cant excess).
    lateral_stiffness_N_per_mm : float
        k_y of the primary suspension to the frame (N/mm); 0: none.
    yaw_stiffness_Nmm_per_rad : float
        k_psi of the primary suspension to the frame (N mm/rad); 0: none.
    frame_yaw_rad : float
        The frame's yaw psi_f relative to the track tangent (rad); 0: radial.
    """

    unbalanced_acceleration_mm_s2: float
    lateral_stiffness_N_per_mm: float = 0.0
    yaw_stiffness_Nmm_per_rad: float = 0.0
    frame_yaw_rad: float = 0.0


__all__ = ["CurveSpec", "CurvingBalance", "G_MM_S2", "HEAD_CENTRES_OVER_GAUGE_MM", "SUSPENSION_KEYS",
           "WHEELSET_POSITIONS"]
