"""Normal contact by the Kik–Piotrowski virtual-penetration method with a Prandtl surface layer (paper sec. 4).

Given the profile separation f(y) (mm), the rolling-direction radius R (mm), the normal force N (N), E (MPa),
Poisson's ratio and alpha: the separation is interpolated onto a FIXED lateral strip grid (centres at integer
multiples of h = ``grid_mm``; y = 0 should be the geometric contact point) and shifted so that its minimum is 0.
For an approach delta (mm):

    delta_0 = alpha delta,  g(y) = max(delta_0 - f(y), 0)                          (eq. 9)
    x_l(y) = sqrt(2 R g(y)),  p(x, y) = p_0 / x_l(0) sqrt(x_l(y)^2 - x^2)           (eqs. 10, 11)
    N = p_0 I1 / x_l(0),  I1 = II sqrt(x_l^2 - x^2) dx dy = sum (pi/2) x_l^2 h       (eq. 12)
    delta = 2 w_0 = u_layer(p_0) + p_0 * 2 (1 - nu^2) I2 / (pi E x_l(0))            (eq. 13, layer exact)

u_layer(p_0) is the displacement of the layer element(s) at the reference point (the max of g) loaded from their
current state to p_0: wheel + rail (+ combined) in series. It is piecewise linear in p_0, so the equation for p_0
at fixed delta is solved EXACTLY by locating its segment (the paper's "iteration on the layer stiffness", done in
one step; the secant stiffness k = p_0/u_layer of eq. 13/14 follows). With no layer this is eq. (14)/(15).
N(delta) is monotone; N(delta) = N_target is solved by log-log secant bracketing and Illinois regula falsi.

Two-point contact: g > 0 on disjoint intervals gives one Patch per interval, each with its own reference point
(max of g in it), x_l(0), p_0 and I2 (over its own strips), all sharing delta; the contact condition is written
at each reference point, 2 w_0 = delta - f(y_ref) (f(y_ref) = 0 for the main patch); N is the sum. The elastic
interaction between separate patches is NEGLECTED (each patch's I2 covers only its own strips).
Units: mm, N, MPa.
"""

from __future__ import annotations

import copy

from dataclasses import dataclass, field

import numpy as np
from scipy.interpolate import PchipInterpolator

from contact.boussinesq import boussinesq_integral
from contact.patch import Patch
from contact.prandtl_layer import LayerPair, PrandtlLayer
from meshes.errors import ConvergenceError, InputError, require

__all__ = ["NormalProblem", "NormalSolution", "RegionSolution", "NormalForceEvaluator", "solve_normal", "LayerPair", "strip_grid",
           "layer_points"]

_MAX_BRACKET_STEPS = 60
_MAX_BRACKETED_ITERATIONS = 100


def strip_grid(y_min_mm: float, y_max_mm: float, grid_mm: float) -> np.ndarray:
    """Strip centres j h (integer j) inside [y_min, y_max] (mm): the fixed lateral grid."""
    j0 = int(np.ceil(y_min_mm / grid_mm - 1e-9))
    j1 = int(np.floor(y_max_mm / grid_mm + 1e-9))
    return np.arange(j0, j1 + 1) * grid_mm


@dataclass(frozen=True)
class NormalProblem:
    """Input of the normal problem (units mm, N, MPa).

    y_mm, f_mm: the separation table (y increasing); interpolation "linear" or "pchip" (monotone cubic) onto the
    strip grid of width ``grid_mm``; ``f_offset_mm`` (optional, same length as the strip grid) is added on the
    grid (dents from earlier passes).
    """

    y_mm: np.ndarray
    f_mm: np.ndarray
    normal_force_N: float
    rolling_radius_mm: float
    E_MPa: float
    poisson: float
    alpha: float = 0.55
    grid_mm: float = 0.1
    interpolation: str = "linear"
    x_subdivision: int = 1
    f_offset_mm: np.ndarray | None = None
    _grid: tuple = field(default=None, init=False, repr=False, compare=False)

    def __post_init__(self):
        y = np.asarray(self.y_mm, dtype=float).ravel()
        f = np.asarray(self.f_mm, dtype=float).ravel()
        object.__setattr__(self, "y_mm", y)
        object.__setattr__(self, "f_mm", f)
        require(y.size == f.size and y.size >= 2, "separation", "y_mm and f_mm need the same length (>= 2)")
        require(bool(np.all(np.isfinite(y)) and np.all(np.isfinite(f))), "separation", "contains NaN/inf")
        require(bool(np.all(np.diff(y) > 0)), "separation.y_mm", "must be strictly increasing")
        for name in ("normal_force_N", "rolling_radius_mm", "E_MPa", "grid_mm"):
            v = getattr(self, name)
            require(bool(np.isfinite(v) and v > 0), name, f"must be a positive number, got {v!r}")
        require(bool(-1.0 < self.poisson < 0.5), "poisson", f"must lie in (-1, 0.5), got {self.poisson!r}")
        require(bool(0.0 < self.alpha <= 1.0), "alpha", f"must lie in (0, 1], got {self.alpha!r}")
        require(self.interpolation in ("linear", "pchip"), "interpolation",
                f"must be 'linear' or 'pchip', got {self.interpolation!r}")
        require(int(self.x_subdivision) >= 1, "x_subdivision", "must be a positive integer")
        yg = strip_grid(y[0], y[-1], self.grid_mm)
        require(yg.size >= 1, "separation.y_mm", f"range shorter than one grid step {self.grid_mm} mm")
        fg = np.interp(yg, y, f) if self.interpolation == "linear" else PchipInterpolator(y, f)(yg)
        object.__setattr__(self, "_grid", (yg, fg))
        self._set_offset(self.f_offset_mm)

    def _set_offset(self, f_offset_mm) -> None:
        yg, fg = self._grid[:2]
        if f_offset_mm is not None:
            off = np.asarray(f_offset_mm, dtype=float).ravel()
            require(off.shape == yg.shape and bool(np.all(np.isfinite(off))), "f_offset_mm",
                    f"needs {yg.size} finite values (one per strip)")
            object.__setattr__(self, "f_offset_mm", off)
            fg = fg + off
        object.__setattr__(self, "_grid", (yg, self._grid[1], fg))

    @property
    def strip_y_mm(self) -> np.ndarray:
        """Centres of the fixed strip grid (mm)."""
        return self._grid[0]

    @property
    def separation_on_grid_mm(self) -> np.ndarray:
        """f on the strip grid, shifted so that its minimum is 0 (mm)."""
        return self._grid[2] - self._grid[2].min()

    @property
    def separation_unshifted_on_grid_mm(self) -> np.ndarray:
        """f interpolated onto the strip grid plus ``f_offset_mm``, not shifted (mm)."""
        return self._grid[2]

    def with_offset(self, f_offset_mm: np.ndarray) -> "NormalProblem":
        """The same problem with the separation raised by ``f_offset_mm`` on the strip grid (dents)."""
        out = copy.copy(self)                      # the interpolated table is shared, only the offset changes
        out._set_offset(f_offset_mm)
        return out

    @property
    def elastic_compliance_factor(self) -> float:
        """2 (1 - nu^2) / (pi E) (1/MPa): elastic part of delta = factor * p_0 * I2 / x_l(0) (mm)."""
        return 2.0 * (1.0 - self.poisson ** 2) / (np.pi * self.E_MPa)


@dataclass(frozen=True)
class RegionSolution:
    """One contact region: strip indices (into the strip grid), reference strip, p_0, integrals, layer part."""

    strips: np.ndarray
    reference: int
    x_lead_mm: np.ndarray
    p0_MPa: float
    I1_mm3: float
    I2_mm2: float
    u_layer_mm: float
    normal_force_N: float
    layer_segments: int


@dataclass(frozen=True)
class NormalSolution:
    """Result of :func:`solve_normal` (units mm, N, MPa). ``u0_mm`` is the layer displacement (all layers) at the
    reference point of the main patch (largest p_0); ``p_peak_MPa`` is p(0, y) on the whole strip grid (0 outside
    contact); ``elastic`` is True when no layer element yields under this load."""

    patches: list[Patch]
    regions: list[RegionSolution]
    delta_mm: float
    delta0_mm: float
    p_max_MPa: float
    length_mm: float
    width_mm: float
    area_mm2: float
    u0_mm: float
    strip_y_mm: np.ndarray
    p_peak_MPa: np.ndarray
    iterations: dict
    residual_N: float
    elastic: bool
    normal_force_N: float


def _regions(g: np.ndarray) -> list[np.ndarray]:
    """Index arrays of the maximal runs of g > 0."""
    on = np.flatnonzero(g > 0)
    if on.size == 0:
        return []
    cuts = np.flatnonzero(np.diff(on) > 1) + 1
    if cuts.size == 0:
        return [on]
    bounds = [0, *cuts.tolist(), on.size]
    return [on[a:b] for a, b in zip(bounds[:-1], bounds[1:])]


def layer_points(layer: PrandtlLayer, y_grid: np.ndarray, h: float) -> np.ndarray:
    """Index of the layer point at each strip centre y_grid (mm), -1 where the layer has no point there."""
    idx = np.searchsorted(layer.y_mm, y_grid - 0.25 * h)
    ok = (idx < layer.n_points)
    ok[ok] = np.abs(layer.y_mm[idx[ok]] - y_grid[ok]) < 0.25 * h
    return np.where(ok, idx, -1)


class _LayerAtReference:
    """Piecewise-linear loading curve u(p) of all layers at one strip, from their current state (p = 0)."""

    def __init__(self, layers: list[tuple[PrandtlLayer, int]]):
        curves = [lay.loading_curve(i) for lay, i in layers]
        knots = np.unique(np.concatenate([c[0] for c in curves] + [[0.0]]))
        self.p = knots[knots >= 0.0]
        self.u = np.zeros_like(self.p)
        self.final_compliance = 0.0
        for pk, uk, kl in curves:
            u = np.interp(self.p, pk, uk)                   # the curve is piecewise linear through its knots
            beyond = self.p > pk[-1]
            u[beyond] = uk[-1] + (self.p[beyond] - pk[-1]) / kl
            self.u += u - uk[0]
            self.final_compliance += 1.0 / kl

    def solve(self, delta: float, c: float) -> tuple[float, float, int]:
        """p_0 with u(p_0) + c p_0 = delta (exact): (p_0, u(p_0), segment number 1..)."""
        h = self.u + c * self.p - delta
        j = int(np.searchsorted(h, 0.0))                    # first knot with h >= 0 (h strictly increasing)
        if j == 0:
            return 0.0, 0.0, 1
        if j >= self.p.size:
            p0 = self.p[-1] - h[-1] / (self.final_compliance + c)
            return float(p0), float(self.u[-1] + (p0 - self.p[-1]) * self.final_compliance), int(self.p.size)
        t = -h[j - 1] / (h[j] - h[j - 1])
        p0 = self.p[j - 1] + t * (self.p[j] - self.p[j - 1])
        return float(p0), float(self.u[j - 1] + t * (self.u[j] - self.u[j - 1])), j


class NormalForceEvaluator:
    """The normal force N(delta) (N) of a problem at a given approach delta (mm), for fixed geometry and layer state.

    ``NormalForceEvaluator(prob, layer)``: the layers (if any) must sit on the problem's strip grid and be unloaded
    (InputError otherwise). :meth:`force_at` solves the contact conditions at that approach (no force target) and
    keeps the regions of the last evaluation in ``last`` = (delta, N, [RegionSolution]); ``evaluations`` counts the
    calls. Used by :func:`solve_normal` (bracketing N(delta) = N_target) and by the wheel–rail load balance, which
    shares one approach between several contact candidates.
    """

    def __init__(self, prob: NormalProblem, layer: LayerPair | None):
        self.prob = prob
        self.y, self.f = prob.strip_y_mm, prob.separation_on_grid_mm
        self.layers = [] if layer is None else list(layer.bodies().values())
        self.index = [layer_points(lay, self.y, prob.grid_mm) for lay in self.layers]
        for lay, ix in zip(self.layers, self.index):
            if np.any(np.abs(lay.pressure_MPa) > 1e-9 * max(1.0, float(np.abs(lay.pressure_MPa).max()))):
                raise InputError(lay.name, "layer must be unloaded (p = 0) before a normal solve")
        self._curves: dict[int, _LayerAtReference] = {}
        self.evaluations = 0
        self.layer_segments = 0
        self.last = None

    def _curve(self, j: int) -> _LayerAtReference | None:
        if not self.layers:
            return None
        if j not in self._curves:
            pairs = []
            for lay, ix in zip(self.layers, self.index):
                if ix[j] < 0:
                    raise InputError(lay.name, f"has no element at strip y = {self.y[j]:.6g} mm (contact there)")
                pairs.append((lay, int(ix[j])))
            self._curves[j] = _LayerAtReference(pairs)
        return self._curves[j]

    def force_at(self, delta: float) -> float:
        """N(delta) (N) at the approach ``delta`` (mm): the sum of the regions' forces (eq. 12)."""
        self.evaluations += 1
        p = self.prob
        h = p.grid_mm
        g = np.maximum(p.alpha * delta - self.f, 0.0)
        regions = []
        total = 0.0
        for strips in _regions(g):
            ref = int(strips[np.argmax(g[strips])])
            xl = np.sqrt(2.0 * p.rolling_radius_mm * g[strips])
            xl0 = float(np.sqrt(2.0 * p.rolling_radius_mm * g[ref]))
            i1 = float(np.sum(0.5 * np.pi * xl * xl) * h)
            i2 = boussinesq_integral(xl, strips - ref, h, p.x_subdivision)
            c = p.elastic_compliance_factor * i2 / xl0
            approach = delta - self.f[ref]                 # contact condition at this region's reference point
            curve = self._curve(ref)
            if curve is None:
                p0, u0, seg = approach / c, 0.0, 1
            else:
                p0, u0, seg = curve.solve(approach, c)
            n_r = p0 * i1 / xl0
            total += n_r
            regions.append(RegionSolution(strips, ref, xl, p0, i1, i2, u0, n_r, seg))
        self.last = (delta, total, regions)
        return total


def _find_delta(ev: NormalForceEvaluator, target: float, delta_guess: float, rtol: float) -> tuple[float, int, int]:
    """Solve N(delta) = target (N increasing in delta). Returns (delta, bracketing steps, bracketed iterations).

    In log-log coordinates N(delta) is nearly a straight line (Hertz: N ~ delta^1.5), so: secant steps in
    log-log (first step with exponent 1.5, step factor limited to [1/4, 4]) until the root is bracketed, then
    Illinois regula falsi in log-log on the bracket (guaranteed, superlinear). Stops at |N - target| <= rtol
    target or when the bracket is below 1e-14 delta; ConvergenceError after too many steps.
    """
    lt = np.log(target)
    pts: list[tuple[float, float]] = []             # (log delta, log N - log target)
    lo = hi = None
    d = delta_guess
    steps = 0
    while lo is None or hi is None:
        steps += 1
        if steps > _MAX_BRACKET_STEPS:
            raise ConvergenceError(f"normal approach delta: no bracket for N = {target:g} N after "
                                   f"{_MAX_BRACKET_STEPS} steps (last delta = {d:g} mm)")
        n = ev.force_at(d)
        if not (np.isfinite(n) and n >= 0):
            raise ConvergenceError(f"normal approach delta: N(delta = {d:g} mm) = {n!r}")
        if abs(n - target) <= rtol * target:
            return d, steps, 0
        r = (np.log(n) if n > 0 else -np.inf) - lt
        pts.append((np.log(d), r))
        if r < 0:
            lo = pts[-1]
        else:
            hi = pts[-1]
        if lo is not None and hi is not None:
            break
        if len(pts) >= 2 and np.isfinite(pts[-2][1]) and np.isfinite(r) and pts[-1][1] != pts[-2][1]:
            slope = (pts[-1][1] - pts[-2][1]) / (pts[-1][0] - pts[-2][0])
            step = -r / slope if slope > 0 else (np.log(4.0) if r < 0 else -np.log(4.0))
        else:
            step = -r / 1.5 if np.isfinite(r) else np.log(4.0)
        d = np.exp(pts[-1][0] + float(np.clip(step, -np.log(4.0), np.log(4.0))))
    side = 0
    for it in range(1, _MAX_BRACKETED_ITERATIONS + 1):
        (xa, fa), (xb, fb) = lo, hi
        if not np.isfinite(fa):                      # N = 0 at lo: bisect
            x = 0.5 * (xa + xb)
        else:
            x = xa - fa * (xb - xa) / (fb - fa)
            if not xa < x < xb:
                x = 0.5 * (xa + xb)
        d = float(np.exp(x))
        n = ev.force_at(d)
        if abs(n - target) <= rtol * target or (xb - xa) < 1e-14:
            return d, steps, it
        r = (np.log(n) if n > 0 else -np.inf) - lt
        if r < 0:
            lo = (x, r)
            if side == -1:
                hi = (hi[0], 0.5 * hi[1])            # Illinois: halve the stale end's residual
            side = -1
        else:
            hi = (x, r)
            if side == 1 and np.isfinite(lo[1]):
                lo = (lo[0], 0.5 * lo[1])
            side = 1
    raise ConvergenceError(f"normal approach delta: not converged after {_MAX_BRACKETED_ITERATIONS} iterations "
                           f"(bracket [{np.exp(lo[0]):g}, {np.exp(hi[0]):g}] mm)")


def _hertz_like_guess(prob: NormalProblem) -> float:
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
                 rtol_N: float = 1e-9) -> NormalSolution:
    """Solve the normal contact (paper eqs. 9–15) for ``prob.normal_force_N``; the layers are NOT modified.

    The layers (if any) must sit on the problem's strip grid (points at the strip centres) and be unloaded.
    Raises ConvergenceError when delta cannot be bracketed or the regula falsi does not converge, or when the residual
    |N - N_target| exceeds rtol_N N_target.
    """
    ev = NormalForceEvaluator(prob, layer)
    guess = delta_guess_mm if delta_guess_mm is not None and delta_guess_mm > 0 else _hertz_like_guess(prob)
    delta, steps, bracketed_iter = _find_delta(ev, prob.normal_force_N, guess, 0.1 * rtol_N)
    if ev.last is None or ev.last[0] != delta:
        ev.force_at(delta)
    _, n_total, regions = ev.last
    residual = n_total - prob.normal_force_N
    if not abs(residual) <= rtol_N * prob.normal_force_N:
        raise ConvergenceError(f"normal force: residual {residual:g} N exceeds {rtol_N:g} N_target at "
                               f"delta = {delta:g} mm")
    h = prob.grid_mm
    y = prob.strip_y_mm
    p_peak = np.zeros_like(y)
    patches = []
    for r in regions:
        pk = r.p0_MPa * r.x_lead_mm / r.x_lead_mm[np.flatnonzero(r.strips == r.reference)[0]]
        p_peak[r.strips] = pk
        patches.append(Patch(h, y[r.strips], r.x_lead_mm, pk))
    main = max(regions, key=lambda r: r.p0_MPa)
    elastic = True
    if layer is not None:
        for lay, ix in zip(ev.layers, ev.index):
            on = p_peak > 0
            if np.any(ix[on] < 0):
                raise InputError(lay.name, "does not cover the contact patch (strips without a layer element)")
            if np.any(p_peak[on] > lay.yield_pressure_MPa()[ix[on]] * (1.0 + 1e-12)):
                elastic = False
    return NormalSolution(
        patches=patches, regions=regions, delta_mm=float(delta), delta0_mm=float(prob.alpha * delta),
        p_max_MPa=float(p_peak.max()), length_mm=max(pt.length_mm() for pt in patches),
        width_mm=float(sum(pt.width_mm() for pt in patches)), area_mm2=float(sum(pt.area_mm2() for pt in patches)),
        u0_mm=float(main.u_layer_mm), strip_y_mm=y, p_peak_MPa=p_peak,
        iterations={"delta_evaluations": ev.evaluations, "bracket_steps": steps,
                    "bracketed_iterations": bracketed_iter, "layer_segments": int(main.layer_segments)},
        residual_N=float(residual), elastic=elastic, normal_force_N=float(n_total))
