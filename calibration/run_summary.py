"""The record of a calibration run (``summary.json``): FEM times, the similarity route's summary and the
outcome per body (units s, mm).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from calibration.tables import BodySummary
from calibration.tasks import PositionNote

if TYPE_CHECKING:  # the anchor's module needs the similarity master's, which a run summary does not
    from calibration.similarity.anchor import DirectReference


@dataclass(frozen=True)
class FemSeconds:
    """Wall time inside the workers of the computed positions, FEM apart from the field output (VTU, PNG).

    Attributes
    ----------
    per_position_min : float
        Shortest FEM time of a position (s).
    per_position_max : float
        Longest FEM time of a position (s).
    total : float
        FEM time of all computed positions (s).
    output_total : float
        Field output time of all computed positions (s).
    """

    per_position_min: float
    per_position_max: float
    total: float
    output_total: float


@dataclass(frozen=True)
class SimilaritySummary:
    """The similarity route of a run (``similarity`` of ``summary.json``).

    Attributes
    ----------
    served : int
        Positions calibrated from the master curves.
    direct : int
        Positions the master did not serve (calibrated by the direct FEM; why: each table entry's ``method`` and
        the summary's ``position_details``).
    master_files : tuple of str
        The master curves written (``similarity_master_<key>.json``).
    master_positions_computed : int
        Master FEM positions computed in this run.
    master_positions_cached : int
        Master FEM positions read from the master's cache.
    master_fem_seconds : float
        FEM time of all master positions, cached ones included (s).
    seconds_per_position : float
        Time per position to route it and (when served) build its characteristic from the master, without the
        fit (s).
    """

    served: int
    direct: int
    master_files: tuple[str, ...]
    master_positions_computed: int
    master_positions_cached: int
    master_fem_seconds: float
    seconds_per_position: float


@dataclass(frozen=True)
class CalibrationResult:
    """The outcome of a calibration run (``summary.json``).

    Attributes
    ----------
    bodies : dict of BodySummary
        Per body: positions, calibrated and failed counts, fit errors and the table's path.
    positions_computed : int
        Positions whose FEM ran in this run.
    positions_cached : int
        Positions whose FEM result came from the cache.
    fem_seconds : FemSeconds or None
        FEM times of the computed positions (None, and absent from the file: nothing computed).
    failed : tuple of PositionNote
        Failed positions: body, y_mm (mm) and error (in the file: ``{"body", "y_mm", "error"}``).
    warnings : tuple of PositionNote
        Warnings about positions (in the file: ``{"body", "y_mm", "warning"}``).
    worst_relative_fit_error : float
        Largest fit error relative to max u over all positions (-).
    seconds : float
        Wall time of the run (s).
    files : tuple of str
        Files written (tables, pictures).
    similarity : SimilaritySummary or None
        The similarity route's summary (None, and absent from the file: ``run.method = "direct"``).
    section_references : dict
        {(body, y): :class:`calibration.similarity.anchor.DirectReference`} of the positions served with their
        section's elastic solve, to anchor a later recalibration of the same positions (not in the file).
    """

    bodies: dict[str, BodySummary]
    positions_computed: int
    positions_cached: int
    fem_seconds: FemSeconds | None
    failed: tuple[PositionNote, ...]
    warnings: tuple[PositionNote, ...]
    worst_relative_fit_error: float
    seconds: float
    files: tuple[str, ...]
    similarity: SimilaritySummary | None = None
    section_references: Mapping[tuple[str, float], DirectReference] = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        """True when every position was calibrated."""
        return not self.failed

    @property
    def tables(self) -> dict[str, Path]:
        """{body: path of its table's JSON file} of the bodies with a table."""
        return {name: Path(b.table) for name, b in self.bodies.items() if b.table is not None}

    def to_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {"bodies": {k: v.to_dict() for k, v in self.bodies.items()},
                               "positions_computed": self.positions_computed,
                               "positions_cached": self.positions_cached}
        if self.fem_seconds is not None:
            out["fem_seconds"] = asdict(self.fem_seconds)
        out.update(failed=[{"body": f.body, "y_mm": f.y_mm, "error": f.message} for f in self.failed],
                   warnings=[{"body": w.body, "y_mm": w.y_mm, "warning": w.message} for w in self.warnings],
                   worst_relative_fit_error=self.worst_relative_fit_error, seconds=self.seconds,
                   files=list(self.files))
        if self.similarity is not None:
            out["similarity"] = asdict(self.similarity)
        return out


__all__ = ["CalibrationResult", "FemSeconds", "SimilaritySummary"]
