"""Which positions the similarity master serves, and their FEM characteristic from it (units mm, MPa, s).

A position is served when its contact is non-conforming (it was not moved to a lower load because b/R exceeded
:data:`calibration.hertz.geometry.HERTZ_B_OVER_R_LIMIT` at the reference load) and its aspect ratio a/b lies in
the master's range; the others are calibrated by the direct FEM, each with the reason. A served position's
characteristic is the master's at its a/b (linear in log(a/b) between the grid's ratios, max(a/b, b/a) by the
half-space's symmetry) scaled by its patch size L = sqrt(a b): p_y = (p_y / Y)(r) Y, u_pl(q p_y) = L U(q; r),
residual dents L R(r), elastic compliance L C(r) / E. The result is an :class:`IndentationResult` as the FEM's
(no mesh: n_dofs = 0), so the fit and the tables treat both routes alike.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace

import numpy as np

from calibration.hertz.geometry import HERTZ_B_OVER_R_LIMIT, conformity, halfspace_centre_compliance_mm_per_MPa
from calibration.results import IndentationResult
from calibration.similarity.master import ASPECTS, MasterCurves
from calibration.tasks import PositionTask, code_hash, inputs_hash

#: Sources that determine a similarity result (its cache key for the fit includes their content).
SIMILARITY_SOURCES = ("calibration/similarity/*.py",)
METHOD_DIRECT, METHOD_SIMILARITY = "direct", "similarity"


@dataclass(frozen=True)
class Route:
    """How one position is calibrated: ``method`` "similarity" or "direct", and ``note`` why the direct FEM is
    used ("" when the master serves it)."""

    method: str
    note: str = ""


def route(task: PositionTask, reference_load_N: float, aspect_range: tuple[float, float] | None = None) -> Route:
    """The route of ``task`` under ``run.method = "similarity"`` (``aspect_range``: the master's, default the
    full grid's [1/20, 20])."""
    geo = task.geometry
    lo, hi = aspect_range or (1.0 / ASPECTS[-1], ASPECTS[-1])
    if geo.reference_load_N is not None and geo.reference_load_N < reference_load_N:
        ratio = conformity(geo) * (reference_load_N / geo.reference_load_N) ** (1.0 / 3.0)
        return Route(METHOD_DIRECT, f"conforming contact (b/R = {ratio:.2f} > {HERTZ_B_OVER_R_LIMIT:g} at "
                                    f"{reference_load_N:g} N): outside the half-space similarity")
    r = geo.a_mm / geo.b_mm
    if not lo * (1 - 1e-9) <= r <= hi * (1 + 1e-9):
        return Route(METHOD_DIRECT, f"aspect ratio a/b = {r:.3g} outside the master's range {lo:.3g}..{hi:.3g}")
    return Route(METHOD_SIMILARITY)


def _weights(aspects: list[float], r: float) -> tuple[int, int, float]:
    """(i, j, t): r lies between aspects[i] and aspects[j], at t in [0, 1] in log scale."""
    x, grid = math.log(max(r, 1.0 / r)), np.log(aspects)
    j = int(np.clip(np.searchsorted(grid, x), 1, len(grid) - 1)) if len(grid) > 1 else 0
    i = max(j - 1, 0)
    t = 0.0 if i == j else float(np.clip((x - grid[i]) / (grid[j] - grid[i]), 0.0, 1.0))
    return i, j, t


def similar_indentation(master: MasterCurves, a_mm: float, b_mm: float) -> IndentationResult:
    """The FEM indentation of the patch a x b (mm) from the master (in the master's range)."""
    t0 = time.perf_counter()
    i, j, t = _weights(master.aspects, a_mm / b_mm)

    def at(values) -> np.ndarray:
        return (1 - t) * np.asarray(values[i], dtype=float) + t * np.asarray(values[j], dtype=float)

    mat = master.material
    length = math.sqrt(a_mm * b_mm)
    p_y = float(at(master.first_yield_over_yield)) * mat.yield_MPa
    c_el = float(at(master.elastic_compliance)) * length / mat.E_MPa
    p = np.asarray(master.q) * p_y
    u_pl = at(master.u_pl_over_length) * length
    peaks = [f * p_y for f in master.unload_factors]
    residual = at(master.residual_over_length) * length
    c_hs = halfspace_centre_compliance_mm_per_MPa(a_mm, b_mm, mat.E_MPa, mat.poisson)
    return IndentationResult("3d", p.tolist(), (c_el * p + u_pl).tolist(), u_pl.tolist(), p_y, p_y, c_el, c_hs,
                             peaks, residual.tolist(), (residual - np.interp(peaks, p, u_pl)).tolist(), 0, 0, 0,
                             time.perf_counter() - t0)


def similarity_task(task: PositionTask, master: MasterCurves, code: str | None = None) -> PositionTask:
    """``task`` keyed by the master and its geometry instead of its own FEM inputs (the fit's cache key)."""
    key = inputs_hash({"similarity": master.key, "geometry": task.geometry.to_dict(),
                       "code": code or code_hash(SIMILARITY_SOURCES)})
    return replace(task, key=key, fields_dir=None)


__all__ = ["METHOD_DIRECT", "METHOD_SIMILARITY", "Route", "SIMILARITY_SOURCES", "route", "similar_indentation",
           "similarity_task"]
