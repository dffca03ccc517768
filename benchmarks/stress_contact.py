"""Randomised stress cases for the contact solver (normal Kik–Piotrowski + layer, passes, FASTSIM).

:func:`random_contact_case` draws a reproducible scene from a seed: normal force 1 kN .. 1 MN (three orders of
magnitude), rolling radius 50 mm .. 5 m, a separation that is very flat, parabolic, sharp (a kink), quartic or has
two separate minima, optionally a layer (one combined layer or wheel + rail in series) with 1..10 segments and an
initial stiffness 1e3 .. 1e7 N/mm^3 (very soft .. nearly rigid), creepages 1e-5 .. 1e-1 (up to full sliding),
1..200 passes in either hardening mode, strip grids 0.05 .. 0.5 mm.

:func:`check_contact_case` runs one case and returns ``"ok"`` when every invariant holds, ``"clear-error"`` when the
solver raised the project's error type (:class:`wrlayer.errors.WrLayerError`); a violated invariant raises
:class:`InvariantViolation`; any other exception propagates (both are failures of the stress run).

Invariants (units mm, N, MPa):
- force balance: |sum of patch forces - N| <= 2 rtol_N N (the solver's rtol_N = 1e-9) on every pass;
- peak pressures finite and >= 0, p_max > 0, approach delta, delta_0, area, width, length finite and > 0;
- every patch lies inside the separation table: it does not use the first or last strip (a patch touching the
  table end would be silently truncated);
- FASTSIM on every patch of the first and last pass: forces finite, |F_t| <= mu N_patch (1 + 1e-9);
- residual displacement added per pass >= 0 on every strip (the cumulative dent is non-decreasing), and each
  body's cumulative residual equals the exact element value computed independently from its characteristic by
  the Masing rule (:func:`masing_residual_mm`): sum over passes of r(p_peak) without hardening, r(largest peak so
  far) with hardening (kept state);
- shakedown reported: no residual beyond the pass tolerance was added, and without hardening
  p_peak(y) <= p_2 + tolerance_mm / (1/S_2 - 1/S_1) (the overshoot whose residual is still below the tolerance).
  With hardening a peak ABOVE max(p_2, earlier peaks) is possible at shakedown: when p/2 lies beyond the last break
  point the Masing residual no longer grows with p (alternating plasticity: the sliders slip back and forth every
  pass, dissipating energy, but the dent stops growing); such cases are counted (``shakedown_above_previous_peak``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from wrlayer.characteristic import Characteristic
from contact.tangential.fastsim import Creepage, solve_tangential
from contact.normal.kik_piotrowski import NormalProblem, NormalSolution
from contact.passes.passes import PassesOptions, PassRecord, run_passes
from contact.layer.prandtl_layer import LayerPair, PrandtlLayer
from wrlayer.errors import WrLayerError

__all__ = [
    "SEPARATION_KINDS",
    "ContactCase",
    "InvariantViolation",
    "check_contact_case",
    "masing_residual_mm",
    "random_contact_case",
]

SEPARATION_KINDS = ("flat", "parabola", "sharp", "quartic", "two_minima")
#: The normal solver these invariants are written for (the Kik–Piotrowski strips whose solutions are checked;
#: named, since a scene's default is the exact solver).
STRESSED_METHOD = "kik_piotrowski"
#: the solver's default relative force tolerance (solve_normal rtol_N)
FORCE_RTOL = 1e-9
#: the pass tolerance used by the stress cases (PassesOptions.tolerance_mm default)
PASS_TOLERANCE_MM = 1e-6


class InvariantViolation(AssertionError):
    """A result that the solver returned but that breaks an invariant (a solver bug or a missing clear error)."""


@dataclass
class ContactCase:
    """One randomised contact scene. Units mm, N, MPa; creepage (vx, vy, phi 1/mm); layer: characteristics by body."""

    seed: int
    kind: str
    normal_force_N: float
    rolling_radius_mm: float
    y_mm: np.ndarray
    f_mm: np.ndarray
    layers: dict[str, Characteristic]
    creepage: tuple[float, float, float]
    friction: float
    passes: int
    hardening: bool
    grid_mm: float
    E_MPa: float = 210e3
    poisson: float = 0.28
    alpha: float = 0.55
    stats: dict = field(default_factory=dict)

    def describe(self) -> str:
        lay = ", ".join(f"{b}: {c.n_segments} seg S1={c.initial_stiffness:.3g}" for b, c in self.layers.items())
        return (f"seed {self.seed}: {self.kind}, N={self.normal_force_N:.4g} N, R={self.rolling_radius_mm:.4g} mm, "
                f"h={self.grid_mm} mm, layer [{lay or 'none'}], {self.passes} passes"
                f"{' (hardening)' if self.hardening else ''}, mu={self.friction:.3g}, creepage={self.creepage}")


def random_characteristic(rng: np.random.Generator, name: str, n_segments: int | None = None) -> Characteristic:
    """1..10 segments (or ``n_segments``: the draws of the recorded seeds stay as they were), initial slope
    S_1 = 1e3..1e7 N/mm^3, each slope 0.05..0.9 of the previous, p steps 30..2000 MPa."""
    n_seg = int(rng.integers(1, 11)) if n_segments is None else int(n_segments)
    s1 = 10 ** rng.uniform(3.0, 7.0)
    slopes = s1 * np.cumprod(np.concatenate([[1.0], rng.uniform(0.05, 0.9, size=n_seg - 1)]))
    p_steps = 10 ** rng.uniform(1.5, 3.3, size=n_seg)
    p = np.concatenate([[0.0], np.cumsum(p_steps)])
    u = np.concatenate([[0.0], np.cumsum(p_steps / slopes)])
    return Characteristic(u, p, name)


def random_separation(rng: np.random.Generator, kind: str) -> tuple[np.ndarray, np.ndarray]:
    """Separation table f(y) (mm) on y in [-40, 40] mm, minimum near y = 0 (two minima: at both sides)."""
    y = np.linspace(-40.0, 40.0, 801)
    ry = 10 ** rng.uniform(0.5, 4.0)                         # lateral radius of relative curvature 3 mm .. 10 m
    if kind == "flat":
        f = y ** 2 / (2 * 10 ** rng.uniform(4.0, 5.0)) + (y / 40.0) ** 8 * rng.uniform(0.5, 5.0)
    elif kind == "parabola":
        f = y ** 2 / (2 * ry)
    elif kind == "sharp":
        f = np.abs(y) * 10 ** rng.uniform(-2.0, 0.0) + y ** 2 / (2 * ry)
    elif kind == "quartic":
        f = (y / rng.uniform(2.0, 20.0)) ** 4
    else:
        y1, y2 = -rng.uniform(3.0, 15.0), rng.uniform(3.0, 15.0)
        f = np.minimum((y - y1) ** 2 / (2 * ry), (y - y2) ** 2 / (2 * ry) + rng.uniform(0.0, 0.05))
    return y, f - f.min()


def random_contact_case(seed: int) -> ContactCase:
    """A reproducible random scene covering the ranges stated in the module docstring."""
    rng = np.random.default_rng(seed)
    kind = SEPARATION_KINDS[int(rng.integers(len(SEPARATION_KINDS)))]
    force = 10 ** rng.uniform(3.0, 6.0)
    radius = 10 ** rng.uniform(np.log10(50.0), np.log10(5000.0))
    y, f = random_separation(rng, kind)
    layers: dict[str, Characteristic] = {}
    draw = rng.random()
    if draw < 0.45:
        layers["combined"] = random_characteristic(rng, "combined layer")
    elif draw < 0.75:
        layers["wheel"] = random_characteristic(rng, "wheel layer")
        layers["rail"] = random_characteristic(rng, "rail layer")
    mu = float(rng.uniform(0.05, 0.6))
    scale = 10 ** rng.uniform(-5.0, -1.0)
    creep = (float(scale * rng.uniform(-1, 1)), float(scale * rng.uniform(-1, 1)),
             float(scale * rng.uniform(-1, 1) * 0.05))          # spin in 1/mm
    passes = int(rng.choice([1, 1, 2, 5, 20, 200]))
    hardening = bool(rng.random() < 0.5)
    grid = float(rng.choice([0.05, 0.1, 0.2, 0.5]))
    return ContactCase(seed, kind, float(force), float(radius), y, f, layers, creep, mu, passes, hardening, grid)


def layer_pair(case: ContactCase, strip_y_mm: np.ndarray) -> LayerPair | None:
    """Uniform layers at the strip centres, one per body of the case (None without a layer)."""
    if not case.layers:
        return None
    return LayerPair(**{b: PrandtlLayer.uniform(c, strip_y_mm, name=f"{b} layer") for b, c in case.layers.items()})


def _require(cond: bool, message: str) -> None:
    if not cond:
        raise InvariantViolation(message)


def _shakedown_margin_MPa(case: ContactCase) -> tuple[float, float]:
    """(p_2, overshoot) for the shakedown check: the smallest elastic limit over the bodies and the largest
    pressure overshoot whose residual stays below the pass tolerance (MPa)."""
    p2, over = np.inf, 0.0
    for c in case.layers.values():
        if c.n_segments > 1:
            s = c.slopes
            p2 = min(p2, c.elastic_limit_MPa)
            over = max(over, PASS_TOLERANCE_MM / (1.0 / s[1] - 1.0 / s[0]))
    return p2, over


def _check_normal(case: ContactCase, sol: NormalSolution, table_y: tuple[float, float]) -> None:
    n = case.normal_force_N
    total = sum(p.normal_force_N() for p in sol.patches)
    _require(abs(total - n) <= 2 * FORCE_RTOL * n, f"force balance: sum of patch forces {total!r} N vs N = {n!r} N")
    for name in ("delta_mm", "delta0_mm", "p_max_MPa", "area_mm2", "width_mm", "length_mm"):
        v = getattr(sol, name)
        _require(bool(np.isfinite(v) and v > 0), f"{name} = {v!r} (must be finite and > 0)")
    _require(bool(np.all(np.isfinite(sol.p_peak_MPa)) and np.all(sol.p_peak_MPa >= 0)), "NaN or negative pressure")
    for p in sol.patches:
        _require(bool(np.all(np.isfinite(p.p_peak_MPa)) and np.all(p.p_peak_MPa >= 0)),
                 "NaN or negative patch pressure")
        # table_y: the centres of the first and last strips; a patch may use every strip but those two (half a
        # strip of margin: comparing with a whole strip rejected patches that end on the second strip)
        _require(bool(p.y_mm[0] - 0.5 * p.grid_mm > table_y[0] and p.y_mm[-1] + 0.5 * p.grid_mm < table_y[1]),
                 f"patch [{p.y_mm[0]:.4g}, {p.y_mm[-1]:.4g}] mm reaches the end strips of the separation table "
                 f"[{table_y[0]:.4g}, {table_y[1]:.4g}] mm (truncated without an error)")


def _check_tangential(case: ContactCase, sol: NormalSolution) -> dict:
    """FASTSIM on every patch; returns {"full_sliding": bool} (all cells slip in every patch)."""
    G = case.E_MPa / (2 * (1 + case.poisson))
    full = True
    for p in sol.patches:
        res = solve_tangential(p, Creepage(*case.creepage), G_MPa=G, poisson=case.poisson, friction=case.friction)
        ft = float(np.hypot(res.Fx_N, res.Fy_N))
        bound = case.friction * p.normal_force_N()
        _require(bool(np.isfinite(ft) and np.isfinite(res.Mz_Nmm)), f"FASTSIM forces not finite: {res.Fx_N}, {res.Fy_N}")
        _require(ft <= bound * (1 + 1e-9) + 1e-12, f"|F_t| = {ft!r} N exceeds mu N = {bound!r} N")
        _require(bool(np.all(np.isfinite(res.tx_MPa)) and np.all(np.isfinite(res.ty_MPa))), "NaN traction")
        full = full and bool(res.slip.all())
    return {"full_sliding": full}


def masing_residual_mm(c: Characteristic, p_MPa: np.ndarray) -> np.ndarray:
    """Exact residual displacement (mm) of a virgin Prandtl element loaded to p (MPa) and unloaded (Masing rule for
    the parallel spring-slider model: unloading retraces twice the backbone at half the drop): u(p) - 2 u(p/2).

    Independent of :mod:`contact.layer.prandtl_layer` (uses only the characteristic); equals eq. (8) for p <= 2 p_2.
    Loading again to a lower peak and unloading leaves it unchanged; a higher peak erases the memory (Masing), so
    with kept state (hardening) the residual after several cycles is this function at the largest peak so far.
    """
    p = np.asarray(p_MPa, dtype=float)
    return c.displacement(p) - 2.0 * c.displacement(0.5 * p)


def _check_passes(case: ContactCase, records: list[PassRecord]) -> dict:
    """Residual displacements against the exact element behaviour and the shakedown rule; returns statistics."""
    _require(1 <= len(records) <= case.passes, f"{len(records)} passes recorded for max_passes = {case.passes}")
    p2, over = _shakedown_margin_MPa(case)
    zeros = np.zeros_like(records[0].strip_y_mm)
    previous = {b: zeros for b in case.layers}
    expected = {b: zeros for b in case.layers}
    peak_before = np.zeros_like(records[0].p_peak_MPa)
    alternating = False
    for k, rec in enumerate(records):
        _require(rec.index == k + 1, f"pass index {rec.index} at position {k + 1}")
        peak_now = np.maximum(peak_before, rec.p_peak_MPa)
        added_total = zeros
        for b, c in case.layers.items():
            cum = rec.cumulative_residual_mm[b]
            _require(bool(np.all(np.isfinite(cum))), f"pass {rec.index}: non-finite residual ({b})")
            added = cum - previous[b]
            scale = 1e-13 + 1e-9 * float(c.displacement(max(rec.p_max_MPa, 1.0)))
            _require(bool(np.all(added >= -scale)),
                     f"pass {rec.index}: residual displacement of {b} decreased by {-added.min():.3g} mm")
            if case.hardening:
                expected[b] = masing_residual_mm(c, peak_now)
            else:
                expected[b] = expected[b] + masing_residual_mm(c, rec.p_peak_MPa)
            err = float(np.abs(cum - expected[b]).max())
            _require(err <= scale * (k + 1), f"pass {rec.index}: residual of {b} differs from the exact element "
                     f"(Masing) value by {err:.3g} mm")
            previous[b] = cum
            added_total = added_total + added
        if rec.shakedown:
            _require(float(np.abs(added_total).max(initial=0.0)) <= PASS_TOLERANCE_MM,
                     f"pass {rec.index}: shakedown reported but residual {np.abs(added_total).max():.3g} mm added")
            if not case.hardening:
                excess = rec.p_peak_MPa - (p2 + over + 1e-9 * rec.p_max_MPa)
                _require(bool(np.all(excess <= 0)), f"pass {rec.index}: shakedown reported but p_peak exceeds the "
                         f"elastic limit p_2 = {p2:.6g} MPa by {excess.max():.4g} MPa")
            else:
                alternating = bool(np.any(rec.p_peak_MPa > np.maximum(p2, peak_before) + over
                                          + 1e-9 * rec.p_max_MPa))
            _require(rec.index == len(records), "passes continued after shakedown")
        peak_before = peak_now
    if len(records) < case.passes:
        _require(records[-1].shakedown, "stopped before max_passes without shakedown")
    return {"shakedown_above_previous_peak": alternating}


def check_contact_case(case: ContactCase) -> str:
    """Run one case: "ok" (all invariants hold) or "clear-error" (WrLayerError); InvariantViolation otherwise."""
    solutions: list[NormalSolution] = []
    try:
        prob = NormalProblem(case.y_mm, case.f_mm, case.normal_force_N, case.rolling_radius_mm, case.E_MPa,
                             case.poisson, alpha=case.alpha, grid_mm=case.grid_mm)
        table_y = (float(prob.strip_y_mm[0]), float(prob.strip_y_mm[-1]))
        layers = layer_pair(case, prob.strip_y_mm)
        records, _ = run_passes(prob, layers, PassesOptions(max_passes=case.passes, hardening=case.hardening,
                                                            tolerance_mm=PASS_TOLERANCE_MM),
                                on_pass=lambda rec, sol: solutions.append(sol), method=STRESSED_METHOD)
        for sol in solutions:
            _check_normal(case, sol, table_y)
        pass_stats = _check_passes(case, records)
        tang = [_check_tangential(case, sol) for sol in {id(s): s for s in (solutions[0], solutions[-1])}.values()]
    except WrLayerError as err:
        case.stats["error"] = f"{type(err).__name__}: {err}"
        return "clear-error"
    case.stats.update(passes_run=len(records), shakedown=bool(records[-1].shakedown),
                      patches=len(solutions[-1].patches), full_sliding=bool(tang[-1]["full_sliding"]),
                      p_max_MPa=float(solutions[-1].p_max_MPa), **pass_stats)
    return "ok"
