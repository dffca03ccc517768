"""Cost estimate of a rolling run, checked before any FEM runs (:mod:`wrlayer.cost`). Units: s.

Model: levels x passes x steps per pass x degrees of freedom x seconds per step and dof, plus the static
indentations (about the cost of one pass each). The seconds per step and dof are measured on the project's 2-core
machine under load with one BLAS thread (benchmarks/bench_rolling.py): the shipped rolling_halfspace.toml (3D
quadratic tetrahedra, EPP steel at 1.3, 1.7, 2.1 p_y, 3 passes + the static dents, 21 steps per pass, 45,951 dofs)
took 345 s at a load average of about 5 on 2 cores, 3.0e-5 s per step and dof (the 2.1 p_y passes 3-4 times
the 1.3 p_y ones); the figures below keep a margin. 2D: the same per dof, halved (fewer quadrature points per dof).
The section (``contact.body = "section"``): its dofs from the section meshed once (one layer,
:func:`calibration.rolling.section_track.section_dof_count`), the same rate per dof.
Material sub-steps (``track.substeps`` = m) cost about 1 + 0.2 (m - 1) times a plain step (more Newton iterations,
docs/rolling-verification.md).
"""

from __future__ import annotations

import numpy as np

from calibration.rolling.config import RollingConfig
from calibration.rolling.passes import pass_targets
from calibration.rolling.section_track import section_dof_count
from calibration.rolling.track_mesh import track_axes
from wrlayer.cost import CostEstimate

#: Measured wall seconds per rolling step and degree of freedom (2D, 3D).
STEP_S_PER_DOF = {"2d": 2.0e-5, "3d": 4.0e-5}

#: Extra cost of one material sub-step, as a fraction of a plain step (measured: 4 sub-steps ~ 1.4-1.6 x).
SUBSTEP_COST = 0.2


def dof_count(config: RollingConfig) -> int:
    """Degrees of freedom of the displacement field on the track mesh, from its grid lines (no mesh built):
    dim x nodes, the nodes of a quadratic simplex grid being those of the grid with every cell halved. The
    section's: :func:`~calibration.rolling.section_track.section_dof_count`."""
    if config.contact.body == "section":
        return section_dof_count(config)
    axes = track_axes(config.contact, config.track, config.mesh)
    k = config.mesh.order
    return int(len(axes) * np.prod([k * (len(ax) - 1) + 1 for ax in axes]))


def rolling_cost(config: RollingConfig) -> CostEstimate:
    """The estimate of ``config`` (before any mesh is built)."""
    steps = len(pass_targets(config.track.positions_over_a(), config.track.ramp_steps))
    levels = len(config.contact.levels)
    dofs = dof_count(config)
    rate = STEP_S_PER_DOF[config.contact.model]
    substep_factor = 1.0 + SUBSTEP_COST * (config.track.substeps - 1)
    seconds = levels * (config.track.n_passes + 1) * steps * dofs * rate * substep_factor
    return CostEstimate(config.source, {"levels": levels, "passes (+1 static)": config.track.n_passes + 1,
                                        "steps": steps, "dofs": dofs}, seconds,
                        note=f"with {config.track.substeps} material sub-steps" if config.track.substeps > 1 else "")


__all__ = ["STEP_S_PER_DOF", "SUBSTEP_COST", "dof_count", "rolling_cost"]
