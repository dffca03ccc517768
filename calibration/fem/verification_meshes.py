"""Graded structured meshes for verifying and benchmarking the FEM engine (not the production meshes).

``graded_axis``: uniform spacing ``h`` on [0, fine] then geometric growth (ratio ``growth``) up to ``length``.
``hertz_block``: quarter (3D: x >= 0, y >= 0) or half (2D: y >= 0) block under a surface at z = 0, boundaries
"surface" (z = 0), "fixed" (bottom), "symmetry" (x = 0, 3D), "sym_y" (y = 0), "side" (the other sides).
``quarter_annulus``: plane-strain thick cylinder a <= r <= b, boundaries "inner", "outer", "sym_y" (y = 0), "sym_z" (z = 0).
``hertz_block_gmsh``: the same block as an unstructured gmsh mesh graded away from the load centre.
``hertz_axis_first_yield``: the closed-form reference for the first yield under a circular Hertz pressure.
"""

from __future__ import annotations

import numpy as np
import skfem

from wrlayer.errors import require


def graded_axis(h: float, fine: float, length: float, growth: float = 1.3) -> np.ndarray:
    """Coordinates 0 = c_0 < ... < c_n = length (mm): spacing h up to ``fine``, then growing by ``growth``."""
    n_fine = max(1, int(round(fine / h)))
    c = list(np.linspace(0.0, n_fine * h, n_fine + 1))
    d = h
    while c[-1] < length:
        d *= growth
        c.append(c[-1] + d)
    c = np.array(c)
    c[-1] = max(c[-1], length)
    if c[-1] - c[-2] < 0.5 * (c[-2] - c[-3]):  # merge a sliver last cell
        c = np.delete(c, -2)
    return c * (length / c[-1]) if c[-1] > length * 1.5 else c


def hertz_block(h: float, fine: float, length: float, order: int = 2, dim: int = 3,
                growth: float = 1.3) -> skfem.Mesh:
    """Graded block (mm) for a Hertz load centred at the origin on the top surface z = 0 (see module doc)."""
    ax = graded_axis(h, fine, length, growth)
    if dim == 3:
        m = skfem.MeshTet1.init_tensor(ax, ax, -ax[::-1])
        m = skfem.MeshTet2.from_mesh(m) if order == 2 else m
        tol = 1e-9 * length
        return m.with_boundaries({
            "surface": lambda x: x[2] > -tol, "fixed": lambda x: x[2] < -length + tol,
            "symmetry": lambda x: x[0] < tol, "sym_y": lambda x: x[1] < tol,
            "side": lambda x: (x[0] > length - tol) | (x[1] > length - tol)})
    m = skfem.MeshTri1.init_tensor(ax, -ax[::-1])
    m = skfem.MeshTri2.from_mesh(m) if order == 2 else m
    tol = 1e-9 * length
    return m.with_boundaries({"surface": lambda x: x[1] > -tol, "fixed": lambda x: x[1] < -length + tol,
                              "sym_y": lambda x: x[0] < tol, "side": lambda x: x[0] > length - tol})


def quarter_annulus(a: float, b: float, n_r: int, n_theta: int, order: int = 2, grading: float = 1.0) -> skfem.Mesh:
    """Quarter of a thick cylinder a <= r <= b in the (y, z) plane, radial spacing growing by ``grading``.

    Boundaries: "inner" (r = a), "outer" (r = b), "sym_y" (the y = 0 edge: fix u_y) and "sym_z" (z = 0: fix u_z).
    """
    w = grading ** np.arange(n_r)
    r = a + (b - a) * np.concatenate([[0.0], np.cumsum(w)]) / w.sum()
    th = np.linspace(0.0, np.pi / 2, n_theta + 1)
    m = skfem.MeshTri1.init_tensor(r, th)
    p = np.vstack([m.p[0] * np.cos(m.p[1]), m.p[0] * np.sin(m.p[1])])
    m = skfem.MeshTri1(p, m.t)
    if order == 2:
        m = skfem.MeshTri2.from_mesh(m)
        # put the mid-edge nodes on the arcs
        rr = np.hypot(m.p[0], m.p[1])
        near_a = np.abs(rr - a) < 0.25 * (r[1] - a)
        near_b = np.abs(rr - b) < 0.25 * (b - r[-2])
        scale = np.where(near_a, a / rr, np.where(near_b, b / rr, 1.0))
        m = skfem.MeshTri2(m.p * scale, m.t)
    tol = 1e-9 * b
    rad = lambda x: np.hypot(x[0], x[1])
    return m.with_boundaries({"inner": lambda x: rad(x) < a + 0.01 * (r[1] - a), "outer": lambda x: rad(x) > b - 0.01 * (b - r[-2]),
                              "sym_y": lambda x: np.abs(x[0]) < tol, "sym_z": lambda x: np.abs(x[1]) < tol})


def hertz_block_gmsh(h: float, fine: float, length: float, order: int = 2, dim: int = 3,
                     coarse_fraction: float = 0.2) -> skfem.Mesh:
    """Like :func:`hertz_block` but unstructured (gmsh): size ``h`` within ``fine`` of the origin, growing
    linearly to ``coarse_fraction * length`` at distance ``length``. Far fewer elements than the tensor grid."""
    import gmsh

    from meshes.meshing.gmsh_session import initialize_gmsh

    initialize_gmsh()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NumThreads", 1)
        gmsh.model.add("hertz_block")
        occ = gmsh.model.occ
        if dim == 3:
            occ.addBox(0.0, 0.0, -length, length, length, length)
        else:
            occ.addRectangle(0.0, -length, 0.0, length, length)
        occ.synchronize()
        origin = gmsh.model.getEntitiesInBoundingBox(-1e-6, -1e-6, -1e-6, 1e-6, 1e-6, 1e-6, 0)
        f = gmsh.model.mesh.field
        dist = f.add("Distance")
        f.setNumbers(dist, "PointsList", [tag for _, tag in origin])
        thr = f.add("Threshold")
        f.setNumber(thr, "InField", dist)
        f.setNumber(thr, "SizeMin", h)
        f.setNumber(thr, "SizeMax", coarse_fraction * length)
        f.setNumber(thr, "DistMin", fine)
        f.setNumber(thr, "DistMax", length)
        f.setAsBackgroundMesh(thr)
        for opt in ("MeshSizeExtendFromBoundary", "MeshSizeFromPoints", "MeshSizeFromCurvature"):
            gmsh.option.setNumber(f"Mesh.{opt}", 0)
        gmsh.model.mesh.generate(dim)
        node_tags, coords, _ = gmsh.model.mesh.getNodes()
        etype = 4 if dim == 3 else 2
        _, elem_nodes = gmsh.model.mesh.getElementsByType(etype)
    finally:
        gmsh.finalize()
    index = np.zeros(int(node_tags.max()) + 1, dtype=np.int64)
    index[node_tags.astype(np.int64)] = np.arange(len(node_tags))
    p = coords.reshape(-1, 3).T[:dim]
    t = index[elem_nodes.astype(np.int64)].reshape(-1, dim + 1).T
    used = np.unique(t)
    remap = np.full(p.shape[1], -1)
    remap[used] = np.arange(len(used))
    p, t = np.ascontiguousarray(p[:, used]), np.ascontiguousarray(remap[t])
    tol = 1e-9 * length
    if dim == 3:
        m = skfem.MeshTet1(p, t)
        m = skfem.MeshTet2.from_mesh(m) if order == 2 else m
        return m.with_boundaries({
            "surface": lambda x: x[2] > -tol, "fixed": lambda x: x[2] < -length + tol,
            "symmetry": lambda x: x[0] < tol, "sym_y": lambda x: x[1] < tol,
            "side": lambda x: (x[0] > length - tol) | (x[1] > length - tol)})
    m = skfem.MeshTri1(p, t)
    m = skfem.MeshTri2.from_mesh(m) if order == 2 else m
    return m.with_boundaries({"surface": lambda x: x[1] > -tol, "fixed": lambda x: x[1] < -length + tol,
                              "sym_y": lambda x: x[0] < tol, "side": lambda x: x[0] > length - tol})


def hertz_axis_first_yield(poisson: float, n: int = 20001) -> tuple[float, float]:
    """First yield of a von Mises half-space under the circular Hertz pressure p0 sqrt(1 - (r/a)^2).

    Returns (p0 / Y, z / a): the peak pressure at which the von Mises stress first reaches the yield stress Y, and
    the depth of that point. Stresses on the axis r = 0 (Johnson, *Contact Mechanics*, 1985, eq. 3.45):
    sigma_r = sigma_theta = p0 [-(1 + nu)(1 - zeta atan(1/zeta)) + 1/(2 (1 + zeta^2))], sigma_z = -p0 / (1 + zeta^2),
    zeta = z/a, no shear, so von Mises = |sigma_z - sigma_r|; its maximum over the depth (a fine grid on
    0 < zeta <= 3, refined by a parabola through the peak) is the maximum in the whole half-space (Johnson, ibid.).
    """
    require(isinstance(poisson, (int, float)) and -1.0 < poisson < 0.5, "poisson",
            f"must be a number in (-1, 0.5), got {poisson!r}")
    zeta = np.linspace(1e-6, 3.0, n)
    s_r = -(1.0 + poisson) * (1.0 - zeta * np.arctan(1.0 / zeta)) + 0.5 / (1.0 + zeta ** 2)
    s_z = -1.0 / (1.0 + zeta ** 2)
    vm = np.abs(s_z - s_r)
    k = int(np.argmax(vm))
    k = min(max(k, 1), n - 2)
    y0, y1, y2 = vm[k - 1:k + 2]
    d = zeta[1] - zeta[0]
    denom = y0 - 2.0 * y1 + y2
    shift = 0.5 * (y0 - y2) / denom if denom != 0 else 0.0
    peak = y1 - 0.25 * (y0 - y2) * shift
    return float(1.0 / peak), float(zeta[k] + shift * d)
