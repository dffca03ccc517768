"""The material response of a Newton iterate, evaluated only where it can be plastic (units mm, N, MPa).

Why: every Newton iteration of a rolling step return-mapped every point of the block through all its material
sub-steps, although the plastic zone under the load is a small part of it: the strains, return mappings and
internal forces were about a third of a rolling pass's CPU time (docs/validation/fem-speed.md). Used by the
rolling steps (:mod:`calibration.rolling.substeps`), not by the engine's load paths (see
:func:`calibration.fem.newton.return_mapped`).

Bound: the first iterate of an increment is evaluated at every point and kept as the reference, with each point's
largest trial yield function f_ref (over the material sub-steps of a rolling step). A later iterate u moves the
strain of a point of element e by at most L_e |u_e - u_ref,e| (L_e:
:attr:`calibration.fem.assembly.Discretisation.strain_bound`; a sub-step's strain moves by at most as much, its
weight on the end strain being at most 1), so its deviatoric trial stress by at most 2 G times that. A point
elastic at the reference whose f_ref stays below -(2 G L_e |u_e - u_ref,e| + ``MARGIN`` Y) is elastic at u: its
stress is C (eps - eps_p) and its internal variables stay those of the converged state. Only the other elements
(the candidates) are return-mapped; the internal forces are K_e u - sum B^T C eps_p dx (every point elastic from the
state) plus the candidates' difference from that. Where the candidates are more than ``FULL_FRACTION`` of the
elements, the iterate is evaluated everywhere and becomes the reference. The numbers are those of the evaluation
at every point up to round-off (tests/calibration/rolling/test_bounded_path.py compares them).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from calibration.fem.problem import TangentProblem
from calibration.fem.return_mapping import ReturnResult, tangent_of_elements
from calibration.fem.solver_state import SolverState

#: a point is skipped only when its trial yield function stays below -MARGIN x yield stress (round-off room)
MARGIN = 1e-6
#: beyond this fraction of candidate elements the iterate is evaluated everywhere (and becomes the reference)
FULL_FRACTION = 0.5


@dataclass(frozen=True)
class MaterialResponse:
    """The material's answer to a displacement iterate u (mm): ``result``, the return mapping whose stress gives
    the internal forces and whose internal variables the converged state; ``plastic``: the points (n_elem, n_qp)
    that decide the elastic-predictor test and carry a plastic tangent (with material sub-steps: plastic in any
    sub-step); ``tangent_of``: plastic elements -> the consistent tangent at their points (n_sel, n_qp, 6, 6).
    A material evaluated only at the points that can be plastic gives ``f_int`` (the internal forces, N) and
    ``complete`` (makes the full result, called once the iterate has converged) instead of ``result``."""

    result: ReturnResult | None
    plastic: np.ndarray
    tangent_of: Callable[[np.ndarray], np.ndarray | None]
    f_int: np.ndarray | None = None
    complete: Callable[[], ReturnResult] | None = None

    def internal_force(self, prob: TangentProblem) -> np.ndarray:
        """The internal forces (N) of the iterate."""
        return self.f_int if self.f_int is not None else prob.disc.internal_force(self.result.stress_MPa)

    def full_result(self) -> ReturnResult:
        """The return mapping at every point (made by ``complete`` where the material gave none)."""
        return self.result if self.result is not None else self.complete()


@dataclass(frozen=True)
class MaterialAtPoints:
    """The material at the points of some elements: ``result`` (the last sub-step's return mapping there),
    ``plastic`` (n_sel, n_qp: the points with a plastic tangent), ``tangent`` (MPa, at those points in the order of
    ``np.nonzero``; None without tangent), ``default`` (the tangent of every other point, 6 x 6; None without),
    ``trial_yield_MPa`` (n_sel, n_qp: the largest trial yield function over the sub-steps)."""

    result: ReturnResult
    plastic: np.ndarray
    tangent: np.ndarray | None
    default: np.ndarray | None
    trial_yield_MPa: np.ndarray


#: (end strains (n_sel, n_qp, 6), the elements or None for all) -> the material's evaluation at their points
Evaluate = Callable[[np.ndarray, "np.ndarray | None"], MaterialAtPoints]


class BoundedMaterial:
    """The material response (:class:`MaterialResponse`) of the iterates of one increment from the converged
    ``state``, evaluated by ``evaluate`` at the candidate points only (module docstring). ``evaluated``: the
    element evaluations made (a count)."""

    def __init__(self, prob: TangentProblem, state: SolverState, evaluate: Evaluate):
        self.prob, self.state, self.evaluate = prob, state, evaluate
        self.disc = prob.disc
        self.reach_per_mm = 2.0 * prob.material.shear_modulus_MPa * self.disc.strain_bound
        self.tolerance = MARGIN * prob.material.yield_MPa
        self.u_ref: np.ndarray | None = None
        self.margin: np.ndarray | None = None     # per element: min over its points of -f_ref (MPa)
        self.f_plastic: np.ndarray | None = None  # sum B^T C eps_p dx of the state (N), on first use
        self.evaluated = 0

    def __call__(self, u: np.ndarray) -> MaterialResponse:
        if self.u_ref is not None:
            moved = np.linalg.norm((u - self.u_ref)[self.disc.element_dofs], axis=1)
            candidates = np.flatnonzero(self.margin < self.reach_per_mm * moved + self.tolerance)
            if candidates.size <= FULL_FRACTION * self.disc.n_elements:
                return self._restricted(u, candidates)
        return self._everywhere(u)

    def _tangent_of(self, ev: MaterialAtPoints, plastic: np.ndarray) -> Callable[[np.ndarray], np.ndarray | None]:
        if ev.default is None:
            return lambda elems: None
        return lambda elems: tangent_of_elements(elems, plastic, ev.tangent, ev.default)

    def _everywhere(self, u: np.ndarray) -> MaterialResponse:
        ev = self.evaluate(self.disc.strain(u), None)
        self.u_ref, self.margin = u.copy(), -ev.trial_yield_MPa.max(axis=1)
        self.evaluated += self.disc.n_elements
        return MaterialResponse(ev.result, ev.plastic, self._tangent_of(ev, ev.plastic))

    def _restricted(self, u: np.ndarray, cand: np.ndarray) -> MaterialResponse:
        st, disc, prob = self.state, self.disc, self.prob
        if self.f_plastic is None:
            self.f_plastic = disc.internal_force(st.plastic_strain @ prob.C)
        eps_b = disc.strain(u, cand)
        ev = self.evaluate(eps_b, cand)
        plastic = np.zeros((disc.n_elements, disc.n_qp), dtype=bool)
        plastic[cand] = ev.plastic  # cand ascending: the plastic points keep the order of ev.tangent
        elastic_stress = (eps_b - st.plastic_strain[cand]) @ prob.C
        f_int = (prob.Ke_free @ u - self.f_plastic
                 + disc.internal_force(ev.result.stress_MPa - elastic_stress, cand))
        self.evaluated += cand.size
        return MaterialResponse(None, plastic, self._tangent_of(ev, plastic), f_int=f_int,
                                complete=lambda: self._complete(u, cand, ev.result))

    def _complete(self, u: np.ndarray, cand: np.ndarray, r: ReturnResult) -> ReturnResult:
        """The (last sub-step's) result at every point: the candidates' from ``r``, elsewhere the state's internal
        variables and the elastic stress."""
        st = self.state
        ps, bs, eq = st.plastic_strain.copy(), st.back_stress_MPa.copy(), st.eq_plastic_strain.copy()
        stress = (self.disc.strain(u) - ps) @ self.prob.C
        plastic = np.zeros(eq.shape, dtype=bool)
        ps[cand], bs[cand], eq[cand] = r.plastic_strain, r.back_stress_MPa, r.eq_plastic_strain
        stress[cand], plastic[cand] = r.stress_MPa, r.plastic
        return ReturnResult(stress, ps, bs, eq, plastic)


def rows(array: np.ndarray, elements: np.ndarray | None) -> np.ndarray:
    """The rows of ``elements`` of a per-element array (all of it for None)."""
    return array if elements is None else array[elements]


__all__ = ["BoundedMaterial", "Evaluate", "MaterialAtPoints", "FULL_FRACTION", "MARGIN", "MaterialResponse", "rows"]
