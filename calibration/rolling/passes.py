"""The passes of one load level: quasi-static steps of the moving load, as a generator of typed records.

Each pass: the load appears at x_start (p0 applied in ``ramp_steps`` equal steps), moves in steps to x_end, and is
removed there (one step); the next pass starts again at x_start from the residual state. Every step is one
Newton increment of the engine (:func:`calibration.fem.newton.newton_increment`) on the kept
:class:`~calibration.fem.problem.TangentProblem` (the elastic factorisation is assembled once and kept across steps
and passes; PCG on the consistent tangent, refreshed as the engine does). The first iterate of a step is the
converged state plus the elastic response to the change of the load vector (a back-substitution with the kept
elastic factorisation, or CG preconditioned by the kept tangent factorisation). A step whose Newton iteration fails is cut in halves (positions and
load fractions interpolated) down to 1/32; then :class:`RollingConvergenceError` names the level, pass and step.
Units mm, N, MPa, s.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, replace

import numpy as np

from calibration.fem.linear_solvers import preconditioned_cg
from calibration.fem.newton import MaterialResponse, newton_increment
from calibration.fem.problem import TangentProblem
from calibration.fem.solver_state import SolverState
from calibration.rolling.moving_load import SurfaceForces
from wrlayer.errors import ConvergenceError

#: The material response of a displacement iterate (mm).
MaterialFn = Callable[[np.ndarray], MaterialResponse]
#: Deepest halving of a failed step (1/2^MAX_CUTS of it).
MAX_CUTS = 5
#: CG tolerance of the elastic predictor when the kept factorisation is a tangent (measured: the tangent's own
#: response to the load change, a plastic zone elsewhere, made Newton diverge and cost the step cuts).
PREDICTOR_RTOL = 1e-6


class RollingConvergenceError(ConvergenceError):
    """A rolling step did not converge after the step cuts; names the level, pass and step (exit code 3)."""


@dataclass(frozen=True)
class MovingLoadStep:
    """One converged step. level: index of the load level; pass_index: 1-based pass; step: 0-based step in the
    pass; x_c_mm: load centre (mm); load_fraction: p0 fraction applied (-; 0 after the removal); newton_iters,
    cg_iters: iterations (sub-steps of a cut summed); n_plastic: quadrature points yielding in the step; cuts: sub-steps
    the step was cut into (1: none); seconds: wall time (s)."""

    level: int
    pass_index: int
    step: int
    x_c_mm: float
    load_fraction: float
    newton_iters: int
    cg_iters: int
    n_plastic: int
    cuts: int
    seconds: float


@dataclass(frozen=True)
class MovingLoadPass:
    """One completed pass (load removed). level, pass_index: as in :class:`MovingLoadStep`; n_steps; newton_iters,
    cg_iters: totals; seconds: wall time of the pass (s); state: the residual state after it (for the groove and
    the fields; not written to JSON)."""

    level: int
    pass_index: int
    n_steps: int
    newton_iters: int
    cg_iters: int
    seconds: float
    state: SolverState


@dataclass(frozen=True)
class Target:
    """Where a step goes: the load centre x_c (mm) and the fraction of p0 applied (-)."""

    x_c_mm: float
    fraction: float

    def towards(self, other: Target, t: float) -> Target:
        return Target(self.x_c_mm + t * (other.x_c_mm - self.x_c_mm),
                      self.fraction + t * (other.fraction - self.fraction))


class RollingSolver:
    """Steps of the moving load on one problem: ``prob`` (the engine's kept tangent problem), ``forces`` (the
    load's nodal forces), p0 (MPa), the Newton iteration limit."""

    def __init__(self, prob: TangentProblem, forces: SurfaceForces, p0_MPa: float, max_newton: int = 10):
        self.prob, self.forces, self.p0, self.max_newton = prob, forces, float(p0_MPa), max_newton

    def load_vector(self, target: Target) -> np.ndarray:
        """The full-p0 nodal forces at the target's position (N); the step scales them by its fraction."""
        return self.forces.force(target.x_c_mm, self.p0)

    def step(self, state: SolverState, start: Target, end: Target) -> tuple[SolverState, dict]:
        """Converged state at ``end`` from ``state`` at ``start``; failed Newton iterations are cut in halves.
        Returns (state, totals {newton_iters, cg_iters, n_plastic, cuts}); ConvergenceError below the floor."""
        totals = {"newton_iters": 0, "cg_iters": 0, "n_plastic": 0, "cuts": 0}
        pending, done = [(start, end, 0)], state
        while pending:
            a, b, depth = pending.pop()
            try:
                done, info = self.increment(done, a, b)
            except ConvergenceError:
                self.prob.reset_to_elastic()
                if depth >= MAX_CUTS:
                    raise
                mid = a.towards(b, 0.5)
                pending += [(mid, b, depth + 1), (a, mid, depth + 1)]
                continue
            totals["newton_iters"] += info["iters"]
            totals["cg_iters"] += info["cg_iters"]
            totals["n_plastic"] = max(totals["n_plastic"], info["n_plastic"])
            totals["cuts"] += 1
        return done, totals

    def increment(self, state: SolverState, a: Target, b: Target) -> tuple[SolverState, dict]:
        """One Newton increment of the engine (:func:`calibration.fem.newton.newton_increment`) from ``state`` at
        ``a`` to ``b`` (no cut), started from :meth:`start`; ConvergenceError when it fails."""
        u_start, elastic_start, material = self.start(state, a, b)
        new, info = newton_increment(self.prob, state, self.load_vector(b), a.fraction, b.fraction, self.max_newton,
                                     p_scale=1.0, u_start=u_start, elastic_start=elastic_start, material=material)
        return replace(new, p0_MPa=self.p0 * b.fraction), info

    def start(self, state: SolverState, a: Target, b: Target) -> tuple[np.ndarray, bool, MaterialFn | None]:
        """(first iterate, whether it is exact for an elastic step, the material response or None: the engine's
        one radial return) of the increment from ``a`` to ``b``: the converged state plus the elastic response to
        the change of the load vector."""
        prob = self.prob
        df = b.fraction * self.load_vector(b) - a.fraction * self.load_vector(a)
        df[prob.fixed] = 0.0
        if prob.factor_is_elastic:
            du = prob.factor.solve(df)
        else:  # the kept factorisation is a tangent of another load position: the ELASTIC response by CG
            du, _ = preconditioned_cg(prob.Ke.dot, df, prob.factor.solve, rtol=PREDICTOR_RTOL, max_iter=200)
        return state.u_mm + du, prob.factor_is_elastic, None


def pass_targets(positions_mm: list[float], ramp_steps: int) -> list[Target]:
    """The targets of one pass: p0 ramped up at x_start, moved to x_end, removed there."""
    x0, x1 = positions_mm[0], positions_mm[-1]
    ramp = [Target(x0, k / ramp_steps) for k in range(1, ramp_steps + 1)]
    return ramp + [Target(x, 1.0) for x in positions_mm[1:]] + [Target(x1, 0.0)]


def roll(solver: RollingSolver, state: SolverState, positions_mm: list[float], n_passes: int, ramp_steps: int,
         level: int = 0, first_pass: int = 1) -> Iterator[MovingLoadStep | MovingLoadPass]:
    """The passes ``first_pass`` .. n_passes from ``state`` (residual state of the previous pass): a
    :class:`MovingLoadStep` per converged step and a :class:`MovingLoadPass` after each pass.
    RollingConvergenceError names the level, pass and step that failed."""
    targets = pass_targets(positions_mm, ramp_steps)
    for k in range(first_pass, n_passes + 1):
        t_pass = time.perf_counter()
        prev = Target(positions_mm[0], 0.0)
        newton = cg = 0
        for j, tgt in enumerate(targets):
            t0 = time.perf_counter()
            try:
                state, tot = solver.step(state, prev, tgt)
            except ConvergenceError as err:
                raise RollingConvergenceError(
                    f"level {level} (p0 = {solver.p0:.6g} MPa), pass {k}, step {j} (x_c = {tgt.x_c_mm:.6g} mm, "
                    f"load fraction {tgt.fraction:.3g}): {err}") from None
            newton += tot["newton_iters"]
            cg += tot["cg_iters"]
            yield MovingLoadStep(level=level, pass_index=k, step=j, x_c_mm=tgt.x_c_mm, load_fraction=tgt.fraction,
                                 newton_iters=tot["newton_iters"], cg_iters=tot["cg_iters"],
                                 n_plastic=tot["n_plastic"], cuts=tot["cuts"], seconds=time.perf_counter() - t0)
            prev = tgt
        yield MovingLoadPass(level=level, pass_index=k, n_steps=len(targets), newton_iters=newton, cg_iters=cg,
                             seconds=time.perf_counter() - t_pass, state=state)


__all__ = ["MAX_CUTS", "MaterialFn", "MovingLoadPass", "MovingLoadStep", "RollingConvergenceError", "RollingSolver",
           "Target", "pass_targets", "roll"]
