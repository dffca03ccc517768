"""The inputs of one wheel on its rail: everything but the profiles (:class:`WheelRailInputs`) and the layers
(:class:`WheelRailLayers`) (units mm, N, MPa, s, rad).

The Python API takes Young's modulus and Poisson's ratio (``E_MPa``, ``poisson``); a scene may give the shear
modulus instead (converted when the scene is read, :func:`wrlayer.elastic.youngs_modulus_MPa`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from wrlayer.characteristic import Characteristic
from contact.layer.strip_lookup import LayerLookup
from contact.normal.method import NormalMethod
from contact.passes.passes import PassesOptions
from contact.tangential.method import TANGENTIAL_METHODS
from contact.wheel_rail.contact_search import SearchSettings
from contact.wheel_rail.reference_point import check_contact_point
from contact.wheel_rail.track_geometry import TrackLayout, WheelsetPose, side_sign
from wrlayer.elastic import shear_modulus_MPa
from wrlayer.errors import require

#: ``method.balance``: "total" (the vertical component of normal + tangential forces equals the load) or "normal"
#: (normal forces only; the earlier model, kept for comparison).
BALANCES = ("total", "normal")


@dataclass(frozen=True)
class WheelRailLayers:
    """Layer tables per body (``rail``, ``wheel``; either may be None) or one ``combined`` characteristic (the
    paper's eq. 13 layer of both bodies). ``names``: body -> table name for messages and the result;
    ``scale_to_patch``: scale the tables' characteristics to each patch's solved semi-axes
    (:mod:`contact.wheel_rail.solve`)."""

    rail: LayerLookup | None = None
    wheel: LayerLookup | None = None
    combined: Characteristic | None = None
    names: dict = field(default_factory=dict)
    scale_to_patch: bool = False

    def __post_init__(self):
        require(self.combined is None or (self.rail is None and self.wheel is None), "layers",
                "give either per-body tables (rail, wheel) or one combined characteristic, not both")
        require(not (self.scale_to_patch and self.combined is not None), "layers.scale_to_patch",
                "only used with calibration tables (rail, wheel), not with a combined characteristic")

    @property
    def empty(self) -> bool:
        return self.rail is None and self.wheel is None and self.combined is None

    def name(self, body: str) -> str:
        """The table name of ``body`` (for messages)."""
        return self.names.get(body, body)


@dataclass(frozen=True)
class WheelRailInputs:
    """Everything but the profiles for one wheel on its rail (units mm, N, MPa, s, rad).

    Attributes
    ----------
    layout : TrackLayout
        Track and wheelset dimensions (mm, rad).
    pose : WheelsetPose
        Lateral displacement (mm), yaw and roll (rad) of the wheelset.
    side : str
        "right" or "left": the wheel solved.
    vertical_load_N : float
        Vertical wheel load Q (N).
    speed_mm_s : float
        Rolling speed V (mm/s).
    pitch_rate_rad_s : float | None
        Wheelset pitch rate (rad/s); None: pure rolling at the nominal radius, V / r0.
    yaw_rate_rad_s : float
        Wheelset yaw rate (rad/s): -V / R in a steady curve of signed radius R (positive to the left), 0 on
        straight track (:func:`contact.wheel_rail.kinematics.creepages`).
    friction : float
        Coulomb friction coefficient mu (-); 0: no tangential solution.
    E_MPa : float
        Young's modulus of both bodies (MPa).
    poisson : float
        Poisson's ratio of both bodies (-).
    alpha : float
        Kik–Piotrowski's virtual penetration factor (-, paper eq. 9).
    grid_mm : float
        Strip grid spacing of the normal problem (mm).
    fastsim_cells : int
        FASTSIM cells per strip (-).
    passes : PassesOptions
        Repeated passes of the layer (paper section 5).
    search : SearchSettings
        Contact search settings (merge level, candidate gap, separation cap; mm).
    normal_method : NormalMethod
        The normal solver (``method.normal``).
    contact_point : str
        "first_contact" or "weighted_centre" (:mod:`contact.wheel_rail.reference_point`).
    balance : str
        "total" or "normal" (:data:`BALANCES`).
    tangential_method : str
        The tangential solver (``method.tangential``): "fastsim", "fastrip" or "exact".
    """

    layout: TrackLayout = field(default_factory=TrackLayout)
    pose: WheelsetPose = field(default_factory=WheelsetPose)
    side: str = "right"
    vertical_load_N: float = 10000.0
    speed_mm_s: float = 2000.0
    pitch_rate_rad_s: float | None = None
    yaw_rate_rad_s: float = 0.0
    friction: float = 0.3
    E_MPa: float = 210000.0
    poisson: float = 0.28
    alpha: float = 0.55
    grid_mm: float = 0.1
    fastsim_cells: int = 60
    passes: PassesOptions = field(default_factory=lambda: PassesOptions(max_passes=1))
    search: SearchSettings = field(default_factory=SearchSettings)
    normal_method: NormalMethod = field(default_factory=NormalMethod)
    contact_point: str = "first_contact"
    balance: str = "total"
    tangential_method: str = "fastsim"

    def __post_init__(self):
        side_sign(self.side)
        check_contact_point(self.contact_point)
        require(self.balance in BALANCES, "method.balance", f"must be one of {', '.join(BALANCES)}, got "
                f"{self.balance!r}")
        for key in ("vertical_load_N", "speed_mm_s", "E_MPa", "grid_mm"):
            v = getattr(self, key)
            require(bool(np.isfinite(v)) and v > 0, key, f"must be a positive number, got {v!r}")
        require(bool(np.isfinite(self.friction)) and self.friction >= 0, "friction",
                f"must be >= 0, got {self.friction!r}")
        require(self.tangential_method in TANGENTIAL_METHODS, "method.tangential",
                f"must be one of {', '.join(TANGENTIAL_METHODS)}, got {self.tangential_method!r}")
        require(0.0 <= self.poisson < 0.5, "poisson", f"must lie in [0, 0.5), got {self.poisson!r}")

    @property
    def G_MPa(self) -> float:
        """Shear modulus (MPa)."""
        return shear_modulus_MPa(self.E_MPa, self.poisson)

    @property
    def omega_rad_s(self) -> float:
        """Pitch rate (rad/s): ``pitch_rate_rad_s`` or V / r0."""
        return self.speed_mm_s / self.layout.nominal_radius_mm if self.pitch_rate_rad_s is None \
            else float(self.pitch_rate_rad_s)


__all__ = ["BALANCES", "WheelRailInputs", "WheelRailLayers"]
