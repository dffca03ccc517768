"""The rolling law fitted to the rolling FEM: first-pass ratio and per-pass increments (units mm, -).

For one level and traction coefficient the FEM gives the static dent s and the grooves g_1 .. g_n after passes
1..n at constant p0. The law (:class:`wrlayer.rolling_law.RollingLaw`) is

    g_k / s = G_k = rho (1 + A (1 - q^(k-1)) / (1 - q) + B (k - 1)),   rho = g_1 / s,

A, B >= 0, 0 <= q < 1: for each q of a grid the non-negative least-squares (A, B) of g_k / g_1 - 1 over
k = 2..n, the q with the smallest residual kept. A groove that falls pass after pass (a ratcheting surface
layer flowing sideways) is not representable (A, B >= 0): the fit then gives A = B = 0 and the error says so.
:func:`rolling_law` assembles the grid of levels x tractions into the table's law.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import nnls

from wrlayer.errors import InputError
from wrlayer.rolling_law import RollingLaw

#: The grid of decay ratios q searched.
DECAY_GRID = np.linspace(0.0, 0.95, 96)


@dataclass(frozen=True)
class PassFit:
    """The law's parameters at one level and traction: rho, A, q, B (-) and the largest relative error of the
    fitted groove over the fitted passes (-)."""

    first_pass_ratio: float
    shakedown_increment: float
    shakedown_decay: float
    ratchet_increment: float
    max_relative_error: float

    def factors(self, n_passes: int) -> np.ndarray:
        """G_1 .. G_n (-)."""
        k = np.arange(1, n_passes + 1, dtype=float)
        q = self.shakedown_decay
        return self.first_pass_ratio * (1.0 + self.shakedown_increment * (1.0 - q ** (k - 1)) / (1.0 - q)
                                        + self.ratchet_increment * (k - 1))


def fit_passes(grooves_mm, static_dent_mm: float, ratcheting: bool = True) -> PassFit:
    """The law's parameters of one groove series (cumulative, passes 1..n, mm) and its static dent (mm);
    ``ratcheting`` False: B = 0 (shakedown only; for a series too short to tell a slowly decaying tail from a
    constant increment)."""
    g = np.asarray(grooves_mm, dtype=float)
    if g.size < 1 or not (static_dent_mm > 0 and g[0] > 0):
        raise InputError("rolling law fit", f"needs a positive first groove and static dent, got {g[:1]} and "
                                            f"{static_dent_mm!r} mm")
    rho = g[0] / static_dent_mm
    rel = g / g[0] - 1.0
    m = np.arange(g.size, dtype=float)  # k - 1
    best = (np.inf, 0.0, 0.0, 0.0)
    if g.size >= 2:
        for q in DECAY_GRID:
            basis = np.column_stack([(1.0 - q ** m[1:]) / (1.0 - q), m[1:]][:2 if ratcheting else 1])
            coef, res = nnls(basis, rel[1:])
            if res < best[0]:
                best = (res, float(q), float(coef[0]), float(coef[1]) if ratcheting else 0.0)
    _, q, a, b = best
    fit = PassFit(float(rho), a, q, b, 0.0)
    err = float(np.max(np.abs(fit.factors(g.size) * static_dent_mm / g - 1.0)))
    return PassFit(float(rho), a, q, b, err)


def rolling_law(levels: list[float], tractions: list[float], fits: dict[tuple[float, float], PassFit],
                source: str) -> RollingLaw:
    """The law on the grid ``levels`` (p0 / p_2) x ``tractions`` from ``fits[(c, level)]``."""
    def grid(name):
        return [[getattr(fits[(c, x)], name) for x in levels] for c in tractions]

    return RollingLaw(list(levels), list(tractions), grid("first_pass_ratio"), grid("shakedown_increment"),
                      grid("shakedown_decay"), grid("ratchet_increment"), source)


__all__ = ["DECAY_GRID", "PassFit", "fit_passes", "rolling_law"]
