"""Surface pressure loads: Hertzian (ellipsoidal / semi-elliptic) pressure and uniform pressure on a named boundary.

The pressure acts along the inward surface normal (traction ``t = -p n_out``). Consistent nodal forces
``F_i = -int p n_out . phi_i dA`` are integrated on the loaded facets with a composite rule (each reference facet
split into ``n_sub`` pieces, Gauss rule on each), which resolves the square-root edge of the Hertz distribution
to well below 1 % of the total force. Forces are for p0 = 1 MPa (N per MPa); the solver scales them.

Hertz geometry (units mm): the centre is the point of the boundary "surface" at lateral position ``y0_mm``
(3D: and x = ``centre_x_mm``). ``t`` is the lateral coordinate measured along the surface tangent at the centre
(points are projected onto the tangent line/plane at the centre; accurate for b << profile radius) and in 3D
``s`` the coordinate along the rolling direction x projected onto that plane:
3D ``p = p0 sqrt(1 - (s/a)^2 - (t/b)^2)``, 2D (plane strain) ``p = p0 sqrt(1 - (t/b)^2)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import skfem
from skfem.quadrature import get_quadrature
from skfem.refdom import RefTri

from wrlayer.errors import InputError, require


@dataclass
class PreparedLoad:
    """A load evaluated on one discretisation: nodal forces per MPa of p0 and the load centre."""

    force_per_MPa: np.ndarray         # (n_dofs,) N/MPa
    centre_mm: np.ndarray | None      # (dim,) surface point at the load centre
    normal_out: np.ndarray | None     # (dim,) outward unit normal at the centre
    centre_probe: object | None       # sparse (dim, n_dofs): displacement components at the centre

    def centre_displacement_mm(self, u: np.ndarray) -> float:
        """Normal displacement of the centre point, positive INTO the body (mm); NaN without a centre."""
        if self.centre_probe is None:
            return float("nan")
        return float(-(self.centre_probe @ u) @ self.normal_out)


def _composite_facet_rule(dim_facet: int, n_sub: int, degree: int) -> tuple[np.ndarray, np.ndarray]:
    """Composite quadrature on the reference facet: [0, 1] (dim_facet 1) or the unit triangle (dim_facet 2)."""
    if dim_facet == 1:
        g, w = np.polynomial.legendre.leggauss(max(1, (degree + 2) // 2))
        edges = np.linspace(0.0, 1.0, n_sub + 1)
        h = np.diff(edges)
        X = (edges[:-1, None] + 0.5 * h[:, None] * (g[None, :] + 1.0)).ravel()
        W = (0.5 * h[:, None] * w[None, :]).ravel()
        return X[None, :], W
    Xt, Wt = get_quadrature(RefTri, degree)
    pts, wts = [], []
    h = 1.0 / n_sub
    for i in range(n_sub):
        for j in range(n_sub - i):
            corners = [np.array([i, j]) * h, np.array([i + 1, j]) * h, np.array([i, j + 1]) * h]
            if j < n_sub - i:
                pts.append(corners[0][:, None] + np.column_stack([corners[1] - corners[0],
                                                                  corners[2] - corners[0]]) @ Xt)
                wts.append(Wt * h * h)
            if j < n_sub - i - 1:  # the upside-down triangle of the cell
                c0 = np.array([i + 1, j + 1]) * h
                pts.append(c0[:, None] + np.column_stack([np.array([i, j + 1]) * h - c0,
                                                          np.array([i + 1, j]) * h - c0]) @ Xt)
                wts.append(Wt * h * h)
    return np.hstack(pts), np.concatenate(wts)


def _boundary_facets(mesh: skfem.Mesh, name: str) -> np.ndarray:
    if mesh.boundaries is None or name not in mesh.boundaries:
        have = sorted(mesh.boundaries) if mesh.boundaries else []
        raise InputError("mesh", f"has no boundary named {name!r} (boundaries: {have})")
    return np.asarray(mesh.boundaries[name])


def _outward_normals(mesh: skfem.Mesh, facets: np.ndarray) -> np.ndarray:
    """Unit outward normals (n_facets, dim) from the facet vertices, oriented away from the adjacent element."""
    p = mesh.p[:, mesh.facets[:, facets]]  # (dim, n_vert_facet, nf)
    if mesh.dim() == 2:
        d = p[:, 1] - p[:, 0]
        n = np.stack([d[1], -d[0]], axis=1)
    else:
        n = np.cross((p[:, 1] - p[:, 0]).T, (p[:, 2] - p[:, 0]).T)
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    elem_centre = mesh.p[:, mesh.t[:mesh.dim() + 1, mesh.f2t[0, facets]]].mean(axis=1).T
    flip = np.einsum("fi,fi->f", n, p.mean(axis=1).T - elem_centre) < 0
    n[flip] *= -1
    return n


def _surface_point(mesh: skfem.Mesh, facets: np.ndarray, lateral: np.ndarray, z0: float | None):
    """Surface point with in-plane coordinates ``lateral`` ((y,) in 2D, (x, y) in 3D): (point, outward normal,
    facet index)."""
    dim = mesh.dim()
    normals = _outward_normals(mesh, facets)
    verts = mesh.p[:, mesh.facets[:, facets]]  # (dim, nv, nf)
    cands = []
    if dim == 2:
        ya, yb = verts[0, 0], verts[0, 1]
        hit = np.nonzero((ya - lateral[0]) * (yb - lateral[0]) <= 0)[0]
        for k in hit:
            s = 0.5 if yb[k] == ya[k] else (lateral[0] - ya[k]) / (yb[k] - ya[k])
            cands.append((verts[:, 0, k] + s * (verts[:, 1, k] - verts[:, 0, k]), normals[k], facets[k]))
    else:
        P = verts[:2]  # xy projection (2, 3, nf)
        T = np.stack([P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]], axis=-1)  # (2, nf, 2)
        det = T[0, :, 0] * T[1, :, 1] - T[0, :, 1] * T[1, :, 0]
        ok = np.abs(det) > 1e-14 * np.max(np.abs(T)) ** 2
        r = lateral[:, None] - P[:, 0]
        with np.errstate(divide="ignore", invalid="ignore"):
            l1 = (r[0] * T[1, :, 1] - r[1] * T[0, :, 1]) / det
            l2 = (T[0, :, 0] * r[1] - T[1, :, 0] * r[0]) / det
        tol = 1e-9
        hit = np.nonzero(ok & (l1 >= -tol) & (l2 >= -tol) & (l1 + l2 <= 1 + tol))[0]
        for k in hit:
            pt = verts[:, 0, k] + l1[k] * (verts[:, 1, k] - verts[:, 0, k]) + l2[k] * (verts[:, 2, k] - verts[:, 0, k])
            cands.append((pt, normals[k], facets[k]))
    if not cands:
        raise InputError("load centre", f"lateral position {lateral.tolist()} mm is not on the boundary 'surface'")
    if z0 is not None:
        dist = [abs(c[0][-1] - z0) for c in cands]
        best = int(np.argmin(dist))
        size = np.linalg.norm(np.ptp(mesh.p, axis=1))
        require(dist[best] <= 1e-3 * size + 1e-9, "load centre",
                f"z0 = {z0} mm is {dist[best]:.4g} mm from the boundary 'surface'")
        return cands[best]
    best = int(np.argmax([abs(c[1][-1]) for c in cands]))  # the facet facing most along +-z
    return cands[best]


def probe_operator(basis: skfem.CellBasis, point: np.ndarray, element: int):
    """Sparse operator (dim, n_dofs) evaluating the displacement at ``point`` inside/on ``element``.

    The reference coordinates come from the element's vertices (exact for straight-sided elements; for curved
    quadratic boundaries the point lies on the chordal facet, an O(h^2) approximation).
    """
    mesh = basis.mesh
    dim = mesh.dim()
    v = mesh.p[:, mesh.t[:dim + 1, element]]  # (dim, dim+1)
    A = v[:, 1:] - v[:, [0]]
    X = np.linalg.solve(A, point - v[:, 0])
    X = np.clip(X, 0.0, 1.0)[:, None]
    scalar = basis.elem.elem
    edofs = basis.element_dofs[:, element]
    rows, cols, vals = [], [], []
    for k, dof in enumerate(edofs):
        phi = float(scalar.lbasis(X, k // dim)[0][0])
        rows.append(k % dim)
        cols.append(dof)
        vals.append(phi)
    return sp.csr_matrix((vals, (rows, cols)), shape=(dim, basis.N))


def _nodal_forces(basis: skfem.CellBasis, facets: np.ndarray, pressure, n_sub: int, degree: int) -> np.ndarray:
    """F_i = -int p(x) n_out . phi_i dA over ``facets`` (N per MPa) for the callable pressure p(x) (MPa)."""
    mesh = basis.mesh
    fb = skfem.FacetBasis(mesh, basis.elem, facets=facets,
                          quadrature=_composite_facet_rule(mesh.dim() - 1, n_sub, degree))

    @skfem.LinearForm
    def traction(v, w):
        n = w.n
        p = pressure(w.x)
        return -p * sum(n[i] * v[i] for i in range(mesh.dim()))

    return traction.assemble(fb)


@dataclass
class HertzLoad:
    """Hertzian pressure on the boundary "surface" (see module docstring). Lengths mm.

    y0_mm: lateral position of the centre; b_mm: lateral semi-axis; a_mm: semi-axis along x (3D only; None for
    plane strain); centre_x_mm: x of the centre (3D); z0_mm: optional expected height of the centre, checked
    against the surface (InputError when off the surface). Total force for p0: 2D pi/2 p0 b (N/mm),
    3D 2/3 pi a b p0 (N).
    """

    y0_mm: float
    b_mm: float
    a_mm: float | None = None
    centre_x_mm: float = 0.0
    z0_mm: float | None = None
    boundary: str = "surface"
    n_sub: int | None = None     # facet subdivisions for the force integral (default 8 in 2D, 4 in 3D)
    degree: int = 4

    def __post_init__(self) -> None:
        require(np.isfinite(self.y0_mm), "y0_mm", f"must be finite, got {self.y0_mm}")
        require(self.b_mm > 0, "b_mm", f"must be > 0, got {self.b_mm}")
        require(self.a_mm is None or self.a_mm > 0, "a_mm", f"must be > 0 or None, got {self.a_mm}")

    def total_force_per_MPa(self) -> float:
        """Analytic resultant per MPa of p0: pi/2 b (N/mm, 2D) or 2/3 pi a b (N, 3D)."""
        return np.pi / 2 * self.b_mm if self.a_mm is None else 2.0 / 3.0 * np.pi * self.a_mm * self.b_mm

    def _centre(self, basis: skfem.CellBasis):
        mesh = basis.mesh
        dim = mesh.dim()
        require((dim == 3) == (self.a_mm is not None), "a_mm",
                "must be given for 3D (tetrahedral) meshes and None for 2D (plane-strain) meshes")
        facets = _boundary_facets(mesh, self.boundary)
        lateral = np.array([self.y0_mm]) if dim == 2 else np.array([self.centre_x_mm, self.y0_mm])
        centre, n_out, facet = _surface_point(mesh, facets, lateral, self.z0_mm)
        return facets, centre, n_out, facet

    def centre_only(self, basis: skfem.CellBasis) -> PreparedLoad:
        """The load centre and its displacement probe without the (costlier) nodal forces (force = None)."""
        _, centre, n_out, facet = self._centre(basis)
        return PreparedLoad(None, centre, n_out, probe_operator(basis, centre, int(basis.mesh.f2t[0, facet])))

    def prepare(self, basis: skfem.CellBasis) -> PreparedLoad:
        """Nodal forces per MPa of p0, centre point, outward normal and centre probe on ``basis``."""
        mesh = basis.mesh
        dim = mesh.dim()
        facets, centre, n_out, facet = self._centre(basis)
        if dim == 2:
            t_hat = np.array([-n_out[1], n_out[0]])
            t_hat *= 1.0 if (t_hat[0] > 0 or (t_hat[0] == 0 and t_hat[1] > 0)) else -1.0
            s_hat = None
        else:
            ex = np.array([1.0, 0.0, 0.0])
            s_hat = ex - (ex @ n_out) * n_out
            s_hat /= np.linalg.norm(s_hat)
            t_hat = np.cross(n_out, s_hat)
            t_hat *= 1.0 if t_hat[1] >= 0 else -1.0
        reach = max(self.b_mm, self.a_mm or 0.0)
        n_sub = self.n_sub or (8 if dim == 2 else 4)
        fmid = mesh.p[:, mesh.facets[:, facets]].mean(axis=1)
        fsize = np.max(np.linalg.norm(mesh.p[:, mesh.facets[:, facets]] - fmid[:, None, :], axis=0), axis=0)
        near = facets[np.linalg.norm(fmid.T - centre, axis=1) <= reach * 1.05 + fsize]

        def pressure(x):
            d = x - centre.reshape((dim,) + (1,) * (x.ndim - 1))
            t = np.einsum("i,i...->...", t_hat, d) / self.b_mm
            q = 1.0 - t ** 2
            if dim == 3:
                q -= (np.einsum("i,i...->...", s_hat, d) / self.a_mm) ** 2
            return np.sqrt(np.clip(q, 0.0, None))

        force = _nodal_forces(basis, near, pressure, n_sub, self.degree)
        return PreparedLoad(force, centre, n_out, probe_operator(basis, centre, int(mesh.f2t[0, facet])))


@dataclass
class UniformPressure:
    """Uniform pressure p = p0 (MPa) on the named boundary, acting inward; e.g. a pressurised bore.

    probe_mm: optional point (on the boundary) whose normal displacement is reported as the centre displacement.
    """

    boundary: str
    probe_mm: tuple[float, ...] | None = None

    def prepare(self, basis: skfem.CellBasis) -> PreparedLoad:
        facets = _boundary_facets(basis.mesh, self.boundary)
        force = _nodal_forces(basis, facets, lambda x: np.ones(x.shape[1:]), 1, 4)
        if self.probe_mm is None:
            return PreparedLoad(force, None, None, None)
        point = np.asarray(self.probe_mm, dtype=float)
        fmid = basis.mesh.p[:, basis.mesh.facets[:, facets]].mean(axis=1).T
        k = int(np.argmin(np.linalg.norm(fmid - point, axis=1)))
        n_out = _outward_normals(basis.mesh, facets[k:k + 1])[0]
        return PreparedLoad(force, point, n_out, probe_operator(basis, point, int(basis.mesh.f2t[0, facets[k]])))
