"""The assembled problem of one discretisation, material and set of constraints (units mm, N, MPa): the elastic
stiffness and its kept factorisation, the consistent tangent (assembled or matrix-free) and the Newton correction
of each strategy (:class:`calibration.fem.solver_state.SolverOptions`); the elastic first-yield solution.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from calibration.fem.assembly import Discretisation
from calibration.fem.linear_solvers import Factoriser, preconditioned_cg
from calibration.fem.material import J2Material, von_mises_MPa
from calibration.fem.solver_state import SolverOptions


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
        # without the constraints (internal forces K_e u: the residual's constrained rows are zeroed anyway); it
        # shares K_e's arrays
        self.Ke_free = sp.csr_matrix((self.Ke_data, self.Ke.indices, self.Ke.indptr), shape=self.Ke.shape)
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
                         cg_rtol: float | None = None) -> Correction:
        """Newton correction for residual r (free dofs) with the chosen strategy (see :class:`Correction`).
        tangent: the consistent tangent (n_sel, n_qp, 6, 6) at the points of ``plastic_elems``; cg_rtol: the CG
        tolerance of this correction (default options.cg_rtol)."""
        cg_rtol = self.opts.cg_rtol if cg_rtol is None else cg_rtol
        strategy = self.opts.strategy
        if strategy == "modified":
            du = self.factor.solve(r)
            return Correction(du, 0, float(r @ du))
        info: dict = {}
        if plastic_elems.size == 0 and self.factor_is_elastic:  # exact up to the Newton tolerance
            du = self.factor.solve_refined(r, self.Ke.dot, rtol=1e-2 * self.opts.rtol, info=info)
            return Correction(du, 0, info["rz0"])
        if strategy == "newton":
            data = self.tangent_data(tangent, plastic_elems)
            self.factor.factorise(data)
            self.factor_is_elastic = plastic_elems.size == 0
            return Correction(self.factor.solve_refined(r, self.disc.csr_matrix(data).dot, rtol=cg_rtol), 0, None)
        du, iters = preconditioned_cg(self.tangent_matvec(tangent, plastic_elems), r, self.factor.solve,
                                      rtol=cg_rtol, max_iter=500, info=info)
        if iters > self.opts.cg_refresh_iters:
            self.factor.factorise(self.tangent_data(tangent, plastic_elems))
            self.factor_is_elastic = plastic_elems.size == 0
        return Correction(du, iters, info["rz0"], info["residual"])


@dataclass(frozen=True)
class Correction:
    """One Newton correction. du: the correction (mm); cg_iters: CG iterations (0 for a direct solve); rz0:
    r . P^-1 r with the factorisation P at hand on entry (None when not computed: the 'newton' strategy);
    linear_residual: |r - K_t du| (N) left by CG (None for a direct solve)."""

    du: np.ndarray
    cg_iters: int
    rz0: float | None
    linear_residual: float | None = None


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


__all__ = ["Correction", "TangentProblem", "elastic_first_yield"]
