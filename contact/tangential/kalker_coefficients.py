"""Kalker's creepage coefficients C11, C22, C23 of the linear theory of rolling contact (dimensionless).

Linear theory for an elliptic contact with semi-axes a (rolling direction x) and b (lateral y), shear modulus G,
creepages vx, vy (-) and spin phi (1/mm), Kalker's sign convention:

    Fx = -G a b C11 vx,        Fy = -G a b (C22 vy + sqrt(a b) C23 phi).

Source of the numbers: J.J. Kalker, *Three-dimensional elastic bodies in rolling contact*, Kluwer 1990, Table E3
(first published in Kalker's 1967 thesis). The table is reproduced verbatim in the open-source program CONTACT
(E.A.H. Vollebregt, Vtech CMCC, Apache-2.0), module ``m_hertz``, subroutine ``linrol``, which was used here to
check every entry; its asymptotes for g = min(a/b, b/a) < 0.1 (Kalker 1990, Table E3, last rows) are used below
the table, as CONTACT does.

Rows: g = 0.1, 0.2, ..., 1.0 for both branches a/b <= 1 and b/a <= 1 (a: semi-axis in the rolling direction).
Columns: Poisson's ratio nu = 0, 0.25, 0.5.

Interpolation: in g between the table rows, linearly in scaled coefficients g^q C that are nearly linear in g
(:data:`SCALE_POWERS`): g C11, g C22 and g^1.5 C23 for b < a (Kalker's asymptotes: they grow like 1/g and
g^-1.5 as g -> 0); C11, C22 and sqrt(g) C23 for a <= b (the power with the smallest leave-one-out error on the
table, 1.4 % at twice the row spacing against 2.6 % for C23 itself); exact at the rows. Piecewise linear in
nu between the columns. (CONTACT interpolates the coefficients themselves linearly in g, and fits a parabola
through 1/C over the three nu columns; at nu = 0.28 the nu rules differ by at most 0.6 % for a >= b, the wheel/rail
case, and 1.7 % for a < b (C23 at a/b = 0.1); over nu in [0, 0.5] by up to 3.8 %.)
Below g = 0.1 Kalker's asymptotic formulae are used; they join the table at g = 0.1 with a jump of up to 6 %
(C23 for a/b -> 0, nu = 0.5; the asymptotes are not exact at g = 0.1).

Accuracy against the exact theory (:mod:`contact.tangential.exact_rolling`, nu = 0.25, extrapolated from 24 and
48 cells across the short axis; ``tests/contact/tangential/test_exact_rolling.py``): at the table's rows within 1 %
(a/b = 0.2, 0.5, 1, 2, 5). Between rows the coefficients are curved in g (C23 ~ g^-1.5 for b < a): interpolated
linearly in the coefficients themselves (CONTACT's rule) they were 6 %, 6 % and 16 % high at a/b = 6.67
(g = 0.15, wheel/rail patches); interpolated in the scaled variables they are within 2 % of the exact theory at
a/b = 3 and 6.67 (slow test in ``test_exact_rolling.py``), and every coefficient of the table predicted from the
rows two apart (a spacing twice the table's) is within 1.8 % of the published value (``tests/contact/tangential/
test_kalker_coefficients.py``), against up to 46 % (C23, b/a = 0.2) for the linear rule.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wrlayer.errors import require

#: Table rows g = min(a/b, b/a).
G_NODES = np.round(np.arange(1, 11) * 0.1, 10)
#: Powers q of g in the scaled coefficients g^q C interpolated linearly between the rows, per branch and name.
SCALE_POWERS = {"a<=b": {"C11": 0.0, "C22": 0.0, "C23": 0.5}, "b<a": {"C11": 1.0, "C22": 1.0, "C23": 1.5}}
#: Table columns (Poisson's ratio).
NU_NODES = np.array([0.0, 0.25, 0.5])

# Kalker 1990, Table E3, branch a/b <= 1 (g = a/b), rows g = 0.1..1.0, columns nu = 0, 0.25, 0.5.
_C11_A_LE_B = np.array([
    [2.51, 3.31, 4.85], [2.59, 3.37, 4.81], [2.68, 3.44, 4.80], [2.78, 3.53, 4.82], [2.88, 3.62, 4.83],
    [2.98, 3.72, 4.91], [3.09, 3.81, 4.97], [3.19, 3.91, 5.05], [3.29, 4.01, 5.12], [3.40, 4.12, 5.20]])
_C22_A_LE_B = np.array([
    [2.51, 2.52, 2.53], [2.59, 2.63, 2.66], [2.68, 2.75, 2.81], [2.78, 2.88, 2.98], [2.88, 3.01, 3.14],
    [2.98, 3.14, 3.31], [3.09, 3.28, 3.48], [3.19, 3.41, 3.65], [3.29, 3.54, 3.82], [3.40, 3.67, 3.98]])
_C23_A_LE_B = np.array([
    [0.334, 0.473, 0.731], [0.483, 0.603, 0.809], [0.607, 0.715, 0.889], [0.720, 0.823, 0.977],
    [0.827, 0.929, 1.07], [0.930, 1.03, 1.18], [1.03, 1.14, 1.29], [1.13, 1.25, 1.40], [1.23, 1.36, 1.51],
    [1.33, 1.47, 1.63]])
# Branch b/a <= 1 (g = b/a), rows g = 0.1..1.0 (the book lists them from b/a = 1 down to 0.1).
_C11_B_LT_A = np.array([
    [10.7, 11.7, 12.9], [6.96, 7.78, 8.82], [5.57, 6.34, 7.34], [4.84, 5.57, 6.57], [4.37, 5.10, 6.11],
    [4.06, 4.78, 5.80], [3.82, 4.54, 5.58], [3.65, 4.36, 5.42], [3.51, 4.22, 5.30], [3.40, 4.12, 5.20]])
_C22_B_LT_A = np.array([
    [10.7, 12.8, 16.0], [6.96, 8.14, 9.79], [5.57, 6.40, 7.51], [4.84, 5.48, 6.31], [4.37, 4.90, 5.56],
    [4.06, 4.50, 5.04], [3.82, 4.21, 4.67], [3.65, 3.99, 4.39], [3.51, 3.81, 4.16], [3.40, 3.67, 3.98]])
_C23_B_LT_A = np.array([
    [12.2, 14.6, 18.0], [5.72, 6.63, 7.89], [3.79, 4.32, 5.01], [2.88, 3.24, 3.70], [2.35, 2.62, 2.96],
    [2.01, 2.23, 2.50], [1.76, 1.95, 2.18], [1.58, 1.75, 1.94], [1.44, 1.59, 1.77], [1.33, 1.47, 1.63]])

#: TABLE[branch][name] -> (10, 3) array; branch "a<=b" (g = a/b) or "b<a" (g = b/a).
TABLE = {
    "a<=b": {"C11": _C11_A_LE_B, "C22": _C22_A_LE_B, "C23": _C23_A_LE_B},
    "b<a": {"C11": _C11_B_LT_A, "C22": _C22_B_LT_A, "C23": _C23_B_LT_A},
}


@dataclass(frozen=True)
class CreepCoefficients:
    """Kalker's coefficients C11, C22, C23 (dimensionless) for one ellipse and Poisson's ratio."""

    C11: float
    C22: float
    C23: float


def _asymptotes(g: float, nu: float, a_le_b: bool) -> tuple[float, float, float]:
    """Kalker's asymptotic coefficients for g = min(a/b, b/a) -> 0 (Kalker 1990, Table E3)."""
    if a_le_b:  # long lateral strip: a << b
        c11 = np.pi**2 / 4.0 / (1.0 - nu)
        c22 = np.pi**2 / 4.0
        c23 = np.pi * np.sqrt(g) / 3.0 / (1.0 - nu) * (1.0 + nu * (np.log(16.0 / g) - 5.0))
    else:  # long in the rolling direction: b << a
        lam = np.log(16.0 / g**2)
        c11 = 2.0 * np.pi / (lam - 2.0 * nu) / g * (1.0 + (3.0 - np.log(4.0)) / (lam - 2.0 * nu))
        den = (1.0 - nu) * lam + 2.0 * nu
        c22 = 2.0 * np.pi / g * (1.0 + (1.0 - nu) * (3.0 - np.log(4.0)) / den) / den
        c23 = 2.0 * np.pi / 3.0 / g**1.5 / ((1.0 - nu) * lam - 2.0 + 4.0 * nu)
    return float(c11), float(c22), float(c23)


def _interp_branch(branch: dict, g: float, nu: float, powers: dict) -> tuple[float, float, float]:
    """(C11, C22, C23) of one branch: g^q C linear in g between the rows (q: ``powers``), piecewise linear in nu
    between the columns."""
    row = min(int(np.searchsorted(G_NODES, g, side="right")) - 1, G_NODES.size - 2)
    fg = (g - G_NODES[row]) / (G_NODES[row + 1] - G_NODES[row])
    col = 0 if nu <= NU_NODES[1] else 1
    fn = (nu - NU_NODES[col]) / (NU_NODES[col + 1] - NU_NODES[col])
    out = []
    for name in ("C11", "C22", "C23"):
        t, q = branch[name], powers[name]
        g0, g1 = G_NODES[row], G_NODES[row + 1]
        by_nu = ((1.0 - fg) * g0 ** q * t[row, col:col + 2] + fg * g1 ** q * t[row + 1, col:col + 2]) / g ** q
        out.append(float((1.0 - fn) * by_nu[0] + fn * by_nu[1]))
    return out[0], out[1], out[2]


def creep_coefficients(a_over_b: float, poisson: float) -> CreepCoefficients:
    """Kalker's C11, C22, C23 for the semi-axis ratio a/b (a in the rolling direction) and Poisson's ratio.

    a_over_b > 0 (finite); poisson in [0, 0.5]. Table E3 values interpolated in g = min(a/b, b/a) (the scaled
    coefficients of :data:`SCALE_POWERS` linearly) and linearly in nu; Kalker's asymptotes below g = 0.1.
    """
    require(bool(np.isfinite(a_over_b)) and a_over_b > 0, "a_over_b",
            f"semi-axis ratio must be a positive finite number, got {a_over_b!r}")
    require(bool(np.isfinite(poisson)) and 0.0 <= poisson <= 0.5, "poisson",
            f"Poisson's ratio must lie in [0, 0.5], got {poisson!r}")
    a_le_b = a_over_b <= 1.0
    g = a_over_b if a_le_b else 1.0 / a_over_b
    if g < 0.1:
        return CreepCoefficients(*_asymptotes(g, poisson, a_le_b))
    branch = "a<=b" if a_le_b else "b<a"
    return CreepCoefficients(*_interp_branch(TABLE[branch], g, poisson, SCALE_POWERS[branch]))
