"""Equivalent conicity of a wheelset from its rolling-radius difference function (EN 15302; units mm, rad).

The one place of these formulas in the project. Input: the rolling-radius difference Delta r(y) = r_right(y) -
r_left(y) (mm) of a wheelset displaced laterally by y (mm, towards the right rail) on its track
(:mod:`contact.geometry.sweep` computes it from the profiles, the gauge and the rail inclination).

What EN 15302 prescribes (checked against the public scope and tables of contents of EN 15302:2008+A1:2010 and
EN 15302:2021; the standard's text itself was not available): the equivalent conicity tan(gamma_e) for an amplitude
y_hat is DEFINED through the wavelength lambda of the free wheelset's kinematic (Klingel) motion computed from the
Delta r function, compared with Klingel's formula for a coned wheelset, lambda = 2 pi sqrt(e0 r0 / tan gamma_e).
The standard imposes no numerical method; its informative annexes describe integration of the nonlinear
differential equation (2021: Annexes D and E, two-step and direct integration; 2008: Annex B), linear regression
of Delta r (2021: Annex F; 2008: Annex C) and harmonic linearisation (2021: Annex G).

Two methods are implemented:

:func:`kinematic_oscillation` (the definition; reported as ``equivalent_conicity``): the kinematic equation
``y'' = -Delta r(y) / (2 e0 r0)`` (x along the track in mm; e0 half the lateral distance between the contact
points, r0 the rolling radius, both at the centred position) conserves ``E = y'^2 / 2 + V(y)`` with
``V(y) = integral_{y0}^{y} Delta r / (2 e0 r0)``, y0 the equilibrium (Delta r(y0) = 0). The oscillation turns at
the peaks y_- < y0 < y_+ with V(y_-) = V(y_+) and y_+ - y_- = 2 y_hat (the amplitude is half the peak-to-peak
lateral motion, so an asymmetric Delta r is handled). Its wavelength is ``lambda = 2 integral_{y_-}^{y_+} dy /
sqrt(2 (E - V(y)))``, evaluated with y = c + y_hat sin(theta) (c the mid-point of the peaks), which removes the
turning points' square-root singularities, and the midpoint rule in theta; ``tan gamma_e = (2 pi)^2 e0 r0 /
lambda^2``. e0 and r0 cancel in gamma_e (they scale the wavelength only). For a linear Delta r = 2 gamma y the
integrand is constant and gamma_e = gamma exactly (Klingel).

:func:`harmonic_conicity` (harmonic linearisation, EN 15302:2021 Annex G; reported as ``harmonic_conicity``): the
describing function of Delta r for y = y_hat sin(phi) about y = 0::

    gamma_e(y_hat) = 1 / (2 pi y_hat) * integral_0^{2 pi} Delta r(y_hat sin phi) sin(phi) dphi

by the midpoint rule in phi (exact for a polynomial Delta r of degree below 2 n_phi); a constant offset of Delta r
drops out. The wear loop reports this one at its amplitude (:mod:`contact.wear.conicity`).

How it was checked (tests/contact/geometry/test_equivalent_conicity.py): cones (both methods give gamma for
every amplitude), a two-slope Delta r against its describing function worked by hand, a cubic Delta r (harmonic:
closed form; the wavelength method within 3 % of it, as the methods differ for a nonlinear Delta r), an offset and
asymmetric Delta r (two cones of different angle: the wavelength method gives the closed-form period of the two
half oscillations); on profiles, tests/contact/geometry/test_sweep.py (cones, circular profiles). The EN 15302
reference profiles and results (its normative annexes) were not available.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np
from scipy.optimize import brentq

from contact.geometry.defaults import DEFAULT_AMPLITUDES_MM
from wrlayer.errors import InputError

DeltaR = Callable[[np.ndarray], np.ndarray]

#: Default amplitude (mm) at which equivalent conicity is reported (EN 15302's usual y_hat = 3 mm).
DEFAULT_AMPLITUDE_MM = 3.0
#: Points per period of the harmonic linearisation.
N_PHI = 64
#: Midpoint-rule points per half wavelength of the kinematic oscillation.
N_THETA = 2000


def _check_amplitude(amplitude_mm: float) -> None:
    if not (np.isfinite(amplitude_mm) and amplitude_mm > 0.0):
        raise InputError("conicity amplitude_mm", f"must be a positive number of mm, got {amplitude_mm!r}")


def harmonic_conicity(delta_r: DeltaR, amplitude_mm: float = DEFAULT_AMPLITUDE_MM, n_phi: int = N_PHI) -> float:
    """Equivalent conicity (-, tan gamma_e) by harmonic linearisation of ``delta_r`` about y = 0.

    Parameters
    ----------
    delta_r : callable
        Delta r(y) in mm for an array of lateral displacements y in mm.
    amplitude_mm : float
        Amplitude y_hat (mm) of the lateral motion.
    n_phi : int
        Midpoint-rule points per period.
    """
    _check_amplitude(amplitude_mm)
    phi = (np.arange(n_phi) + 0.5) * (2.0 * np.pi / n_phi)
    s = np.sin(phi)
    dr = np.asarray(delta_r(amplitude_mm * s), dtype=float)
    if not np.all(np.isfinite(dr)):
        raise InputError("conicity delta_r_mm", f"not finite within +-{amplitude_mm:g} mm")
    return float(np.mean(dr * s) / amplitude_mm)


def sampled_delta_r(y_mm: np.ndarray, delta_r_mm: np.ndarray) -> DeltaR:
    """Delta r as a function, linear between samples (y strictly increasing); outside them an InputError."""
    y_mm, delta_r_mm = _checked_samples(y_mm, delta_r_mm)

    def delta_r(y: np.ndarray) -> np.ndarray:
        y = np.asarray(y, dtype=float)
        if y.size and (y.min() < y_mm[0] - 1e-12 or y.max() > y_mm[-1] + 1e-12):
            raise InputError("conicity amplitude_mm", f"Delta r is known on {y_mm[0]:g}..{y_mm[-1]:g} mm only")
        return np.interp(y, y_mm, delta_r_mm)

    return delta_r


def _checked_samples(y_mm, delta_r_mm) -> tuple[np.ndarray, np.ndarray]:
    y_mm = np.asarray(y_mm, dtype=float)
    delta_r_mm = np.asarray(delta_r_mm, dtype=float)
    if y_mm.ndim != 1 or y_mm.shape != delta_r_mm.shape or y_mm.size < 2 or np.any(np.diff(y_mm) <= 0.0):
        raise InputError("conicity delta_r_mm", "needs at least two samples at strictly increasing y")
    if not np.all(np.isfinite(delta_r_mm)):
        raise InputError("conicity delta_r_mm", "has non-finite values")
    return y_mm, delta_r_mm


# ------------------------------------------------------------------------------------------ kinematic oscillation
@dataclass(frozen=True)
class KinematicOscillation:
    """The free wheelset's kinematic oscillation of one amplitude and the equivalent conicity it defines.

    amplitude_mm: y_hat, half the peak-to-peak lateral motion; equivalent_conicity: tan gamma_e (-);
    wavelength_mm: lambda along the track; centre_mm: equilibrium y0 (Delta r(y0) = 0); peak_low_mm /
    peak_high_mm: the turning points y_- and y_+ (mm); e0_mm, r0_mm: the half contact-point distance and
    rolling radius used (they scale lambda only).
    """

    amplitude_mm: float
    equivalent_conicity: float
    wavelength_mm: float
    centre_mm: float
    peak_low_mm: float
    peak_high_mm: float
    e0_mm: float
    r0_mm: float


class _Potential:
    """V(y) = integral_{y0}^{y} Delta r dy (mm^2; without the 1 / (2 e0 r0)), exact for the piecewise-linear
    Delta r through the samples."""

    def __init__(self, y: np.ndarray, dr: np.ndarray):
        self.y, self.dr = y, dr
        self.centre = equilibrium(y, dr)
        self.cum = np.r_[0.0, np.cumsum(0.5 * (dr[1:] + dr[:-1]) * np.diff(y))]
        self.offset = 0.0
        self.offset = float(self(np.array([self.centre]))[0])

    def __call__(self, y: np.ndarray) -> np.ndarray:
        y = np.asarray(y, dtype=float)
        k = np.clip(np.searchsorted(self.y, y, side="right") - 1, 0, self.y.size - 2)
        d = np.interp(y, self.y, self.dr)
        return self.cum[k] + 0.5 * (y - self.y[k]) * (self.dr[k] + d) - self.offset


def equilibrium(y_mm: np.ndarray, delta_r_mm: np.ndarray) -> float:
    """The equilibrium y0 (mm) of the kinematic motion: the zero of Delta r nearest y = 0 (a run of zeros: its
    middle); InputError when Delta r does not change sign from - to + within the samples."""
    y, dr = np.asarray(y_mm, float), np.asarray(delta_r_mm, float)
    zero = np.flatnonzero(dr == 0.0)
    roots = []
    if zero.size:
        runs = np.split(zero, np.flatnonzero(np.diff(zero) > 1) + 1)
        roots += [0.5 * (y[r[0]] + y[r[-1]]) for r in runs]
    up = np.flatnonzero((dr[:-1] < 0.0) & (dr[1:] > 0.0))
    roots += [float(y[k] - dr[k] * (y[k + 1] - y[k]) / (dr[k + 1] - dr[k])) for k in up]
    if not roots:
        raise InputError("conicity delta_r_mm", f"Delta r does not change sign from - to + on {y[0]:g}..{y[-1]:g} "
                                                "mm: the wheelset has no centred equilibrium (no restoring Delta r)")
    return float(min(roots, key=abs))


def _peaks(pot: _Potential, amplitude_mm: float) -> tuple[float, float]:
    """Turning points (y_-, y_+) with V(y_-) = V(y_+) and y_+ - y_- = 2 amplitude."""
    y0, y_lo, y_hi = pot.centre, float(pot.y[0]), float(pot.y[-1])

    def low_peak(energy: float) -> float:
        f = lambda v: float(pot(np.array([v]))[0]) - energy  # noqa: E731
        if f(y_lo) <= 0.0:  # the energy of the range's end (round-off): the end is the peak
            return y_lo
        return brentq(f, y_lo, y0, xtol=1e-12) if f(y0) < 0.0 else y0

    v_lo, v_hi = float(pot(np.array([y_lo]))[0]), float(pot(np.array([y_hi]))[0])
    if v_lo <= 0.0 or v_hi <= 0.0:
        raise InputError("conicity delta_r_mm", "Delta r does not restore the wheelset over the sampled range")
    top = y_hi if v_hi <= v_lo else brentq(lambda v: float(pot(np.array([v]))[0]) - v_lo, y0, y_hi, xtol=1e-12)
    width = lambda up: up - low_peak(float(pot(np.array([up]))[0])) - 2.0 * amplitude_mm  # noqa: E731
    if width(top) < 0.0:
        raise InputError("conicity amplitude_mm", f"{amplitude_mm:g} mm: the oscillation leaves the lateral range "
                                                  f"{y_lo:g}..{y_hi:g} mm of Delta r (widen the sweep)")
    up = brentq(width, y0 + 1e-12, top, xtol=1e-10) if width(y0 + 1e-12) < 0.0 else y0
    low = low_peak(float(pot(np.array([up]))[0]))
    inside = (pot.y > low) & (pot.y < up)
    wrong = inside & (np.sign(pot.dr) == -np.sign(pot.y - y0)) & (pot.dr != 0.0)
    if np.any(wrong):
        i = int(np.flatnonzero(wrong)[0])
        raise InputError("conicity delta_r_mm", f"Delta r = {pot.dr[i]:.4g} mm at y = {pot.y[i]:g} mm pushes the "
                                                f"wheelset away from its equilibrium y0 = {y0:.4g} mm within the "
                                                f"oscillation of amplitude {amplitude_mm:g} mm (several equilibria: "
                                                "a special case of EN 15302 not handled)")
    return low, up


def kinematic_oscillation(y_mm, delta_r_mm, amplitude_mm: float, e0_mm: float, r0_mm: float,
                          n_theta: int = N_THETA) -> KinematicOscillation:
    """Equivalent conicity from the wavelength of the free wheelset's kinematic motion (see the module docstring).

    ``y_mm``, ``delta_r_mm``: samples of Delta r (linear between them; strictly increasing y, mm);
    ``amplitude_mm``: y_hat, half the peak-to-peak lateral motion; ``e0_mm``, ``r0_mm``: half the lateral distance
    between the contact points and the rolling radius (mm)."""
    _check_amplitude(amplitude_mm)
    for key, v in (("e0_mm", e0_mm), ("r0_mm", r0_mm)):
        if not (np.isfinite(v) and v > 0.0):
            raise InputError(f"conicity {key}", f"must be a positive number of mm, got {v!r}")
    y, dr = _checked_samples(y_mm, delta_r_mm)
    pot = _Potential(y, dr)
    low, high = _peaks(pot, amplitude_mm)
    k = 1.0 / (2.0 * e0_mm * r0_mm)
    centre, half = 0.5 * (low + high), 0.5 * (high - low)
    theta = -0.5 * np.pi + (np.arange(n_theta) + 0.5) * (np.pi / n_theta)
    energy = k * float(pot(np.array([high]))[0])
    gap = np.maximum(energy - k * pot(centre + half * np.sin(theta)), 1e-300)
    wavelength = 2.0 * float(np.sum(half * np.cos(theta) / np.sqrt(2.0 * gap))) * (np.pi / n_theta)
    gamma = (2.0 * math.pi) ** 2 * e0_mm * r0_mm / wavelength ** 2
    return KinematicOscillation(float(amplitude_mm), gamma, wavelength, pot.centre, low, high, e0_mm, r0_mm)


# ------------------------------------------------------------------------------------------ over amplitudes


@dataclass(frozen=True, eq=False)
class ConicityCurve:
    """Equivalent conicity as a function of the amplitude (arrays of equal length).

    amplitude_mm: y_hat (mm); equivalent_conicity: tan gamma_e by the kinematic wavelength (-, the definition);
    harmonic_conicity: by harmonic linearisation about y = 0 (-); wavelength_mm: the kinematic wavelength (mm);
    e0_mm, r0_mm: as in :class:`KinematicOscillation`.
    """

    amplitude_mm: np.ndarray
    equivalent_conicity: np.ndarray
    harmonic_conicity: np.ndarray
    wavelength_mm: np.ndarray
    e0_mm: float
    r0_mm: float

    def at(self, amplitude_mm: float) -> float:
        """tan gamma_e (kinematic wavelength) at one of the curve's amplitudes (InputError for another)."""
        hit = np.flatnonzero(np.isclose(self.amplitude_mm, amplitude_mm, rtol=0.0, atol=1e-9))
        if not hit.size:
            raise InputError("amplitude_mm", f"{amplitude_mm:g} mm is not one of the curve's amplitudes")
        return float(self.equivalent_conicity[hit[0]])


def conicity_curve(y_mm, delta_r_mm, e0_mm: float, r0_mm: float,
                   amplitudes_mm=DEFAULT_AMPLITUDES_MM, n_phi: int = 512) -> ConicityCurve:
    """:func:`kinematic_oscillation` and :func:`harmonic_conicity` of sampled Delta r at every amplitude (mm)."""
    amps = np.asarray(amplitudes_mm, dtype=float)
    if amps.ndim != 1 or amps.size == 0:
        raise InputError("amplitudes_mm", "needs at least one amplitude")
    osc = [kinematic_oscillation(y_mm, delta_r_mm, a, e0_mm, r0_mm) for a in amps]
    f = sampled_delta_r(y_mm, delta_r_mm)
    harm = np.array([harmonic_conicity(f, a, n_phi) for a in amps])
    return ConicityCurve(amps, np.array([o.equivalent_conicity for o in osc]), harm,
                         np.array([o.wavelength_mm for o in osc]), float(e0_mm), float(r0_mm))


__all__ = ["DEFAULT_AMPLITUDES_MM", "DEFAULT_AMPLITUDE_MM", "ConicityCurve", "KinematicOscillation",
           "conicity_curve", "equilibrium", "harmonic_conicity", "kinematic_oscillation", "sampled_delta_r"]
