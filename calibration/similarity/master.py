"""The similarity master of one material: the 3D FEM indentation on a grid of patch aspect ratios, made
dimensionless (units mm, MPa).

The master positions are 3D FEM positions like any other (:class:`calibration.tasks.PositionTask`, cached by the
hash of their inputs, run by :class:`wrlayer.runner.Runner` locally or on Dask): the builtin 60E1 rail at its
crown (y = 0, lateral radius 300 mm) under given semi-axes a = L sqrt(r), b = L / sqrt(r), the long axis along the
rail, for the aspect ratios r of :data:`ASPECTS` (1..20; a patch with a/b < 1 is the same half-space problem
turned by 90 degrees, so the master serves a/b in [1/20, 20]) and the patch sizes L of :data:`LENGTHS_MM`. Two
sizes, because the FEM model is not exactly self-similar (its far-field element size ``mesh.h_max_mm`` and the
rail head are fixed lengths): u_pl / L at L = 6.2 mm differs by up to 2 % from that at L = 3 mm at the crown
(benchmarks/bench_similarity.py). Each result is resampled at the load path's levels as multiples of its own
first-yield pressure p_y and divided by L:

    p_y(r) / yield_MPa,   u_pl(q p_y; r) / L,   residual(f p_y; r) / L,   c_el(r) E / L

(q: the load path's points as multiples of p_y, :func:`path_levels`; f: the unloading peaks). The mesh and load
settings are the configuration's, so the master answers the same question as the direct FEM.
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from calibration.hertz.geometry import given_geometry
from calibration.results import IndentationResult
from calibration.settings import CalibrationConfig, MaterialSettings
from calibration.tasks import PositionTask, code_hash, inputs_hash, position_task
from meshes.profiles import get_profile
from wrlayer import validate
from wrlayer.atomic_write import atomic_write_text
from wrlayer.errors import InputError

#: Aspect ratios a/b of the master grid (-): 11 values evenly spaced in log from 1 to 20 (step x1.35).
ASPECTS = tuple(float(20.0 ** (k / 10.0)) for k in range(11))
#: The master patch sizes sqrt(a b) (mm), spanning the default run's patches (L = 2.9-6.2 mm at 100 kN); at L = 3 mm
#: and a/b = 20: a = 13.4, b = 0.67 mm, as the default run's elongated patches (a = 9-10 mm, b = 0.7-0.8 mm).
LENGTHS_MM = (3.0, 6.5)
#: Longest semi-axis of a master patch (mm): the grid point L = 6.5 mm, a/b = 20 (a = 29 mm, b = 1.45 mm) fails to
#: mesh ("Gmsh produced a degenerate element") and is not computed but filled from L = 3 mm, listed in
#: ``substituted`` (a failed point would be retried by every run).
MAX_SEMI_AXIS_MM = 26.0
#: Where the master positions stand: the builtin rail's crown.
MASTER_PROFILE = "60E1"
MASTER_Y_MM = 0.0


def master_tasks(cfg: CalibrationConfig, material: MaterialSettings) -> list[PositionTask]:
    """The FEM tasks of ``material``'s master, one per patch size and aspect ratio with a semi-axis of at most
    :data:`MAX_SEMI_AXIS_MM` (no field output), by size."""
    profile = get_profile(MASTER_PROFILE)
    code = code_hash()  # once: the sources' hash is part of every task's key
    tasks = []
    for length in LENGTHS_MM:
        for r in ASPECTS:
            if length * r ** 0.5 <= MAX_SEMI_AXIS_MM:
                geo = given_geometry(profile, MASTER_Y_MM, length * r ** 0.5, length / r ** 0.5)
                tasks.append(position_task(cfg, "rail", MASTER_PROFILE, geo, material, None, code))
    return tasks


def _length(t: PositionTask) -> float:
    """The patch size sqrt(a b) of a master task (mm)."""
    return round(math.sqrt(t.geometry.a_mm * t.geometry.b_mm), 9)


def _task_at(tasks: list[PositionTask], length: float, r: float) -> PositionTask | None:
    """The master task of patch size ``length`` (mm) and aspect ratio ``r`` (None: not in ``tasks``)."""
    return next((t for t in tasks if math.isclose(_length(t), length, rel_tol=1e-6)
                 and math.isclose(t.geometry.a_mm / t.geometry.b_mm, r, rel_tol=1e-6)), None)


def _row(ind: IndentationResult, length: float, q: np.ndarray, material: MaterialSettings) -> tuple:
    """(p_y / Y, u_pl(q p_y) / L, residual dents / L, c_el E / L) of one master result."""
    p_y = ind.first_yield_MPa
    return (p_y / material.yield_MPa, (np.interp(q * p_y, ind.p_MPa, ind.u_pl_mm) / length).tolist(),
            (np.asarray(ind.residual_fem_mm) / length).tolist(),
            ind.fem_elastic_compliance_mm_per_MPa * material.E_MPa / length)


def path_levels(results: list[IndentationResult]) -> np.ndarray:
    """q: the load path's points as multiples of p_y (-), those of the first result: every master position, and
    every direct position, is loaded along the same multiples of its own p_y (the levels of
    :func:`calibration.indentation.load_levels` and the solver's increments between them), so a position from the
    master carries the points its direct FEM would."""
    first = results[0]
    return np.asarray(first.p_MPa) / first.first_yield_MPa


@dataclass(frozen=True)
class MasterCurves:
    """The master curves of one material (``OUT/similarity_master_<key>.json``).

    Attributes
    ----------
    key : str
        Hash of the master's FEM task keys (-).
    material : MaterialSettings
        The material (E_MPa, poisson, yield_MPa, H_iso_MPa, H_kin_MPa; MPa, -).
    lengths_mm : list of float
        The master patch sizes sqrt(a b), ascending (mm).
    aspects : list of float
        Aspect ratios a/b of the grid, ascending, from 1 (-).
    q : list of float
        Load levels p0 / p_y of the curves, from 0 (-).
    unload_factors : list of float
        Unloading peaks as multiples of p_y (-).
    first_yield_over_yield : list of list of float
        FEM first-yield pressure p_y over the yield stress, per size and aspect ratio (-).
    u_pl_over_length : list of list of list of float
        u_pl(q p_y) / sqrt(a b), per size, aspect ratio and level (-).
    residual_over_length : list of list of list of float
        FEM residual dent after unloading from each peak / sqrt(a b), per size and aspect ratio (-).
    elastic_compliance : list of list of float
        The FEM mesh's elastic centre compliance c_el E / sqrt(a b), per size and aspect ratio (-).
    fem_seconds : float
        FEM time of the master positions (s).
    substituted : list of str
        Grid points whose FEM failed, filled from the same aspect ratio at the nearest other size.
    """

    key: str
    material: MaterialSettings
    lengths_mm: list[float]
    aspects: list[float]
    q: list[float]
    unload_factors: list[float]
    first_yield_over_yield: list[list[float]]
    u_pl_over_length: list[list[list[float]]]
    residual_over_length: list[list[list[float]]]
    elastic_compliance: list[list[float]]
    fem_seconds: float
    substituted: list[str]

    @classmethod
    def build(cls, cfg: CalibrationConfig, material: MaterialSettings, tasks: list[PositionTask],
              results: dict[str, IndentationResult]) -> MasterCurves | None:
        """The curves from the master tasks' results (as :func:`master_tasks` orders them). A grid point whose
        FEM failed takes the result of the same aspect ratio at the nearest other size (listed in
        ``substituted``); the aspect ratios end before the first one that failed at every size (None: not even
        a/b = 1)."""
        n = len(ASPECTS)
        by_size = [[_task_at(tasks, length, r) for r in ASPECTS] for length in LENGTHS_MM]  # None: not computed
        good = next((k for k in range(n) if all(ts[k] is None or ts[k].key not in results for ts in by_size)), n)
        if good == 0:
            return None
        q = path_levels([results[t.key] for t in tasks if t.key in results])
        grid, substituted, seconds = [], [], 0.0
        for s, ts in enumerate(by_size):
            rows = []
            for k, t in enumerate(ts[:good]):
                if t is None or t.key not in results:
                    t = min((other[k] for other in by_size if other[k] is not None and other[k].key in results),
                            key=lambda o: abs(math.log(_length(o) / LENGTHS_MM[s])))
                    substituted.append(f"L = {LENGTHS_MM[s]:g} mm, a/b = {ASPECTS[k]:.3g}: from L = {_length(t):g} mm")
                else:
                    seconds += results[t.key].seconds
                rows.append(_row(results[t.key], _length(t), q, material))
            grid.append(rows)
        return cls(inputs_hash([t.key for t in tasks]), material, list(LENGTHS_MM), list(ASPECTS[:good]), q.tolist(),
                   [float(f) for f in sorted(cfg.load.unload_factors)],
                   *([[r[c] for r in rows] for rows in grid] for c in range(4)), float(seconds), substituted)

    @property
    def aspect_range(self) -> tuple[float, float]:
        """The a/b range the master serves (-): [1 / largest, largest]."""
        return 1.0 / self.aspects[-1], self.aspects[-1]

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    @classmethod
    def from_dict(cls, data: Any, what: str = "master") -> MasterCurves:
        """Validate and build (InputError naming the field)."""
        validate.table(data, what)
        validate.check_known(data, list(cls.__dataclass_fields__), what)
        for name in cls.__dataclass_fields__:
            if name not in data:
                raise InputError(validate.join(what, name), "missing")
        kw = dict(data)
        kw["material"] = MaterialSettings(**validate.table(data["material"], validate.join(what, "material")))
        for name in ("aspects", "q", "unload_factors"):
            validate.number_list(data[name], validate.join(what, name), min_len=1 if name != "unload_factors" else 0)
        validate.number_list(data["lengths_mm"], validate.join(what, "lengths_mm"), min_len=1)
        shape = (len(data["lengths_mm"]), len(data["aspects"]))
        for name in ("first_yield_over_yield", "u_pl_over_length", "residual_over_length", "elastic_compliance"):
            try:
                arr = np.asarray(data[name], dtype=float)
            except (TypeError, ValueError):
                raise InputError(validate.join(what, name), "must be a regular array of numbers") from None
            if arr.shape[:2] != shape or not np.all(np.isfinite(arr)):
                raise InputError(validate.join(what, name), f"must be finite numbers per size and aspect ratio "
                                                            f"{shape}, got shape {arr.shape}")
        return cls(**kw)

    def write(self, out_dir: Path) -> Path:
        """Write ``OUT/similarity_master_<key[:12]>.json`` (atomically); returns its path."""
        path = Path(out_dir) / f"similarity_master_{self.key[:12]}.json"
        atomic_write_text(path, json.dumps(self.to_dict(), indent=1) + "\n")
        return path


__all__ = ["ASPECTS", "LENGTHS_MM", "MASTER_PROFILE", "MAX_SEMI_AXIS_MM", "MASTER_Y_MM", "MasterCurves", "master_tasks",
           "path_levels"]
