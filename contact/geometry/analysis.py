"""The wheel/rail contact-geometry analysis of a wheelset on its track: the API function and its result (units mm,
rad).

:func:`contact_geometry` sweeps the wheelset laterally (:mod:`contact.geometry.sweep`: rigid contact, roll
included), finds the jumps of the contact points (:mod:`contact.geometry.jumps`) and the equivalent conicity over
the amplitudes (:mod:`contact.geometry.conicity`, EN 15302). What every multibody pre-processor gives for a
wheel/rail pair, before any contact mechanics.

Example::

    from contact.geometry import WheelsetProfiles, contact_geometry
    from contact.wheel_rail.track_geometry import TrackLayout
    from meshes.profiles import S1002, Rail60E1

    result = contact_geometry(WheelsetProfiles(Rail60E1(), S1002()), TrackLayout(gauge_mm=1435.0))
    result.conicity.at(3.0)          # tan gamma_e at 3 mm amplitude (-)
    result.sweep.delta_r_mm          # Delta r(y) (mm) at result.sweep.lateral_mm
"""

from __future__ import annotations

from dataclasses import dataclass

from contact.geometry.conicity import ConicityCurve, conicity_curve
from contact.geometry.defaults import DEFAULT_AMPLITUDES_MM, DEFAULT_JUMP_MM, DEFAULT_LATERAL_MM, DEFAULT_STEP_MM
from contact.geometry.jumps import ContactJump, contact_jumps
from contact.geometry.sweep import LateralSweep, WheelsetProfiles, lateral_positions, lateral_sweep
from contact.wheel_rail.track_geometry import TrackLayout
from wrlayer.errors import InputError



@dataclass(frozen=True, eq=False)
class GeometryResult:
    """The contact geometry of one wheelset on its track.

    profiles, layout: the inputs; sweep: rigid contact at every lateral displacement; conicity: equivalent conicity
    over the amplitudes; jumps: the contact-point jumps of both sides; jump_mm: the threshold that found them.
    """

    profiles: WheelsetProfiles
    layout: TrackLayout
    sweep: LateralSweep
    conicity: ConicityCurve
    jumps: tuple[ContactJump, ...]
    jump_mm: float

    def __repr__(self) -> str:
        y = self.sweep.lateral_mm
        return (f"GeometryResult({self.profiles.wheel.name} on {self.profiles.rail.name}, gauge "
                f"{self.layout.gauge_mm:g} mm, lateral {y[0]:g}..{y[-1]:g} mm ({y.size} positions), "
                f"{len(self.jumps)} jump(s))")

    def summary_lines(self) -> list[str]:
        """Key numbers for the terminal (each line < 100 columns)."""
        c, s = self.conicity, self.sweep
        lines = [f"e0 = {s.e0_mm:.2f} mm, r0 = {s.r0_mm:.2f} mm at the centred position"]
        for a in (1.0, 2.0, 3.0, 4.0, 6.0, 10.0):
            hit = [i for i, v in enumerate(c.amplitude_mm) if abs(v - a) < 1e-9]
            if hit:
                i = hit[0]
                lines.append(f"amplitude {a:4.1f} mm: tan gamma_e = {c.equivalent_conicity[i]:.4f} (harmonic "
                             f"{c.harmonic_conicity[i]:.4f}), wavelength {c.wavelength_mm[i] / 1000:.2f} m")
        for j in self.jumps:
            lines.append(f"jump {j.side:5s} at y = {j.lateral_from_mm:+.2f}..{j.lateral_to_mm:+.2f} mm: rail "
                         f"{j.y_rail_from_mm:+.2f} -> {j.y_rail_to_mm:+.2f} mm, wheel {j.y_wheel_from_mm:+.2f} -> "
                         f"{j.y_wheel_to_mm:+.2f} mm")
        return lines


def contact_geometry(profiles: WheelsetProfiles, layout: TrackLayout = TrackLayout(),
                     lateral_min_mm: float = DEFAULT_LATERAL_MM[0], lateral_max_mm: float = DEFAULT_LATERAL_MM[1],
                     step_mm: float = DEFAULT_STEP_MM, amplitudes_mm=DEFAULT_AMPLITUDES_MM,
                     jump_mm: float = DEFAULT_JUMP_MM, with_roll: bool = True) -> GeometryResult:
    """Rigid contact geometry of a wheelset over a lateral range and its equivalent conicity (EN 15302).

    Parameters
    ----------
    profiles : WheelsetProfiles
        Rail and wheel profiles (right side; the left side's when they differ).
    layout : TrackLayout
        Gauge, gauge depth, rail inclination (rad), back-to-back distance, flange-back coordinate and nominal
        rolling radius (mm).
    lateral_min_mm, lateral_max_mm, step_mm : float
        Lateral displacements of the wheelset (mm, positive towards the right rail); 0 is always included.
    amplitudes_mm : sequence of float
        Amplitudes of the equivalent conicity (mm; default 0.5..10 in 0.5 mm steps). Each must fit in the range.
    jump_mm : float
        Contact-point travel per step above which the step is reported as a jump (mm).
    with_roll : bool
        Roll the wheelset so that both wheels touch (True, as a rigid wheelset does) or keep it level and lower
        each wheel onto its rail on its own (False, as the wear loop's Delta r).

    Raises
    ------
    InputError
        For a bad range, an amplitude whose oscillation leaves the range, or profiles that do not meet.
    """
    y = lateral_positions(lateral_min_mm, lateral_max_mm, step_mm)
    if not (y[0] < 0.0 < y[-1]):
        raise InputError("lateral range", f"{y[0]:g}..{y[-1]:g} mm must contain the centred position 0")
    sweep = lateral_sweep(profiles, layout, y, with_roll=with_roll)
    curve = conicity_curve(sweep.lateral_mm, sweep.delta_r_mm, sweep.e0_mm, sweep.r0_mm, amplitudes_mm)
    jumps = tuple(contact_jumps("right", y, sweep.right.y_rail_mm, sweep.right.y_wheel_mm, jump_mm)
                  + contact_jumps("left", y, sweep.left.y_rail_mm, sweep.left.y_wheel_mm, jump_mm))
    return GeometryResult(profiles, layout, sweep, curve, jumps, float(jump_mm))


__all__ = ["DEFAULT_LATERAL_MM", "GeometryResult", "contact_geometry"]
