"""One calibration position: mesh, elastoplastic Hertzian indentation with unloading branches -> raw
characteristic points (units mm, N, MPa). The definition is documented in docs/calibration.md:

- The FEM model (3D local half model, default; or the 2D plane-strain section) is loaded by the Hertzian
  pressure with the position's semi-axes; p0 rises monotonically to ``max_factor`` times the FEM first-yield
  pressure p_y (first yield within a few semi-axes of the load centre; see :func:`local_first_yield_MPa`).
- u_FEM(p0) is the normal displacement of the load centre (into the body) against the clamped far-field cut, as
  on a half-space (or, with ``reference_depth_factor`` > 0, against the material point that far below it). Its
  elastic part on the SAME mesh is c_el p0 (c_el from the linear solution), so the inelastic part
  u_pl(p0) = u_FEM(p0) - c_el p0 is free of the mesh's and the finite section's elastic error. In 3D it does not
  depend on the support or the cut depth (tests/calibration/test_support_independence.py, < 1 %). With elastic
  unloading u_pl equals the residual dent; the FEM unloading runs from several peaks check this
  (``reverse_plasticity_mm`` = u_res,FEM - u_pl at the peak).
- The layer has no elasticity of its own (the contact solver's half-space carries it): S_1 is set so that the
  layer's elastic displacement is below the FEM's accuracy (calibration.position_fit.first_slope_N_per_mm3).
- The monotonic characteristic is u(p) = p / S_1 + u_pl(p) with p_2 = p_y. Eq. (8) then returns u_pl(p0), the
  FEM residual dent, by construction (up to reverse plasticity, reported).
"""

from __future__ import annotations

import importlib.util
import math
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import scipy.sparse as sp

from calibration.fem.assembly import Discretisation, discretise
from calibration.fem.elastoplastic_solver import LoadPath, SolverOptions, SolverState, solve_load_path
from calibration.fem.material import J2Material, von_mises_MPa
from calibration.fem.solver_state import Increment
from calibration.hertz.geometry import LocalGeometry, halfspace_centre_compliance_mm_per_MPa
from calibration.hertz.load import HertzLoad, probe_operator
# the mesh names are also re-exported (__all__) for the benchmarks that import them from this module
from calibration.position_mesh import (AUTO_EXTRUDED_ASPECT, add_support_boundary, build_mesh, check_resolution,
                                       mesh_style)
from calibration.results import IndentationResult
from calibration.settings import LoadSettings, MeshSettings
from wrlayer.errors import require


def local_first_yield_MPa(disc, elastic_result, material: J2Material, radius_mm: float) -> float:
    """p0 (MPa) at which the von Mises stress first reaches yield within ``radius_mm`` of the load centre, from
    the elastic solution at p0 = 1 MPa. Structural stress concentrations far from the contact (e.g. the
    head/web fillet or the corners of the clamped cut) are excluded: they are not the contact's elastic limit."""
    vm = von_mises_MPa(elastic_result.state.stress_MPa) / elastic_result.state.p0_MPa
    x = disc.qp_coordinates()
    c = np.asarray(elastic_result.centre_mm, dtype=float).reshape((-1,) + (1,) * (x.ndim - 1))
    near = np.sqrt(np.sum((x - c) ** 2, axis=0)) <= radius_mm
    require(bool(np.any(near)), "mesh", f"no quadrature point within {radius_mm:g} mm of the load centre")
    return float(material.yield_MPa / np.max(vm[near]))


def point_probe(disc, point_mm: np.ndarray, direction: np.ndarray):
    """Sparse (1, n_dofs) functional: the displacement component along ``direction`` at ``point_mm`` inside the
    mesh (element found by barycentric coordinates of its vertices); InputError when the point is outside."""
    mesh = disc.mesh
    dim = mesh.dim()
    point = np.asarray(point_mm, dtype=float)
    v = mesh.p[:, mesh.t[:dim + 1]]                       # (dim, dim+1, n_elem)
    A = np.moveaxis(v[:, 1:] - v[:, :1], -1, 0)           # (n_elem, dim, dim)
    with np.errstate(all="ignore"):
        lam = np.linalg.solve(A, (point[:, None] - v[:, 0])[..., None].transpose(1, 0, 2))[..., 0]
    full = np.column_stack([1.0 - lam.sum(axis=1), lam])
    inside = np.nonzero(np.all(full >= -1e-9, axis=1))[0]
    require(inside.size > 0, "reference_depth_factor",
            f"the reference point {np.round(point, 3).tolist()} mm lies outside the mesh (section too shallow)")
    op = probe_operator(disc.basis, point, int(inside[0]))        # (dim, n_dofs)
    return sp.csr_matrix(np.asarray(direction, dtype=float)[None, :] @ op)


def solver_counts(disc) -> dict:
    """Triangular solves and factorisations of the discretisation's kept factoriser (machine-independent cost)."""
    fac = [v.factor for v in disc.problem_cache.values() if hasattr(v, "factor")]
    return {"linear_solves": int(sum(f.n_solves for f in fac)),
            "factorisations": int(sum(f.n_factorisations for f in fac))}


def load_levels(p_y: float, load: LoadSettings) -> list[float]:
    """The loading levels p0 (MPa): 0.5 p_y, p_y, n_levels equal steps up to max_factor p_y, and the peaks."""
    above = p_y * np.linspace(1.0, load.max_factor, load.n_levels + 1)[1:]
    peaks = [f * p_y for f in load.unload_factors]
    levels = sorted(set([0.5 * p_y, p_y] + above.tolist() + peaks))
    # one level where a step and a peak meet up to round-off (1.15 from the steps and from unload_factors): a
    # step of zero length would stop the predictor's extrapolation
    return [p for k, p in enumerate(levels) if k == 0 or p - levels[k - 1] > 1e-9 * p_y]


@dataclass(frozen=True)
class PositionModel:
    """The FEM model of one position: its mesh and discretisation, the Hertz load, the Dirichlet map (None: the
    solver's default), the displacement probes {name: functional} at the reference depths (name "ref": the layer
    displacement's reference; the others: the ``extra_depth_factors``), their depth factors (-) and the length
    they multiply (mm: max(a, b) in 3D, b in 2D)."""

    mesh: object
    disc: Discretisation
    load: HertzLoad
    dirichlet: dict | None
    probes: dict
    depth_factors: dict[str, float]
    length_mm: float


def position_model(profile, geometry: LocalGeometry, model: str, mesh_settings: MeshSettings,
                   extra_depth_factors: tuple[float, ...] = ()) -> PositionModel:
    """Mesh, discretisation, load and probes of one position (InputError for a mesh or probe that is not
    possible)."""
    check_resolution(geometry, model, mesh_settings)
    mesh = build_mesh(profile, geometry, model, mesh_settings)
    disc = discretise(mesh, mesh_settings.order)
    dirichlet = None
    if profile.body == "rail" and mesh_settings.rail_support_below_mm is not None:
        dirichlet = add_support_boundary(mesh, mesh_settings.rail_support_below_mm)
    load = HertzLoad(geometry.y_mm, geometry.b_mm, geometry.a_mm if model == "3d" else None,
                     z0_mm=geometry.z_mm)
    where = load.centre_only(disc.basis)
    length = max(geometry.a_mm, geometry.b_mm) if model == "3d" else geometry.b_mm
    factors = {"ref": mesh_settings.reference_depth_factor}
    factors.update({f"{f:g}": float(f) for f in extra_depth_factors})
    probes = {name: point_probe(disc, where.centre_mm - f * length * where.normal_out, -where.normal_out)
              for name, f in factors.items() if f > 0}
    probes["ref"] = probes.get("ref", lambda u: 0.0)  # factor 0: against the clamped far field
    return PositionModel(mesh, disc, load, dirichlet, probes, factors, length)


@dataclass(frozen=True)
class ElasticResponse:
    """The position's elastic solution at p0 = 1 MPa: the local first-yield pressure p_y and the whole model's
    (MPa), the load centre's compliance against the far field and against each probe (mm/MPa)."""

    p_y_MPa: float
    first_yield_anywhere_MPa: float
    compliance_abs_mm_per_MPa: float
    compliance_mm_per_MPa: dict[str, float]


def elastic_response(pm: PositionModel, material: J2Material, geometry: LocalGeometry, mesh_settings: MeshSettings,
                     linear_solver: str) -> ElasticResponse:
    """Solve the unit load elastically; InputError when the solution is degenerate."""
    p_probe = 1.0
    elastic = solve_load_path(pm.mesh, material, pm.load, [p_probe], disc=pm.disc, probes=pm.probes,
                              options=SolverOptions(dirichlet=pm.dirichlet, linear_solver=linear_solver))
    p_y = local_first_yield_MPa(pm.disc, elastic, material, mesh_settings.yield_search_radius_factor * geometry.b_mm)
    h_el = elastic.history[-1]
    c_el = {k: (h_el.u_centre_mm - v) / p_probe for k, v in h_el.probes_mm.items()}
    require(math.isfinite(p_y) and p_y > 0 and c_el["ref"] > 0, "indentation",
            f"elastic solution at y = {geometry.y_mm:g} mm is degenerate (p_y = {p_y}, compliance {c_el['ref']})")
    return ElasticResponse(p_y, float(elastic.first_yield_p0_MPa), h_el.u_centre_mm / p_probe, c_el)


@dataclass(frozen=True)
class LoadStageRecord:
    """One load stage of an indentation: loading up to ``end_MPa`` and, when that is an unloading peak, the
    unloading from it. increments: the loading increments; residual_mm: the dent after the unloading against
    the reference probe (mm; None: no unloading); newton_iterations: of loading and unloading; files: the VTK/PNG
    files written; output_seconds: wall time of the field output (s)."""

    end_MPa: float
    increments: tuple[Increment, ...]
    residual_mm: float | None
    newton_iterations: int
    files: tuple[str, ...]
    output_seconds: float


def load_stages(pm: PositionModel, material: J2Material, opts: SolverOptions, levels: list[float],
                peaks: list[float], out_dir: Path | None, series=None) -> Iterator[LoadStageRecord]:
    """The load stages of the path ``levels`` (MPa), one per unloading peak and the last level, each continuing
    the previous stage's loading branch; VTK/PNG fields at the highest peak and after unloading from it into
    ``out_dir`` (when given), every converged level to ``series`` (when given)."""
    top = max(peaks) if peaks else None
    state: SolverState | None = None
    branch = None
    start = 0.0
    for end in sorted(set(peaks + [levels[-1]])):
        stage = [p for p in levels if start < p <= end + 1e-9 * end]
        write = out_dir is not None and top is not None and abs(end - top) <= 1e-9 * top
        path = LoadPath(pm.mesh, material, pm.load, stage, opts, state, pm.disc, pm.probes, branch)
        loaded = list(path.levels([len(stage) - 1] if write else (), out_dir / "peak" if write else None, series))
        state, branch = path.state, path.branch  # the next stage extrapolates this loading branch
        increments = tuple(h for r in loaded for h in r.increments)
        files = [str(f) for r in loaded for f in r.files]
        output_s = sum(r.output_seconds for r in loaded)
        newton = sum(h.newton_iters for h in increments)
        residual = None
        if any(abs(end - pk) <= 1e-9 * pk for pk in peaks):
            unl = solve_load_path(pm.mesh, material, pm.load, [0.0], options=opts, initial_state=state, disc=pm.disc,
                                  vtk_at=[0] if write else (), out_dir=out_dir / "unloaded" if write else None,
                                  probes=pm.probes, on_level=series)
            h = unl.history[-1]
            residual = h.u_centre_mm - h.probes_mm["ref"]
            newton += sum(h.newton_iters for h in unl.history)
            output_s += unl.output_seconds
            files += [str(f) for f in unl.files]
        yield LoadStageRecord(end, increments, residual, newton, tuple(files), output_s)
        start = end


@dataclass(frozen=True, kw_only=True)
class IndentationJob:
    """What one position's indentation computes (built by keyword): ``profile`` (:class:`meshes.profiles.base.Profile`)
    and ``geometry`` (the Hertz patch, mm) of the position, its ``material`` (MPa), ``model`` '2d' | '3d', the
    ``mesh`` and ``load`` settings, the ``linear_solver`` 'auto' | 'pardiso' | 'scipy' (SuperLU: faster for small
    2D sections on a busy machine) and ``extra_depth_factors``: further reference depths (as
    ``mesh.reference_depth_factor``) whose inelastic displacements are reported in ``u_pl_depth_mm``
    (benchmarks). InputError for a model or unloading factor out of range."""

    profile: object
    geometry: LocalGeometry
    material: J2Material
    model: str = "2d"
    mesh: MeshSettings = MeshSettings()
    load: LoadSettings = LoadSettings()
    linear_solver: str = "auto"
    extra_depth_factors: tuple[float, ...] = ()

    def __post_init__(self):
        require(self.model in ("2d", "3d"), "model", f"must be '2d' or '3d', got {self.model!r}")
        load = self.load
        require(all(0 < f <= load.max_factor + 1e-12 for f in load.unload_factors), "unload_factors",
                f"must lie in (0, max_factor = {load.max_factor}], got {list(load.unload_factors)}")


def indent(job: IndentationJob, *, out_dir: Path | None = None,
           progress: Callable[[int], object] | None = None) -> IndentationResult:
    """Run the indentation of one position; ``progress(n)`` is called after the elastic solve and after each load
    stage (optional).

    The layer displacement is the normal displacement of the load centre (relative to the material point at the
    reference depth d_ref = reference_depth_factor * max(a, b) below it when that factor is > 0). When ``out_dir``
    is given, VTK/PNG fields at the highest peak and after unloading from it are written there, and every
    converged level of the whole path as a ParaView time series ``out_dir/load_path/load_path.pvd`` (load level
    p0_MPa in each file's FieldData). Raises ConvergenceError (FEM) or InputError (geometry, mesh) naming the
    cause.
    """
    profile, geometry, material, model = job.profile, job.geometry, job.material, job.model
    mesh_settings, load_settings, linear_solver = job.mesh, job.load, job.linear_solver
    t0 = time.perf_counter()
    if out_dir is not None and importlib.util.find_spec("calibration.fem.output") is None:
        out_dir = None  # the FEM engine's field output is not available: no VTK/PNG pictures
    pm = position_model(profile, geometry, model, mesh_settings, job.extra_depth_factors)
    el = elastic_response(pm, material, geometry, mesh_settings, linear_solver)
    if progress:
        progress(1)
    p_y = el.p_y_MPa
    # unloading in one step (cut on failure like any step): it is elastic up to reverse plasticity, and the
    # many small steps it took before were a third of the increments (benchmarks/bench_fem.py)
    # rtol 1e-6 / etol 1e-8: the dents agree with 1e-8 / 1e-10 to 1e-7 relative at 22 % fewer solves (measured,
    # docs/calibration.md)
    opts = SolverOptions(max_increment_MPa=load_settings.max_increment_factor * p_y, dirichlet=pm.dirichlet,
                         linear_solver=linear_solver, max_unload_increment_MPa=load_settings.max_factor * p_y,
                         rtol=1e-6, etol=1e-8,
                         output_label=f"{profile.body} {profile.name}, y = {geometry.y_mm:g} mm ({model.upper()})")
    levels = load_levels(p_y, load_settings)
    peaks = sorted(f * p_y for f in load_settings.unload_factors)
    series, series_s = None, 0.0
    if out_dir is not None:  # every converged level of the path as a ParaView time series
        from calibration.fem.output import FieldSeries  # pyvista/meshio only where fields are written

        t_out = time.perf_counter()
        series = FieldSeries(Path(out_dir) / "load_path", material)
        series(pm.disc, SolverState.virgin(pm.disc))  # step 0: the unloaded body
        series_s += time.perf_counter() - t_out
    stages = []
    for record in load_stages(pm, material, opts, levels, peaks, out_dir, series):
        stages.append(record)
        if progress:
            progress(1)
    files = [f for r in stages for f in r.files]
    if series is not None:
        t_out = time.perf_counter()
        files += [str(p) for _, p in series.steps] + [str(series.write_pvd())]
        series_s += time.perf_counter() - t_out
    output_s = series_s + sum(r.output_seconds for r in stages)
    return _result(pm, el, material, geometry, model, stages, peaks, files, time.perf_counter() - t0 - output_s,
                   output_s)


def _result(pm: PositionModel, el: ElasticResponse, material: J2Material, geometry: LocalGeometry, model: str,
            stages: list[LoadStageRecord], peaks: list[float], files: list[str], seconds: float,
            output_seconds: float) -> IndentationResult:
    """The indentation's characteristic points from its load stages (u_pl = u - c_el p, >= 0 below p_y)."""
    history = [h for r in stages for h in r.increments]
    residuals = [r.residual_mm for r in stages if r.residual_mm is not None]
    p = np.array([0.0] + [h.p0_MPa for h in history])
    u_abs = np.array([0.0] + [h.u_centre_mm for h in history])
    u_pl_depth = {}
    for name in pm.depth_factors:
        rel = u_abs - np.array([0.0] + [h.probes_mm[name] for h in history])
        pl = rel - el.compliance_mm_per_MPa[name] * p
        pl[p <= el.p_y_MPa] = np.maximum(pl[p <= el.p_y_MPa], 0.0)
        u_pl_depth[name] = pl
    u_pl = u_pl_depth.pop("ref")
    u = u_abs - np.array([0.0] + [h.probes_mm["ref"] for h in history])
    u_pl_at_peaks = np.interp(peaks, p, u_pl)
    c_hs = halfspace_centre_compliance_mm_per_MPa(geometry.a_mm, geometry.b_mm, material.E_MPa, material.poisson)
    ref_factor = pm.depth_factors["ref"]
    return IndentationResult(model, p.tolist(), u.tolist(), u_pl.tolist(), float(el.p_y_MPa),
                             float(el.first_yield_anywhere_MPa), float(el.compliance_mm_per_MPa["ref"]), float(c_hs),
                             [float(x) for x in peaks], [float(x) for x in residuals],
                             (np.array(residuals) - u_pl_at_peaks).tolist(), int(pm.disc.n_dofs),
                             int(pm.mesh.t.shape[1]), int(sum(r.newton_iterations for r in stages)), seconds, files,
                             reference_depth_mm=float(ref_factor * pm.length_mm) if ref_factor > 0 else None,
                             u_centre_abs_mm=u_abs.tolist(),
                             fem_absolute_compliance_mm_per_MPa=float(el.compliance_abs_mm_per_MPa),
                             u_pl_depth_mm={k: v.tolist() for k, v in u_pl_depth.items()},
                             output_seconds=float(output_seconds), **solver_counts(pm.disc))


__all__ = ["AUTO_EXTRUDED_ASPECT", "ElasticResponse", "IndentationJob", "IndentationResult", "LoadSettings", "LoadStageRecord",
           "MeshSettings", "add_support_boundary", "build_mesh", "mesh_style",
           "PositionModel", "elastic_response", "indent", "load_levels", "load_stages", "local_first_yield_MPa",
           "point_probe", "position_model", "solver_counts"]
