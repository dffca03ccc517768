"""The block under the rolling track (units mm): a tensor grid refined only along the loaded strip.

Coordinates: 3D (x, y, z) with x the rolling direction, y across the track (half model y >= 0, symmetric about the
track centreline y = 0) and z up (surface z = 0); 2D plane strain (x, z), the engine's (y, z) section with its
first axis taken as the rolling direction. Spacing h = a / elements_per_semi_axis (across: b / it, in depth:
min(a, b) / it) on the track (x_start - a .. x_end + a), within ``fine_width_factor`` b of the centreline and
``fine_depth_factor`` a below the surface, then growing by ``growth`` up to ``size_factor`` a beyond them.

Boundaries: "surface" (z = 0), "fixed" (bottom: all components), "ends" (x = both ends: u_x = 0), 3D also
"sym_y" (y = 0: u_y = 0, the symmetry plane) and "side" (y = far side, free).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import skfem

from calibration.fem.verification_meshes import graded_axis
from calibration.rolling.config import ContactSettings, TrackMeshSettings, TrackSettings


@dataclass(frozen=True)
class TrackMesh:
    """The mesh and its Dirichlet map {boundary: components} (the engine's ``SolverOptions.dirichlet``)."""

    mesh: skfem.Mesh
    dirichlet: dict
    track_half_mm: float

    @property
    def dim(self) -> int:
        return self.mesh.dim()


def symmetric_axis(h: float, fine: float, length: float, growth: float) -> np.ndarray:
    """Coordinates from -length to +length (mm): spacing h on [-fine, fine], growing outside."""
    half = graded_axis(h, fine, length, growth)
    return np.concatenate([-half[::-1], half[1:]])


def track_axes(contact: ContactSettings, track: TrackSettings, mesh: TrackMeshSettings) -> list[np.ndarray]:
    """The grid lines (mm) of the block: [x, z] (2D) or [x, y, z] (3D), z <= 0."""
    a, b = contact.a_mm, contact.lateral_mm
    n = mesh.elements_per_semi_axis
    half_track = track.length_factor * a
    ax_x = symmetric_axis(a / n, half_track + a, half_track + mesh.size_factor * a, mesh.growth)
    h_z = min(a, b) / n if contact.model == "3d" else a / n
    ax_z = -graded_axis(h_z, mesh.fine_depth_factor * a, mesh.size_factor * a, mesh.growth)[::-1]
    if contact.model == "2d":
        return [ax_x, ax_z]
    return [ax_x, graded_axis(b / n, mesh.fine_width_factor * b, max(mesh.size_factor * a, 3.0 * b), mesh.growth),
            ax_z]


def track_mesh(contact: ContactSettings, track: TrackSettings, mesh: TrackMeshSettings) -> TrackMesh:
    """The refined block of a contact and track (see the module docstring)."""
    axes = track_axes(contact, track, mesh)
    ax_x, ax_z = axes[0], axes[-1]
    half_track = track.length_factor * contact.a_mm
    tol = 1e-9 * float(-ax_z[0])
    x_end = ax_x[-1]
    if contact.model == "2d":
        m = skfem.MeshTri1.init_tensor(ax_x, ax_z)
        m = skfem.MeshTri2.from_mesh(m) if mesh.order == 2 else m
        m = m.with_boundaries({"surface": lambda x: x[1] > -tol, "fixed": lambda x: x[1] < ax_z[0] + tol,
                               "ends": lambda x: np.abs(x[0]) > x_end - tol})
        return TrackMesh(m, {"fixed": [0, 1], "ends": [0]}, half_track)
    ax_y = axes[1]
    m = skfem.MeshTet1.init_tensor(ax_x, ax_y, ax_z)
    m = skfem.MeshTet2.from_mesh(m) if mesh.order == 2 else m
    y_far = ax_y[-1]
    m = m.with_boundaries({"surface": lambda x: x[2] > -tol, "fixed": lambda x: x[2] < ax_z[0] + tol,
                           "ends": lambda x: np.abs(x[0]) > x_end - tol, "sym_y": lambda x: x[1] < tol,
                           "side": lambda x: x[1] > y_far - tol})
    return TrackMesh(m, {"fixed": [0, 1, 2], "sym_y": [1], "ends": [0]}, half_track)


__all__ = ["TrackMesh", "symmetric_axis", "track_axes", "track_mesh"]
