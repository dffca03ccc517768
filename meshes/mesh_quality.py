"""Shape quality of simplex meshes (scikit-fem meshes; quadratic meshes are judged by their vertices).

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
