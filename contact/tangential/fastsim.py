"""Tangential rolling contact on a Kik–Piotrowski patch: Kalker's simplified theory (FASTSIM), strip by strip.

Units: mm, N, MPa (N/mm^2), s; creepages vx, vy dimensionless, spin phi in 1/mm; flexibilities L in mm/MPa.

Sign convention (Kalker's): the creepages are the rigid slip velocity of body 1 relative to body 2 divided by the
rolling speed V; tractions and forces act on body 1 and oppose the slip, so for an ellipse at small creepage
Fx = -G a b C11 vx and Fy = -G a b (C22 vy + sqrt(ab) C23 phi). With the usual railway creepages (wheel relative to
rail) the results are the forces exerted BY THE RAIL ON THE WHEEL (the paper's Table 1: vx = 0.002 -> Fx < 0).
Mz is the moment about the z axis through the patch origin (x = 0 on every strip, y = 0 of the patch frame).

Rolling direction x; material enters each strip at the leading edge x = +x_l(y) and leaves at -x_l(y).

Algorithm (Kalker 1982, "A fast algorithm for the simplified theory of rolling contact", VSD 11):
surface displacement u = L * traction with three flexibilities; in adhesion the slip s = w - du/dx vanishes, w the
rigid slip (vx - phi y, vy + phi x). Each strip (its own length 2 x_l(y)) is cut into ``nx`` equal cells; the
traction at cell centre k is marched from the leading edge (traction 0) with the rigid-slip increment evaluated at
the middle of each step (exact for the linear w, so the adhesion solution is exact at the stations):

    pH_k = t_{k-1} - (vx/L1 - phi y/L3, vy/L2 + phi x_mid/L3) * step_k,   step_0 = dx/2, step_k = dx
    t_k  = pH_k                        if |pH_k| <= mu pn_k  (adhesion)
    t_k  = mu pn_k pH_k / |pH_k|       otherwise             (slip; Coulomb bound)

pn_k is the cell average of the semi-elliptic pressure p_peak sqrt(1 - (x/x_l)^2) (eq. 11), so that full slip
gives exactly mu N of the patch. A slipping step moves the surfaces by the slip displacement
du_k = (L1 (t_x - pH_x), L2 (t_y - pH_y)) (mm); |du| / dx * V is the cell's slip velocity (mm/s). (With spin the
FASTSIM spin slip is the rigid spin slip scaled by L1/L3, L2/L3, a known property of the three-flexibility method.)

Frictional work per unit area of a step: (|t_{k-1}| + |t_k|)/2 |du_k| (trapezoid in the traction). The traction
left at the last station is released at the trailing edge, where the bound mu p vanishes (slip L t_last, work
L |t_last|^2 / 2), in the trailing half of the last cell: it is the continuum slip zone at the trailing edge
when that zone is narrower than a cell. A step between two cell centres gives half its work and slip to each
cell, so that every cell collects exactly its own length dx. With these two rules the dissipated power equals the creep-force power
-(Fx vx + Fy vy + Mz phi) V to O(dx^2) (0.3 % at nx = 60, vx = 0.002, pure longitudinal creepage), while the
plain |t_k| |s_k| rule misses ~10 % there. Outputs: frictional power density P_T = V * work / dx
(N/mm^2 * mm/s = 1e-3 W/mm^2, converted to W/mm^2) and frictional work per unit area over one pass
W_T = sum of the work along the strip (= integral |t| |s V| dt over the passage, N/mm = N mm/mm^2).

Non-elliptic extension (the flexibility rule): ONE set of flexibilities for the whole patch, from the equivalent
ellipse of Kik & Piotrowski (2008) that keeps the patch area A and its length/width ratio (as in CONTACT,
m_hertz.equiv_ellipse): a = sqrt(A/pi) sqrt(l/w), b = sqrt(A/pi) sqrt(w/l) with l = 2 max x_l, w = n_strips h;
then (Kalker 1982) L1 = 8a/(3 G C11), L2 = 8a/(3 G C22), L3 = pi a sqrt(a/b)/(4 G C23), C_ij(a/b, nu) from
:mod:`contact.tangential.kalker_coefficients`. Each strip keeps its own length x_l(y) and pressure. For an elliptic patch
this reproduces Kalker's linear theory exactly in the continuum limit (strip integrals of 2 x_l(y)^2 and
4/3 x_l(y)^3 give 8a^2b/3 and pi a^3 b/2). The alternative per-strip rule L(y) = 8 x_l(y)/(3 G C11) would change
the small-creepage force of an ellipse by the factor 3 pi/8 = 1.18 and is therefore not used.
Options (``flexibility=``): "three" (default, Kalker's three flexibilities), "single" (one combined flexibility,
as CONTACT at large creepage; closer to the paper's Table 1 forces, see benchmarks/bench_fastsim.py) and
"blended" (CONTACT's creepage-dependent blend of the two), see :func:`flexibilities`.

"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from contact.tangential.kalker_coefficients import CreepCoefficients, creep_coefficients
from contact.normal.patch import Patch
from wrlayer.errors import require
from wrlayer.jit import kernel
from wrlayer.short_repr import short_repr

#: N/mm^2 * mm/s = N mm/(s mm^2) = 1e-3 W/mm^2.
W_PER_NMM_S = 1e-3


@dataclass(frozen=True)
class Creepage:
    """Creepages: longitudinal vx (-), lateral vy (-), spin phi_per_mm (1/mm)."""

    vx: float = 0.0
    vy: float = 0.0
    phi_per_mm: float = 0.0

    def __post_init__(self):
        for name in ("vx", "vy", "phi_per_mm"):
            value = getattr(self, name)
            require(isinstance(value, (int, float, np.floating, np.integer)) and bool(np.isfinite(value)),
                    f"creepage.{name}", f"must be a finite number, got {value!r}")

    def is_zero(self) -> bool:
        return self.vx == 0.0 and self.vy == 0.0 and self.phi_per_mm == 0.0

    def about(self, x_mm: float = 0.0, y_mm: float = 0.0) -> "Creepage":
        """The same rigid motion described about the point (x_mm, y_mm) of this creepage's frame (mm).

        The rigid slip / V is w(x, y) = (vx - phi y, vy + phi x) about the origin, so about the point P it is
        (vx - phi y_P, vy + phi x_P) plus the spin phi about P: a patch whose frame has its origin at P (e.g. a
        patch's reference strip y_P off the scene's origin) must be given these creepages.
        """
        return Creepage(float(self.vx - self.phi_per_mm * y_mm), float(self.vy + self.phi_per_mm * x_mm),
                        self.phi_per_mm)


@dataclass(frozen=True)
class EquivalentEllipse:
    """Equivalent ellipse of a patch (Kik–Piotrowski: same area and length/width ratio) and its flexibilities.

    a_mm, b_mm: semi-axes (a in the rolling direction); L1/L2/L3_mm_per_MPa: Kalker's flexibilities.
    """

    a_mm: float
    b_mm: float
    coefficients: CreepCoefficients
    L1_mm_per_MPa: float
    L2_mm_per_MPa: float
    L3_mm_per_MPa: float


@dataclass(frozen=True)
class TangentialResult:
    """FASTSIM solution on a patch. Fields have shape (ny, nx): strips by cells (cell k centred at x_mm[j, k]).

    Forces/moment act on body 1 (see the module docstring): Fx_N, Fy_N (N), Mz_Nmm (N mm, about the patch origin).
    tx_MPa, ty_MPa: tangential tractions; pn_MPa: cell-average normal pressure; slip: slipping cells;
    slip_velocity_mm_s: |slip velocity|; PT_W_per_mm2: frictional power density; WT_N_per_mm: frictional work per
    unit area over one pass, per strip (ny,); WT_field_N_per_mm: the same accumulated from the leading edge up to
    each cell (its last column equals WT_N_per_mm). Areas in mm^2. flexibility, L_mm_per_MPa: the rule and the
    flexibilities (L1, L2, L3) actually used (mm/MPa). method: "fastsim", "fastrip" or "exact" (the solver of the
    result); iterations, residual: the exact solver's sweeps and last relative traction change (0 for a march).
    """

    Fx_N: float
    Fy_N: float
    Mz_Nmm: float
    normal_force_N: float
    friction: float
    speed_mm_s: float
    y_mm: np.ndarray
    dx_mm: np.ndarray
    x_mm: np.ndarray
    pn_MPa: np.ndarray
    tx_MPa: np.ndarray
    ty_MPa: np.ndarray
    slip: np.ndarray
    slip_velocity_mm_s: np.ndarray
    PT_W_per_mm2: np.ndarray
    WT_field_N_per_mm: np.ndarray
    WT_N_per_mm: np.ndarray
    PT_max_W_per_mm2: float
    WT_max_N_per_mm: float
    adhesion_area_mm2: float
    slip_area_mm2: float
    ellipse: EquivalentEllipse
    flexibility: str
    L_mm_per_MPa: tuple[float, float, float]
    method: str = "fastsim"
    iterations: int = 0
    residual: float = 0.0

    __repr__ = short_repr  # the arrays by their shapes

    @property
    def adhesion(self) -> np.ndarray:
        """Cells in adhesion (loaded and not slipping), (ny, nx) bool."""
        return (self.pn_MPa > 0) & ~self.slip

    @property
    def traction_MPa(self) -> np.ndarray:
        """|t| (ny, nx) in MPa."""
        return np.hypot(self.tx_MPa, self.ty_MPa)


def equivalent_ellipse(patch: Patch, G_MPa: float, poisson: float) -> EquivalentEllipse:
    """Kik–Piotrowski equivalent ellipse of the patch (area and length/width kept) and Kalker's flexibilities."""
    area, length, width = patch.area_mm2(), patch.length_mm(), patch.width_mm()
    a = np.sqrt(area / np.pi * length / width)
    b = np.sqrt(area / np.pi * width / length)
    c = creep_coefficients(a / b, poisson)
    L1 = 8.0 * a / (3.0 * G_MPa * c.C11)
    L2 = 8.0 * a / (3.0 * G_MPa * c.C22)
    L3 = np.pi * a * np.sqrt(a / b) / (4.0 * G_MPa * c.C23)
    return EquivalentEllipse(float(a), float(b), c, float(L1), float(L2), float(L3))


FLEXIBILITY_RULES = ("three", "single", "blended")


def flexibilities(ell: EquivalentEllipse, creepage: Creepage, rule: str, G_MPa: float, mu_N: float,
                  ) -> tuple[float, float, float]:
    """Flexibilities (L1, L2, L3) in mm/MPa used by the march, by ``rule`` (mu_N: friction times normal force, N).

    "three": Kalker's L1, L2, L3 (exact linear theory for any combination of creepages; the default).
    "single": one flexibility for all three, CONTACT's combined L = (vx^2 + vy^2 + (f phi)^2) /
    (vx^2/L1 + vy^2/L2 + (f phi)^2/L3), f = 3 pi a / 32 (mm): slip opposite to the traction and the power balance
    exact also with spin; exact linear theory for each creepage alone but not for combinations.
    "blended": CONTACT's blend (1 - w) L_i + w L with w = min(1, r/3), r = |(vx, vy, phi)| / |(vx_s, vy_s, phi_s)|,
    saturation creepages vx_s = mu N/(G c^2 C11), vy_s = mu N/(G c^2 C22), phi_s = mu N/(G c^3 C23), c = sqrt(ab),
    (vector norms mixing 1 and 1/mm exactly as CONTACT, with lengths in mm): three flexibilities at small
    creepage, one at large (source: CONTACT, m_hertz.simpflex).
    """
    L = (ell.L1_mm_per_MPa, ell.L2_mm_per_MPa, ell.L3_mm_per_MPa)
    if rule == "three" or creepage.is_zero():
        return L
    f_phi = 3.0 * np.pi * ell.a_mm / 32.0 * creepage.phi_per_mm
    weights = (creepage.vx**2, creepage.vy**2, f_phi**2)
    single = sum(weights) / sum(w / li for w, li in zip(weights, L))
    if rule == "single":
        return single, single, single
    c = np.sqrt(ell.a_mm * ell.b_mm)
    k = ell.coefficients
    saturation = np.array([mu_N / (G_MPa * c**2 * k.C11), mu_N / (G_MPa * c**2 * k.C22),
                           mu_N / (G_MPa * c**3 * k.C23)])
    norm_sat = float(np.sqrt(np.sum(saturation**2)))
    ratio = np.hypot(np.hypot(creepage.vx, creepage.vy), creepage.phi_per_mm) / norm_sat if norm_sat > 0 else np.inf
    w = min(1.0, ratio / 3.0)
    return tuple(float((1.0 - w) * li + w * single) for li in L)


def _semi_ellipse_primitive(xi):
    """Antiderivative of sqrt(1 - xi^2): (xi sqrt(1 - xi^2) + arcsin xi) / 2."""
    return 0.5 * (xi * np.sqrt(np.clip(1.0 - xi * xi, 0.0, None)) + np.arcsin(xi))


@functools.lru_cache(maxsize=64)
def _semi_ellipse_cell_means(nx: int) -> np.ndarray:
    """Mean of sqrt(1 - xi^2) over the nx equal cells of xi from +1 down to -1 (exact integrals; read-only)."""
    edges = 1.0 - 2.0 * np.arange(nx + 1) / nx
    edges[-1] = -1.0
    prim = _semi_ellipse_primitive(edges)
    means = (prim[:-1] - prim[1:]) / (edges[:-1] - edges[1:])
    means.flags.writeable = False
    return means


def simplified_theory_fx_ratio(kappa: float) -> float:
    """|Fx| / (mu N) of the continuum simplified theory, one flexibility L, pure longitudinal creepage (exact).

    Holds for every patch with p_peak(y) proportional to x_l(y): Hertz ellipses and all Kik–Piotrowski patches
    (eq. 11). Every strip is then self-similar with kappa = |vx| x_l / (L mu p_peak): traction kappa mu p_peak
    (1 - xi) in adhesion from the leading edge xi = x/x_l = 1 down to xi* = (kappa^2 - 1)/(kappa^2 + 1), where the
    line meets the bound mu p_peak sqrt(1 - xi^2); Coulomb slip behind. Small kappa: 4 kappa / pi (Kalker's
    linear theory for L = L1); kappa -> infinity: 1. A reference for the discretised march (tests, benchmark).
    """
    k = float(kappa)
    xs = (k * k - 1.0) / (k * k + 1.0)
    adhesion = 0.5 * k * (1.0 - xs) ** 2
    slip = float(_semi_ellipse_primitive(xs) - _semi_ellipse_primitive(-1.0))
    return (adhesion + slip) / (0.5 * np.pi)


@kernel()
def _march(x_lead, x_centre, y, pn, nx, L1, L2, rx, ry, spin, mu):  # pragma: no cover - compiled
    """FASTSIM march on all strips; rx = vx/L1, ry = vy/L2, spin = phi/L3; strip j spans x_centre[j] +- x_lead[j].

    Returns, per cell (ny, nx): tractions tx, ty (MPa) at the cell centre; |slip displacement| (mm) and frictional
    work per unit area (N/mm) accumulated over the cell's length (each full step between two cell centres is
    shared equally by the two cells; |t| trapezoid-averaged over the step); the slip flag of the centre. The last
    cell also receives the exit release (traction left at the last centre dropping to zero at the trailing edge,
    where the bound vanishes).
    """
    ny = x_lead.size
    tx = np.zeros((ny, nx))
    ty = np.zeros((ny, nx))
    du = np.zeros((ny, nx))
    work = np.zeros((ny, nx))
    slip = np.zeros((ny, nx), dtype=np.bool_)
    for j in range(ny):
        dx = 2.0 * x_lead[j] / nx
        wx = rx - spin * y[j]
        px = 0.0
        py = 0.0
        for k in range(nx):
            step = 0.5 * dx if k == 0 else dx
            x_mid = x_centre[j] + (x_lead[j] - 0.25 * dx if k == 0 else x_lead[j] - k * dx)
            hx = px - wx * step
            hy = py - (ry + spin * x_mid) * step
            t_prev = np.sqrt(px * px + py * py)
            bound = mu * pn[j, k]
            mag = np.sqrt(hx * hx + hy * hy)
            if mag > bound:
                scale = bound / mag
                px = hx * scale
                py = hy * scale
                slip[j, k] = True
                d = np.sqrt((L1 * (px - hx)) ** 2 + (L2 * (py - hy)) ** 2)
                w = 0.5 * (t_prev + bound) * d
                if k == 0:  # the first half step lies in cell 0
                    du[j, 0] += d
                    work[j, 0] += w
                else:  # step k straddles the trailing half of cell k-1 and the leading half of cell k
                    du[j, k - 1] += 0.5 * d
                    du[j, k] += 0.5 * d
                    work[j, k - 1] += 0.5 * w
                    work[j, k] += 0.5 * w
            else:
                px = hx
                py = hy
            tx[j, k] = px
            ty[j, k] = py
        d = np.sqrt((L1 * px) ** 2 + (L2 * py) ** 2)  # exit release in the trailing half of the last cell
        du[j, nx - 1] += d
        work[j, nx - 1] += 0.5 * np.sqrt(px * px + py * py) * d
    return tx, ty, du, work, slip


def _check_inputs(patch, creepage, G_MPa, poisson, friction, speed_mm_s, nx):
    require(isinstance(patch, Patch), "patch", f"must be a contact.normal.patch.Patch, got {type(patch).__name__}")
    require(patch.n_strips > 0 and patch.normal_force_N() > 0.0, "patch", "empty patch (no normal force)")
    require(isinstance(creepage, Creepage), "creepage", "must be a contact.tangential.fastsim.Creepage")
    require(bool(np.isfinite(G_MPa)) and G_MPa > 0, "G_MPa", f"shear modulus must be > 0, got {G_MPa!r}")
    require(bool(np.isfinite(poisson)) and 0.0 <= poisson <= 0.5, "poisson", f"must lie in [0, 0.5], got {poisson!r}")
    require(bool(np.isfinite(friction)) and friction >= 0, "friction", f"must be a finite number >= 0, got {friction!r}")
    require(bool(np.isfinite(speed_mm_s)) and speed_mm_s > 0, "speed_mm_s", f"must be > 0, got {speed_mm_s!r}")
    require(isinstance(nx, (int, np.integer)) and nx >= 2, "nx", f"cells per strip must be an integer >= 2, got {nx!r}")


@dataclass(frozen=True)
class StripCells:
    """The cells of a strip patch shared by the strip methods (FASTSIM, FaStrip): nx cells per strip from the
    leading edge. x_mm (ny, nx) cell centres, dx_mm (ny,) cell lengths, centre_mm (ny,) strip centres (mm),
    pn_MPa (ny, nx) cell pressures (MPa); creepage, friction, speed_mm_s (mm/s): the inputs; flexibility:
    FASTSIM's flexibility rule."""

    x_mm: np.ndarray
    dx_mm: np.ndarray
    centre_mm: np.ndarray
    pn_MPa: np.ndarray
    creepage: Creepage
    friction: float
    speed_mm_s: float
    flexibility: str = "three"

    __repr__ = short_repr  # the arrays by their shapes

    def result(self, patch: Patch, tx, ty, slip, slip_velocity_mm_s, work, ell: EquivalentEllipse, method: str,
               flex: tuple[float, float, float], iterations: int = 0, residual: float = 0.0) -> TangentialResult:
        """The TangentialResult of per-cell tractions (MPa), slip flags, |slip velocity| (mm/s) and frictional work
        per unit area (N/mm) of each cell over one pass."""
        cell_area = (self.dx_mm * patch.grid_mm)[:, None]
        WT_field = np.cumsum(work, axis=1)
        PT = W_PER_NMM_S * self.speed_mm_s * work / self.dx_mm[:, None]
        slip_area = float(np.sum(slip * cell_area))
        x, y = self.x_mm, patch.y_mm
        return TangentialResult(
            Fx_N=float(np.sum(tx * cell_area)), Fy_N=float(np.sum(ty * cell_area)),
            Mz_Nmm=float(np.sum((x * ty - y[:, None] * tx) * cell_area)),
            normal_force_N=patch.normal_force_N(), friction=float(self.friction), speed_mm_s=float(self.speed_mm_s),
            y_mm=y, dx_mm=self.dx_mm, x_mm=x, pn_MPa=self.pn_MPa, tx_MPa=tx, ty_MPa=ty, slip=slip,
            slip_velocity_mm_s=slip_velocity_mm_s, PT_W_per_mm2=PT, WT_field_N_per_mm=WT_field,
            WT_N_per_mm=WT_field[:, -1].copy(), PT_max_W_per_mm2=float(PT.max()),
            WT_max_N_per_mm=float(WT_field.max()), adhesion_area_mm2=patch.area_mm2() - slip_area,
            slip_area_mm2=slip_area, ellipse=ell, flexibility=self.flexibility if method == "fastsim" else method,
            L_mm_per_MPa=flex, method=method, iterations=int(iterations), residual=float(residual))


def strip_cells(patch: Patch, creepage: Creepage, G_MPa: float, poisson: float, friction: float,
                speed_mm_s: float, nx: int, pressure_cells_MPa: np.ndarray | None = None,
                strip_centre_mm: np.ndarray | None = None, flexibility: str = "three") -> StripCells:
    """Validated inputs of a strip method and its cells (see :func:`solve_tangential` for the arguments)."""
    _check_inputs(patch, creepage, G_MPa, poisson, friction, speed_mm_s, nx)
    ny = patch.n_strips
    xl = patch.x_lead_mm
    dx = 2.0 * xl / nx
    if strip_centre_mm is None:
        xc = np.zeros(ny)
    else:
        xc = np.asarray(strip_centre_mm, dtype=float)
        require(xc.shape == (ny,) and bool(np.all(np.isfinite(xc))), "strip_centre_mm",
                f"needs {ny} finite values (one x per strip, mm)")
    x = xc[:, None] + xl[:, None] * (1.0 - (2.0 * np.arange(nx) + 1.0) / nx)[None, :]
    if pressure_cells_MPa is None:
        pn = patch.p_peak_MPa[:, None] * _semi_ellipse_cell_means(nx)[None, :]
    else:                                   # a given pressure shape per strip (the exact normal solver's)
        pn = np.asarray(pressure_cells_MPa, dtype=float)
        require(pn.shape == (ny, nx) and bool(np.all(np.isfinite(pn)) and np.all(pn >= 0)), "pressure_cells_MPa",
                f"needs ({ny}, {nx}) finite values >= 0 (strips x cells from the leading edge)")
    return StripCells(x, dx, xc, pn, creepage, float(friction), float(speed_mm_s), flexibility)


def solve_tangential(patch: Patch, creepage: Creepage, G_MPa: float, poisson: float, friction: float,
                     speed_mm_s: float = 1000.0, nx: int = 60, flexibility: str = "three",
                     pressure_cells_MPa: np.ndarray | None = None,
                     strip_centre_mm: np.ndarray | None = None) -> TangentialResult:
    """FASTSIM on the patch's strips with ``nx`` cells per strip; see the module docstring for conventions.

    G_MPa: shear modulus (E / (2 (1 + nu)), both bodies of one steel); poisson: Poisson's ratio; friction: Coulomb
    coefficient mu (>= 0); speed_mm_s: rolling speed V (only scales slip velocities and P_T); flexibility: "three"
    (default), "single" or "blended", see :func:`flexibilities`; pressure_cells_MPa: optional (ny, nx) cell
    pressures of each strip from the leading edge (MPa) replacing the semi-elliptic cell means (the exact normal
    solver's shape, :func:`contact.normal.exact.fastsim_pressure`); strip_centre_mm: optional (ny,) x of each
    strip's centre (mm; default 0: strips symmetric about x = 0, as Kik–Piotrowski's are; the exact solver's rolling
    mode shifts them towards the leading edge, :func:`contact.normal.exact.strip_centres`). The centre enters the
    spin slip, Mz and the cell coordinates ``x_mm``. The spin acts about the patch frame's origin (y = 0, x = 0):
    creepages given about another point are moved with :meth:`Creepage.about`
    (:func:`contact.tangential.spin_centre.solve_about_centroid` takes the spin about the patch's centroid).
    """
    require(flexibility in FLEXIBILITY_RULES, "flexibility", f"must be one of {FLEXIBILITY_RULES}, got {flexibility!r}")
    cells = strip_cells(patch, creepage, G_MPa, poisson, friction, speed_mm_s, nx, pressure_cells_MPa,
                        strip_centre_mm, flexibility)
    ell = equivalent_ellipse(patch, G_MPa, poisson)
    L1, L2, L3 = flexibilities(ell, creepage, flexibility, G_MPa, friction * patch.normal_force_N())
    ny, xl, xc, pn, dx = patch.n_strips, patch.x_lead_mm, cells.centre_mm, cells.pn_MPa, cells.dx_mm
    if creepage.is_zero():
        tx = np.zeros((ny, nx))
        ty, du, work = tx.copy(), tx.copy(), tx.copy()
        slip = np.zeros((ny, nx), dtype=bool)
    else:
        tx, ty, du, work, slip = _march(xl, xc, patch.y_mm, pn, int(nx), L1, L2, creepage.vx / L1,
                                        creepage.vy / L2, creepage.phi_per_mm / L3, float(friction))
    return cells.result(patch, tx, ty, slip, du * (speed_mm_s / dx[:, None]), work, ell, "fastsim", (L1, L2, L3))


__all__ = ["FLEXIBILITY_RULES", "Creepage", "StripCells", "strip_cells", "EquivalentEllipse", "TangentialResult",
           "equivalent_ellipse", "flexibilities", "simplified_theory_fx_ratio", "solve_tangential"]
