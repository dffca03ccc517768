"""Equivalent conicity of a wheelset from its rolling-radius difference function (EN 15302; units mm, rad).

The rolling-radius difference Delta r(y) = r_right(y) - r_left(y) (mm) of a wheelset displaced laterally by y
(mm, towards the right rail) on its track is the input; it comes from the profiles, the track gauge and the rail
inclination of a scene (rigid contact, see :mod:`contact.wear.conicity`).

Harmonic linearisation (EN 15302, the describing function of Delta r for a sinusoidal lateral motion
y = y_hat sin(phi) of amplitude y_hat)::

    gamma_e(y_hat) = 1 / (2 pi y_hat) * integral_0^{2 pi} Delta r(y_hat sin phi) sin(phi) dphi

evaluated with the midpoint rule in phi, which is exact for a Delta r that is a polynomial of degree below
``2 n_phi`` and converges geometrically for a smooth one. A constant offset of Delta r (asymmetric profiles)
drops out, as it should. For a pair of cones of angle gamma, Delta r = 2 gamma y and gamma_e = gamma.

Kinematic wavelength (Klingel): a free wheelset follows y'' = -Delta r(y) / (2 e0 r0) along the track (x in mm;
e0 half the distance between the contact points, r0 the nominal rolling radius); with the oscillation's wavelength
lambda(y_hat) the equivalent conicity is gamma_e = (2 pi)^2 e0 r0 / lambda^2 (EN 15302, the definition the
linearised methods approximate). :func:`wavelength_conicity` integrates the period in closed quadrature; for a
linear Delta r both methods give gamma exactly, for a nonlinear one they differ by a few per cent, which is why a
result states its method.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from wrlayer.errors import InputError

DeltaR = Callable[[np.ndarray], np.ndarray]

#: Default amplitude (mm) at which equivalent conicity is reported (EN 15302's usual y_hat = 3 mm).
DEFAULT_AMPLITUDE_MM = 3.0
#: Points per period of the harmonic linearisation.
N_PHI = 64


def _check_amplitude(amplitude_mm: float) -> None:
    if not (np.isfinite(amplitude_mm) and amplitude_mm > 0.0):
        raise InputError("conicity amplitude_mm", f"must be a positive number of mm, got {amplitude_mm!r}")


def harmonic_conicity(delta_r: DeltaR, amplitude_mm: float = DEFAULT_AMPLITUDE_MM, n_phi: int = N_PHI) -> float:
    """Equivalent conicity (rad, small-angle: tan gamma_e = gamma_e) by harmonic linearisation of ``delta_r``.

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


def wavelength_conicity(delta_r: DeltaR, amplitude_mm: float, e0_mm: float, r0_mm: float,
                        n_theta: int = 200) -> tuple[float, float]:
    """Equivalent conicity (rad) and kinematic wavelength (mm) from the free wheelset's oscillation (Klingel).

    The half-periods on both sides of y = 0 are integrated separately (an asymmetric Delta r gives different
    excursions); each uses the substitution y = y_max sin(theta), which removes the turning point's square-root
    singularity. The oscillation is taken with positive excursion ``amplitude_mm``; the negative excursion follows
    from energy conservation.
    """
    _check_amplitude(amplitude_mm)
    k = 1.0 / (2.0 * e0_mm * r0_mm)

    def potential(y: np.ndarray) -> np.ndarray:
        # V(y) = k * integral_0^y Delta r, by Gauss-Legendre on [0, y] (vectorised over y).
        t, w = np.polynomial.legendre.leggauss(24)
        pts = 0.5 * (t[None, :] + 1.0) * y[:, None]
        return k * 0.5 * y * (delta_r(pts.ravel()).reshape(pts.shape) @ w)

    offset = float(delta_r(np.zeros(1))[0])
    if abs(offset) > 0.0:  # oscillation about the equilibrium y0 where Delta r(y0) = 0
        raise InputError("conicity delta_r_mm", f"Delta r(0) = {offset:g} mm; the wavelength method needs a "
                                                "centred Delta r (use harmonic_conicity)")
    energy = float(potential(np.array([amplitude_mm]))[0])
    if energy <= 0.0:
        raise InputError("conicity delta_r_mm", "Delta r does not restore the wheelset (no oscillation)")
    # negative turning point: V(y_neg) = energy, found by bisection on [-4 y_hat, 0]
    lo, hi = -4.0 * amplitude_mm, 0.0
    if float(potential(np.array([lo]))[0]) < energy:
        raise InputError("conicity delta_r_mm", "no turning point within 4 amplitudes on the negative side")
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if float(potential(np.array([mid]))[0]) > energy else (lo, mid)
    y_neg = 0.5 * (lo + hi)
    theta = (np.arange(n_theta) + 0.5) * (0.5 * np.pi / n_theta)
    half = 0.0
    for y_max in (amplitude_mm, y_neg):
        y = y_max * np.sin(theta)
        gap = np.maximum(energy - potential(y), 1e-300)
        half += float(np.sum(abs(y_max) * np.cos(theta) / np.sqrt(2.0 * gap)) * (0.5 * np.pi / n_theta))
    wavelength = 2.0 * half
    return (2.0 * np.pi) ** 2 * e0_mm * r0_mm / wavelength ** 2, wavelength


def sampled_delta_r(y_mm: np.ndarray, delta_r_mm: np.ndarray) -> DeltaR:
    """Delta r as a function, linear between samples (y strictly increasing); outside them an InputError."""
    y_mm = np.asarray(y_mm, dtype=float)
    delta_r_mm = np.asarray(delta_r_mm, dtype=float)
    if y_mm.ndim != 1 or y_mm.shape != delta_r_mm.shape or y_mm.size < 2 or np.any(np.diff(y_mm) <= 0.0):
        raise InputError("conicity delta_r_mm", "needs at least two samples at strictly increasing y")

    def delta_r(y: np.ndarray) -> np.ndarray:
        y = np.asarray(y, dtype=float)
        if y.size and (y.min() < y_mm[0] - 1e-12 or y.max() > y_mm[-1] + 1e-12):
            raise InputError("conicity amplitude_mm", f"Delta r is known on {y_mm[0]:g}..{y_mm[-1]:g} mm only")
        return np.interp(y, y_mm, delta_r_mm)

    return delta_r


__all__ = ["DEFAULT_AMPLITUDE_MM", "harmonic_conicity", "sampled_delta_r", "wavelength_conicity"]
