"""The inputs of one wheel on its rail: the scene's sections (:mod:`contact.scenes.sections`,
:mod:`contact.wheel_rail.sections`) with the track layout, the wheelset pose and the simulated side (units mm, N,
MPa, s, rad). The layers are :class:`contact.scenes.layers.LayerSources`.

The Python API takes Young's modulus and Poisson's ratio (:class:`contact.scenes.sections.MaterialSpec`); a scene may
give the shear modulus instead (converted when the scene is read, :func:`wrlayer.elastic.youngs_modulus_MPa`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from contact.normal.method import NormalMethod
from contact.scenes.sections import MaterialSpec, PassesSpec, TangentialSpec
from contact.wheel_rail.contact_search import SearchSettings
from contact.wheel_rail.reference_point import check_contact_point
from contact.wheel_rail.sections import BALANCES, WheelLoadSpec, WheelRailMethodSpec
from contact.wheel_rail.track_geometry import TrackLayout, WheelsetPose, side_sign
from wrlayer.errors import require


#: Plain name -> (section, key) of the section values the solvers read from :class:`WheelRailInputs`.
SECTION_OF = {"vertical_load_N": ("load", "vertical_load_N"), "speed_mm_s": ("load", "speed_mm_s"),
              "friction": ("tangential", "friction"), "E_MPa": ("material", "E_MPa"),
              "poisson": ("material", "poisson"), "G_MPa": ("material", "G_MPa"), "alpha": ("method", "alpha"),
              "grid_mm": ("method", "grid_mm"), "fastsim_cells": ("method", "fastsim_cells"),
              "contact_point": ("method", "contact_point"), "balance": ("method", "balance"),
              "tangential_method": ("method", "tangential")}


@dataclass(frozen=True)
class WheelRailInputs:
    """Everything but the profiles and the layers for one wheel on its rail (units mm, N, MPa, s, rad).

    Attributes
    ----------
    layout : TrackLayout
        Track and wheelset dimensions (mm, rad).
    pose : WheelsetPose
        Lateral displacement (mm), yaw and roll (rad) of the wheelset.
    side : str
        "right" or "left": the wheel solved.
    load : WheelLoadSpec
        Vertical wheel load Q (N) and rolling speed V (mm/s).
    pitch_rate_rad_s : float | None
        Wheelset pitch rate (rad/s); None: pure rolling at the nominal radius, V / r0.
    yaw_rate_rad_s : float
        Wheelset yaw rate (rad/s): -V / R in a steady curve of signed radius R (positive to the left), 0 on
        straight track (:func:`contact.wheel_rail.kinematics.creepages`).
    creepages : tuple or None
        Creepages (vx, vy, phi (1/mm)) of this wheel given from outside (a multibody export), used at every patch
        instead of the kinematic ones; None: from the kinematics.
    material : MaterialSpec
        Young's modulus (MPa) and Poisson's ratio (-) of both bodies.
    tangential : TangentialSpec
        Coulomb friction coefficient mu (-); 0: no tangential solution.
    method : WheelRailMethodSpec
        Solver settings (alpha, strip grid, FASTSIM cells, normal and tangential solvers, contact search, reference
        point, balance).
    passes : PassesSpec
        Repeated passes of the layer (paper section 5).
    """

    layout: TrackLayout = field(default_factory=TrackLayout)
    pose: WheelsetPose = field(default_factory=WheelsetPose)
    side: str = "right"
    load: WheelLoadSpec = field(default_factory=WheelLoadSpec)
    pitch_rate_rad_s: float | None = None
    yaw_rate_rad_s: float = 0.0
    creepages: tuple[float, float, float] | None = None
    material: MaterialSpec = field(default_factory=MaterialSpec)
    tangential: TangentialSpec = field(default_factory=TangentialSpec)
    method: WheelRailMethodSpec = field(default_factory=WheelRailMethodSpec)
    passes: PassesSpec = field(default_factory=PassesSpec)

    def __post_init__(self):
        side_sign(self.side)
        m = self.method
        check_contact_point(m.contact_point)
        require(m.balance in BALANCES, "method.balance", f"must be one of {', '.join(BALANCES)}, got {m.balance!r}")
        for key, v in (("vertical_load_N", self.vertical_load_N), ("speed_mm_s", self.speed_mm_s),
                       ("E_MPa", self.E_MPa), ("grid_mm", self.grid_mm)):
            require(bool(np.isfinite(v)) and v > 0, key, f"must be a positive number, got {v!r}")
        require(bool(np.isfinite(self.friction)) and self.friction >= 0, "friction",
                f"must be >= 0, got {self.friction!r}")
        from contact.tangential.method import TANGENTIAL_METHODS  # here: the tangential solvers compile with numba

        require(m.tangential in TANGENTIAL_METHODS, "method.tangential",
                f"must be one of {', '.join(TANGENTIAL_METHODS)}, got {m.tangential!r}")
        require(0.0 <= self.poisson < 0.5, "poisson", f"must lie in [0, 0.5), got {self.poisson!r}")

    def __getattr__(self, name: str):
        """The section values the solvers read by their plain names (``vertical_load_N``, ``E_MPa``, ``alpha``,
        ``tangential_method``, ...; :data:`SECTION_OF`)."""
        if name not in SECTION_OF:
            raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")
        section, key = SECTION_OF[name]
        return getattr(getattr(self, section), key)

    @property
    def normal_method(self) -> NormalMethod:
        """The normal solver (``method.normal``)."""
        return self.method.normal_method()

    @property
    def search(self) -> SearchSettings:
        """Contact search settings (merge level, candidate gap, separation cap; mm)."""
        return self.method.search

    @property
    def omega_rad_s(self) -> float:
        """Pitch rate (rad/s): ``pitch_rate_rad_s`` or V / r0."""
        return self.speed_mm_s / self.layout.nominal_radius_mm if self.pitch_rate_rad_s is None \
            else float(self.pitch_rate_rad_s)


__all__ = ["BALANCES", "SECTION_OF", "WheelRailInputs"]
