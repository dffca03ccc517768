"""One calibration position: mesh, elastoplastic Hertzian indentation with unloading branches -> raw
characteristic points (units mm, N, MPa).

Definition of the layer characteristic at a position (documented in the README):

- The FEM model (2D plane-strain section or 3D local half model) is loaded by the Hertzian pressure with the
  position's semi-axes; p0 rises monotonically to ``max_factor`` times the FEM first-yield pressure p_y (first
  yield within a few semi-axes of the load centre; see :func:`local_first_yield_MPa`).
- u_FEM(p0) is the normal displacement of the load centre (into the body). Its elastic part on the SAME mesh is
  c_el p0 (c_el from the linear solution), so the inelastic part u_pl(p0) = u_FEM(p0) - c_el p0 is free of the
  mesh's and the finite section's elastic error. With elastic unloading u_pl equals the residual dent; the FEM
  unloading runs from several peaks check this (``reverse_plasticity_mm`` = u_res,FEM - u_pl at the peak).
- The layer's elastic part is a stated small fraction f (``elastic_fraction``) of the half-space centre
  displacement of this body under the same Hertz pressure, c_hs p0 (the contact solver computes the half-space
  part itself), so S_1 = 1 / (f c_hs).
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

from calibration.fem.elastoplastic_solver import SolverOptions, solve_load_path
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
    First yield is searched within yield_search_radius_factor * b of the load centre."""

    elements_per_semi_axis: float = 8.0
    h_max_mm: float = 6.0
    order: int = 2
    depth_mm: float | None = None
    rail_support_below_mm: float | None = 35.0
    length_factor: float = 5.0
    grading: float = 0.3
    yield_search_radius_factor: float = 3.0


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
    structural stress concentration); compliances in mm/MPa; ``files``: VTK/PNG outputs."""

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
    box = (1.2 * geometry.a_mm, 1.2 * geometry.b_mm, 1.0 * geometry.b_mm)
    return local_mesh(profile, geometry.y_mm, h_min, h_max, length_mm=length, depth_mm=mesh.depth_mm,
                      order=mesh.order, refine_box=box, grading=mesh.grading)


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


def _levels(p_y: float, load: LoadSettings) -> list[float]:
    above = p_y * np.linspace(1.0, load.max_factor, load.n_levels + 1)[1:]
    peaks = [f * p_y for f in load.unload_factors]
    return sorted(set([0.5 * p_y, p_y] + above.tolist() + peaks))


def indent(profile, geometry: LocalGeometry, material: J2Material, model: str = "2d",
           mesh_settings: MeshSettings = MeshSettings(), load_settings: LoadSettings = LoadSettings(),
           out_dir: Path | None = None, progress=None, linear_solver: str = "auto") -> IndentationResult:
    """Run the indentation of one position; ``progress(n)`` is called after each load stage (optional);
    linear_solver: 'auto' | 'pardiso' | 'scipy' (SuperLU: faster for small 2D sections on a busy machine).

    VTK/PNG fields at the highest peak and after unloading from it are written to ``out_dir`` when given.
    Raises ConvergenceError (FEM) or InputError (geometry, mesh) naming the cause.
    """
    require(model in ("2d", "3d"), "model", f"must be '2d' or '3d', got {model!r}")
    require(all(0 < f <= load_settings.max_factor + 1e-12 for f in load_settings.unload_factors), "unload_factors",
            f"must lie in (0, max_factor = {load_settings.max_factor}], got {list(load_settings.unload_factors)}")
    t0 = time.perf_counter()
    if out_dir is not None and importlib.util.find_spec("calibration.fem.output") is None:
        out_dir = None  # the FEM engine's field output is not available: no VTK/PNG pictures
    mesh = build_mesh(profile, geometry, model, mesh_settings)
    disc = discretise(mesh, mesh_settings.order)
    dirichlet = None
    if profile.body == "rail" and mesh_settings.rail_support_below_mm is not None:
        dirichlet = add_support_boundary(mesh, mesh_settings.rail_support_below_mm)
    load = HertzLoad(geometry.y_mm, geometry.b_mm, geometry.a_mm if model == "3d" else None,
                     z0_mm=geometry.z_mm)
    p_probe = 1.0
    elastic = solve_load_path(mesh, material, load, [p_probe], disc=disc, options=SolverOptions(dirichlet=dirichlet, linear_solver=linear_solver))
    p_y = local_first_yield_MPa(disc, elastic, material, mesh_settings.yield_search_radius_factor * geometry.b_mm)
    c_el = elastic.history[-1].u_centre_mm / p_probe
    require(math.isfinite(p_y) and p_y > 0 and c_el > 0, "indentation",
            f"elastic solution at y = {geometry.y_mm:g} mm is degenerate (p_y = {p_y}, compliance {c_el})")
    if progress:
        progress(1)
    opts = SolverOptions(max_increment_MPa=load_settings.max_increment_factor * p_y, dirichlet=dirichlet,
                         linear_solver=linear_solver)
    levels = _levels(p_y, load_settings)
    peaks = sorted(f * p_y for f in load_settings.unload_factors)
    top = max(peaks) if peaks else None
    state, history, newton = None, [], 0
    residuals, files = [], []
    stage_ends = sorted(set(peaks + [levels[-1]]))
    start = 0.0
    for end in stage_ends:
        stage = [p for p in levels if start < p <= end + 1e-9 * end]
        write = out_dir is not None and top is not None and abs(end - top) <= 1e-9 * top
        res = solve_load_path(mesh, material, load, stage, options=opts, initial_state=state, disc=disc,
                              vtk_at=[len(stage) - 1] if write else (), out_dir=out_dir / "peak" if write else None)
        state = res.state
        history += res.history
        files += [str(f) for f in res.files]
        newton += sum(h.newton_iters for h in res.history)
        if any(abs(end - pk) <= 1e-9 * pk for pk in peaks):
            unl = solve_load_path(mesh, material, load, [0.0], options=opts, initial_state=state, disc=disc,
                                  vtk_at=[0] if write else (), out_dir=out_dir / "unloaded" if write else None)
            residuals.append(unl.history[-1].u_centre_mm)
            newton += sum(h.newton_iters for h in unl.history)
            files += [str(f) for f in unl.files]
        if progress:
            progress(1)
        start = end
    p = np.array([0.0] + [h.p0_MPa for h in history])
    u = np.array([0.0] + [h.u_centre_mm for h in history])
    u_pl = u - c_el * p
    u_pl[p <= p_y] = np.maximum(u_pl[p <= p_y], 0.0)
    u_pl_at_peaks = np.interp(peaks, p, u_pl)
    c_hs = halfspace_centre_compliance_mm_per_MPa(geometry.a_mm, geometry.b_mm, material.E_MPa, material.poisson)
    return IndentationResult(model, p.tolist(), u.tolist(), u_pl.tolist(), float(p_y),
                             float(elastic.first_yield_p0_MPa), float(c_el), float(c_hs),
                             [float(x) for x in peaks], [float(x) for x in residuals],
                             (np.array(residuals) - u_pl_at_peaks).tolist(), int(disc.n_dofs),
                             int(mesh.t.shape[1]), int(newton), time.perf_counter() - t0, files)
