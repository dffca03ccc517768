"""Prandtl-body surface layer: many independent elements with slider state (paper sections 2–3, eqs. 1–8).

One element (paper Fig. 1) = N springs in parallel; springs 1..N-1 each in series with a dry-friction slider, spring
N alone. With the slip s_i of slider i (mm) and the element displacement u (mm) the normal stress is

    p = sum_{i<N} k_i (u - s_i) + k_N u,     |k_i (u - s_i)| <= T_0i      (eqs. 1–3)

so the force in branch i is k_i * clip(u - s_i, -rho e_i, e_i) with the elastic half-width e_i = T_0i / k_i (mm) and
the element's reverse factor rho (the reverse threshold over the forward one; 1: the paper's symmetric slider).
A monotonic move from the current state to a target pressure is therefore piecewise linear in u with break points
at s_i +- e_i: :meth:`PrandtlLayer.move_to` finds the segment and solves it exactly (no iteration), then updates
the slips; this gives the EXACT element behaviour for any load history (rho = 1, Masing: an unloading drop that moves branch i by more
than 2 e_i makes slider i slip backwards; in general (1 + rho) e_i). The dissipated energy per unit area, sum T_0i |delta s_i| (N/mm =
N mm/mm^2), is accumulated per point.

Eq. (8) (unloading parallel to the first segment) is exact only while no slider slips backwards on unloading, i.e.
for a virgin element loaded to p_0 <= (1 + rho) p_2 (unloading by Delta p retraces (1 + rho) times the backbone at
Delta p/(1 + rho)); for larger p_0 the exact residual is u(p_0) - (1 + rho) u(p_0/(1 + rho)) < eq. (8)
(:meth:`wrlayer.characteristic.Characteristic.unloading_residual`). See ``tests/contact/test_prandtl_layer.py``.

Representation: arrays (n_points, M) with M = the largest number of sliders over the points. Points whose
characteristic has fewer segments are padded with branches of ZERO stiffness and zero half-width: such a branch
carries no force, has no break point that changes a slope, and dissipates nothing, so padding changes no result.

Units: mm, MPa (N/mm^2), stiffness N/mm^3, dissipated energy N/mm (= N mm / mm^2).
"""

from __future__ import annotations

import copy

from dataclasses import dataclass, replace
from typing import Callable, Sequence

import numpy as np

from wrlayer.characteristic import Characteristic
from wrlayer.errors import InputError
from wrlayer.jit import kernel
from wrlayer.rolling_law import RollingLaw


@kernel()
def _element_pressure(x, slip, k, e, k_last, rho):
    """p = sum_i k_i clip(x - s_i, -rho e_i, e_i) + k_N x for one element at displacement x (MPa)."""
    p = k_last * x
    for i in range(slip.size):
        p += k[i] * min(max(x - slip[i], -rho * e[i]), e[i])
    return p


@kernel()
def _pressures(u, slip, k, e, k_last, rho):
    """Current pressure of each element (MPa)."""
    out = np.empty(u.size)
    for j in range(u.size):
        out[j] = _element_pressure(u[j], slip[j], k[j], e[j], k_last[j], rho[j])
    return out


@kernel()
def move_elements(u, slip, k, e, k_last, p_target, rho):
    """Exact monotonic move of elements (u (n,), slips (n, m)) to p_target (n,): (u, slips, dissipation).

    Unloading is loading of the mirrored element (u, s, p) -> (-u, -s, -p), whose forward half-widths are the
    reverse ones rho e_i. On loading, branch i carries k_i min(u - s_i, f_i) (f_i the forward half-width), so p(u)
    is piecewise linear with break points s_i + f_i: walk the break points in order until the target pressure is
    reached, then slip the sliders passed.
    """
    n, m = slip.shape
    u_out = np.empty(n)
    s_out = np.empty((n, m))
    diss = np.zeros(n)
    for j in range(n):
        p_cur = _element_pressure(u[j], slip[j], k[j], e[j], k_last[j], rho[j])
        sign = 1.0 if p_target[j] >= p_cur else -1.0
        scale = 1.0 if sign > 0.0 else rho[j]  # forward half-width over e_i in this direction
        x = sign * u[j]
        pt = sign * p_target[j]
        p = sign * p_cur
        while True:
            slope = k_last[j]
            b_next = np.inf
            for i in range(m):
                b = sign * slip[j, i] + scale * e[j, i]
                if b > x and k[j, i] > 0.0:
                    slope += k[j, i]
                    if b < b_next:
                        b_next = b
            if b_next == np.inf or p + slope * (b_next - x) >= pt:
                x += (pt - p) / slope
                break
            p += slope * (b_next - x)
            x = b_next
        u_out[j] = sign * x
        for i in range(m):
            sp = sign * slip[j, i]
            sn = max(sp, x - scale * e[j, i])
            diss[j] += k[j, i] * scale * e[j, i] * (sn - sp)
            s_out[j, i] = sign * sn
    return u_out, s_out, diss


@kernel()
def _yield_pressures(u, slip, k, e, k_last, rho):
    """Pressure of each element when its first stuck slider reaches its threshold on loading (inf: none)."""
    n, m = slip.shape
    out = np.full(n, np.inf)
    for j in range(n):
        first = np.inf
        for i in range(m):
            if k[j, i] > 0.0:
                first = min(first, max(slip[j, i] + e[j, i], u[j]))
        if first < np.inf:
            out[j] = _element_pressure(first, slip[j], k[j], e[j], k_last[j], rho[j])
    return out


@dataclass
class PrandtlLayer:
    """Prandtl elements at points ``y_mm`` (n,) of a lateral strip grid, with their state.

    Parameters: ``k_N_per_mm3`` (n, M) slider-branch stiffnesses k_i, ``half_width_mm`` (n, M) e_i = T_0i/k_i,
    ``k_last_N_per_mm3`` (n,) the spring without slider (k_N). State: ``u_mm`` (n,) displacement (positive into the
    body), ``slip_mm`` (n, M) slider slips, ``dissipated_energy_N_per_mm`` (n,) accumulated friction work.
    ``rolling_law``: what a rolling pass leaves relative to the static residual (:mod:`wrlayer.rolling_law`, from
    the layer table; None: none), used by the passes' "rolling" memory rule (:mod:`contact.passes.passes`).
    ``reverse_factor`` (n,): each element's reverse slider threshold over the forward one (-; default 1, the paper's
    element). ``lateral_curvature_per_mm`` (n,): the body's own lateral curvature 1/R at each point (1/mm, convex
    > 0; default 0), with which a rolling law with convexity nodes is read (b / (2 R), b the patch's lateral
    semi-axis).
    """

    y_mm: np.ndarray
    k_N_per_mm3: np.ndarray
    half_width_mm: np.ndarray
    k_last_N_per_mm3: np.ndarray
    u_mm: np.ndarray = None
    slip_mm: np.ndarray = None
    dissipated_energy_N_per_mm: np.ndarray = None
    name: str = "layer"
    rolling_law: RollingLaw | None = None
    reverse_factor: np.ndarray = None
    lateral_curvature_per_mm: np.ndarray = None

    def __post_init__(self):
        self.y_mm = np.atleast_1d(np.asarray(self.y_mm, dtype=float))
        n = self.y_mm.size
        self.k_N_per_mm3 = np.ascontiguousarray(np.asarray(self.k_N_per_mm3, dtype=float).reshape(n, -1))
        self.half_width_mm = np.ascontiguousarray(np.asarray(self.half_width_mm, dtype=float).reshape(n, -1))
        self.k_last_N_per_mm3 = np.ascontiguousarray(np.asarray(self.k_last_N_per_mm3, dtype=float).reshape(n))
        if not (np.all(np.isfinite(self.y_mm)) and np.all(np.diff(self.y_mm) > 0)):
            raise InputError(self.name, "point positions y_mm must be finite and strictly increasing")
        if self.half_width_mm.shape != self.k_N_per_mm3.shape:
            raise InputError(self.name, "k_N_per_mm3 and half_width_mm must have the same shape")
        if (np.any(self.k_N_per_mm3 < 0) or np.any(self.half_width_mm < 0) or np.any(self.k_last_N_per_mm3 <= 0)
                or not np.all(np.isfinite(self.k_N_per_mm3)) or not np.all(np.isfinite(self.half_width_mm))):
            raise InputError(self.name, "stiffnesses and slider half-widths must be finite, >= 0 (last spring > 0)")
        self.u_mm = np.zeros(n) if self.u_mm is None else np.asarray(self.u_mm, dtype=float).reshape(n).copy()
        self.slip_mm = (np.zeros_like(self.k_N_per_mm3) if self.slip_mm is None
                        else np.asarray(self.slip_mm, dtype=float).reshape(self.k_N_per_mm3.shape).copy())
        self.dissipated_energy_N_per_mm = (np.zeros(n) if self.dissipated_energy_N_per_mm is None else
                                           np.asarray(self.dissipated_energy_N_per_mm, dtype=float).reshape(n).copy())
        self.reverse_factor = np.ascontiguousarray(np.broadcast_to(
            np.asarray(1.0 if self.reverse_factor is None else self.reverse_factor, dtype=float), (n,)))
        if not (np.all(np.isfinite(self.reverse_factor)) and np.all(self.reverse_factor > 0)):
            raise InputError(self.name, "reverse factors must be finite and > 0")
        self.lateral_curvature_per_mm = np.ascontiguousarray(np.broadcast_to(np.asarray(
            0.0 if self.lateral_curvature_per_mm is None else self.lateral_curvature_per_mm, dtype=float), (n,)))
        if not np.all(np.isfinite(self.lateral_curvature_per_mm)):
            raise InputError(self.name, "lateral curvatures must be finite")

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_characteristics(cls, characteristics: Sequence[Characteristic], y_mm, name: str = "layer",
                             rolling_law: RollingLaw | None = None, lateral_curvature_per_mm=None):
        """One characteristic per point (padded to a common number of sliders with zero branches), each with its
        reverse factor; ``lateral_curvature_per_mm``: per point (1/mm, None: 0)."""
        y = np.atleast_1d(np.asarray(y_mm, dtype=float))
        if len(characteristics) != y.size:
            raise InputError(name, f"{len(characteristics)} characteristics for {y.size} points")
        m = max(c.n_segments for c in characteristics) - 1
        k = np.zeros((y.size, m))
        e = np.zeros((y.size, m))
        k_last = np.empty(y.size)
        for j, c in enumerate(characteristics):
            par = c.to_parameters()
            ns = par.n_segments - 1
            k[j, :ns] = par.k_N_per_mm3[:-1]
            e[j, :ns] = par.break_displacements_mm
            k_last[j] = par.k_N_per_mm3[-1]
        rho = np.array([c.reverse_factor for c in characteristics], dtype=float)
        return cls(y, k, e, k_last, name=name, rolling_law=rolling_law, reverse_factor=rho,
                   lateral_curvature_per_mm=lateral_curvature_per_mm)

    @classmethod
    def uniform(cls, characteristic: Characteristic, y_mm, name: str = "layer",
                rolling_law: RollingLaw | None = None) -> "PrandtlLayer":
        """The same characteristic at every point ``y_mm``."""
        y = np.atleast_1d(np.asarray(y_mm, dtype=float))
        par = characteristic.to_parameters()
        k = np.broadcast_to(par.k_N_per_mm3[:-1], (y.size, par.n_segments - 1))
        e = np.broadcast_to(par.break_displacements_mm, k.shape)
        return cls(y, k, e, np.full(y.size, par.k_N_per_mm3[-1]), name=name, rolling_law=rolling_law,
                   reverse_factor=characteristic.reverse_factor)

    @classmethod
    def along(cls, characteristic_at: Callable[[float], Characteristic], y_mm, name: str = "layer",
              rolling_law: RollingLaw | None = None):
        """Per-point characteristics from a function of y (e.g. ``LayerTable.characteristic_at``)."""
        y = np.atleast_1d(np.asarray(y_mm, dtype=float))
        return cls.from_characteristics([characteristic_at(float(v)) for v in y], y, name=name,
                                        rolling_law=rolling_law)

    def _with(self, u_mm, slip_mm, energy) -> "PrandtlLayer":
        """A shallow copy (parameters shared, they are never modified) with the given state arrays."""
        out = copy.copy(self)
        out.u_mm, out.slip_mm, out.dissipated_energy_N_per_mm = u_mm, slip_mm, energy
        return out

    def copy(self) -> "PrandtlLayer":
        return self._with(self.u_mm.copy(), self.slip_mm.copy(), self.dissipated_energy_N_per_mm.copy())

    def relaxed(self) -> "PrandtlLayer":
        """A copy with unstressed sliders and zero displacement (the paper's mode between passes; energy kept)."""
        return self._with(np.zeros_like(self.u_mm), np.zeros_like(self.slip_mm),
                          self.dissipated_energy_N_per_mm.copy())

    def state_dict(self) -> dict:
        """The state as plain lists (JSON-serialisable); restore with :meth:`with_state`."""
        return {"u_mm": self.u_mm.tolist(), "slip_mm": self.slip_mm.tolist(),
                "dissipated_energy_N_per_mm": self.dissipated_energy_N_per_mm.tolist()}

    def with_state(self, state: dict) -> "PrandtlLayer":
        return replace(self, u_mm=np.asarray(state["u_mm"], dtype=float),
                       slip_mm=np.asarray(state["slip_mm"], dtype=float),
                       dissipated_energy_N_per_mm=np.asarray(state["dissipated_energy_N_per_mm"], dtype=float))

    # ------------------------------------------------------------------ evaluation
    @property
    def dissipated_energy(self) -> np.ndarray:
        """Accumulated friction work per element (N/mm = N mm/mm^2), >= 0."""
        return self.dissipated_energy_N_per_mm

    @property
    def n_points(self) -> int:
        return int(self.y_mm.size)

    @property
    def pressure_MPa(self) -> np.ndarray:
        """Current normal stress of each element (MPa)."""
        return _pressures(self.u_mm, self.slip_mm, self.k_N_per_mm3, self.half_width_mm, self.k_last_N_per_mm3,
                          self.reverse_factor)

    def pressure_roundoff_MPa(self) -> np.ndarray:
        """Size of the rounding error of :attr:`pressure_MPa` per element (MPa): the pressure is a sum of branch
        stresses k_i (u - s_i) + k_N u, so its error grows with k_i (|u| + |s_i|), not with p itself."""
        u = np.abs(self.u_mm)
        terms = np.sum(self.k_N_per_mm3 * (u[:, None] + np.abs(self.slip_mm)), axis=-1) + self.k_last_N_per_mm3 * u
        return 1e-12 * terms

    def is_unloaded(self) -> bool:
        """True when every element is at p = 0 up to rounding (|p| <= 1e-9 MPa + :meth:`pressure_roundoff_MPa`).

        After an exact :meth:`unload` of a deep hardened state p is zero only up to the rounding of u - s_i:
        e.g. u = 1.57 mm with k_i = 3e6 N/mm^3 leaves |p| = 1.7e-9 MPa (stress seed 1921)."""
        return bool(np.all(np.abs(self.pressure_MPa) <= 1e-9 + self.pressure_roundoff_MPa()))

    def _solve(self, p_target, index=None):
        """Exact monotonic move of points ``index`` to ``p_target``: (u, new slips, dissipation increment)."""
        sl = slice(None) if index is None else index
        k, e, kl, rho = self.k_N_per_mm3[sl], self.half_width_mm[sl], self.k_last_N_per_mm3[sl], self.reverse_factor[sl]
        u0, s0 = self.u_mm[sl], self.slip_mm[sl]
        p_target = np.asarray(p_target, dtype=float)
        if not np.all(np.isfinite(p_target)):
            raise InputError(f"{self.name} target pressure", "must be finite")
        if index is None and p_target.shape == u0.shape:       # the common case: one target per element
            return move_elements(u0, s0, k, e, kl, np.ascontiguousarray(p_target), rho)
        shape = np.broadcast_shapes(np.shape(u0), p_target.shape)
        m = k.shape[-1]
        flat = [np.ascontiguousarray(np.broadcast_to(a, shape).reshape(-1)) for a in (u0, kl, p_target, rho)]
        size = int(np.prod(shape))
        mats = [np.ascontiguousarray(np.broadcast_to(a, shape + (m,)).reshape(size, m)) for a in (s0, k, e)]
        u, s, d = move_elements(flat[0], mats[0], mats[1], mats[2], flat[1], flat[2], flat[3])
        return u.reshape(shape), s.reshape(shape + (m,)), d.reshape(shape)

    def displacement_at(self, p_MPa, index=None) -> np.ndarray:
        """Displacement (mm) after a monotonic move from the current state to ``p_MPa`` (no state change)."""
        return self._solve(p_MPa, index)[0]

    def move_to(self, p_MPa) -> np.ndarray:
        """Move every element monotonically to the pressure ``p_MPa`` (per point or scalar); returns u (mm)."""
        u, s, d = self._solve(p_MPa)
        self.u_mm, self.slip_mm = u, s
        self.dissipated_energy_N_per_mm = self.dissipated_energy_N_per_mm + d
        return u.copy()

    def load_to(self, p_MPa) -> np.ndarray:
        """Monotonic loading from the current state to ``p_MPa`` (MPa, per point); returns u (mm)."""
        return self.move_to(p_MPa)

    def unload(self) -> np.ndarray:
        """Unload every element to p = 0 (exact, with reverse slip where it occurs); returns the residual u (mm)."""
        return self.move_to(np.zeros(self.n_points))

    def yield_pressure_MPa(self, index: np.ndarray | None = None) -> np.ndarray:
        """Pressure at which the first stuck slider starts to slip on further loading from the current state
        (inf for elements without sliders); of the elements ``index`` only (integer array) when given."""
        if index is None:
            return _yield_pressures(self.u_mm, self.slip_mm, self.k_N_per_mm3, self.half_width_mm,
                                    self.k_last_N_per_mm3, self.reverse_factor)
        return _yield_pressures(self.u_mm[index], self.slip_mm[index], self.k_N_per_mm3[index],
                                self.half_width_mm[index], self.k_last_N_per_mm3[index], self.reverse_factor[index])

    def loading_curve(self, index: int) -> tuple[np.ndarray, np.ndarray, float]:
        """Monotonic loading curve of element ``index`` from its current state.

        Returns (p_knots MPa, u_knots mm, final slope N/mm^3): piecewise linear, starting at the current (p, u);
        beyond the last knot u grows with slope 1/final slope. Knots may repeat (sliders already at threshold).
        """
        k, e = self.k_N_per_mm3[index], self.half_width_mm[index]
        u0, s0, kl = self.u_mm[index], self.slip_mm[index], self.k_last_N_per_mm3[index]
        knots = np.concatenate([[u0], np.sort(np.maximum(s0 + e, u0))])
        p = np.sum(k * np.clip(knots[:, None] - s0, -self.reverse_factor[index] * e, e), axis=-1) + kl * knots
        return p, knots, float(kl)

    def stiffness_at(self, p_MPa, index=None) -> np.ndarray:
        """Tangent stiffness dp/du (N/mm^3) on loading from the current state at pressure ``p_MPa``."""
        sl = slice(None) if index is None else index
        u = self.displacement_at(p_MPa, index)
        brk = self.slip_mm[sl] + self.half_width_mm[sl]
        return self.k_last_N_per_mm3[sl] + np.sum(self.k_N_per_mm3[sl] * (brk > u[..., None]), axis=-1)


@dataclass
class LayerPair:
    """The layers of the two bodies; in the normal direction they act in series (same p, displacements add).

    ``wheel`` and ``rail`` are per-body layers; ``combined`` is one layer standing for both bodies together (the
    paper's Fig. 5 characteristic enters eq. (13) that way). Any of them may be None; all given layers are used.
    """

    wheel: PrandtlLayer | None = None
    rail: PrandtlLayer | None = None
    combined: PrandtlLayer | None = None

    def bodies(self) -> dict[str, PrandtlLayer]:
        """The layers that are present, by name ("wheel", "rail", "combined")."""
        return {n: lay for n, lay in (("wheel", self.wheel), ("rail", self.rail), ("combined", self.combined))
                if lay is not None}

    def copy(self) -> "LayerPair":
        return LayerPair(*(None if lay is None else lay.copy() for lay in (self.wheel, self.rail, self.combined)))

    def relaxed(self) -> "LayerPair":
        return LayerPair(*(None if lay is None else lay.relaxed() for lay in (self.wheel, self.rail, self.combined)))
