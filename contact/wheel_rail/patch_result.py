"""The result record of one loaded patch of a wheel, as written to result.json (units mm, N, MPa, s, rad;
conventions: :data:`contact.wheel_rail.result_files.CONVENTIONS`, docs/wheel-rail.md). Field names are the JSON
keys; built from a solved patch by :meth:`PatchResult.of`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from contact.passes.passes import PassRecord
from wrlayer.json_io import Record
from contact.wheel_rail.reference_point import weighted_centre_eta
from contact.wheel_rail.solution import PatchSolution

OMIT_NONE = {"omit_none": True}


@dataclass(frozen=True)
class FirstContactPoint(Record):
    """The rigid first-contact point of a patch's candidate.

    Attributes
    ----------
    y_rail_mm : float
        Rail profile coordinate (mm).
    y_wheel_mm : float
        Wheel profile coordinate (mm).
    Y_track_mm : float
        Lateral track coordinate (mm).
    Z_track_mm : float
        Vertical track coordinate (mm).
    X_lead_mm : float
        Longitudinal track coordinate (mm, lead of the contact point).
    contact_angle_rad : float
        Contact angle of the candidate (rad).
    """

    y_rail_mm: float
    y_wheel_mm: float
    Y_track_mm: float
    Z_track_mm: float
    X_lead_mm: float
    contact_angle_rad: float


@dataclass(frozen=True)
class WeightedCentrePoint(Record):
    """The depth-weighted centre of a patch's interpenetration region.

    Attributes
    ----------
    eta_mm : float
        Position along the contact plane's lateral axis from the first contact (mm).
    y_rail_mm : float
        Rail profile coordinate (mm).
    y_wheel_mm : float
        Wheel profile coordinate (mm).
    Y_track_mm : float
        Lateral track coordinate (mm).
    Z_track_mm : float
        Vertical track coordinate (mm).
    """

    eta_mm: float
    y_rail_mm: float
    y_wheel_mm: float
    Y_track_mm: float
    Z_track_mm: float


@dataclass(frozen=True)
class RegionResult(Record):
    """One contact region of a patch (paper section 4: a region of the virtual penetration).

    Attributes
    ----------
    eta_min_mm : float
        First strip of the region (mm, strip coordinate).
    eta_max_mm : float
        Last strip of the region (mm).
    p0_MPa : float
        Peak pressure at the region's reference strip (MPa, paper eq. 11).
    normal_force_N : float
        Normal force of the region (N).
    """

    eta_min_mm: float
    eta_max_mm: float
    p0_MPa: float
    normal_force_N: float


@dataclass(frozen=True)
class LayerScaling(Record):
    """The patch size the table layers were scaled to (``layers.scale_to_patch``).

    Attributes
    ----------
    a_mm : float
        Semi-axis along the rolling direction (mm).
    b_mm : float
        Lateral semi-axis (mm).
    balances : int
        Balances solved with scaled layers (-).
    """

    a_mm: float
    b_mm: float
    balances: int


@dataclass(frozen=True)
class StripsResult(Record):
    """The strips in contact and their neighbourhood (separation <= 2 delta0), track orientation.

    Attributes
    ----------
    eta_mm : tuple[float, ...]
        Strip positions from the contact point (mm).
    f_mm : tuple[float, ...]
        Separation in the contact plane, shifted to min 0 (mm).
    p_peak_MPa : tuple[float, ...]
        Peak pressure p(0, eta) (MPa).
    y_rail_mm : tuple[float, ...]
        The strips' rail profile coordinates (mm).
    y_wheel_mm : tuple[float, ...]
        The strips' wheel profile coordinates (mm).
    """

    eta_mm: tuple[float, ...]
    f_mm: tuple[float, ...]
    p_peak_MPa: tuple[float, ...]
    y_rail_mm: tuple[float, ...]
    y_wheel_mm: tuple[float, ...]

    def __repr__(self) -> str:
        return f"StripsResult({len(self.eta_mm)} strips)"


@dataclass(frozen=True)
class PassSummary(Record):
    """One pass of a patch's layer (paper section 5).

    Attributes
    ----------
    index : int
        Pass number, 1-based (-).
    delta_mm : float
        Approach of the pass (mm).
    delta0_mm : float
        Virtual penetration (mm, paper eq. 9).
    p_max_MPa : float
        Largest pressure (MPa).
    length_mm : float
        Patch length (mm).
    width_mm : float
        Patch width (mm).
    area_mm2 : float
        Patch area (mm^2).
    normal_force_N : float
        Normal force (N).
    residual_N : float
        Force residual of the normal solve (N).
    u0_mm : float
        Layer displacement at the reference point under load (mm).
    up0_mm : float
        Residual displacement at the reference point added by the pass (mm).
    max_residual_mm : float
        Largest residual displacement added by the pass (mm).
    elastic : bool
        The pass stayed elastic (-).
    shakedown : bool
        The pass added no residual beyond the tolerance (-).
    max_cumulative_residual_mm : dict
        Per layer ("rail", "wheel", "combined"): largest accumulated residual displacement (mm).
    """

    index: int
    delta_mm: float
    delta0_mm: float
    p_max_MPa: float
    length_mm: float
    width_mm: float
    area_mm2: float
    normal_force_N: float
    residual_N: float
    u0_mm: float
    up0_mm: float
    max_residual_mm: float
    elastic: bool
    shakedown: bool
    max_cumulative_residual_mm: dict

    @classmethod
    def of(cls, record: PassRecord) -> PassSummary:
        """From a :class:`contact.passes.passes.PassRecord`."""
        return cls(**record.summary(), max_cumulative_residual_mm={
            b: float(np.max(v, initial=0.0)) for b, v in record.cumulative_residual_mm.items()})


@dataclass(frozen=True)
class PatchResult(Record):
    """One loaded patch of a wheel (track-frame forces of the rail on the wheel; location conventions:
    :mod:`contact.wheel_rail.contact_search`).

    Attributes
    ----------
    contact_point : str
        The reference point: "first_contact" or "weighted_centre" (-).
    eta_ref_mm : float
        Reference point along the contact plane from the first contact (mm).
    y_rail_mm : float
        Rail profile coordinate of the reference point (mm).
    y_wheel_mm : float
        Wheel profile coordinate of the reference point (mm).
    Y_track_mm : float
        Lateral track coordinate of the reference point (mm).
    Z_track_mm : float
        Vertical track coordinate of the reference point (mm).
    X_lead_mm : float
        Longitudinal track coordinate of the reference point (mm).
    first_contact : FirstContactPoint
        The rigid first-contact point.
    weighted_centre : WeightedCentrePoint
        The depth-weighted centre of the interpenetration.
    contact_angle_rad : float
        Contact angle at the reference point (rad).
    contact_angle_deg : float
        The same in degrees (deg).
    wheel_contact_angle_rad : float
        Wheel profile slope angle at the contact (rad).
    wheel_radius_mm : float
        Rolling radius at the contact (mm).
    rolling_radius_kp_mm : float
        Kik–Piotrowski radius in the rolling direction (mm).
    normal_gap_mm : float
        Normal gap of the candidate at rigid contact (mm).
    normal_force_N : float
        Normal force (N).
    delta_mm : float
        Normal approach (mm).
    delta0_mm : float
        Virtual penetration (mm, paper eq. 9).
    area_mm2 : float
        Patch area (mm^2).
    p_max_MPa : float
        Largest pressure (MPa).
    length_mm : float
        Patch length (mm).
    width_mm : float
        Patch width (mm).
    n_regions : int
        Contact regions of the patch (-).
    regions : tuple[RegionResult, ...]
        The regions.
    creepage_x : float
        Longitudinal creepage (-).
    creepage_y : float
        Lateral creepage (-).
    spin_per_mm : float
        Spin creepage (1/mm).
    Fx_N : float
        Longitudinal creep force (N).
    Fy_N : float
        Lateral creep force, contact-plane lateral axis (N).
    Mz_Nmm : float
        Spin moment about the reference point (N mm).
    WT_max : float | None
        Largest frictional work per unit area over one pass (N/mm); None without friction.
    PT_max_W_per_mm2 : float | None
        Largest frictional power density (W/mm^2); None without friction.
    force_on_wheel_track_N : tuple[float, float, float]
        Contact force of the rail on the wheel, track frame (N).
    normal_track : tuple[float, float, float]
        Contact normal, track frame (-).
    lateral_track : tuple[float, float, float]
        Contact-plane lateral axis, track frame (-).
    elastic : bool
        The first pass stayed elastic (-).
    u0_mm : float
        Layer displacement at the reference point under load (mm).
    layer_scaled_to_patch : LayerScaling | None
        The patch size the table layers were scaled to; None when not scaled.
    strips : StripsResult
        The strips in contact and their neighbourhood.
    passes : tuple[PassSummary, ...] | None
        Every pass of the layer; left out without a layer.
    load_share : float
        The patch's share of the wheel's vertical force (-).
    """

    contact_point: str
    eta_ref_mm: float
    y_rail_mm: float
    y_wheel_mm: float
    Y_track_mm: float
    Z_track_mm: float
    X_lead_mm: float
    first_contact: FirstContactPoint
    weighted_centre: WeightedCentrePoint
    contact_angle_rad: float
    contact_angle_deg: float
    wheel_contact_angle_rad: float
    wheel_radius_mm: float
    rolling_radius_kp_mm: float
    normal_gap_mm: float
    normal_force_N: float
    delta_mm: float
    delta0_mm: float
    area_mm2: float
    p_max_MPa: float
    length_mm: float
    width_mm: float
    n_regions: int
    regions: tuple[RegionResult, ...]
    creepage_x: float
    creepage_y: float
    spin_per_mm: float
    Fx_N: float
    Fy_N: float
    Mz_Nmm: float
    WT_max: float | None
    PT_max_W_per_mm2: float | None
    force_on_wheel_track_N: tuple[float, float, float]
    normal_track: tuple[float, float, float]
    lateral_track: tuple[float, float, float]
    elastic: bool
    u0_mm: float
    layer_scaled_to_patch: LayerScaling | None
    strips: StripsResult
    passes: tuple[PassSummary, ...] | None = field(default=None, metadata=OMIT_NONE)
    load_share: float = 1.0

    def __repr__(self) -> str:
        return (f"PatchResult(y_rail={self.y_rail_mm:.4g} mm, angle={self.contact_angle_deg:.3g} deg, "
                f"N={self.normal_force_N:.6g} N, Fx={self.Fx_N:.6g} N, Fy={self.Fy_N:.6g} N, "
                f"p_max={self.p_max_MPa:.5g} MPa)")

    @classmethod
    def of(cls, p: PatchSolution, load_share: float) -> PatchResult:
        """The record of a solved patch carrying ``load_share`` of its wheel's vertical force."""
        c, ns, t, ref, sign = p.candidate, p.normal, p.tangential, p.reference, p.strip_sign
        y, f = p.problem.strip_y_mm, p.problem.separation_on_grid_mm
        near = f <= 2.0 * ns.delta0_mm  # the strips in contact and their neighbourhood
        return cls(
            ref.kind, ref.eta_mm, ref.y_rail_mm, ref.y_wheel_mm, float(p.point_track[1]), float(p.point_track[2]),
            float(p.point_track[0]),
            FirstContactPoint(c.y_rail_mm, c.y_wheel_mm, sign * c.Y_mm, c.Z_mm, c.X_mm, c.contact_angle_rad),
            _weighted_centre(p), ref.angle_rad, math.degrees(ref.angle_rad), c.wheel_contact_angle_rad,
            c.wheel_radius_mm, c.rolling_radius_kp_mm, c.normal_gap_mm, p.normal_force_N, ns.delta_mm, ns.delta0_mm,
            ns.area_mm2, ns.p_max_MPa, ns.length_mm, ns.width_mm, len(ns.patches),
            tuple(RegionResult(float(pt.y_mm[0]), float(pt.y_mm[-1]), r.p0_MPa, r.normal_force_N)
                  for pt, r in zip(ns.patches, ns.regions)),
            p.kinematics.vx, p.kinematics.vy, p.kinematics.phi_per_mm, p.Fx_N, p.Fy_N, p.Mz_Nmm,
            max((r.WT_max_N_per_mm for r in t), default=None), max((r.PT_max_W_per_mm2 for r in t), default=None),
            tuple(p.force_track_N().tolist()), tuple(p.normal_track.tolist()), tuple(p.lateral_track.tolist()),
            bool(ns.elastic), ns.u0_mm,
            None if p.layer_patch_mm is None else LayerScaling(*p.layer_patch_mm, p.layer_scaling_solves),
            StripsResult(*(tuple(v[near].tolist()) for v in (y, f, ns.p_peak_MPa, p.rail_y_of_strip,
                                                              p.wheel_y_of_strip))),
            tuple(PassSummary.of(r) for r in p.passes) if p.passes else None, load_share)


def _weighted_centre(p: PatchSolution) -> WeightedCentrePoint:
    c = p.candidate
    eta = weighted_centre_eta(c, p.normal.delta_mm)
    return WeightedCentrePoint(eta, float(c.rail_coordinate(eta)), float(c.wheel_coordinate(eta)),
                               p.strip_sign * float(c.Y_mm + eta * c.lateral[1]),
                               float(c.Z_mm + eta * c.lateral[2]))


__all__ = ["FirstContactPoint", "LayerScaling", "PassSummary", "PatchResult", "RegionResult", "StripsResult",
           "WeightedCentrePoint"]
