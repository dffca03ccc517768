"""The typed wheel–rail scene: one frozen dataclass per TOML section, field names = TOML keys (units mm, N, MPa, s,
rad). Built once from the TOML content by :func:`contact.wheel_rail.parse.parse_wheel_rail_scene`; the cost
estimate, the run and the wear loop read it.

The scene records the inputs as given (resolved: defaults filled in, ``inclination`` 1:n as ``inclination_rad``,
``G_MPa`` as ``E_MPa``, file names as resolved paths); the profiles and calibration tables it names are read once
when it is built and kept beside the inputs (not compared, not written by :meth:`WheelRailScene.to_dict`;
:meth:`WheelRailScene.from_dict` reads them again).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from contact.normal.method import NormalMethod
from contact.scenes.result_io import Record
from contact.scenes.scene_spec import PassesSpec
from contact.wheel_rail.contact_search import SearchSettings
from contact.wheel_rail.inputs import WheelRailInputs, WheelRailLayers
from contact.wheel_rail.layers_spec import LayersSpec
from contact.wheel_rail.scene_files import read_profile
from contact.wheel_rail.sweep_spec import CaseSpec, SweepSpec
from contact.wheel_rail.track_geometry import TrackLayout, WheelsetPose
from meshes.profiles import Profile
from wrlayer.elastic import shear_modulus_MPa


@dataclass(frozen=True)
class ProfilesSpec(Record):
    """[profiles]: the profiles as the scene names them.

    Attributes
    ----------
    rail : str
        Rail profile: a standard name (e.g. "60E1") or a profile file (.prr/.txt/.csv, relative to the scene file,
        or "reference:NAME" in the shared reference folder).
    wheel : str
        Wheel profile: a standard name (e.g. "S1002") or a profile file (.prw/.txt/.csv), as ``rail``.
    accept_unusual_profile : bool
        Read profile files without the plausibility checks (units, orientation, steps, spikes;
        :mod:`meshes.profiles.plausibility`): for a profile that is unusual on purpose.
    """

    rail: str = "60E1"
    wheel: str = "S1002"
    accept_unusual_profile: bool = False


@dataclass(frozen=True)
class TrackSpec(Record):
    """[track]: the track dimensions.

    Attributes
    ----------
    gauge_mm : float
        Track gauge between the gauge points (mm).
    gauge_depth_mm : float
        Depth of the gauge points below the rail top (mm).
    inclination_rad : float
        Rail cant towards the track centre (rad); the scene may give ``inclination`` = n of 1:n instead
        (atan(1/n); 0: upright).
    back_to_back_mm : float
        Distance between the wheels' flange backs (mm).
    flange_back_y_mm : float
        Wheel profile coordinate of the flange back (mm).
    """

    gauge_mm: float = 1435.0
    gauge_depth_mm: float = 14.0
    inclination_rad: float = math.atan(1.0 / 40.0)
    back_to_back_mm: float = 1360.0
    flange_back_y_mm: float = -70.0


@dataclass(frozen=True)
class WheelSpec(Record):
    """[wheel]: the wheel radius and the simulated side(s).

    Attributes
    ----------
    nominal_radius_mm : float
        Rolling radius at the wheel profile's y = 0 (taping line) (mm).
    side : str
        "right", "left" or "both" (-).
    """

    nominal_radius_mm: float = 460.0
    side: str = "right"


@dataclass(frozen=True)
class WheelsetSpec(Record):
    """[wheelset]: the wheelset pose and pitch rate of the single case (a sweep may vary them per case).

    Attributes
    ----------
    lateral_mm : float
        Lateral displacement towards the right rail (mm).
    yaw_rad : float
        Yaw angle, counter-clockwise seen from above (rad).
    roll_rad : float | str
        Roll angle lifting the right wheel (rad), or "auto": the rigid wheelset's roll at which both wheels touch.
    pitch_rate_rad_s : float | None
        Pitch rate (rad/s); None: speed / nominal radius (pure rolling).
    """

    lateral_mm: float = 0.0
    yaw_rad: float = 0.0
    roll_rad: float | str = 0.0
    pitch_rate_rad_s: float | None = None

    @property
    def roll_auto(self) -> bool:
        return self.roll_rad == "auto"


@dataclass(frozen=True)
class LoadSpec(Record):
    """[load]: load and speed of the single case (a sweep may vary them per case).

    Attributes
    ----------
    vertical_load_N : float
        Vertical load per wheel Q (N).
    speed_mm_s : float
        Rolling speed V (mm/s).
    """

    vertical_load_N: float = 10000.0
    speed_mm_s: float = 2000.0


@dataclass(frozen=True)
class MaterialSpec(Record):
    """[material]: elastic constants of wheel and rail (the scene may give ``G_MPa`` instead of ``E_MPa``).

    Attributes
    ----------
    E_MPa : float
        Young's modulus (MPa).
    poisson : float
        Poisson's ratio (-).
    """

    E_MPa: float = 210000.0
    poisson: float = 0.28

    @property
    def G_MPa(self) -> float:
        """Shear modulus E / (2 (1 + nu)) (MPa)."""
        return shear_modulus_MPa(self.E_MPa, self.poisson)


@dataclass(frozen=True)
class TangentialSpec(Record):
    """[tangential]: the friction of the tangential solution (``method.tangential``).

    Attributes
    ----------
    friction : float
        Coulomb friction coefficient mu (-); 0: no tangential solution.
    """

    friction: float = 0.3


@dataclass(frozen=True)
class MethodSpec(Record):
    """[method]: solver settings.

    Attributes
    ----------
    alpha : float
        Kik–Piotrowski's virtual penetration factor (-, paper eq. 9).
    grid_mm : float
        Strip grid spacing of the normal problem (mm).
    fastsim_cells : int
        FASTSIM cells per strip (-).
    merge_mm : float
        Barrier height below which neighbouring gap minima are one contact candidate (mm).
    candidate_gap_mm : float
        Largest gap above the first contact of a kept contact candidate (mm).
    f_cap_mm : float
        The separation function is cut where it exceeds this (mm).
    normal : str
        The normal solver: "kik_piotrowski", "exact" or "coarse_exact" (the half-space on a coarse grid) (-).
    exact_cells : int | None
        Exact solver grid: cells along x over the patch length (-); None: the solver's default.
    layer_mode : str
        Exact solver's layer mode: "indentation" or "rolling" (-).
    contact_point : str
        The reported point of a patch, where creepages are evaluated: "first_contact" or "weighted_centre" (-).
    balance : str
        Vertical load balance: "total" (normal + tangential forces) or "normal" (normal forces only) (-).
    tangential : str
        The tangential solver: "fastsim" (Kalker's simplified theory), "fastrip" (FaStrip) or "exact" (Kalker's
        full theory on the grid) (-; docs/tangential.md).
    """

    alpha: float = 0.55
    grid_mm: float = 0.1
    fastsim_cells: int = 60
    merge_mm: float = 0.005
    candidate_gap_mm: float = 1.0
    f_cap_mm: float = 2.0
    normal: str = "kik_piotrowski"
    exact_cells: int | None = None
    layer_mode: str = "indentation"
    contact_point: str = "first_contact"
    balance: str = "total"
    tangential: str = "fastsim"

    @property
    def normal_method(self) -> NormalMethod:
        return NormalMethod(self.normal, exact_cells=self.exact_cells, layer_mode=self.layer_mode)

    @property
    def search(self) -> SearchSettings:
        return SearchSettings(merge_mm=self.merge_mm, candidate_gap_mm=self.candidate_gap_mm, f_cap_mm=self.f_cap_mm)


@dataclass(frozen=True)
class OutputSpec(Record):
    """[output]: extra output files.

    Attributes
    ----------
    deformed_profiles : bool
        With layers: write each case's deformed rail and wheel profiles (SIMPACK .prr/.prw and CSV) (-).
    vtk : bool
        Write the patches' fields for ParaView (vtk/contact_fields.pvd over the cases, one .vtu per case, wheel and
        patch) (-).
    convention : str
        "wrlayer" (default) or "contact": also write every patch in CONTACT's sign convention
        (contact_convention.csv; docs/conventions.md) (-).
    contact_table : bool
        Also write the contact table for multibody codes (contact_table.csv, one row per case, wheel and loaded
        patch; docs/contact-tables.md) (-).
    frictional_csv : bool
        Write the wear-ready frictional CSVs (frictional_cells.csv, frictional_strips.csv: every FASTSIM cell and
        strip; about 0.9 MB and 0.1 s per elastic case of both wheels) (-).
    """

    deformed_profiles: bool = True
    vtk: bool = True
    convention: str = "wrlayer"
    contact_table: bool = False
    frictional_csv: bool = True


@dataclass(frozen=True)
class RunSpec(Record):
    """[run]: where the cases are solved (:class:`wrlayer.runner.Runner`; the numbers do not depend on it).

    Attributes
    ----------
    workers : int
        Local worker processes solving the cases, one BLAS thread each (1: one after the other in this process) (-).
    scheduler : str
        Dask scheduler address, e.g. "tcp://host:8786" ("": local); with it the cases run on the cluster.
    """

    workers: int = 1
    scheduler: str = ""

    @property
    def parallel(self) -> bool:
        """True when the cases go through the runner (several workers or a scheduler)."""
        return self.workers > 1 or bool(self.scheduler)


#: The sections of a wheel–rail scene with their dataclasses (the order of :meth:`WheelRailScene.to_dict`).
SECTIONS = {"profiles": ProfilesSpec, "track": TrackSpec, "wheel": WheelSpec, "wheelset": WheelsetSpec,
            "load": LoadSpec, "material": MaterialSpec, "tangential": TangentialSpec, "layers": LayersSpec,
            "passes": PassesSpec, "method": MethodSpec, "sweep": SweepSpec, "output": OutputSpec, "run": RunSpec}


@dataclass(frozen=True)
class WheelRailScene:
    """A validated wheel–rail scene (:mod:`contact.wheel_rail.parse` lists the keys).

    Attributes
    ----------
    path : Path
        The scene file (relative file names in it are taken from its folder).
    title : str
        Free text.
    description : str
        Free text.
    profiles, track, wheel, wheelset, load, material, tangential, passes, method, sweep, output, run : Record
        The sections (see their classes).
    layers : LayersSpec | None
        [layers]; None: elastic bodies.
    data : dict
        The TOML content as read (echoed in the result).
    rail_profile : Profile
        The rail profile as read (not compared).
    wheel_profile : Profile
        The wheel profile as read (not compared).
    """

    path: Path
    title: str
    description: str
    profiles: ProfilesSpec
    track: TrackSpec
    wheel: WheelSpec
    wheelset: WheelsetSpec
    load: LoadSpec
    material: MaterialSpec
    tangential: TangentialSpec
    layers: LayersSpec | None
    passes: PassesSpec
    method: MethodSpec
    sweep: SweepSpec
    output: OutputSpec
    run: RunSpec = field(default_factory=RunSpec)
    data: dict = field(default_factory=dict)
    rail_profile: Profile | None = field(default=None, compare=False, repr=False)
    wheel_profile: Profile | None = field(default=None, compare=False, repr=False)

    def __repr__(self) -> str:
        return (f"WheelRailScene({self.path.name}: {self.profiles.rail}/{self.profiles.wheel}, sides {self.sides}, "
                f"{len(self.cases)} cases, layers {'none' if self.layers is None else 'yes'})")

    @property
    def layout(self) -> TrackLayout:
        """Track and wheelset dimensions (mm, rad)."""
        t = self.track
        return TrackLayout(gauge_mm=t.gauge_mm, gauge_depth_mm=t.gauge_depth_mm, inclination_rad=t.inclination_rad,
                           back_to_back_mm=t.back_to_back_mm, flange_back_y_mm=t.flange_back_y_mm,
                           nominal_radius_mm=self.wheel.nominal_radius_mm)

    @property
    def sides(self) -> list[str]:
        """The simulated wheels: ["right"], ["left"] or ["right", "left"]."""
        return ["right", "left"] if self.wheel.side == "both" else [self.wheel.side]

    @property
    def roll_auto(self) -> bool:
        return self.wheelset.roll_auto

    @property
    def cases(self) -> tuple[CaseSpec, ...]:
        return self.sweep.cases

    @property
    def solver_layers(self) -> WheelRailLayers | None:
        """The layers for the solver (None without [layers])."""
        return None if self.layers is None else self.layers.solver

    def inputs(self, side: str = "right", pose: WheelsetPose | None = None, case: CaseSpec | None = None
               ) -> WheelRailInputs:
        """The solver inputs of one wheel: the scene's settings with the case's pitch rate, load and speed (the
        scene's [wheelset]/[load] without a case)."""
        m = self.method
        pitch = self.wheelset.pitch_rate_rad_s if case is None else case.pitch_rate_rad_s
        load = self.load if case is None else case
        return WheelRailInputs(layout=self.layout, pose=pose or WheelsetPose(), side=side,
                               vertical_load_N=load.vertical_load_N, speed_mm_s=load.speed_mm_s,
                               pitch_rate_rad_s=pitch, friction=self.tangential.friction,
                               E_MPa=self.material.E_MPa, poisson=self.material.poisson, alpha=m.alpha,
                               grid_mm=m.grid_mm, fastsim_cells=m.fastsim_cells, passes=self.passes.options,
                               search=m.search, normal_method=m.normal_method, contact_point=m.contact_point,
                               balance=m.balance, tangential_method=m.tangential)

    def to_dict(self) -> dict[str, Any]:
        """Plain data (the resolved inputs; the profiles and tables by name)."""
        out: dict[str, Any] = {"path": str(self.path), "title": self.title, "description": self.description}
        for name in SECTIONS:
            value = getattr(self, name)
            out[name] = None if value is None else value.to_dict()
        out["data"] = self.data
        return out

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> WheelRailScene:
        """The scene of :meth:`to_dict` (profiles and tables read again)."""
        path = Path(data["path"])
        sections = {name: None if data[name] is None else kind.from_dict(data[name])
                    for name, kind in SECTIONS.items()}
        profiles = sections["profiles"]
        return cls(path, data["title"], data["description"], **sections, data=data["data"],
                   rail_profile=read_profile(profiles.rail, path.parent, "rail", f"{path.name}: profiles.rail"),
                   wheel_profile=read_profile(profiles.wheel, path.parent, "wheel", f"{path.name}: profiles.wheel"))


__all__ = ["SECTIONS", "LoadSpec", "MaterialSpec", "MethodSpec", "OutputSpec", "PassesSpec", "ProfilesSpec", "RunSpec",
           "TangentialSpec", "TrackSpec", "WheelRailScene", "WheelSpec", "WheelsetSpec"]
