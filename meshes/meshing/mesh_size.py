"""Graded element size around the load point (mm): h_min inside a refinement zone, growing linearly outside.

    h(d) = min(h_max, h_min + grading * d),   d = distance (mm) from the refinement zone,

the zone being a box of half-sizes (bx, by, bz) around the load point (x = 0, y0, z0), widened by ``radius``.
The same formula is evaluated by numpy (:meth:`GradedSize.size`, for checks) and handed to Gmsh as a
``MathEval`` background field (:meth:`GradedSize.gmsh_expression`).
"""

from __future__ import annotations

from dataclasses import dataclass

import gmsh
import numpy as np

#: Gmsh coordinate names holding the physical x (rolling), y (lateral), z (vertical) in the 2D and 3D meshes.
GMSH_AXES_2D = {"y": "x", "z": "y"}
GMSH_AXES_3D = {"x": "z", "y": "x", "z": "y"}

#: Elements per 2*pi of boundary curvature (keeps small fillets and arcs resolved where h_max is coarse;
#: chord sag = 0.0086 R). Applied per curved entity with a restricted constant field, because Gmsh's own
#: Mesh.MeshSizeFromCurvature takes seconds on spline boundaries.
ELEMENTS_PER_2PI = 24


@dataclass(frozen=True)
class GradedSize:
    """Element size field (mm). ``grading``: growth of the size per mm of distance (dimensionless)."""

    h_min: float
    h_max: float
    grading: float
    centre: tuple[float, float, float]  # (x, y0, z0), mm
    half_box: tuple[float, float, float] = (0.0, 0.0, 0.0)  # (bx, by, bz), mm
    radius: float = 0.0  # mm

    def __post_init__(self):  # plain floats: their repr is what the Gmsh expression parser reads
        for name in ("h_min", "h_max", "grading", "radius"):
            object.__setattr__(self, name, float(getattr(self, name)))
        for name in ("centre", "half_box"):
            object.__setattr__(self, name, tuple(float(v) for v in getattr(self, name)))

    def distance(self, xyz: np.ndarray) -> np.ndarray:
        """Distance (mm) of points (n, 3) = (x, y, z) from the refinement zone (0 inside)."""
        gap = np.maximum(np.abs(np.asarray(xyz, float) - self.centre) - self.half_box, 0.0)
        return np.maximum(np.linalg.norm(gap, axis=-1) - self.radius, 0.0)

    def size(self, xyz: np.ndarray) -> np.ndarray:
        """Target element size (mm) at points (n, 3)."""
        return np.minimum(self.h_max, self.h_min + self.grading * self.distance(xyz))

    def gmsh_expression(self, axes: dict[str, str]) -> str:
        """The size formula in Gmsh's MathEval syntax; ``axes`` maps x/y/z to Gmsh's coordinate names."""
        terms = []
        for k, name in enumerate("xyz"):
            if name in axes:
                terms.append(f"Max(Abs({axes[name]} - ({self.centre[k]!r})) - {self.half_box[k]!r}, 0)^2")
        dist = f"Max(Sqrt({' + '.join(terms)}) - {self.radius!r}, 0)"
        return f"Min({self.h_max!r}, {self.h_min!r} + {self.grading!r} * {dist})"

    def curvature_size(self, radius: float) -> float:
        """Size limit (mm) on a boundary entity of the given smallest radius of curvature (mm)."""
        return curvature_size(radius, self.h_min, self.h_max)

    def apply(self, axes: dict[str, str], curved: list[tuple[float, str, list[int]]] = (),
              extra: tuple[GradedSize, ...] = ()) -> None:
        """Make this the background size field of the current Gmsh model (sizes from points/boundary off).

        ``curved``: (smallest radius in mm, "CurvesList" or "SurfacesList", entity tags) of curved boundary
        entities, whose size is further limited by :meth:`curvature_size`. ``extra``: further size fields (e.g. a
        finer zone inside this one's); the smallest size applies.
        """
        mesh_field = gmsh.model.mesh.field
        fields = [mesh_field.add("MathEval")]
        mesh_field.setString(fields[0], "F", self.gmsh_expression(axes))
        for zone in extra:
            fields.append(mesh_field.add("MathEval"))
            mesh_field.setString(fields[-1], "F", zone.gmsh_expression(axes))
        set_background_size(fields, [(self.curvature_size(radius), kind, tags) for radius, kind, tags in curved],
                            min([self.h_min] + [z.h_min for z in extra]), self.h_max)


def curvature_size(radius: float, h_min: float, h_max: float) -> float:
    """Size limit (mm) on a boundary entity of smallest radius of curvature ``radius`` (mm): 2 pi R /
    ELEMENTS_PER_2PI, kept within [h_min, h_max]."""
    return min(h_max, max(h_min, 2.0 * np.pi * radius / ELEMENTS_PER_2PI))


def set_background_size(fields: list[int], curved: list[tuple[float, str, list[int]]], h_min: float,
                        h_max: float) -> None:
    """Make min(``fields``, the curvature limits) the background size of the current Gmsh model, with sizes from
    points, boundaries and curvature off. ``curved``: (size limit in mm, "CurvesList" or "SurfacesList", entity
    tags); limits not below h_max are skipped. Mesh.MeshSizeMin/Max = h_min/h_max (mm)."""
    mesh_field = gmsh.model.mesh.field
    fields = list(fields)
    for size, kind, tags in curved:
        if size < h_max:
            fields.append(mesh_field.add("Constant"))
            mesh_field.setNumber(fields[-1], "VIn", size)
            mesh_field.setNumbers(fields[-1], kind, tags)
    if len(fields) > 1:
        fields.append(mesh_field.add("Min"))
        mesh_field.setNumbers(fields[-1], "FieldsList", fields[:-1])
    mesh_field.setAsBackgroundMesh(fields[-1])
    for key, value in {"Mesh.MeshSizeExtendFromBoundary": 0, "Mesh.MeshSizeFromPoints": 0,
                       "Mesh.MeshSizeFromCurvature": 0, "Mesh.MeshSizeMin": h_min, "Mesh.MeshSizeMax": h_max}.items():
        gmsh.option.setNumber(key, value)
