"""Normal contact by the Kik–Piotrowski virtual-penetration method with a Prandtl surface layer (paper sec. 4).

Given the profile separation f(y) (mm) on the problem's strip grid (:class:`~contact.normal.problem.NormalProblem`),
the rolling-direction radius R (mm), the normal force N (N), E (MPa), Poisson's ratio and alpha, for an approach
delta (mm):

    delta_0 = alpha delta,  g(y) = max(delta_0 - f(y), 0)                          (eq. 9)
    x_l(y) = sqrt(2 R g(y)),  p(x, y) = p_0 / x_l(0) sqrt(x_l(y)^2 - x^2)           (eqs. 10, 11)
    N = p_0 I1 / x_l(0),  I1 = II sqrt(x_l^2 - x^2) dx dy = sum (pi/2) x_l^2 h       (eq. 12)
    delta = 2 w_0 = u_layer(p_0) + p_0 * 2 (1 - nu^2) I2 / (pi E x_l(0))            (eq. 13, layer exact)

u_layer(p_0) is the displacement of the layer element(s) at the reference point (the max of g), solved exactly on
its piecewise-linear loading curve (:mod:`contact.normal.layer_at_strip`); with no layer this is eq. (14)/(15).
N(delta) at one approach, with several interacting contact regions: :mod:`contact.normal.regions`.
N(delta) = N_target is solved by log-log secant bracketing and Illinois regula falsi
(:mod:`contact.normal.delta_search`). Units: mm, N, MPa.
"""

from __future__ import annotations

import numpy as np

from contact.layer.prandtl_layer import LayerPair
from contact.normal.delta_search import find_delta
from contact.normal.layer_at_strip import layer_points
from contact.normal.patch import Patch
from contact.normal.problem import NormalProblem, strip_grid
from contact.normal.regions import NormalForceEvaluator
from contact.normal.solution import NormalSolution, RegionSolution
from wrlayer.errors import ConvergenceError, InputError

# NormalProblem, NormalSolution, ... are re-exported: callers import the solver's input and output from here
__all__ = ["NormalProblem", "NormalSolution", "RegionSolution", "NormalForceEvaluator", "solve_normal", "LayerPair",
           "strip_grid", "layer_points", "check_arguments"]


def check_arguments(prob, layer, caller: str) -> None:
    """TypeError unless ``prob`` is a NormalProblem and ``layer`` a LayerPair or None (a clear message instead of an
    AttributeError deep in the solver when the arguments are swapped or a PrandtlLayer is passed alone)."""
    if not isinstance(prob, NormalProblem):
        raise TypeError(f"{caller}: the first argument must be a NormalProblem, got {type(prob).__name__}")
    if layer is not None and not isinstance(layer, LayerPair):
        hint = " (wrap it: LayerPair(combined=layer))" if type(layer).__name__ == "PrandtlLayer" else ""
        raise TypeError(f"{caller}: layer must be a LayerPair or None, got {type(layer).__name__}{hint}")


def hertz_like_guess(prob: NormalProblem) -> float:
    """A starting approach (mm) from the local curvature of f at its minimum, Hertz circle-like estimate."""
    f = prob.separation_on_grid_mm
    j = int(np.argmin(f))
    r_eff = prob.rolling_radius_mm
    e_star = prob.E_MPa / (2.0 * (1.0 - prob.poisson ** 2))
    if 0 < j < f.size - 1:
        curv = (f[j - 1] - 2 * f[j] + f[j + 1]) / prob.grid_mm ** 2
        if curv > 0:
            r_eff = np.sqrt(prob.rolling_radius_mm / curv)
    return float((9.0 * prob.normal_force_N ** 2 / (16.0 * r_eff * e_star ** 2)) ** (1.0 / 3.0))


def solve_normal(prob: NormalProblem, layer: LayerPair | None = None, delta_guess_mm: float | None = None,
                 rtol_N: float = 1e-9, loglog_slope_guess: float | None = None) -> NormalSolution:
    """Solve the normal contact (paper eqs. 9–15) for ``prob.normal_force_N``; the layers are NOT modified.

    Parameters
    ----------
    prob : NormalProblem
        Separation (mm), normal force (N), rolling radius (mm), ``E_MPa`` and ``poisson``, alpha, strip grid.
    layer : LayerPair, optional
        The layers (if any), on the problem's strip grid (points at the strip centres) and unloaded.
    delta_guess_mm : float, optional
        Starting approach (mm); default: a Hertz-like estimate from the curvature of f at its minimum.
    rtol_N : float
        Relative force tolerance |N - N_target| <= rtol_N N_target (1).
    loglog_slope_guess : float, optional
        d log N / d log delta to start with, e.g. ``iterations["loglog_slope"]`` of a neighbouring solve
        (default 1.5, Hertz).

    Returns
    -------
    NormalSolution

    Raises
    ------
    InputError
        When the patch reaches either end of the separation table (it would be truncated) or a layer does not
        cover it.
    ConvergenceError
        When delta cannot be bracketed, the regula falsi does not converge or the residual exceeds rtol_N.
    """
    check_arguments(prob, layer, "solve_normal")
    ev = NormalForceEvaluator(prob, layer)
    guess = delta_guess_mm if delta_guess_mm is not None and delta_guess_mm > 0 else hertz_like_guess(prob)
    slope = loglog_slope_guess if loglog_slope_guess is not None and loglog_slope_guess > 0 else 1.5
    delta, steps, bracketed_iter, slope = find_delta(ev, prob.normal_force_N, guess, 0.1 * rtol_N, slope)
    if ev.last is None or ev.last[0] != delta:
        ev.force_at(delta)
    _, n_total, regions = ev.last
    residual = n_total - prob.normal_force_N
    if not abs(residual) <= rtol_N * prob.normal_force_N:
        raise ConvergenceError(f"normal force: residual {residual:g} N exceeds {rtol_N:g} N_target at "
                               f"delta = {delta:g} mm")
    _check_inside_table(prob, regions)
    search = {"bracket_steps": steps, "bracketed_iterations": bracketed_iter, "loglog_slope": float(slope)}
    return _solution(prob, ev, regions, float(delta), search, float(residual), float(n_total))


def _check_inside_table(prob: NormalProblem, regions: list[RegionSolution]) -> None:
    """InputError when a region reaches either end of the strip grid (the patch would be truncated)."""
    y = prob.strip_y_mm
    for r in regions:
        if r.strips[0] == 0 or r.strips[-1] == y.size - 1:
            end = y[0] if r.strips[0] == 0 else y[-1]
            raise InputError("separation.y_mm", f"the contact patch reaches the end of the separation table at "
                             f"y = {end:.4g} mm (N = {prob.normal_force_N:g} N): extend the table (it covers "
                             f"{prob.y_mm[0]:.4g}..{prob.y_mm[-1]:.4g} mm)")


def _solution(prob: NormalProblem, ev: NormalForceEvaluator, regions: list[RegionSolution], delta: float,
              search: dict, residual: float, n_total: float) -> NormalSolution:
    """The patches (eqs. 10-11), sizes and layer state of the converged regions; ``search``: the delta search's
    counts and slope."""
    h, y = prob.grid_mm, prob.strip_y_mm
    p_peak = np.zeros_like(y)
    patches = []
    for r in regions:
        pk = r.p0_MPa * r.x_lead_mm / r.x_lead_mm[np.flatnonzero(r.strips == r.reference)[0]]
        p_peak[r.strips] = pk
        patches.append(Patch(h, y[r.strips], r.x_lead_mm, pk))
    main = max(regions, key=lambda r: r.p0_MPa)
    elastic = True
    for lay, ix in zip(ev.layers, ev.index):
        on = p_peak > 0
        if np.any(ix[on] < 0):
            raise InputError(lay.name, "does not cover the contact patch (strips without a layer element)")
        if np.any(p_peak[on] > lay.yield_pressure_MPa(ix[on]) * (1.0 + 1e-12)):
            elastic = False
    iterations = {"delta_evaluations": ev.evaluations, "bracket_steps": search["bracket_steps"],
                  "bracketed_iterations": search["bracketed_iterations"], "layer_segments": int(main.layer_segments),
                  "loglog_slope": search["loglog_slope"]}
    return NormalSolution(
        patches=patches, regions=regions, delta_mm=delta, delta0_mm=float(prob.alpha * delta),
        p_max_MPa=float(p_peak.max()), length_mm=max(pt.length_mm() for pt in patches),
        width_mm=float(sum(pt.width_mm() for pt in patches)), area_mm2=float(sum(pt.area_mm2() for pt in patches)),
        u0_mm=float(main.u_layer_mm), strip_y_mm=y, p_peak_MPa=p_peak, iterations=iterations,
        residual_N=residual, elastic=elastic, normal_force_N=n_total)
