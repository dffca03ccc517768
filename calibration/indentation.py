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
  layer's elastic displacement is below the FEM's accuracy (calibration.pipeline.first_slope_N_per_mm3).
- The monotonic characteristic is u(p) = p / S_1 + u_pl(p) with p_2 = p_y. Eq. (8) then returns u_pl(p0), the
  FEM residual dent, by construction (up to reverse plasticity, reported).
"""

from __future__ import annotations

import importlib.util
import math
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np
import scipy.sparse as sp

from calibration.fem.elastoplastic_solver import SolverOptions, SolverState, solve_load_path
from calibration.fem.assembly import discretise
from calibration.hertz.geometry import LocalGeometry, halfspace_centre_compliance_mm_per_MPa
from calibration.hertz.load import HertzLoad
from calibration.fem.material import J2Material, von_mises_MPa
from wrlayer.errors import require


@dataclass(frozen=True)
class MeshSettings:
    """Mesh sizes: h_min = b / elements_per_semi_axis at the load point, growing to h_max_mm; 3D half-model length
    length_factor * a (at least 4 b); element order 1 or 2; section depth in mm (None: the mesh module's default
    per body); rail_support_below_mm: the rail head is also held on its side/underside boundary below
    z = -rail_support_below_mm (the head underside and web), so that the section does not bend over the thin
    web like a cantilever (a plane-strain artefact: the real load is short in x); None: clamped cut only.
    3D: h_min fills the box of half-sizes (1.2 a, 1.2 b, refine_depth_factor * b) at the load point (the plastic
    zone). First yield is searched within yield_search_radius_factor * b of the load centre. reference_depth_factor > 0:
    the layer displacement is measured against the material point reference_depth_factor * max(a, b) (2D: * b)
    below the load centre; 0 (default): against the clamped far field, as a half-space's.
    style (3D): "isotropic" (unstructured tetrahedra of size min(a, b) / elements_per_semi_axis filling the box),
    "stretched" (the isotropic mesh of the patch with x divided by s = max(1, (a/b) / STRETCH_ASPECT), stretched
    back by s: elements s times longer along x, as many as for a round patch; identical to "isotropic" where
    a/b <= STRETCH_ASPECT; docs/calibration.md "Stretched mesh"),
    "auto" (extruded when a/b >= AUTO_EXTRUDED_ASPECT, else isotropic) or "extruded" (the section meshed with
    min(a, b) / elements_per_semi_axis in the box's (y, z) extent and extruded along x in structured layers of a / elements_per_semi_axis over 0 <= x <= 1.2 a, unstructured
    beyond: its element count does not grow with a/b; meshes.meshing.extruded_mesh, docs/calibration.md);
    x_elements_per_semi_axis (extruded only): layers a / x_elements_per_semi_axis instead (None: the same n);
    "structured": a core |s| <= 1.2 b along the surface arc, refine_depth_factor * b deep along the normal,
    0 <= x <= 1.2 a, meshed in cells of at most b / n, b / n and a / n (n = elements_per_semi_axis), the rest
    unstructured (meshes.meshing.structured_core_mesh, docs/calibration.md "Mesh convergence").
    yield_zone_refinement f > 1 (isotropic and stretched meshes, also under "auto"): h_min / f in the zone
    YIELD_ZONE around the point of first yield (YIELD_ZONE_DEPTH_FACTOR * b below the load centre along the
    normal), which decides p_y and through it every quantity compared at multiples of p_y; 1: off."""

    elements_per_semi_axis: float = 8.0
    h_max_mm: float = 6.0
    order: int = 2
    depth_mm: float | None = None
    rail_support_below_mm: float | None = 35.0
    length_factor: float = 5.0
    grading: float = 0.3
    yield_search_radius_factor: float = 3.0
    reference_depth_factor: float = 0.0
    refine_depth_factor: float = 1.0
    style: str = "isotropic"  # the library default; calibration/configs/default.toml sets "auto"
    x_elements_per_semi_axis: float | None = None
    yield_zone_refinement: float = 1.0


#: MeshSettings.yield_zone_refinement: centre of the finer zone, this many b below the load centre along the inward
#: normal (the von Mises maximum of the Hertz pressure lies 0.47-0.55 b deep for a/b = 1-2), and its half-sizes
#: (x, y, z) as multiples of (a, b, b): it covers 0.15-0.95 b in depth (docs/calibration.md, "Mesh convergence").
YIELD_ZONE_DEPTH_FACTOR = 0.55
YIELD_ZONE = (0.45, 0.45, 0.4)
#: The 3D mesh styles of MeshSettings.style.
MESH_STYLES = ("isotropic", "stretched", "extruded", "structured", "auto")
#: style "auto": the extruded mesh for patches with a/b at least this, the isotropic one below (docs/calibration.md,
#: "Anisotropic (extruded) mesh" and "Every position": with the finer zone around the first-yield point the
#: isotropic mesh is within 0.9 % of finer meshes at a/b = 3.2-3.7, where the extruded one is 0.6-3.0 % off, at
#: 1.3-1.8x its time; at a/b >= 5.8 the isotropic mesh costs 2-3x more than the extruded one).
AUTO_EXTRUDED_ASPECT = 4.0
#: style "stretched": patches with a/b above this are meshed as the isotropic mesh of a patch of this aspect (x
#: divided by a/b / STRETCH_ASPECT) and stretched back along x (docs/calibration.md, "Stretched mesh"); the round
#: patches of the default run (a/b <= 1.35) are meshed exactly as by "isotropic".
STRETCH_ASPECT = 1.4


@dataclass(frozen=True)
class LoadSettings:
    """Load path: p0 up to max_factor * p_y in n_levels equal steps above p_y (plus 0.5 p_y and p_y), unloading
    runs from the peaks unload_factors * p_y (each <= max_factor); max_increment_factor * p_y is the largest
    solver step."""

    max_factor: float = 2.5
    n_levels: int = 12
    unload_factors: tuple[float, ...] = (1.5, 2.0, 2.5)
    max_increment_factor: float = 0.125


@dataclass
class IndentationResult:
    """Raw FEM characteristic of one position (mm, MPa, s). ``p_MPa``/``u_fem_mm``/``u_pl_mm``: all converged
    loading increments (u_pl = u_FEM - c_el p); ``unload_peaks_MPa``/``residual_fem_mm``: FEM dents after full
    unloading; ``first_yield_MPa``: p_y near the contact; ``first_yield_anywhere_MPa``: the whole model's (may be a
    structural stress concentration); compliances in mm/MPa; ``files``: VTK/PNG outputs; ``seconds``: wall time of
    the FEM (mesh, solves; without the field output), ``output_seconds``: wall time of writing ``files``."""

    model: str
    p_MPa: list[float]
    u_fem_mm: list[float]
    u_pl_mm: list[float]
    first_yield_MPa: float
    first_yield_anywhere_MPa: float
    fem_elastic_compliance_mm_per_MPa: float
    halfspace_compliance_mm_per_MPa: float
    unload_peaks_MPa: list[float]
    residual_fem_mm: list[float]
    reverse_plasticity_mm: list[float]
    n_dofs: int
    n_elements: int
    newton_iterations: int
    seconds: float
    files: list[str] = field(default_factory=list)
    reference_depth_mm: float | None = None
    u_centre_abs_mm: list[float] = field(default_factory=list)
    fem_absolute_compliance_mm_per_MPa: float | None = None
    u_pl_depth_mm: dict[str, list[float]] = field(default_factory=dict)
    linear_solves: int = 0
    factorisations: int = 0
    output_seconds: float = 0.0

    def to_dict(self) -> dict:
        return asdict(self)


def build_mesh(profile, geometry: LocalGeometry, model: str, mesh: MeshSettings):
    """The 2D section mesh or 3D local mesh refined at the position (sizes from the semi-axes)."""
    from meshes.meshing.local_mesh import local_mesh
    from meshes.meshing.section_mesh import section_mesh

    h_min = min(geometry.b_mm, geometry.a_mm if model == "3d" else geometry.b_mm) / mesh.elements_per_semi_axis
    h_max = max(mesh.h_max_mm, h_min)
    if model == "2d":
        return section_mesh(profile, geometry.y_mm, h_min, h_max, depth_mm=mesh.depth_mm, order=mesh.order,
                            refine_radius_mm=1.2 * geometry.b_mm, grading=mesh.grading)
    length = max(mesh.length_factor * geometry.a_mm, 4.0 * geometry.b_mm)
    require(mesh.style in MESH_STYLES, "mesh.style", f"must be one of {MESH_STYLES}, got {mesh.style!r}")
    if mesh_style(geometry, mesh) == "structured":
        from meshes.meshing.structured_core_mesh import core_for_contact, structured_core_local_mesh

        core = core_for_contact(geometry.a_mm, geometry.b_mm, mesh.elements_per_semi_axis,
                                depth_factor=mesh.refine_depth_factor)
        return structured_core_local_mesh(profile, geometry.y_mm, core, h_max, length_mm=length,
                                          depth_mm=mesh.depth_mm, order=mesh.order, grading=mesh.grading)
    if mesh_style(geometry, mesh) == "extruded":
        from meshes.meshing.extruded_mesh import extruded_local_mesh

        h_x = geometry.a_mm / (mesh.x_elements_per_semi_axis or mesh.elements_per_semi_axis)
        return extruded_local_mesh(profile, geometry.y_mm, h_min, h_x, max(h_max, h_x), length_mm=length,
                                   core_length_mm=1.2 * geometry.a_mm, depth_mm=mesh.depth_mm,
                                   order=mesh.order, grading=mesh.grading,
                                   refine_box_yz=(1.2 * geometry.b_mm, mesh.refine_depth_factor * geometry.b_mm))
    box = (1.2 * geometry.a_mm, 1.2 * geometry.b_mm, mesh.refine_depth_factor * geometry.b_mm)
    inner = None
    if mesh.yield_zone_refinement > 1.0:
        from meshes.meshing.mesh_size import GradedSize

        z0 = float(profile.z(geometry.y_mm))
        centre = np.array([geometry.y_mm, z0]) - YIELD_ZONE_DEPTH_FACTOR * geometry.b_mm * np.asarray(
            profile.normal(geometry.y_mm), dtype=float)
        half = (YIELD_ZONE[0] * geometry.a_mm, YIELD_ZONE[1] * geometry.b_mm, YIELD_ZONE[2] * geometry.b_mm)
        inner = GradedSize(h_min / mesh.yield_zone_refinement, h_max, mesh.grading,
                           (0.0, float(centre[0]), float(centre[1])), half_box=half)
    sx = x_stretch(geometry, mesh)
    return local_mesh(profile, geometry.y_mm, h_min, h_max, length_mm=length, depth_mm=mesh.depth_mm,
                      order=mesh.order, refine_box=box, grading=mesh.grading, inner_zone=inner, x_stretch=sx)


def x_stretch(geometry: LocalGeometry, mesh: MeshSettings) -> float:
    """The factor by which style "stretched" elongates the isotropic mesh along x: (a/b) / STRETCH_ASPECT when
    that exceeds 1, else 1 (and 1 for every other style)."""
    if mesh_style(geometry, mesh) != "stretched":
        return 1.0
    return max(1.0, geometry.a_mm / geometry.b_mm / STRETCH_ASPECT)


def mesh_style(geometry: LocalGeometry, mesh: MeshSettings) -> str:
    """The 3D mesh style used at a position: mesh.style, "auto" resolved by the patch's a/b."""
    if mesh.style != "auto":
        return mesh.style
    return "extruded" if geometry.a_mm >= AUTO_EXTRUDED_ASPECT * geometry.b_mm else "isotropic"


#: Fewest elements across the contact's shorter semi-axis (h_min = min(a, b) / elements_per_semi_axis): below
#: this the Hertz pressure is carried by one or two element faces and the dent is not resolved.
MIN_ELEMENTS_PER_SEMI_AXIS = 2.0


def check_resolution(geometry: LocalGeometry, model: str, mesh: MeshSettings) -> None:
    """InputError naming ``mesh.elements_per_semi_axis`` when the mesh is too coarse for the contact."""
    short = min(geometry.a_mm, geometry.b_mm) if model == "3d" else geometry.b_mm
    require(mesh.elements_per_semi_axis >= MIN_ELEMENTS_PER_SEMI_AXIS, "mesh.elements_per_semi_axis",
            f"{mesh.elements_per_semi_axis:g} elements across the semi-axis {short:.3g} mm (h_min = "
            f"{short / mesh.elements_per_semi_axis:.3g} mm) is too coarse for the load: at least "
            f"{MIN_ELEMENTS_PER_SEMI_AXIS:g} are needed")


def add_support_boundary(mesh, below_mm: float) -> dict:
    """Add the boundary "support" (facets of "side" whose midpoint lies below z = -below_mm) to ``mesh`` and
    return the Dirichlet map {fixed: all, support: all (, symmetry: x)} for the solver."""
    dim = mesh.dim()
    side = np.asarray(mesh.boundaries["side"])
    z_mid = mesh.p[dim - 1, mesh.facets[:, side]].mean(axis=0)
    support = side[z_mid < -float(below_mm)]
    require(support.size > 0, "rail_support_below_mm", f"no side facet lies below z = -{below_mm:g} mm")
    mesh.boundaries["support"] = support
    out = {"fixed": list(range(dim)), "support": list(range(dim))}
    if "symmetry" in mesh.boundaries:
        out["symmetry"] = [0]
    return out


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
    from calibration.hertz.load import _probe

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
    op = _probe(disc.basis, point, int(inside[0]))        # (dim, n_dofs)
    return sp.csr_matrix(np.asarray(direction, dtype=float)[None, :] @ op)


def _solver_counts(disc) -> dict:
    """Triangular solves and factorisations of the discretisation's kept factoriser (machine-independent cost)."""
    fac = [v.factor for v in disc.problem_cache.values() if hasattr(v, "factor")]
    return {"linear_solves": int(sum(f.n_solves for f in fac)),
            "factorisations": int(sum(f.n_factorisations for f in fac))}


def _levels(p_y: float, load: LoadSettings) -> list[float]:
    above = p_y * np.linspace(1.0, load.max_factor, load.n_levels + 1)[1:]
    peaks = [f * p_y for f in load.unload_factors]
    return sorted(set([0.5 * p_y, p_y] + above.tolist() + peaks))


def indent(profile, geometry: LocalGeometry, material: J2Material, model: str = "2d",
           mesh_settings: MeshSettings = MeshSettings(), load_settings: LoadSettings = LoadSettings(),
           out_dir: Path | None = None, progress=None, linear_solver: str = "auto",
           extra_depth_factors: tuple[float, ...] = ()) -> IndentationResult:
    """Run the indentation of one position; ``progress(n)`` is called after each load stage (optional);
    linear_solver: 'auto' | 'pardiso' | 'scipy' (SuperLU: faster for small 2D sections on a busy machine).

    The layer displacement is the normal displacement of the load centre (relative to the material point at the
    reference depth d_ref = reference_depth_factor * max(a, b) below it when that factor is > 0). ``extra_depth_factors``:
    further reference depths (same unit) whose inelastic displacements are reported in ``u_pl_depth_mm``
    (benchmarks). When ``out_dir`` is given, VTK/PNG fields at the highest peak and after unloading from it are
    written there, and every converged level of the whole path as a ParaView time series
    ``out_dir/load_path/load_path.pvd`` (load level p0_MPa in each file's FieldData). Raises ConvergenceError (FEM) or InputError (geometry, mesh) naming the cause.
    """
    require(model in ("2d", "3d"), "model", f"must be '2d' or '3d', got {model!r}")
    require(all(0 < f <= load_settings.max_factor + 1e-12 for f in load_settings.unload_factors), "unload_factors",
            f"must lie in (0, max_factor = {load_settings.max_factor}], got {list(load_settings.unload_factors)}")
    t0 = time.perf_counter()
    if out_dir is not None and importlib.util.find_spec("calibration.fem.output") is None:
        out_dir = None  # the FEM engine's field output is not available: no VTK/PNG pictures
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
    p_probe = 1.0
    elastic = solve_load_path(mesh, material, load, [p_probe], disc=disc, probes=probes,
                              options=SolverOptions(dirichlet=dirichlet, linear_solver=linear_solver))
    p_y = local_first_yield_MPa(disc, elastic, material, mesh_settings.yield_search_radius_factor * geometry.b_mm)
    h_el = elastic.history[-1]
    c_el_abs = h_el.u_centre_mm / p_probe
    c_el = {k: (h_el.u_centre_mm - v) / p_probe for k, v in h_el.probes_mm.items()}
    require(math.isfinite(p_y) and p_y > 0 and c_el["ref"] > 0, "indentation",
            f"elastic solution at y = {geometry.y_mm:g} mm is degenerate (p_y = {p_y}, compliance {c_el['ref']})")
    if progress:
        progress(1)
    # unloading in one step (cut on failure like any step): it is elastic up to reverse plasticity, and the
    # many small steps it took before were a third of the increments (benchmarks/bench_fem.py)
    # rtol 1e-6 / etol 1e-8: the dents agree with 1e-8 / 1e-10 to 1e-7 relative at 22 % fewer solves (measured,
    # docs/calibration.md)
    opts = SolverOptions(max_increment_MPa=load_settings.max_increment_factor * p_y, dirichlet=dirichlet,
                         linear_solver=linear_solver, max_unload_increment_MPa=load_settings.max_factor * p_y,
                         rtol=1e-6, etol=1e-8,
                         output_label=f"{profile.body} {profile.name}, y = {geometry.y_mm:g} mm ({model.upper()})")
    levels = _levels(p_y, load_settings)
    peaks = sorted(f * p_y for f in load_settings.unload_factors)
    top = max(peaks) if peaks else None
    state, history, newton = None, [], 0
    output_s = 0.0  # field output (VTU series, PNGs), kept out of the FEM time
    residuals, files = [], []
    stage_ends = sorted(set(peaks + [levels[-1]]))
    series = None
    if out_dir is not None:  # every converged level of the path as a ParaView time series
        from calibration.fem.output import FieldSeries

        t_out = time.perf_counter()
        series = FieldSeries(Path(out_dir) / "load_path", material)
        series(disc, SolverState.virgin(disc))  # step 0: the unloaded body
        output_s += time.perf_counter() - t_out
    start, branch = 0.0, None
    for end in stage_ends:
        stage = [p for p in levels if start < p <= end + 1e-9 * end]
        write = out_dir is not None and top is not None and abs(end - top) <= 1e-9 * top
        res = solve_load_path(mesh, material, load, stage, options=opts, initial_state=state, disc=disc,
                              vtk_at=[len(stage) - 1] if write else (), out_dir=out_dir / "peak" if write else None,
                              probes=probes, on_level=series, branch_points=branch)
        state, branch = res.state, res.branch_points  # the next stage extrapolates this loading branch
        output_s += res.output_seconds
        history += res.history
        files += [str(f) for f in res.files]
        newton += sum(h.newton_iters for h in res.history)
        if any(abs(end - pk) <= 1e-9 * pk for pk in peaks):
            unl = solve_load_path(mesh, material, load, [0.0], options=opts, initial_state=state, disc=disc,
                                  vtk_at=[0] if write else (), out_dir=out_dir / "unloaded" if write else None,
                                  probes=probes, on_level=series)
            h = unl.history[-1]
            residuals.append(h.u_centre_mm - h.probes_mm["ref"])
            newton += sum(h.newton_iters for h in unl.history)
            output_s += unl.output_seconds
            files += [str(f) for f in unl.files]
        if progress:
            progress(1)
        start = end
    if series is not None:
        t_out = time.perf_counter()
        files += [str(p) for _, p in series.steps] + [str(series.write_pvd())]
        output_s += time.perf_counter() - t_out
    p = np.array([0.0] + [h.p0_MPa for h in history])
    u_abs = np.array([0.0] + [h.u_centre_mm for h in history])
    u_pl_depth = {}
    for name in factors:
        rel = u_abs - np.array([0.0] + [h.probes_mm[name] for h in history])
        pl = rel - c_el[name] * p
        pl[p <= p_y] = np.maximum(pl[p <= p_y], 0.0)
        u_pl_depth[name] = pl
    u_pl = u_pl_depth.pop("ref")
    u = u_abs - np.array([0.0] + [h.probes_mm["ref"] for h in history])
    u_pl_at_peaks = np.interp(peaks, p, u_pl)
    c_hs = halfspace_centre_compliance_mm_per_MPa(geometry.a_mm, geometry.b_mm, material.E_MPa, material.poisson)
    return IndentationResult(model, p.tolist(), u.tolist(), u_pl.tolist(), float(p_y),
                             float(elastic.first_yield_p0_MPa), float(c_el["ref"]), float(c_hs),
                             [float(x) for x in peaks], [float(x) for x in residuals],
                             (np.array(residuals) - u_pl_at_peaks).tolist(), int(disc.n_dofs),
                             int(mesh.t.shape[1]), int(newton), time.perf_counter() - t0 - output_s, files,
                             reference_depth_mm=float(factors["ref"] * length) if factors["ref"] > 0 else None,
                             u_centre_abs_mm=u_abs.tolist(), fem_absolute_compliance_mm_per_MPa=float(c_el_abs),
                             u_pl_depth_mm={k: v.tolist() for k, v in u_pl_depth.items()},
                             output_seconds=float(output_s),
                             **_solver_counts(disc))
