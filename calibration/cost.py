"""Cost estimate of a calibration run, checked before any FEM runs (:mod:`wrlayer.cost`). Units: s.

Model: positions to compute × CPU seconds per position / workers. Per-position CPU times measured on the
project's 2-core machine with the shipped configurations (README: ``default.toml``, 24 positions 2D in about
1 min with 2 workers -> about 5 s per position; ``default_3d.toml``, 16 positions 3D in 11 min 50 s with 2
workers -> about 90 s per position), scaled by the load stages and the mesh density relative to the defaults
(FEM work grows with the number of elements, ~ elements_per_semi_axis^2 in 2D and ^3 in 3D).
"""

from __future__ import annotations

from wrlayer.cost import CostEstimate

#: CPU seconds per position at the default settings (elements_per_semi_axis 8, 12 levels, 3 unloads).
POSITION_S = {"2d": 5.0, "3d": 90.0}
_DEFAULT_EPSA = 8.0
_DEFAULT_STAGES = 12 + 3


def calibration_cost(cfg, tasks, scheduler: str | None = None) -> CostEstimate:
    """Estimate for the positions ``tasks`` still to compute (cached ones cost nothing)."""
    n = len(tasks)
    model = cfg.run.model
    density = (cfg.mesh.elements_per_semi_axis / _DEFAULT_EPSA) ** (2 if model == "2d" else 3)
    stages = (cfg.load.n_levels + len(cfg.load.unload_factors)) / _DEFAULT_STAGES
    workers = max(1, min(cfg.run.workers, n)) if not scheduler else max(1, cfg.run.workers)
    seconds = n * POSITION_S.get(model, 90.0) * max(density, 0.05) * max(stages, 0.1) / workers
    return CostEstimate(cfg.source, {f"{model.upper()} FEM position(s)": n}, seconds, note=f"on {workers} worker(s)")


__all__ = ["POSITION_S", "calibration_cost"]
