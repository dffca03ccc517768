"""Repeated passes at the same normal force: residual dents, shakedown and strain hardening (paper section 5).

Each pass: solve the normal problem (Kik–Piotrowski with the layer,
:func:`contact.normal.kik_piotrowski.solve_normal`, or the exact solver, ``method``), load every strip's element(s)
of each body to the strip's peak pressure p(0, y) (the largest along the strip), unload them (exact element
behaviour), and add each body's residual displacement increment u_p(y) of this pass to the separation of the next
pass (a dent on either body increases f). Stop when a pass adds no residual displacement
beyond ``tolerance_mm`` (computational shakedown) or after ``max_passes``. Without hardening the peak pressure at
shakedown sits at the elastic limit p_2 of the reference element (within the tolerance). With hardening, "no added
residual" can also be alternating plasticity: when p/2 lies beyond the characteristic's last break point the
Masing residual stops growing with p, so the dent is stable while the sliders still slip back and forth every
pass (energy is dissipated; ``dissipated_energy_N_per_mm`` of the record shows it) and the peak may stay above
p_2. The stress tests count such cases (benchmarks/stress_contact.py).

Memory rules (``memory``): "relaxed" relaxes the sliders before each pass (the paper's example: the residual
deformation is moved into the profile, the element starts virgin, the same pressure adds the same residual again);
"state_kept" keeps the spring/slider state, so an element does not move inelastically until the load exceeds what
its stuck sliders hold; "rolling" (the default) relaxes the sliders as "relaxed" does but adds the residual the
rolling FEM leaves, from the layer's rolling law (:mod:`contact.passes.rolling_memory`): the first pass a fraction
of the static residual, later passes geometrically decaying (shakedown) or constant (ratcheting) increments. A
layer without a rolling law (the paper's characteristic, tables before the law) falls back to "relaxed" under
"rolling". ``hardening=True`` is "state_kept" whatever ``memory`` says (the older key). Units: mm, N, MPa.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from contact.normal.layer_at_strip import layer_points
from contact.normal.method import NormalMethod, solve_normal_with
from contact.normal.problem import NormalProblem
from contact.normal.solution import NormalSolution
from contact.layer.prandtl_layer import LayerPair
from contact.passes.record import PassRecord
from contact.passes.rolling_memory import MEMORY_RULES, RollingMemory, patch_shape
from wrlayer.errors import require

__all__ = ["PassesOptions", "PassRecord", "run_passes"]


@dataclass(frozen=True)
class PassesOptions:
    """How the passes run (scene keys ``passes.max``, ``passes.tolerance_mm``, ``passes.hardening``).

    Attributes
    ----------
    max_passes : int
        Largest number of passes (>= 1).
    tolerance_mm : float
        Shakedown when a pass adds at most this residual displacement anywhere (mm).
    hardening : bool
        Keep the sliders' state between passes (strain hardening): the memory rule "state_kept" whatever
        ``memory`` says.
    memory : str
        The memory rule: "rolling" (the layer's rolling law; "relaxed" for a layer without one), "relaxed" (the
        paper's model) or "state_kept".
    traction_coefficient : float
        Traction coefficient c = q / p of the rolling law (-, in [-1, 1]; its magnitude is used).
    """

    max_passes: int = 50
    tolerance_mm: float = 1e-6
    hardening: bool = False
    memory: str = "rolling"
    traction_coefficient: float = 0.0

    @property
    def rule(self) -> str:
        """The memory rule in effect ("state_kept" with ``hardening``)."""
        return "state_kept" if self.hardening else self.memory

    def __post_init__(self):
        require(self.memory in MEMORY_RULES, "memory", f"must be one of {', '.join(MEMORY_RULES)}, got "
                                                       f"{self.memory!r}")
        require(bool(np.isfinite(self.traction_coefficient) and abs(self.traction_coefficient) <= 1.0),
                "traction_coefficient", f"must be in [-1, 1], got {self.traction_coefficient!r}")
        require(int(self.max_passes) >= 1, "max_passes", f"must be >= 1, got {self.max_passes!r}")
        require(bool(np.isfinite(self.tolerance_mm) and self.tolerance_mm >= 0), "tolerance_mm",
                f"must be >= 0, got {self.tolerance_mm!r}")


def _next_delta_guess(deltas: list[float]) -> float | None:
    """Start value of the next pass's approach (mm): linear extrapolation of the last two passes' deltas (the
    sequence changes smoothly towards shakedown); only a start value, the solve brackets from any guess > 0."""
    if len(deltas) < 2:
        return deltas[-1] if deltas else None
    return 2.0 * deltas[-1] - deltas[-2]


def _load_and_unload(sol: NormalSolution, bodies: dict, points: dict, rolling: dict, cumulative: dict,
                     strip_width_mm: float) -> tuple[np.ndarray, float, float, dict[str, float]]:
    """One pass of every body's elements: each loaded to its strip's peak pressure p(0, y) and unloaded; the
    residual increment (with a rolling law: the law's increment, on each strip's contact region shape) added to
    ``cumulative`` (mm, per body, updated); ``strip_width_mm``: the strip grid's spacing (mm).
    Returns the increment on the strip grid summed over the bodies (mm), the elements' displacement u0 and
    residual increment up0 at the reference strip (mm) and each body's largest dissipated energy (N/mm)."""
    ref = max(sol.regions, key=lambda r: r.p0_MPa).reference
    added = np.zeros_like(sol.p_peak_MPa, dtype=float)
    aspect, b_mm = patch_shape(sol, strip_width_mm) if rolling else (None, None)
    u0 = up0 = 0.0
    energy = {}
    for name, body_layer in bodies.items():
        ix = points[name]
        on = ix >= 0
        p_points = np.zeros(body_layer.n_points)
        p_points[ix[on]] = sol.p_peak_MPa[on]
        before = body_layer.u_mm.copy()
        loaded = body_layer.load_to(p_points)
        residual = body_layer.unload() - before
        if name in rolling:  # the relaxed element's static residual -> the rolling law's increment
            a_points, b_points = np.ones(body_layer.n_points), np.zeros(body_layer.n_points)
            a_points[ix[on]], b_points[ix[on]] = aspect[on], b_mm[on]
            residual = rolling[name].advance(p_points, residual, a_points, b_points)
        inc = np.zeros_like(added)
        inc[on] = residual[ix[on]]
        cumulative[name] = cumulative[name] + inc
        added += inc
        if ix[ref] >= 0:
            u0 += loaded[ix[ref]] - before[ix[ref]]
            up0 += inc[ref]
        energy[name] = float(body_layer.dissipated_energy_N_per_mm.max(initial=0.0))
    return added, u0, up0, energy


def run_passes(prob: NormalProblem, layer: LayerPair | None, options: PassesOptions = PassesOptions(),
               on_pass: Callable[[PassRecord, NormalSolution], None] | None = None,
               method: NormalMethod | str = NormalMethod(),
               first: NormalSolution | None = None) -> tuple[list[PassRecord], np.ndarray]:
    """Passes at the same normal force until shakedown or ``options.max_passes`` (paper section 5).

    Parameters
    ----------
    prob : NormalProblem
        The first pass's problem (separation mm, force N, radius mm, ``E_MPa``, ``poisson``).
    layer : LayerPair or None
        The layers on the problem's strip grid; not modified (copied). None: one elastic pass.
    options : PassesOptions
        Largest number of passes, shakedown tolerance (mm), hardening.
    on_pass : callable, optional
        ``on_pass(record, solution)`` after each pass (e.g. for the tangential solve).
    method : NormalMethod or str
        The normal solver (``method.normal``; the exact solver's p_peak is the largest pressure on each line y).
    first : NormalSolution, optional
        The first pass's solution when the caller has it (``prob`` with ``layer`` unloaded, e.g. the wheel–rail
        balance's): pass 1 is then that solution. The half-space solvers' answer depends on where their grid
        search starts (within their tolerance), so a re-solve would differ a little from the caller's.

    Returns
    -------
    records : list of PassRecord
        One per pass.
    final_f : numpy.ndarray
        The separation on the strip grid ``prob.strip_y_mm`` (mm) after the last pass's dents, i.e. the one the
        next pass would see (not shifted to a zero minimum).
    """
    layers = None if layer is None else layer.copy()
    y, h = prob.strip_y_mm, prob.grid_mm
    base_offset = np.zeros_like(y) if prob.f_offset_mm is None else np.asarray(prob.f_offset_mm, dtype=float)
    offset = base_offset.copy()
    bodies = {} if layers is None else layers.bodies()
    cumulative = {name: np.zeros_like(y) for name in bodies}
    points = {name: layer_points(lay, y, h) for name, lay in bodies.items()}
    rolling = {name: RollingMemory(lay, options.traction_coefficient) for name, lay in bodies.items()
               if options.rule == "rolling" and lay.rolling_law is not None}
    records: list[PassRecord] = []
    deltas: list[float] = []
    slope = None
    for k in range(1, int(options.max_passes) + 1):
        current = prob if k == 1 else prob.with_offset(offset)
        # KP's force-approach slope starts the next pass (KP and the exact solver, whose grid KP places); the
        # coarse-grid solver has none
        sol = first if k == 1 and first is not None else solve_normal_with(
            current, layers, method=method, delta_guess_mm=_next_delta_guess(deltas),
            **({} if slope is None else {"loglog_slope_guess": slope}))
        deltas.append(sol.delta_mm)
        slope = sol.iterations.get("loglog_slope")
        added, u0, up0, energy = _load_and_unload(sol, bodies, points, rolling, cumulative, h)
        max_added = float(np.max(np.abs(added))) if added.size else 0.0
        shakedown = max_added <= options.tolerance_mm
        rec = PassRecord.of(
            sol, k, u0_elements_mm=float(u0), up0_mm=float(up0), max_residual_mm=max_added, shakedown=shakedown,
            max_cumulative_residual_mm={n: float(np.max(c, initial=0.0)) for n, c in cumulative.items()},
            dissipated_energy_N_per_mm=energy,
            cumulative_residual_mm={n: c.copy() for n, c in cumulative.items()})
        records.append(rec)
        offset = offset + added
        if on_pass is not None:
            on_pass(rec, sol)
        if layers is not None and options.rule != "state_kept":
            layers = layers.relaxed()
            bodies = layers.bodies()
        if shakedown:
            break
    final = prob if len(records) == 0 else prob.with_offset(offset)
    return records, final.separation_unshifted_on_grid_mm
