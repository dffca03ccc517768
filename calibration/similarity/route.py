"""Which positions the similarity master serves, and their FEM characteristic from it (units mm, MPa, s).

A position is served when its contact is non-conforming (it was not moved to a lower load because b/R exceeded
:data:`calibration.hertz.geometry.HERTZ_B_OVER_R_LIMIT` at the reference load), the body's own surface over the
patch is as convex as the master's (within :data:`CONVEXITY_LIMIT`: the master is the convex 60E1 crown, nearly a
half-space) and its aspect ratio a/b lies in the master's range; the others are calibrated by the direct FEM, each with the reason. A served
position's characteristic is the master's at its a/b and patch size L = sqrt(a b) (linear in log(a/b) and log L
between the grid's values, max(a/b, b/a) by the half-space's symmetry; L outside the master's sizes takes the
nearest size's curves, pure similarity) scaled by L: p_y = (p_y / Y)(r, L) Y, u_pl(q p_y) = L U(q; r, L),
residual dents L R(r, L), elastic compliance L C(r, L) / E. The result is an :class:`IndentationResult` as the FEM's
(no mesh: n_dofs = 0), so the fit and the tables treat both routes alike.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np

from calibration.config import profile_of
from calibration.hertz.geometry import HERTZ_B_OVER_R_LIMIT, conformity, halfspace_centre_compliance_mm_per_MPa
from calibration.results import IndentationResult
from calibration.settings import CalibrationConfig
from calibration.similarity.master import ASPECTS, MASTER_PROFILE, MASTER_Y_MM, MasterCurves
from calibration.tasks import PositionTask, code_hash, inputs_hash
from meshes.profiles import get_profile

#: Sources that determine a similarity result (its cache key for the fit includes their content).
SIMILARITY_SOURCES = ("calibration/similarity/*.py",)
METHOD_DIRECT, METHOD_SIMILARITY = "direct", "similarity"
#: Largest difference between the convexity of the position's surface over the patch and that of the master's
#: surface (the 60E1 crown, lateral radius 300 mm) at the same b (-): convexity = the largest distance of the
#: surface from its tangent over y - b .. y + b, over b, positive where the surface bends away from the material
#: (a circle of radius R: b / (2 R)). The master carries the crown's convexity in its curves, so a position as
#: convex as the crown is served however curved it is, and a concave wheel tread is not (default run, against the
#: direct FEM, benchmarks/bench_similarity.py: up to 1.7 % at differences 0-0.004, 1.9-2.8 % at 0.014-0.018 (wheel
#: tread -7.5 ... 7.5 mm, concave), 1.6-2.7 % at 0.012 (rail 15, 20 mm); a bound on the sag alone served the
#: concave tread with errors of 2.75 %).
CONVEXITY_LIMIT = 0.01


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
    own = patch_convexity(profile_of(task.profile), geo.y_mm, geo.b_mm)
    master = patch_convexity(master_profile(), MASTER_Y_MM, geo.b_mm)
    if abs(own - master) > CONVEXITY_LIMIT:
        return Route(METHOD_DIRECT, f"surface convexity over y +- b {own:+.3f} b, the master's {master:+.3f} b "
                                    f"(differ by more than {CONVEXITY_LIMIT:g} b): outside the similarity")
    return Route(METHOD_SIMILARITY)


def patch_convexity(profile, y_mm: float, b_mm: float) -> float:
    """The signed largest distance of the profile from its tangent at y over y - b .. y + b (clipped to the
    profile), over b, positive where the surface bends away from the body's material (convex) (-)."""
    ys = np.clip(y_mm + np.linspace(-b_mm, b_mm, 41), profile.y_min, profile.y_max)
    dev = np.asarray(profile.z(ys)) - float(profile.z(y_mm)) - float(profile.dz(y_mm)) * (ys - y_mm)
    worst = float(dev[np.argmax(np.abs(dev))]) / b_mm
    return -worst if profile.body == "rail" else worst  # rail: material below z; wheel: above


@lru_cache(maxsize=1)
def master_profile():
    """The profile the master positions stand on."""
    return get_profile(MASTER_PROFILE)


def _weights(grid_values: list[float], x: float) -> tuple[int, int, float]:
    """(i, j, t): x lies between grid_values[i] and [j], at t in [0, 1] in log scale (clamped at the ends)."""
    x, grid = math.log(x), np.log(grid_values)
    j = int(np.clip(np.searchsorted(grid, x), 1, len(grid) - 1)) if len(grid) > 1 else 0
    i = max(j - 1, 0)
    t = 0.0 if i == j else float(np.clip((x - grid[i]) / (grid[j] - grid[i]), 0.0, 1.0))
    return i, j, t


def similar_indentation(master: MasterCurves, a_mm: float, b_mm: float) -> IndentationResult:
    """The FEM indentation of the patch a x b (mm) from the master (in the master's range)."""
    t0 = time.perf_counter()
    length = math.sqrt(a_mm * b_mm)
    i, j, t = _weights(master.aspects, max(a_mm / b_mm, b_mm / a_mm))
    k, m, s = _weights(master.lengths_mm, length)

    def at(values) -> np.ndarray:
        v = [np.asarray(values[n], dtype=float) for n in (k, m)]
        by_size = [(1 - t) * w[i] + t * w[j] for w in v]
        return (1 - s) * by_size[0] + s * by_size[1]

    mat = master.material
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


def served_config(cfg: CalibrationConfig, tasks: list[PositionTask]
                  ) -> tuple[CalibrationConfig, dict[tuple[str, float], str]]:
    """``cfg`` with only the positions of ``tasks`` (its :func:`calibration.tasks.make_tasks`) that the full master
    grid serves, and {(body, y): why the direct FEM} of the others (a body left without positions is dropped):
    a similarity run of it computes no FEM once the master exists."""
    routes = {(t.body, t.y_mm): route(t, cfg.reference_load_N) for t in tasks}
    bodies = []
    for b in cfg.bodies:
        ys = tuple(y for y in b.positions_mm if routes.get((b.body, y), Route(METHOD_DIRECT)).method
                   == METHOD_SIMILARITY)
        if ys:
            bodies.append(replace(b, positions_mm=ys))
    return replace(cfg, bodies=tuple(bodies)), {k: r.note for k, r in routes.items() if r.method == METHOD_DIRECT}


def similarity_task(task: PositionTask, master: MasterCurves, code: str | None = None) -> PositionTask:
    """``task`` keyed by the master and its geometry instead of its own FEM inputs (the fit's cache key)."""
    key = inputs_hash({"similarity": master.key, "geometry": task.geometry.to_dict(),
                       "code": code or code_hash(SIMILARITY_SOURCES)})
    return replace(task, key=key, fields_dir=None)


__all__ = ["METHOD_DIRECT", "METHOD_SIMILARITY", "Route", "CONVEXITY_LIMIT", "SIMILARITY_SOURCES", "master_profile", "patch_convexity", "route", "served_config",
           "similar_indentation", "similarity_task"]
