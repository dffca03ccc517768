"""The one Newton loop of the engine: small-strain J2 elastoplasticity, one increment from a converged state to
a new load (units mm, N, MPa). The load paths (:mod:`calibration.fem.elastoplastic_solver`) and the moving-load
steps (:mod:`calibration.rolling.passes`, with material sub-steps :mod:`calibration.rolling.substeps`) all run
:func:`newton_increment`; what differs between them is the first iterate and the material response of an iterate.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from calibration.fem.bounded_material import MaterialResponse
from calibration.fem.problem import TangentProblem
from calibration.fem.return_mapping import radial_return
from calibration.fem.solver_state import SolverOptions, SolverState
from wrlayer.errors import ConvergenceError


def return_mapped(prob: TangentProblem, state: SolverState) -> Callable[[np.ndarray], MaterialResponse]:
    """The engine's material of one increment: backward-Euler radial return from the converged ``state`` to the
    strain of u (one step; the consistent tangent unless the 'modified' strategy needs none), at every point. (The
    bound of :class:`calibration.fem.bounded_material.BoundedMaterial`, which the rolling steps use, does not pay
    here: on the direct 3D calibration position the candidates are 20-46 % of the elements and copying their rows
    cost what the skipped points saved: 3.89 s against 3.93 s of material CPU time, cProfile at load 2-3.)"""
    disc, mat = prob.disc, prob.material
    with_tangent = prob.opts.strategy != "modified"

    def response(u: np.ndarray) -> MaterialResponse:
        res = radial_return(mat, disc.strain(u), state.plastic_strain, state.back_stress_MPa,
                            state.eq_plastic_strain, with_tangent=with_tangent)
        return MaterialResponse(res, res.plastic, res.tangent_of)

    return response


def _relative_energy(prob: TangentProblem, r: np.ndarray, it: int, rnorm: float, residuals: list[float],
                     e0: float | None) -> tuple[float, float | None]:
    """The energy norm r . P^-1 r of iteration ``it``'s residual relative to the reference e0 (P the current
    factorisation), and the reference; nan where it is not evaluated. One back-substitution, so it is evaluated
    only on the first iteration (the reference) and once the force residual has passed, unless the increment
    started below the force tolerance, where the force criterion alone decides (measured: this halves the
    triangular solves of a 3D indentation, benchmarks/bench_fem.py). The reference is the first preconditioner
    application of the first correction (no solve of its own: 1.0 here, e0 set by the caller from the
    correction), except with the 'newton' strategy, which refactorises first."""
    opts = prob.opts
    if it == 0 and opts.strategy != "newton":
        return 1.0, e0
    if it == 0 or (rnorm <= opts.rtol and residuals[0] > opts.rtol):
        energy = abs(float(r @ prob.factor.solve(r)))
        e0 = energy if e0 is None else e0
        return energy / max(e0, 1e-300), e0
    return float("nan"), e0


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
    opts = prob.opts
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
    linear = None  # |r_k - K_t du_k| / ref_k left by the last correction's CG (None: not known)
    for it in range(max_iter + 1):
        response = material(u)
        f_int = response.internal_force(prob)
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
            return _converged(u, response.full_result(), p_new, it, residuals, energies, cg_total)
        energy, e0 = _relative_energy(prob, r, it, rnorm, residuals, e0)
        energies.append(energy)
        if opts.verbose:
            print(f"    p0={p_new:.6g} it={it} |r|/ref={rnorm:.3e} energy={energies[-1]:.3e}")
        # an increment that started below the force tolerance (an exact elastic predictor) has a round-off energy
        # reference: after one correction the force criterion alone decides
        if rnorm <= opts.rtol and (energies[-1] <= opts.etol or (it >= 1 and residuals[0] <= opts.rtol)):
            return _converged(u, response.full_result(), p_new, it, residuals, energies, cg_total)
        if it == max_iter or rnorm > 1e6 or (it >= 4 and rnorm > 10 * residuals[0]):
            break
        plastic_elems = np.nonzero(response.plastic.any(axis=1))[0]
        try:
            step = prob.solve_correction(r, response.tangent_of(plastic_elems), plastic_elems,
                                         cg_tolerance(opts, it, rnorm, residuals, linear))
        except ConvergenceError as err:
            residuals.append(float("nan"))
            if opts.verbose:
                print(f"    linear solve failed: {err}")
            break
        cg_total += step.cg_iters
        if e0 is None and step.rz0 is not None:
            e0 = abs(step.rz0)
        linear = None if step.linear_residual is None else step.linear_residual / ref
        du = step.du
        du[prob.fixed] = 0.0
        u = u + du
    hist = ", ".join(f"{x:.3e}" for x in residuals)
    raise ConvergenceError(f"Newton did not converge from p0 = {p_old:.6g} to {p_new:.6g} MPa "
                           f"(relative residuals: {hist})")


def cg_tolerance(opts: SolverOptions, it: int, rnorm: float, residuals: list[float],
                 linear: float | None = None) -> float:
    """The inner CG tolerance (relative to |r_k|) of Newton iteration ``it`` (rnorm = |r_k| / ref, residuals: the
    relative residuals so far, r_k last; linear: |r_k-1 - K_t du_k-1| / ref, what the last CG left).

    'fixed': options.cg_rtol. Adaptive forcing (Eisenstat & Walker 1996, SIAM J. Sci. Comput. 17(1)):
    'adaptive', choice 2 (gamma = 0.9): eta = gamma (|r_k| / |r_k-1|)^2, which assumes Newton's quadratic
    convergence; 'mismatch', choice 1: eta = | |r_k| - |r_k-1 - K_t du_k-1| | / |r_k-1|, how far the residual
    found is from the one the last linear model predicted. Where the tangent is inexact (the sub-stepped rolling
    material, :mod:`calibration.rolling.substeps`) Newton converges linearly and choice 2 solves every correction
    to cg_rtol for nothing; where it is exact the mismatch is small and choice 1 solves as tightly. Then, for both,
    no tighter than ``cg_target_fraction`` rtol / |r_k|: a correction solved below that fraction of the Newton
    tolerance cannot make the iteration converge sooner. First iteration: cg_rtol_max; always within
    [cg_rtol, cg_rtol_max]."""
    if opts.cg_forcing == "fixed":
        return opts.cg_rtol
    if it == 0:
        eta = opts.cg_rtol_max
    elif opts.cg_forcing == "mismatch" and linear is not None:
        eta = abs(rnorm - linear) / residuals[-2]
    else:
        eta = 0.9 * (rnorm / residuals[-2]) ** 2
    eta = max(eta, opts.cg_target_fraction * opts.rtol / max(rnorm, 1e-300))
    return min(opts.cg_rtol_max, max(opts.cg_rtol, eta))


def _converged(u, res, p_new, it, residuals, energies, cg_total):
    new = SolverState(u, res.plastic_strain, res.back_stress_MPa, res.eq_plastic_strain, p_new, res.stress_MPa)
    return new, dict(iters=it, residuals=residuals, energies=energies, n_plastic=int(np.count_nonzero(res.plastic)),
                     cg_iters=cg_total)


__all__ = ["MaterialResponse", "cg_tolerance", "newton_increment", "return_mapped"]
