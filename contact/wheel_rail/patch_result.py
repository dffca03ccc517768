"""The result record of one loaded patch of a wheel, as written to result.json (units mm, N, MPa, s, rad;
conventions: :data:`contact.wheel_rail.result_files.CONVENTIONS`, docs/wheel-rail.md). Field names are the JSON
keys; built from a solved patch by :meth:`PatchResult.of`. Its regions, passes and layer scaling are the records
every scene kind uses (:mod:`contact.passes.record`, :class:`contact.scenes.run_result.PatchScaling`), written in
the wheel–rail keys (``*_LAYOUT``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from contact.passes.record import PATCH_PASS_LAYOUT, PATCH_REGION_LAYOUT, PassRecord, RegionRecord
from contact.scenes.run_result import PATCH_SCALING_LAYOUT, PatchScaling
from contact.wheel_rail.reference_point import weighted_centre_eta
from contact.wheel_rail.solution import PatchSolution
from wrlayer.json_io import Record

OMIT_NONE = {"omit_none": True}


@dataclass(frozen=True, kw_only=True)
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


@dataclass(frozen=True, kw_only=True)
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


@dataclass(frozen=True, kw_only=True)
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


@dataclass(frozen=True, kw_only=True)
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
    regions : tuple[RegionRecord, ...]
        The regions (strip range ``eta_min_mm``/``eta_max_mm``, p0, normal force).
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
    WT_max_N_per_mm : float | None
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
    layer_scaled_to_patch : PatchScaling | None
        The patch size the table layers were scaled to (``a_mm``, ``b_mm``, ``balances``); None when not scaled.
    strips : StripsResult
        The strips in contact and their neighbourhood.
    passes : tuple[PassRecord, ...] | None
        Every pass of the layer (``index``, approach, ..., ``max_cumulative_residual_mm``); left out without a
        layer.
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
    regions: tuple[RegionRecord, ...] = field(metadata={"layout": PATCH_REGION_LAYOUT})
    creepage_x: float
    creepage_y: float
    spin_per_mm: float
    Fx_N: float
    Fy_N: float
    Mz_Nmm: float
    WT_max_N_per_mm: float | None
    PT_max_W_per_mm2: float | None
    force_on_wheel_track_N: tuple[float, float, float]
    normal_track: tuple[float, float, float]
    lateral_track: tuple[float, float, float]
    elastic: bool
    u0_mm: float
    layer_scaled_to_patch: PatchScaling | None = field(metadata={"layout": PATCH_SCALING_LAYOUT})
    strips: StripsResult
    passes: tuple[PassRecord, ...] | None = field(default=None, metadata={**OMIT_NONE, "layout": PATCH_PASS_LAYOUT})
    load_share: float = 1.0

    @property
    def n_passes(self) -> int:
        """Passes run on the patch's layer (0 without a layer) (-)."""
        return len(self.passes or ())

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
            contact_point=ref.kind, eta_ref_mm=ref.eta_mm, y_rail_mm=ref.y_rail_mm, y_wheel_mm=ref.y_wheel_mm,
            Y_track_mm=float(p.point_track[1]), Z_track_mm=float(p.point_track[2]), X_lead_mm=float(p.point_track[0]),
            first_contact=FirstContactPoint(y_rail_mm=c.y_rail_mm, y_wheel_mm=c.y_wheel_mm, Y_track_mm=sign * c.Y_mm,
                                            Z_track_mm=c.Z_mm, X_lead_mm=c.X_mm,
                                            contact_angle_rad=c.contact_angle_rad),
            weighted_centre=_weighted_centre(p), contact_angle_rad=ref.angle_rad,
            contact_angle_deg=math.degrees(ref.angle_rad), wheel_contact_angle_rad=c.wheel_contact_angle_rad,
            wheel_radius_mm=c.wheel_radius_mm, rolling_radius_kp_mm=c.rolling_radius_kp_mm,
            normal_gap_mm=c.normal_gap_mm, normal_force_N=p.normal_force_N, delta_mm=ns.delta_mm,
            delta0_mm=ns.delta0_mm, area_mm2=ns.area_mm2, p_max_MPa=ns.p_max_MPa, length_mm=ns.length_mm,
            width_mm=ns.width_mm, n_regions=len(ns.patches),
            regions=tuple(RegionRecord(y_min_mm=float(pt.y_mm[0]), y_max_mm=float(pt.y_mm[-1]), p0_MPa=r.p0_MPa,
                                       normal_force_N=r.normal_force_N) for pt, r in zip(ns.patches, ns.regions)),
            creepage_x=p.kinematics.vx, creepage_y=p.kinematics.vy, spin_per_mm=p.kinematics.phi_per_mm,
            Fx_N=p.Fx_N, Fy_N=p.Fy_N, Mz_Nmm=p.Mz_Nmm,
            WT_max_N_per_mm=max((r.WT_max_N_per_mm for r in t), default=None),
            PT_max_W_per_mm2=max((r.PT_max_W_per_mm2 for r in t), default=None),
            force_on_wheel_track_N=tuple(p.force_track_N().tolist()), normal_track=tuple(p.normal_track.tolist()),
            lateral_track=tuple(p.lateral_track.tolist()), elastic=bool(ns.elastic), u0_mm=ns.u0_mm,
            layer_scaled_to_patch=None if p.layer_patch_mm is None else PatchScaling(
                a_mm=p.layer_patch_mm[0], b_mm=p.layer_patch_mm[1], solves=p.layer_scaling_solves),
            strips=StripsResult(**{name: tuple(v[near].tolist()) for name, v in (
                ("eta_mm", y), ("f_mm", f), ("p_peak_MPa", ns.p_peak_MPa), ("y_rail_mm", p.rail_y_of_strip),
                ("y_wheel_mm", p.wheel_y_of_strip))}),
            passes=tuple(r.projected(PATCH_PASS_LAYOUT) for r in p.passes) if p.passes else None,
            load_share=load_share)


def _weighted_centre(p: PatchSolution) -> WeightedCentrePoint:
    c = p.candidate
    eta = weighted_centre_eta(c, p.normal.delta_mm)
    return WeightedCentrePoint(eta_mm=eta, y_rail_mm=float(c.rail_coordinate(eta)),
                               y_wheel_mm=float(c.wheel_coordinate(eta)),
                               Y_track_mm=p.strip_sign * float(c.Y_mm + eta * c.lateral[1]),
                               Z_track_mm=float(c.Z_mm + eta * c.lateral[2]))


__all__ = ["FirstContactPoint", "PatchResult", "StripsResult",
           "WeightedCentrePoint"]
