"""The tangential solution of a normal solution's patches, whichever normal solver produced it (units mm, N, MPa, s).

The one entry both scene kinds use: :class:`TangentialSettings` (the scene's keys) and :func:`solve_regions`, which
dispatches to :func:`contact.tangential.method.solve_for_normal_solution` ("fastsim", "fastrip" or "exact"). The
creepages hold at one point of the solution's strip coordinate, ``origin_y_mm`` (a contact scene's origin, a
wheel–rail patch's reference point); every result's strip y and Mz refer to it, and FASTSIM takes the spin about
each patch's force centroid with the creepages moved there (:mod:`contact.tangential.spin_centre`).
"""

from __future__ import annotations

from dataclasses import dataclass

from contact.normal.kik_piotrowski import NormalSolution
from contact.tangential.fastsim import Creepage, TangentialResult
from contact.tangential.exact_rolling import RollingOptions
from contact.tangential.method import TANGENTIAL_METHODS, solve_for_normal_solution
from wrlayer.elastic import shear_modulus_MPa
from wrlayer.errors import require


@dataclass(frozen=True)
class TangentialSettings:
    """What the tangential solution needs besides the patches and the creepages.

    Attributes
    ----------
    E_MPa : float
        Young's modulus of both bodies (MPa).
    poisson : float
        Poisson's ratio of both bodies (-).
    friction : float
        Coulomb friction coefficient mu (-), > 0.
    speed_mm_s : float
        Rolling speed V (mm/s).
    cells : int
        Cells per strip of the strip methods (FASTSIM, FaStrip; the exact theory on a Kik–Piotrowski patch) (-).
    flexibility : str
        FASTSIM flexibility rule: "three", "single" or "blended" (:func:`contact.tangential.fastsim.flexibilities`).
    method : str
        The tangential method: "fastsim", "fastrip" or "exact" (:mod:`contact.tangential.method`).
    """

    E_MPa: float
    poisson: float
    friction: float
    speed_mm_s: float
    cells: int
    flexibility: str = "three"
    method: str = "fastsim"

    def __post_init__(self):
        require(self.method in TANGENTIAL_METHODS, "method.tangential",
                f"must be one of {', '.join(TANGENTIAL_METHODS)}, got {self.method!r}")
        require(self.friction > 0, "tangential.friction", f"must be > 0 for a tangential solution ({self.method}), "
                f"got {self.friction!r}")


def solve_regions(solution: NormalSolution, creepage: Creepage, settings: TangentialSettings,
                  origin_y_mm: float = 0.0, start: list[TangentialResult] | None = None,
                  rolling: RollingOptions = RollingOptions()) -> list[TangentialResult]:
    """The tangential solution of every region of ``solution`` with ``creepage`` holding at ``origin_y_mm`` (mm,
    the solution's strip coordinate); results' strip y and Mz about that point. ``start``: an earlier result to
    start the exact theory or FaStrip from (:func:`contact.tangential.method.solve_for_normal_solution`);
    ``rolling``: the exact theory's iteration options (e.g. a loose tolerance for a first estimate)."""
    return solve_for_normal_solution(solution, creepage, settings.friction,
                                     shear_modulus_MPa(settings.E_MPa, settings.poisson), settings.poisson,
                                     settings.method, settings.speed_mm_s, settings.cells, settings.flexibility,
                                     options=rolling, origin_y_mm=origin_y_mm, start=start)


__all__ = ["TangentialSettings", "solve_regions"]
