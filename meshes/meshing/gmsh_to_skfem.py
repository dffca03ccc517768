"""Turn the current Gmsh model's mesh into a scikit-fem mesh with named boundaries (no files).

Only nodes used by the volume (3D) or surface (2D) elements are kept: vertices first (in Gmsh tag order, so the
result is deterministic), then the mid-edge nodes of quadratic elements. Boundaries are ``mesh.boundaries``
entries (facet indices) matched from the boundary elements of the given Gmsh entities.
"""

from __future__ import annotations

import gmsh
import numpy as np
import skfem

#: Gmsh element type -> (scikit-fem mesh class, number of vertices, column order from Gmsh to scikit-fem).
_ELEMENTS = {
    2: (skfem.MeshTri1, 3, [0, 1, 2]),
    9: (skfem.MeshTri2, 3, [0, 1, 2, 3, 4, 5]),  # Gmsh and scikit-fem edges: 01, 12, 20
    4: (skfem.MeshTet1, 4, [0, 1, 2, 3]),
    11: (skfem.MeshTet2, 4, [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]),  # Gmsh 8 = edge 23, 9 = edge 13
}


def _elements(dim: int, tag: int = -1) -> tuple[int, np.ndarray]:
    """The single element type and its node-tag connectivity (n_elements, n_nodes) of entities of ``dim``."""
    types, _, nodes = gmsh.model.mesh.getElements(dim, tag)
    if len(types) != 1:
        raise RuntimeError(f"expected one element type in dimension {dim}, got {list(types)}")
    n = gmsh.model.mesh.getElementProperties(types[0])[3]
    return int(types[0]), np.asarray(nodes[0], dtype=np.int64).reshape(-1, n)


def _facet_keys(facets: np.ndarray, n_vertices: int) -> np.ndarray:
    """One integer per facet (columns = facets, rows = vertex indices), independent of vertex order."""
    return np.ravel_multi_index(np.sort(facets, axis=0), (n_vertices,) * facets.shape[0])


def gmsh_to_skfem(dim: int, boundary_entities: dict[str, list[int]], axes: list[int]) -> skfem.Mesh:
    """Mesh of the current model's ``dim``-dimensional entities as a scikit-fem mesh.

    ``boundary_entities`` maps boundary names to Gmsh entity tags of dimension ``dim - 1``; ``axes`` lists which
    Gmsh coordinates (0, 1, 2) become the mesh's coordinates, in order.
    """
    node_tags, coords, _ = gmsh.model.mesh.getNodes()
    coords = np.asarray(coords).reshape(-1, 3)
    etype, conn = _elements(dim)
    mesh_type, n_vert, order = _ELEMENTS[etype]
    conn = conn[:, order]
    vertices = np.unique(conn[:, :n_vert])
    mids = np.setdiff1d(np.unique(conn[:, n_vert:]), vertices)
    used = np.concatenate([vertices, mids])
    index = np.full(int(np.max(node_tags)) + 1, -1, dtype=np.int64)
    index[used] = np.arange(used.size)
    position = np.empty((index.size, 3))
    position[np.asarray(node_tags, dtype=np.int64)] = coords
    points = position[used][:, axes].T
    mesh = mesh_type(np.ascontiguousarray(points), np.ascontiguousarray(index[conn].T))

    facet_keys = _facet_keys(mesh.facets, vertices.size)
    sorter = np.argsort(facet_keys)
    boundaries = {}
    for name, tags in boundary_entities.items():
        found = []
        for tag in tags:
            _, fconn = _elements(dim - 1, tag)
            keys = _facet_keys(index[fconn[:, :dim]].T, vertices.size)
            pos = sorter[np.searchsorted(facet_keys, keys, sorter=sorter)]
            if not np.array_equal(facet_keys[pos], keys):
                raise RuntimeError(f"boundary {name!r}: Gmsh facets not found among the mesh facets")
            found.append(pos)
        boundaries[name] = np.unique(np.concatenate(found)).astype(np.int64)
    return mesh.with_boundaries(boundaries)
