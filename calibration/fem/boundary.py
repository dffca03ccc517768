"""Boundary conditions of the engine (felupe's "boundary"): the constrained degrees of freedom of a
discretisation from named mesh boundaries (homogeneous Dirichlet; displacements in mm).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from calibration.fem.assembly import Discretisation
from wrlayer.errors import InputError, require


def dirichlet_dofs(disc: Discretisation, dirichlet: dict[str, Sequence[int]] | None) -> np.ndarray:
    """Indices of constrained dofs; InputError for unknown boundaries / components or a missing "fixed"."""
    mesh = disc.mesh
    names = sorted(mesh.boundaries) if mesh.boundaries else []
    dim = mesh.dim()
    if dirichlet is None:
        if "fixed" not in names:
            raise InputError("mesh", f"has no boundary named 'fixed' (boundaries: {names})")
        dirichlet = {"fixed": range(dim)}
        if "symmetry" in names:
            dirichlet["symmetry"] = [0]
    dofs = []
    for name, comps in dirichlet.items():
        if name not in names:
            raise InputError("dirichlet", f"mesh has no boundary named {name!r} (boundaries: {names})")
        comps = list(comps)
        require(all(isinstance(c, (int, np.integer)) and 0 <= c < dim for c in comps), "dirichlet",
                f"components of {name!r} must be integers in [0, {dim - 1}], got {comps}")
        view = disc.basis.get_dofs(name)
        dofs.append(view.all([f"u^{c + 1}" for c in comps]))
    out = np.unique(np.concatenate(dofs)).astype(np.int64)
    require(out.size > 0, "dirichlet", "constrains no degree of freedom")
    return out


__all__ = ["dirichlet_dofs"]
