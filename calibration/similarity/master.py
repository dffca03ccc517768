"""The similarity master of one material: the 3D FEM indentation on a grid of surface shapes, patch aspect ratios
and patch sizes, made dimensionless (units mm, MPa).

The master positions are 3D FEM positions like any other (:class:`calibration.tasks.PositionTask`, cached by the
hash of their inputs, run by :class:`wrlayer.runner.Runner` locally or on Dask): each stands at y = 0 of a synthetic
rail block whose surface is a circular arc of convexity c = b / (2 R) (:func:`calibration.similarity.sections.
arc_section`: concave c < 0, flat c = 0, convex c > 0) under given semi-axes a = L sqrt(r), b = L / sqrt(r), the long
axis along the rail, for the convexities of :data:`CONVEXITIES`, the aspect ratios r of :data:`ASPECTS` (1..20; a
patch with a/b < 1 is the same problem turned by 90 degrees) and the patch sizes L of :data:`LENGTHS_MM`. Two sizes,
because the FEM model is not exactly self-similar (its far-field element size ``mesh.h_max_mm`` and the block are
fixed lengths). Each result is resampled at the load path's points as multiples of its own first-yield pressure p_y
and divided by L:

    p_y(c, L, r) / yield_MPa,   u_pl(q p_y) / L,   residual(f p_y) / L,   c_el E / L

(q: the load path's points as multiples of p_y, :func:`path_levels`; f: the unloading peaks). The mesh and load
settings are the configuration's, so the master answers the same question as the direct FEM. The JSON form carries
:data:`FORMAT_VERSION`; a file of another version is refused (:class:`MasterFormatError`) and the master rebuilt
from its FEM positions.
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
from calibration.similarity.sections import arc_section
from calibration.tasks import PositionTask, code_hash, inputs_hash, position_task
from wrlayer import validate
from wrlayer.atomic_write import atomic_write_text
from wrlayer.errors import InputError

#: Version of the master's JSON form: 1 (no field) the 60E1-crown master over (size, aspect); 2 the synthetic-arc
#: master over (convexity, size, aspect).
FORMAT_VERSION = 2
#: Surface convexities c = b / (2 R) of the master's sections (-), concave to convex: the default run's positions
#: lie in -0.10 (flange root) .. +0.10 (gauge corner; conforming positions are calibrated at b/R = 0.2), the crown
#: at +0.009, the tread at -0.008 .. +0.004.
CONVEXITIES = (-0.12, -0.05, 0.0, 0.05, 0.12)
#: Aspect ratios a/b of the master grid (-): 6 values evenly spaced in log from 1 to 20 (step x1.82).
ASPECTS = tuple(float(20.0 ** (k / 5.0)) for k in range(6))
#: The curved sections (c != 0) are computed at these aspect ratios (-) and :data:`SHAPE_LENGTH_MM` only; the grid's
#: other curved points are the flat section's value plus the shape's difference at SHAPE_LENGTH_MM (interpolated
#: in log a/b, constant beyond): the FEM count of the master is 11 flat + 4 x 4 curved points instead of 55. a/b = 6
#: took the flange root at y = -30 mm (a/b 5.8) from 2.32 % to 1.91 % of the direct FEM, and no position moved by
#: more than 0.1 % the other way (``benchmarks/bench_similarity_arc.py``: the master against an arc block's own FEM).
SHAPE_ASPECTS = (ASPECTS[0], ASPECTS[2], ASPECTS[3], ASPECTS[4])
#: The master patch sizes sqrt(a b) (mm), spanning the default run's patches (L = 2.9-6.2 mm at 100 kN); at L = 3 mm
#: and a/b = 20: a = 13.4, b = 0.67 mm, as the default run's elongated patches (a = 9-10 mm, b = 0.7-1.0 mm).
LENGTHS_MM = (3.0, 6.5)
#: The patch size of the curved sections (mm).
SHAPE_LENGTH_MM = LENGTHS_MM[0]
#: Longest semi-axis of a master patch (mm): the grid point L = 6.5 mm, a/b = 20 (a = 29 mm, b = 1.45 mm) fails to
#: mesh ("Gmsh produced a degenerate element") and is not computed but filled from L = 3 mm, listed in
#: ``substituted`` (a failed point would be retried by every run).
MAX_SEMI_AXIS_MM = 26.0
#: The y of the master positions on their sections (mm).
MASTER_Y_MM = 0.0


class MasterFormatError(InputError):
    """A master file of another format version (rebuilt from its FEM positions, never read as this one)."""


def grid_points() -> list[tuple[float, float, float]]:
    """(convexity, patch size in mm, aspect ratio) of every computed master point: the flat section over the whole
    (size, aspect) grid, the curved ones at :data:`SHAPE_LENGTH_MM` and :data:`SHAPE_ASPECTS`."""
    return [(c, length, r) for c in CONVEXITIES for length in LENGTHS_MM for r in ASPECTS
            if length * r ** 0.5 <= MAX_SEMI_AXIS_MM
            and (c == 0.0 or (length == SHAPE_LENGTH_MM and r in SHAPE_ASPECTS))]


def master_tasks(cfg: CalibrationConfig, material: MaterialSettings) -> list[PositionTask]:
    """The FEM tasks of ``material``'s master, one per point of :func:`grid_points` (no field output)."""
    code = code_hash()  # once: the sources' hash is part of every task's key
    return [arc_task(cfg, material, c, length * r ** 0.5, length / r ** 0.5, code) for c, length, r in grid_points()]


def arc_task(cfg: CalibrationConfig, material: MaterialSettings, convexity: float, a_mm: float, b_mm: float,
             code: str | None = None) -> PositionTask:
    """The FEM task of one synthetic arc block (:func:`arc_section` of ``convexity`` for the half-width ``b_mm``)
    loaded with the semi-axes a_mm, b_mm (mm) at y = :data:`MASTER_Y_MM`: a master point, or any point between."""
    section = arc_section(convexity, round(b_mm, 9))
    return position_task(cfg, "rail", section, given_geometry(section, MASTER_Y_MM, a_mm, b_mm), material, None, code)


def master_key(tasks: list[PositionTask]) -> str:
    """The master's key: the hash of its FEM task keys (those of :func:`master_tasks`)."""
    return inputs_hash([t.key for t in tasks])


def _length(t: PositionTask) -> float:
    """The patch size sqrt(a b) of a master task (mm)."""
    return round(math.sqrt(t.geometry.a_mm * t.geometry.b_mm), 9)


def _row(ind: IndentationResult, length: float, q: np.ndarray, material: MaterialSettings) -> tuple:
    """(p_y / Y, u_pl(q p_y) / L, residual dents / L, c_el E / L) of one master result."""
    p_y = ind.first_yield_MPa
    return (p_y / material.yield_MPa, (np.interp(q * p_y, ind.p_MPa, ind.u_pl_mm) / length).tolist(),
            (np.asarray(ind.residual_fem_mm) / length).tolist(),
            ind.fem_elastic_compliance_mm_per_MPa * material.E_MPa / length)


def _difference(row: tuple, base: tuple) -> tuple:
    """row - base, component by component (scalars and lists of the same length)."""
    return tuple((np.asarray(a, dtype=float) - np.asarray(b, dtype=float)) for a, b in zip(row, base))


def _sum(row: tuple, delta: tuple) -> tuple:
    """row + delta as a row of plain floats and lists."""
    out = [np.asarray(a, dtype=float) + d for a, d in zip(row, delta)]
    return tuple(float(v) if v.ndim == 0 else v.tolist() for v in out)


def _shape_at(shape: dict, c: float, r: float) -> tuple:
    """The shape difference of convexity ``c`` (a grid value) at aspect ratio ``r``: linear in log(a/b) between
    :data:`SHAPE_ASPECTS`, constant beyond."""
    logs = np.log(SHAPE_ASPECTS)
    x = float(np.clip(math.log(r), logs[0], logs[-1]))
    j = int(np.clip(np.searchsorted(logs, x), 1, len(logs) - 1))
    t = (x - logs[j - 1]) / (logs[j] - logs[j - 1])
    lo, hi = shape[c, SHAPE_ASPECTS[j - 1]], shape[c, SHAPE_ASPECTS[j]]
    return tuple((1 - t) * a + t * b for a, b in zip(lo, hi))


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
    format_version : int
        :data:`FORMAT_VERSION` (-).
    key : str
        Hash of the master's FEM task keys (-).
    material : MaterialSettings
        The material (E_MPa, poisson, yield_MPa, H_iso_MPa, H_kin_MPa; MPa, -).
    convexities : list of float
        Surface convexities b / (2 R) of the grid, ascending (-).
    lengths_mm : list of float
        The master patch sizes sqrt(a b), ascending (mm).
    aspects : list of float
        Aspect ratios a/b of the grid, ascending, from 1 (-).
    q : list of float
        Load levels p0 / p_y of the curves, from 0 (-).
    unload_factors : list of float
        Unloading peaks as multiples of p_y (-).
    first_yield_over_yield : list
        FEM first-yield pressure p_y over the yield stress, per convexity, size and aspect ratio (-).
    u_pl_over_length : list
        u_pl(q p_y) / sqrt(a b), per convexity, size, aspect ratio and level (-).
    residual_over_length : list
        FEM residual dent after unloading from each peak / sqrt(a b), per convexity, size, aspect ratio and peak (-).
    elastic_compliance : list
        The FEM mesh's elastic centre compliance c_el E / sqrt(a b), per convexity, size and aspect ratio (-).
    fem_seconds : float
        FEM time of the master positions (s).
    substituted : list of str
        Flat grid points whose FEM failed or was not computed, filled from the same aspect ratio at the nearest
        other size (the curved points off :data:`SHAPE_LENGTH_MM` and :data:`SHAPE_ASPECTS` are derived, see
        :meth:`build`).
    """

    format_version: int
    key: str
    material: MaterialSettings
    convexities: list[float]
    lengths_mm: list[float]
    aspects: list[float]
    q: list[float]
    unload_factors: list[float]
    first_yield_over_yield: list
    u_pl_over_length: list
    residual_over_length: list
    elastic_compliance: list
    fem_seconds: float
    substituted: list[str]

    @classmethod
    def build(cls, cfg: CalibrationConfig, material: MaterialSettings, tasks: list[PositionTask],
              results: dict[str, IndentationResult]) -> MasterCurves | None:
        """The curves from the master tasks' results (as :func:`master_tasks` orders them) on the whole grid
        (convexity, size, aspect). A flat point without a result takes the result of the same aspect ratio at the
        nearest other size; a curved point not computed is the flat value plus the shape's difference at
        :data:`SHAPE_LENGTH_MM` (both listed in ``substituted``). None when a needed point has no result (the
        master is incomplete: its positions are calibrated by the direct FEM)."""
        points = dict(zip(grid_points(), tasks))
        have = [t for t in tasks if t.key in results]
        if not have:
            return None
        q = path_levels([results[t.key] for t in have])
        substituted: list[str] = []

        def computed(c: float, length: float, r: float) -> tuple | None:
            t = points.get((c, length, r))
            return None if t is None or t.key not in results else _row(results[t.key], _length(t), q, material)

        flat = {}
        for length in LENGTHS_MM:
            for r in ASPECTS:
                row = computed(0.0, length, r)
                if row is None:
                    others = [o for o in LENGTHS_MM if o != length and computed(0.0, o, r) is not None]
                    if not others:
                        return None
                    other = min(others, key=lambda o: abs(math.log(o / length)))
                    row = computed(0.0, other, r)  # dimensionless: pure similarity
                    substituted.append(f"c = 0, L = {length:g} mm, a/b = {r:.3g}: from L = {other:g} mm")
                flat[length, r] = row
        shape = {}  # the shape's dimensionless difference from the flat section at SHAPE_LENGTH_MM
        for c in CONVEXITIES:
            for r in SHAPE_ASPECTS:
                row = flat[SHAPE_LENGTH_MM, r] if c == 0.0 else computed(c, SHAPE_LENGTH_MM, r)
                if row is None:
                    return None
                shape[c, r] = _difference(row, flat[SHAPE_LENGTH_MM, r])
        grid = []
        for c in CONVEXITIES:
            by_size = []
            for length in LENGTHS_MM:
                rows = []
                for r in ASPECTS:
                    row = computed(c, length, r) if c != 0.0 else flat[length, r]
                    if row is None:
                        row = _sum(flat[length, r], _shape_at(shape, c, r))
                    rows.append(row)
                by_size.append(rows)
            grid.append(by_size)
        seconds = sum(results[t.key].seconds for t in have)
        columns = [[[[row[k] for row in rows] for rows in by_size] for by_size in grid] for k in range(4)]
        return cls(FORMAT_VERSION, master_key(tasks), material, list(CONVEXITIES), list(LENGTHS_MM), list(ASPECTS),
                   q.tolist(), [float(f) for f in sorted(cfg.load.unload_factors)], *columns, float(seconds),
                   substituted)

    @property
    def aspect_range(self) -> tuple[float, float]:
        """The a/b range the master serves (-): [1 / largest, largest]."""
        return 1.0 / self.aspects[-1], self.aspects[-1]

    @property
    def convexity_range(self) -> tuple[float, float]:
        """The surface convexities b / (2 R) the master serves (-)."""
        return self.convexities[0], self.convexities[-1]

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    @classmethod
    def from_dict(cls, data: Any, what: str = "master") -> MasterCurves:
        """Validate and build (InputError naming the field; :class:`MasterFormatError` for another format
        version, e.g. a file without ``format_version``)."""
        validate.table(data, what)
        version = data.get("format_version", 1)
        if version != FORMAT_VERSION:
            raise MasterFormatError(validate.join(what, "format_version"), f"{version!r} is not this master's "
                                    f"format {FORMAT_VERSION} (the master is rebuilt from its FEM positions)")
        validate.check_known(data, list(cls.__dataclass_fields__), what)
        for name in cls.__dataclass_fields__:
            if name not in data:
                raise InputError(validate.join(what, name), "missing")
        kw = dict(data)
        kw["material"] = MaterialSettings(**validate.table(data["material"], validate.join(what, "material")))
        for name in ("convexities", "lengths_mm", "aspects", "q", "unload_factors"):
            validate.number_list(data[name], validate.join(what, name), min_len=0 if name == "unload_factors" else 1)
        shape = (len(data["convexities"]), len(data["lengths_mm"]), len(data["aspects"]))
        for name in ("first_yield_over_yield", "u_pl_over_length", "residual_over_length", "elastic_compliance"):
            try:
                arr = np.asarray(data[name], dtype=float)
            except (TypeError, ValueError):
                raise InputError(validate.join(what, name), "must be a regular array of numbers") from None
            if arr.shape[:3] != shape or not np.all(np.isfinite(arr)):
                raise InputError(validate.join(what, name), f"must be finite numbers per convexity, size and "
                                                            f"aspect ratio {shape}, got shape {arr.shape}")
        return cls(**kw)

    @classmethod
    def read(cls, path: Path) -> MasterCurves:
        """The master of a JSON file (InputError naming the file; :class:`MasterFormatError` for another
        version)."""
        try:
            data = json.loads(Path(path).read_text())
        except (OSError, ValueError) as err:
            raise InputError(str(path), f"not a readable master file ({err})") from None
        return cls.from_dict(data, str(path))

    def write(self, out_dir: Path) -> Path:
        """Write ``OUT/similarity_master_<key[:12]>.json`` (atomically); returns its path."""
        path = Path(out_dir) / f"similarity_master_{self.key[:12]}.json"
        atomic_write_text(path, json.dumps(self.to_dict(), indent=1) + "\n")
        return path


def stored_master(out_dir: Path, key: str) -> MasterCurves | None:
    """The master of key ``key`` written into ``out_dir`` before, or None: no file, or a file of another format
    version or content (then rebuilt from the master's FEM positions, never misread)."""
    path = Path(out_dir) / f"similarity_master_{key[:12]}.json"
    if not path.is_file():
        return None
    try:
        master = MasterCurves.read(path)
    except InputError:  # MasterFormatError included: an older master is recomputed
        return None
    return master if master.key == key else None


__all__ = ["ASPECTS", "CONVEXITIES", "FORMAT_VERSION", "LENGTHS_MM", "MASTER_Y_MM", "MAX_SEMI_AXIS_MM", "SHAPE_ASPECTS",
           "SHAPE_LENGTH_MM", "MasterCurves", "MasterFormatError", "arc_task", "grid_points", "master_key",
           "master_tasks", "path_levels", "stored_master"]
