"""The contact table for multibody codes: a wheel–rail sweep written as one CSV lookup table (``contact_table.csv``,
one row per case, wheel and loaded patch; :class:`ContactTableRow`), with ``output.contact_table = true``
(units mm, N, rad; docs/contact-tables.md).

Every value but the profile heights and the creep coefficients is the sweep's own (result.json's
``cases[k].wheels[side].patches[i]``, wrlayer's convention: :data:`contact.wheel_rail.result_files.CONVENTIONS`).
The heights are the profiles' z at the reported coordinates; the creep coefficients are Kalker's linear theory on
the patch's equivalent ellipse, the one FASTSIM uses (:func:`contact.tangential.fastsim.equivalent_ellipse`: area
and length/width of the patch kept; Kalker 1990, Table E3), so that a multibody code may compute its own creep
forces at small creepage (wheel relative to rail, forces of the rail on the wheel):

    Fx = -f11 vx,   Fy = -f22 vy - f23 phi,   f11 = G a b C11,  f22 = G a b C22,  f23 = G (a b)^(3/2) C23

The failed cases are listed in ``contact_table_failed.csv`` (case, inputs, wheel, reason), written only when some
case failed; the run then exits 4 as every sweep does.
"""

from __future__ import annotations

import csv
import dataclasses
import io
import math
from dataclasses import dataclass
from pathlib import Path

from contact.tangential.fastsim import equivalent_ellipse
from contact.wheel_rail.patch_result import PatchResult
from contact.wheel_rail.results import CaseResult, SweepResult
from contact.wheel_rail.scene import WheelRailScene
from wrlayer.atomic_write import atomic_write_text
from wrlayer.json_io import Record

TABLE_FILE = "contact_table.csv"
FAILED_FILE = "contact_table_failed.csv"
#: Columns of contact_table_failed.csv.
FAILED_COLUMNS = ("case", "lateral_mm", "yaw_rad", "roll_rad", "pitch_rate_rad_s", "vertical_load_N", "speed_mm_s",
                  "wheel", "error")


@dataclass(frozen=True)
class PatchSize:
    """A solved patch's size as :func:`contact.tangential.fastsim.equivalent_ellipse` reads it (mm, mm^2)."""

    area: float
    length: float
    width: float

    def area_mm2(self) -> float:
        return self.area

    def length_mm(self) -> float:
        return self.length

    def width_mm(self) -> float:
        return self.width


@dataclass(frozen=True, kw_only=True)
class ContactTableRow(Record):
    """One row of contact_table.csv: one loaded patch of one wheel in one case (the column names are the fields).

    Attributes
    ----------
    case : int
        Case number of the sweep, 0-based (-).
    lateral_mm : float
        Lateral wheelset displacement towards the right rail (mm).
    yaw_rad : float
        Wheelset yaw angle, counter-clockwise seen from above (rad).
    roll_rad : float
        Wheelset roll angle lifting the right wheel (rad; the solved one with ``wheelset.roll_rad = "auto"``).
    pitch_rate_rad_s : float
        Wheelset pitch rate, positive rolling forwards (rad/s).
    vertical_load_N : float
        Vertical load on the wheel (N).
    speed_mm_s : float
        Rolling speed (mm/s).
    side : str
        The wheel: "right" (at +Y) or "left" (-).
    patch : int
        The loaded patch of the wheel, 0-based in the solver's order (-).
    n_patches : int
        Loaded patches of the wheel in this case (-).
    y_rail_mm : float
        Rail profile coordinate of the contact point, + towards the field side, same for both rails (mm).
    z_rail_mm : float
        Rail profile height there, the rail profile's frame, z up (mm).
    y_wheel_mm : float
        Wheel profile coordinate of the contact point (S1002: 0 at the taping line, + towards the field side) (mm).
    z_wheel_mm : float
        Wheel profile height there, the wheel profile's frame, z up (mm).
    Y_track_mm : float
        Lateral track coordinate of the contact point, from the track centre, + towards the right rail (mm).
    Z_track_mm : float
        Vertical track coordinate of the contact point, 0 in the plane of the rail tops, up (mm).
    contact_angle_rad : float
        Angle of the contact normal from the track vertical, + tilting towards the track centre, same sign on both
        wheels (rad).
    rolling_radius_mm : float
        Wheel rolling radius at the contact point (mm).
    normal_force_N : float
        Normal force of the patch (N).
    a_mm : float
        Semi-axis of the patch's equivalent ellipse along the rolling direction (mm).
    b_mm : float
        Lateral semi-axis of the equivalent ellipse (mm).
    area_mm2 : float
        Patch area (mm^2).
    C11 : float
        Kalker's longitudinal creep coefficient at a/b and Poisson's ratio (-).
    C22 : float
        Kalker's lateral creep coefficient (-).
    C23 : float
        Kalker's lateral-spin creep coefficient (-).
    f11_N : float
        Linear longitudinal creep-force coefficient G a b C11 (N).
    f22_N : float
        Linear lateral creep-force coefficient G a b C22 (N).
    f23_Nmm : float
        Linear lateral-spin creep-force coefficient G (a b)^(3/2) C23 (N mm).
    creepage_x : float
        Longitudinal creepage of the wheel relative to the rail (-).
    creepage_y : float
        Lateral creepage along the contact-plane lateral axis (positive track-Y component) (-).
    spin_per_mm : float
        Spin creepage (1/mm).
    Fx_N : float
        Longitudinal creep force of the rail on the wheel (N).
    Fy_N : float
        Lateral creep force of the rail on the wheel along the contact-plane lateral axis (N).
    Mz_Nmm : float
        Spin moment of the rail on the wheel about the contact normal through the contact point (N mm).
    """

    case: int
    lateral_mm: float
    yaw_rad: float
    roll_rad: float
    pitch_rate_rad_s: float
    vertical_load_N: float
    speed_mm_s: float
    side: str
    patch: int
    n_patches: int
    y_rail_mm: float
    z_rail_mm: float
    y_wheel_mm: float
    z_wheel_mm: float
    Y_track_mm: float
    Z_track_mm: float
    contact_angle_rad: float
    rolling_radius_mm: float
    normal_force_N: float
    a_mm: float
    b_mm: float
    area_mm2: float
    C11: float
    C22: float
    C23: float
    f11_N: float
    f22_N: float
    f23_Nmm: float
    creepage_x: float
    creepage_y: float
    spin_per_mm: float
    Fx_N: float
    Fy_N: float
    Mz_Nmm: float


#: Columns of contact_table.csv, in order.
TABLE_COLUMNS = tuple(f.name for f in dataclasses.fields(ContactTableRow))


def patch_row(scene: WheelRailScene, case: CaseResult, side: str, index: int, p: PatchResult, n_patches: int
              ) -> ContactTableRow:
    """The row of patch ``index`` of the ``side`` wheel of a solved case."""
    G, nu = scene.material.G_MPa, scene.material.poisson
    ellipse = equivalent_ellipse(PatchSize(p.area_mm2, p.length_mm, p.width_mm), G, nu)
    a, b, k = ellipse.a_mm, ellipse.b_mm, ellipse.coefficients
    f = G * a * b
    return ContactTableRow(
        case=case.case, lateral_mm=case.lateral_mm, yaw_rad=case.yaw_rad, roll_rad=case.roll_rad,
        pitch_rate_rad_s=case.pitch_rate_rad_s, vertical_load_N=case.vertical_load_N, speed_mm_s=case.speed_mm_s,
        side=side, patch=index, n_patches=n_patches,
        y_rail_mm=p.y_rail_mm, z_rail_mm=float(scene.rail_profile.z(p.y_rail_mm)),
        y_wheel_mm=p.y_wheel_mm, z_wheel_mm=float(scene.wheel_profile.z(p.y_wheel_mm)),
        Y_track_mm=p.Y_track_mm, Z_track_mm=p.Z_track_mm, contact_angle_rad=p.contact_angle_rad,
        rolling_radius_mm=p.wheel_radius_mm, normal_force_N=p.normal_force_N, a_mm=a, b_mm=b, area_mm2=p.area_mm2,
        C11=k.C11, C22=k.C22, C23=k.C23, f11_N=f * k.C11, f22_N=f * k.C22, f23_Nmm=f * math.sqrt(a * b) * k.C23,
        creepage_x=p.creepage_x, creepage_y=p.creepage_y, spin_per_mm=p.spin_per_mm,
        Fx_N=p.Fx_N, Fy_N=p.Fy_N, Mz_Nmm=p.Mz_Nmm)


def table_rows(result: SweepResult, scene: WheelRailScene) -> list[ContactTableRow]:
    """Every loaded patch of every solved case: case order, then the scene's wheel order, then the patches."""
    return [patch_row(scene, case, side, i, p, wheel.n_patches)
            for case in result.cases if case.wheels for side, wheel in case.wheels.items()
            for i, p in enumerate(wheel.patches)]


def _csv(columns: tuple[str, ...], rows: list[dict]) -> str:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(columns)
    for row in rows:
        w.writerow(["" if row[c] is None else f"{row[c]:.10g}" if isinstance(row[c], float) else row[c]
                    for c in columns])
    return buf.getvalue()


def table_csv(rows: list[ContactTableRow]) -> str:
    """The rows as CSV text: a header of :data:`TABLE_COLUMNS`, numbers with 10 significant digits."""
    return _csv(TABLE_COLUMNS, [r.to_dict() for r in rows])


def failed_csv(result: SweepResult) -> str:
    """The failed cases as CSV text (:data:`FAILED_COLUMNS`; ``wheel`` "wheelset" when the rigid roll failed)."""
    return _csv(FAILED_COLUMNS, [{**{c: getattr(case, c, None) for c in FAILED_COLUMNS[:-2]},
                                  "wheel": case.failed_wheel or "wheelset", "error": case.error}
                                 for case in result.cases if case.error is not None])


def write_contact_table(result: SweepResult, scene: WheelRailScene, out_dir: Path) -> list[str]:
    """Write contact_table.csv (and contact_table_failed.csv when some case failed) into ``out_dir``; returns the
    names written."""
    out_dir = Path(out_dir)
    atomic_write_text(out_dir / TABLE_FILE, table_csv(table_rows(result, scene)))
    if not result.n_failed:
        return [TABLE_FILE]
    atomic_write_text(out_dir / FAILED_FILE, failed_csv(result))
    return [TABLE_FILE, FAILED_FILE]


__all__ = ["FAILED_COLUMNS", "FAILED_FILE", "TABLE_COLUMNS", "TABLE_FILE", "ContactTableRow", "PatchSize",
           "failed_csv", "patch_row", "table_csv", "table_rows", "write_contact_table"]
