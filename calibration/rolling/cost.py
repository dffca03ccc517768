"""Cost estimate of a rolling run, checked before any FEM runs (:mod:`wrlayer.cost`). Units: s.

Model: levels x passes x steps per pass x degrees of freedom x seconds per step and dof, plus the static
indentations (about the cost of one pass each). The seconds per step and dof are measured on the project's 2-core
machine under load with one BLAS thread (benchmarks/bench_rolling.py): 2D quadratic triangles and 3D quadratic
tetrahedra, EPP steel at 1.3-2.1 p_y (most steps plastic).
"""

from __future__ import annotations

from calibration.rolling.config import RollingConfig
from calibration.rolling.passes import pass_targets
from wrlayer.cost import CostEstimate

#: Measured wall seconds per rolling step and degree of freedom (2D, 3D).
STEP_S_PER_DOF = {"2d": 2.0e-5, "3d": 4.0e-5}


def dof_count(mesh) -> int:
    """Degrees of freedom of the displacement field on a scikit-fem simplex mesh (vertices and, P2, edges)."""
    n = mesh.p.shape[1]  # MeshTri2/MeshTet2 carry the edge midpoints as points too
    return int(mesh.dim() * n)


def rolling_cost(config: RollingConfig, mesh) -> CostEstimate:
    """The estimate of ``config`` on ``mesh`` (built, not yet discretised)."""
    steps = len(pass_targets(config.track.positions_over_a(), config.track.ramp_steps))
    levels = len(config.contact.levels)
    dofs = dof_count(mesh)
    rate = STEP_S_PER_DOF[config.contact.model]
    seconds = levels * (config.track.n_passes + 1) * steps * dofs * rate
    return CostEstimate(config.source, {"levels": levels, "passes (+1 static)": config.track.n_passes + 1,
                                        "steps": steps, "dofs": dofs}, seconds)


__all__ = ["STEP_S_PER_DOF", "dof_count", "rolling_cost"]
