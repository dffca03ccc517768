"""The static indentation on the rolling block and the calibrated layer's prediction pass after pass.

Static dent: the same Hertz pressure, not moving, at mid-track x = 0 (the engine's
:class:`~calibration.fem.elastoplastic_solver.LoadPath` with :class:`~calibration.hertz.load.HertzLoad` on the
same discretisation and kept factorisation), loaded to p0 and unloaded; its residual depth relative to the far
field (:mod:`calibration.rolling.groove`).

Layer: the characteristic is fitted, as the calibration does (:mod:`calibration.position_fit`), to the loading
curve of the static indentation at the highest level: u(p) = p / S_1 + u_pl(p), u_pl = u_rel - c_el p (c_el: the
elastic compliance of the same mesh, u_rel: the centre's depth relative to the far field), first break point at
the FEM first-yield pressure p_y (paper eqs. 4-8). Under the same constant peak p0 each pass, the element's exact
(Masing) residual after load and unload from the virgin state is r = u(p0) - 2 u(p0/2) (eq. 8, u(p0) - p0/S_1,
while p0 <= 2 p_2). The two memory rules of :mod:`contact.passes.passes` then give, after pass n:
"relaxed" (a virgin element every pass) n r; "state kept" (the sliders keep their slip: reloading to the same
peak retraces the unloading branch, no new slip) r. Units mm, MPa, N/mm^3.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from calibration.fem.elastoplastic_solver import LoadPath
from calibration.fit.characteristic_fit import fit_characteristic
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


def masing_residual(characteristic, p0_MPa: float) -> float:
    """Residual (mm) of a virgin element loaded to p0 and unloaded: u(p0) - 2 u(p0/2) (Masing; = eq. 8 while
    p0 <= 2 p_2)."""
    u = characteristic.displacement(np.array([p0_MPa, 0.5 * p0_MPa]))
    return float(max(u[0] - 2.0 * u[1], 0.0))


def layer_grooves(top: StaticCurve, p_y_MPa: float, levels_MPa: list[float], n_passes: int,
                  n_segments: int) -> list[LayerGroove]:
    """The layer fitted to the highest level's static curve ``top``; its groove per level and pass."""
    fit = FitSettings(n_segments=n_segments)
    u_pl = np.where(top.p_MPa <= p_y_MPa, np.maximum(top.u_pl_mm, 0.0), top.u_pl_mm)
    curve = replace(top, u_pl_mm=u_pl)
    s1 = first_slope_N_per_mm3(curve, fit)
    res = fit_characteristic(curve.p_MPa, curve.p_MPa / s1 + u_pl, n_segments, s1_N_per_mm3=s1, p2_MPa=p_y_MPa,
                             what="rolling: static characteristic", max_relative_error=fit.max_relative_error)
    out = []
    for p0 in levels_MPa:
        r = masing_residual(res.characteristic, p0)
        out.append(LayerGroove([r * n for n in range(1, n_passes + 1)], [r] * n_passes))
    return out


__all__ = ["LayerGroove", "StaticCurve", "layer_grooves", "masing_residual", "static_curve"]
