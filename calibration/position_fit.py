"""The layer characteristic of one position from its FEM indentation: the elastic slope S_1 and the Prandtl element
fit of u(p) = p / S_1 + u_pl(p) (paper eqs. 4-8; docs/calibration-method.md), by the operating-range fit
(:mod:`calibration.fit.operating_range`, the default) or the paper's fixed-N fit. Units mm, MPa, N/mm^3.
"""

from __future__ import annotations

import numpy as np

from calibration.fit.characteristic_fit import CharacteristicFit, fit_characteristic
from calibration.fit.operating_range import fit_operating_range
from calibration.hertz.geometry import LocalGeometry
from calibration.results import FemSummary, IndentationResult, PositionFit
from calibration.settings import FitSettings
from wrlayer.errors import InputError


def first_slope_N_per_mm3(ind: IndentationResult, fit: FitSettings) -> float:
    """The layer's elastic slope S_1 (N/mm^3). The FEM body is homogeneous steel whose elasticity the contact
    solver's half-space already carries, so the layer has no elastic displacement of its own (S_1 -> inf); the
    Prandtl element needs a finite S_1 (eqs. 4-6), taken so that its elastic displacement at the largest
    calibrated pressure is ``fit.elastic_tolerance`` times the FEM inelastic one there (below the FEM's accuracy):
    S_1 = p_max / (t u_pl(p_max)). With ``fit.elastic_fraction`` given, the former S_1 = 1 / (f c_hs)."""
    if fit.elastic_fraction is not None:
        return 1.0 / (fit.elastic_fraction * ind.halfspace_compliance_mm_per_MPa)
    p = np.asarray(ind.p_MPa)
    u_pl = np.asarray(ind.u_pl_mm)
    k = int(np.argmax(p))
    if not u_pl[k] > 0:
        raise InputError("fit.elastic_tolerance", f"no inelastic displacement at the largest pressure "
                                                  f"{p[k]:.6g} MPa: S_1 undefined (raise load.max_factor)")
    return float(p[k] / (fit.elastic_tolerance * u_pl[k]))


def fit_position(ind: IndentationResult, geometry: LocalGeometry, fit: FitSettings, what: str) -> PositionFit:
    """The table entry of one position: fitted characteristic, parameters, errors, geometry and raw FEM data;
    InputError naming ``what`` when no characteristic fits."""
    p = np.asarray(ind.p_MPa)
    u_pl = np.asarray(ind.u_pl_mm)
    s1 = first_slope_N_per_mm3(ind, fit)
    u = p / s1 + u_pl
    peaks = np.asarray(ind.unload_peaks_MPa)
    res_fem = np.asarray(ind.residual_fem_mm)
    extra = {}
    if fit.mode == "paper":
        res: CharacteristicFit = fit_characteristic(p, u, fit.n_segments, s1_N_per_mm3=s1,
                                                    p2_MPa=ind.first_yield_MPa, what=what,
                                                    max_relative_error=fit.max_relative_error)
        res_fit = res.characteristic.residual_displacement(peaks) if peaks.size else np.zeros(0)
    else:
        op = fit_operating_range(p, u_pl, s1, ind.first_yield_MPa, peaks, res_fem, fit.weight_range,
                                 fit.target_error, fit.max_segments, fit.max_relative_error, what,
                                 error_floor=fit.error_floor)
        res, res_fit = op.fit, np.asarray(op.residual_fit_mm)
        extra = dict(levels_over_p2=list(op.levels_over_p2), u_pl_error=list(op.u_pl_error),
                     residual_error=list(op.residual_error))
    ch = res.characteristic
    return PositionFit(
        y_mm=geometry.y_mm, characteristic=ch.to_dict(), n_segments=res.n_segments,
        k_N_per_mm3=res.parameters.k_N_per_mm3.tolist(), T0_MPa=res.parameters.T0_MPa.tolist(),
        slopes_N_per_mm3=ch.slopes.tolist(), p2_MPa=ch.elastic_limit_MPa, first_yield_fem_MPa=ind.first_yield_MPa,
        max_error_mm=res.max_error_mm, rms_error_mm=res.rms_error_mm, residual_peaks_MPa=peaks.tolist(),
        residual_fit_mm=np.asarray(res_fit).tolist(), residual_fem_mm=ind.residual_fem_mm,
        residual_error_mm=(np.asarray(res_fit) - res_fem).tolist(), geometry=geometry, fem=FemSummary.of(ind),
        fem_points={"p_MPa": p.tolist(), "u_mm": u.tolist()}, fit_mode=fit.mode,
        calibrated_max_MPa=float(np.max(p)), **extra)


__all__ = ["first_slope_N_per_mm3", "fit_position"]
