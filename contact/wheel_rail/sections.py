"""The sections of a wheel–rail scene that extend or replace the common ones (:mod:`contact.scenes.sections`):
[load] (the wheel load and speed), [method] (the common solver settings and the contact search's) and [output]
(the wheel–rail scene's extra files). Units mm, N, MPa, s.
"""

from __future__ import annotations

from dataclasses import dataclass

from contact.scenes.result_io import Record
from contact.scenes.sections import MethodSpec, OutputSpec
from contact.wheel_rail.contact_search import CANDIDATE_GAP_MM, F_CAP_MM, MERGE_MM, SearchSettings
from contact.wheel_rail.reference_point import CONTACT_POINTS
from wrlayer.section_keys import key
from wrlayer.validate import MIN_FORCE_N

#: ``method.balance``: "total" (the vertical component of normal + tangential forces equals the load) or "normal"
#: (normal forces only; the earlier model, kept for comparison).
BALANCES = ("total", "normal")


@dataclass(frozen=True)
class WheelLoadSpec(Record):
    """[load] of a wheel–rail scene: load and speed of the single case (a sweep may vary them per case).

    Attributes
    ----------
    vertical_load_N : float
        Vertical load per wheel Q (N).
    speed_mm_s : float
        Rolling speed V (mm/s).
    """

    vertical_load_N: float = key(10000.0, "N", ge=MIN_FORCE_N, plausible="wheel_load_N")
    speed_mm_s: float = key(2000.0, "mm/s", gt=0.0, plausible="speed_mm_s")


@dataclass(frozen=True)
class WheelRailMethodSpec(MethodSpec):
    """[method] of a wheel–rail scene: the common solver settings (:class:`contact.scenes.sections.MethodSpec`)
    and the contact search's.

    Attributes
    ----------
    merge_mm : float
        Barrier height below which neighbouring gap minima are one contact candidate (mm).
    candidate_gap_mm : float
        Largest gap above the first contact of a kept contact candidate (mm).
    f_cap_mm : float
        The separation function is cut where it exceeds this (mm).
    contact_point : str
        The reported point of a patch, where creepages are evaluated: "first_contact" or "weighted_centre" (-).
    balance : str
        Vertical load balance: "total" (normal + tangential forces) or "normal" (normal forces only) (-).
    """

    merge_mm: float = key(MERGE_MM, "mm", ge=0.0)
    candidate_gap_mm: float = key(CANDIDATE_GAP_MM, "mm", gt=0.0)
    f_cap_mm: float = key(F_CAP_MM, "mm", gt=0.0)
    contact_point: str = key("first_contact", choices=CONTACT_POINTS)
    balance: str = key("total", choices=BALANCES)

    @property
    def search(self) -> SearchSettings:
        return SearchSettings(merge_mm=self.merge_mm, candidate_gap_mm=self.candidate_gap_mm, f_cap_mm=self.f_cap_mm)


@dataclass(frozen=True)
class WheelRailOutputSpec(OutputSpec):
    """[output] of a wheel–rail scene: the common output keys and the wheel–rail scene's files.

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
    vtk_frame : str
        Where the VTK fields lie: "track" (default: on the deformed rail and wheel surfaces in track coordinates,
        with the surfaces; :mod:`contact.wheel_rail.track_vtk`) or "local" (each patch flat in its own frame) (-).
    """

    deformed_profiles: bool = key(True)
    contact_table: bool = key(False)
    frictional_csv: bool = key(True)
    vtk_frame: str = key("track", choices=("track", "local"))


__all__ = ["BALANCES", "WheelLoadSpec", "WheelRailMethodSpec", "WheelRailOutputSpec"]
