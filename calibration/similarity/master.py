"""The similarity master of one material: the 3D FEM indentation on a grid of patch aspect ratios, made
dimensionless (units mm, MPa).

The master positions are 3D FEM positions like any other (:class:`calibration.tasks.PositionTask`, cached by the
hash of their inputs, run by :class:`wrlayer.runner.Runner` locally or on Dask): the builtin 60E1 rail at its
crown (y = 0, lateral radius 300 mm) under given semi-axes a = L sqrt(r), b = L / sqrt(r) with L =
:data:`REFERENCE_LENGTH_MM` (b / R <= 0.01: a half-space for the patch), the long axis along the rail, for the
aspect ratios r of :data:`ASPECTS` (1..20; a patch with a/b < 1 is the same half-space problem turned by 90
degrees, so the master serves a/b in [1/20, 20]). Each result is resampled at the load path's levels as multiples
of its own first-yield pressure p_y and divided by L:

    p_y(r) / yield_MPa,   u_pl(q p_y; r) / L,   residual(f p_y; r) / L,   c_el(r) E / L

(q: the levels of :func:`calibration.indentation.load_levels` at p_y = 1 and the midpoints between them; f: the
unloading peaks). The mesh and load settings are the configuration's, so the master answers the same question as
the direct FEM.
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from calibration.hertz.geometry import given_geometry
from calibration.indentation import load_levels
from calibration.results import IndentationResult
from calibration.settings import CalibrationConfig, LoadSettings, MaterialSettings
from calibration.tasks import PositionTask, inputs_hash, position_task
from meshes.profiles import get_profile
from wrlayer import validate
from wrlayer.atomic_write import atomic_write_text
from wrlayer.errors import InputError

#: Aspect ratios a/b of the master grid (-): 11 values evenly spaced in log from 1 to 20 (step x1.35).
ASPECTS = tuple(float(20.0 ** (k / 10.0)) for k in range(11))
#: The master patch's size sqrt(a b) (mm): a = 13.4, b = 0.67 mm at a/b = 20, as the default run's elongated
#: patches (a = 9-10 mm, b = 0.7 mm at the gauge corner).
REFERENCE_LENGTH_MM = 3.0
#: Where the master positions stand: the builtin rail's crown.
MASTER_PROFILE = "60E1"
MASTER_Y_MM = 0.0


def master_tasks(cfg: CalibrationConfig, material: MaterialSettings) -> list[PositionTask]:
    """The FEM tasks of ``material``'s master, one per aspect ratio (no field output)."""
    profile = get_profile(MASTER_PROFILE)
    tasks = []
    for r in ASPECTS:
        geo = given_geometry(profile, MASTER_Y_MM, REFERENCE_LENGTH_MM * r ** 0.5, REFERENCE_LENGTH_MM / r ** 0.5)
        tasks.append(position_task(cfg, "rail", MASTER_PROFILE, geo, material))
    return tasks


def normalised_levels(load: LoadSettings) -> np.ndarray:
    """q: the load levels as multiples of p_y, from 0, with the midpoints between them (-)."""
    levels = np.array([0.0] + load_levels(1.0, load))
    mids = 0.5 * (levels[1:] + levels[:-1])
    return np.unique(np.concatenate([levels, mids]))


@dataclass(frozen=True)
class MasterCurves:
    """The master curves of one material (``OUT/similarity_master_<key>.json``).

    Attributes
    ----------
    key : str
        Hash of the master's FEM task keys (-).
    material : MaterialSettings
        The material (E_MPa, poisson, yield_MPa, H_iso_MPa, H_kin_MPa; MPa, -).
    reference_length_mm : float
        The master patch size sqrt(a b) (mm).
    aspects : list of float
        Aspect ratios a/b of the grid, ascending, from 1 (-).
    q : list of float
        Load levels p0 / p_y of the curves, from 0 (-).
    unload_factors : list of float
        Unloading peaks as multiples of p_y (-).
    first_yield_over_yield : list of float
        FEM first-yield pressure p_y over the yield stress, per aspect ratio (-).
    u_pl_over_length : list of list of float
        u_pl(q p_y) / sqrt(a b), per aspect ratio and level (-).
    residual_over_length : list of list of float
        FEM residual dent after unloading from each peak / sqrt(a b), per aspect ratio (-).
    elastic_compliance : list of float
        The FEM mesh's elastic centre compliance c_el E / sqrt(a b), per aspect ratio (-).
    fem_seconds : float
        FEM time of the master positions (s).
    """

    key: str
    material: MaterialSettings
    reference_length_mm: float
    aspects: list[float]
    q: list[float]
    unload_factors: list[float]
    first_yield_over_yield: list[float]
    u_pl_over_length: list[list[float]]
    residual_over_length: list[list[float]]
    elastic_compliance: list[float]
    fem_seconds: float

    @classmethod
    def build(cls, cfg: CalibrationConfig, material: MaterialSettings, tasks: list[PositionTask],
              results: dict[str, IndentationResult]) -> MasterCurves | None:
        """The curves from the master tasks' results, over the aspect ratios from 1 up to the first one whose
        FEM failed (None: not even a/b = 1)."""
        q = normalised_levels(cfg.load)
        rows = []
        for t in tasks:
            ind = results.get(t.key)
            if ind is None:
                break
            p_y, length = ind.first_yield_MPa, (t.geometry.a_mm * t.geometry.b_mm) ** 0.5
            rows.append((t.geometry.a_mm / t.geometry.b_mm, p_y / material.yield_MPa,
                         np.interp(q * p_y, ind.p_MPa, ind.u_pl_mm) / length,
                         np.asarray(ind.residual_fem_mm) / length,
                         ind.fem_elastic_compliance_mm_per_MPa * material.E_MPa / length, ind.seconds))
        if not rows:
            return None
        return cls(inputs_hash([t.key for t in tasks]), material, REFERENCE_LENGTH_MM, [r[0] for r in rows],
                   q.tolist(), [float(f) for f in sorted(cfg.load.unload_factors)], [r[1] for r in rows],
                   [r[2].tolist() for r in rows], [r[3].tolist() for r in rows], [r[4] for r in rows],
                   float(sum(r[5] for r in rows)))

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
        for name in ("aspects", "q", "unload_factors", "first_yield_over_yield", "elastic_compliance"):
            validate.number_list(data[name], validate.join(what, name), min_len=1 if name != "unload_factors" else 0)
        n = len(data["aspects"])
        for name in ("u_pl_over_length", "residual_over_length"):
            rows = data[name]
            if not isinstance(rows, list) or len(rows) != n:
                raise InputError(validate.join(what, name), f"must hold one list per aspect ratio ({n})")
            for i, row in enumerate(rows):
                validate.number_list(row, validate.join(what, f"{name}[{i}]"), min_len=0)
        return cls(**kw)

    def write(self, out_dir: Path) -> Path:
        """Write ``OUT/similarity_master_<key[:12]>.json`` (atomically); returns its path."""
        path = Path(out_dir) / f"similarity_master_{self.key[:12]}.json"
        atomic_write_text(path, json.dumps(self.to_dict(), indent=1) + "\n")
        return path


__all__ = ["ASPECTS", "MASTER_PROFILE", "MASTER_Y_MM", "MasterCurves", "REFERENCE_LENGTH_MM", "master_tasks",
           "normalised_levels"]
