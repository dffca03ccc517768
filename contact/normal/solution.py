"""What a normal solve returns: one :class:`RegionSolution` per contact region and the :class:`NormalSolution`.

Both normal solvers (:mod:`contact.normal.kik_piotrowski`, :mod:`contact.normal.exact`) return these, so passes,
FASTSIM, pictures, tables and wheel-rail scenes work with either. Their ``repr`` shows the key numbers only (the
arrays stay available as attributes). Units: mm, N, MPa.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from contact.normal.patch import Patch

__all__ = ["GridPressure", "NormalNumbers", "NormalSolution", "RegionSolution"]


@dataclass(frozen=True, repr=False)
class RegionSolution:
    """One contact region of a normal solve (paper eqs. 9-13).

    Attributes
    ----------
    strips : numpy.ndarray
        Indices of the region's strips into the problem's strip grid (contiguous).
    reference : int
        Index of the reference strip (where the contact condition, eq. 13, is imposed).
    x_lead_mm : numpy.ndarray
        Leading edge x_l per strip (mm), eq. 10.
    p0_MPa : float
        Peak pressure p_0 at the reference point (MPa), eq. 11.
    I1_mm3 : float
        Integral I1 of eq. 12 (mm^3).
    I2_mm2 : float
        Boussinesq integral I2 of the region's own strips about the reference point (mm^2), eq. 13.
    u_layer_mm : float
        Layer displacement (all layers) at the reference point (mm).
    normal_force_N : float
        Normal force carried by the region (N), eq. 12.
    layer_segments : int
        Segment of the layer's loading curve p_0 lies on (1: elastic).
    approach_mm : float
        Local approach a at the reference strip, delta - f(y_ref) - interaction (mm).
    interaction_mm : float
        Elastic displacement at the reference point caused by the other regions (mm).
    """

    strips: np.ndarray
    reference: int
    x_lead_mm: np.ndarray
    p0_MPa: float
    I1_mm3: float
    I2_mm2: float
    u_layer_mm: float
    normal_force_N: float
    layer_segments: int
    approach_mm: float = float("nan")
    interaction_mm: float = 0.0

    def __repr__(self) -> str:
        return (f"RegionSolution(strips {int(self.strips[0])}..{int(self.strips[-1])}, reference={self.reference}, "
                f"p0={self.p0_MPa:.6g} MPa, N={self.normal_force_N:.6g} N, u_layer={self.u_layer_mm:.6g} mm)")


@dataclass(frozen=True, repr=False)
class GridPressure:
    """A pressure on a uniform grid of cells: x_mm (nx,) cell centres along the rolling direction, y_mm (ny,)
    line centres (the solution's strip coordinate; a line of no contact carries zeros), p_MPa (ny, nx) (mm, MPa);
    edge_power: the power of p that is linear near a contact end (2: Hertz's p^2; 1 with a layer). The coarse-grid
    solver's own grid (:mod:`contact.normal.coarse_exact`); the exact tangential theory solves its patches on this
    grid refined (:func:`contact.normal.coarse_tangential.tangential_grid`, :mod:`contact.tangential.method`)."""

    x_mm: np.ndarray
    y_mm: np.ndarray
    p_MPa: np.ndarray
    edge_power: int = 2

    def __repr__(self) -> str:
        return f"GridPressure({self.y_mm.size} lines x {self.x_mm.size} cells)"


@dataclass(frozen=True, kw_only=True, repr=False)
class NormalNumbers:
    """The numbers of a normal solve, kept by every pass record (:class:`contact.passes.record.PassRecord`).

    Attributes
    ----------
    delta_mm : float
        Approach delta of the bodies (mm), eq. 13.
    delta0_mm : float
        Virtual penetration delta_0 = alpha delta (mm), eq. 9.
    p_max_MPa : float
        Largest pressure (MPa).
    length_mm : float
        Patch length in the rolling direction, 2 max x_l (mm).
    width_mm : float
        Lateral extent of the patches (mm).
    area_mm2 : float
        Contact area (mm^2).
    normal_force_N : float
        Normal force of the solution (N).
    residual_N : float
        Force residual N - N_target (N).
    elastic : bool
        True when no layer element yields under this load.
    u0_mm : float | None
        Layer displacement (all layers) at the reference point of the main patch, the one with the largest p_0 (mm).
    iterations : dict
        Iteration counts of the solve ("delta_evaluations", ...; "loglog_slope" d log N / d log delta).
    strip_y_mm : numpy.ndarray | None
        The strip grid (mm).
    p_peak_MPa : numpy.ndarray | None
        p(0, y) on the whole strip grid (MPa), 0 outside contact.
    """

    delta_mm: float
    delta0_mm: float
    p_max_MPa: float
    length_mm: float
    width_mm: float
    area_mm2: float
    normal_force_N: float
    residual_N: float
    elastic: bool
    u0_mm: float | None = None
    iterations: dict = field(default_factory=dict)
    strip_y_mm: np.ndarray | None = field(default=None, compare=False)
    p_peak_MPa: np.ndarray | None = field(default=None, compare=False)


@dataclass(frozen=True, kw_only=True, repr=False)
class NormalSolution(NormalNumbers):
    """Result of a normal solve (:func:`contact.normal.solve_normal` or :func:`contact.normal.solve_normal_with`):
    its numbers (:class:`NormalNumbers`: approach, virtual penetration, p_max, size, force, residual, layer
    displacement u0, iterations, the strip grid and p(0, y) on it), patches and regions.

    Attributes
    ----------
    patches : list of Patch
        One discretised patch per contact region (strips, x_l, peak pressure).
    regions : list of RegionSolution
        The regions' reference points, peak pressures and forces.
    method : str
        The normal solver that produced it: "kik_piotrowski" or "exact".
    field : ExactField or None
        The exact solver's pressure grid (:class:`contact.normal.exact_field.ExactField`), None for Kik-Piotrowski.
    grid_pressure : GridPressure or None
        The coarse-grid solver's pressure on its own grid (its lines need not be strips), None for the others.
    """

    patches: list[Patch]
    regions: list[RegionSolution]
    method: str = "kik_piotrowski"
    field: object = None
    grid_pressure: GridPressure | None = dataclasses.field(default=None, compare=False)  # `field` is taken above

    def __repr__(self) -> str:
        return (f"NormalSolution({self.method}: N={self.normal_force_N:.6g} N, delta={self.delta_mm:.6g} mm, "
                f"p_max={self.p_max_MPa:.6g} MPa, length={self.length_mm:.4g} mm, width={self.width_mm:.4g} mm, "
                f"area={self.area_mm2:.4g} mm^2, u0={self.u0_mm:.4g} mm, {len(self.patches)} patch(es)"
                f"{'' if self.elastic else ', layer yields'})")
