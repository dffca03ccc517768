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

Several contact regions (``region_interaction=True``, the default). Every local minimum m of f (strip y_m,
f_m = f(y_m) < delta) is a candidate reference point. Its local approach is a_m = delta - f_m - w_m, where w_m is
the elastic displacement at (0, y_m) caused by the pressures of the OTHER regions,
w_m = sum_k 2 (1 - nu^2) / (pi E) p_0k I2_mk / x_l0,k (eq. 13's Boussinesq integral of region k about y_m, the
same exact-kernel table with integer strip offsets). A candidate with a_m > 0 (not inside a lower candidate's
region) gets its own virtual penetration, the paper's rule applied to its local approach:
g_m(y) = alpha a_m - (f(y) - f_m) on the run of strips around y_m where it is > 0 (runs that overlap or touch are
merged: larger g, reference at the lower minimum), and its contact condition at y_m is
a_m = u_layer(p_0m) + p_0m 2 (1 - nu^2) I2_mm / (pi E x_l0,m). A candidate with a_m <= 0 is lifted off. The
w_m are found by an accelerated fixed-point iteration (to 1e-14 delta; ConvergenceError after 200 iterations). Hence a region
appears when the deformed surfaces touch (f_m = delta - w_m, where a_m = 0) with zero size and load, and its
load grows continuously (~a_m^1.5) from there. With one candidate (one region, e.g. the paper's example) this is
exactly eqs. 9–15 above: a = delta, g = alpha delta - f. ``region_interaction=False`` reproduces the earlier
independent regions: one region per run of alpha delta - f > 0, condition delta - f(y_ref) at its reference
(max of g), no interaction; there a region that alpha delta just touches carries a finite load (p_0 -> infinity
as its width -> 0), a discontinuity of N(delta).
Units: mm, N, MPa.
"""

from __future__ import annotations

import copy

from dataclasses import dataclass, field

import numpy as np
from scipy.interpolate import PchipInterpolator

from contact.normal.boussinesq import boussinesq_integral
from contact.normal.patch import Patch
from contact.layer.prandtl_layer import LayerPair, PrandtlLayer
from wrlayer.errors import ConvergenceError, InputError, require

__all__ = ["NormalProblem", "NormalSolution", "RegionSolution", "NormalForceEvaluator", "solve_normal", "LayerPair", "strip_grid",
           "layer_points"]

_MAX_BRACKET_STEPS = 60
_MAX_BRACKETED_ITERATIONS = 100
_MAX_INTERACTION_ITERATIONS = 200


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
    grid (dents from earlier passes). ``region_interaction``: separate contact regions interact elastically and each
    region's virtual penetration comes from its own local approach (module docstring); False: the independent
    regions of the earlier solver (kept for comparison).
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
    region_interaction: bool = True
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
    """One contact region: strip indices (into the strip grid), reference strip, x_l per strip (mm), p_0 (MPa),
    I1 (mm^3), own-region I2 (mm^2), layer displacement at the reference (mm), force (N), layer segment;
    approach_mm: the local approach a at the reference strip (delta - f(y_ref) - interaction, mm);
    interaction_mm: the elastic displacement at the reference point caused by the OTHER regions (mm)."""

    strips: np.ndarray
    reference: int
    x_lead_mm: np.ndarray
    p0_MPa: float
    I1_mm3: float
    I2_mm2: float
    u_layer_mm: float
    normal_force_N: float
    layer_segments: int
    approach_mm: float = float("nan")
    interaction_mm: float = 0.0


@dataclass(frozen=True)
class NormalSolution:
    """Result of :func:`solve_normal` (units mm, N, MPa). ``u0_mm`` is the layer displacement (all layers) at the
    reference point of the main patch (largest p_0); ``p_peak_MPa`` is p(0, y) on the whole strip grid (0 outside
    contact); ``elastic`` is True when no layer element yields under this load. ``method``: the normal solver that
    produced it ("kik_piotrowski" or "exact"); ``field``: the exact solver's pressure grid
    (:class:`contact.normal.exact.ExactField`), None for Kik–Piotrowski."""

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
    method: str = "kik_piotrowski"
    field: object = None


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


def _single_valley(f: np.ndarray) -> bool:
    """True when f has one local minimum (possibly flat): every descent comes before every ascent."""
    d = np.diff(f)
    down, up = np.flatnonzero(d < 0), np.flatnonzero(d > 0)
    return down.size == 0 or up.size == 0 or down[-1] < up[0]


def _local_minima(f: np.ndarray) -> np.ndarray:
    """Strip indices of the local minima of f (first strip of a flat bottom; the table ends count), ordered by
    ascending f (ties: left first)."""
    d = np.diff(f)
    steps = np.flatnonzero(d)                            # f changes between strips i and i + 1
    if steps.size == 0:
        return np.zeros(1, dtype=np.int64)
    up = d[steps] > 0
    mins = steps[:-1][~up[:-1] & up[1:]] + 1            # a descent followed by an ascent
    if up[0]:
        mins = np.concatenate([[0], mins])
    if not up[-1]:
        mins = np.concatenate([mins, steps[-1:] + 1])
    return mins[np.argsort(f[mins], kind="stable")]


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
        self.minima = _local_minima(self.f) if prob.region_interaction and not _single_valley(self.f) else None
        self.minima_f = None if self.minima is None else self.f[self.minima]     # None: always one region
        self._warm = None                                  # (delta, candidates, w) of the last interaction solve
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
        if self.minima is not None and self.minima_f[1] < delta:   # two or more local minima of f below delta
            n_cand = int(np.searchsorted(self.minima_f, delta))
            regions = self._interacting_regions(delta, [int(m) for m in self.minima[:n_cand]])
        else:                                                    # independent regions (one region: identical)
            g = np.maximum(self.prob.alpha * delta - self.f, 0.0)
            regions = [self._region(strips, g[strips], ref, delta - self.f[ref], 0.0)
                       for strips in _regions(g) for ref in (int(strips[np.argmax(g[strips])]),)]
        total = 0.0
        for r in regions:
            total += r.normal_force_N
        self.last = (delta, total, regions)
        return total

    def _region(self, strips: np.ndarray, g: np.ndarray, ref: int, approach: float,
                interaction: float) -> RegionSolution:
        """Solve one region for its p_0: approach = u_layer(p_0) + p_0 * 2 (1 - nu^2) I2 / (pi E x_l(0)) at the
        reference strip (eq. 13, own strips' I2); g: the virtual penetration on ``strips`` (mm)."""
        p = self.prob
        xl = np.sqrt(2.0 * p.rolling_radius_mm * g)
        xl0 = float(xl[ref - strips[0]])                          # strips are contiguous
        i1 = float(np.sum(0.5 * np.pi * xl * xl) * p.grid_mm)
        i2 = boussinesq_integral(xl, strips - ref, p.grid_mm, p.x_subdivision)
        c = p.elastic_compliance_factor * i2 / xl0
        curve = self._curve(ref)
        if curve is None:
            p0, u0, seg = approach / c, 0.0, 1
        else:
            p0, u0, seg = curve.solve(approach, c)
        return RegionSolution(strips, ref, xl, p0, i1, i2, u0, p0 * i1 / xl0, seg, approach, interaction)

    def displacement_at(self, region: RegionSolution, strip: int) -> float:
        """Elastic displacement (mm) at the point (x = 0, y = strip centre) caused by ``region``'s pressure
        (Boussinesq integral of eq. 13 about that point; strip: index into the strip grid)."""
        p = self.prob
        xl0 = float(region.x_lead_mm[region.reference - region.strips[0]])
        i2 = boussinesq_integral(region.x_lead_mm, region.strips - strip, p.grid_mm, p.x_subdivision)
        return p.elastic_compliance_factor * i2 / xl0 * region.p0_MPa

    def _interacting_regions(self, delta: float, cand: list[int]) -> list[RegionSolution]:
        """The regions at approach delta with elastic interaction (module docstring): fixed point w = W(w) on the
        displacements w_m that the other regions cause at the candidate reference strips (local minima of f),
        accelerated by Anderson mixing (memory 3; when the regions' strips change or the residual grows, e.g. a
        region lifts off, the history is dropped and a step damped by 1/2 is taken), warm-started from the previous
        delta's solution scaled by (delta/delta_prev)^1.5 (Hertz). ConvergenceError after
        _MAX_INTERACTION_ITERATIONS iterations."""
        tol = 1e-14 * delta
        w = np.zeros(len(cand))
        if self._warm is not None and self._warm[1] == cand:
            w = self._warm[2] * (delta / self._warm[0]) ** 1.5
        hist_g: list[np.ndarray] = []
        hist_r: list[np.ndarray] = []
        last_shape, damp = None, 1.0
        for _ in range(_MAX_INTERACTION_ITERATIONS):
            regions = [self._region(strips, g, ref, delta - self.f[ref] - w[cand.index(ref)], w[cand.index(ref)])
                       for strips, g, ref in self._local_penetrations(delta, cand, w)]
            owner = [next((r for r in regions if r.strips[0] <= m <= r.strips[-1]), None) for m in cand]
            w_new = np.array([0.0 if o is not None and o.reference != m else      # absorbed: w_m not used
                              sum(self.displacement_at(r, m) for r in regions if r is not o) for m, o in
                              zip(cand, owner)])                                 # the other regions' displacement
            res = w_new - w
            if np.max(np.abs(res)) <= tol:
                self._warm = (delta, cand, w)
                return regions
            shape = [(r.reference, r.strips[0], r.strips[-1]) for r in regions]
            if hist_r and (shape != last_shape or np.max(np.abs(res)) > np.max(np.abs(hist_r[-1]))):
                hist_g, hist_r = [], []        # regions changed or not contracting: restart with a damped step
                damp = 0.5
            last_shape = shape
            hist_g.append(w_new)
            hist_r.append(res)
            del hist_g[:-4], hist_r[:-4]
            if len(hist_r) >= 2:
                d_r = np.diff(np.array(hist_r), axis=0).T
                d_g = np.diff(np.array(hist_g), axis=0).T
                gamma = np.linalg.lstsq(d_r, res, rcond=None)[0]
                w = w_new - d_g @ gamma
            else:
                w = w + damp * res
        raise ConvergenceError(f"contact regions at delta = {delta:g} mm: the elastic interaction between regions "
                               f"did not converge in {_MAX_INTERACTION_ITERATIONS} iterations (lift-off cycling)")

    def _local_penetrations(self, delta: float, cand: list[int], w: np.ndarray) -> list[tuple[np.ndarray, np.ndarray, int]]:
        """(strips, g on them, reference strip) of each region, ordered by y. Candidate m (ascending f) that is
        not inside an earlier region and has a local approach a = delta - f_m - w_m > 0 gets the run of strips
        around m with g = alpha a - (f - f_m) > 0; where that run would reach an earlier region, it ends at the
        ridge (max of f) between the two (each region keeps its own basin)."""
        f, alpha = self.f, self.prob.alpha
        runs: list[tuple[int, int, int, float]] = []           # (first, last, reference, level)
        for m in cand:
            if any(r[0] <= m <= r[1] for r in runs):
                continue
            a = delta - f[m] - w[cand.index(m)]
            if a <= 0.0:
                continue
            level = f[m] + alpha * a
            lo = m - int(np.argmax(np.append(f[m::-1] >= level, True))) + 1
            hi = m + int(np.argmax(np.append(f[m:] >= level, True))) - 1
            for r in runs:                                   # ridge: max of f strictly between the two
                if r[1] < m and lo <= r[1] + 1:                  # spills over into the region on the left
                    between = f[r[1] + 1:m]
                    lo = max(lo, r[1] + 1 + int(np.argmax(between)) if between.size else m)
                if r[0] > m and hi >= r[0] - 1:                  # ... on the right (it may start at m + 1)
                    between = f[m + 1:r[0]]
                    hi = min(hi, m + 1 + int(np.argmax(between)) if between.size else m)
            runs.append((lo, hi, m, level))
        out = []
        for lo, hi, m, level in sorted(runs):
            strips = np.arange(lo, hi + 1)
            out.append((strips, level - f[strips], m))
        return out


def _find_delta(ev: NormalForceEvaluator, target: float, delta_guess: float, rtol: float,
                slope_guess: float = 1.5) -> tuple[float, int, int, float]:
    """Solve N(delta) = target (N increasing in delta). Returns (delta, bracketing steps, bracketed iterations,
    the last secant slope d log N / d log delta, or ``slope_guess`` when none was computed).

    In log-log coordinates N(delta) is nearly a straight line (Hertz: N ~ delta^1.5), so: secant steps in
    log-log (first step with exponent ``slope_guess``, step factor limited to [1/4, 4]) until the root is bracketed, then
    Illinois regula falsi in log-log on the bracket (guaranteed, superlinear). Stops at |N - target| <= rtol
    target or when the bracket is below 1e-14 delta; ConvergenceError after too many steps.
    """
    lt = np.log(target)
    pts: list[tuple[float, float]] = []             # (log delta, log N - log target)
    lo = hi = None
    d = delta_guess
    steps = 0
    last_slope = slope_guess
    while lo is None or hi is None:
        steps += 1
        if steps > _MAX_BRACKET_STEPS:
            raise ConvergenceError(f"normal approach delta: no bracket for N = {target:g} N after "
                                   f"{_MAX_BRACKET_STEPS} steps (last delta = {d:g} mm)")
        n = ev.force_at(d)
        if not (np.isfinite(n) and n >= 0):
            raise ConvergenceError(f"normal approach delta: N(delta = {d:g} mm) = {n!r}")
        if abs(n - target) <= rtol * target:
            return d, steps, 0, last_slope
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
            if slope > 0:
                last_slope = slope
            step = -r / slope if slope > 0 else (np.log(4.0) if r < 0 else -np.log(4.0))
        else:
            step = -r / last_slope if np.isfinite(r) else np.log(4.0)
        d = np.exp(pts[-1][0] + float(np.clip(step, -np.log(4.0), np.log(4.0))))
    side = 0
    n_at = [lo[1], hi[1]]                            # log(N / target) at the bracket ends (not Illinois-halved)
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
        if abs(n - target) <= rtol * target:
            return d, steps, it, last_slope
        if (xb - xa) < 1e-14:  # the bracket has collapsed onto a jump of N(delta)
            n_lo, n_hi = np.exp(lt + np.array(n_at))
            raise ConvergenceError(f"normal approach delta: N(delta) jumps across the target N = {target:g} N at "
                                   f"delta = {d:g} mm (from {n_lo:g} to {n_hi:g} N; a discontinuity of the region "
                                   "model, e.g. contact regions merging or separating): no approach gives this "
                                   "force")
        r = (np.log(n) if n > 0 else -np.inf) - lt
        if r < 0:
            n_at[0] = r
            lo = (x, r)
            if side == -1:
                hi = (hi[0], 0.5 * hi[1])            # Illinois: halve the stale end's residual
            side = -1
        else:
            n_at[1] = r
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
                 rtol_N: float = 1e-9, loglog_slope_guess: float | None = None) -> NormalSolution:
    """Solve the normal contact (paper eqs. 9–15) for ``prob.normal_force_N``; the layers are NOT modified.

    The layers (if any) must sit on the problem's strip grid (points at the strip centres) and be unloaded.
    ``delta_guess_mm`` and ``loglog_slope_guess`` (d log N / d log delta, e.g. ``iterations["loglog_slope"]`` of a
    neighbouring solve; default 1.5, Hertz) only start the iteration on delta.
    Raises InputError when the patch reaches either end of the separation table (it would be truncated), and
    ConvergenceError when delta cannot be bracketed or the regula falsi does not converge, or when the residual
    |N - N_target| exceeds rtol_N N_target.
    """
    ev = NormalForceEvaluator(prob, layer)
    guess = delta_guess_mm if delta_guess_mm is not None and delta_guess_mm > 0 else _hertz_like_guess(prob)
    slope = loglog_slope_guess if loglog_slope_guess is not None and loglog_slope_guess > 0 else 1.5
    delta, steps, bracketed_iter, slope = _find_delta(ev, prob.normal_force_N, guess, 0.1 * rtol_N, slope)
    if ev.last is None or ev.last[0] != delta:
        ev.force_at(delta)
    _, n_total, regions = ev.last
    residual = n_total - prob.normal_force_N
    if not abs(residual) <= rtol_N * prob.normal_force_N:
        raise ConvergenceError(f"normal force: residual {residual:g} N exceeds {rtol_N:g} N_target at "
                               f"delta = {delta:g} mm")
    h = prob.grid_mm
    y = prob.strip_y_mm
    for r in regions:
        if r.strips[0] == 0 or r.strips[-1] == y.size - 1:
            end = y[0] if r.strips[0] == 0 else y[-1]
            raise InputError("separation.y_mm", f"the contact patch reaches the end of the separation table at "
                             f"y = {end:.4g} mm (N = {prob.normal_force_N:g} N): extend the table (it covers "
                             f"{prob.y_mm[0]:.4g}..{prob.y_mm[-1]:.4g} mm)")
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
                    "bracketed_iterations": bracketed_iter, "layer_segments": int(main.layer_segments),
                    "loglog_slope": float(slope)},
        residual_N=float(residual), elastic=elastic, normal_force_N=float(n_total))
