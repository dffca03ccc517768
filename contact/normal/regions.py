"""The normal force N(delta) at a given approach delta: the contact regions and their elastic interaction.

One region (a single valley of f, e.g. the paper's example) is eqs. 9-13: g = alpha delta - f > 0 on the region's
strips, x_l = sqrt(2 R g), p_0 from the contact condition at the reference strip (the max of g), N from eq. 12.

Several contact regions (``region_interaction=True``, the default). Every local minimum m of f (strip y_m,
f_m = f(y_m) < delta) is a candidate reference point. Its local approach is a_m = delta - f_m - w_m, where w_m is
the elastic displacement at (0, y_m) caused by the pressures of the OTHER regions,
w_m = sum_k 2 (1 - nu^2) / (pi E) p_0k I2_mk / x_l0,k (eq. 13's Boussinesq integral of region k about y_m, the
same exact-kernel table with integer strip offsets). A candidate with a_m > 0 (not inside a lower candidate's
region) gets its own virtual penetration, the paper's rule applied to its local approach:
g_m(y) = alpha a_m - (f(y) - f_m) on the run of strips around y_m where it is > 0 (runs that overlap or touch are
merged: larger g, reference at the lower minimum), and its contact condition at y_m is
a_m = u_layer(p_0m) + p_0m 2 (1 - nu^2) I2_mm / (pi E x_l0,m). A candidate with a_m <= 0 is lifted off. The
w_m are found by an accelerated fixed-point iteration (to 1e-14 delta; ConvergenceError after 200 iterations).
Hence a region appears when the deformed surfaces touch (f_m = delta - w_m, where a_m = 0) with zero size and
load, and its load grows continuously (~a_m^1.5) from there. With one candidate this is exactly eqs. 9-15:
a = delta, g = alpha delta - f. ``region_interaction=False`` reproduces the earlier independent regions: one
region per run of alpha delta - f > 0, condition delta - f(y_ref) at its reference (max of g), no interaction;
there a region that alpha delta just touches carries a finite load (p_0 -> infinity as its width -> 0), a
discontinuity of N(delta). Units: mm, N, MPa.
"""

from __future__ import annotations

import numpy as np

from contact.layer.prandtl_layer import LayerPair
from contact.normal.boussinesq import boussinesq_integral
from contact.normal.layer_at_strip import LayerAtReference, layer_points
from contact.normal.problem import NormalProblem
from contact.normal.solution import RegionSolution
from wrlayer.errors import ConvergenceError, InputError

__all__ = ["NormalForceEvaluator"]

_MAX_INTERACTION_ITERATIONS = 200


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
            if not lay.is_unloaded():
                raise InputError(lay.name, "layer must be unloaded (p = 0) before a normal solve")
        self.minima = _local_minima(self.f) if prob.region_interaction and not _single_valley(self.f) else None
        self.minima_f = None if self.minima is None else self.f[self.minima]     # None: always one region
        self._warm = None                                  # (delta, candidates, w) of the last interaction solve
        self._curves: dict[int, LayerAtReference] = {}
        self.evaluations = 0
        self.layer_segments = 0
        self.last = None

    def _curve(self, j: int) -> LayerAtReference | None:
        if not self.layers:
            return None
        if j not in self._curves:
            pairs = []
            for lay, ix in zip(self.layers, self.index):
                if ix[j] < 0:
                    raise InputError(lay.name, f"has no element at strip y = {self.y[j]:.6g} mm (contact there)")
                pairs.append((lay, int(ix[j])))
            self._curves[j] = LayerAtReference(pairs)
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

    def _local_penetrations(self, delta: float, cand: list[int], w: np.ndarray
                            ) -> list[tuple[np.ndarray, np.ndarray, int]]:
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
