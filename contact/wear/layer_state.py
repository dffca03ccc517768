"""The layer's state per profile position between wear steps: strain hardening (units mm, MPa).

A Prandtl element (paper section 2) loaded monotonically to p_hist and unloaded (without reverse slip of its
sliders, i.e. for p_hist below about twice its elastic limit) keeps its slipped sliders at their break stress
minus the unloading. Reloaded, it responds elastically with the initial slope S_1 until p_hist, where every slipped
slider is back at its break stress, and then follows its virgin characteristic, shifted by the residual
u_p(p_hist) already left in the surface (the paper's "strain hardening": an element does not move on the next load
unless the load exceeds what its stuck sliders hold). That reloading response is itself a monotonic
characteristic,

    (0, 0) -> (p_hist / S_1, p_hist) -> (u_i - u_p(p_hist), p_i) for the virgin points with p_i > p_hist,

so a hardened element can be given to the solvers as a virgin element of this characteristic
(:func:`hardened`): its residual after a load p is 0 for p <= p_hist and u_p(p) - u_p(p_hist) beyond.

Between wear steps the loop keeps, per side and body, the largest peak pressure p_hist(y) every profile position
has carried (profile coordinate y of the initial profile, interpolated between the positions of a grid), and the
next step's solver looks the layer up through :class:`HardenedTable`. Assumptions (stated): the residual of
each step is moved into the profile (the dent is part of the new profile); the profile coordinate of a material
point does not change by wear (the depths are < 1 mm, the lateral shift of y is smaller); no reverse slip on
unloading. A ``combined`` (one characteristic for both bodies) layer has no positions: it stays virgin.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wrlayer.characteristic import Characteristic
from contact.wear.condition import BODIES, ConditionResult
from contact.wear.profile_grid import ArcGrid
from contact.scenes.layers import LayerSources
from meshes.profiles import Profile

#: (profile coordinates y (mm), largest peak pressure p_hist (MPa)) per (side, body).
History = dict[tuple[str, str], tuple[np.ndarray, np.ndarray]]

_TOL = 1e-9


def hardened(char: Characteristic, p_hist_MPa: float) -> Characteristic:
    """The reloading characteristic of an element of ``char`` loaded to ``p_hist_MPa`` and unloaded (see the module
    docstring); ``char`` itself when p_hist is at or below its elastic limit."""
    p_hist = float(p_hist_MPa)
    if not p_hist > char.elastic_limit_MPa * (1.0 + _TOL):
        return char
    s1 = char.initial_stiffness
    up = float(char.displacement(p_hist)) - p_hist / s1
    keep = char.p_MPa > p_hist * (1.0 + _TOL)
    u = [0.0, p_hist / s1] + list(char.u_mm[keep] - up)
    p = [0.0, p_hist] + list(char.p_MPa[keep])
    if not np.any(keep):  # beyond the last point: the last segment continues
        slope = float(char.slopes[-1])
        u.append(u[-1] + 0.01)
        p.append(p_hist + slope * 0.01)
    return char.with_points(np.array(u), np.array(p), name=f"{char.name}, hardened to {p_hist:.6g} MPa")


@dataclass(frozen=True)
class HardenedTable:
    """A layer table (``characteristic_at(y)``, ``y_range_mm``) whose elements carry the peak pressures
    ``p_hist_MPa`` at the profile coordinates ``y_mm`` (linear between them, 0 outside)."""

    table: object
    y_mm: np.ndarray
    p_hist_MPa: np.ndarray

    @property
    def y_range_mm(self) -> tuple[float, float]:
        return self.table.y_range_mm

    @property
    def body(self) -> str:
        return self.table.body

    @property
    def rolling_law(self):
        """The table's rolling law (None: none), unchanged by the hardening."""
        return self.table.rolling_law

    def calibrated_max_MPa(self, y_mm: float) -> float | None:
        """The table's calibrated pressure range at y (MPa), unchanged by the hardening."""
        return self.table.calibrated_max_MPa(y_mm)

    def lateral_curvature_at(self, y_mm):
        """The table's lateral curvature at y (1/mm; y a float or an array), unchanged by the hardening."""
        return self.table.lateral_curvature_at(y_mm)

    def characteristic_at(self, y_mm: float, patch_mm: tuple[float, float] | None = None) -> Characteristic:
        """The table's characteristic at y (scaled to ``patch_mm`` = (a, b) mm when given, ``scale_to_patch``),
        hardened to the peak pressure its element has carried."""
        virgin = (self.table.characteristic_at(y_mm) if patch_mm is None
                  else self.table.characteristic_at(y_mm, patch_mm=patch_mm))
        p = float(np.interp(float(y_mm), self.y_mm, self.p_hist_MPa, left=0.0, right=0.0))
        return hardened(virgin, p)


def virgin_history(profiles: dict[str, dict[str, Profile]], grid_mm: float) -> History:
    """No load carried yet: p_hist = 0 at the profile-grid nodes (spacing ``grid_mm``) of every side's initial
    profiles."""
    history = {}
    for side, bodies in profiles.items():
        for body in BODIES:
            y = ArcGrid.of(bodies[body], grid_mm).y_mm
            history[side, body] = (y, np.zeros(y.size))
    return history


def raised_history(history: History, results: list[ConditionResult]) -> History:
    """p_hist = max(p_hist, the peak pressures of the step's ``results``) at every (side, body)'s coordinates; the
    arrays of ``history`` are not changed."""
    out = {key: (y, p.copy()) for key, (y, p) in history.items()}
    for r in results:
        for body, patches in r.peaks.items():
            if (r.side, body) not in out:
                continue
            y, p = out[r.side, body]
            for ys, pk in patches:
                order = np.argsort(ys)
                ys, pk = ys[order], pk[order]
                inside = (y >= ys[0]) & (y <= ys[-1])
                p[inside] = np.maximum(p[inside], np.interp(y[inside], ys, pk))
    return out


def side_layers(layers: LayerSources | None, history: History | None, side: str,
                tables: dict | None = None) -> LayerSources | None:
    """The layers of one side: ``layers`` (or the tables recalibrated on the worn profiles, ``tables[(side,
    body)]``), every table position hardened to its largest peak pressure so far when a ``history`` is given. A
    combined characteristic has no positions: returned as it is."""
    if layers is None or layers.combined is not None:
        return layers
    tables = tables or {}
    chosen = {}
    for body in BODIES:
        table = tables.get((side, body), getattr(layers, body))
        if history and table is not None and (side, body) in history:
            y, p = history[side, body]
            table = HardenedTable(table, y, p)
        chosen[body] = table
    names = {**layers.names, **{b: f"recalibrated {b} table" for (s, b) in tables if s == side}}
    return LayerSources(rail=chosen["rail"], wheel=chosen["wheel"], names=names,
                           scale_to_patch=layers.scale_to_patch)


__all__ = ["History", "HardenedTable", "hardened", "raised_history", "side_layers", "virgin_history"]
