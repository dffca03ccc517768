"""Small-strain displacement FE discretisation on scikit-fem: B-matrices at quadrature points, batched assembly.

scikit-fem provides the mesh, the (isoparametric) basis, gradients and ``dx`` (quadrature weight x |J|);
element matrices ``K_e = sum_q B_q^T D_q B_q dx_q``, strains and internal forces are formed here with numpy's
batched matmul (the quadrature points and strain components stacked into one axis) from the precomputed B-matrices
(measured faster than ``BilinearForm`` with quadrature-point tangents, see benchmarks/bench_fem.py, and 1.1-7x
faster than the same products as numpy einsum)
and scattered into a CSR matrix whose pattern and scatter map are computed once.

2D meshes (MeshTri1/2, coordinates (y, z)) are plane strain: in-plane axes map to tensor indices 0, 1, the
out-of-plane axis to index 2 (eps_33 = 0). Strains/stresses are Mandel 6-vectors (calibration.fem.material).
"""

from __future__ import annotations

import functools
import gc
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import skfem

from calibration.fem.material import SQRT2
from wrlayer.errors import InputError

#: Positive-weight quadrature rules on the reference simplices (points (dim, nqp), weights (nqp,)).
_A, _B = 0.1381966011250105, 0.5854101966249685
QUADRATURE = {
    ("tet", 1): (np.array([[0.25], [0.25], [0.25]]), np.array([1.0 / 6.0])),
    # Keast / Stroud 4-point degree-2 rule on the reference tetrahedron (volume 1/6).
    ("tet", 2): (np.array([[_A, _B, _A, _A], [_A, _A, _B, _A], [_A, _A, _A, _B]]), np.full(4, 1.0 / 24.0)),
    ("tri", 1): (np.array([[1.0 / 3.0], [1.0 / 3.0]]), np.array([0.5])),
    # Strang-Fix 3-point degree-2 rule on the reference triangle (area 1/2).
    ("tri", 2): (np.array([[1 / 6, 2 / 3, 1 / 6], [1 / 6, 1 / 6, 2 / 3]]), np.full(3, 1.0 / 6.0)),
}
#: Mandel components that can be non-zero in plane strain (11, 22, 12) and in 3D (all).
PLANE_STRAIN_COMPONENTS = np.array([0, 1, 5])
SOLID_COMPONENTS = np.arange(6)
# (i, j, Mandel index, factor): eps_M[c] += factor * grad[i][j]
_STRAIN_MAP_3D = [(0, 0, 0, 1.0), (1, 1, 1, 1.0), (2, 2, 2, 1.0),
                  (1, 2, 3, 1 / SQRT2), (2, 1, 3, 1 / SQRT2), (0, 2, 4, 1 / SQRT2), (2, 0, 4, 1 / SQRT2),
                  (0, 1, 5, 1 / SQRT2), (1, 0, 5, 1 / SQRT2)]


def mesh_kind(mesh: skfem.Mesh) -> tuple[str, int]:
    """('tet' | 'tri', polynomial order) of a scikit-fem simplex mesh; InputError otherwise."""
    kinds = {skfem.MeshTet1: ("tet", 1), skfem.MeshTet2: ("tet", 2),
             skfem.MeshTri1: ("tri", 1), skfem.MeshTri2: ("tri", 2)}
    for cls, kind in kinds.items():
        if type(mesh) is cls:
            return kind
    raise InputError("mesh", f"must be skfem MeshTri1/MeshTri2 (plane strain) or MeshTet1/MeshTet2 (3D), "
                             f"got {type(mesh).__name__}")


def field_element(kind: str, order: int) -> skfem.Element:
    """Vector Lagrange element of the given order for the displacement field."""
    scalar = {("tet", 1): skfem.ElementTetP1, ("tet", 2): skfem.ElementTetP2,
              ("tri", 1): skfem.ElementTriP1, ("tri", 2): skfem.ElementTriP2}[(kind, order)]
    return skfem.ElementVector(scalar())


@dataclass
class Discretisation:
    """Everything needed to map nodal displacements (mm) to quadrature-point strains and back to forces (N).

    basis: skfem CellBasis (vector Lagrange); B: (n_elem, n_qp, n_comp, n_dof_el) strain-displacement
    matrices for the ``components`` of the Mandel strain; dx: (n_elem, n_qp) integration weights (mm^3 in 3D,
    mm^2 per mm thickness in plane strain); element_dofs: (n_elem, n_dof_el).
    """

    mesh: skfem.Mesh
    basis: skfem.CellBasis
    B: np.ndarray
    dx: np.ndarray
    element_dofs: np.ndarray
    components: np.ndarray
    plane_strain: bool
    csr_indptr: np.ndarray
    csr_indices: np.ndarray
    scatter: np.ndarray   # (n_elem, n_dof_el * n_dof_el) position of each element-matrix entry in csr data
    #: the solver keeps its assembled elastic stiffness and factorisation here between calls (one entry)
    problem_cache: dict = field(default_factory=dict, repr=False)

    @property
    def n_dofs(self) -> int:
        return self.basis.N

    @property
    def n_elements(self) -> int:
        return self.B.shape[0]

    @property
    def n_qp(self) -> int:
        return self.B.shape[1]

    def strain(self, u: np.ndarray, elements: np.ndarray | None = None) -> np.ndarray:
        """Mandel strains (n_elem, n_qp, 6) of the nodal displacement vector ``u`` (mm); with ``elements``: at
        the points of those elements only (n_sel, n_qp, 6)."""
        B, edofs = (self.B, self.element_dofs) if elements is None else (self.B[elements],
                                                                         self.element_dofs[elements])
        n_el, n_qp, n_c, n_i = B.shape
        eps = np.zeros((n_el, n_qp, 6))
        # batched matmul over elements (B is C-contiguous: the reshape is a view); 1.1-1.8x numpy's einsum here
        eps[..., self.components] = np.matmul(B.reshape(n_el, n_qp * n_c, n_i),
                                              u[edofs][:, :, None]).reshape(n_el, n_qp, n_c)
        return eps

    def internal_force(self, stress: np.ndarray, elements: np.ndarray | None = None) -> np.ndarray:
        """Nodal internal forces f = sum B^T sigma dx (N) of Mandel stresses (n_elem, n_qp, 6) in MPa; with
        ``elements``: the forces of those elements' stresses (n_sel, n_qp, 6) alone."""
        B, dx, edofs = ((self.B, self.dx, self.element_dofs) if elements is None else
                        (self.B[elements], self.dx[elements], self.element_dofs[elements]))
        n_el, n_qp, n_c, n_i = B.shape
        weighted = (stress[..., self.components] * dx[:, :, None]).reshape(n_el, 1, n_qp * n_c)
        fe = np.matmul(weighted, B.reshape(n_el, n_qp * n_c, n_i))  # 3-7x numpy's einsum here
        return np.bincount(edofs.ravel(), weights=fe.ravel(), minlength=self.n_dofs)

    @functools.cached_property
    def strain_bound(self) -> np.ndarray:
        """Per element, the largest spectral norm over its points of the strain-displacement matrix (1/mm,
        (n_elem,)): |eps(u) at any point of element e| <= strain_bound[e] |u_e| (Mandel norm, u_e: the element's
        nodal displacements). Bounds how far an iterate's strain can have moved from a reference's."""
        BBt = np.matmul(self.B, self.B.transpose(0, 1, 3, 2))  # (n_el, n_qp, n_c, n_c)
        return np.sqrt(np.linalg.eigvalsh(BBt)[..., -1].max(axis=1))

    def element_matrices(self, tangent: np.ndarray, elements: np.ndarray | None = None,
                         selected: bool = False) -> np.ndarray:
        """Element stiffness matrices (n_sel, n_dof_el, n_dof_el) in N/mm for tangents (n_elem, n_qp, 6, 6)
        (selected=True: ``tangent`` holds only the rows of ``elements``, (n_sel, n_qp, 6, 6))."""
        c = self.components
        if elements is None:
            B, D, dx = self.B, tangent[..., c[:, None], c[None, :]], self.dx
        else:
            D = (tangent if selected else tangent[elements])[..., c[:, None], c[None, :]]
            B, dx = self.B[elements], self.dx[elements]
        n_el, n_qp, n_c, n_i = B.shape
        DB = np.matmul(D * dx[:, :, None, None], B).reshape(n_el, n_qp * n_c, n_i)  # 1.7x numpy's einsum here
        return np.matmul(B.reshape(n_el, n_qp * n_c, n_i).transpose(0, 2, 1), DB)

    def csr_data(self, element_matrices: np.ndarray, elements: np.ndarray | None = None) -> np.ndarray:
        """Scatter element matrices into the data array of the global CSR pattern (summing overlaps)."""
        idx = self.scatter if elements is None else self.scatter[elements]
        return np.bincount(idx.ravel(), weights=element_matrices.ravel(), minlength=len(self.csr_indices))

    def csr_matrix(self, data: np.ndarray) -> sp.csr_matrix:
        """CSR matrix (n_dofs x n_dofs) with the fixed pattern and the given data."""
        return sp.csr_matrix((data, self.csr_indices, self.csr_indptr), shape=(self.n_dofs, self.n_dofs))

    def stiffness(self, tangent: np.ndarray) -> sp.csr_matrix:
        """Global stiffness (N/mm) for quadrature-point tangents (n_elem, n_qp, 6, 6)."""
        return self.csr_matrix(self.csr_data(self.element_matrices(tangent)))

    def qp_coordinates(self) -> np.ndarray:
        """Global coordinates (dim, n_elem, n_qp) of the quadrature points (mm)."""
        return self.basis.mapping.F(self.basis.X)


def discretise(mesh: skfem.Mesh, order: int | None = None) -> Discretisation:
    """Build the displacement discretisation of ``mesh`` (order: 1 or 2; default = the mesh's own order).

    Quadrature: 1 point for linear, a positive 4-point (tet) / 3-point (tri) degree-2 rule for quadratic
    elements (scikit-fem's default tetrahedral rules of order 3 and 4 have negative weights).
    """
    kind, mesh_order = mesh_kind(mesh)
    order = mesh_order if order is None else order
    if order not in (1, 2):
        raise InputError("order", f"must be 1 or 2, got {order}")
    basis = skfem.Basis(mesh, field_element(kind, order), quadrature=QUADRATURE[(kind, order)])
    dim = mesh.dim()
    n_el, n_qp = basis.dx.shape
    n_dof_el = len(basis.basis)
    plane_strain = kind == "tri"
    components = PLANE_STRAIN_COMPONENTS if plane_strain else SOLID_COMPONENTS
    # filled component by component in (component, local dof, element, point) order, where each update is one
    # contiguous block, then transposed once (filling the (element, point, component, dof) layout directly wrote
    # with a stride of 6 n_dof_el: 0.3 of 0.8 s at 40k dofs, measured)
    full = np.zeros((len(components), n_dof_el, n_el, n_qp))
    row = {int(c): r for r, c in enumerate(components)}
    for k, phi in enumerate(basis.basis):
        grad = phi[0].grad  # (dim component, dim derivative, n_el, n_qp)
        for i, j, c, f in _STRAIN_MAP_3D:
            if i < dim and j < dim and c in row:
                full[row[c], k] += f * grad[i, j]
    B = np.ascontiguousarray(full.transpose(2, 3, 0, 1))
    edofs = np.ascontiguousarray(basis.element_dofs.T)
    pattern = _csr_pattern_blocked(edofs, basis.N, dim)
    if pattern is None:
        pattern = _csr_pattern(edofs, basis.N)
    indptr, indices, scatter = pattern
    return Discretisation(mesh, basis, B, np.ascontiguousarray(basis.dx), edofs, components, plane_strain,
                          indptr, indices, scatter)


def frees_its_meshes(func):
    """Decorate a function that builds and drops whole meshes (a rolling block, a static study point): a full
    garbage collection runs when it returns. scikit-fem's meshes refer to themselves (mesh <-> its cached mapping
    and dofs) and pypardiso's solvers to their library handle, so they are freed only by a full collection, which
    Python runs rarely (numpy's and PARDISO's memory do not count towards its thresholds); one process running
    block after block otherwise keeps growing (measured, benchmarks/bench_fem_memory.py)."""

    @functools.wraps(func)
    def wrapper(*args, **kwargs):
        try:
            return func(*args, **kwargs)
        finally:
            gc.collect()

    return wrapper


def _csr_pattern(edofs: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(indptr, indices, scatter) of the global CSR pattern (sorted indices) of element dofs ``edofs``
    (n_elem, n_dof_el); scatter (n_elem, n_dof_el**2): position of each element-matrix entry in the CSR data."""
    n_el, n_dof_el = edofs.shape
    rows = np.repeat(edofs, n_dof_el, axis=1)
    cols = np.tile(edofs, (1, n_dof_el))
    keys = rows.astype(np.int64) * n + cols
    unique, scatter = np.unique(keys.ravel(), return_inverse=True)
    urow = unique // n
    indptr = np.searchsorted(urow, np.arange(n + 1)).astype(np.int64)
    indices = (unique % n).astype(np.int32)
    return indptr, indices, scatter.reshape(n_el, n_dof_el * n_dof_el)


def _csr_pattern_blocked(edofs: np.ndarray, n: int, dim: int):
    """The same as :func:`_csr_pattern` from the NODE pattern when the vector dofs come in blocks (global dof =
    dim * node + component, local dofs ordered node by node, as scikit-fem's ElementVector numbers them): the
    node pairs are dim**2 times fewer keys to sort (the sort dominated ``discretise``: 2.6 of 3.1 s at 62k dofs,
    measured). None when the numbering is not blocked."""
    n_el, n_dof_el = edofs.shape
    if n_dof_el % dim or n % dim:
        return None
    base = edofs[:, 0::dim]
    if np.any(base % dim) or any(np.any(edofs[:, c::dim] != base + c) for c in range(1, dim)):
        return None
    nodes = base // dim                                   # (n_el, nn)
    n_nodes, nn = n // dim, nodes.shape[1]
    keys = np.repeat(nodes, nn, axis=1).astype(np.int64) * n_nodes + np.tile(nodes, (1, nn))
    unique, q = np.unique(keys.ravel(), return_inverse=True)
    urow, ucol = unique // n_nodes, unique % n_nodes
    nptr = np.searchsorted(urow, np.arange(n_nodes + 1)).astype(np.int64)
    rowlen = np.diff(nptr)
    # dof row dim*I + a holds dim * rowlen[I] entries: for each node J of node row I (ascending), dim*J + b
    indptr = np.concatenate([[0], np.cumsum(np.repeat(dim * rowlen, dim))]).astype(np.int64)
    indices = np.empty(indptr[-1], dtype=np.int32)
    qs = np.arange(unique.size)
    start, offset = dim * dim * nptr[urow], dim * (qs - nptr[urow])
    for a in range(dim):
        for b in range(dim):
            indices[start + a * dim * rowlen[urow] + offset + b] = dim * ucol + b
    # element entry (k, l), k = dim*kn + a, l = dim*ln + b -> node pair q[e, kn, ln]
    q = q.reshape(n_el, nn, nn)
    rows = np.broadcast_to(nodes[:, :, None], q.shape)
    s0 = dim * dim * nptr[rows] + dim * (q - nptr[rows])  # (n_el, nn, nn)
    rl = dim * rowlen[rows]
    a = np.arange(dim)[None, None, :, None, None]
    b = np.arange(dim)[None, None, None, None, :]
    scatter = s0[:, :, None, :, None] + a * rl[:, :, None, :, None] + b  # (n_el, kn, a, ln, b)
    return indptr, indices, scatter.reshape(n_el, n_dof_el * n_dof_el)
