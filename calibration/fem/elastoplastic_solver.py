"""Incremental Newton driver for small-strain J2 elastoplasticity on scikit-fem meshes (units mm, N, MPa).

Public API (used by the calibration)::

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

import io
import math
import time
from collections.abc import Iterable, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np
import skfem

from calibration.fem.assembly import Discretisation, discretise
from calibration.fem.linear_solvers import PRECISIONS, Factoriser, preconditioned_cg, resolve_backend
from calibration.fem.material import J2Material, von_mises_MPa
from calibration.fem.return_mapping import radial_return
from wrlayer.atomic_write import atomic_write_bytes
from wrlayer.errors import ConvergenceError, InputError, require

STRATEGIES = ("pcg", "newton", "modified")


@dataclass
class SolverOptions:
    """Numerical options. rtol: relative residual tolerance; etol: relative energy tolerance; max_newton:
    iterations per increment (modified Newton gets 10x); max_increment_MPa: largest p0 step (None: the requested
    levels only); min_increment_fraction: step-cut floor relative to the requested step; linear_solver:
    'auto' | 'pardiso' | 'scipy'; strategy: 'pcg' | 'newton' | 'modified'; order: element order (None: the
    mesh's own); dirichlet: {boundary name: components (0=x/y.., 1, 2)} replacing the default
    {"fixed": all, "symmetry": [0]}; cg_rtol: inner CG tolerance relative to the residual; cg_refresh_iters: refactorise the CG
    preconditioner with the current tangent when CG needed more iterations than this; predictor: start each
    increment from the extrapolation of the converged loading branch in the same direction (``predictor_order``); output_label: heads the titles
    of the PNG pictures (e.g. body and position); max_unload_increment_MPa:
    largest step towards a LOWER level (None: max_increment_MPa; unloading is nearly elastic, so one step usually
    converges, and a failed step is cut as any other); factor_precision: 'single' (default) or 'double'
    factorisations with PARDISO (single: 0.6x the solve and factorisation time at 62k dofs; the factorisation only
    preconditions CG or is refined in double precision, so the converged states agree to the Newton tolerance,
    docs/calibration.md "Speed"; SuperLU is always double); cg_forcing: 'fixed' (every CG to cg_rtol) or
    'adaptive' (Eisenstat-Walker: the CG tolerance of Newton iteration k is gamma (|r_k| / |r_k-1|)^2, at most
    cg_rtol_max and at least cg_rtol, and the first iteration's cg_rtol_max: the early corrections of an increment
    are limited by the change of the plastic zone, not by the linear solve); elastic_predictor: start an
    increment from a virgin state, and every unloading increment, from the elastic solution (the state plus
    (p_new - p_old) times the unit-load elastic displacement): elastic loading converges without an iteration,
    and so does an elastic unloading (the return mapping of the residual check verifies that no point re-yields;
    if some do, Newton continues from there); predictor_order: 2 (default) extrapolates the last three converged
    points of the loading branch quadratically in p0, 1 the last two linearly (measured on the default 3D
    calibration: 7-13 % fewer triangular solves than linear, with the branch carried across load stages,
    docs/calibration.md "Speed")."""

    rtol: float = 1e-8
    etol: float = 1e-10
    max_newton: int = 25
    max_increment_MPa: float | None = None
    min_increment_fraction: float = 1.0 / 64.0
    linear_solver: str = "auto"
    strategy: str = "pcg"
    order: int | None = None
    dirichlet: dict[str, Sequence[int]] | None = None
    cg_rtol: float = 1e-3
    cg_refresh_iters: int = 12
    predictor: bool = True
    output_label: str = ""
    max_unload_increment_MPa: float | None = None
    verbose: bool = False
    factor_precision: str = "single"
    cg_forcing: str = "adaptive"
    cg_rtol_max: float = 0.1
    elastic_predictor: bool = True
    predictor_order: int = 2

    def validate(self) -> None:
        require(0 < self.rtol < 1, "rtol", f"must be in (0, 1), got {self.rtol}")
        require(0 < self.etol < 1, "etol", f"must be in (0, 1), got {self.etol}")
        require(self.max_newton >= 1, "max_newton", f"must be >= 1, got {self.max_newton}")
        require(self.max_increment_MPa is None or self.max_increment_MPa > 0, "max_increment_MPa",
                f"must be > 0 or None, got {self.max_increment_MPa}")
        require(0 < self.min_increment_fraction <= 1, "min_increment_fraction",
                f"must be in (0, 1], got {self.min_increment_fraction}")
        require(self.strategy in STRATEGIES, "strategy", f"must be one of {STRATEGIES}, got {self.strategy!r}")
        resolve_backend(self.linear_solver)
        require(self.cg_forcing in ("fixed", "adaptive"), "cg_forcing",
                f"must be 'fixed' or 'adaptive', got {self.cg_forcing!r}")
        require(0 < self.cg_rtol <= self.cg_rtol_max < 1, "cg_rtol",
                f"need 0 < cg_rtol <= cg_rtol_max < 1, got {self.cg_rtol}, {self.cg_rtol_max}")
        require(self.predictor_order in (1, 2), "predictor_order",
                f"must be 1 (linear) or 2 (quadratic), got {self.predictor_order!r}")
        require(self.factor_precision in PRECISIONS, "factor_precision",
                f"must be one of {PRECISIONS}, got {self.factor_precision!r}")


@dataclass
class SolverState:
    """Converged state: displacement u_mm (n_dofs), Mandel plastic strain and back stress (n_elem, n_qp, 6),
    equivalent plastic strain (n_elem, n_qp), the load level p0_MPa and the stress (MPa, for output)."""

    u_mm: np.ndarray
    plastic_strain: np.ndarray
    back_stress_MPa: np.ndarray
    eq_plastic_strain: np.ndarray
    p0_MPa: float = 0.0
    stress_MPa: np.ndarray | None = None

    @classmethod
    def virgin(cls, disc: Discretisation) -> SolverState:
        shape = (disc.n_elements, disc.n_qp)
        return cls(np.zeros(disc.n_dofs), np.zeros(shape + (6,)), np.zeros(shape + (6,)), np.zeros(shape), 0.0,
                   np.zeros(shape + (6,)))

    def save_state(self, path: str | Path) -> Path:
        """Write the state to ``path`` (.npz) atomically."""
        buf = io.BytesIO()
        arrays = {k: v for k, v in asdict(self).items() if v is not None}
        arrays["p0_MPa"] = np.array(self.p0_MPa)
        np.savez(buf, **arrays)
        return atomic_write_bytes(path, buf.getvalue())


def save_state(state: SolverState, path: str | Path) -> Path:
    """Write ``state`` to ``path`` (.npz) atomically."""
    return state.save_state(path)


def load_state(path: str | Path) -> SolverState:
    """Read a state written by :func:`save_state`; InputError when missing or malformed."""
    path = Path(path)
    try:
        with np.load(path) as z:
            kw = {k: z[k] for k in z.files}
    except (OSError, ValueError) as err:
        raise InputError(str(path), f"cannot read solver state: {err}") from err
    try:
        kw["p0_MPa"] = float(kw["p0_MPa"])
        return SolverState(**kw)
    except (KeyError, TypeError) as err:
        raise InputError(str(path), f"not a solver state file: {err}") from err


@dataclass
class Increment:
    """One converged increment. p0_MPa: load level; u_centre_mm: normal displacement of the load centre,
    positive into the body; n_plastic: quadrature points yielding in this increment; n_yielded: points with
    eq. plastic strain > 0; newton_iters; residuals: relative residual norms per iteration (first = before the
    first solve); energies: relative energy norms; first_yield: first increment with plastic flow;
    requested: this p0 is one of the requested levels (else an automatic sub-step); cg_iters: inner CG
    iterations (pcg strategy); probes_mm: the values of the ``probes`` given to :func:`solve_load_path` (mm)."""

    p0_MPa: float
    u_centre_mm: float
    n_plastic: int
    n_yielded: int
    newton_iters: int
    residuals: list[float]
    energies: list[float]
    first_yield: bool = False
    requested: bool = True
    cg_iters: int = 0
    probes_mm: dict[str, float] = field(default_factory=dict)


@dataclass
class FemResult:
    """Result of :func:`solve_load_path`; see the module docstring. ``branch_points``: the last (up to three)
    converged (p0 in MPa, u in mm) points of the final monotone branch (restart with ``branch_points=``);
    ``output_seconds``: wall time (s) of the field output (``on_level`` and the VTK/PNG files of ``vtk_at``)."""

    history: list[Increment]
    first_yield_p0_MPa: float
    state: SolverState
    centre_mm: np.ndarray | None
    n_dofs: int
    files: list[Path] = field(default_factory=list)
    branch_points: list[tuple[float, np.ndarray]] = field(default_factory=list)
    output_seconds: float = 0.0


def dirichlet_dofs(disc: Discretisation, dirichlet: dict[str, Sequence[int]] | None) -> np.ndarray:
    """Indices of constrained dofs; InputError for unknown boundaries / components or a missing "fixed"."""
    mesh = disc.mesh
    names = sorted(mesh.boundaries) if mesh.boundaries else []
    dim = mesh.dim()
    if dirichlet is None:
        if "fixed" not in names:
            raise InputError("mesh", f"has no boundary named 'fixed' (boundaries: {names})")
        dirichlet = {"fixed": range(dim)}
        if "symmetry" in names:
            dirichlet["symmetry"] = [0]
    dofs = []
    for name, comps in dirichlet.items():
        if name not in names:
            raise InputError("dirichlet", f"mesh has no boundary named {name!r} (boundaries: {names})")
        comps = list(comps)
        require(all(isinstance(c, (int, np.integer)) and 0 <= c < dim for c in comps), "dirichlet",
                f"components of {name!r} must be integers in [0, {dim - 1}], got {comps}")
        view = disc.basis.get_dofs(name)
        dofs.append(view.all([f"u^{c + 1}" for c in comps]))
    out = np.unique(np.concatenate(dofs)).astype(np.int64)
    require(out.size > 0, "dirichlet", "constrains no degree of freedom")
    return out


class _Problem:
    """Assembled pieces shared by all increments of one solve.

    ``factor`` holds one factorisation: the elastic stiffness at first; with the 'pcg' strategy it is refreshed
    with the current consistent tangent whenever preconditioned CG needed more than ``cg_refresh_iters``
    iterations; with 'newton' it is the current tangent; with 'modified' it stays elastic.
    """

    def __init__(self, disc: Discretisation, material: J2Material, constrained: np.ndarray, opts: SolverOptions):
        self.disc, self.material, self.opts = disc, material, opts
        n = disc.n_dofs
        self.fixed = np.zeros(n, dtype=bool)
        self.fixed[constrained] = True
        rows = np.repeat(np.arange(n), np.diff(disc.csr_indptr))
        self.zero_mask = self.fixed[rows] | self.fixed[disc.csr_indices]
        self.diag_mask = (rows == disc.csr_indices) & self.fixed[rows]
        C = material.elastic_matrix()
        self.C_qp = np.broadcast_to(C, (disc.n_elements, disc.n_qp, 6, 6))
        self.C = C
        self.Ke_data = disc.csr_data(disc.element_matrices(self.C_qp))
        self.Ke_bc_data = self._bc(self.Ke_data.copy())  # with the Dirichlet rows/cols replaced
        self.Ke = disc.csr_matrix(self.Ke_bc_data)  # shares the array (never written after this): one copy less
        self.factor = Factoriser(disc.csr_indptr, disc.csr_indices, n, opts.linear_solver, opts.factor_precision)
        self.factor.factorise(self.Ke_bc_data)
        self.factor_is_elastic = True

    def reset_to_elastic(self) -> None:
        """Refactorise the elastic stiffness if the kept factorisation is a tangent (after a failed increment the
        tangent of a diverged iterate may be near-singular, so it must not precondition the cut step)."""
        if not self.factor_is_elastic:
            self.factor.factorise(self.Ke_bc_data)
            self.factor_is_elastic = True

    def _bc(self, data: np.ndarray) -> np.ndarray:
        data[self.zero_mask] = 0.0
        data[self.diag_mask] = 1.0
        return data

    def tangent_data(self, tangent: np.ndarray, plastic_elems: np.ndarray) -> np.ndarray:
        """CSR data of K_e + sum over plastic elements of (K_ep - K_e), Dirichlet rows/cols replaced."""
        data = self.Ke_data.copy()
        if plastic_elems.size:  # K_ep - K_e = B^T (C_ep - C) B: one product over the plastic elements only
            dK = self.disc.element_matrices(tangent[plastic_elems] - self.C, plastic_elems, selected=True)
            data += self.disc.csr_data(dK, plastic_elems)
        return self._bc(data)

    def tangent_matvec(self, tangent: np.ndarray, plastic_elems: np.ndarray):
        """x -> K_t x without assembling K_t: the elastic K_e x plus, over the plastic elements only, the element
        products (K_ep - K_e) x_e (Dirichlet rows/cols replaced as in :meth:`tangent_data`). Measured: the
        assembly of K_t's CSR data (copy, scatter, boundary conditions of all 5e6 entries at 62k dofs) cost more
        than all the matvecs of the CG that used it."""
        if plastic_elems.size == 0:
            return self.Ke.dot
        dK = self.disc.element_matrices(tangent[plastic_elems] - self.C, plastic_elems, selected=True)
        edofs = self.disc.element_dofs[plastic_elems]
        flat = edofs.ravel()
        fixed, n = self.fixed, self.disc.n_dofs

        def matvec(x: np.ndarray) -> np.ndarray:
            xf = np.where(fixed, 0.0, x)
            ye = np.matmul(dK, xf[edofs][:, :, None])[:, :, 0]
            y = self.Ke.dot(x) + np.bincount(flat, weights=ye.ravel(), minlength=n)
            y[fixed] = x[fixed]
            return y

        return matvec

    def solve_correction(self, r: np.ndarray, tangent: np.ndarray, plastic_elems: np.ndarray,
                         cg_rtol: float | None = None) -> tuple[np.ndarray, int, float | None]:
        """Newton correction for residual r (free dofs) with the chosen strategy; returns (du, cg iterations,
        r . P^-1 r with the factorisation P at hand on entry, or None when not computed: the 'newton' strategy).
        cg_rtol: the CG tolerance of this correction (default options.cg_rtol)."""
        cg_rtol = self.opts.cg_rtol if cg_rtol is None else cg_rtol
        strategy = self.opts.strategy
        if strategy == "modified":
            du = self.factor.solve(r)
            return du, 0, float(r @ du)
        info: dict = {}
        if plastic_elems.size == 0 and self.factor_is_elastic:  # exact up to the Newton tolerance
            return self.factor.solve_refined(r, self.Ke.dot, rtol=1e-2 * self.opts.rtol, info=info), 0, info["rz0"]
        if strategy == "newton":
            data = self.tangent_data(tangent, plastic_elems)
            self.factor.factorise(data)
            self.factor_is_elastic = plastic_elems.size == 0
            return self.factor.solve_refined(r, self.disc.csr_matrix(data).dot, rtol=cg_rtol), 0, None
        du, iters = preconditioned_cg(self.tangent_matvec(tangent, plastic_elems), r, self.factor.solve,
                                      rtol=cg_rtol, max_iter=500, info=info)
        if iters > self.opts.cg_refresh_iters:
            self.factor.factorise(self.tangent_data(tangent, plastic_elems))
            self.factor_is_elastic = plastic_elems.size == 0
        return du, iters, info["rz0"]


def _newton_increment(prob: _Problem, state: SolverState, force: np.ndarray, p_old: float, p_new: float,
                      max_iter: int, p_scale: float = 0.0, u_start: np.ndarray | None = None,
                      elastic_start: bool = False):
    """Newton iteration from the converged ``state`` at p_old to p_new. Returns (new state, info) or raises
    ConvergenceError with the residual history.

    Converged when |r_k| <= rtol * max(|f_ext|, |f_int|) and r_k . P^-1 r_k <= etol * r_0 . P^-1 r_0 (energy
    norm of the residual; P the current factorisation: elastic or a recent tangent). ``u_start``: the first
    iterate (a predictor; default the converged displacement); elastic_start: u_start is the state plus the
    elastic solution of the load change (then accepted without iteration when no point yields and the force
    residual passes).
    """
    disc, mat, opts = prob.disc, prob.material, prob.opts
    free = ~prob.fixed
    u = (state.u_mm if u_start is None else u_start).copy()
    f_ext = p_new * force
    # reference force: the largest of the increment's ends and of the load level being approached (p_scale), so
    # that the last sub-step of an unloading to zero is still measured against the level's load, not against 0
    f_ref_ext = max(abs(p_new), abs(p_old), abs(p_scale)) * np.linalg.norm(force[free])
    residuals, energies = [], []
    e0 = None
    cg_total = 0
    for it in range(max_iter + 1):
        res = radial_return(mat, disc.strain(u), state.plastic_strain, state.back_stress_MPa,
                            state.eq_plastic_strain, with_tangent=opts.strategy != "modified")
        f_int = disc.internal_force(res.stress_MPa)
        r = f_ext - f_int
        r[prob.fixed] = 0.0
        ref = max(f_ref_ext, np.linalg.norm(f_int[free]), 1e-300)
        rnorm = np.linalg.norm(r) / ref
        if not math.isfinite(rnorm):
            break
        residuals.append(rnorm)
        # nothing to do (the same level again, or an exact elastic predictor; 1e-13: round-off, which a tighter
        # rtol could not pass through the energy norm)
        # an elastic predictor that no point contradicts (the return mapping just run found no plastic point) is
        # exact: the residual is what the converged start state left (<= rtol), no iteration is needed
        elastic_exact = elastic_start and it == 0 and rnorm <= opts.rtol and not res.plastic.any()
        if elastic_exact or (it == 0 and rnorm <= max(1e-3 * opts.rtol, 1e-13)):
            energies.append(0.0)
            return _converged(u, res, p_new, it, residuals, energies, cg_total)
        # energy norm of the residual (current factorisation): one back-substitution, so it is evaluated only
        # on the first iteration (the reference) and once the force residual has passed (measured: this
        # halves the triangular solves of a 3D indentation, benchmarks/bench_fem.py). The reference r_0 . P^-1 r_0
        # is the first preconditioner application of the first correction (no solve of its own), except with
        # the 'newton' strategy, which refactorises first.
        if it == 0 and opts.strategy != "newton":
            energies.append(1.0)  # e0 is set from the first correction below
        elif it == 0 or rnorm <= opts.rtol:
            energy = abs(float(r @ prob.factor.solve(r)))
            e0 = energy if e0 is None else e0
            energies.append(energy / max(e0, 1e-300))
        else:
            energies.append(float("nan"))
        if opts.verbose:
            print(f"    p0={p_new:.6g} it={it} |r|/ref={rnorm:.3e} energy={energies[-1]:.3e}")
        # an increment that started below the force tolerance (an exact elastic predictor) has a round-off energy
        # reference: after one correction the force criterion alone decides
        if rnorm <= opts.rtol and (energies[-1] <= opts.etol or (it >= 1 and residuals[0] <= opts.rtol)):
            return _converged(u, res, p_new, it, residuals, energies, cg_total)
        if it == max_iter or rnorm > 1e6 or (it >= 4 and rnorm > 10 * residuals[0]):
            break
        plastic_elems = np.nonzero(res.plastic.any(axis=1))[0]
        cg_rtol = opts.cg_rtol
        if opts.cg_forcing == "adaptive":  # Eisenstat-Walker (choice 2, gamma = 0.9)
            eta = opts.cg_rtol_max if it == 0 else 0.9 * (rnorm / residuals[-2]) ** 2
            cg_rtol = min(opts.cg_rtol_max, max(opts.cg_rtol, eta))
        try:
            du, ncg, rz0 = prob.solve_correction(r, res.tangent_MPa, plastic_elems, cg_rtol)
        except ConvergenceError as err:
            residuals.append(float("nan"))
            if opts.verbose:
                print(f"    linear solve failed: {err}")
            break
        cg_total += ncg
        if e0 is None:
            e0 = abs(rz0)
        du[prob.fixed] = 0.0
        u = u + du
    hist = ", ".join(f"{x:.3e}" for x in residuals)
    raise ConvergenceError(f"Newton did not converge from p0 = {p_old:.6g} to {p_new:.6g} MPa "
                           f"(relative residuals: {hist})")


def _converged(u, res, p_new, it, residuals, energies, cg_total):
    new = SolverState(u, res.plastic_strain, res.back_stress_MPa, res.eq_plastic_strain, p_new, res.stress_MPa)
    return new, dict(iters=it, residuals=residuals, energies=energies, n_plastic=int(np.count_nonzero(res.plastic)),
                     cg_iters=cg_total)


def _first_yield(prob: _Problem, force: np.ndarray) -> tuple[float, np.ndarray]:
    """(p0 (MPa) at which the max quadrature-point von Mises stress of the elastic solution reaches yield, the
    elastic displacement under p0 = 1 MPa (mm), the elastic predictor)."""
    r = force.copy()
    r[prob.fixed] = 0.0
    if prob.factor_is_elastic:
        u1 = prob.factor.solve_refined(r, prob.Ke.dot, rtol=1e-12)
    else:  # the kept factorisation is a tangent: solve K_e u = r by CG preconditioned with it
        u1, _ = preconditioned_cg(prob.Ke.dot, r, prob.factor.solve, rtol=1e-12, max_iter=500)
    vm = von_mises_MPa(prob.disc.strain(u1) @ prob.material.elastic_matrix())
    peak = float(vm.max())
    return (prob.material.yield_MPa / peak if peak > 0 else float("inf")), u1


def _probe_values(probes: dict | None, u: np.ndarray) -> dict[str, float]:
    out = {}
    for name, op in (probes or {}).items():
        out[name] = float(op(u)) if callable(op) else float(np.ravel(op @ u)[0])
    return out


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
    opts = options or SolverOptions()
    opts.validate()
    require(isinstance(material, J2Material), "material", "must be a J2Material")
    levels = [float(p) for p in p0_levels_MPa]
    require(len(levels) > 0, "p0_levels_MPa", "must contain at least one level")
    require(all(math.isfinite(p) and p >= 0 for p in levels), "p0_levels_MPa",
            f"must be finite and >= 0 MPa, got {levels}")
    if disc is None:
        disc = discretise(mesh, opts.order)
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
        prob = _Problem(disc, material, dirichlet_dofs(disc, opts.dirichlet), opts)
        disc.problem_cache[key] = prob
    disc.problem_cache[load_key] = prepared
    prob.opts = opts
    if opts.strategy == "modified":
        prob.reset_to_elastic()
    state = initial_state if initial_state is not None else SolverState.virgin(disc)
    if initial_state is not None:
        require(state.u_mm.shape == (disc.n_dofs,), "initial_state",
                f"has {state.u_mm.size} dofs, the discretisation {disc.n_dofs}")
    vtk_idx = set(range(len(levels))) if vtk_at == "all" else {int(i) for i in vtk_at}
    require(not vtk_idx or out_dir is not None, "out_dir", "must be given when vtk_at is not empty")
    fy_key = ("first_yield", load_key, key)
    if fy_key not in disc.problem_cache:  # an elastic solve (a CG when the kept factorisation is a tangent)
        disc.problem_cache[fy_key] = _first_yield(prob, prepared.force_per_MPa)
    first_yield, u_unit = disc.problem_cache[fy_key]
    history: list[Increment] = []
    files: list[Path] = []
    output_seconds = 0.0
    yielded_before = bool(np.any(state.eq_plastic_strain > 0))
    max_iter = opts.max_newton * (10 if opts.strategy == "modified" else 1)
    # converged (p0, u) points of the monotone branch leading to ``state`` (last = state), for the predictor
    branch = list(branch_points or [])
    if not branch or branch[-1][0] != state.p0_MPa:
        branch = [(state.p0_MPa, state.u_mm)]
    for k, target in enumerate(levels):
        start = state.p0_MPa
        n_sub = 1
        max_step = opts.max_increment_MPa
        if target < start and opts.max_unload_increment_MPa is not None:
            max_step = opts.max_unload_increment_MPa
        if max_step is not None:
            n_sub = max(1, math.ceil(abs(target - start) / max_step - 1e-9))
        step_req = (target - start) / n_sub
        floor = abs(step_req) * opts.min_increment_fraction
        step = step_req
        while True:
            remaining = target - state.p0_MPa
            if abs(step) > abs(remaining):
                step = remaining
            # the last sub-step lands exactly on the target (no round-off residue of summed steps)
            p_new = target if abs(remaining - step) <= 1e-9 * max(abs(step_req), abs(target)) else state.p0_MPa + step
            u_start, elastic_start = None, False
            if opts.predictor and (p_new - state.p0_MPa) * _direction(branch) > 0:
                # extrapolation of the converged branch in the same direction (quadratic through its last three
                # points when it has them, else linear)
                u_start = _extrapolate(branch[-3:] if opts.predictor_order == 2 else branch[-2:], p_new)
            elif opts.elastic_predictor and (p_new < state.p0_MPa or not yielded_before):
                # elastic unloading / elastic loading of a virgin body: exact unless some point (re-)yields
                u_start, elastic_start = state.u_mm + (p_new - state.p0_MPa) * u_unit, True
            try:
                state_new, info = _newton_increment(prob, state, prepared.force_per_MPa, state.p0_MPa, p_new,
                                                    max_iter, p_scale=max(abs(start), abs(target)),
                                                    u_start=u_start, elastic_start=elastic_start)
            except ConvergenceError as err:
                branch = [(state.p0_MPa, state.u_mm)]  # the cut step restarts from the converged state
                if abs(step) / 2 < floor * (1 - 1e-12) or step == 0.0:
                    raise ConvergenceError(f"load step cut below the floor at p0 = {state.p0_MPa:.6g} MPa "
                                           f"towards {target:.6g} MPa: {err}") from None
                step /= 2
                prob.reset_to_elastic()
                if opts.verbose:
                    print(f"  cutting the step to {step:.6g} MPa")
                continue
            if (p_new - state.p0_MPa) * _direction(branch) < 0:
                branch = [branch[-1]]  # the direction of loading changed: a new branch
            branch = (branch + [(p_new, state_new.u_mm)])[-3:]
            state = state_new
            step = step_req if abs(2 * step) >= abs(step_req) else 2 * step  # grow back after a cut
            n_yielded = int(np.count_nonzero(state.eq_plastic_strain > 0))
            fy = (not yielded_before) and n_yielded > 0
            yielded_before = yielded_before or fy
            history.append(Increment(p_new, prepared.centre_displacement_mm(state.u_mm), info["n_plastic"],
                                     n_yielded, info["iters"], info["residuals"], info["energies"], fy,
                                     p_new == target, info["cg_iters"], _probe_values(probes, state.u_mm)))
            if opts.verbose:
                print(f"  p0 = {p_new:.6g} MPa: {info['iters']} iterations, {info['n_plastic']} plastic points")
            if p_new == target:
                break
        if on_level is not None or k in vtk_idx:
            t_out = time.perf_counter()
            if on_level is not None:
                on_level(disc, state, prepared)
            if k in vtk_idx:
                from calibration.fem.output import write_increment_output
                files += write_increment_output(disc, state, material, prepared, Path(out_dir), k,
                                                label=opts.output_label)
            output_seconds += time.perf_counter() - t_out
    return FemResult(history, first_yield, state, prepared.centre_mm, disc.n_dofs, files, branch, output_seconds)


def _direction(branch: list[tuple[float, np.ndarray]]) -> float:
    """p0 change of the branch's last step (0 for a single point: no direction yet)."""
    return branch[-1][0] - branch[-2][0] if len(branch) >= 2 else 0.0


def _extrapolate(points: list[tuple[float, np.ndarray]], p: float) -> np.ndarray:
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
