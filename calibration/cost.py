"""Cost estimate of a calibration run, checked before any FEM runs (:mod:`wrlayer.cost`). Units: s.

Model: positions to compute × CPU seconds per position / workers. The seconds per position are measured on the
project's 2-core machine with the shipped configurations (plots on) and scaled by the load stages and the mesh
density relative to them (FEM work grows with the number of elements, ~ elements_per_semi_axis^2 in 2D and ^3 in
3D): ``default.toml`` (3D, 4 elements per semi-axis with the yield-zone refinement 2, 8 levels + 3 unloadings):
24 positions took 361 s of FEM (2026-11-24, 2 workers; 10.6-14.8 s for round patches, up to 34 s for a/b = 13.6),
i.e. 15.0 s per position (kept as the conservative figure: later runs on a quieter machine took 264 s of FEM and 44 s
of field output with the isotropic mesh up to a/b = 4, 12.9 s per position, and 226 s + 48 s with the stretched
mesh, 11.4 s per position); ``default_2d.toml`` (2D, 6 per semi-axis, 10 levels + 3
unloadings): 24 positions in about 1 min on 2 workers, about 5 s per position. An estimate, for the guard against
runs far beyond the intended size (it is not a timing promise: the elongated positions cost twice the mean).
"""

from __future__ import annotations

from wrlayer.cost import CostEstimate

#: Measured CPU seconds per position, at (elements_per_semi_axis, load stages = n_levels + unloadings).
POSITION_S = {"2d": 5.0, "3d": 15.0}
REFERENCE_SETTINGS = {"2d": (6.0, 10 + 3), "3d": (4.0, 8 + 3)}


def calibration_cost(cfg, tasks, scheduler: str | None = None) -> CostEstimate:
    """Estimate for the positions ``tasks`` still to compute (cached ones cost nothing)."""
    n = len(tasks)
    model = cfg.run.model
    epsa, stages_ref = REFERENCE_SETTINGS.get(model, REFERENCE_SETTINGS["3d"])
    density = (cfg.mesh.elements_per_semi_axis / epsa) ** (2 if model == "2d" else 3)
    stages = (cfg.load.n_levels + len(cfg.load.unload_factors)) / stages_ref
    workers = max(1, min(cfg.run.workers, n)) if not scheduler else max(1, cfg.run.workers)
    seconds = n * POSITION_S.get(model, POSITION_S["3d"]) * max(density, 0.05) * max(stages, 0.1) / workers
    return CostEstimate(cfg.source, {f"{model.upper()} FEM position(s)": n}, seconds, note=f"on {workers} worker(s)")


__all__ = ["POSITION_S", "REFERENCE_SETTINGS", "calibration_cost"]
