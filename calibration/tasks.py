"""The positions of a calibration as tasks: each position's local geometry, mesh check and cache key, and the worker
that runs its FEM indentation (units mm, N, MPa, s).

A position's FEM inputs (profile and its file content, position, mating geometry, material, model, mesh and load
settings, the source code that computes the FEM result) are hashed (SHA-256) into its cache key, so a rerun with
nothing changed does no FEM and changing one position recomputes only that one.
"""

from __future__ import annotations

import json
import pickle
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from calibration.config import profile_of
from calibration.fem.material import J2Material
from calibration.hertz.geometry import (HERTZ_B_OVER_R_LIMIT, LocalGeometry, conformity, fitted_load_N,
                                        given_geometry, local_geometry)
from calibration.indentation import IndentationJob, indent
from calibration.placement import cant_rad
from calibration.results import IndentationResult
from calibration.settings import (BodySettings, CalibrationConfig, LoadSettings, MaterialSettings, MeshSettings)
from meshes.meshing.section_mesh import DEFAULT_DEPTH_MM, check_mesh_inputs
from meshes.profiles import Profile
from wrlayer.errors import InputError, WrLayerError
from wrlayer.hashing import file_sha256, sha256_hex
from wrlayer.runner import report_progress

ROOT = Path(__file__).resolve().parent.parent
#: Sources that determine a position's FEM result (the cache key includes their content).
#: The sources whose code determines a FEM result. calibration/settings.py is not one: its dataclasses hold data
#: only, and the material, mesh and load settings enter a task's key by value (:func:`position_task`), so a new
#: run key does not invalidate every cached FEM result.
FEM_SOURCES = ("calibration/indentation.py", "calibration/position_mesh.py", "calibration/hertz/*.py",
               "calibration/fem/*.py", "meshes/**/*.py")


def code_hash(patterns: tuple[str, ...] = FEM_SOURCES) -> str:
    """SHA-256 of the Python sources matching ``patterns`` (default: those that determine the FEM results)."""
    return sha256_hex(b"".join(part for pattern in patterns for f in sorted(ROOT.glob(pattern))
                               for part in (str(f.relative_to(ROOT)).encode(), f.read_bytes())))


def inputs_hash(obj: Any) -> str:
    """SHA-256 of the JSON form of ``obj`` (sorted keys): the cache key of a result made from ``obj``."""
    return sha256_hex(json.dumps(obj, sort_keys=True, default=str))


def profile_identity(spec: Any) -> str:
    """What identifies a profile in a cache key: its builtin name, its file's content, or an in-memory
    Profile's content (pickled)."""
    if isinstance(spec, Profile):
        return f"object:{sha256_hex(pickle.dumps(spec, protocol=4))}"
    p = Path(spec)
    if p.is_file():
        return f"file:{file_sha256(p)}"
    return f"builtin:{spec.upper()}"


def profile_label(spec: Any) -> str:
    """The profile's name for tables and messages: the builtin name, the file name or the Profile's name."""
    if isinstance(spec, Profile):
        return spec.name
    return Path(spec).name if Path(spec).is_file() else spec


def profile_source(spec: Any) -> str:
    """Where the profile came from (tables' ``profile_source``): the name or path, or "<name> (in memory)"."""
    return f"{spec.name} (in memory)" if isinstance(spec, Profile) else spec


@dataclass(frozen=True)
class PositionTask:
    """Everything a worker needs for one position (picklable). key: the cache key of its FEM result;
    fields_dir: where its VTK/PNG fields go (None: none); profile: as in :class:`BodySettings`."""

    body: str
    profile: Any
    y_mm: float
    geometry: LocalGeometry
    material: MaterialSettings
    model: str
    mesh: MeshSettings
    load: LoadSettings
    key: str
    fields_dir: str | None
    linear_solver: str = "scipy"

    @property
    def label(self) -> str:
        return f"{self.body} {profile_label(self.profile)} y = {self.y_mm:g} mm"

    @property
    def stages(self) -> int:
        """Progress steps of the position: the elastic solve plus one per loading stage."""
        return 1 + len(set(self.load.unload_factors) | {self.load.max_factor})

    @property
    def aspect(self) -> float:
        """The contact patch's elongation max(a, b) / min(a, b) (-)."""
        a, b = self.geometry.a_mm, self.geometry.b_mm
        return max(a, b) / min(a, b)


@dataclass(frozen=True)
class PositionOutcome:
    """What the worker returns for one position: its FEM result, or the error that stopped it."""

    key: str
    indentation: IndentationResult | None
    error: str | None = None


def task_failure(task: PositionTask, err: Exception) -> str:
    """The one-line error of a worker's failed position, naming it (a project error as it is, any other with its
    type)."""
    return f"{task.label}: {err}" if isinstance(err, WrLayerError) else f"{task.label}: {type(err).__name__}: {err}"


def run_position(task: PositionTask) -> PositionOutcome:
    """Worker: the FEM indentation of one position (progress through :func:`wrlayer.runner.report_progress`).
    Never raises for a failed position: the error is returned with the position named."""
    try:
        fields_dir = Path(task.fields_dir) if task.fields_dir else None
        job = IndentationJob(profile=profile_of(task.profile), geometry=task.geometry,
                             material=J2Material(**asdict(task.material)), model=task.model, mesh=task.mesh,
                             load=task.load, linear_solver=task.linear_solver)
        res = indent(job, out_dir=fields_dir, progress=report_progress)
        return PositionOutcome(task.key, res)
    except Exception as err:  # a failed position must not stop the others; report the cause
        return PositionOutcome(task.key, None, task_failure(task, err))


def position_geometry(b: BodySettings, profile, mate, y: float, reference_load_N: float):
    """(LocalGeometry, warning or None) of one position: the Hertz patch at the reference load, or, at a
    conforming position (b/R_min > HERTZ_B_OVER_R_LIMIT), at the load whose patch has b/R_min at the limit."""
    if b.semi_axes_mm is not None:
        return given_geometry(profile, y, *b.semi_axes_mm), None
    args = (b.material.E_MPa, b.material.poisson, cant_rad(b, f"bodies.{b.body}"), b.wheel_radius_mm,
            b.max_lateral_radius_mm)
    geo = local_geometry(profile, y, mate, reference_load_N, *args)
    ratio = conformity(geo)
    if ratio <= HERTZ_B_OVER_R_LIMIT:
        return geo, None
    load_n = fitted_load_N(geo)
    geo = local_geometry(profile, y, mate, load_n, *args)
    return geo, (f"{b.body} y = {y:g} mm: conforming contact (b/R = {ratio:.2f} > {HERTZ_B_OVER_R_LIMIT:g} at "
                 f"{reference_load_N:g} N: the Hertz half-space load does not fit); calibrated at {load_n:.4g} N "
                 f"(b = {geo.b_mm:.3g} mm, b/R = {conformity(geo):.2f})")


#: Mesh arguments checked by meshes.meshing.section_mesh.check_mesh_inputs -> the configuration key they come from.
_MESH_KEYS = {"h_min": "mesh.h_max_mm", "h_max": "mesh.h_max_mm", "depth_mm": "mesh.depth_mm",
              "grading": "mesh.grading", "order": "mesh.order"}


def check_mesh_settings(cfg: CalibrationConfig, b: BodySettings, profile, geometry: LocalGeometry) -> None:
    """The mesh of one position is possible: h_max_mm >= h_min (= semi-axis / elements_per_semi_axis) and the
    section depth leaves material at the load point. InputError naming the configuration key and the position
    (checked before any FEM runs or any file is written)."""
    m = cfg.mesh
    a, bb = geometry.a_mm, geometry.b_mm
    h_min = min(bb, a if cfg.run.model == "3d" else bb) / m.elements_per_semi_axis
    where = f"{b.body} y = {geometry.y_mm:g} mm"
    if m.h_max_mm < h_min:
        raise InputError(f"{cfg.source}: mesh.h_max_mm", f"{m.h_max_mm:g} mm is below h_min = {h_min:.3g} mm "
                         f"(semi-axis / mesh.elements_per_semi_axis) at {where}")
    depth = DEFAULT_DEPTH_MM[profile.body] if m.depth_mm is None else m.depth_mm
    try:
        check_mesh_inputs(profile, geometry.y_mm, h_min, m.h_max_mm, depth, m.order, m.grading)
    except InputError as err:
        key = _MESH_KEYS.get(err.what, f"mesh.{err.what}")
        raise InputError(f"{cfg.source}: {key}", f"{err.problem} ({where})") from None


@dataclass(frozen=True)
class PositionNote:
    """A failed position or a warning about one: body, lateral position (mm) and the message."""

    body: str
    y_mm: float
    message: str


def make_tasks(cfg: CalibrationConfig, out_dir: Path, plots: bool | None = None
               ) -> tuple[list[PositionTask], list[PositionNote], list[PositionNote]]:
    """Tasks for all positions, failures found already while computing the local geometry, and warnings
    (conforming positions, b/R above HERTZ_B_OVER_R_LIMIT, calibrated at a lower load). With ``plots``
    (default: the configuration's) each task writes VTK/PNG fields into OUT/fields/<body>_y<y>mm."""
    plots = cfg.run.plots if plots is None else plots
    code = code_hash()
    tasks, failed, warnings = [], [], []
    for b in cfg.bodies:
        cant_rad(b, f"{cfg.source}: bodies.{b.body}")  # a rail of unknown placement: refused before any position
        profile = profile_of(b.profile)
        mate = profile_of(b.mate) if b.mate else None
        for y in b.positions_mm:
            try:
                geo, warning = position_geometry(b, profile, mate, y, cfg.reference_load_N)
                if warning:
                    warnings.append(PositionNote(b.body, y, warning))
            except WrLayerError as err:
                failed.append(PositionNote(b.body, y, str(err)))
                continue
            check_mesh_settings(cfg, b, profile, geo)
            fields = out_dir / "fields" / f"{b.body}_y{y:+08.3f}mm" if plots else None
            tasks.append(position_task(cfg, b.body, b.profile, geo, b.material, fields, code))
    return tasks, failed, warnings


def position_task(cfg: CalibrationConfig, body: str, profile: Any, geometry: LocalGeometry,
                  material: MaterialSettings, fields_dir: Path | None = None, code: str | None = None
                  ) -> PositionTask:
    """The task of one position, keyed by the hash of its FEM inputs (``code``: :func:`code_hash`, computed when
    not given)."""
    fem_inputs = {"profile": profile_identity(profile), "body": body, "y_mm": geometry.y_mm,
                  "geometry": geometry.to_dict(), "material": asdict(material), "model": cfg.run.model,
                  "mesh": asdict(cfg.mesh), "load": asdict(cfg.load), "code": code or code_hash()}
    return PositionTask(body, profile, float(geometry.y_mm), geometry, material, cfg.run.model, cfg.mesh, cfg.load,
                        inputs_hash(fem_inputs), str(fields_dir) if fields_dir else None, cfg.run.linear_solver)


__all__ = ["FEM_SOURCES", "PositionNote", "PositionOutcome", "PositionTask", "check_mesh_settings", "code_hash",
           "inputs_hash", "make_tasks", "position_geometry", "position_task", "profile_identity", "profile_label", "profile_source",
           "run_position", "task_failure"]
