"""The nodal forces of the moving Hertz load at a load position x_c (units mm, N, MPa).

Pressure (acting into the body) and surface traction along +x (the rolling direction) on the surface of the
track mesh, the block's flat z = 0 (:mod:`calibration.rolling.track_mesh`) or a profile section extruded along x
(:mod:`calibration.rolling.section_track`):

    3D:  p(x, t) = p0 sqrt(1 - ((x - x_c)/a)^2 - (t/b)^2),   2D (per unit length):  p(x) = p0 sqrt(1 - ((x - x_c)/a)^2)
    q = c p   (traction coefficient c)

with t the lateral coordinate: y on the block, the arc length along the profile from the track centreline y0 on
a section. The pressure acts along the inward normal: -e_z on the block, -n(y) on a section (n the profile's
outward normal, tilted in the (y, z) plane at a gauge corner or flange root).

Consistent nodal forces F_i = int (q e_x - p n) . phi_i dA over the surface facets of the strip, integrated
with a composite rule (each facet split into ``n_sub`` pieces per edge, Gauss rule of ``degree`` on each) whose
points are fixed: F = S p(x_qp) with S (scalar dofs x quadrature points; on a section one per component, S
scaled by the normal at each point) assembled once, so moving the load costs a sparse product per component and
step. Resultant (3D half model y >= 0): pi/3 a b p0 (N); section (full model): 2/3 pi a b p0 (N); 2D: pi/2 a p0
(N/mm).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import skfem
from skfem.quadrature import get_quadrature
from skfem.refdom import RefTri

from wrlayer.errors import require


def composite_rule(dim_facet: int, n_sub: int, degree: int) -> tuple[np.ndarray, np.ndarray]:
    """Points (dim_facet, n) and weights (n,) of a composite Gauss rule on the reference facet ([0, 1] or the
    unit triangle split into n_sub^2 triangles): resolves the square-root edge of the Hertz pressure."""
    if dim_facet == 1:
        g, w = np.polynomial.legendre.leggauss(max(1, (degree + 2) // 2))
        edges = np.linspace(0.0, 1.0, n_sub + 1)
        h = np.diff(edges)
        X = (edges[:-1, None] + 0.5 * h[:, None] * (g[None, :] + 1.0)).ravel()
        return X[None, :], (0.5 * h[:, None] * w[None, :]).ravel()
    Xt, Wt = get_quadrature(RefTri, degree)
    h = 1.0 / n_sub
    pts, wts = [], []
    for i in range(n_sub):
        for j in range(n_sub - i):
            tris = [(np.array([i, j]), np.array([1, 0]), np.array([0, 1]))]
            if j < n_sub - i - 1:  # the upside-down triangle of the cell
                tris.append((np.array([i + 1, j + 1]), np.array([-1, 0]), np.array([0, -1])))
            for c0, e1, e2 in tris:
                pts.append(h * (c0[:, None] + np.column_stack([e1, e2]) @ Xt))
                wts.append(Wt * h * h)
    return np.hstack(pts), np.concatenate(wts)


@dataclass(frozen=True)
class MovingHertzLoad:
    """The moving load's shape: semi-axes a (along x) and b (across; None in 2D), traction coefficient c (-);
    on a section the profile (:class:`meshes.profiles.base.Profile`) and the track centreline's y0 (mm), None on
    the block."""

    a_mm: float
    b_mm: float | None
    traction_coefficient: float = 0.0
    profile: object = None
    y0_mm: float = 0.0

    def __post_init__(self):
        require(self.a_mm > 0, "a_mm", f"must be > 0, got {self.a_mm}")
        require(self.b_mm is None or self.b_mm > 0, "b_mm", f"must be > 0 or None, got {self.b_mm}")

    @property
    def on_section(self) -> bool:
        return self.profile is not None

    def lateral(self, x_qp: np.ndarray) -> np.ndarray | None:
        """The lateral coordinate t (mm) of points x_qp (dim, ...): y on the block, the arc length from y0 along
        the profile on a section (None in 2D)."""
        if self.b_mm is None:
            return None
        if not self.on_section:
            return x_qp[1]
        y = np.clip(x_qp[1], self.profile.y_min, self.profile.y_max)
        return self.profile.arc_length(y) - float(self.profile.arc_length(self.y0_mm))

    def inward_normal(self, x_qp: np.ndarray) -> np.ndarray:
        """Unit inward normal (n_y, n_z) of the profile at the points' y (section only; (2, ...))."""
        y = np.clip(x_qp[1], self.profile.y_min, self.profile.y_max)
        return -np.moveaxis(np.asarray(self.profile.normal(y), dtype=float), -1, 0)

    def shape(self, x_qp: np.ndarray, x_c: float, lateral: np.ndarray | None = None) -> np.ndarray:
        """p / p0 (-) at points x_qp (dim, ...) for the load centre at x = x_c (mm); ``lateral``: their t (mm;
        default :meth:`lateral`)."""
        q = 1.0 - ((x_qp[0] - x_c) / self.a_mm) ** 2
        if self.b_mm is not None:
            t = self.lateral(x_qp) if lateral is None else lateral
            q = q - (t / self.b_mm) ** 2
        return np.sqrt(np.clip(q, 0.0, None))

    def resultant_per_MPa(self) -> float:
        """Normal resultant per MPa of p0 on the model: pi/2 a (N/mm, 2D), pi/3 a b (N, 3D half block) or
        2/3 pi a b (N, full section)."""
        if self.b_mm is None:
            return np.pi / 2 * self.a_mm
        return (2.0 if self.on_section else 1.0) * np.pi / 3 * self.a_mm * self.b_mm


class SurfaceForces:
    """The load's nodal forces on a discretisation: ``force(x_c, p0)`` (N) for the load centre at x_c (mm).

    ``x_range``: the track's extent in x (mm) whose surface facets (widened by a and a facet) carry the load.
    """

    def __init__(self, basis: skfem.CellBasis, load: MovingHertzLoad, x_range: tuple[float, float],
                 n_sub: int | None = None, degree: int = 4):
        mesh = basis.mesh
        dim = mesh.dim()
        require(mesh.boundaries is not None and "surface" in mesh.boundaries, "mesh",
                "has no boundary named 'surface'")
        facets = np.asarray(mesh.boundaries["surface"])
        mid = mesh.p[:, mesh.facets[:, facets]].mean(axis=1)
        reach = load.a_mm + 2.0 * float(np.max(np.ptp(mesh.p[0, mesh.facets[:, facets]], axis=0)))
        near = (mid[0] >= x_range[0] - reach) & (mid[0] <= x_range[1] + reach)
        if dim == 3:
            near &= np.abs(load.lateral(mid)) <= load.b_mm + reach
        facets = facets[near]
        rule = composite_rule(dim - 1, n_sub or (8 if dim == 2 else 4), degree)
        fb = skfem.FacetBasis(mesh, basis.elem.elem, facets=facets, quadrature=rule)
        self.x_qp = fb.global_coordinates().value            # (dim, n_facets, n_qp)
        n_f, n_q = fb.dx.shape
        cols = np.arange(n_f * n_q).reshape(n_f, n_q)
        rows, vals = [], []
        for k, phi in enumerate(fb.basis):
            rows.append(np.broadcast_to(fb.element_dofs[k][:, None], (n_f, n_q)).ravel())
            vals.append((phi[0].value * fb.dx).ravel())
        self.S = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.tile(cols.ravel(), len(vals)))),
                               shape=(basis.N // dim, n_f * n_q))
        self.lateral_qp = load.lateral(self.x_qp)
        # on a section the pressure's (y, z) components: S scaled by the inward normal at each point
        self.S_normal = None if not load.on_section else [
            (self.S @ sp.diags(n.ravel())).tocsr() for n in load.inward_normal(self.x_qp)]
        self.load, self.dim, self.n_dofs = load, dim, basis.N

    def force(self, x_c: float, p0_MPa: float, traction: bool = True) -> np.ndarray:
        """Nodal forces (N) of the pressure p0 (MPa) and (with ``traction``) its traction with the load centre at
        x = x_c (mm)."""
        p = p0_MPa * self.load.shape(self.x_qp, x_c, self.lateral_qp).ravel()
        f = self.S @ p
        out = np.zeros(self.n_dofs)
        if self.S_normal is None:
            out[self.dim - 1::self.dim] = -f                # pressure into the body (-z)
        else:
            out[1::3], out[2::3] = self.S_normal[0] @ p, self.S_normal[1] @ p
        if traction:
            out[0::self.dim] = self.load.traction_coefficient * f  # traction along +x
        return out


__all__ = ["MovingHertzLoad", "SurfaceForces", "composite_rule"]
