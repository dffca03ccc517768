"""The residual groove after a pass: the surface displacement left by the load, relative to the far field.

Depths are positive INTO the body: d(x, y) = u_z(far field) - u_z(x, y) (mm) at the surface vertices, the far
field being the surface far from the track (2D: the mean of the block's two ends; 3D: the far lateral edge at
mid-track). ``groove_mm``: the mean of d along the centreline over the mid-track window |x| <= a/2 (the steady
part of the track, away from where the load appears and is removed). ``shift_mm``: the mean residual surface
displacement along x there (relative to the far field; the forward flow of a ratcheting surface layer).
``max_eq_plastic_strain``: the largest equivalent plastic strain at the quadrature points below the window's
x range widened to |x| <= a (-). The static dent is measured at the same points (:func:`depth_at`). Units mm.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from calibration.fem.assembly import Discretisation
from calibration.fem.solver_state import SolverState


@dataclass(frozen=True)
class GrooveProfile:
    """The groove after one pass.

    Attributes
    ----------
    x_mm : list of float
        Positions along the centreline y = 0 (section: y = y0) (mm).
    depth_along_mm : list of float
        Residual depth d along the centreline (mm, positive into the body; section: along the inward normal).
    y_mm : list of float
        Positions across the track at mid-track x = 0 (mm; section: profile coordinates; 3D only, empty in 2D).
    depth_across_mm : list of float
        Residual depth d across the track at mid-track (mm; 3D only).
    groove_mm : float
        Mean depth along the centreline over |x| <= a/2 (mm).
    shift_mm : float
        Mean residual surface displacement along x over |x| <= a/2 (mm).
    max_eq_plastic_strain : float
        Largest equivalent plastic strain below |x| <= a (-).
    """

    x_mm: list[float]
    depth_along_mm: list[float]
    y_mm: list[float]
    depth_across_mm: list[float]
    groove_mm: float
    shift_mm: float
    max_eq_plastic_strain: float

    def to_dict(self) -> dict:
        return {k: getattr(self, k) for k in self.__dataclass_fields__}


class SurfaceProbe:
    """The surface vertices of a track mesh used for the groove (see the module docstring)."""

    def __init__(self, disc: Discretisation, a_mm: float):
        mesh = disc.mesh
        self.dim, self.a = mesh.dim(), a_mm
        p = mesh.p[:, :disc.basis.nodal_dofs.shape[1]]  # vertices (their dofs come first)
        tol = 1e-9 * float(np.ptp(p[-1]))
        top = np.nonzero(p[-1] > -tol)[0]
        if self.dim == 2:
            self.along = top[np.argsort(p[0, top])]
            self.across = np.zeros(0, dtype=int)
            ends = [self.along[0], self.along[-1]]
        else:
            line = top[np.abs(p[1, top]) < tol]
            self.along = line[np.argsort(p[0, line])]
            x_mid = p[0, top][np.argmin(np.abs(p[0, top]))]
            row = top[np.abs(p[0, top] - x_mid) < tol]
            self.across = row[np.argsort(p[1, row])]
            ends = [self.across[-1]]
        self.ends = np.array(ends)
        self.p, self.disc = p, disc
        self.window = self.along[np.abs(p[0, self.along]) <= 0.5 * a_mm + tol]
        x_qp = disc.qp_coordinates()[0]
        self.below = np.abs(x_qp) <= a_mm + tol

    def far_field(self, u: np.ndarray) -> float:
        """The far field's u_z (mm)."""
        return float(np.mean(u[self.dim * self.ends + self.dim - 1]))

    def depth(self, u: np.ndarray, nodes: np.ndarray) -> np.ndarray:
        """Residual depth (mm, positive into the body) at vertex ``nodes`` relative to the far field."""
        return self.far_field(u) - u[self.dim * nodes + self.dim - 1]

    def depth_at(self, u: np.ndarray, x_mm: float) -> float:
        """Depth at the centreline vertex nearest x (mm)."""
        k = self.along[np.argmin(np.abs(self.p[0, self.along] - x_mm))]
        return float(self.depth(u, np.array([k]))[0])

    def profile(self, state: SolverState) -> GrooveProfile:
        """The :class:`GrooveProfile` of a residual state."""
        u, dim = state.u_mm, self.dim
        shift = float(np.mean(u[dim * self.window]) - np.mean(u[dim * self.ends]))
        eq = state.eq_plastic_strain[self.below]
        return GrooveProfile(self.p[0, self.along].tolist(), self.depth(u, self.along).tolist(),
                             self.p[1, self.across].tolist() if dim == 3 else [],
                             self.depth(u, self.across).tolist() if dim == 3 else [],
                             float(np.mean(self.depth(u, self.window))), shift,
                             float(eq.max()) if eq.size else 0.0)


__all__ = ["GrooveProfile", "SurfaceProbe"]
