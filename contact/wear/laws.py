"""Abrasive wear laws applied cell by cell to a FASTSIM solution (units mm, N, MPa, s; wear depths in mm).

Both laws turn the frictional quantities of every FASTSIM cell (:class:`contact.tangential.fastsim.TangentialResult`)
into a wear depth of the body's surface per pass. A material point of a strip crosses every cell of its strip
once per pass, so the depth per strip per pass is the sum over the strip's cells (the integral in the rolling
direction).

Archard (Archard 1953; coefficient map of Jendel 2002, Wear 253, 89-99)
-----------------------------------------------------------------------
Worn volume = k N s / H, so per unit area the depth of a cell is dz = k p s / H with p the cell's normal pressure
(MPa), s the slip distance accumulated in the cell (mm) and H the hardness (MPa). The dimensionless coefficient k
depends on the regime (Jendel's map, as reproduced e.g. by Braghin et al. 2006 and Enblom & Berg 2005):

    K1  p > 0.8 H                        k = 300..400e-4   (seizure)
    K2  p <= 0.8 H, v_slip <= 0.2 m/s    k = 1..10e-4      (mild)
    K3  p <= 0.8 H, 0.2 < v_slip <= 0.7  k = 30..40e-4     (severe)
    K4  p <= 0.8 H, v_slip > 0.7 m/s     k = 1..10e-4      (mild, oxidative)

The map gives ranges; the defaults are the middle of each range (350e-4, 5.5e-4, 35e-4, 5.5e-4) and each value is
a scene key. (The map was built for dry contact; Enblom & Berg scale it down for wet and lubricated contact.)
H defaults to 2550 MPa (260 HB, the minimum hardness of rail grade R260, 1 HB = 9.807 MPa) for both
bodies; set it per body. The thresholds (0.8 H, 0.2 and 0.7 m/s), the k ranges and their assignment to the
velocity bands follow the map as reproduced in the secondary literature; neither Jendel's figure nor a secondary
source reproducing it could be read to check them (searches listed in docs/wear.md). Every map carries a
``source`` text that result.json records with the coefficients.

USFD T-gamma law (Lewis & Dwyer-Joyce 2004; Braghin et al. 2006, Wear 261, 1253-1264)
--------------------------------------------------------------------------------------
Wear rate K (ug of material per metre rolled per mm^2 of contact) against the local frictional work per unit
area per unit rolled distance T gamma / A (N/mm^2). Published regimes for R8T wheel steel against rail (twin-disc):

    T gamma/A < 10.4             K = 5.3 T gamma/A       (mild)
    10.4 <= T gamma/A <= 77.2    K = 55.0                (severe)
    T gamma/A > 77.2             K = 61.9 T gamma/A - 4778.7   (catastrophic)

(implemented as read from Braghin et al. 2006 when the law was added, including the drop of K at 77.2 where the
catastrophic line starts near 0; the table could not be re-read in the later source check, docs/wear.md).
The local T gamma / A of a cell is its frictional work per unit area (N/mm) divided by the cell length (mm). A
material point spends dx/V in a cell, so its depth increment there is K dx / rho (dx in m, rho in ug/mm^3, which is
numerically rho in kg/m^3). The coefficients for R260 (or UIC60 900A / R220) rail steel could not be found in a
source readable to this project (searches listed in docs/wear.md); a scene table takes any three-regime table
(thresholds and coefficients), and the default applies the R8T regimes to the rail as well, stated in the shipped
scene file and in result.json (``inputs.usfd.rail.name`` and ``.source``).
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields

import numpy as np

from contact.tangential.fastsim import TangentialResult
from wrlayer.errors import InputError, require

LAWS = ("archard", "usfd")

JENDEL_SOURCE = ("Jendel 2002, Wear 253, 89-99 (coefficient map, dry contact), as reproduced in secondary "
                 "wheel-wear papers; thresholds, ranges and band assignment not checked against a readable source "
                 "(docs/wear.md); defaults = middle of each range")
R8T_SOURCE = ("R8T wheel steel regimes (twin-disc), Braghin et al. 2006, Wear 261, 1253-1264 / Lewis & Dwyer-Joyce "
              "2004; for rail steel no published table could be read (docs/wear.md)")


@dataclass(frozen=True)
class ArchardMap:
    """Jendel's Archard coefficient map (dimensionless k) and the body's hardness H (MPa): ``[wear.archard.wheel]``,
    ``[wear.archard.rail]``.

    Attributes
    ----------
    hardness_MPa : float
        Hardness H of the body (MPa); default 2550 MPa = 260 HB (rail grade R260).
    k_seizure : float
        k where p > seizure_pressure_ratio x H (regime K1, seizure; -).
    k_low_speed : float
        k at slip velocities up to v_low_m_s (regime K2, mild; -).
    k_mid_speed : float
        k at slip velocities between v_low_m_s and v_high_m_s (regime K3, severe; -).
    k_high_speed : float
        k at slip velocities above v_high_m_s (regime K4, mild oxidative; -).
    v_low_m_s : float
        Upper slip velocity of the low-speed band (m/s).
    v_high_m_s : float
        Upper slip velocity of the middle band (m/s).
    seizure_pressure_ratio : float
        p / H above which k_seizure applies (-).
    source : str
        Where the map values come from; left empty it is filled in: :data:`JENDEL_SOURCE` when every map value
        (all but the hardness) is the default, else ``"scene values"`` (recorded in result.json).
    """

    hardness_MPa: float = 2550.0
    k_seizure: float = 350e-4
    k_low_speed: float = 5.5e-4
    k_mid_speed: float = 35e-4
    k_high_speed: float = 5.5e-4
    v_low_m_s: float = 0.2
    v_high_m_s: float = 0.7
    seizure_pressure_ratio: float = 0.8
    source: str = ""

    def __post_init__(self):
        if not self.source:
            default = all(getattr(self, f.name) == f.default for f in fields(self)
                          if f.name not in ("hardness_MPa", "source"))
            object.__setattr__(self, "source", JENDEL_SOURCE if default else "scene values")
        for key in ("hardness_MPa", "v_low_m_s", "v_high_m_s", "seizure_pressure_ratio"):
            v = getattr(self, key)
            require(bool(np.isfinite(v)) and v > 0, key, f"must be a positive number, got {v!r}")
        for key in ("k_seizure", "k_low_speed", "k_mid_speed", "k_high_speed"):
            v = getattr(self, key)
            require(bool(np.isfinite(v)) and v >= 0, key, f"must be a number >= 0, got {v!r}")
        require(self.v_high_m_s > self.v_low_m_s, "v_high_m_s", "must exceed v_low_m_s")

    def coefficient(self, p_MPa: np.ndarray, v_slip_m_s: np.ndarray) -> np.ndarray:
        """k by regime (same shape as the inputs)."""
        p, v = np.asarray(p_MPa, float), np.asarray(v_slip_m_s, float)
        k = np.where(v <= self.v_low_m_s, self.k_low_speed,
                     np.where(v <= self.v_high_m_s, self.k_mid_speed, self.k_high_speed))
        return np.where(p > self.seizure_pressure_ratio * self.hardness_MPa, self.k_seizure, k)


@dataclass(frozen=True)
class UsfdTable:
    """Three-regime USFD wear function: K (ug/(m mm^2)) of T gamma / A (N/mm^2): a table ``[wear.usfd.wheel]``,
    ``[wear.usfd.rail]``, or a published material by name.

    K = mild_slope x                   for x < t1
    K = severe_rate                    for t1 <= x <= t2
    K = cat_slope x - cat_offset       for x > t2

    Attributes
    ----------
    name : str
        The material's name (``"R8T"``; a scene table is ``"custom <body>"``).
    t1 : float
        T gamma / A where the mild regime ends (N/mm^2).
    t2 : float
        T gamma / A where the severe regime ends (N/mm^2).
    mild_slope : float
        Slope of K in the mild regime (ug/(m mm^2) per N/mm^2).
    severe_rate : float
        K in the severe regime (ug/(m mm^2)).
    cat_slope : float
        Slope of K in the catastrophic regime (ug/(m mm^2) per N/mm^2).
    cat_offset : float
        Offset of K in the catastrophic regime (ug/(m mm^2)).
    source : str
        Where the table comes from; left empty it is filled in: :data:`R8T_SOURCE` for the R8T table, else
        ``"scene table"`` (recorded in result.json).
    """

    name: str = "R8T"
    t1: float = 10.4
    t2: float = 77.2
    mild_slope: float = 5.3
    severe_rate: float = 55.0
    cat_slope: float = 61.9
    cat_offset: float = 4778.7
    source: str = ""

    def __post_init__(self):
        if not self.source:
            r8t = all(getattr(self, f.name) == f.default for f in fields(self) if f.name != "source")
            object.__setattr__(self, "source", R8T_SOURCE if r8t else "scene table")
        require(0 < self.t1 < self.t2, f"usfd.{self.name}", f"needs 0 < t1 < t2, got {self.t1}, {self.t2}")
        for key in ("mild_slope", "severe_rate", "cat_slope"):
            require(getattr(self, key) >= 0, f"usfd.{self.name}.{key}", "must be >= 0")

    def rate(self, tgamma_per_area: np.ndarray) -> np.ndarray:
        """Wear rate K (ug/(m mm^2)), never negative."""
        x = np.asarray(tgamma_per_area, float)
        k = np.where(x < self.t1, self.mild_slope * x,
                     np.where(x <= self.t2, self.severe_rate, self.cat_slope * x - self.cat_offset))
        return np.clip(k, 0.0, None)


USFD_MATERIALS = {"R8T": UsfdTable()}


@dataclass(frozen=True)
class WearLaw:
    """The selected abrasive wear law with per-body coefficients (``[wear]`` ``law`` and its tables).

    Attributes
    ----------
    name : str
        The law, scene key ``law``: ``"archard"`` or ``"usfd"``.
    archard : dict
        ``archard[body]``: :class:`ArchardMap` of the wheel and the rail (``[wear.archard.<body>]``).
    usfd : dict
        ``usfd[body]``: :class:`UsfdTable` of the wheel and the rail (``[wear.usfd]``).
    density_kg_m3 : float
        Steel density (kg/m^3, numerically ug/mm^3): the USFD depth and the mass loss.
    """

    name: str = "archard"
    archard: dict = field(default_factory=lambda: {"wheel": ArchardMap(), "rail": ArchardMap()})
    usfd: dict = field(default_factory=lambda: {"wheel": UsfdTable(), "rail": UsfdTable()})
    density_kg_m3: float = 7850.0

    def __post_init__(self):
        if self.name not in LAWS:
            raise InputError("wear.law", f"must be one of {', '.join(LAWS)}, got {self.name!r}")
        require(self.density_kg_m3 > 0, "wear.density_kg_m3", f"must be > 0, got {self.density_kg_m3!r}")


@dataclass(frozen=True)
class CellWear:
    """Frictional quantities and wear of one FASTSIM result, per cell (ny, nx) and per strip (ny,).

    work_N_per_mm: frictional work per unit area in the cell per pass (N mm/mm^2); slip_mm: slip distance in the
    cell; tgamma_per_area_N_per_mm2: local T gamma / A (work per area per rolled length); depth_mm[body]: wear depth
    per pass per cell; strip_depth_mm[body]: per strip per pass (sum over the strip's cells).
    """

    y_mm: np.ndarray
    work_N_per_mm: np.ndarray
    slip_mm: np.ndarray
    tgamma_per_area_N_per_mm2: np.ndarray
    depth_mm: dict
    strip_depth_mm: dict


def cell_work(t: TangentialResult) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(work per area per cell (N/mm), slip distance per cell (mm), T gamma / A per cell (N/mm^2))."""
    wf = np.asarray(t.WT_field_N_per_mm, float)
    work = np.diff(np.concatenate([np.zeros((wf.shape[0], 1)), wf], axis=1), axis=1)
    dx = np.asarray(t.dx_mm, float)[:, None]
    slip = np.asarray(t.slip_velocity_mm_s, float) * dx / t.speed_mm_s
    return work, slip, work / dx


def wear_of(t: TangentialResult, law: WearLaw) -> CellWear:
    """Wear depth per pass of both bodies for one FASTSIM result (see the module docstring)."""
    work, slip, tga = cell_work(t)
    dx = np.asarray(t.dx_mm, float)[:, None] * np.ones_like(work)
    depth = {}
    for body in ("wheel", "rail"):
        if law.name == "archard":
            m: ArchardMap = law.archard[body]
            v = np.asarray(t.slip_velocity_mm_s, float) * 1e-3
            k = m.coefficient(t.pn_MPa, v)
            depth[body] = k * np.asarray(t.pn_MPa, float) * slip / m.hardness_MPa
        else:
            tab: UsfdTable = law.usfd[body]
            depth[body] = tab.rate(tga) * (dx * 1e-3) / law.density_kg_m3
    return CellWear(np.asarray(t.y_mm, float), work, slip, tga, depth,
                    {b: d.sum(axis=1) for b, d in depth.items()})


__all__ = ["JENDEL_SOURCE", "LAWS", "R8T_SOURCE", "USFD_MATERIALS", "ArchardMap", "CellWear", "UsfdTable", "WearLaw",
           "cell_work", "wear_of"]
