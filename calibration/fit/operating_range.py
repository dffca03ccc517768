"""The operating-range fit of a position's layer: the Prandtl element (paper eqs. 4-6) fitted to the FEM's loaded
inelastic displacement u_pl at every load level and to its residual dents, over the range of levels where wheels run
(docs/calibration-method.md, "Fit over the operating range"). Units mm, MPa, N/mm^3.

Error measures. Both u_pl and the residual vanish at first yield, so a relative error means nothing there; the error
at a level is taken relative to

    scale(p) = max(v(p), f v(1.5 p_2))        (v: the FEM's u_pl or residual)

The target's measure (the errors stored in a table and reported) has f = 1/3: 3 % of the value or 1 % of the value
at 1.5 p_2, whichever is larger, is a scaled error of 0.03. The fit itself weighs and chooses its segments with
f = ``error_floor`` (default 1/30, about v(1.1 p_2) / v(1.5 p_2) on the default positions), i.e. relative to the
value itself from about 1.1 p_2 up: with f = 1/3 the element was 15-17 % off the FEM at 1.1 p_2 and 6 % at 1.15
(within the target's measure), where most wheel contacts yield.

Loaded branch. The FEM's u_pl points are first joined by a monotone cubic (PCHIP, no overshoot) and read on a
grid of ``DENSE_STEP`` p_2 from p_2 up (:func:`densified`): a break point between two FEM levels could otherwise bend
the element away from the curve where no point checks it (measured: 7-10 % at 1.4 p_2, between the levels 1.3 and
1.5, while the element was within 2 % at the levels themselves; with the grid at 0.05 p_2 the chord between 1.1
and 1.15 p_2 was still 5 % off the cubic). The points u(p) = p / S_1 + u_pl(p) are fitted by weighted least
squares (weights 1 / scale(p) on the points inside ``weight_range`` times p_2, ``OUTSIDE_WEIGHT`` times that
outside), with p_2 pinned to the FEM first yield and S_1 fixed (as the paper's fit); the number of segments grows
from 2 until the largest scaled error over the points inside the range is at most ``target_error`` (else the best
number up to ``max_segments`` is kept). The errors stored are those at the FEM's own levels.

Unloading branch. The element's sliders slip back at -rho T_0i (:mod:`wrlayer.characteristic`); rho is the smallest
value in [1, ``MAX_REVERSE_FACTOR``] whose exact element residuals at the FEM's unloading peaks are as close to the
FEM's dents as any rho gets (within ``RHO_SLACK`` of the best error in the fit's measure). The paper's element is
rho = 1 (Masing).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import PchipInterpolator

from calibration.fit.characteristic_fit import N_SEGMENTS_RANGE, CharacteristicFit, fit_characteristic
from calibration.fit.chord_knots import chord_knots
from wrlayer.characteristic import Characteristic
from wrlayer.errors import InputError

#: Weight of the levels outside the operating range relative to those inside (-).
OUTSIDE_WEIGHT = 0.1
#: Largest reverse factor tried (-): the element then unloads elastically from up to 1 + this times p_2.
MAX_REVERSE_FACTOR = 10.0
#: Step of the reverse factors tried (-).
RHO_STEP = 0.01
#: Slack on the best residual error within which the smallest reverse factor is taken (scaled error, -).
RHO_SLACK = 1e-3
#: The reference level of the error scale (p0 / p_2, -).
SCALE_LEVEL = 1.5
#: The floor of the target's error measure, a fraction of the value at SCALE_LEVEL (-; module docstring).
TARGET_FLOOR = 1.0 / 3.0
#: Step of the grid on which the FEM's loading curve is fitted (x p_2, -).
DENSE_STEP = 0.025


def error_scale_mm(p_MPa: np.ndarray, value_mm: np.ndarray, p2_MPa: float, at_p: np.ndarray,
                   floor: float = TARGET_FLOOR) -> np.ndarray:
    """scale(p) = max(|v(p)|, floor v(1.5 p_2)) at the pressures ``at_p`` (mm), v given at ``p_MPa`` (module
    docstring; the default ``floor`` is the target's measure); v(1.5 p_2) is the value at the largest point when
    the points end below 1.5 p_2."""
    ref = float(np.interp(min(SCALE_LEVEL * p2_MPa, float(np.max(p_MPa))), p_MPa, value_mm))
    v = np.interp(at_p, p_MPa, value_mm)
    return np.maximum(np.abs(v), abs(ref) * floor)


@dataclass(frozen=True)
class OperatingRangeFit:
    """The fitted element of one position and its errors.

    Attributes
    ----------
    fit : CharacteristicFit
        The loaded branch (characteristic with its reverse factor, parameters, least-squares errors in mm).
    levels_over_p2 : tuple of float
        The FEM loading levels p0 / p_2 at and above first yield (-).
    u_pl_error : tuple of float
        (fit - FEM) u_pl at those levels over scale(p), the target's measure (-; the module docstring).
    residual_error : tuple of float
        (element - FEM) residual dent at the unloading peaks over scale(p), the target's measure (-).
    residual_fit_mm : tuple of float
        The element's exact residual dents at the unloading peaks (mm).
    """

    fit: CharacteristicFit
    levels_over_p2: tuple[float, ...]
    u_pl_error: tuple[float, ...]
    residual_error: tuple[float, ...]
    residual_fit_mm: tuple[float, ...]

    @property
    def characteristic(self) -> Characteristic:
        return self.fit.characteristic


def level_weights(p_MPa: np.ndarray, u_pl_mm: np.ndarray, p2_MPa: float,
                  weight_range: tuple[float, float], floor: float) -> np.ndarray:
    """Least-squares weight of every point: 1 / scale(p) (1/mm; the fit's ``floor``), times OUTSIDE_WEIGHT outside
    the range."""
    w = 1.0 / error_scale_mm(p_MPa, u_pl_mm, p2_MPa, p_MPa, floor)
    x = p_MPa / p2_MPa
    inside = (x >= weight_range[0] - 1e-9) & (x <= weight_range[1] + 1e-9)
    return np.where(inside | (x < 1.0), w, OUTSIDE_WEIGHT * w)


def _loaded_errors(ch: Characteristic, p: np.ndarray, u_pl: np.ndarray, s1: float, p2: float,
                   floor: float = TARGET_FLOOR) -> np.ndarray:
    """(fit - FEM) u_pl over scale(p) with ``floor`` at every point (-)."""
    fitted = ch.displacement(p) - p / s1
    return (fitted - u_pl) / error_scale_mm(p, u_pl, p2, p, floor)


def fit_loaded_branch(p: np.ndarray, u_pl: np.ndarray, s1: float, p2: float, weight_range: tuple[float, float],
                      target_error: float, max_segments: int, max_relative_error: float, what: str,
                      error_floor: float) -> CharacteristicFit:
    """The fewest segments (2..max_segments) whose largest scaled u_pl error (floor ``error_floor``) inside
    ``weight_range`` is at most ``target_error``, else the best of them; break points from
    :func:`calibration.fit.chord_knots.chord_knots` on the points from p2 up; InputError naming ``what`` when none
    fits at all."""
    u = p / s1 + u_pl
    w = level_weights(p, u_pl, p2, weight_range, error_floor)
    x = p / p2
    inside = (x >= max(1.0, weight_range[0]) - 1e-9) & (x <= weight_range[1] + 1e-9)
    above = p > p2 * (1.0 + 1e-9)
    n_max = min(max_segments, N_SEGMENTS_RANGE[1])
    # the polygon starts at p2 with u_pl = 0 (the pinned first break point; a vertex, so its weight is never used)
    knots_p = np.concatenate([[p2], p[above]])
    knots = chord_knots(knots_p, np.concatenate([[0.0], u_pl[above]]), np.concatenate([[1.0], w[above]]), n_max - 1)
    best, best_err, last_error = None, np.inf, None
    for n in range(2, n_max + 1):
        if n - 1 not in knots:
            break
        try:
            res = fit_characteristic(p, u, n, s1_N_per_mm3=s1, p2_MPa=p2, what=what,
                                     max_relative_error=max_relative_error, weights=w,
                                     breakpoints_MPa=knots_p[knots[n - 1][:-1]])
        except InputError as err:  # a degenerate placement: try more segments
            last_error = err
            continue
        err = float(np.max(np.abs(_loaded_errors(res.characteristic, p, u_pl, s1, p2, error_floor)[inside]),
                           initial=0.0))
        if err < best_err:
            best, best_err = res, err
        if err <= target_error:
            break
    if best is None:
        raise last_error if last_error is not None else InputError(what, "no characteristic fits the points")
    return best


def fitted_reverse_factor(ch: Characteristic, peaks: np.ndarray, residual_fem: np.ndarray, p2: float,
                          error_floor: float) -> float:
    """The smallest rho in [1, MAX_REVERSE_FACTOR] whose element residuals at ``peaks`` (MPa) are within RHO_SLACK
    of the best scaled error (floor ``error_floor``) against the FEM's ``residual_fem`` (mm); 1 without peaks."""
    if peaks.size == 0:
        return 1.0
    scale = error_scale_mm(peaks, residual_fem, p2, peaks, error_floor)
    rhos = np.arange(1.0, MAX_REVERSE_FACTOR + RHO_STEP / 2, RHO_STEP)
    f = 1.0 + rhos[:, None]  # Characteristic.unloading_residual for every rho at once
    residual = np.maximum(ch.displacement(peaks)[None, :] - f * ch.displacement(peaks[None, :] / f), 0.0)
    errors = np.max(np.abs(residual - residual_fem) / scale, axis=1)
    return float(rhos[int(np.argmax(errors <= errors.min() + RHO_SLACK))])


def densified(p: np.ndarray, u_pl: np.ndarray, p2: float) -> tuple[np.ndarray, np.ndarray]:
    """The FEM points (p sorted, MPa; u_pl, mm) with the monotone cubic through them read on the grid of
    ``DENSE_STEP`` p2 between p2 and the largest point (module docstring)."""
    grid = p2 * np.arange(1.0 + DENSE_STEP, p[-1] / p2, DENSE_STEP)
    new = grid[np.min(np.abs(grid[:, None] - p[None, :]), axis=1) > 1e-6 * p2]  # not on a FEM point
    if new.size == 0:
        return p, u_pl
    pd = np.concatenate([p, new])
    order = np.argsort(pd)
    return pd[order], np.concatenate([u_pl, PchipInterpolator(p, u_pl)(new)])[order]


def fit_operating_range(p_MPa, u_pl_mm, s1: float, p2: float, peaks_MPa, residual_fem_mm,
                        weight_range: tuple[float, float], target_error: float, max_segments: int,
                        max_relative_error: float, what: str, *, error_floor: float) -> OperatingRangeFit:
    """Fit the loaded branch, then the unloading branch (module docstring) of one position (MPa, mm, N/mm^3);
    ``error_floor``: f of the fit's error measure (:attr:`calibration.settings.FitSettings.error_floor`)."""
    order = np.argsort(np.asarray(p_MPa, dtype=float))
    p = np.asarray(p_MPa, dtype=float)[order]
    u_pl = np.asarray(u_pl_mm, dtype=float)[order]
    loaded = fit_loaded_branch(*densified(p, u_pl, p2), s1, p2, weight_range, target_error, max_segments,
                               max_relative_error, what, error_floor)
    ch0 = loaded.characteristic
    peaks = np.asarray(peaks_MPa, dtype=float)
    res_fem = np.asarray(residual_fem_mm, dtype=float)
    rho = fitted_reverse_factor(ch0, peaks, res_fem, p2, error_floor)
    ch = Characteristic(ch0.u_mm, ch0.p_MPa, ch0.name, rho)
    fit = CharacteristicFit(ch, ch.to_parameters(), loaded.n_segments, loaded.max_error_mm, loaded.rms_error_mm)
    above = p >= p2 * (1.0 - 1e-9)
    res_fit = ch.unloading_residual(peaks) if peaks.size else np.zeros(0)
    res_err = ((res_fit - res_fem) / error_scale_mm(peaks, res_fem, p2, peaks)) if peaks.size else np.zeros(0)
    return OperatingRangeFit(fit, tuple((p[above] / p2).tolist()),
                             tuple(_loaded_errors(ch, p, u_pl, s1, p2)[above].tolist()), tuple(res_err.tolist()),
                             tuple(np.asarray(res_fit).tolist()))


__all__ = ["DENSE_STEP", "MAX_REVERSE_FACTOR", "TARGET_FLOOR", "OperatingRangeFit", "densified", "error_scale_mm",
           "fit_loaded_branch", "fit_operating_range", "fitted_reverse_factor", "level_weights"]
