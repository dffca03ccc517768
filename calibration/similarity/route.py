"""Which positions the similarity master serves, and their FEM characteristic from it (units mm, MPa, s).

A position is served when its patch lies on its profile (y - b .. y + b within the profile's ends), its aspect
ratio a/b lies in the master's range and its surface convexity over the patch c = b / (2 R)
(:func:`calibration.similarity.sections.patch_convexity`) in the master's convexity range; conforming positions
(calibrated at a lower load, b/R at :data:`calibration.hertz.geometry.HERTZ_B_OVER_R_LIMIT`) are served at their
own semi-axes like the others. The others are calibrated by the direct FEM, each with the reason, or (``[run]
similarity_outside = "nearest"``, the wear loop's recalibration) served from the master's nearest point with the
reason in the entry's warnings. A served
position's characteristic is the master's at its convexity c, a/b and patch size L = sqrt(a b) (linear in c and in
log(a/b) and log L between the grid's values; a/b < 1 on a flat surface as max(a/b, b/a) by the half-space's
symmetry; L outside the master's sizes takes the nearest size's curves, pure similarity) scaled by L:
p_y = (p_y / Y)(c, r, L) Y, u_pl(q p_y) = L U(q; c, r, L), residual dents L R(c, r, L), elastic compliance
L C(c, r, L) / E, where U and R are taken at the convexity c_p over 3 b
(:func:`calibration.similarity.sections.plastic_convexity`: the plastic zone's surface; c itself for a/b < 1, whose
long axis lies across the profile). The result is an :class:`IndentationResult` as the FEM's (no mesh: n_dofs = 0),
so the fit and the tables treat both routes alike.
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass, replace

import numpy as np

from calibration.config import profile_of
from calibration.hertz.geometry import halfspace_centre_compliance_mm_per_MPa
from calibration.results import IndentationResult
from calibration.similarity.master import ASPECTS, CONVEXITIES, MasterCurves
from calibration.similarity.sections import patch_convexity, plastic_convexity
from calibration.tasks import PositionTask, code_hash, inputs_hash

#: Sources that determine a similarity result (its cache key for the fit includes their content).
SIMILARITY_SOURCES = ("calibration/similarity/*.py",)
METHOD_DIRECT, METHOD_SIMILARITY = "direct", "similarity"
#: Largest |convexity| (-) of a surface treated as flat for a patch with a/b < 1 (its long axis across the
#: profile): the master's curved sections carry the curvature along the patch's short axis only.
FLAT_CONVEXITY = 0.005


@dataclass(frozen=True)
class Route:
    """How one position is calibrated: ``method`` "similarity" or "direct", ``note`` why the direct FEM is used
    ("" when the master serves it), the position's surface convexity b / (2 R) over the patch (-) and the one the
    plastic curves are taken at (:func:`calibration.similarity.sections.plastic_convexity`; None: ``convexity``)."""

    method: str
    note: str = ""
    convexity: float = 0.0
    plastic_convexity: float | None = None


def route(task: PositionTask, master_ranges: tuple[tuple[float, float], tuple[float, float]] | None = None,
          outside: str = "direct") -> Route:
    """The route of ``task`` under ``run.method = "similarity"`` (``master_ranges``: the master's aspect and
    convexity ranges, default the full grid's). A position outside the master's domain goes to the direct FEM, or
    with ``outside = "nearest"`` is served from the master's nearest point (convexity clamped to its range), the
    reason in ``note``."""
    (lo, hi), (c_lo, c_hi) = master_ranges or ((1.0 / ASPECTS[-1], ASPECTS[-1]), (CONVEXITIES[0], CONVEXITIES[-1]))
    c, why = _shape(task, (lo, hi))
    if not why and not c_lo - 1e-9 <= c <= c_hi + 1e-9:
        why = f"surface convexity b/(2R) = {c:+.3f} over the patch outside the master's range {c_lo:+g}..{c_hi:+g}"
    if why and outside != "nearest":
        return Route(METHOD_DIRECT, why, c)
    geo = task.geometry
    wide = plastic_convexity(profile_of(task.profile), geo.y_mm, geo.b_mm) if geo.a_mm >= geo.b_mm else c
    clamp = (lambda v: min(max(v, c_lo), c_hi))  # noqa: E731
    if not why:
        return Route(METHOD_SIMILARITY, "", c, clamp(wide))
    return Route(METHOD_SIMILARITY, f"{why}; served from the master's nearest point", clamp(c), clamp(wide))


def _shape(task: PositionTask, aspect_range: tuple[float, float]) -> tuple[float, str]:
    """(surface convexity over the patch, why the master's sections do not represent the position, "" if they
    do)."""
    geo = task.geometry
    profile = profile_of(task.profile)
    c = patch_convexity(profile, geo.y_mm, geo.b_mm)
    if geo.y_mm - geo.b_mm < profile.y_min or geo.y_mm + geo.b_mm > profile.y_max:
        return c, (f"the patch y +- b = {geo.y_mm - geo.b_mm:.3g} .. {geo.y_mm + geo.b_mm:.3g} mm reaches past the "
                   f"profile's end ({profile.y_min:.4g} .. {profile.y_max:.4g} mm)")
    r = geo.a_mm / geo.b_mm
    lo, hi = aspect_range
    if not lo * (1 - 1e-9) <= r <= hi * (1 + 1e-9):
        return c, f"aspect ratio a/b = {r:.3g} outside the master's range {lo:.3g}..{hi:.3g}"
    if r < 1.0 and abs(c) > FLAT_CONVEXITY:
        return c, (f"a/b = {r:.3g} < 1 on a curved surface (convexity {c:+.3f}): the master's sections curve "
                   "along the patch's short axis only")
    return c, ""


def _weights(grid_values: list[float], x: float, log: bool = True) -> tuple[int, int, float]:
    """(i, j, t): x lies between grid_values[i] and [j], at t in [0, 1] (in log scale when ``log``; clamped at the
    ends)."""
    grid = np.log(grid_values) if log else np.asarray(grid_values, dtype=float)
    x = math.log(x) if log else float(x)
    j = int(np.clip(np.searchsorted(grid, x), 1, len(grid) - 1)) if len(grid) > 1 else 0
    i = max(j - 1, 0)
    t = 0.0 if i == j else float(np.clip((x - grid[i]) / (grid[j] - grid[i]), 0.0, 1.0))
    return i, j, t


def similar_indentation(master: MasterCurves, a_mm: float, b_mm: float, convexity: float = 0.0,
                        plastic_convexity: float | None = None) -> IndentationResult:
    """The FEM indentation of the patch a x b (mm) on a surface of convexity b / (2 R) = ``convexity`` (-) from the
    master (in the master's range): p_y and the elastic compliance at ``convexity``, the plastic curves (u_pl and the
    residual dents at the levels q p_y, dimensionless) at ``plastic_convexity`` (None: ``convexity``)."""
    t0 = time.perf_counter()
    length = math.sqrt(a_mm * b_mm)
    i, j, t = _weights(master.aspects, max(a_mm / b_mm, b_mm / a_mm))
    k, m, s = _weights(master.lengths_mm, length)
    elastic = _weights(master.convexities, convexity, log=False)
    plastic = elastic if plastic_convexity is None else _weights(master.convexities, plastic_convexity, log=False)

    def at(values, shape=elastic) -> np.ndarray:
        def plane(w):  # one convexity: bilinear in log L and log(a/b)
            by_size = [(1 - t) * np.asarray(w[n][i], dtype=float) + t * np.asarray(w[n][j], dtype=float)
                       for n in (k, m)]
            return (1 - s) * by_size[0] + s * by_size[1]
        g, h, v = shape
        return (1 - v) * plane(values[g]) + v * plane(values[h])

    mat = master.material
    p_y = float(at(master.first_yield_over_yield)) * mat.yield_MPa
    c_el = float(at(master.elastic_compliance)) * length / mat.E_MPa
    p = np.asarray(master.q) * p_y
    u_pl = at(master.u_pl_over_length, plastic) * length
    peaks = [f * p_y for f in master.unload_factors]
    residual = at(master.residual_over_length, plastic) * length
    c_hs = halfspace_centre_compliance_mm_per_MPa(a_mm, b_mm, mat.E_MPa, mat.poisson)
    return IndentationResult("3d", p.tolist(), (c_el * p + u_pl).tolist(), u_pl.tolist(), p_y, p_y, c_el, c_hs,
                             peaks, residual.tolist(), (residual - np.interp(peaks, p, u_pl)).tolist(), 0, 0, 0,
                             time.perf_counter() - t0)


def task_indentation(master: MasterCurves, task: PositionTask, convexity: float,
                     plastic_convexity: float | None = None) -> IndentationResult:
    """:func:`similar_indentation` at ``task``'s semi-axes and the surface convexities of its route."""
    return similar_indentation(master, task.geometry.a_mm, task.geometry.b_mm, convexity, plastic_convexity)


def similarity_task(task: PositionTask, master: MasterCurves, convexity: float, code: str | None = None,
                    reference=None, elastic=None, plastic_convexity: float | None = None) -> PositionTask:
    """``task`` keyed by the master, its geometry and its surface convexity instead of its own FEM inputs (the
    fit's cache key), by the direct FEM ``reference`` that anchors it
    (:class:`calibration.similarity.anchor.DirectReference`; None: not anchored) and by its section's elastic
    solution (:class:`calibration.similarity.elastic.SectionElastic`; None: none)."""
    key = inputs_hash({"similarity": master.key, "geometry": task.geometry.to_dict(), "convexity": convexity,
                       **({"plastic_convexity": plastic_convexity} if plastic_convexity is not None else {}),
                       "code": code or code_hash(SIMILARITY_SOURCES),
                       **({"anchor": asdict(reference)} if reference is not None else {}),
                       **({"section": [elastic.p_y_MPa, elastic.compliance_mm_per_MPa]} if elastic is not None
                          else {})})
    return replace(task, key=key, fields_dir=None)


__all__ = ["FLAT_CONVEXITY", "METHOD_DIRECT", "METHOD_SIMILARITY", "Route", "SIMILARITY_SOURCES", "route",
           "similar_indentation", "similarity_task", "task_indentation"]
