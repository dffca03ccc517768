"""Mesh output (mm): scikit-fem meshes to meshio, written atomically as .vtu (VTK) or .msh (Gmsh 2.2 ASCII).

- ``.vtu``: the elements; each named boundary is encoded as scikit-fem cell data (``skfem:b:<name>``), so
  ``skfem.io.meshio.from_file`` restores ``mesh.boundaries``.
- ``.msh``: the elements plus, per named boundary, its facets (linear lines/triangles) as a Gmsh physical
  group with that name; readable by Gmsh, meshio and ``skfem.io.meshio.from_file`` (boundaries restored).
"""

from __future__ import annotations

import os
from pathlib import Path

import meshio
import numpy as np
import skfem
from skfem.io.meshio import to_meshio as _skfem_to_meshio

from wrlayer.atomic_write import atomic_output_dir
from wrlayer.errors import InputError

_FACET_CELL = {2: "line", 3: "triangle"}


def to_meshio(mesh: skfem.Mesh) -> meshio.Mesh:
    """The mesh as meshio.Mesh, boundaries encoded as scikit-fem cell data (quadratic nodes kept)."""
    return _skfem_to_meshio(mesh)


def to_meshio_gmsh(mesh: skfem.Mesh) -> meshio.Mesh:
    """The mesh as meshio.Mesh with one Gmsh physical group per named boundary (tags 1, 2, ...)."""
    plain = _skfem_to_meshio(mesh, encode_cell_data=False)
    volume_tag = len(mesh.boundaries or {}) + 1
    cells = [plain.cells[0]]
    physical = [np.full(len(plain.cells[0].data), volume_tag)]
    field_data = {"domain": np.array([volume_tag, mesh.dim()])}
    for tag, (name, facets) in enumerate((mesh.boundaries or {}).items(), start=1):
        cells.append(meshio.CellBlock(_FACET_CELL[mesh.dim()], mesh.facets[:, np.asarray(facets)].T))
        physical.append(np.full(len(facets), tag))
        field_data[name] = np.array([tag, mesh.dim() - 1])
    return meshio.Mesh(plain.points, cells, field_data=field_data,
                       cell_data={"gmsh:physical": physical, "gmsh:geometrical": physical})


def check_mesh_path(path: str | os.PathLike) -> Path:
    """The path as Path; InputError unless it ends in .vtu or .msh."""
    path = Path(path)
    if path.suffix.lower() not in (".vtu", ".msh"):
        raise InputError(str(path), "mesh files must end in .vtu or .msh")
    return path


def write_mesh(mesh: skfem.Mesh, path: str | os.PathLike) -> Path:
    """Write ``mesh`` to ``path`` (.vtu or .msh) atomically; returns the path."""
    path = check_mesh_path(path)
    suffix = path.suffix.lower()
    with atomic_output_dir(path.parent) as tmp:
        if suffix == ".vtu":
            meshio.write(tmp / path.name, to_meshio(mesh), file_format="vtu")
        else:
            meshio.write(tmp / path.name, to_meshio_gmsh(mesh), file_format="gmsh22", binary=False)
    return path
