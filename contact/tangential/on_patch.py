"""FASTSIM on the regions of a normal solution, whichever solver produced it (units mm, N, MPa, s).

Each region (patch) of the normal solution is solved in its own frame: the strip coordinate measured from a
reference strip position ``y_ref_mm`` (the point where the creepages hold; the spin and Mz refer to it). With the
exact normal solver each strip's cells carry the exact pressure along that line
(:func:`contact.normal.exact.fastsim_pressure`) and its extent (:func:`contact.normal.exact.strip_centres`), not a
semi-ellipse; with Kik–Piotrowski the semi-ellipses of the patch.
"""

from __future__ import annotations

from dataclasses import dataclass

from contact.normal.exact import fastsim_pressure, strip_centres
from contact.normal.kik_piotrowski import NormalSolution
from contact.normal.patch import Patch
from contact.tangential.fastsim import Creepage, TangentialResult, solve_tangential
from wrlayer.elastic import shear_modulus_MPa


@dataclass(frozen=True)
class FastsimSettings:
    """What FASTSIM needs besides the patch and the creepages.

    Attributes
    ----------
    E_MPa : float
        Young's modulus of both bodies (MPa).
    poisson : float
        Poisson's ratio of both bodies (-).
    friction : float
        Coulomb friction coefficient mu (-).
    speed_mm_s : float
        Rolling speed V (mm/s).
    cells : int
        FASTSIM cells per strip (-).
    flexibility : str
        FASTSIM flexibility rule: "three", "single" or "blended" (:func:`contact.tangential.fastsim.flexibilities`).
    """

    E_MPa: float
    poisson: float
    friction: float
    speed_mm_s: float
    cells: int
    flexibility: str = "three"


def local_patch(patch: Patch, y_ref_mm: float) -> Patch:
    """``patch`` with its strip coordinate measured from ``y_ref_mm`` (mm)."""
    return Patch(patch.grid_mm, patch.y_mm - y_ref_mm, patch.x_lead_mm, patch.p_peak_MPa)


def solve_region(solution: NormalSolution, index: int, patch: Patch, creepage: Creepage,
                 settings: FastsimSettings) -> TangentialResult:
    """FASTSIM on region ``index`` of ``solution``; ``patch`` is that region in the frame to solve in
    (:func:`local_patch`)."""
    pressure = centres = None
    if getattr(solution, "field", None) is not None:   # the exact solver: its pressure and each line's extent
        pressure = fastsim_pressure(solution, index, settings.cells)
        centres = strip_centres(solution, index)
    return solve_tangential(patch, creepage, shear_modulus_MPa(settings.E_MPa, settings.poisson), settings.poisson,
                            settings.friction, settings.speed_mm_s, nx=settings.cells,
                            flexibility=settings.flexibility, pressure_cells_MPa=pressure, strip_centre_mm=centres)


def solve_regions(solution: NormalSolution, creepage: Creepage, settings: FastsimSettings,
                  y_ref_mm: float = 0.0) -> list[TangentialResult]:
    """FASTSIM on every region of ``solution``, all about the same reference position ``y_ref_mm`` (mm, the
    solution's strip coordinate)."""
    return [solve_region(solution, k, p if y_ref_mm == 0.0 else local_patch(p, y_ref_mm), creepage, settings)
            for k, p in enumerate(solution.patches)]


__all__ = ["FastsimSettings", "local_patch", "solve_region", "solve_regions"]
