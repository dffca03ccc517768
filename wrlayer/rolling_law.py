"""The rolling law of a layer table: what a rolling pass does to a layer element, from the rolling FEM (mm, MPa).

A layer element loaded to p0 and unloaded leaves the static (Masing) residual r(p0) (paper eq. 8). A rolling
load at the same constant p0 leaves, after pass n, the groove

    R_n = r(p0) G_n(x, c),   G_n = rho (1 + A (1 - q^(n-1)) / (1 - q) + B (n - 1)),   x = p0 / p_2

with rho the first-pass groove over the static dent, A q^(n-2) + B the increment of pass n >= 2 over the
first-pass groove (A, q: the geometrically decaying part, shakedown; B: the constant part per pass,
ratcheting), x the peak over the element's elastic limit p_2 (the FEM first-yield pressure) and c the traction
coefficient q_x / p of the rolling load. Each parameter is tabulated on a grid of levels x and traction
coefficients c and interpolated bilinearly; outside the grid x and |c| are clamped to it (stated rule: below
the lowest level the lowest level's ratios apply, the residual itself goes to zero at x = 1).

Varying peaks (equivalent-pass rule): an element carries its accumulated rolling residual U. A pass at peak p
first finds the equivalent pass count n* >= 1 with r(p) G_n*(x, c) = U; the pass leaves r(p) G_(n*+1). When U is
below the first-pass groove r(p) G_1 (a higher load than before) the pass leaves r(p) G_1; when U is beyond
what any number of passes at p leaves (shakedown at a lower groove) it adds nothing. Under a constant peak this is
R_n exactly.

Stored in a layer table (``format_version`` 3, key ``rolling_law``; :mod:`wrlayer.layer_table`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wrlayer import validate
from wrlayer.errors import InputError

#: The format of a rolling law.
KIND = "first-pass ratio, geometric shakedown + constant ratcheting increments"
#: Passes beyond which the equivalent-pass search stops (a groove beyond G_(MAX_PASSES) adds nothing).
MAX_PASSES = 1.0e7


@dataclass(frozen=True)
class RollingLaw:
    """The rolling law (``rolling_law`` of a layer table), per level x and traction coefficient c.

    Attributes
    ----------
    p0_over_p2 : list of float
        Levels x = p0 / p_2 of the grid (-, strictly increasing, > 1).
    traction_coefficient : list of float
        Traction coefficients c of the grid (-, strictly increasing, >= 0).
    first_pass_ratio : list of list of float
        rho: first-pass groove over the static dent, [c][x] (-, > 0).
    shakedown_increment : list of list of float
        A: increment of pass 2 over the first-pass groove, decaying part, [c][x] (-, >= 0).
    shakedown_decay : list of list of float
        q: ratio of successive decaying increments, [c][x] (-, in [0, 1)).
    ratchet_increment : list of list of float
        B: constant increment per pass over the first-pass groove, [c][x] (-, >= 0).
    source : str
        Where the law was calibrated (the rolling FEM cases, mesh and step).
    """

    p0_over_p2: list[float]
    traction_coefficient: list[float]
    first_pass_ratio: list[list[float]]
    shakedown_increment: list[list[float]]
    shakedown_decay: list[list[float]]
    ratchet_increment: list[list[float]]
    source: str = ""

    def __post_init__(self):
        what = "rolling_law"
        x = validate.number_list(self.p0_over_p2, f"{what}.p0_over_p2", gt=1.0)
        c = validate.number_list(self.traction_coefficient, f"{what}.traction_coefficient", ge=0.0)
        for name, arr in (("p0_over_p2", x), ("traction_coefficient", c)):
            if np.any(np.diff(arr) <= 0):
                raise InputError(f"{what}.{name}", "must be strictly increasing")
        bounds = {"first_pass_ratio": dict(gt=0.0), "shakedown_increment": dict(ge=0.0),
                  "shakedown_decay": dict(ge=0.0, lt=1.0), "ratchet_increment": dict(ge=0.0)}
        object.__setattr__(self, "p0_over_p2", x.tolist())
        object.__setattr__(self, "traction_coefficient", c.tolist())
        for name, b in bounds.items():
            rows = getattr(self, name)
            if not isinstance(rows, (list, tuple)) or len(rows) != c.size:
                raise InputError(f"{what}.{name}", f"must have one row per traction coefficient ({c.size})")
            checked = [validate.number_list(row, f"{what}.{name}[{i}]", min_len=x.size, max_len=x.size, **b).tolist()
                       for i, row in enumerate(rows)]
            object.__setattr__(self, name, checked)

    # ------------------------------------------------------------------ parameters
    def parameters(self, x, c) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(rho, A, q, B) at levels x = p0 / p_2 and traction coefficients c (arrays of a common shape)."""
        xs, cs = np.asarray(self.p0_over_p2), np.asarray(self.traction_coefficient)
        x = np.clip(np.asarray(x, dtype=float), xs[0], xs[-1])
        c = np.clip(np.abs(np.asarray(c, dtype=float)), cs[0], cs[-1])
        x, c = np.broadcast_arrays(x, c)
        out = []
        for name in ("first_pass_ratio", "shakedown_increment", "shakedown_decay", "ratchet_increment"):
            grid = np.asarray(getattr(self, name), dtype=float)
            by_c = np.array([np.interp(x, xs, row) for row in grid])          # (n_c, *shape)
            if cs.size == 1:
                out.append(by_c[0])
                continue
            j = np.clip(np.searchsorted(cs, c, side="right") - 1, 0, cs.size - 2)
            t = (c - cs[j]) / (cs[j + 1] - cs[j])
            lo = np.take_along_axis(by_c, j[None], 0)[0]
            hi = np.take_along_axis(by_c, (j + 1)[None], 0)[0]
            out.append((1.0 - t) * lo + t * hi)
        return tuple(out)

    def factor(self, n, x, c) -> np.ndarray:
        """G_n: the groove after n passes (n >= 1, real) over the static residual at x = p0 / p_2, c (-)."""
        rho, a, q, b = self.parameters(x, c)
        return _factor(np.asarray(n, dtype=float), rho, a, q, b)

    def next_residual(self, accumulated_mm, static_mm, x, c) -> np.ndarray:
        """The accumulated residual (mm) after one more pass at x = p_peak / p_2 with static residual
        ``static_mm`` (r(p_peak), mm), from ``accumulated_mm`` (see the module docstring: equivalent passes)."""
        u = np.asarray(accumulated_mm, dtype=float)
        r = np.asarray(static_mm, dtype=float)
        rho, a, q, b = self.parameters(x, c)
        u, r, rho, a, q, b = np.broadcast_arrays(u, r, rho, a, q, b)
        target = np.divide(u, r, out=np.zeros_like(u), where=r > 0)
        lo, hi = np.ones_like(u), np.full_like(u, MAX_PASSES)
        beyond = target >= _factor(hi, rho, a, q, b)
        first = target < rho * (1.0 - 1e-9)
        for _ in range(80):  # bisection on the equivalent pass count (G_n increasing in n)
            mid = np.sqrt(lo * hi)
            below = _factor(mid, rho, a, q, b) < target
            lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
        n_eq = np.where(first, 0.0, 0.5 * (lo + hi))
        new = np.where(r > 0, r * _factor(n_eq + 1.0, rho, a, q, b), 0.0)
        return np.where(beyond | (r <= 0), u, np.maximum(new, u))

    # ------------------------------------------------------------------ JSON
    def to_dict(self) -> dict:
        out = {"kind": KIND}
        out.update({k: getattr(self, k) for k in self.__dataclass_fields__})
        return out

    @classmethod
    def from_dict(cls, data, what: str = "rolling_law") -> RollingLaw:
        """Validate a JSON object into a law (InputError naming ``what`` and the key)."""
        data = validate.table(data, what)
        validate.check_known(data, ("kind",) + tuple(cls.__dataclass_fields__), what)
        if data.get("kind", KIND) != KIND:
            raise InputError(f"{what}.kind", f"must be {KIND!r}, got {data.get('kind')!r}")
        missing = [k for k in cls.__dataclass_fields__ if k != "source" and k not in data]
        if missing:
            raise InputError(what, f"missing {', '.join(missing)}")
        try:
            return cls(**{k: data[k] for k in cls.__dataclass_fields__ if k in data})
        except InputError as err:
            raise validate.rewrap(err, what) from None


def _factor(n, rho, a, q, b):
    """G_n = rho (1 + A (1 - q^(n-1)) / (1 - q) + B (n - 1)) for n >= 1 (G_0 = 0 below n = 1)."""
    m = np.maximum(n - 1.0, 0.0)
    g = rho * (1.0 + a * (1.0 - q ** m) / (1.0 - q) + b * m)
    return np.where(n >= 1.0, g, rho * np.clip(n, 0.0, 1.0))


__all__ = ["KIND", "MAX_PASSES", "RollingLaw"]
