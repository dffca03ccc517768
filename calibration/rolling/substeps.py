"""Material sub-steps along the load's path inside one rolling step (units mm, N, MPa).

Why: a plain step moves the load from x_a to x_b in one jump, and the backward-Euler return mapping of the engine
integrates the stress from the state at x_a straight to the strain at x_b. Under a moving load the stress path of
a point turns (the principal axes rotate as the load passes), so the straight return cuts the path short and
underestimates the plastic flow at first order in the step ds (docs/rolling-verification.md: the first-pass
groove grows by 4.6 % from a/4 to a/8 and 2.4 % more to a/16).

Method: the displacement inside the step is taken as the converged state at x_a plus the ELASTIC response of the
load change up to the sub-position plus the rest of the step's correction interpolated linearly,

    u(t) = u_a + [w(t) - w(0)] + t (u_b - u_a - [w(1) - w(0)]),   w(t) = f(t) p0 K_e^-1 F(x(t)),   0 <= t <= 1,

with x(t) and the load fraction f(t) interpolated between the step's ends and F(x) the unit load vector
(:class:`~calibration.rolling.moving_load.SurfaceForces`). u(1) = u_b, the unknown of the Newton iteration. The
material is return-mapped (radial return, :func:`calibration.fem.return_mapping.radial_return`) through the
strains of u(t_k) at t_k = k / m, k = 1..m, each sub-step starting from the internal variables of the one before;
the stress of the last sub-step gives the internal forces at x_b. The elastic part of the path is exact for any
step (it is linear in the load), so what remains of the first-order error is that of the linearly interpolated
plastic correction.

Cost: no factorisation of its own. The unit responses K_e^-1 F(x) are computed once per load position on the
sub-step grid and kept (back-substitutions with the kept elastic factorisation, or CG preconditioned by the kept
tangent one) and shared by all passes and levels (the response is linear in p0); each Newton iteration runs the
return mapping m times instead of once, only at the points that can be plastic
(:mod:`calibration.fem.bounded_material`). The Newton tangent is carried through the sub-steps
(:meth:`SubstepSolver.material_path`), so the iteration keeps the engine's convergence.
"""

from __future__ import annotations

import numpy as np

from calibration.fem.bounded_material import BoundedMaterial, MaterialAtPoints, rows
from calibration.fem.linear_solvers import preconditioned_cg
from calibration.fem.problem import TangentProblem
from calibration.fem.return_mapping import radial_return
from calibration.fem.solver_state import SolverState
from calibration.rolling.moving_load import SurfaceForces
from calibration.rolling.passes import PREDICTOR_RTOL, MaterialFn, RollingSolver, Target
from wrlayer.errors import require

#: Newton iterations allowed per step with sub-steps.
MAX_NEWTON = 15


class UnitResponses:
    """The elastic displacement K_e^-1 F(x) (mm per MPa of p0) of the unit load at position x (mm), computed on
    first use and kept (keyed by x rounded to 1e-9 a)."""

    def __init__(self, prob: TangentProblem, forces: SurfaceForces):
        self.prob, self.forces = prob, forces
        self.cache: dict[int, np.ndarray] = {}
        self.key_scale = 1e9 / forces.load.a_mm

    def __call__(self, x_mm: float) -> np.ndarray:
        key = int(round(x_mm * self.key_scale))
        w = self.cache.get(key)
        if w is None:
            prob = self.prob
            f = self.forces.force(x_mm, 1.0)
            f[prob.fixed] = 0.0
            if prob.factor_is_elastic:
                w = prob.factor.solve(f)
            else:  # the kept factorisation is a tangent: the elastic response by CG preconditioned with it
                w, _ = preconditioned_cg(prob.Ke.dot, f, prob.factor.solve, rtol=PREDICTOR_RTOL, max_iter=200)
            self.cache[key] = w
        return w


class SubstepSolver(RollingSolver):
    """A :class:`~calibration.rolling.passes.RollingSolver` whose increments integrate the material in
    ``substeps`` sub-steps along the load's path (module docstring); substeps = 1 is the plain backward-Euler step.
    ``responses``: the kept unit responses of the mesh (shared between levels; default: new)."""

    def __init__(self, prob: TangentProblem, forces: SurfaceForces, p0_MPa: float, substeps: int,
                 max_newton: int = MAX_NEWTON, responses: UnitResponses | None = None):
        require(isinstance(substeps, int) and 1 <= substeps <= 64, "substeps",
                f"must be an integer in [1, 64], got {substeps}")
        super().__init__(prob, forces, p0_MPa, max_newton)
        self.substeps = substeps
        self.responses = responses if responses is not None else UnitResponses(prob, forces)
        self.C_inv = np.linalg.inv(prob.C)

    def elastic_path(self, a: Target, b: Target) -> list[np.ndarray]:
        """w(t_k) - w(0) (mm) for k = 1..m: the elastic response of the load change up to each sub-position."""
        w0 = a.fraction * self.p0 * self.responses(a.x_c_mm)
        out = []
        for k in range(1, self.substeps + 1):
            t = a.towards(b, k / self.substeps)
            out.append(t.fraction * self.p0 * self.responses(t.x_c_mm) - w0)
        return out

    def material_path(self, state: SolverState, eps_a: np.ndarray, eps_path: list[np.ndarray], u: np.ndarray):
        """Return mapping through the sub-steps for the end displacement u at every point: (the last sub-step's
        ReturnResult, the points plastic in any sub-step (bool (n_elem, n_qp)), the tangent d sigma_m / d eps_b
        through all sub-steps at those points (n_yielded, 6, 6) in the order of ``np.nonzero``, MPa; symmetrised,
        and the tangent of every other point: C, summed as m times C / m); see :meth:`return_path`."""
        r, yielded, tangent, elastic, _ = self.return_path(
            self.prob.disc.strain(u), eps_a, eps_path, state.plastic_strain, state.back_stress_MPa,
            state.eq_plastic_strain)
        return r, yielded, tangent, elastic

    def return_path(self, eps_b: np.ndarray, eps_a: np.ndarray, eps_path: list[np.ndarray], ps: np.ndarray,
                    bs: np.ndarray, eq: np.ndarray):
        """:meth:`material_path` on arrays of points (any leading shape (n, n_qp)): the end strain eps_b, the
        start strain eps_a, the elastic path's strains and the internal variables at the start; also returns the
        largest trial yield function of each point over the sub-steps (MPa, (n, n_qp)).

        Tangent: the trial stress of sub-step k is sigma_k-1 + C (eps_k - eps_k-1) and eps_k depends on eps_b with
        weight t_k, so T_k = R_k (T_k-1 + C (t_k - t_k-1)), T_0 = 0, with R_k = C_ep,k C^-1 the return's
        derivative with respect to its trial stress (exact for perfect plasticity; the hardening variables' own
        dependence on eps_b is left out). T_m is the consistent tangent C_ep for m = 1. A point elastic so far has
        T_k = t_k C, so T is carried only at the points that have yielded (a small part of the block), from the
        sub-step at which they first yield."""
        mat, m, C = self.prob.material, self.substeps, self.prob.C
        rest = eps_b - eps_a - eps_path[-1]          # strain of the linearly interpolated correction D
        yielded = np.zeros(eps_b.shape[:-1], dtype=bool)
        f_max = np.full(eps_b.shape[:-1], -np.inf)
        points = np.zeros(0, dtype=np.int64)         # flat indices of the yielded points (ascending)
        tangent = np.zeros((0, 6, 6))                # T at those points
        elastic = np.zeros((6, 6))                   # T_k of a point elastic so far (sum of the C / m)
        for k in range(1, m + 1):
            eps_k = eps_b if k == m else eps_a + eps_path[k - 1] + (k / m) * rest
            r = radial_return(mat, eps_k, ps, bs, eq, with_tangent=True)
            ps, bs, eq = r.plastic_strain, r.back_stress_MPa, r.eq_plastic_strain
            np.maximum(f_max, r.trial_yield_MPa, out=f_max)
            plastic = np.flatnonzero(r.plastic)
            new = plastic[~yielded.ravel()[plastic]]
            if new.size:  # points yielding for the first time join with T_k-1 of an elastic point
                merged = np.union1d(points, new)
                grown = np.empty((merged.size, 6, 6))
                grown[np.searchsorted(merged, points)] = tangent
                grown[np.searchsorted(merged, new)] = elastic
                points, tangent = merged, grown
                yielded.ravel()[new] = True
            tangent += C / m
            elastic += C / m
            if plastic.size:
                at = np.searchsorted(points, plastic)
                tangent[at] = r.plastic_tangent_MPa @ self.C_inv @ tangent[at]
        tangent = 0.5 * (tangent + np.swapaxes(tangent, -1, -2))
        return r, yielded, tangent, elastic, f_max

    def start(self, state: SolverState, a: Target, b: Target) -> tuple[np.ndarray, bool, MaterialFn | None]:
        """(first iterate: the state plus the elastic path's end, exact for an elastic step; the sub-stepped
        material response of an iterate, evaluated only where it can be plastic,
        :class:`~calibration.fem.bounded_material.BoundedMaterial`) of the increment from ``a`` to ``b``. With
        substeps = 1 this is the plain backward-Euler step of :class:`RollingSolver` (the same first iterate from
        the kept unit responses instead of a solve of its own, the same return mapping)."""
        disc = self.prob.disc
        du_path = self.elastic_path(a, b)
        eps_a = disc.strain(state.u_mm)
        eps_path = [disc.strain(d) for d in du_path]

        def evaluate(eps_b: np.ndarray, elements: np.ndarray | None) -> MaterialAtPoints:
            return MaterialAtPoints(*self.return_path(eps_b, rows(eps_a, elements), [rows(e, elements) for e in eps_path],
                                                rows(state.plastic_strain, elements),
                                                rows(state.back_stress_MPa, elements),
                                                rows(state.eq_plastic_strain, elements)))

        return state.u_mm + du_path[-1], True, BoundedMaterial(self.prob, state, evaluate)


__all__ = ["MAX_NEWTON", "SubstepSolver", "UnitResponses"]
