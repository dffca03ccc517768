"""3D local meshes: the profile section extruded along the rolling direction x, refined at the load point (mm).

Half model: x = 0 is the symmetry plane through the load centre, x = length_mm the far end. Coordinates
(x, y, z) with (y, z) the profile frame. Boundaries: "surface", "side", "fixed" (the far-field cut of the
section, extruded), "symmetry" (x = 0) and "end" (x = length_mm). Element size: h_min inside ``refine_box``
(half-sizes (bx, by, bz) in mm around (0, y0, z(y0))), growing by ``grading`` mm per mm up to h_max.
"""

from __future__ import annotations

import dataclasses
import math

import skfem

from wrlayer.errors import require
from meshes.meshing.gmsh_outline import add_section
from meshes.meshing.gmsh_session import generate, gmsh_session
from meshes.meshing.gmsh_to_skfem import gmsh_to_skfem
from meshes.meshing.mesh_size import GMSH_AXES_3D, GradedSize
from meshes.meshing.section_mesh import (
    DEFAULT_GRADING,
    check_mesh_inputs,
    check_quality,
    default_depth_mm,
)

#: Default half-model length (mm) along the rolling direction.
DEFAULT_LENGTH_MM = 30.0


def local_mesh(profile, y0: float, h_min: float, h_max: float, length_mm: float = DEFAULT_LENGTH_MM,
               depth_mm: float | None = None, order: int = 1,
               refine_box: tuple[float, float, float] = (0.0, 0.0, 0.0),
               grading: float = DEFAULT_GRADING, optimize_netgen: bool = True,
               inner_zone: GradedSize | None = None, x_stretch: float = 1.0) -> skfem.Mesh:
    """Tetrahedral mesh (mm) of the section extruded over 0 <= x <= length_mm, refined at (0, y0, z(y0)).

    depth_mm: section depth as in :func:`meshes.meshing.section_mesh.section_mesh` (default by body).
    refine_box: half-sizes (bx, by, bz) in mm of the box around the load point meshed with h_min (e.g. the
    contact semi-axes and the depth of interest). optimize_netgen: also run Gmsh's Netgen optimiser (about 3x
    the meshing time; raises the worst mean-ratio quality, e.g. 60E1 at h_min 0.5 mm from 0.22 to 0.30).
    inner_zone: an optional finer size field inside the refinement box (e.g. at the first-yield point, mm); the
    smaller of the two sizes applies. x_stretch s in [1, 20]: the body is meshed over 0 <= x <= length_mm / s (the
    refinement box and the inner zone divided by s along x) and the mesh stretched back by s along x: the same body,
    elements s times longer along x than across (an affine anisotropic mesh for loads elongated along x). Returns
    ``MeshTet1`` (order 1) or ``MeshTet2`` (order 2).
    """
    depth_mm = default_depth_mm(profile) if depth_mm is None else depth_mm
    z0 = check_mesh_inputs(profile, y0, h_min, h_max, depth_mm, order, grading)
    length = float(length_mm)
    require(math.isfinite(length) and length >= 2 * float(h_min), "length_mm",
            f"must be at least 2 h_min = {2 * float(h_min):.3g} mm, got {length_mm!r}")
    box = tuple(float(b) for b in refine_box)
    require(len(box) == 3 and all(math.isfinite(b) and b >= 0 for b in box), "refine_box",
            f"must be three half-sizes >= 0 mm (bx, by, bz), got {refine_box!r}")
    sx = float(x_stretch)
    require(math.isfinite(sx) and 1.0 <= sx <= 20.0, "x_stretch", f"must lie in [1, 20], got {x_stretch!r}")
    # meshed in x / sx and stretched back: sizes along x become sx times those across (an affine anisotropic mesh)
    size = GradedSize(float(h_min), float(h_max), float(grading), (0.0, float(y0), z0),
                      half_box=(box[0] / sx, box[1], box[2]))
    if inner_zone is not None and sx != 1.0:
        inner_zone = dataclasses.replace(inner_zone, centre=(inner_zone.centre[0] / sx, *inner_zone.centre[1:]),
                                         half_box=(inner_zone.half_box[0] / sx, *inner_zone.half_box[1:]))
    outline = profile.section_outline(float(depth_mm))
    with gmsh_session("local") as gmsh:
        section = add_section(outline)
        extruded = gmsh.model.geo.extrude([(2, section.surface)], 0.0, 0.0, length / sx)
        gmsh.model.geo.synchronize()
        # extrude returns: the far end surface, the volume, then one lateral surface per outline curve
        end, lateral = extruded[0][1], [tag for _, tag in extruded[2:]]
        size.apply(GMSH_AXES_3D, [(r, "SurfacesList", [s]) for r, s in zip(section.curve_radii, lateral)]
                   + [(r, "CurvesList", [c]) for r, c in zip(section.curve_radii, section.curves)],
                   extra=() if inner_zone is None else (inner_zone,))
        gmsh.option.setNumber("Mesh.Algorithm", 6)
        gmsh.option.setNumber("Mesh.Algorithm3D", 1)  # Delaunay
        gmsh.option.setNumber("Mesh.Optimize", 1)
        gmsh.option.setNumber("Mesh.OptimizeNetgen", int(bool(optimize_netgen)))
        generate(3, order)
        groups = {n: [s for s, c in zip(lateral, section.curve_names) if c == n]
                  for n in ("surface", "side", "fixed")}
        groups.update(symmetry=[section.surface], end=[end])
        mesh = gmsh_to_skfem(3, groups, axes=[2, 0, 1])
    if sx != 1.0:
        mesh = mesh.scaled([sx, 1.0, 1.0])
    return check_quality(mesh)
