"""2D plane-strain cross-section meshes of a rail head or wheel rim, refined at the load point (mm).

``section_mesh`` meshes the profile's ``section_outline(depth_mm)`` with Gmsh (exact arcs and splines) into a
scikit-fem ``MeshTri1``/``MeshTri2`` in the (y, z) profile frame with boundaries "surface" (running surface),
"side" and "fixed" (far-field cut). Element size: h_min at the load point (y0, z(y0)), growing by ``grading``
mm per mm of distance up to h_max (see :mod:`meshes.meshing.mesh_size`).
"""

from __future__ import annotations

import math

import numpy as np
import skfem

from wrlayer.errors import ConvergenceError, InputError, require
from meshes.meshing.gmsh_outline import add_section
from meshes.meshing.gmsh_session import generate, gmsh_session
from meshes.meshing.gmsh_to_skfem import gmsh_to_skfem
from meshes.meshing.mesh_quality import element_quality
from meshes.meshing.mesh_size import GMSH_AXES_2D, GradedSize

#: Default growth of the element size per mm of distance from the refinement zone (dimensionless).
DEFAULT_GRADING = 0.3
#: Default section depth (mm): rail cut at z = -60 (below the 60E1/54E1 head/web junction), wheel rim cut
#: at z = +40.
DEFAULT_DEPTH_MM = {"rail": 60.0, "wheel": 40.0}
#: The load point must lie at least this many h_min away from the far-field cut.
MIN_DEPTH_IN_H_MIN = 4.0
#: Smallest element size accepted (mm): 1 µm, far below any wheel/rail contact semi-axis; smaller values would ask
#: Gmsh for billions of elements and are refused up front instead of running out of memory.
MIN_H_MM = 1e-3
#: Largest ratio h_max / h_min accepted (a size range beyond it is a typing error, not a graded mesh).
MAX_SIZE_RATIO = 1e5
#: Below this mean-ratio quality (0..1) a mesh is rejected as broken.
MIN_ACCEPTED_QUALITY = 0.02


def _positive(value, what: str) -> float:
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise InputError(what, f"must be a number, got {value!r}") from None
    require(math.isfinite(value) and value > 0, what, f"must be a positive number of mm, got {value!r}")
    return value


def default_depth_mm(profile) -> float:
    """The default section depth (mm) for the profile's body ("rail" or "wheel")."""
    return DEFAULT_DEPTH_MM[profile.body]


def check_mesh_inputs(profile, y0: float, h_min: float, h_max: float, depth_mm: float, order: int,
                      grading: float) -> float:
    """Validate the common mesh arguments (InputError naming the argument); returns z0 = z(y0) in mm."""
    h_min, h_max = _positive(h_min, "h_min"), _positive(h_max, "h_max")
    require(h_min <= h_max, "h_min", f"must not exceed h_max ({h_min!r} > {h_max!r} mm)")
    require(h_min >= MIN_H_MM, "h_min", f"must be at least {MIN_H_MM:g} mm (1 µm), got {h_min!r} mm")
    require(h_max <= MAX_SIZE_RATIO * h_min, "h_max",
            f"must not exceed {MAX_SIZE_RATIO:g} h_min ({h_max!r} mm against h_min = {h_min!r} mm)")
    require(order in (1, 2) and not isinstance(order, bool), "order", f"must be 1 or 2, got {order!r}")
    _positive(grading, "grading")
    depth_mm = _positive(depth_mm, "depth_mm")
    try:
        y0 = float(y0)
    except (TypeError, ValueError):
        raise InputError("y0", f"must be a number of mm, got {y0!r}") from None
    profile.check_y(y0, "y0")
    z0 = float(profile.z(y0))
    room = depth_mm + z0 if profile.body == "rail" else depth_mm - z0
    require(room >= MIN_DEPTH_IN_H_MIN * h_min, "depth_mm",
            f"{depth_mm!r} mm leaves only {room:.3g} mm of material at the load point y0 = {y0!r} mm "
            f"(need at least {MIN_DEPTH_IN_H_MIN:g} h_min = {MIN_DEPTH_IN_H_MIN * h_min:.3g} mm)")
    return z0


def check_quality(mesh: skfem.Mesh) -> skfem.Mesh:
    """Return ``mesh`` unless an element is (nearly) degenerate, which is reported as ConvergenceError."""
    worst = float(np.min(element_quality(mesh)))
    if worst < MIN_ACCEPTED_QUALITY:
        raise ConvergenceError(f"Gmsh produced a degenerate element (mean-ratio quality {worst:.3g} < "
                               f"{MIN_ACCEPTED_QUALITY}); change h_min/h_max/grading")
    return mesh


def section_mesh(profile, y0: float, h_min: float, h_max: float, depth_mm: float | None = None,
                 order: int = 1, refine_radius_mm: float = 0.0,
                 grading: float = DEFAULT_GRADING) -> skfem.Mesh:
    """Triangle mesh (mm) of the profile's cross-section, refined at (y0, z(y0)).

    h_min, h_max: element sizes (mm) at the load point and far away; depth_mm: section depth (rail: cut at
    z = -depth_mm, wheel: rim cut at z = +depth_mm; default :data:`DEFAULT_DEPTH_MM`); refine_radius_mm:
    radius (mm) of the disc around the load point meshed with h_min; grading: size growth per mm of distance
    beyond it.
    Boundaries: "surface", "side", "fixed". Deterministic: the same arguments give identical arrays.
    """
    depth_mm = default_depth_mm(profile) if depth_mm is None else depth_mm
    z0 = check_mesh_inputs(profile, y0, h_min, h_max, depth_mm, order, grading)
    radius = float(refine_radius_mm)
    require(math.isfinite(radius) and radius >= 0, "refine_radius_mm", f"must be >= 0 mm, got {radius!r}")
    size = GradedSize(float(h_min), float(h_max), float(grading), (0.0, float(y0), z0), radius=radius)
    outline = profile.section_outline(float(depth_mm))
    with gmsh_session("section") as gmsh:
        section = add_section(outline)
        gmsh.model.geo.synchronize()
        size.apply(GMSH_AXES_2D, [(r, "CurvesList", [c]) for r, c in zip(section.curve_radii, section.curves)])
        gmsh.option.setNumber("Mesh.Algorithm", 6)  # Frontal-Delaunay: well-shaped triangles
        generate(2, order)
        names = ("surface", "side", "fixed")
        mesh = gmsh_to_skfem(2, {n: section.curves_named(n) for n in names}, axes=[0, 1])
    return check_quality(mesh)
