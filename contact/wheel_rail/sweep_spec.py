"""The cases of a wheel–rail scene as typed data: one :class:`CaseSpec` per case, the [sweep] that gave them
(:class:`SweepSpec`) and its CSV file (:class:`SweepCsv`) (units mm, N, s, rad). Read by
:func:`contact.wheel_rail.sweep.parse_sweep`.
"""

from __future__ import annotations

from dataclasses import dataclass

from contact.scenes.result_io import Record

#: Per-case inputs a sweep may vary (a list per key, a {start, stop, step} range, or a column of a CSV file).
SWEEP_KEYS = ("lateral_mm", "yaw_rad", "roll_rad", "pitch_rate_rad_s", "vertical_load_N", "speed_mm_s")


@dataclass(frozen=True)
class CaseSpec(Record):
    """One case of the scene: a wheelset pose, load and speed.

    Attributes
    ----------
    lateral_mm : float
        Lateral displacement towards the right rail (mm).
    yaw_rad : float
        Yaw angle (rad).
    roll_rad : float
        Roll angle (rad); 0 with ``wheelset.roll_rad = "auto"`` (solved per case).
    pitch_rate_rad_s : float | None
        Pitch rate (rad/s); None: speed / nominal radius.
    vertical_load_N : float
        Vertical load per wheel (N).
    speed_mm_s : float
        Rolling speed (mm/s).
    """

    lateral_mm: float
    yaw_rad: float
    roll_rad: float
    pitch_rate_rad_s: float | None
    vertical_load_N: float
    speed_mm_s: float


@dataclass(frozen=True)
class SweepCsv(Record):
    """The sweep CSV file (``sweep.csv``) as read.

    Attributes
    ----------
    file : str
        Resolved path of the CSV file.
    sha256 : str
        sha256 of the file (hex).
    convention : str
        Sign convention of its columns: "wrlayer" or "contact" (CONTACT's roll and pitch-rate signs) (-).
    columns : tuple[str, ...]
        The columns used (named like the sweep keys).
    ignored_columns : tuple[str, ...]
        The other columns.
    """

    file: str
    sha256: str
    convention: str
    columns: tuple[str, ...]
    ignored_columns: tuple[str, ...]


@dataclass(frozen=True)
class SweepSpec(Record):
    """[sweep]: the cases of the scene (one case, from [wheelset] and [load], without a [sweep]).

    Attributes
    ----------
    mode : str
        "zip" (case k takes the k-th value of each list) or "product" (-).
    csv : SweepCsv | None
        The sweep CSV, when the cases come from one.
    cases : tuple[CaseSpec, ...]
        The cases in order.
    """

    mode: str = "zip"
    csv: SweepCsv | None = None
    cases: tuple[CaseSpec, ...] = ()

    def __repr__(self) -> str:
        return f"SweepSpec({self.mode}, {len(self.cases)} cases{', csv' if self.csv is not None else ''})"


__all__ = ["SWEEP_KEYS", "CaseSpec", "SweepCsv", "SweepSpec"]
