"""Shape quality and geometric checks of simplex meshes (scikit-fem meshes, mm).

Quadratic meshes are judged by their vertices for the shape quality.

Mean-ratio quality, 1 for the equilateral simplex and 0 for a degenerate one:
triangle ``4 sqrt(3) A / sum(l^2)``, tetrahedron ``12 (3 V)^(2/3) / sum(l^2)`` (l: edge lengths).
"""

from __future__ import annotations

import itertools

import numpy as np
import skfem


def element_quality(mesh: skfem.Mesh) -> np.ndarray:
    """Mean-ratio quality of every element (triangles or tetrahedra), shape (n_elements,)."""
    corners = mesh.p[:, mesh.t[: mesh.dim() + 1]]  # (dim, n_vertices, n_elements)
    edges = corners[:, [1 + i for i in range(mesh.dim())]] - corners[:, [0]]
    sum_l2 = sum(np.sum((corners[:, i] - corners[:, j]) ** 2, axis=0)
                 for i, j in itertools.combinations(range(mesh.dim() + 1), 2))
    det = np.abs(np.linalg.det(np.moveaxis(edges, -1, 0)))
    if mesh.dim() == 2:
        return 2.0 * np.sqrt(3.0) * det / sum_l2  # area = det / 2
    if mesh.dim() == 3:
        return 12.0 * (det / 2.0) ** (2.0 / 3.0) / sum_l2  # 3 V = det / 2
    raise ValueError(f"element_quality: {mesh.dim()}D meshes are not supported")


def edge_lengths_at(mesh: skfem.Mesh, point: np.ndarray) -> np.ndarray:
    """Lengths (mm) of the mesh edges that touch the vertex nearest to ``point``."""
    vertices = np.unique(mesh.t)  # quadratic meshes: mesh.p also holds the mid-edge nodes
    vertex = int(vertices[np.argmin(np.linalg.norm(mesh.p[:, vertices].T - np.asarray(point, float), axis=1))])
    edges = mesh.facets if mesh.dim() == 2 else mesh.edges
    touching = edges[:, np.any(edges == vertex, axis=0)]
    return np.linalg.norm(mesh.p[:, touching[0]] - mesh.p[:, touching[1]], axis=0)


def mesh_measure(mesh: skfem.Mesh) -> float:
    """Area (mm^2, 2D) or volume (mm^3, 3D) of the mesh, integrated on its (possibly curved) elements."""
    basis = skfem.Basis(mesh, mesh.elem(), intorder=2)
    return float(skfem.Functional(lambda w: 1.0 + 0.0 * w.x[0]).assemble(basis))


def surface_deviation_mm(mesh: skfem.Mesh, profile, boundary: str = "surface") -> float:
    """Largest distance (mm) of the nodes (vertices and mid-edge nodes) of a boundary from the profile curve.

    Distance of a node (y, z) from z = profile.z(y) measured along the normal, |z - z(y)| / sqrt(1 + z'(y)^2)
    (first order in the deviation).
    """
    facet_dofs = mesh.dofs.get_facet_dofs(mesh.boundaries[boundary])
    nodes = np.unique(np.concatenate([np.unique(facet_dofs.nodal[k]) for k in facet_dofs.nodal]
                                     + [np.unique(facet_dofs.facet[k]) for k in facet_dofs.facet]
                                     + [np.unique(facet_dofs.edge[k]) for k in facet_dofs.edge]))
    y, z = mesh.doflocs[-2, nodes], mesh.doflocs[-1, nodes]
    return float(np.max(np.abs(z - profile.z(y)) / np.sqrt(1.0 + profile.dz(y) ** 2)))
