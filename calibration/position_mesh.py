"""The FEM mesh of one calibration position (units mm): the 2D section or one of the 3D local mesh styles of
:class:`calibration.settings.MeshSettings`, sized from the position's Hertz semi-axes, and the rail's support
boundary. docs/calibration.md, "Mesh styles".
"""

from __future__ import annotations

import numpy as np

from calibration.hertz.geometry import LocalGeometry
from calibration.settings import MESH_STYLES, MeshSettings
from wrlayer.errors import require

#: MeshSettings.yield_zone_refinement: centre of the finer zone, this many b below the load centre along the inward
#: normal (the von Mises maximum of the Hertz pressure lies 0.47-0.55 b deep for a/b = 1-2), and its half-sizes
#: (x, y, z) as multiples of (a, b, b): it covers 0.15-0.95 b in depth (docs/calibration.md, "Validated accuracy").
YIELD_ZONE_DEPTH_FACTOR = 0.55
YIELD_ZONE = (0.45, 0.45, 0.4)
#: style "auto": the extruded mesh for patches with a/b at least this, the isotropic one below (docs/calibration.md,
#: "Mesh styles": with the finer zone around the first-yield point the
#: isotropic mesh is within 0.9 % of finer meshes at a/b = 3.2-3.7, where the extruded one is 0.6-3.0 % off, at
#: 1.3-1.8x its time; at a/b >= 5.8 the isotropic mesh costs 2-3x more than the extruded one).
AUTO_EXTRUDED_ASPECT = 4.0
#: style "stretched": patches with a/b above this are meshed as the isotropic mesh of a patch of this aspect (x
#: divided by a/b / STRETCH_ASPECT) and stretched back along x (docs/calibration.md, "Mesh styles"); the round
#: patches of the default run (a/b <= 1.35) are meshed exactly as by "isotropic".
STRETCH_ASPECT = 1.4


def build_mesh(profile, geometry: LocalGeometry, model: str, mesh: MeshSettings):
    """The 2D section mesh or 3D local mesh refined at the position (sizes from the semi-axes)."""
    from meshes.meshing.local_mesh import local_mesh
    from meshes.meshing.section_mesh import section_mesh

    h_min = min(geometry.b_mm, geometry.a_mm if model == "3d" else geometry.b_mm) / mesh.elements_per_semi_axis
    h_max = max(mesh.h_max_mm, h_min)
    if model == "2d":
        return section_mesh(profile, geometry.y_mm, h_min, h_max, depth_mm=mesh.depth_mm, order=mesh.order,
                            refine_radius_mm=1.2 * geometry.b_mm, grading=mesh.grading)
    length = max(mesh.length_factor * geometry.a_mm, 4.0 * geometry.b_mm)
    require(mesh.style in MESH_STYLES, "mesh.style", f"must be one of {MESH_STYLES}, got {mesh.style!r}")
    if mesh_style(geometry, mesh) == "structured":
        from meshes.meshing.structured_core_mesh import core_for_contact, structured_core_local_mesh

        core = core_for_contact(geometry.a_mm, geometry.b_mm, mesh.elements_per_semi_axis,
                                depth_factor=mesh.refine_depth_factor)
        return structured_core_local_mesh(profile, geometry.y_mm, core, h_max, length_mm=length,
                                          depth_mm=mesh.depth_mm, order=mesh.order, grading=mesh.grading)
    if mesh_style(geometry, mesh) == "extruded":
        from meshes.meshing.extruded_mesh import extruded_local_mesh

        h_x = geometry.a_mm / (mesh.x_elements_per_semi_axis or mesh.elements_per_semi_axis)
        return extruded_local_mesh(profile, geometry.y_mm, h_min, h_x, max(h_max, h_x), length_mm=length,
                                   core_length_mm=1.2 * geometry.a_mm, depth_mm=mesh.depth_mm,
                                   order=mesh.order, grading=mesh.grading,
                                   refine_box_yz=(1.2 * geometry.b_mm, mesh.refine_depth_factor * geometry.b_mm))
    box = (1.2 * geometry.a_mm, 1.2 * geometry.b_mm, mesh.refine_depth_factor * geometry.b_mm)
    inner = None
    if mesh.yield_zone_refinement > 1.0:
        from meshes.meshing.mesh_size import GradedSize

        z0 = float(profile.z(geometry.y_mm))
        centre = np.array([geometry.y_mm, z0]) - YIELD_ZONE_DEPTH_FACTOR * geometry.b_mm * np.asarray(
            profile.normal(geometry.y_mm), dtype=float)
        half = (YIELD_ZONE[0] * geometry.a_mm, YIELD_ZONE[1] * geometry.b_mm, YIELD_ZONE[2] * geometry.b_mm)
        inner = GradedSize(h_min / mesh.yield_zone_refinement, h_max, mesh.grading,
                           (0.0, float(centre[0]), float(centre[1])), half_box=half)
    sx = x_stretch(geometry, mesh)
    return local_mesh(profile, geometry.y_mm, h_min, h_max, length_mm=length, depth_mm=mesh.depth_mm,
                      order=mesh.order, refine_box=box, grading=mesh.grading, inner_zone=inner, x_stretch=sx)


def x_stretch(geometry: LocalGeometry, mesh: MeshSettings) -> float:
    """The factor by which style "stretched" elongates the isotropic mesh along x: (a/b) / STRETCH_ASPECT when
    that exceeds 1, else 1 (and 1 for every other style)."""
    if mesh_style(geometry, mesh) != "stretched":
        return 1.0
    return max(1.0, geometry.a_mm / geometry.b_mm / STRETCH_ASPECT)


def mesh_style(geometry: LocalGeometry, mesh: MeshSettings) -> str:
    """The 3D mesh style used at a position: mesh.style, "auto" resolved by the patch's a/b."""
    if mesh.style != "auto":
        return mesh.style
    return "extruded" if geometry.a_mm >= AUTO_EXTRUDED_ASPECT * geometry.b_mm else "isotropic"


#: Fewest elements across the contact's shorter semi-axis (h_min = min(a, b) / elements_per_semi_axis): below
#: this the Hertz pressure is carried by one or two element faces and the dent is not resolved.
MIN_ELEMENTS_PER_SEMI_AXIS = 2.0


def check_resolution(geometry: LocalGeometry, model: str, mesh: MeshSettings) -> None:
    """InputError naming ``mesh.elements_per_semi_axis`` when the mesh is too coarse for the contact."""
    short = min(geometry.a_mm, geometry.b_mm) if model == "3d" else geometry.b_mm
    require(mesh.elements_per_semi_axis >= MIN_ELEMENTS_PER_SEMI_AXIS, "mesh.elements_per_semi_axis",
            f"{mesh.elements_per_semi_axis:g} elements across the semi-axis {short:.3g} mm (h_min = "
            f"{short / mesh.elements_per_semi_axis:.3g} mm) is too coarse for the load: at least "
            f"{MIN_ELEMENTS_PER_SEMI_AXIS:g} are needed")


def add_support_boundary(mesh, below_mm: float) -> dict:
    """Add the boundary "support" (facets of "side" whose midpoint lies below z = -below_mm) to ``mesh`` and
    return the Dirichlet map {fixed: all, support: all (, symmetry: x)} for the solver."""
    dim = mesh.dim()
    side = np.asarray(mesh.boundaries["side"])
    z_mid = mesh.p[dim - 1, mesh.facets[:, side]].mean(axis=0)
    support = side[z_mid < -float(below_mm)]
    require(support.size > 0, "rail_support_below_mm", f"no side facet lies below z = -{below_mm:g} mm")
    mesh.boundaries["support"] = support
    out = {"fixed": list(range(dim)), "support": list(range(dim))}
    if "symmetry" in mesh.boundaries:
        out["symmetry"] = [0]
    return out


__all__ = ["AUTO_EXTRUDED_ASPECT", "MIN_ELEMENTS_PER_SEMI_AXIS", "STRETCH_ASPECT", "YIELD_ZONE",
           "YIELD_ZONE_DEPTH_FACTOR", "add_support_boundary", "build_mesh", "check_resolution", "mesh_style",
           "x_stretch"]
