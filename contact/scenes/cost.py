"""Cost estimates of contact runs, checked before a run starts (:mod:`wrlayer.cost`). Units: s, mm.

Model (per-unit times measured in-process on the project's 2-core machine under load from other users, see
docs/inputs-and-errors.md): a Kik–Piotrowski scene costs passes × strips × (STRIP_S + cells × CELL_S) with
cells = ``method.fastsim_cells`` when there is a tangential solve (else 0) and strips = separation table width /
``method.grid_mm``; ``method.normal = "exact"`` adds strips × ``exact_cells`` × EXACT_CELL_S per pass,
``"coarse_exact"`` COARSE_SOLVE_S per pass (and per wheel and case).
A wheel–rail scene costs cases × wheels × (CASE_WHEEL_S [+ LAYER_CASE_WHEEL_S with layers] +
passes × strips × (STRIP_S + cells × CELL_S)), strips = WHEEL_RAIL_WINDOW_MM / grid_mm. ``passes`` is the
``passes.max`` asked for (a run may stop earlier at shakedown; the guard assumes it does not).
"""

from __future__ import annotations

from contact.normal.exact import DEFAULT_CELLS
from wrlayer.cost import CostEstimate

#: Normal solve (+ layer) per strip and pass (s): 7.5-17 us measured on the paper scenes; rounded up.
STRIP_S = 2e-5
#: FASTSIM per cell (s): 22 ns measured (60 -> 600 cells on the paper scene); rounded up.
CELL_S = 5e-8
#: Contact search + load balance of one wheel of one case, elastic (s): 13 ms measured (A-2.2 sweep).
CASE_WHEEL_S = 0.02
#: Extra per wheel and case with calibration tables (layer lookup, deformed profiles written) (s): 240 ms/case.
LAYER_CASE_WHEEL_S = 0.15
#: Exact (FFT half-space) normal solver per strip of the table and x cell, per pass (s): 27 ms CPU for the paper
#: scene with the layer (160 strips, 48 cells; docs/exact-solver.md) -> 3.5 us; rounded up.
EXACT_CELL_S = 5e-6
#: Coarse-grid exact normal solve per pass (s): 1-4 ms CPU measured on the 30-patch set under load
#: (benchmarks/bench_fast_normal.py); rounded up, so that a scene using it compiles its kernels.
COARSE_SOLVE_S = 0.01
#: Lateral extent of a wheel–rail contact candidate's strip grid assumed by the estimate (mm).
WHEEL_RAIL_WINDOW_MM = 40.0


def scene_cost(scene) -> CostEstimate:
    """Estimate of a parsed Kik–Piotrowski scene (:class:`contact.scenes.scene.Scene`); with ``method.normal =
    "exact"`` each pass adds strips × exact cells × EXACT_CELL_S."""
    strips = max(1.0, float(scene.separation.y_mm[-1] - scene.separation.y_mm[0]) / scene.method.grid_mm)
    tangential = scene.tangential is not None and scene.tangential.has_creepage
    cells = scene.method.fastsim_cells if tangential else 0
    passes = scene.passes.max
    factors: dict[str, float] = {"passes": passes, "strips": round(strips)}
    if cells:
        factors["cells"] = cells
    per_strip = STRIP_S + cells * CELL_S
    if getattr(scene.method, "normal", "kik_piotrowski") == "exact":
        exact_cells = scene.method.exact_cells or DEFAULT_CELLS
        factors["exact cells"] = exact_cells
        per_strip += exact_cells * EXACT_CELL_S
    seconds = passes * strips * per_strip
    if getattr(scene.method, "normal", "kik_piotrowski") == "coarse_exact":
        factors["coarse solves"] = passes
        seconds += passes * COARSE_SOLVE_S
    return CostEstimate(scene.path.name, factors, seconds)


def wheel_rail_cost(scene) -> CostEstimate:
    """Estimate of a parsed wheel–rail scene (:class:`contact.wheel_rail.scene.WheelRailScene`)."""
    method = scene.method
    cases = len(scene.sweep.cases)
    wheels = len(scene.sides)
    passes = scene.passes.max
    strips = WHEEL_RAIL_WINDOW_MM / method.grid_mm
    cells = method.fastsim_cells if scene.tangential.friction > 0 else 0
    per = CASE_WHEEL_S + (LAYER_CASE_WHEEL_S if scene.layers is not None else 0.0)
    per_strip = STRIP_S + cells * CELL_S
    factors: dict[str, float] = {"cases": cases, "wheels": wheels, "passes": passes, "strips": round(strips)}
    if cells:
        factors["cells"] = cells
    if method.normal == "exact":
        exact_cells = method.exact_cells or DEFAULT_CELLS
        factors["exact cells"] = exact_cells
        per_strip += exact_cells * EXACT_CELL_S
    if method.normal == "coarse_exact":
        per += passes * COARSE_SOLVE_S
    workers = max(1, min(scene.run.workers, cases))
    seconds = cases * wheels * (per + passes * strips * per_strip) / workers
    return CostEstimate(scene.path.name, factors, seconds, note=f"on {workers} worker(s)" if workers > 1 else "")


__all__ = ["scene_cost", "wheel_rail_cost"]
