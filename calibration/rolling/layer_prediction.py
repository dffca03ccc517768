"""The static indentation on the rolling block and the calibrated layer's prediction pass after pass.

Static dent: the same Hertz pressure, not moving, at mid-track x = 0 (the engine's
:class:`~calibration.fem.elastoplastic_solver.LoadPath` with :class:`~calibration.hertz.load.HertzLoad` on the
same discretisation and kept factorisation), loaded to p0 and unloaded; its residual depth relative to the far
field (:mod:`calibration.rolling.groove`).

Layer: the characteristic is fitted as the calibration fits it (:mod:`calibration.fit.operating_range`) to the
loading curve of the static indentation at the highest level, u(p) = p / S_1 + u_pl(p), u_pl = u_rel - c_el p (c_el:
the elastic compliance of the same mesh, u_rel: the centre's depth relative to the far field), first break point at
the FEM first-yield pressure p_y (paper eqs. 4-8), and its reverse factor to the static dents of all levels. Under
the same constant peak p0 each pass, the element's exact residual after load and unload from the virgin state is
r = u(p0) - (1 + rho) u(p0 / (1 + rho)) (eq. 8 while p0 <= (1 + rho) p_2). The two memory rules of
:mod:`contact.passes.passes` then give, after pass n: "relaxed" (a virgin element every pass) n r; "state kept"
(the sliders keep their slip: reloading to the same peak retraces the unloading branch, no new slip) r. Units mm,
MPa, N/mm^3.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from calibration.fem.elastoplastic_solver import LoadPath
from calibration.fit.operating_range import fit_operating_range
from calibration.position_fit import first_slope_N_per_mm3
from calibration.settings import FitSettings


@dataclass(frozen=True)
class StaticCurve:
    """The static indentation at one level: loading points p_MPa (MPa) and inelastic centre displacement
    u_pl_mm (mm), the residual depth after unloading dent_mm (mm) (the attribute names are those
    :func:`calibration.position_fit.first_slope_N_per_mm3` reads)."""

    p_MPa: np.ndarray
    u_pl_mm: np.ndarray
    dent_mm: float


@dataclass(frozen=True)
class LayerGroove:
    """The layer's groove after each pass under the same constant peak pressure.

    Attributes
    ----------
    relaxed : list of float
        Groove after passes 1..n with the "relaxed" memory rule (mm).
    state_kept : list of float
        Groove after passes 1..n with the "state kept" memory rule (mm).
    rolling : list of float
        Groove after passes 1..n with the "rolling" memory rule: the static residual times the rolling law
        fitted to this run's passes (mm; empty without passes).
    """

    relaxed: list[float]
    state_kept: list[float]
    rolling: list[float] = field(default_factory=list)

    def to_dict(self) -> dict:
        return {"relaxed": self.relaxed, "state_kept": self.state_kept, "rolling": self.rolling}


def static_curve(path: LoadPath, depth_at, compliance_mm_per_MPa: float) -> StaticCurve:
    """Load ``path`` (a virgin static LoadPath whose requested levels are [p0, 0], with the probe "far": the
    far-field u_z in mm) and unload it: the curve. ``depth_at(u)``: the residual depth at the centre (mm)."""
    records = list(path.levels())
    loading = records[0].increments
    p = np.array([0.0] + [h.p0_MPa for h in loading])
    u_rel = np.array([0.0] + [h.u_centre_mm + h.probes_mm["far"] for h in loading])
    return StaticCurve(p, u_rel - compliance_mm_per_MPa * p, float(depth_at(records[-1].state.u_mm)))


def layer_grooves(top: StaticCurve, p_y_MPa: float, levels_MPa: list[float], n_passes: int, max_segments: int,
                  dents_mm: list[float] | None = None,
                  dent_levels_MPa: list[float] | None = None) -> list[LayerGroove]:
    """The layer fitted, as the calibration fits (at most ``max_segments`` segments), to the highest level's
    static curve ``top`` and to the static dents ``dents_mm`` at the peaks ``dent_levels_MPa`` (default
    ``levels_MPa``; ``dents_mm`` None: ``top``'s own dent at the highest level); its groove per level of
    ``levels_MPa`` and pass."""
    fit = FitSettings(max_segments=max_segments)
    u_pl = np.where(top.p_MPa <= p_y_MPa, np.maximum(top.u_pl_mm, 0.0), top.u_pl_mm)
    curve = replace(top, u_pl_mm=u_pl)
    s1 = first_slope_N_per_mm3(curve, fit)
    if dents_mm is None:
        peaks, dents = np.array([float(np.max(top.p_MPa))]), np.array([top.dent_mm])
    else:
        at = levels_MPa if dent_levels_MPa is None else dent_levels_MPa
        order = np.argsort(at)
        peaks = np.asarray(at, dtype=float)[order]
        dents = np.asarray(dents_mm, dtype=float)[order]
    above = peaks > p_y_MPa
    res = fit_operating_range(curve.p_MPa, u_pl, s1, p_y_MPa, peaks[above], dents[above], fit.weight_range,
                              fit.target_error, fit.max_segments, fit.max_relative_error,
                              "rolling: static characteristic", error_floor=fit.error_floor)
    out = []
    for p0 in levels_MPa:
        r = float(res.characteristic.unloading_residual(p0))
        out.append(LayerGroove([r * n for n in range(1, n_passes + 1)], [r] * n_passes))
    return out


__all__ = ["LayerGroove", "StaticCurve", "layer_grooves", "static_curve"]
