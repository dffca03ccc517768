"""The profile section under the rolling track (units mm): the section of a calibration position extruded along x.

The position's profile section (y, z) (:meth:`meshes.profiles.base.Profile.section_outline`, cut as the
calibration cuts it) is meshed once, triangles of size h = min(a, b) / elements_per_semi_axis in the box of
half-sizes (``fine_width_factor`` b, ``fine_depth_factor`` a) around the load point (y0, z(y0)), growing by the
calibration's grading (0.3 mm per mm) up to its h_max (6 mm; :class:`calibration.settings.MeshSettings`), and
extruded in structured layers along the block's x grid lines (:func:`calibration.rolling.track_mesh.track_axes`:
a / elements_per_semi_axis on the track x_start - a .. x_end + a, growing by ``growth`` up to ``size_factor`` a
beyond; full model in x) by :func:`meshes.meshing.extruded_mesh.extruded_local_mesh`. Full model across: the
section is not symmetric about y0.

Supports: the section's far cut clamped ("fixed") and, for a rail, its sides below z = -35 mm as the calibration
does (:func:`calibration.position_mesh.add_support_boundary`); the two ends x = +-(L/2 + size a) on rollers
("ends": u_x = 0) like the block. The static load of the section (:class:`SectionStaticLoad`) is the moving load
held at x = 0, frictionless.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import skfem

from calibration.fem.assembly import Discretisation
from calibration.hertz.load import PreparedLoad, probe_operator
from calibration.position_mesh import add_support_boundary
from calibration.rolling.config import RollingConfig
from calibration.rolling.moving_load import SurfaceForces
from calibration.rolling.track_mesh import TrackMesh, track_axes
from calibration.settings import MeshSettings
from meshes.meshing.extruded_mesh import MAX_LAYERS, extruded_local_mesh
from wrlayer.errors import InputError

#: The calibration's section meshing (size growth, far size, depth, rail support).
SECTION_MESH = MeshSettings()


def section_sizes(config: RollingConfig) -> tuple[float, float, tuple[float, float]]:
    """The section's element size h at the load point, its far size h_max (mm) and the refined box's half-sizes
    (across, in depth; mm)."""
    c, m = config.contact, config.mesh
    h = min(c.a_mm, c.lateral_mm) / m.elements_per_semi_axis
    return h, max(SECTION_MESH.h_max_mm, h), (m.fine_width_factor * c.lateral_mm, m.fine_depth_factor * c.a_mm)


def section_extrusion(config: RollingConfig, x_layers) -> skfem.Mesh:
    """The position's section meshed as in the module docstring and extruded in layers at ``x_layers`` (mm)."""
    c = config.contact
    h, h_max, box = section_sizes(config)
    h_x = c.a_mm / config.mesh.elements_per_semi_axis
    return extruded_local_mesh(c.section_profile(), c.y_mm, h, h_x, max(h_max, h_x), 0.0, 0.0,
                               depth_mm=SECTION_MESH.depth_mm, order=config.mesh.order, refine_box_yz=box,
                               grading=SECTION_MESH.grading, x_layers=x_layers)


def section_track_mesh(config: RollingConfig) -> TrackMesh:
    """The section track mesh of ``config`` (``contact.body = "section"``; see the module docstring)."""
    c = config.contact
    profile = c.section_profile()
    mesh = section_extrusion(config, track_axes(c, config.track, config.mesh)[0])
    dirichlet = {"fixed": [0, 1, 2]}
    if profile.body == "rail" and SECTION_MESH.rail_support_below_mm is not None:
        dirichlet = add_support_boundary(mesh, SECTION_MESH.rail_support_below_mm)
    mesh.boundaries["ends"] = np.concatenate([mesh.boundaries["start"], mesh.boundaries["end"]])
    dirichlet["ends"] = [0]
    return TrackMesh(mesh, dirichlet, config.track.length_factor * c.a_mm)


def section_dof_count(config: RollingConfig) -> int:
    """Degrees of freedom of the section track mesh of ``config`` without building it: the section meshed once
    and extruded by one layer (a structured extrusion of order k has the section's nodes on k layers + 1 planes
    of nodes per layer)."""
    c, k = config.contact, config.mesh.order
    ax_x = track_axes(c, config.track, config.mesh)[0]
    if len(ax_x) - 1 > MAX_LAYERS:
        raise InputError(f"{config.source}: mesh.elements_per_semi_axis",
                         f"gives {len(ax_x) - 1} element layers along the section's track (at most {MAX_LAYERS}: "
                         f"fewer elements per semi-axis or a shorter track.length_factor)")
    one = section_extrusion(config, [0.0, c.a_mm / config.mesh.elements_per_semi_axis])
    section_nodes = one.p.shape[1] // (k + 1)
    return 3 * section_nodes * (k * (len(ax_x) - 1) + 1)


def point_probes(disc: Discretisation, profile, x_mm: np.ndarray, y_mm: np.ndarray) -> list[sp.csr_matrix]:
    """Sparse (3, n_dofs) per surface point (x, y, z(y)): its displacement, evaluated at the point's projection
    onto the nearest facet of the boundary "surface" (a chordal facet, O(h^2) from the curved surface;
    :func:`calibration.hertz.load.probe_operator`)."""
    mesh = disc.mesh
    facets = np.asarray(mesh.boundaries["surface"])
    v = mesh.p[:, mesh.facets[:3, facets]]                       # (3, 3 vertices, n_facets)
    mid = v.mean(axis=1)
    out = []
    for x, y in zip(np.ravel(x_mm), np.ravel(y_mm)):
        pt = np.array([x, y, float(profile.z(y))])
        best = None
        for k in np.argsort(np.linalg.norm(mid.T - pt, axis=1))[:12]:
            e1, e2 = v[:, 1, k] - v[:, 0, k], v[:, 2, k] - v[:, 0, k]
            lam = np.linalg.lstsq(np.column_stack([e1, e2]), pt - v[:, 0, k], rcond=None)[0]
            outside = max(0.0, -lam[0], -lam[1], lam.sum() - 1.0)
            if best is None or outside < best[0]:
                best = (outside, k, lam)
        _, k, lam = best
        lam = np.clip(lam, 0.0, 1.0) / max(1.0, float(np.clip(lam, 0.0, 1.0).sum()))
        on = v[:, 0, k] + lam[0] * (v[:, 1, k] - v[:, 0, k]) + lam[1] * (v[:, 2, k] - v[:, 0, k])
        out.append(probe_operator(disc.basis, on, int(mesh.f2t[0, facets[k]])).tocsr())
    return out


def normal_probe(disc: Discretisation, profile, x_mm: np.ndarray, y_mm: np.ndarray) -> sp.csr_matrix:
    """Sparse (n, n_dofs): the displacement INTO the body along the inward normal at the surface points (x, y)."""
    y = np.asarray(y_mm, dtype=float).ravel()
    nrm = np.asarray(profile.normal(y), dtype=float).reshape(-1, 2)
    rows = [-(n[0] * P[1] + n[1] * P[2]) for n, P in zip(nrm, point_probes(disc, profile, x_mm, y))]
    return sp.vstack(rows).tocsr()


@dataclass(frozen=True)
class SectionStaticLoad:
    """The moving load held at x = 0 without traction, as an engine load (``prepare(basis)``): the static
    indentation of the section with the rolling load's own pressure and normals."""

    forces: SurfaceForces
    centre_probe: sp.csr_matrix     # (3, n_dofs): the displacement at the load centre
    centre_mm: tuple[float, float, float]
    normal_out: tuple[float, float, float]

    def prepare(self, basis: skfem.CellBasis) -> PreparedLoad:
        return PreparedLoad(self.forces.force(0.0, 1.0, traction=False), np.array(self.centre_mm),
                            np.array(self.normal_out), self.centre_probe)


def section_static_load(disc: Discretisation, forces: SurfaceForces, profile, y0_mm: float) -> SectionStaticLoad:
    """The static load of the section at (0, y0) (see :class:`SectionStaticLoad`)."""
    (P,) = point_probes(disc, profile, np.array([0.0]), np.array([y0_mm]))
    n = np.asarray(profile.normal(y0_mm), dtype=float)
    return SectionStaticLoad(forces, P, (0.0, float(y0_mm), float(profile.z(y0_mm))),
                             (0.0, float(n[0]), float(n[1])))


__all__ = ["SECTION_MESH", "SectionStaticLoad", "normal_probe", "section_dof_count", "section_extrusion", "section_sizes", "section_static_load",
           "section_track_mesh", "point_probes"]
