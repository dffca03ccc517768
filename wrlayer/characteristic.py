"""Monotonic characteristic of a Prandtl-body element and its parameters (paper section 2–3, eqs. 4–8).

The characteristic is the piecewise-linear, concave relation between the normal stress p (MPa) and the element's
normal displacement u (mm) under monotonically growing p (paper Fig. 2): end points (u_i, p_i), i = 1..N+1, with
u_1 = p_1 = 0 and slopes S_1 > S_2 > ... > S_N > 0 (N/mm^3). Beyond the last point the last segment continues
(spring N alone: linear hardening). The element's parameters are the spring stiffnesses k_i (N/mm^3) and the
slider break stresses T_0i (MPa):

    (4) k_N = S_N      (5) k_i = S_i - S_{i+1}      (6) T_0i = k_i u_{i+1}      (i = 1..N-1)

Residual displacement of a virgin element unloaded from the peak p_0 (eq. 8): u_p = u(p_0) - p_0 / S_1.

Unloading branch. The paper's sliders are symmetric (Masing): slider i slips back at -T_0i, so an element unloaded
from p_0 follows twice the backbone at half the drop, and eq. (8) holds only up to p_0 = 2 p_2. A slider may slip
back at -rho T_0i instead (``reverse_factor`` rho > 0; rho = 1 is the paper's element): the unloading drop of a
virgin element then follows (1 + rho) u(Delta p / (1 + rho)), so eq. (8) holds up to p_0 = (1 + rho) p_2 and the
exact residual is u(p_0) - (1 + rho) u(p_0 / (1 + rho)) (:meth:`Characteristic.unloading_residual`). The
calibration fits rho to the FEM's residual dents (docs/calibration-method.md, "Unloading").
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from wrlayer.errors import InputError

_REL_TOL = 1e-12
#: Bounds of the reverse threshold factor rho (-): the reverse slider threshold over the forward one.
REVERSE_FACTOR_RANGE = (0.1, 1000.0)


@dataclass(frozen=True)
class PrandtlParameters:
    """Spring stiffnesses k (N,) in N/mm^3 and slider break stresses T0 (N-1,) in MPa (eqs. 4–6)."""

    k_N_per_mm3: np.ndarray
    T0_MPa: np.ndarray

    @property
    def n_segments(self) -> int:
        return int(np.asarray(self.k_N_per_mm3).size)

    @property
    def break_displacements_mm(self) -> np.ndarray:
        """u_{i+1} = T_0i / k_i, the displacement at which slider i breaks (mm)."""
        return np.asarray(self.T0_MPa, dtype=float) / np.asarray(self.k_N_per_mm3, dtype=float)[:-1]


@dataclass(frozen=True)
class Characteristic:
    """Piecewise-linear concave p(u) through (u_mm[i], p_MPa[i]); u_mm[0] = p_MPa[0] = 0. Units mm, MPa.
    ``reverse_factor``: the element's reverse slider threshold over the forward one (rho, -; 1: the paper's
    symmetric, Masing element; see the module docstring)."""

    u_mm: np.ndarray
    p_MPa: np.ndarray
    name: str = "layer characteristic"
    reverse_factor: float = 1.0

    def __post_init__(self):
        u = np.asarray(self.u_mm, dtype=float).ravel()
        p = np.asarray(self.p_MPa, dtype=float).ravel()
        object.__setattr__(self, "u_mm", u)
        object.__setattr__(self, "p_MPa", p)
        what = self.name
        rho = self.reverse_factor
        lo, hi = REVERSE_FACTOR_RANGE
        if isinstance(rho, bool) or not isinstance(rho, (int, float, np.floating)) or not lo <= float(rho) <= hi:
            raise InputError(what, f"reverse_factor must be a number in [{lo:g}, {hi:g}], got {rho!r}")
        object.__setattr__(self, "reverse_factor", float(rho))
        if u.size != p.size:
            raise InputError(what, f"u_mm has {u.size} points but p_MPa has {p.size}")
        if u.size < 2:
            raise InputError(what, "needs at least 2 points (one segment)")
        if not (np.all(np.isfinite(u)) and np.all(np.isfinite(p))):
            raise InputError(what, "contains NaN or infinite values")
        if u[0] != 0.0 or p[0] != 0.0:
            raise InputError(what, f"must start at (u, p) = (0, 0), got ({u[0]:g}, {p[0]:g})")
        if np.any(np.diff(u) <= 0):
            i = int(np.argmax(np.diff(u) <= 0))
            raise InputError(what, f"u_mm must be strictly increasing: u[{i}] = {u[i]:.6g} >= u[{i + 1}] = "
                             f"{u[i + 1]:.6g} mm")
        if np.any(np.diff(p) <= 0):
            i = int(np.argmax(np.diff(p) <= 0))
            raise InputError(what, f"p_MPa must be strictly increasing (slopes must be positive): p[{i}] = "
                             f"{p[i]:.6g} >= p[{i + 1}] = {p[i + 1]:.6g} MPa")
        s = np.diff(p) / np.diff(u)
        bad = np.diff(s) >= -_REL_TOL * s[:-1]
        if np.any(bad):
            i = int(np.argmax(bad))  # the first offending pair of segments (a long array would be unreadable)
            raise InputError(what, "slopes must strictly decrease (the characteristic must be concave); "
                             f"segment {i + 2} (from u = {u[i + 1]:.6g} mm) has slope {s[i + 1]:.6g} N/mm^3 >= "
                             f"{s[i]:.6g} N/mm^3 of segment {i + 1}")

    # ------------------------------------------------------------------ construction
    @classmethod
    def linear(cls, stiffness_N_per_mm3: float, u_end_mm: float = 1.0, name: str = "linear layer"):
        """A single-segment (Winkler, purely elastic) characteristic of slope ``stiffness``."""
        if not (np.isfinite(stiffness_N_per_mm3) and stiffness_N_per_mm3 > 0):
            raise InputError(name, f"stiffness must be positive, got {stiffness_N_per_mm3!r}")
        return cls(np.array([0.0, u_end_mm]), np.array([0.0, stiffness_N_per_mm3 * u_end_mm]), name)

    @classmethod
    def from_parameters(cls, params: PrandtlParameters, u_end_mm: float | None = None,
                        name: str = "layer characteristic") -> "Characteristic":
        """Reverse of eqs. (4)–(6): slopes S_i = sum_{j>=i} k_j, break points u_{i+1} = T_0i / k_i.

        ``u_end_mm`` is the last drawn point (default 1.5 u_N, or 1 mm for N = 1).
        """
        k = np.asarray(params.k_N_per_mm3, dtype=float).ravel()
        t0 = np.asarray(params.T0_MPa, dtype=float).ravel()
        if k.size < 1 or t0.size != k.size - 1:
            raise InputError(name, f"needs N stiffnesses and N-1 thresholds, got {k.size} and {t0.size}")
        if np.any(~np.isfinite(k)) or np.any(k <= 0) or np.any(~np.isfinite(t0)) or np.any(t0 <= 0):
            raise InputError(name, "stiffnesses k_i and thresholds T_0i must be positive and finite")
        slopes = np.cumsum(k[::-1])[::-1]
        u_break = t0 / k[:-1]
        if np.any(np.diff(u_break) <= 0):
            raise InputError(name, "break displacements T_0i/k_i must increase with i")
        if u_end_mm is None:
            u_end_mm = 1.5 * u_break[-1] if u_break.size else 1.0
        if u_break.size and u_end_mm <= u_break[-1]:
            raise InputError(name, "u_end_mm must lie beyond the last break point")
        u = np.concatenate([[0.0], u_break, [u_end_mm]])
        p = np.concatenate([[0.0], np.cumsum(slopes * np.diff(u))])
        return cls(u, p, name)

    @classmethod
    def from_dict(cls, data: dict[str, Any], name: str = "layer") -> "Characteristic":
        """From ``{"u_mm": [...], "p_MPa": [...]}`` (InputError naming ``name`` on bad content)."""
        from wrlayer import validate

        validate.table(data, name)
        for key in ("u_mm", "p_MPa"):
            if key not in data:
                raise InputError(name, f"missing key {key!r}")
        # flat lists of finite real numbers (no strings, booleans or nested lists)
        u = validate.number_list(data["u_mm"], f"{name}: u_mm", min_len=2)
        p = validate.number_list(data["p_MPa"], f"{name}: p_MPa", min_len=2)
        rho = 1.0
        if "reverse_factor" in data:
            lo, hi = REVERSE_FACTOR_RANGE
            rho = validate.number(data["reverse_factor"], f"{name}: reverse_factor", ge=lo, le=hi)
        return cls(u, p, name, rho)

    def to_dict(self) -> dict[str, Any]:
        """``{"u_mm", "p_MPa"}`` and, for an element that is not the paper's, ``reverse_factor``."""
        out: dict[str, Any] = {"u_mm": self.u_mm.tolist(), "p_MPa": self.p_MPa.tolist()}
        if self.reverse_factor != 1.0:
            out["reverse_factor"] = self.reverse_factor
        return out

    def with_points(self, u_mm, p_MPa, name: str | None = None) -> "Characteristic":
        """A characteristic through other points with this one's element (its reverse factor)."""
        return Characteristic(u_mm, p_MPa, self.name if name is None else name, self.reverse_factor)

    # ------------------------------------------------------------------ properties
    @property
    def n_segments(self) -> int:
        return int(self.u_mm.size - 1)

    @property
    def slopes(self) -> np.ndarray:
        """S_i = (p_{i+1} - p_i)/(u_{i+1} - u_i), N/mm^3, strictly decreasing."""
        return np.diff(self.p_MPa) / np.diff(self.u_mm)

    @property
    def initial_stiffness(self) -> float:
        """S_1 (N/mm^3), the elastic (unloading) stiffness of a virgin element."""
        return float(self.slopes[0])

    @property
    def elastic_limit_MPa(self) -> float:
        """p_2, the pressure below which a virgin element stays elastic (inf for a single segment)."""
        return float(self.p_MPa[1]) if self.n_segments > 1 else float("inf")

    def to_parameters(self) -> PrandtlParameters:
        """Eqs. (4)–(6): k_N = S_N, k_i = S_i - S_{i+1}, T_0i = k_i u_{i+1}."""
        s = self.slopes
        k = np.append(s[:-1] - s[1:], s[-1])
        t0 = k[:-1] * self.u_mm[1:-1]
        return PrandtlParameters(k, t0)

    # ------------------------------------------------------------------ evaluation (monotonic loading)
    def pressure(self, u_mm) -> np.ndarray:
        """p(u) on the monotonic characteristic (MPa); the last segment is extended beyond the last point."""
        u = np.asarray(u_mm, dtype=float)
        i = np.clip(np.searchsorted(self.u_mm, u, side="right") - 1, 0, self.n_segments - 1)
        return self.p_MPa[i] + self.slopes[i] * (u - self.u_mm[i])

    def displacement(self, p_MPa) -> np.ndarray:
        """u(p) on the monotonic characteristic (mm), inverse of :meth:`pressure`; p >= 0."""
        p = np.asarray(p_MPa, dtype=float)
        i = np.clip(np.searchsorted(self.p_MPa, p, side="right") - 1, 0, self.n_segments - 1)
        return self.u_mm[i] + (p - self.p_MPa[i]) / self.slopes[i]

    def secant_stiffness(self, p_MPa) -> np.ndarray:
        """p / u(p) (N/mm^3): the linear stiffness k that puts (p, u) on the characteristic (eq. 13's k)."""
        p = np.asarray(p_MPa, dtype=float)
        u = self.displacement(p)
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(p > 0, p / np.where(u > 0, u, 1.0), self.initial_stiffness)

    def residual_displacement(self, p0_MPa) -> np.ndarray:
        """Eq. (8) for a virgin element loaded to p_0 and fully unloaded: u(p_0) - p_0/S_1 (mm), >= 0."""
        p0 = np.asarray(p0_MPa, dtype=float)
        return np.maximum(self.displacement(p0) - p0 / self.initial_stiffness, 0.0)

    def unloading_residual(self, p0_MPa) -> np.ndarray:
        """The exact residual of a virgin element loaded to p_0 and fully unloaded (mm, >= 0): the unloading drop
        follows (1 + rho) times the backbone at Delta p / (1 + rho), so u_p = u(p_0) - (1 + rho) u(p_0 / (1 + rho));
        eq. (8) up to p_0 = (1 + rho) p_2 (module docstring)."""
        p0 = np.asarray(p0_MPa, dtype=float)
        f = 1.0 + self.reverse_factor
        return np.maximum(self.displacement(p0) - f * self.displacement(p0 / f), 0.0)

    # ------------------------------------------------------------------ combinations
    def series(self, other: "Characteristic", name: str | None = None) -> "Characteristic":
        """Two layers in series (same pressure, displacements add): wheel + rail -> combined layer."""
        p_end = max(self.p_MPa[-1], other.p_MPa[-1])
        p = np.unique(np.concatenate([self.p_MPa, other.p_MPa]))
        p = p[p <= p_end]
        u = self.displacement(p) + other.displacement(p)
        # elements in series unload as one when their sliders' reverse factors agree; otherwise the smaller one
        # (the earlier reverse slip) is kept, a stated approximation
        rho = min(self.reverse_factor, other.reverse_factor)
        return _merged(u, p, name or f"{self.name} + {other.name}", rho)

    @staticmethod
    def interpolate(a: "Characteristic", b: "Characteristic", t: float, name: str | None = None) -> "Characteristic":
        """(1 - t) p_a(u) + t p_b(u) on the union of break points: concave and increasing for t in [0, 1]."""
        if not 0.0 <= t <= 1.0:
            raise InputError("interpolation weight", f"must lie in [0, 1], got {t!r}")
        u_end = max(a.u_mm[-1], b.u_mm[-1])
        u = np.unique(np.concatenate([a.u_mm, b.u_mm]))
        u = u[u <= u_end]
        p = (1.0 - t) * a.pressure(u) + t * b.pressure(u)
        rho = (1.0 - t) * a.reverse_factor + t * b.reverse_factor
        return _merged(u, p, name or a.name, rho)


def _merged(u: np.ndarray, p: np.ndarray, name: str, reverse_factor: float = 1.0) -> Characteristic:
    """A characteristic through (u, p) with collinear interior points removed (keeps slopes strictly decreasing)."""
    u = np.asarray(u, dtype=float)
    p = np.asarray(p, dtype=float)
    distinct = np.concatenate([[True], np.diff(u) > 1e-12 * max(abs(float(u[-1])), 1e-300)])
    u, p = u[distinct], p[distinct]  # a break point shared by both bodies appears once
    keep = [0]
    for i in range(1, u.size - 1):
        s_in = (p[i] - p[keep[-1]]) / (u[i] - u[keep[-1]])
        s_out = (p[i + 1] - p[i]) / (u[i + 1] - u[i])
        if s_out < s_in * (1.0 - 1e-9):
            keep.append(i)
    keep.append(u.size - 1)
    return Characteristic(u[keep], p[keep], name, reverse_factor)
