"""One Newton increment of small-strain J2 elastoplasticity and the assembled problem it works on (units mm, N,
MPa): the constrained dofs, the elastic stiffness and its kept factorisation, the consistent tangent (assembled or
matrix-free) and the Newton correction of each strategy (:class:`calibration.fem.solver_state.SolverOptions`).
"""

from __future__ import annotations

import math
import weakref
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from calibration.fem.assembly import Discretisation
from calibration.fem.linear_solvers import Factoriser, preconditioned_cg
from calibration.fem.material import J2Material, von_mises_MPa
from calibration.fem.return_mapping import ReturnResult, radial_return
from calibration.fem.solver_state import SolverOptions, SolverState
from wrlayer.errors import ConvergenceError, InputError, require

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


class TangentProblem:
    """Assembled pieces shared by all increments of one solve.

    ``factor`` holds one factorisation: the elastic stiffness at first; with the 'pcg' strategy it is refreshed
    with the current consistent tangent whenever preconditioned CG needed more than ``cg_refresh_iters``
    iterations; with 'newton' it is the current tangent; with 'modified' it stays elastic.

    The problem refers to its discretisation weakly: the discretisation keeps the problem in its
    ``problem_cache``, and a strong reference back would make a cycle that only Python's rare full garbage
    collection frees (numpy arrays and PARDISO's memory do not count towards its thresholds): one process that
    built several meshes kept every one of them with its factorisation (GBs for fine rolling blocks).
    """

    def __init__(self, disc: Discretisation, material: J2Material, constrained: np.ndarray, opts: SolverOptions):
        self._disc = weakref.ref(disc)
        self.material, self.opts = material, opts
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

    @property
    def disc(self) -> Discretisation:
        """The discretisation this problem was assembled on (it must be kept alive by its user)."""
        disc = self._disc()
        if disc is None:
            raise RuntimeError("the discretisation of this TangentProblem no longer exists: keep a reference to it")
        return disc

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
        """CSR data of K_e + sum over plastic elements of (K_ep - K_e), Dirichlet rows/cols replaced;
        ``tangent``: the consistent tangent (n_sel, n_qp, 6, 6) at the points of ``plastic_elems``."""
        data = self.Ke_data.copy()
        if plastic_elems.size:  # K_ep - K_e = B^T (C_ep - C) B: one product over the plastic elements only
            dK = self.disc.element_matrices(tangent - self.C, plastic_elems, selected=True)
            data += self.disc.csr_data(dK, plastic_elems)
        return self._bc(data)

    def tangent_matvec(self, tangent: np.ndarray, plastic_elems: np.ndarray):
        """x -> K_t x without assembling K_t: the elastic K_e x plus, over the plastic elements only, the element
        products (K_ep - K_e) x_e (Dirichlet rows/cols replaced as in :meth:`tangent_data`). Measured: the
        assembly of K_t's CSR data (copy, scatter, boundary conditions of all 5e6 entries at 62k dofs) cost more
        than all the matvecs of the CG that used it. ``tangent``: as in :meth:`tangent_data`."""
        if plastic_elems.size == 0:
            return self.Ke.dot
        dK = self.disc.element_matrices(tangent - self.C, plastic_elems, selected=True)
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
        tangent: the consistent tangent (n_sel, n_qp, 6, 6) at the points of ``plastic_elems``; cg_rtol: the CG
        tolerance of this correction (default options.cg_rtol)."""
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


@dataclass(frozen=True)
class MaterialResponse:
    """The material's answer to a displacement iterate u (mm): ``result``, the return mapping whose stress gives
    the internal forces and whose internal variables the converged state; ``plastic``: the points (n_elem, n_qp)
    that decide the elastic-predictor test and carry a plastic tangent (with material sub-steps: plastic in any
    sub-step); ``tangent_of``: plastic elements -> the consistent tangent at their points (n_sel, n_qp, 6, 6)."""

    result: ReturnResult
    plastic: np.ndarray
    tangent_of: Callable[[np.ndarray], np.ndarray | None]


def return_mapped(prob: TangentProblem, state: SolverState) -> Callable[[np.ndarray], MaterialResponse]:
    """The engine's material of one increment: backward-Euler radial return from the converged ``state`` to the
    strain of u (one step; the consistent tangent unless the 'modified' strategy needs none)."""
    disc, mat = prob.disc, prob.material
    with_tangent = prob.opts.strategy != "modified"

    def response(u: np.ndarray) -> MaterialResponse:
        res = radial_return(mat, disc.strain(u), state.plastic_strain, state.back_stress_MPa,
                            state.eq_plastic_strain, with_tangent=with_tangent)
        return MaterialResponse(res, res.plastic, res.tangent_of)

    return response


def newton_increment(prob: TangentProblem, state: SolverState, force: np.ndarray, p_old: float, p_new: float,
                     max_iter: int, p_scale: float = 0.0, u_start: np.ndarray | None = None,
                     elastic_start: bool = False,
                     material: Callable[[np.ndarray], MaterialResponse] | None = None):
    """Newton iteration from the converged ``state`` at p_old to p_new: the one Newton loop of the engine (the
    load paths of :mod:`calibration.fem.elastoplastic_solver` and the moving-load steps of
    :mod:`calibration.rolling.passes` and :mod:`calibration.rolling.substeps` all run it). Returns (new state,
    info) or raises ConvergenceError with the residual history.

    Converged when |r_k| <= rtol * max(|f_ext|, |f_int|) and r_k . P^-1 r_k <= etol * r_0 . P^-1 r_0 (energy
    norm of the residual; P the current factorisation: elastic or a recent tangent). ``force``: the load vector
    (N) of p = 1, applied as p_new * force. ``u_start``: the first iterate (a predictor; default the converged
    displacement); elastic_start: u_start is the state plus the elastic solution of the load change (then
    accepted without iteration when no point yields and the force residual passes). ``material``: the material
    response of an iterate (default :func:`return_mapped`: one radial return from ``state``).
    """
    disc, opts = prob.disc, prob.opts
    material = return_mapped(prob, state) if material is None else material
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
        response = material(u)
        res = response.result
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
        elastic_exact = elastic_start and it == 0 and rnorm <= opts.rtol and not response.plastic.any()
        if elastic_exact or (it == 0 and rnorm <= max(1e-3 * opts.rtol, 1e-13)):
            energies.append(0.0)
            return _converged(u, res, p_new, it, residuals, energies, cg_total)
        # energy norm of the residual (current factorisation): one back-substitution, so it is evaluated only
        # on the first iteration (the reference) and once the force residual has passed, unless the increment
        # started below the force tolerance, where the force criterion alone decides (measured: this halves the
        # triangular solves of a 3D indentation, benchmarks/bench_fem.py). The reference r_0 . P^-1 r_0 is the
        # first preconditioner application of the first correction (no solve of its own), except with the
        # 'newton' strategy, which refactorises first.
        if it == 0 and opts.strategy != "newton":
            energies.append(1.0)  # e0 is set from the first correction below
        elif it == 0 or (rnorm <= opts.rtol and residuals[0] > opts.rtol):
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
        plastic_elems = np.nonzero(response.plastic.any(axis=1))[0]
        try:
            du, ncg, rz0 = prob.solve_correction(r, response.tangent_of(plastic_elems), plastic_elems,
                                                 cg_tolerance(opts, it, rnorm, residuals))
        except ConvergenceError as err:
            residuals.append(float("nan"))
            if opts.verbose:
                print(f"    linear solve failed: {err}")
            break
        cg_total += ncg
        if e0 is None and rz0 is not None:
            e0 = abs(rz0)
        du[prob.fixed] = 0.0
        u = u + du
    hist = ", ".join(f"{x:.3e}" for x in residuals)
    raise ConvergenceError(f"Newton did not converge from p0 = {p_old:.6g} to {p_new:.6g} MPa "
                           f"(relative residuals: {hist})")


def cg_tolerance(opts: SolverOptions, it: int, rnorm: float, residuals: list[float]) -> float:
    """The inner CG tolerance of Newton iteration ``it``: options.cg_rtol, or with adaptive forcing
    (Eisenstat-Walker, choice 2, gamma = 0.9) gamma (|r_k| / |r_k-1|)^2 within [cg_rtol, cg_rtol_max]."""
    if opts.cg_forcing != "adaptive":
        return opts.cg_rtol
    eta = opts.cg_rtol_max if it == 0 else 0.9 * (rnorm / residuals[-2]) ** 2
    return min(opts.cg_rtol_max, max(opts.cg_rtol, eta))


def _converged(u, res, p_new, it, residuals, energies, cg_total):
    new = SolverState(u, res.plastic_strain, res.back_stress_MPa, res.eq_plastic_strain, p_new, res.stress_MPa)
    return new, dict(iters=it, residuals=residuals, energies=energies, n_plastic=int(np.count_nonzero(res.plastic)),
                     cg_iters=cg_total)


def elastic_first_yield(prob: TangentProblem, force: np.ndarray) -> tuple[float, np.ndarray]:
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



__all__ = ["MaterialResponse", "TangentProblem", "cg_tolerance", "dirichlet_dofs", "elastic_first_yield",
           "newton_increment", "return_mapped"]
