"""The typed wheel–rail scene: one frozen dataclass per TOML section, field names = TOML keys (units mm, N, MPa, s,
rad). Built once from the TOML content by :func:`contact.wheel_rail.parse.parse_wheel_rail_scene`; the cost
estimate, the run and the wear loop read it.

The scene records the inputs as given (resolved: defaults filled in, ``inclination`` 1:n as ``inclination_rad``,
``G_MPa`` as ``E_MPa``, file names as resolved paths); the profiles and calibration tables it names are read once
when it is built and kept beside the inputs (not compared). :meth:`WheelRailScene.to_dict` is the inputs record of
result.json; :meth:`WheelRailScene.from_dict` parses its TOML content again.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from contact.scenes.layers import LayerSources, LayersSpec
from contact.scenes.result_io import Record
from contact.scenes.sections import MaterialSpec, PassesSpec, TangentialSpec
from contact.wheel_rail.inputs import WheelRailInputs
from contact.wheel_rail.sections import WheelLoadSpec, WheelRailMethodSpec, WheelRailOutputSpec
from wrlayer.hashing import file_sha256
from contact.wheel_rail.sweep_spec import CaseSpec, SweepSpec
from contact.wheel_rail.track_geometry import TrackLayout, WheelsetPose
from meshes.profiles import PROFILE_UNITS, Profile
from wrlayer.section_keys import key
from wrlayer.validate import MAX_RADIUS_MM, MIN_RADIUS_MM

#: Largest number of local worker processes of [run] (as the calibration's run.workers).
MAX_WORKERS = 64
#: Values of ``wheel.side``.
SIDES = ("right", "left", "both")


@dataclass(frozen=True)
class ProfilesSpec(Record):
    """[profiles]: the profiles as the scene names them.

    Attributes
    ----------
    rail : str
        Rail profile: a standard name (e.g. "60E1") or a profile file (.prr/.txt/.csv/.ban, relative to the scene
        file, or "reference:NAME" in the shared reference folder).
    wheel : str
        Wheel profile: a standard name (e.g. "S1002") or a profile file (.prw/.txt/.csv/.whl), as ``rail``.
    units : str | None
        Length unit of the profile files named ("mm" or "m"; both files); not given: mm for text, CSV and MiniProf
        files, the header's ``units.len.f`` for SIMPACK files (a given unit must agree with it).
    accept_unusual_profile : bool
        Read profile files without the plausibility checks (units, orientation, steps, spikes;
        :mod:`meshes.profiles.plausibility`): for a profile that is unusual on purpose.
    """

    rail: str = key("60E1")
    wheel: str = key("S1002")
    units: str | None = key(None, choices=tuple(PROFILE_UNITS))
    accept_unusual_profile: bool = key(False)


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

    gauge_mm: float = key(TrackLayout.gauge_mm, "mm", plausible="gauge_mm")
    gauge_depth_mm: float = key(TrackLayout.gauge_depth_mm, "mm", gt=0.0)
    inclination_rad: float = key(TrackLayout.inclination_rad, "rad", ge=-0.2, le=0.2)
    back_to_back_mm: float = key(TrackLayout.back_to_back_mm, "mm", gt=0.0)
    flange_back_y_mm: float = key(TrackLayout.flange_back_y_mm, "mm")


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

    nominal_radius_mm: float = key(TrackLayout.nominal_radius_mm, "mm", ge=MIN_RADIUS_MM, le=MAX_RADIUS_MM,
                                   plausible="wheel_radius_mm")
    side: str = key("right", choices=SIDES)


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

    lateral_mm: float = key(0.0, "mm")
    yaw_rad: float = key(0.0, "rad", ge=-0.2, le=0.2)
    roll_rad: float | str = field(default=0.0, metadata={"unit": "rad"})
    pitch_rate_rad_s: float | None = key(None, "rad/s")

    @property
    def roll_auto(self) -> bool:
        return self.roll_rad == "auto"


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

    workers: int = key(1, ge=1, le=MAX_WORKERS)
    scheduler: str = key("")

    @property
    def parallel(self) -> bool:
        """True when the cases go through the runner (several workers or a scheduler)."""
        return self.workers > 1 or bool(self.scheduler)


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
    load: WheelLoadSpec
    material: MaterialSpec
    tangential: TangentialSpec
    layers: LayersSpec | None
    passes: PassesSpec
    method: WheelRailMethodSpec
    sweep: SweepSpec
    output: WheelRailOutputSpec
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
    def solver_layers(self) -> LayerSources | None:
        """The layers for the solver (None without [layers])."""
        return None if self.layers is None else self.layers.sources

    def inputs(self, side: str = "right", pose: WheelsetPose | None = None, case: CaseSpec | None = None
               ) -> WheelRailInputs:
        """The solver inputs of one wheel: the scene's settings with the case's pitch rate, load and speed (the
        scene's [wheelset]/[load] without a case)."""
        pitch = self.wheelset.pitch_rate_rad_s if case is None else case.pitch_rate_rad_s
        load = self.load if case is None else WheelLoadSpec(case.vertical_load_N, case.speed_mm_s)
        return WheelRailInputs(layout=self.layout, pose=pose or WheelsetPose(), side=side, load=load,
                               pitch_rate_rad_s=pitch, material=self.material, tangential=self.tangential,
                               method=self.method, passes=self.passes)

    def to_dict(self) -> dict[str, Any]:
        """The resolved inputs as plain data (result.json "inputs"): the file and its sha256, the profiles by name,
        the track, sides, load, material and method as the solver uses them (defaults filled in), the layers' table
        names and sha256, and the TOML content as read (:meth:`from_dict` parses it again)."""
        lay, inp, layers = self.layout, self.inputs(), self.layers
        m = self.method
        return {
            "scene_file": str(self.path.resolve()),
            "content_sha256": file_sha256(self.path) if self.path.is_file() else None,
            "title": self.title, "description": self.description,
            "rail_profile": self.rail_profile.name, "wheel_profile": self.wheel_profile.name,
            "track": {**self.track.to_dict(), "nominal_radius_mm": lay.nominal_radius_mm},
            "sides": self.sides, "roll": "auto" if self.roll_auto else "given",
            "vertical_load_N": self.load.vertical_load_N, "speed_mm_s": self.load.speed_mm_s,
            "pitch_rate_rad_s": inp.omega_rad_s,
            "friction": self.tangential.friction, "E_MPa": self.material.E_MPa, "poisson": self.material.poisson,
            "G_MPa": self.material.G_MPa,
            "method": {"alpha": m.alpha, "grid_mm": m.grid_mm, "fastsim_cells": m.fastsim_cells, "normal": m.normal,
                       "exact_cells": m.exact_cells, "layer_mode": m.layer_mode, "contact_point": m.contact_point,
                       "balance": m.balance, **vars(m.search)},
            "sweep_csv": None if self.sweep.csv is None else self.sweep.csv.to_dict(),
            "passes": vars(self.passes.options),
            "layers": None if layers is None else (
                {"combined": layers.sources.combined.to_dict()} if layers.combined is not None else
                {**layers.sources.names, "sha256": layers.sha256}),
            "scene_toml": self.data,
        }

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> WheelRailScene:
        """The scene of :meth:`to_dict`: its TOML content parsed again (profiles and tables read again)."""
        from contact.wheel_rail.parse import parse_wheel_rail_scene  # here: the parser builds this class

        return parse_wheel_rail_scene(data["scene_toml"], Path(data["scene_file"]))


__all__ = ["MAX_WORKERS", "SIDES", "ProfilesSpec", "RunSpec", "TrackSpec", "WheelLoadSpec",
           "WheelRailMethodSpec", "WheelRailOutputSpec", "WheelRailScene", "WheelSpec", "WheelsetSpec"]
