"""Incremental Newton driver for small-strain J2 elastoplasticity on scikit-fem meshes (units mm, N, MPa).

Public API (used by the calibration)::

    path = LoadPath(mesh, material, load, p0_levels_MPa, options=SolverOptions())
    for level in path.levels():
        level.increments, level.state   # one LevelRecord per requested level, as it converges
    for inc in path.increments(p0_MPa):  # or the increments towards one level, as they converge
        inc.p0_MPa, path.state
    res = solve_load_path(mesh, material, load, p0_levels_MPa, options=SolverOptions(), vtk_at=(), out_dir=None)
    res.history            # list[Increment]: p0_MPa, u_centre_mm (into the body), n_plastic, newton_iters, ...
    res.first_yield_p0_MPa # p0 at which the first quadrature point yields (scaled elastic solution)
    res.state              # SolverState at the last level (restart: solve_load_path(..., initial_state=state))

Each requested level p0 is reached from the previous one in increments no larger than
``options.max_increment_MPa``; an increment whose Newton iteration fails is halved (recursively) down to
``options.min_increment_fraction`` of the requested step, then ``ConvergenceError`` reports the load level and
the residual history. Convergence requires BOTH ``|r_k| <= rtol * max(|f_ext|, |f_int|)`` and the energy
norm of the residual ``r_k . P^-1 r_k <= etol * r_0 . P^-1 r_0`` (P: the stiffness factorisation at hand,
elastic or a recent tangent; one extra back-substitution per iteration).

The options, states and records are in :mod:`calibration.fem.solver_state`, one Newton increment in
:mod:`calibration.fem.newton`, the assembled problem in :mod:`calibration.fem.problem`, the constraints in
:mod:`calibration.fem.boundary`.

Stiffness: K_e is assembled and factorised once (PARDISO: in single precision by default, refined in double
where a solve is used directly); the tangent is ``K_e + sum_plastic_elements (K_ep - K_e)``, applied matrix-free in
CG (assembled only to be factorised).
Strategies (``options.strategy``): 'newton' (factorise the consistent tangent each iteration), 'pcg'
(conjugate gradients on the consistent tangent preconditioned by the last factorisation: the elastic one
at first, refreshed with the current tangent when CG needs many iterations; default, see benchmarks/bench_fem.py), 'modified' (elastic stiffness only).
Boundary conditions: homogeneous Dirichlet on named boundaries, default "fixed" -> all components and
"symmetry" -> u_x (component 0) when present.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import skfem

from calibration.fem.assembly import Discretisation, discretise
from calibration.fem.linear_solvers import resolve_backend
from calibration.fem.material import J2Material
from calibration.fem.boundary import dirichlet_dofs
from calibration.fem.newton import newton_increment
from calibration.fem.problem import TangentProblem, elastic_first_yield
from calibration.fem.solver_state import (STRATEGIES, FemResult, Increment, SolverOptions, SolverState, load_state,
                                          save_state)
from wrlayer.errors import ConvergenceError, require


@dataclass(frozen=True)
class LevelRecord:
    """One requested level of a load path, converged. index: its place in the requested levels; p0_MPa: the
    level (MPa); increments: the converged increments that reached it (automatic sub-steps included); state: the
    converged state there; branch_points: the last (up to three) converged (p0 in MPa, u in mm) points of the
    monotone branch (restart with ``branch_points=``); files: the VTK/PNG files written at it; output_seconds:
    wall time (s) of its field output (``on_level`` and the files)."""

    index: int
    p0_MPa: float
    increments: tuple[Increment, ...]
    state: SolverState
    branch_points: list[tuple[float, np.ndarray]]
    files: tuple[Path, ...] = ()
    output_seconds: float = 0.0


def probe_values(probes: dict | None, u: np.ndarray) -> dict[str, float]:
    """The values of ``probes`` ({name: sparse 1 x n_dofs functional or callable u -> float}) at ``u`` (mm)."""
    out = {}
    for name, op in (probes or {}).items():
        out[name] = float(op(u)) if callable(op) else float(np.ravel(op @ u)[0])
    return out


class LoadPath:
    """The load path p0_levels_MPa (MPa; may go up and down) of one problem, followed level by level with
    :meth:`levels`; the arguments are those of :func:`solve_load_path`. Builds (or reuses, from ``disc``'s cache)
    the nodal forces, the elastic stiffness and its factorisation and the elastic first-yield solution."""

    def __init__(self, mesh: skfem.Mesh, material: J2Material, load, p0_levels_MPa: Iterable[float],
                 options: SolverOptions | None = None, initial_state: SolverState | None = None,
                 disc: Discretisation | None = None, probes: dict | None = None,
                 branch_points: list[tuple[float, np.ndarray]] | None = None):
        opts = options or SolverOptions()
        opts.validate()
        require(isinstance(material, J2Material), "material", "must be a J2Material")
        self.requested = [float(p) for p in p0_levels_MPa]
        require(len(self.requested) > 0, "p0_levels_MPa", "must contain at least one level")
        require(all(math.isfinite(p) and p >= 0 for p in self.requested), "p0_levels_MPa",
                f"must be finite and >= 0 MPa, got {self.requested}")
        self.disc = disc if disc is not None else discretise(mesh, opts.order)
        self.material, self.opts, self.probes = material, opts, probes
        self._prepare(load)
        state = initial_state if initial_state is not None else SolverState.virgin(self.disc)
        if initial_state is not None:
            require(state.u_mm.shape == (self.disc.n_dofs,), "initial_state",
                    f"has {state.u_mm.size} dofs, the discretisation {self.disc.n_dofs}")
        self.state = state
        self.yielded_before = bool(np.any(state.eq_plastic_strain > 0))
        # converged (p0, u) points of the monotone branch leading to ``state`` (last = state), for the predictor
        branch = list(branch_points or [])
        self.branch = branch if branch and branch[-1][0] == state.p0_MPa else [(state.p0_MPa, state.u_mm)]

    def _prepare(self, load) -> None:
        disc, opts, material = self.disc, self.opts, self.material
        load_key = ("load", repr(load))
        prepared = disc.problem_cache.get(load_key)
        if prepared is None:  # nodal forces of the same load are reused across calls on this discretisation
            prepared = load.prepare(disc.basis)
        key = (material, None if opts.dirichlet is None else tuple(sorted((k, tuple(v)) for k, v in
                                                                          opts.dirichlet.items())),
               resolve_backend(opts.linear_solver), opts.strategy == "modified", opts.factor_precision)
        prob = disc.problem_cache.get(key)
        if prob is None:  # assemble + factorise K_e once per discretisation, material and constraints
            disc.problem_cache.clear()
            prob = TangentProblem(disc, material, dirichlet_dofs(disc, opts.dirichlet), opts)
            disc.problem_cache[key] = prob
        disc.problem_cache[load_key] = prepared
        prob.opts = opts
        if opts.strategy == "modified":
            prob.reset_to_elastic()
        fy_key = ("first_yield", load_key, key)
        if fy_key not in disc.problem_cache:  # an elastic solve (a CG when the kept factorisation is a tangent)
            disc.problem_cache[fy_key] = elastic_first_yield(prob, prepared.force_per_MPa)
        self.prob, self.prepared = prob, prepared
        self.first_yield_p0_MPa, self.u_unit = disc.problem_cache[fy_key]

    def levels(self, vtk_at: Iterable[int] | str = (), out_dir: str | Path | None = None,
               on_level=None) -> Iterator[LevelRecord]:
        """One :class:`LevelRecord` per requested level as it converges (see :func:`solve_load_path` for
        ``vtk_at``, ``out_dir`` and ``on_level``); ConvergenceError when a step is cut below the floor."""
        vtk_idx = set(range(len(self.requested))) if vtk_at == "all" else {int(i) for i in vtk_at}
        require(not vtk_idx or out_dir is not None, "out_dir", "must be given when vtk_at is not empty")
        for k, target in enumerate(self.requested):
            increments = list(self.increments(target))
            files: list[Path] = []
            t_out = time.perf_counter()
            if on_level is not None:
                on_level(self.disc, self.state, self.prepared)
            if k in vtk_idx:
                from calibration.fem.output import write_increment_output  # pyvista/matplotlib only for pictures

                files += write_increment_output(self.disc, self.state, self.material, self.prepared, Path(out_dir),
                                                k, label=self.opts.output_label)
            output_s = time.perf_counter() - t_out if on_level is not None or k in vtk_idx else 0.0
            yield LevelRecord(k, target, tuple(increments), self.state, list(self.branch), tuple(files), output_s)

    def increments(self, target: float) -> Iterator[Increment]:
        """The converged increments from the current state to ``target`` (MPa), one at a time (after each,
        :attr:`state` is its state): steps of at most the options' largest increment, halved on a failed Newton
        iteration (down to the floor; then ConvergenceError), grown back after a success."""
        opts, prob, prepared = self.opts, self.prob, self.prepared
        max_iter = opts.max_newton * (10 if opts.strategy == "modified" else 1)
        start = self.state.p0_MPa
        max_step = opts.max_increment_MPa
        if target < start and opts.max_unload_increment_MPa is not None:
            max_step = opts.max_unload_increment_MPa
        n_sub = 1 if max_step is None else max(1, math.ceil(abs(target - start) / max_step - 1e-9))
        step_req = (target - start) / n_sub
        floor = abs(step_req) * opts.min_increment_fraction
        step = step_req
        while True:
            state = self.state
            remaining = target - state.p0_MPa
            if abs(step) > abs(remaining):
                step = remaining
            # the last sub-step lands exactly on the target (no round-off residue of summed steps)
            p_new = target if abs(remaining - step) <= 1e-9 * max(abs(step_req), abs(target)) else state.p0_MPa + step
            u_start, elastic_start = self._predictor(p_new)
            try:
                state_new, info = newton_increment(prob, state, prepared.force_per_MPa, state.p0_MPa, p_new,
                                                   max_iter, p_scale=max(abs(start), abs(target)),
                                                   u_start=u_start, elastic_start=elastic_start)
            except ConvergenceError as err:
                self.branch = [(state.p0_MPa, state.u_mm)]  # the cut step restarts from the converged state
                if abs(step) / 2 < floor * (1 - 1e-12) or step == 0.0:
                    raise ConvergenceError(f"load step cut below the floor at p0 = {state.p0_MPa:.6g} MPa "
                                           f"towards {target:.6g} MPa: {err}") from None
                step /= 2
                prob.reset_to_elastic()
                if opts.verbose:
                    print(f"  cutting the step to {step:.6g} MPa")
                continue
            yield self._accept(p_new, state_new, info, p_new == target)
            step = step_req if abs(2 * step) >= abs(step_req) else 2 * step  # grow back after a cut
            if p_new == target:
                return

    def _predictor(self, p_new: float) -> tuple[np.ndarray | None, bool]:
        """(first Newton iterate or None, whether it is the elastic predictor) of the increment to p_new."""
        opts, state, branch = self.opts, self.state, self.branch
        if opts.predictor and (p_new - state.p0_MPa) * _direction(branch) > 0:
            # extrapolation of the converged branch in the same direction (quadratic through its last three
            # points when it has them, else linear)
            return extrapolate(branch[-3:] if opts.predictor_order == 2 else branch[-2:], p_new), False
        if opts.elastic_predictor and (p_new < state.p0_MPa or not self.yielded_before):
            # elastic unloading / elastic loading of a virgin body: exact unless some point (re-)yields
            return state.u_mm + (p_new - state.p0_MPa) * self.u_unit, True
        return None, False

    def _accept(self, p_new: float, state_new: SolverState, info: dict, requested: bool) -> Increment:
        """Make the converged increment the current state (and the branch's last point); its record."""
        if (p_new - self.state.p0_MPa) * _direction(self.branch) < 0:
            self.branch = [self.branch[-1]]  # the direction of loading changed: a new branch
        self.branch = (self.branch + [(p_new, state_new.u_mm)])[-3:]
        self.state = state_new
        n_yielded = int(np.count_nonzero(state_new.eq_plastic_strain > 0))
        fy = (not self.yielded_before) and n_yielded > 0
        self.yielded_before = self.yielded_before or fy
        if self.opts.verbose:
            print(f"  p0 = {p_new:.6g} MPa: {info['iters']} iterations, {info['n_plastic']} plastic points")
        return Increment(p_new, self.prepared.centre_displacement_mm(state_new.u_mm), info["n_plastic"], n_yielded,
                         info["iters"], info["residuals"], info["energies"], fy, requested, info["cg_iters"],
                         probe_values(self.probes, state_new.u_mm))


def solve_load_path(mesh: skfem.Mesh, material: J2Material, load, p0_levels_MPa: Iterable[float],
                    options: SolverOptions | None = None, vtk_at: Iterable[int] | str = (),
                    out_dir: str | Path | None = None, initial_state: SolverState | None = None,
                    disc: Discretisation | None = None, probes: dict | None = None,
                    on_level=None, branch_points: list[tuple[float, np.ndarray]] | None = None) -> FemResult:
    """Follow the load path p0_levels_MPa (MPa; may go up and down) and return a :class:`FemResult`.

    mesh: skfem MeshTri1/2 (plane strain, coordinates (y, z)) or MeshTet1/2 (3D, (x, y, z)) with named
    boundaries; load: HertzLoad / UniformPressure (anything with ``prepare(basis)``); vtk_at: indices into
    p0_levels_MPa (or "all") at which VTK (.vtu) and PNG files are written to out_dir; initial_state: restart
    from a saved state (its p0_MPa is the starting level); disc: a prebuilt discretisation of ``mesh`` (reuse it
    across calls: it also caches the elastic stiffness and its factorisation for the same material/constraints);
    probes: {name: linear functional (sparse 1 x n_dofs or a callable u -> float)} recorded in each increment's
    ``probes_mm``; on_level: called as ``on_level(disc, state, prepared)`` after each level of the path has
    converged (e.g. to write a field time series, :func:`calibration.fem.output.FieldSeries`); branch_points:
    the converged (p0, u) points of the monotone branch that led to ``initial_state`` (its last point; a previous
    result's ``branch_points``), so that the predictor extrapolates across calls (ignored when the last point is
    not at the start level).
    """
    path = LoadPath(mesh, material, load, p0_levels_MPa, options, initial_state, disc, probes, branch_points)
    records = list(path.levels(vtk_at, out_dir, on_level))
    return FemResult([h for r in records for h in r.increments], path.first_yield_p0_MPa, path.state,
                     path.prepared.centre_mm, path.disc.n_dofs, [f for r in records for f in r.files], path.branch,
                     sum(r.output_seconds for r in records))


def _direction(branch: list[tuple[float, np.ndarray]]) -> float:
    """p0 change of the branch's last step (0 for a single point: no direction yet)."""
    return branch[-1][0] - branch[-2][0] if len(branch) >= 2 else 0.0


def extrapolate(points: list[tuple[float, np.ndarray]], p: float) -> np.ndarray:
    """Lagrange extrapolation of converged (p0, u) points (2 or 3, distinct p0) to p0 = p."""
    ps = [q for q, _ in points]
    out = np.zeros_like(points[-1][1])
    for i, (pi, ui) in enumerate(points):
        w = 1.0
        for j, pj in enumerate(ps):
            if j != i:
                w *= (p - pj) / (pi - pj)
        out += w * ui
    return out


__all__ = ["FemResult", "Increment", "LevelRecord", "LoadPath", "STRATEGIES", "SolverOptions", "SolverState",
           "extrapolate", "load_state", "probe_values", "save_state", "solve_load_path"]
