"""Engineering ranges of wheel/rail inputs and results: a value outside is an input slip until the user says otherwise.

Units: mm, N, MPa, s. A scene key whose value lies outside the range of its quantity (:data:`INPUT_RANGES`, steel
wheels and rails, standard and light-rail gauges, test rigs included) is an :class:`ImplausibleInput` (exit 2) naming
the key, the value and the range, and when the value times 1000 or 1/1000 (or 1e6) lies inside, the slip that
explains it (``E_MPa = 210``: "GPa typed as MPa?"). A scene that means it (a polymer model, a scaled rig) sets the
top-level override key ``accept_implausible = true`` (:data:`OVERRIDE_KEY`): the check is skipped. Section keys
declare their quantity once (``key(..., plausible="E_MPa")``, :mod:`wrlayer.section_keys`); the reader checks them.

A result whose peak pressure, approach or patch size lies outside :data:`RESULT_RANGES` is not refused (the inputs
were plausible): :func:`result_warnings` gives one line per value for ``result.json`` (``warnings``) and stderr.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from wrlayer.errors import InputError

#: The top-level scene key that switches the input check off (a documented override).
OVERRIDE_KEY = "accept_implausible"


class ImplausibleInput(InputError):
    """A physical input outside the engineering range of its quantity (:data:`INPUT_RANGES`); exit code 2."""


@dataclass(frozen=True)
class PlausibleRange:
    """The engineering range of one quantity.

    Attributes
    ----------
    quantity : str
        What the value is (``Young's modulus``).
    unit : str
        The unit the value is given in (``MPa``).
    low : float
        Smallest plausible magnitude (in ``unit``).
    high : float
        Largest plausible magnitude (in ``unit``).
    magnitude : bool
        True when the sign carries meaning of its own (a concave radius is negative): the range bounds |value|.
    slips : tuple[tuple[float, str], ...]
        (factor, description): when value x factor lies in the range, the description names the likely slip.
    """

    quantity: str
    unit: str
    low: float
    high: float
    magnitude: bool = False
    slips: tuple[tuple[float, str], ...] = ()

    def contains(self, value: float) -> bool:
        v = abs(value) if self.magnitude else value
        return self.low <= v <= self.high

    def slip(self, value: float) -> str | None:
        """The unit slip that brings an implausible ``value`` into the range, None when none does (or it is
        plausible)."""
        if not math.isfinite(value) or self.contains(value):
            return None
        return next((slip for factor, slip in self.slips if self.contains(value * factor)), None)

    def problem(self, value: float) -> str | None:
        """None when ``value`` is plausible, else what is wrong with it (one line)."""
        if not math.isfinite(value):
            return f"{value!r} is not a finite number"
        if self.contains(value):
            return None
        text = (f"{value:g} {self.unit} is outside the engineering range of the {self.quantity} for steel wheels "
                f"and rails ({self.low:g}..{self.high:g} {self.unit}{', magnitude' if self.magnitude else ''})")
        for factor, slip in self.slips:
            if self.contains(value * factor):
                return f"{text}: {slip} (x {factor:g} gives {value * factor:g} {self.unit})"
        return f"{text}; set {OVERRIDE_KEY} = true if it is meant"


_GPA = ((1e3, "GPa typed as MPa?"), (1e-6, "Pa typed as MPa?"))
_METRES = ((1e3, "metres typed as millimetres?"),)
_KN = ((1e3, "kN typed as N?"), (1e-3, "mN or a factor 1000 too large?"))

#: Input quantities (scene keys name one of these through :func:`check_input`).
INPUT_RANGES: dict[str, PlausibleRange] = {
    "E_MPa": PlausibleRange("Young's modulus", "MPa", 150e3, 250e3, slips=_GPA),
    "G_MPa": PlausibleRange("shear modulus", "MPa", 55e3, 100e3, slips=_GPA),
    "poisson": PlausibleRange("Poisson's ratio", "-", 0.2, 0.35),
    "yield_MPa": PlausibleRange("yield stress", "MPa", 150.0, 2500.0, slips=_GPA),
    "hardening_MPa": PlausibleRange("hardening modulus", "MPa", 0.0, 100e3, slips=_GPA),
    "wheel_radius_mm": PlausibleRange("wheel rolling radius", "mm", 150.0, 700.0, slips=_METRES),
    "rolling_radius_mm": PlausibleRange("rolling-direction radius", "mm", 100.0, 5000.0, magnitude=True,
                                        slips=_METRES),
    "profile_radius_mm": PlausibleRange("transverse profile radius", "mm", 2.0, 1e9, magnitude=True,
                                        slips=_METRES),
    "normal_force_N": PlausibleRange("normal force of a contact", "N", 100.0, 500e3, slips=_KN),
    "wheel_load_N": PlausibleRange("vertical wheel load", "N", 1e3, 500e3, slips=_KN),
    "speed_mm_s": PlausibleRange("rolling speed", "mm/s", 100.0, 150e3,
                                 slips=((1e3, "m/s typed as mm/s?"), (1e3 / 3.6, "km/h typed as mm/s?"))),
    "gauge_mm": PlausibleRange("track gauge", "mm", 600.0, 1700.0, slips=_METRES),
}

#: Result quantities and their plausible ranges (a warning, not an error).
RESULT_RANGES: dict[str, PlausibleRange] = {
    "p_max_MPa": PlausibleRange("peak contact pressure", "MPa", 50.0, 6000.0),
    "approach_mm": PlausibleRange("approach", "mm", 1e-4, 1.0),
    "semi_axis_mm": PlausibleRange("contact patch half-length", "mm", 0.05, 40.0),
}


def check_input(key: str, value: float, quantity: str, accept: bool = False, slips_only: bool = False) -> float:
    """``value`` of scene key ``key`` (full dotted name) when it lies in the range of ``quantity``
    (:data:`INPUT_RANGES`) or ``accept`` (the override key) is set; else :class:`ImplausibleInput`.
    ``slips_only``: refuse only a value that a unit slip explains (a reader's first check, before its hard bounds,
    whose message is clearer for a negative or zero value)."""
    rng = INPUT_RANGES[quantity]
    problem = rng.problem(float(value))
    if problem is not None and not accept and (not slips_only or rng.slip(float(value)) is not None):
        raise ImplausibleInput(key, problem)
    return value


def result_warnings(where: str, values: dict[str, float]) -> list[str]:
    """One warning line per result value outside its plausible range (``values``: quantity name of
    :data:`RESULT_RANGES` -> value). ``where`` names the scene, case or patch."""
    lines = []
    for quantity, value in values.items():
        rng = RESULT_RANGES[quantity]
        if math.isfinite(value) and not rng.contains(value):
            lines.append(f"warning: {where}: {quantity} = {value:.4g} {rng.unit} is outside the plausible range of "
                         f"the {rng.quantity} of steel wheel/rail contact ({rng.low:g}..{rng.high:g} {rng.unit}): "
                         "check the inputs' units")
    return lines
