"""The rolling law of a layer table: what a rolling pass does to a layer element, from the rolling FEM (mm, MPa).

A layer element loaded to p0 and unloaded leaves the static (Masing) residual r(p0) (paper eq. 8). A rolling
load at the same constant p0 leaves, after pass n, the groove

    R_n = r(p0) G_n(x, c),   G_n = rho (1 + A (1 - q^(n-1)) / (1 - q) + B (n - 1)),   x = p0 / p_2

with rho the first-pass groove over the static dent, A q^(n-2) + B the increment of pass n >= 2 over the
first-pass groove (A, q: the geometrically decaying part, shakedown; B: the constant part per pass,
ratcheting), x the peak over the element's elastic limit p_2 (the FEM first-yield pressure) and c the traction
coefficient q_x / p of the rolling load. Each parameter is tabulated on a grid of levels x and traction
coefficients c and interpolated bilinearly; outside the grid x and |c| are clamped to it (stated rule: below
the lowest level the lowest level's ratios apply, the residual itself goes to zero at x = 1). A law may also have
patch-shape nodes ``aspect_ratio`` (a/b of the rolling patch, a along the rolling direction): one such grid per
node, linear in log(a/b) between the nodes and clamped outside them. The rolling FEM's groove over its static dent
depends on the patch shape, most with traction: at 1.5 p_y, c = 0.2 the first-pass ratio is 1.23 on a block at
a/b = 3.83 against 1.03 for the mean of the crown and gauge-corner blocks at a/b = 1.34
(docs/rolling-gap.md). It depends on the surface's own lateral convexity s = b / (2 R) too (R the body's lateral
radius, negative where concave; b the patch's lateral semi-axis): on the wheel section at a/b 1.33, c = 0.2,
1.3 p_y, pass 5, 1.20 at the tread (s = -0.008) against 1.31 at the flange root (s = -0.10). A law may therefore
give its nodes a ``convexity`` s as well: the nodes of one a/b are interpolated linearly in s (clamped), then the
a/b groups in log(a/b) as above.

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
#: The law's parameters, in the order of :meth:`RollingLaw.parameters`.
PARAMETERS = ("first_pass_ratio", "shakedown_increment", "shakedown_decay", "ratchet_increment")
#: Between the nodes' sources in a law with patch-shape nodes (:meth:`RollingLaw.by_aspect`).
NODE_SEPARATOR = " | "
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
    aspect_ratio : list of float or None
        Patch shapes a/b of the law's nodes (-, strictly increasing, > 0; a along the rolling direction); each
        parameter is then [node][c][x]. None: one patch shape, [c][x]. With ``convexity``: non-decreasing, the
        nodes of one a/b strictly increasing in convexity.
    convexity : list of float or None
        The surface convexity s = b / (2 R) of each node (-, convex > 0; needs ``aspect_ratio``). None: the law
        does not depend on it.
    """

    p0_over_p2: list[float]
    traction_coefficient: list[float]
    first_pass_ratio: list[list[float]]
    shakedown_increment: list[list[float]]
    shakedown_decay: list[list[float]]
    ratchet_increment: list[list[float]]
    source: str = ""
    aspect_ratio: list[float] | None = None
    convexity: list[float] | None = None

    def __post_init__(self):
        what = "rolling_law"
        x = validate.number_list(self.p0_over_p2, f"{what}.p0_over_p2", gt=1.0)
        c = validate.number_list(self.traction_coefficient, f"{what}.traction_coefficient", ge=0.0)
        axes = [("p0_over_p2", x), ("traction_coefficient", c)]
        if self.aspect_ratio is not None:
            axes.append(("aspect_ratio", validate.number_list(self.aspect_ratio, f"{what}.aspect_ratio", gt=0.0)))
        for name, arr in axes:
            if np.any(np.diff(arr) < 0) or (np.any(np.diff(arr) == 0) and not (
                    name == "aspect_ratio" and self.convexity is not None)):
                raise InputError(f"{what}.{name}", "must be strictly increasing")
            object.__setattr__(self, name, arr.tolist())
        if self.convexity is not None:
            self._check_convexity(what)
        bounds = {"first_pass_ratio": dict(gt=0.0), "shakedown_increment": dict(ge=0.0),
                  "shakedown_decay": dict(ge=0.0, lt=1.0), "ratchet_increment": dict(ge=0.0)}
        for name, b in bounds.items():
            if self.aspect_ratio is None:
                object.__setattr__(self, name, _grid(getattr(self, name), f"{what}.{name}", c.size, x.size, b))
                continue
            nodes = getattr(self, name)
            if not isinstance(nodes, (list, tuple)) or len(nodes) != len(self.aspect_ratio):
                raise InputError(f"{what}.{name}", f"must have one grid per aspect ratio ({len(self.aspect_ratio)})")
            object.__setattr__(self, name, [_grid(g, f"{what}.{name}[{k}]", c.size, x.size, b)
                                            for k, g in enumerate(nodes)])

    def _check_convexity(self, what: str) -> None:
        """The ``convexity`` nodes: one per a/b node, finite, strictly increasing within each a/b."""
        if self.aspect_ratio is None:
            raise InputError(f"{what}.convexity", "needs aspect_ratio (one convexity per patch-shape node)")
        s = validate.number_list(self.convexity, f"{what}.convexity", min_len=len(self.aspect_ratio),
                                 max_len=len(self.aspect_ratio))
        same = np.diff(np.asarray(self.aspect_ratio)) == 0
        if np.any(np.diff(s)[same] <= 0):
            raise InputError(f"{what}.convexity", "must be strictly increasing among the nodes of one aspect_ratio")
        object.__setattr__(self, "convexity", s.tolist())

    @classmethod
    def by_aspect(cls, nodes, source: str = "") -> RollingLaw:
        """The law with patch-shape nodes from single-shape laws: ``nodes`` = [(a/b, law), ...] (strictly
        increasing a/b), every law on the same levels and traction coefficients (InputError otherwise)."""
        return cls.by_shape([(r, None, law) for r, law in nodes], source)

    @classmethod
    def by_shape(cls, nodes, source: str = "") -> RollingLaw:
        """The law with patch-shape nodes from single-shape laws: ``nodes`` = [(a/b, s, law), ...] sorted by a/b,
        then by the convexity s (None for every node: a law without convexity nodes), every law on the same
        levels and traction coefficients (InputError otherwise)."""
        nodes = list(nodes)
        first = nodes[0][2] if nodes else None
        if first is None or any(law.aspect_ratio is not None or law.p0_over_p2 != first.p0_over_p2
                                or law.traction_coefficient != first.traction_coefficient for *_, law in nodes):
            raise InputError("rolling_law", "patch-shape nodes need single-shape laws on one grid of levels and "
                                            "traction coefficients")
        convex = [s for _, s, _ in nodes]
        if any(s is None for s in convex) and any(s is not None for s in convex):
            raise InputError("rolling_law.convexity", "give every patch-shape node a convexity, or none")

        def label(r, s):
            return f"a/b = {r:.3g}" + ("" if s is None else f", b/(2R) = {s:+.3f}")

        return cls(first.p0_over_p2, first.traction_coefficient,
                   *([getattr(law, name) for *_, law in nodes] for name in PARAMETERS),
                   source=source or NODE_SEPARATOR.join(f"{label(r, s)}: {law.source}" for r, s, law in nodes),
                   aspect_ratio=[float(r) for r, _, _ in nodes],
                   convexity=None if convex[0] is None else [float(s) for s in convex])

    def node(self, k: int) -> RollingLaw:
        """The single-shape law of patch-shape node ``k`` (a law without nodes: itself)."""
        if self.aspect_ratio is None:
            return self
        parts = self.source.split(NODE_SEPARATOR)  # the nodes' own sources as :meth:`by_aspect` joined them
        source = parts[k].split(": ", 1)[-1] if len(parts) == len(self.aspect_ratio) else self.source
        return RollingLaw(self.p0_over_p2, self.traction_coefficient, *(getattr(self, n)[k] for n in PARAMETERS),
                          source=source)

    # ------------------------------------------------------------------ parameters
    def parameters(self, x, c, aspect=None, convexity=None) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(rho, A, q, B) at levels x = p0 / p_2, traction coefficients c and (a law with patch-shape nodes)
        patch shapes ``aspect`` = a/b and (a law with convexity nodes) surface convexities ``convexity`` = b / (2 R)
        (arrays of a common shape; InputError when a shaped law gets no a/b or convexity)."""
        xs, cs = np.asarray(self.p0_over_p2), np.asarray(self.traction_coefficient)
        x = np.clip(np.asarray(x, dtype=float), xs[0], xs[-1])
        c = np.clip(np.abs(np.asarray(c, dtype=float)), cs[0], cs[-1])
        if self.aspect_ratio is None:
            x, c = np.broadcast_arrays(x, c)
            return tuple(_bilinear(np.asarray(getattr(self, n), dtype=float), xs, cs, x, c) for n in PARAMETERS)
        if aspect is None:
            raise InputError("rolling_law.aspect_ratio", "the law has patch-shape nodes: the patch's a/b is needed")
        if self.convexity is not None and convexity is None:
            raise InputError("rolling_law.convexity", "the law has convexity nodes: the surface's b/(2R) is needed")
        groups = sorted(set(self.aspect_ratio))  # the nodes of one a/b: one group, linear in the convexity
        nodes = np.log(np.asarray(groups))
        la = np.clip(np.log(np.maximum(np.asarray(aspect, dtype=float), 1e-300)), nodes[0], nodes[-1])
        s = np.asarray(0.0 if convexity is None else convexity, dtype=float)
        x, c, la, s = np.broadcast_arrays(x, c, la, s)
        k = np.clip(np.searchsorted(nodes, la, side="right") - 1, 0, max(nodes.size - 2, 0))
        t = (la - nodes[k]) / (nodes[np.minimum(k + 1, nodes.size - 1)] - nodes[k]) if nodes.size > 1 else 0.0 * la
        out = []
        for name in PARAMETERS:
            at = [_bilinear(np.asarray(g, dtype=float), xs, cs, x, c) for g in getattr(self, name)]
            at = np.array([self._in_group(at, r, s) for r in groups])
            lo = np.take_along_axis(at, k[None], 0)[0]
            hi = np.take_along_axis(at, np.minimum(k + 1, nodes.size - 1)[None], 0)[0]
            out.append((1.0 - t) * lo + t * hi)
        return tuple(out)

    def _in_group(self, at: list[np.ndarray], aspect: float, s: np.ndarray) -> np.ndarray:
        """A parameter of the nodes at a/b = ``aspect`` (``at``: every node's value per point) at the convexities
        ``s``: linear between the group's convexity nodes, clamped outside them."""
        k = [i for i, r in enumerate(self.aspect_ratio) if r == aspect]
        if len(k) == 1:
            return at[k[0]]
        sk = np.asarray([self.convexity[i] for i in k])
        j = np.clip(np.searchsorted(sk, s, side="right") - 1, 0, sk.size - 2)
        w = np.clip((s - sk[j]) / (sk[j + 1] - sk[j]), 0.0, 1.0)
        vals = np.array([at[i] for i in k])
        return (1.0 - w) * np.take_along_axis(vals, j[None], 0)[0] + w * np.take_along_axis(vals, (j + 1)[None], 0)[0]

    def factor(self, n, x, c, aspect=None, convexity=None) -> np.ndarray:
        """G_n: the groove after n passes (n >= 1, real) over the static residual at x = p0 / p_2, c, the patch
        shape a/b ``aspect`` (a law with patch-shape nodes) and the convexity b / (2 R) (a law with convexity
        nodes) (-)."""
        rho, a, q, b = self.parameters(x, c, aspect, convexity)
        return _factor(np.asarray(n, dtype=float), rho, a, q, b)

    def next_residual(self, accumulated_mm, static_mm, x, c, aspect=None, convexity=None) -> np.ndarray:
        """The accumulated residual (mm) after one more pass at x = p_peak / p_2 with static residual
        ``static_mm`` (r(p_peak), mm), from ``accumulated_mm``, on a patch of shape a/b ``aspect`` (a law with
        patch-shape nodes) on a surface of convexity b / (2 R) ``convexity`` (a law with convexity nodes) (see the
        module docstring: equivalent passes)."""
        u = np.asarray(accumulated_mm, dtype=float)
        r = np.asarray(static_mm, dtype=float)
        rho, a, q, b = self.parameters(x, c, aspect, convexity)
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
        out.update({k: getattr(self, k) for k in self.__dataclass_fields__
                    if k not in ("aspect_ratio", "convexity") or getattr(self, k) is not None})
        return out

    @classmethod
    def from_dict(cls, data, what: str = "rolling_law") -> RollingLaw:
        """Validate a JSON object into a law (InputError naming ``what`` and the key)."""
        data = validate.table(data, what)
        validate.check_known(data, ("kind",) + tuple(cls.__dataclass_fields__), what)
        if data.get("kind", KIND) != KIND:
            raise InputError(f"{what}.kind", f"must be {KIND!r}, got {data.get('kind')!r}")
        missing = [k for k in cls.__dataclass_fields__ if k not in ("source", "aspect_ratio", "convexity")
                   and k not in data]
        if missing:
            raise InputError(what, f"missing {', '.join(missing)}")
        try:
            return cls(**{k: data[k] for k in cls.__dataclass_fields__ if k in data})
        except InputError as err:
            raise validate.rewrap(err, what) from None


def _grid(rows, what: str, n_c: int, n_x: int, bounds: dict) -> list[list[float]]:
    """One [c][x] parameter grid, validated (InputError naming ``what``)."""
    if not isinstance(rows, (list, tuple)) or len(rows) != n_c:
        raise InputError(what, f"must have one row per traction coefficient ({n_c})")
    return [validate.number_list(row, f"{what}[{i}]", min_len=n_x, max_len=n_x, **bounds).tolist()
            for i, row in enumerate(rows)]


def _bilinear(grid: np.ndarray, xs: np.ndarray, cs: np.ndarray, x: np.ndarray, c: np.ndarray) -> np.ndarray:
    """A [c][x] grid at (x, c), already clamped to it: linear in x on every row, then linear in c."""
    by_c = np.array([np.interp(x, xs, row) for row in grid])          # (n_c, *shape)
    if cs.size == 1:
        return by_c[0]
    j = np.clip(np.searchsorted(cs, c, side="right") - 1, 0, cs.size - 2)
    t = (c - cs[j]) / (cs[j + 1] - cs[j])
    lo = np.take_along_axis(by_c, j[None], 0)[0]
    hi = np.take_along_axis(by_c, (j + 1)[None], 0)[0]
    return (1.0 - t) * lo + t * hi


def _factor(n, rho, a, q, b):
    """G_n = rho (1 + A (1 - q^(n-1)) / (1 - q) + B (n - 1)) for n >= 1 (G_0 = 0 below n = 1)."""
    m = np.maximum(n - 1.0, 0.0)
    g = rho * (1.0 + a * (1.0 - q ** m) / (1.0 - q) + b * m)
    return np.where(n >= 1.0, g, rho * np.clip(n, 0.0, 1.0))


__all__ = ["KIND", "MAX_PASSES", "PARAMETERS", "RollingLaw"]
