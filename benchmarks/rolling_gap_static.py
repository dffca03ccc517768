"""The gap's static dents under mesh refinement and the mesh-corrected rolling FEM groove (units mm, MPa).

The gap cases (:mod:`benchmarks.rolling_gap_cases`) roll on a coarse block (h = a/2 quadratic tetrahedra) whose
static dent is 11-16 % off the calibrated (mesh-converged) residual of the shipped tables. A rolling case at a
finer mesh costs 100-200 s per pass; a static indentation costs seconds. So:

1. the static dent s(h) of every gap position and level (the same virgin load path the cases use:
   :func:`calibration.rolling.run.static_dents`, load to p0 = level x p_y(h) in steps of p_y / 10 and unload) on
   the block at h = a/2, a/3, a/4, ... (:func:`static_point`), and its mesh limit s_inf (:func:`extrapolate`:
   Richardson on the three finest meshes when they are monotone and the observed order is in
   [``MIN_ORDER``, ``MAX_ORDER``], otherwise the finest value);
2. the mesh-corrected FEM groove g_n* = (g_n(a/2) / s(a/2)) s_inf (:func:`corrected_groove`), under the
   assumption that the groove over the static dent is mesh-converged (checked by direct rolling runs at h = a/4:
   docs/rolling-gap.md);
3. the half-space layer: the characteristic fitted to the finest block's static curve at the highest level with
   the calibration's default fit (:func:`benchmarks.rolling_gap.layer_static_residuals`).

``python -m benchmarks.rolling_gap_static OUT [--meshes 2 3 4 5]`` computes the study, one JSON file per
(position, mesh) written as soon as it is done (a present file is read, not recomputed).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from calibration.fem.assembly import frees_its_meshes
from calibration.rolling.config import TrackMeshSettings, TrackSettings
from benchmarks.rolling_gap_cases import (GAP_MESH, GAP_TRACK, LEVELS, GapCase, GapCaseResult, GapPosition,
                                          default_positions)
from benchmarks.rolling_gap import TARGET, GapRow, HalfspaceStatic
from calibration.rolling.layer_prediction import StaticCurve
from calibration.rolling.run import build_model, static_dents
from calibration.rolling.track_mesh import track_mesh
from wrlayer.atomic_write import atomic_write_text

#: The meshes of the study: elements per contact semi-axis (h = a / n).
MESHES = (2.0, 3.0, 4.0, 5.0)
#: Richardson extrapolation only for an observed convergence order in this range (asymptotic range, -).
MIN_ORDER = 0.5
MAX_ORDER = 4.0


@dataclass(frozen=True)
class StaticPoint:
    """The static dents of one position on one mesh (a file ``<position>_h<n>.json``).

    Attributes
    ----------
    position : str
        Name of the position.
    elements_per_semi_axis : float
        Mesh: elements per contact semi-axis, h = a / n (-).
    n_dofs : int
        Degrees of freedom of the block.
    p_y_MPa : float
        The block's FEM first-yield pressure of the static load on this mesh (MPa).
    levels : list of float
        Peak pressures over p_y (-).
    dent_mm : list of float
        Residual depth of the static indentation at each level (mm).
    top_p_MPa : list of float
        Loading points of the highest level's indentation (MPa).
    top_u_pl_mm : list of float
        Inelastic centre displacement at those points (mm).
    seconds : float
        Wall time of the model and the indentations (s).
    """

    position: str
    elements_per_semi_axis: float
    n_dofs: int
    p_y_MPa: float
    levels: list[float]
    dent_mm: list[float]
    top_p_MPa: list[float] = field(default_factory=list)
    top_u_pl_mm: list[float] = field(default_factory=list)
    seconds: float = 0.0

    @property
    def h_over_a(self) -> float:
        return 1.0 / self.elements_per_semi_axis

    def dent_at(self, level: float) -> float:
        """The static dent at ``level`` (mm)."""
        return self.dent_mm[[round(x, 9) for x in self.levels].index(round(level, 9))]

    def top_curve(self) -> StaticCurve:
        """The highest level's loading curve (its dent included)."""
        return StaticCurve(np.array(self.top_p_MPa), np.array(self.top_u_pl_mm), self.dent_mm[-1])

    def reference(self) -> HalfspaceStatic:
        """The static indentation a half-space layer is fitted to: the top curve and every level's dent."""
        return HalfspaceStatic(self.top_curve(), self.p_y_MPa, tuple(self.levels), tuple(self.dent_mm))

    def to_dict(self) -> dict:
        return {k: getattr(self, k) for k in self.__dataclass_fields__}

    @classmethod
    def from_dict(cls, data: dict) -> StaticPoint:
        return cls(**{k: data[k] for k in cls.__dataclass_fields__ if k in data})


@dataclass(frozen=True)
class Extrapolation:
    """The mesh limit of a sequence: value (the sequence's unit), observed order p (-; nan without Richardson)
    and the method ("richardson" or "finest")."""

    value: float
    order: float
    method: str


def observed_order(h: np.ndarray, f: np.ndarray) -> float:
    """The order p with (f1 - f2) / (f2 - f3) = (h1^p - h2^p) / (h2^p - h3^p) for three meshes h1 > h2 > h3
    (nan when no p in [MIN_ORDER / 2, 2 MAX_ORDER] fits)."""
    d1, d2 = f[0] - f[1], f[1] - f[2]
    if d1 == 0.0 or d2 == 0.0 or np.sign(d1) != np.sign(d2):
        return math.nan
    ratio = d1 / d2

    def gap(p: float) -> float:
        return (h[0] ** p - h[1] ** p) / (h[1] ** p - h[2] ** p) - ratio

    lo, hi = 0.5 * MIN_ORDER, 2.0 * MAX_ORDER
    if gap(lo) * gap(hi) > 0.0:
        return math.nan
    return float(brentq(gap, lo, hi, xtol=1e-10))


def extrapolate(h, values) -> Extrapolation:
    """The mesh limit of ``values`` on meshes ``h`` (any order): Richardson on the three finest when they are
    monotone with an observed order in [MIN_ORDER, MAX_ORDER], otherwise the finest value."""
    order = np.argsort(-np.asarray(h, dtype=float))
    hs = np.asarray(h, dtype=float)[order]
    fs = np.asarray(values, dtype=float)[order]
    if hs.size < 3:
        return Extrapolation(float(fs[-1]), math.nan, "finest")
    p = observed_order(hs[-3:], fs[-3:])
    if not (MIN_ORDER <= p <= MAX_ORDER):
        return Extrapolation(float(fs[-1]), p, "finest")
    h2, h3 = hs[-2] ** p, hs[-1] ** p
    return Extrapolation(float(fs[-1] + (fs[-1] - fs[-2]) * h3 / (h2 - h3)), p, "richardson")


def corrected_groove(coarse_groove_mm, coarse_static_mm: float, converged_static_mm: float) -> np.ndarray:
    """The mesh-corrected FEM groove (mm): the coarse groove over the coarse static dent (assumed mesh-converged)
    times the converged static dent."""
    return np.asarray(coarse_groove_mm, dtype=float) / coarse_static_mm * converged_static_mm


@frees_its_meshes
def static_point(position: GapPosition, elements_per_semi_axis: float, levels=LEVELS, track: TrackSettings = GAP_TRACK,
                 mesh: TrackMeshSettings = GAP_MESH) -> StaticPoint:
    """The static dents of ``position`` at ``levels`` (x p_y) on the gap's block (``track``, ``mesh``) with
    h = a / ``elements_per_semi_axis``."""
    t0 = time.perf_counter()
    cfg = GapCase(position, max(levels), 0.0, 1, elements_per_semi_axis).config(track, mesh)
    model = build_model(cfg, track_mesh(cfg.contact, cfg.track, cfg.mesh))
    curves = static_dents(model, cfg, [lv * model.p_y_MPa for lv in levels])
    return StaticPoint(position.name, float(elements_per_semi_axis), int(model.disc.n_dofs), float(model.p_y_MPa),
                       [float(x) for x in levels], [c.dent_mm for c in curves], curves[-1].p_MPa.tolist(),
                       curves[-1].u_pl_mm.tolist(), time.perf_counter() - t0)


def point_path(out_dir: Path, position: str, elements_per_semi_axis: float) -> Path:
    return Path(out_dir) / f"{position.replace(' ', '_')}_h{elements_per_semi_axis:g}.json"


def load_points(out_dir: Path) -> list[StaticPoint]:
    """The study's files in ``out_dir``."""
    return [StaticPoint.from_dict(json.loads(p.read_text())) for p in sorted(Path(out_dir).glob("*_h*.json"))]


def converged_dents(points: list[StaticPoint]) -> dict[tuple[str, float], Extrapolation]:
    """The mesh limit of the static dent per (position, level)."""
    out = {}
    for pos in sorted({p.position for p in points}):
        mine = [p for p in points if p.position == pos]
        for lv in mine[0].levels:
            out[(pos, lv)] = extrapolate([p.h_over_a for p in mine], [p.dent_at(lv) for p in mine])
    return out


def common_pressure_dents(points: list[StaticPoint]) -> dict[tuple[str, float], Extrapolation]:
    """The mesh limit per (position, level) of the inelastic displacement at a common peak p0 = level x the
    smallest p_y(h) of the meshes, relative to the finest mesh's value there (-): each mesh's highest-level loading
    curve read at p0 (equal to the residual dent after unloading from p0 within 0.2 % on these blocks). This
    removes the scatter of each mesh's own first-yield estimate p_y(h), the unit of :func:`converged_dents`, and
    estimates the finest mesh's remaining error."""
    out = {}
    for pos in sorted({p.position for p in points}):
        mine = [p for p in points if p.position == pos]
        p_ref = min(p.p_y_MPa for p in mine)
        for lv in mine[0].levels:
            u = np.array([np.interp(lv * p_ref, p.top_p_MPa, p.top_u_pl_mm) for p in mine])
            h = [p.h_over_a for p in mine]
            ext = extrapolate(h, u / u[int(np.argmin(h))])
            out[(pos, lv)] = ext
    return out


def corrected_rows(rows: list[GapRow], converged: dict[tuple[str, float], Extrapolation]) -> list[GapRow]:
    """The gap rows against the mesh-corrected FEM: FEM groove and the law on the block scaled by s_inf / s(a/2)
    (the block's static dent replaced by its mesh limit); the layer's columns unchanged. Rows without a converged
    dent are left out."""
    out = []
    for r in rows:
        ext = converged.get((r.position, r.p0_over_py))
        if ext is None:
            continue
        k = ext.value / r.static_dent_mm
        out.append(replace(r, static_dent_mm=ext.value, fem_mm=[k * g for g in r.fem_mm],
                           law_on_block_mm=[k * g for g in r.law_on_block_mm]))
    return out


@dataclass(frozen=True)
class RatioCheck:
    """The groove over the static dent of one case on the gap's mesh and on a finer one, after ``passes``.

    Attributes
    ----------
    key : str
        The case (position, traction coefficient, level).
    coarse_dofs : int
        Degrees of freedom of the gap's block.
    fine_dofs : int
        Degrees of freedom of the finer block.
    passes : list of int
        The passes compared.
    coarse_ratio : list of float
        FEM groove over the block's static dent on the gap's mesh (-).
    fine_ratio : list of float
        The same on the finer mesh (-).
    fine_groove_mm : list of float
        FEM groove on the finer mesh after ``passes`` (mm).
    """

    key: str
    coarse_dofs: int
    fine_dofs: int
    passes: list[int]
    coarse_ratio: list[float]
    fine_ratio: list[float]
    fine_groove_mm: list[float]

    def change(self) -> list[float]:
        """fine / coarse - 1 per pass (-)."""
        return [f / c - 1.0 for f, c in zip(self.fine_ratio, self.coarse_ratio)]


def ratio_checks(coarse: list[GapCaseResult], fine: list[GapCaseResult]) -> list[RatioCheck]:
    """The ratio checks of every finer case with a coarse case of the same position, level and traction (the
    passes both computed)."""
    out = []
    for f in fine:
        c = next((r for r in coarse if (r.position, r.traction, r.p0_over_py) == (f.position, f.traction,
                                                                                 f.p0_over_py)), None)
        n = min(len(f.groove_mm), len(c.groove_mm)) if c is not None else 0
        if n == 0:
            continue
        out.append(RatioCheck(c.key, c.n_dofs, f.n_dofs, list(range(1, n + 1)),
                              [g / c.static_dent_mm for g in c.groove_mm[:n]],
                              [g / f.static_dent_mm for g in f.groove_mm[:n]], list(f.groove_mm[:n])))
    return out


def within_target(rows: list[GapRow], column: str = "rolling_mm", target: float = TARGET) -> list[GapRow]:
    """The rows whose ``column`` is within ``target`` of the FEM groove at every reported pass."""
    return [r for r in rows if r.error(column) <= target]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.rolling_gap_static", description=__doc__.splitlines()[0])
    ap.add_argument("out", type=Path)
    ap.add_argument("--meshes", type=float, nargs="+", default=list(MESHES))
    ap.add_argument("--only", default="", help="only the positions whose name contains this")
    args = ap.parse_args(argv)
    from threadpoolctl import threadpool_limits  # one BLAS thread on the shared machine

    with threadpool_limits(limits=1):
        for n in args.meshes:
            for pos in default_positions():
                path = point_path(args.out, pos.name, n)
                if (args.only and args.only not in pos.name) or path.exists():
                    continue
                pt = static_point(pos, n)
                path.parent.mkdir(parents=True, exist_ok=True)
                atomic_write_text(path, json.dumps(pt.to_dict(), indent=1))
                print(f"{pos.name} h = a/{n:g}: dents {pt.dent_mm} mm ({pt.seconds:.0f} s)", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())


__all__ = ["Extrapolation", "MAX_ORDER", "MESHES", "MIN_ORDER", "RatioCheck", "StaticPoint", "common_pressure_dents",
           "converged_dents",
           "corrected_groove", "corrected_rows", "extrapolate", "load_points", "observed_order",
           "ratio_checks", "static_point", "within_target"]
