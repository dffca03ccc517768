"""The sub-stepped material of one rolling increment evaluated only where it can be plastic (units mm, N, MPa).

Why: a Newton iteration of a rolling step return-mapped every point of the block through all its material
sub-steps (:class:`calibration.rolling.substeps.SubstepSolver`), although the plastic zone under the load is a
small part of the block: the strains, return mappings and internal forces were about a third of a pass's CPU time
(docs/validation/fem-speed.md).

Bound: the first iterate of an increment is evaluated at every point and kept as the reference, with each point's
largest trial yield function over the sub-steps, f_ref. A later iterate u moves the end strain of a point of
element e by at most L_e |u_e - u_ref,e| (L_e: :attr:`calibration.fem.assembly.Discretisation.strain_bound`) and
the strain of every sub-step by at most as much (its weight on the end strain is at most 1), so the deviatoric
trial stress by at most 2 G times that. A point elastic in every sub-step of the reference whose f_ref stays below
-(2 G L_e |u_e - u_ref,e| + ``MARGIN`` Y) is elastic in every sub-step of u: its stress is C (eps - eps_p) and its
internal variables stay those of the state. Only the other elements (the candidates) are return-mapped; the
internal forces are K_e u - sum B^T C eps_p dx (every point elastic from the state) plus the candidates'
difference from that. Where the candidates are more than ``FULL_FRACTION`` of the elements, the iterate is
evaluated everywhere and becomes the reference. The numbers are those of the evaluation at every point up to
round-off (the test compares them).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from calibration.fem.newton import MaterialResponse
from calibration.fem.return_mapping import ReturnResult, tangent_of_elements
from calibration.fem.solver_state import SolverState

if TYPE_CHECKING:
    from calibration.rolling.substeps import SubstepSolver

#: a point is skipped only when its trial yield function stays below -MARGIN x yield stress (round-off room)
MARGIN = 1e-6
#: beyond this fraction of candidate elements the iterate is evaluated everywhere (and becomes the reference)
FULL_FRACTION = 0.5


class BoundedPath:
    """The material response (:class:`calibration.fem.newton.MaterialResponse`) of the iterates of one increment
    from ``state`` along the elastic path ``du_path`` (mm, :meth:`SubstepSolver.elastic_path`), evaluated at the
    candidate points only (module docstring). ``evaluated``: the element evaluations made (counts)."""

    def __init__(self, solver: SubstepSolver, state: SolverState, du_path: list[np.ndarray]):
        prob = solver.prob
        disc = prob.disc
        self.solver, self.state, self.disc = solver, state, disc
        self.eps_a = disc.strain(state.u_mm)
        self.eps_path = [disc.strain(d) for d in du_path]
        self.stiffness = disc.csr_matrix(prob.Ke_data)  # without the constraints (they zero the residual's rows)
        self.f_plastic = disc.internal_force(state.plastic_strain @ prob.C)
        self.reach_per_mm = 2.0 * prob.material.shear_modulus_MPa * disc.strain_bound
        self.tolerance = MARGIN * prob.material.yield_MPa
        self.u_ref: np.ndarray | None = None
        self.margin: np.ndarray | None = None   # per element: min over its points of -f_ref (MPa)
        self.evaluated = 0

    def __call__(self, u: np.ndarray) -> MaterialResponse:
        if self.u_ref is not None:
            moved = np.linalg.norm((u - self.u_ref)[self.disc.element_dofs], axis=1)
            candidates = np.flatnonzero(self.margin < self.reach_per_mm * moved + self.tolerance)
            if candidates.size <= FULL_FRACTION * self.disc.n_elements:
                return self._restricted(u, candidates)
        return self._everywhere(u)

    def _everywhere(self, u: np.ndarray) -> MaterialResponse:
        st = self.state
        r, yielded, tangent, elastic, f_max = self.solver.return_path(
            self.disc.strain(u), self.eps_a, self.eps_path, st.plastic_strain, st.back_stress_MPa,
            st.eq_plastic_strain)
        self.u_ref, self.margin = u.copy(), -f_max.max(axis=1)
        self.evaluated += self.disc.n_elements
        return MaterialResponse(r, yielded, lambda elems: tangent_of_elements(elems, yielded, tangent, elastic))

    def _restricted(self, u: np.ndarray, cand: np.ndarray) -> MaterialResponse:
        st, disc, C = self.state, self.disc, self.solver.prob.C
        eps_b = disc.strain(u, cand)
        ps = st.plastic_strain[cand]
        r, yielded_c, tangent, elastic, _ = self.solver.return_path(
            eps_b, self.eps_a[cand], [e[cand] for e in self.eps_path], ps, st.back_stress_MPa[cand],
            st.eq_plastic_strain[cand])
        yielded = np.zeros((disc.n_elements, disc.n_qp), dtype=bool)
        yielded[cand] = yielded_c  # cand ascending: the yielded points keep the order of ``tangent``
        f_int = (self.stiffness @ u - self.f_plastic
                 + disc.internal_force(r.stress_MPa - (eps_b - ps) @ C, cand))
        self.evaluated += cand.size
        return MaterialResponse(None, yielded,
                                lambda elems: tangent_of_elements(elems, yielded, tangent, elastic),
                                f_int=f_int, complete=lambda: self._complete(u, cand, r))

    def _complete(self, u: np.ndarray, cand: np.ndarray, r: ReturnResult) -> ReturnResult:
        """The last sub-step's result at every point: the candidates' from ``r``, the state's internal variables
        and the elastic stress elsewhere."""
        st = self.state
        ps, bs, eq = st.plastic_strain.copy(), st.back_stress_MPa.copy(), st.eq_plastic_strain.copy()
        stress = (self.disc.strain(u) - ps) @ self.solver.prob.C
        plastic = np.zeros(eq.shape, dtype=bool)
        ps[cand], bs[cand], eq[cand] = r.plastic_strain, r.back_stress_MPa, r.eq_plastic_strain
        stress[cand], plastic[cand] = r.stress_MPa, r.plastic
        return ReturnResult(stress, ps, bs, eq, plastic)


__all__ = ["BoundedPath", "FULL_FRACTION", "MARGIN"]
