"""3D local meshes with a structured core: the graded 2D section mesh extruded in layers along x (mm).

The anisotropic alternative to :func:`meshes.meshing.local_mesh.local_mesh` for elongated contact patches. The
section (y, z) is meshed once with triangles of size h_yz in the box of half-sizes (by, bz) around the load point
(y0, z(y0)), growing by ``grading`` mm per mm beyond it up to h_max. Over the core 0 <= x <= core_length_mm it is
extruded in equal structured layers of thickness about h_x (each prism split into three tetrahedra by Gmsh), so
that the core has (section triangles) x 3 x (layers) elements, independent of a/b when h_yz = b/n and h_x = a/n.
The rest, core_length_mm <= x <= length_mm, is meshed with unstructured tetrahedra conforming to the core's end
face, of size h_yz + grading * (distance from the core's refinement box), up to h_max.

Boundaries as in the isotropic local mesh: "surface", "side", "fixed" (the far cut, extruded), "symmetry" (x = 0)
and "end" (x = length_mm).

With ``x_layers`` (layer coordinates along x) the whole body is one structured extrusion instead, from x_layers[0]
to x_layers[-1] with a layer between each pair of coordinates (graded layers for a track along x); its end faces
are "start" (x = x_layers[0]) and "end".
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import skfem

from wrlayer.errors import require
from meshes.meshing.gmsh_outline import add_section
from meshes.meshing.gmsh_session import generate, gmsh_session
from meshes.meshing.gmsh_to_skfem import gmsh_to_skfem
from meshes.meshing.mesh_size import GMSH_AXES_3D, GradedSize
from meshes.meshing.section_mesh import DEFAULT_GRADING, check_mesh_inputs, check_quality, default_depth_mm

#: Largest number of structured layers accepted (a guard against typing errors in h_x).
MAX_LAYERS = 200
#: The boundary names of the local meshes (both styles).
BOUNDARY_NAMES = ("surface", "side", "fixed", "symmetry", "end")


def core_layers(h_x: float, core_length_mm: float) -> int:
    """Number of equal layers of thickness <= h_x (mm) over the core."""
    n = int(math.ceil(float(core_length_mm) / float(h_x) - 1e-9))
    require(n <= MAX_LAYERS, "h_x", f"gives {n} layers over the core (at most {MAX_LAYERS})")
    return max(1, n)


def extruded_local_mesh(profile, y0: float, h_yz: float, h_x: float, h_max: float, length_mm: float,
                        core_length_mm: float, depth_mm: float | None = None, order: int = 1,
                        refine_box_yz: tuple[float, float] = (0.0, 0.0),
                        grading: float = DEFAULT_GRADING, x_layers: Sequence[float] | None = None) -> skfem.Mesh:
    """Tetrahedral mesh (mm) of the section over 0 <= x <= length_mm with a structured core (module docstring).

    h_yz: triangle size (mm) of the section in the box of half-sizes ``refine_box_yz`` (by, bz) around the load
    point; h_x: largest layer thickness (mm) over 0 <= x <= core_length_mm (< length_mm). x_layers: increasing
    layer coordinates (mm) of a fully structured extrusion (module docstring; length_mm and core_length_mm are then
    not used). Returns ``MeshTet1`` (order 1) or ``MeshTet2`` (order 2).
    """
    depth_mm = default_depth_mm(profile) if depth_mm is None else depth_mm
    z0 = check_mesh_inputs(profile, y0, h_yz, h_max, depth_mm, order, grading)
    h_x = float(h_x)
    require(math.isfinite(h_x) and 1e-3 <= h_x <= float(h_max), "h_x",
            f"must lie in [0.001 mm, h_max], got {h_x!r}")
    box = tuple(float(b) for b in refine_box_yz)
    require(len(box) == 2 and all(math.isfinite(b) and b >= 0 for b in box), "refine_box_yz",
            f"must be two half-sizes >= 0 mm (by, bz), got {refine_box_yz!r}")
    if x_layers is not None:
        return check_quality(_structured_track(profile, y0, z0, float(h_yz), h_x, float(h_max), float(depth_mm),
                                               order, box, float(grading), x_layers))
    length, core = float(length_mm), float(core_length_mm)
    require(math.isfinite(core) and core > 0, "core_length_mm", f"must be > 0 mm, got {core_length_mm!r}")
    require(math.isfinite(length) and length > core + h_x, "length_mm",
            f"must exceed core_length_mm + h_x = {core + h_x:.3g} mm, got {length_mm!r}")
    n_layers = core_layers(h_x, core)
    # one field for the section (x = 0: the core's box reaches it) and the unstructured rest
    size = GradedSize(float(h_yz), float(h_max), float(grading), (0.0, float(y0), z0), half_box=(core, *box))
    outline = profile.section_outline(float(depth_mm))
    with gmsh_session("extruded") as gmsh:
        section = add_section(outline)
        # extrude returns: the far end surface, the volume, then one lateral surface per boundary curve
        first = gmsh.model.geo.extrude([(2, section.surface)], 0.0, 0.0, core, numElements=[n_layers])
        second = gmsh.model.geo.extrude([first[0]], 0.0, 0.0, length - core)
        gmsh.model.geo.synchronize()
        lateral = [t for _, t in first[2:]] + [t for _, t in second[2:]]
        names = list(section.curve_names) * 2
        size.apply(GMSH_AXES_3D, [(r, "CurvesList", [c]) for r, c in zip(section.curve_radii, section.curves)])
        gmsh.option.setNumber("Mesh.Algorithm", 6)
        gmsh.option.setNumber("Mesh.Algorithm3D", 1)  # Delaunay (the unstructured rest)
        gmsh.option.setNumber("Mesh.Optimize", 1)
        generate(3, order)
        groups = {n: [s for s, c in zip(lateral, names) if c == n] for n in ("surface", "side", "fixed")}
        groups.update(symmetry=[section.surface], end=[second[0][1]])
        mesh = gmsh_to_skfem(3, groups, axes=[2, 0, 1])
    return check_quality(mesh)


def _structured_track(profile, y0: float, z0: float, h_yz: float, h_x: float, h_max: float, depth_mm: float,
                      order: int, box: tuple[float, float], grading: float, x_layers) -> skfem.Mesh:
    """The section meshed as by :func:`extruded_local_mesh` and extruded in one structured layer per interval of
    ``x_layers`` (mm): boundaries "surface", "side", "fixed", "start" and "end"."""
    xs = np.asarray(x_layers, dtype=float)
    require(xs.ndim == 1 and xs.size >= 2 and bool(np.all(np.isfinite(xs))) and bool(np.all(np.diff(xs) > 0)),
            "x_layers", "must be at least two increasing finite coordinates (mm)")
    require(xs.size - 1 <= MAX_LAYERS, "x_layers", f"gives {xs.size - 1} layers (at most {MAX_LAYERS})")
    length = float(xs[-1] - xs[0])
    size = GradedSize(h_yz, h_max, grading, (0.0, float(y0), z0), half_box=(h_x, *box))
    with gmsh_session("extruded") as gmsh:
        section = add_section(profile.section_outline(depth_mm))
        heights = ((xs[1:] - xs[0]) / length).tolist()
        ext = gmsh.model.geo.extrude([(2, section.surface)], 0.0, 0.0, length, numElements=[1] * len(heights),
                                     heights=heights)
        gmsh.model.geo.synchronize()
        size.apply(GMSH_AXES_3D, [(r, "CurvesList", [c]) for r, c in zip(section.curve_radii, section.curves)])
        gmsh.option.setNumber("Mesh.Algorithm", 6)
        generate(3, order)
        lateral = [t for _, t in ext[2:]]
        groups = {n: [s for s, c in zip(lateral, section.curve_names) if c == n] for n in ("surface", "side", "fixed")}
        groups.update(start=[section.surface], end=[ext[0][1]])
        mesh = gmsh_to_skfem(3, groups, axes=[2, 0, 1])
    return mesh.translated((float(xs[0]), 0.0, 0.0))
