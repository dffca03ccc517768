"""The result records of a Kik–Piotrowski scene run, as written to result.json (units mm, N, MPa, s; units of
every field: :data:`contact.scenes.result_io.UNITS`). Field names are the JSON keys (``pass`` is written from
:attr:`PassResult.number`); converted to JSON only when written (:class:`contact.scenes.result_io.Record`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from wrlayer.json_io import Record

OMIT_NONE = {"omit_none": True}


@dataclass(frozen=True)
class RegionResult(Record):
    """One contact region (patch) of a pass, in its own frame (origin at the reference strip ``y_ref_mm``).

    Attributes
    ----------
    y_ref_mm : float
        Reference strip of the region, separation-table coordinate (mm).
    y_min_mm : float
        First strip of the region (mm).
    y_max_mm : float
        Last strip of the region (mm).
    length_mm : float
        Region length along the rolling direction (mm).
    width_mm : float
        Region width (mm).
    area_mm2 : float
        Region area (mm^2).
    p0_MPa : float
        Peak pressure at the reference strip (MPa, paper eq. 11).
    p_max_MPa : float
        Largest peak pressure of the region (MPa).
    normal_force_N : float
        Normal force of the region (N).
    u_layer_mm : float
        Layer displacement at the reference strip (mm).
    Fx_N : float
        Longitudinal creep force on body 1, the wheel (N).
    Fy_N : float
        Lateral creep force on the wheel (N).
    Mz_Nmm : float
        Spin moment about the region's origin (N mm).
    WT_max : float | None
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

    y_ref_mm: float
    y_min_mm: float
    y_max_mm: float
    length_mm: float
    width_mm: float
    area_mm2: float
    p0_MPa: float
    p_max_MPa: float
    normal_force_N: float
    u_layer_mm: float
    Fx_N: float = 0.0
    Fy_N: float = 0.0
    Mz_Nmm: float = 0.0
    WT_max: float | None = None
    PT_max_W_per_mm2: float | None = None
    slip_area_mm2: float | None = None
    adhesion_area_mm2: float | None = None
    equivalent_ellipse_a_mm: float | None = field(default=None, metadata=OMIT_NONE)
    equivalent_ellipse_b_mm: float | None = field(default=None, metadata=OMIT_NONE)


@dataclass(frozen=True)
class PassResult(Record):
    """One pass (paper section 5; the Table 1 quantities, layer numbers and solver statistics).

    Attributes
    ----------
    number : int
        Pass number, 1-based (-); written as ``pass``.
    length_mm : float
        Patch length (mm).
    width_mm : float
        Patch width (mm).
    area_mm2 : float
        Contact area (mm^2).
    delta_mm : float
        Approach (mm).
    delta0_mm : float
        Virtual penetration (mm, paper eq. 9).
    p_max_MPa : float
        Largest pressure (MPa).
    Fx_N : float
        Longitudinal creep force, sum over the regions (N).
    Fy_N : float
        Lateral creep force, sum over the regions (N).
    Mz_Nmm : float
        Spin moment, sum over the regions (each about its own origin) (N mm).
    WT_max : float | None
        Largest frictional work per unit area over the pass (N/mm); None without creepage.
    PT_max_W_per_mm2 : float | None
        Largest frictional power density (W/mm^2); None without creepage.
    u0_mm : float
        Layer displacement at the reference point under load (mm).
    up0_mm : float
        Residual displacement at the reference point added by the pass (mm).
    up_max_mm : float
        Largest residual displacement added by the pass (mm).
    elastic : bool
        The pass stayed elastic (-).
    shakedown : bool
        The pass added no residual beyond ``passes.tolerance_mm`` (-).
    dissipated_energy_max_N_per_mm : dict
        Per layer: largest accumulated slider friction work of an element (N/mm).
    n_patches : int
        Contact regions (-).
    normal_force_N : float
        Normal force (N).
    residual_N : float
        Force residual of the normal solve (N).
    iterations : dict
        Solver statistics (counts, -).
    timings_s : dict
        Wall-clock times of the pass's steps (s).
    patches : tuple[RegionResult, ...]
        The regions.
    """

    number: int = field(metadata={"key": "pass"})
    length_mm: float
    width_mm: float
    area_mm2: float
    delta_mm: float
    delta0_mm: float
    p_max_MPa: float
    Fx_N: float
    Fy_N: float
    Mz_Nmm: float
    WT_max: float | None
    PT_max_W_per_mm2: float | None
    u0_mm: float
    up0_mm: float
    up_max_mm: float
    elastic: bool
    shakedown: bool
    dissipated_energy_max_N_per_mm: dict
    n_patches: int
    normal_force_N: float
    residual_N: float
    iterations: dict
    timings_s: dict
    patches: tuple[RegionResult, ...]

    def __repr__(self) -> str:
        return (f"PassResult({self.number}: delta={self.delta_mm:.6g} mm, p_max={self.p_max_MPa:.5g} MPa, "
                f"Fx={self.Fx_N:.6g} N, Fy={self.Fy_N:.6g} N, up0={self.up0_mm:.3g} mm, shakedown={self.shakedown})")


@dataclass(frozen=True)
class MethodDescription(Record):
    """The methods a run used, in words.

    Attributes
    ----------
    normal : str
        The normal solver.
    tangential : str | None
        The tangential solver; None without creepage.
    layer : tuple[str, ...] | None
        The layers ("combined", "rail", "wheel"); None without a layer.
    """

    normal: str
    tangential: str | None
    layer: tuple[str, ...] | None


@dataclass(frozen=True)
class PatchScaling(Record):
    """The patch size the table layers were scaled to (``scale_to_patch``).

    Attributes
    ----------
    a_mm : float
        Semi-axis along the rolling direction (mm).
    b_mm : float
        Lateral semi-axis (mm).
    solves : int
        Normal solves of the fixed point, the unscaled first one included (-).
    """

    a_mm: float
    b_mm: float
    solves: int


@dataclass(frozen=True)
class StripGrid(Record):
    """The fixed strip grid of the run and the separation on it.

    Attributes
    ----------
    y_mm : tuple[float, ...]
        Strip positions (mm).
    separation_before_mm : tuple[float, ...]
        Separation before the first pass, shifted to min 0 (mm).
    separation_after_mm : tuple[float, ...]
        Separation after the last pass's dents (mm).
    residual_mm : dict[str, tuple[float, ...]]
        Per layer ("wheel", "rail", "combined"): cumulative residual displacement after the last pass (mm).
    """

    y_mm: tuple[float, ...]
    separation_before_mm: tuple[float, ...]
    separation_after_mm: tuple[float, ...]
    residual_mm: dict[str, tuple[float, ...]]

    def __repr__(self) -> str:
        return f"StripGrid({len(self.y_mm)} strips, layers {sorted(self.residual_mm)})"


@dataclass(frozen=True)
class SolverStats(Record):
    """Run statistics.

    Attributes
    ----------
    total_s : float
        Wall-clock time of the run (s).
    delta_evaluations : int
        Approach evaluations of the normal solver over all passes (-).
    """

    total_s: float
    delta_evaluations: int


@dataclass(frozen=True)
class SceneResult(Record):
    """The result of a Kik–Piotrowski scene (result.json).

    Attributes
    ----------
    inputs : dict
        The resolved inputs (:func:`contact.scenes.scene.scene_inputs`).
    code_version : Any
        Version of the code that ran.
    units : dict
        Units of the result fields.
    method : MethodDescription
        The methods used.
    layer_scaled_to_patch : PatchScaling | None
        The patch size the table layers were scaled to; None when not scaled.
    n_passes : int
        Passes run (-).
    shakedown_pass : int | None
        First pass that added no residual beyond the tolerance (-); None when none did or without a layer.
    passes : tuple[PassResult, ...]
        Every pass.
    reference_deviation : dict
        Relative deviation (value - reference) / |reference| of the last pass from the scene's [reference] (-).
    strip_grid : StripGrid
        The strip grid and the separation on it.
    solver : SolverStats
        Run statistics.
    frictional_outputs : tuple[str, ...] | None
        The wear-ready frictional CSV files written (by the command line).
    pictures : tuple[str, ...] | None
        The pictures written (with ``--plots``).
    """

    inputs: dict
    code_version: Any
    units: dict
    method: MethodDescription
    layer_scaled_to_patch: PatchScaling | None
    n_passes: int
    shakedown_pass: int | None
    passes: tuple[PassResult, ...]
    reference_deviation: dict
    strip_grid: StripGrid
    solver: SolverStats
    frictional_outputs: tuple[str, ...] | None = field(default=None, metadata=OMIT_NONE)
    pictures: tuple[str, ...] | None = field(default=None, metadata=OMIT_NONE)

    def __repr__(self) -> str:
        last = self.passes[-1]
        return (f"SceneResult({self.n_passes} passes, shakedown_pass={self.shakedown_pass}, last: "
                f"delta={last.delta_mm:.6g} mm, p_max={last.p_max_MPa:.5g} MPa)")


def reference_deviation(reference: dict[str, Any], last: PassResult) -> dict[str, float]:
    """Relative deviation (value - reference) / |reference| of the last pass from the scene's [reference] numbers
    (and ``passes``: the pass count); empty without a reference."""
    values = last.to_dict()
    out = {}
    for key, ref in reference.items():
        value = last.number if key == "passes" else values.get(key)
        if isinstance(ref, float) and ref != 0.0 and value is not None:
            out[key] = (float(value) - ref) / abs(ref)
    return out


__all__ = ["MethodDescription", "PassResult", "PatchScaling", "RegionResult", "SceneResult", "SolverStats",
           "StripGrid", "reference_deviation"]
