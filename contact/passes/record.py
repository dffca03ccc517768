"""The one record of a pass and the one record of a contact region, for every scene kind (units mm, N, MPa, s).

:func:`contact.passes.passes.run_passes` makes a :class:`PassRecord` per pass (the normal solve's numbers, the
layer's residual displacements); a contact scene adds the tangential solution of the pass's regions
(:class:`RegionRecord`) and its timings (:func:`contact.scenes.simulation.pass_result`). result.json writes the
record in the scene kind's keys (:data:`SCENE_PASS_LAYOUT` for a contact scene's ``passes``,
:data:`PATCH_PASS_LAYOUT` for a wheel–rail patch's ``passes``, :data:`PATCH_REGION_LAYOUT` for its ``regions``;
:class:`wrlayer.json_io.Record`).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

from contact.normal.solution import NormalNumbers, NormalSolution
from wrlayer.json_io import Layout, Record

__all__ = ["PATCH_PASS_LAYOUT", "PATCH_REGION_LAYOUT", "SCENE_PASS_LAYOUT", "PassRecord", "RegionRecord"]

OMIT_NONE = {"omit_none": True}


@dataclass(frozen=True, kw_only=True)
class RegionRecord(Record):
    """One contact region (patch) of a pass: its strips, load and, with creepage, its tangential solution.

    Attributes
    ----------
    y_ref_mm : float | None
        Reference strip of the region, separation-table coordinate (mm).
    y_min_mm : float
        First strip of the region (mm; a wheel–rail patch's strip coordinate ``eta_min_mm``).
    y_max_mm : float
        Last strip of the region (mm; ``eta_max_mm``).
    length_mm : float | None
        Region length along the rolling direction (mm).
    width_mm : float | None
        Region width (mm).
    area_mm2 : float | None
        Region area (mm^2).
    p0_MPa : float
        Peak pressure at the reference strip (MPa, paper eq. 11).
    p_max_MPa : float | None
        Largest peak pressure of the region (MPa).
    normal_force_N : float
        Normal force of the region (N).
    u_layer_mm : float | None
        Layer displacement at the reference strip (mm).
    Fx_N : float
        Longitudinal creep force on body 1, the wheel (N).
    Fy_N : float
        Lateral creep force on the wheel (N).
    Mz_Nmm : float
        Spin moment about the region's origin (N mm).
    WT_max_N_per_mm : float | None
        Largest frictional work per unit area over one pass (N/mm); None without creepage.
    PT_max_W_per_mm2 : float | None
        Largest frictional power density (W/mm^2); None without creepage.
    slip_area_mm2 : float | None
        Slip area (mm^2); None without creepage.
    adhesion_area_mm2 : float | None
        Adhesion area (mm^2); None without creepage.
    equivalent_ellipse_a_mm : float | None
        FASTSIM's equivalent ellipse, semi-axis along x (mm); left out without creepage.
    equivalent_ellipse_b_mm : float | None
        FASTSIM's equivalent ellipse, lateral semi-axis (mm); left out without creepage.
    """

    y_ref_mm: float | None = None
    y_min_mm: float
    y_max_mm: float
    length_mm: float | None = None
    width_mm: float | None = None
    area_mm2: float | None = None
    p0_MPa: float
    p_max_MPa: float | None = None
    normal_force_N: float
    u_layer_mm: float | None = None
    Fx_N: float = 0.0
    Fy_N: float = 0.0
    Mz_Nmm: float = 0.0
    WT_max_N_per_mm: float | None = None
    PT_max_W_per_mm2: float | None = None
    slip_area_mm2: float | None = None
    adhesion_area_mm2: float | None = None
    equivalent_ellipse_a_mm: float | None = field(default=None, metadata=OMIT_NONE)
    equivalent_ellipse_b_mm: float | None = field(default=None, metadata=OMIT_NONE)


@dataclass(frozen=True, kw_only=True, repr=False)
class PassRecord(NormalNumbers, Record):
    """One pass (paper section 5): the normal solve, the layer's residual displacements and, in a contact scene,
    the tangential solution of its regions (the Table 1 quantities) and its timings.

    The normal solve's numbers (``delta_mm``, ``delta0_mm``, ``p_max_MPa``, ``length_mm``, ``width_mm``,
    ``area_mm2``, ``normal_force_N``, ``residual_N``, ``elastic``, ``u0_mm``, ``iterations``, ``strip_y_mm``,
    ``p_peak_MPa``; the arrays are not written) are :class:`contact.normal.solution.NormalNumbers`.

    Attributes
    ----------
    index : int
        Pass number, 1-based (-).
    u0_mm : float | None
        Layer displacement (all layers) at the reference point of the main patch under load, as the normal solve
        gives it (mm); None in a wheel–rail patch's pass read back from result.json (it keeps ``u0_elements_mm``).
    u0_elements_mm : float
        The same from loading the layer's elements to the strips' peak pressures (mm; equal up to rounding); 0
        without a layer.
    up0_mm : float
        Residual displacement added at the reference point in this pass (mm), eq. 8.
    max_residual_mm : float
        Largest residual displacement added in this pass on any strip (mm).
    shakedown : bool
        This pass added no residual displacement beyond the tolerance.
    max_cumulative_residual_mm : dict
        Per body ("wheel", "rail", "combined"): largest residual displacement accumulated so far (mm).
    dissipated_energy_N_per_mm : dict
        Per body: the largest accumulated friction work of an element (N/mm).
    Fx_N : float
        Longitudinal creep force, sum over the regions (N).
    Fy_N : float
        Lateral creep force, sum over the regions (N).
    Mz_Nmm : float
        Spin moment, sum over the regions (each about its own origin) (N mm).
    WT_max_N_per_mm : float | None
        Largest frictional work per unit area over the pass (N/mm); None without creepage.
    PT_max_W_per_mm2 : float | None
        Largest frictional power density (W/mm^2); None without creepage.
    regions : tuple[RegionRecord, ...]
        The contact regions of a contact scene's pass.
    timings_s : dict
        Wall-clock times of the pass's steps (s).
    cumulative_residual_mm : dict
        Per body: the dents so far on the strip grid (mm); not written.
    """

    index: int
    u0_elements_mm: float = 0.0
    up0_mm: float = 0.0
    max_residual_mm: float = 0.0
    shakedown: bool = False
    max_cumulative_residual_mm: dict = field(default_factory=dict)
    dissipated_energy_N_per_mm: dict = field(default_factory=dict)
    Fx_N: float = 0.0
    Fy_N: float = 0.0
    Mz_Nmm: float = 0.0
    WT_max_N_per_mm: float | None = None
    PT_max_W_per_mm2: float | None = None
    regions: tuple[RegionRecord, ...] = ()
    timings_s: dict = field(default_factory=dict)
    cumulative_residual_mm: dict = field(default_factory=dict, compare=False)

    @classmethod
    def of(cls, solution: NormalSolution, index: int, **layer) -> PassRecord:
        """The record of pass ``index`` from its normal solution (the one place its numbers are copied) and the
        layer's numbers ``layer`` (residual displacements, shakedown, ...; none for a pass without a layer)."""
        numbers = {f.name: getattr(solution, f.name) for f in dataclasses.fields(NormalNumbers)}
        return cls(index=index, **{**numbers, "iterations": dict(solution.iterations)}, **layer)

    @property
    def n_patches(self) -> int:
        """Contact regions of the pass (-)."""
        return len(self.regions)

    def __repr__(self) -> str:
        return (f"PassRecord(pass {self.index}: delta={self.delta_mm:.6g} mm, p_max={self.p_max_MPa:.6g} MPa, "
                f"Fx={self.Fx_N:.6g} N, Fy={self.Fy_N:.6g} N, u0={self.u0_mm} mm, up0={self.up0_mm:.4g} mm, "
                f"max residual={self.max_residual_mm:.4g} mm{', shakedown' if self.shakedown else ''})")


def _same(*names: str) -> Layout:
    return tuple((name, name) for name in names)


#: A contact scene's ``passes[k]`` (result.json).
SCENE_PASS_LAYOUT: Layout = (
    ("pass", "index"), *_same("length_mm", "width_mm", "area_mm2", "delta_mm", "delta0_mm", "p_max_MPa", "Fx_N",
                              "Fy_N", "Mz_Nmm", "WT_max_N_per_mm", "PT_max_W_per_mm2"),
    *_same("u0_mm", "up0_mm"), ("up_max_mm", "max_residual_mm"), *_same("elastic", "shakedown"),
    ("dissipated_energy_max_N_per_mm", "dissipated_energy_N_per_mm"),
    *_same("n_patches", "normal_force_N", "residual_N", "iterations", "timings_s"), ("patches", "regions"))

#: A wheel–rail patch's ``passes[k]`` (result.json).
PATCH_PASS_LAYOUT: Layout = (
    *_same("index", "delta_mm", "delta0_mm", "p_max_MPa", "length_mm", "width_mm", "area_mm2", "normal_force_N",
           "residual_N"), ("u0_mm", "u0_elements_mm"),
    *_same("up0_mm", "max_residual_mm", "elastic", "shakedown", "max_cumulative_residual_mm"))

#: A wheel–rail patch's ``regions[k]`` (result.json).
PATCH_REGION_LAYOUT: Layout = (("eta_min_mm", "y_min_mm"), ("eta_max_mm", "y_max_mm"),
                               *_same("p0_MPa", "normal_force_N"))
