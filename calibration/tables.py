"""The layer table of one calibrated body (``OUT/<body>_layer_table.json`` and ``.csv``, format
:class:`wrlayer.layer_table.LayerTable`): its header, its positions and failed positions, written only when
its inputs changed, and the body's line of the run summary. Units mm, N, MPa, N/mm^3.
"""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any

from calibration.hertz.geometry import HERTZ_B_OVER_R_LIMIT
from calibration.placement import cant_rad
from calibration.results import PositionFit
from calibration.settings import BodySettings, CalibrationConfig
from calibration.tasks import PositionNote, code_hash, inputs_hash, profile_label, profile_source
from wrlayer.layer_table import LayerTable
from wrlayer.errors import WrLayerError
from wrlayer.version import code_version, software_versions

#: Sources that determine a fit and the table written from it (the fit cache key includes their content).
FIT_SOURCES = ("calibration/fit/*.py", "calibration/position_fit.py", "calibration/results.py",
               "calibration/tables.py", "wrlayer/characteristic.py", "wrlayer/layer_table.py")

#: The layer's definition, recorded in every table header (docs/calibration.md).
DEFINITION = ("u(p) = p/S_1 + u_pl(p); u_pl = FEM approach of the load centre towards the material point "
              "reference_depth_factor * max(a, b) below it, minus the same mesh's elastic part; S_1 = p_max / "
              "(elastic_tolerance * u_pl(p_max)) (or 1/(elastic_fraction * half-space centre compliance) when "
              "elastic_fraction is given); p_2 = FEM first yield (docs/calibration.md)")


@dataclass(frozen=True)
class PositionReport:
    """One calibrated position in the run summary (``bodies.<body>.position_details[i]`` of ``summary.json``).

    Attributes
    ----------
    y_mm : float
        Lateral position on the body's profile (mm).
    y_mate_mm : float or None
        The mating profile's position in contact with it (mm; None: given semi-axes).
    a_mm : float
        Hertz semi-axis in the rolling direction (mm).
    b_mm : float
        Hertz semi-axis in the lateral direction (mm).
    method : str
        How the position was calibrated: "direct" (its own FEM) or "similarity" (master curves).
    note : str
        Why the direct FEM was used under ``run.method = "similarity"`` ("" otherwise).
    """

    y_mm: float
    y_mate_mm: float | None
    a_mm: float
    b_mm: float
    method: str
    note: str = ""

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


@dataclass(frozen=True)
class BodySummary:
    """One body of a calibration run (``bodies.<body>`` of ``summary.json``).

    Attributes
    ----------
    positions : int
        Positions of the body in the configuration.
    calibrated : int
        Positions calibrated (in the table).
    failed : int
        Positions that failed (listed in the table).
    table : str or None
        Path of the table's JSON file (None: nothing calibrated, no table).
    max_fit_error_mm : float or None
        Largest fit error over the positions (mm).
    max_relative_fit_error : float or None
        Largest fit error relative to the position's max u (-).
    max_residual_error_mm : float or None
        Largest |eq. (8) residual dent - FEM residual dent| (mm).
    position_details : tuple of PositionReport
        Per calibrated position: the mating position, the semi-axes and the route.
    """

    positions: int
    calibrated: int
    failed: int
    table: str | None = None
    max_fit_error_mm: float | None = None
    max_relative_fit_error: float | None = None
    max_residual_error_mm: float | None = None
    position_details: tuple[PositionReport, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        head = {"positions": self.positions, "calibrated": self.calibrated, "failed": self.failed}
        if self.table is None:
            return dict(head, table=None)
        return dict(head, max_fit_error_mm=self.max_fit_error_mm, max_relative_fit_error=self.max_relative_fit_error,
                    max_residual_error_mm=self.max_residual_error_mm, table=self.table,
                    position_details=[p.to_dict() for p in self.position_details])


def table_header(cfg: CalibrationConfig, b: BodySettings) -> dict[str, Any]:
    """The JSON header of a body's table: inputs, units, definition, software and code versions."""
    return {"body": b.body, "profile": profile_label(b.profile), "profile_source": profile_source(b.profile),
            "mate": None if b.mate is None else profile_source(b.mate), "model": cfg.run.model,
            "method": cfg.run.method, "inclination_rad": cant_rad(b, f"bodies.{b.body}"),
            "units": {"length": "mm", "pressure": "MPa", "stiffness": "N/mm^3", "force": "N"},
            "material": asdict(b.material), "mesh": asdict(cfg.mesh), "load": asdict(cfg.load),
            "reference_load_N": cfg.reference_load_N, "fit": asdict(cfg.fit), "definition": DEFINITION,
            "software": software_versions(), "code_version": code_version(), "code_hash": code_hash(),
            "config": cfg.source, "created_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}


def previous_table(json_path: Path) -> LayerTable | None:
    """The valid table at ``json_path`` (None: no file, or not a valid table)."""
    try:
        return LayerTable.read(json_path) if json_path.is_file() else None
    except (WrLayerError, OSError, UnicodeDecodeError):
        return None


def with_rolling_law(table: LayerTable, previous: LayerTable | None) -> LayerTable:
    """``table`` carrying the rolling law of ``previous`` (the table it replaces, or the template it was
    recalibrated from) when it has none of its own. The law is fitted to the rolling FEM once (calibration.rolling,
    docs/rolling.md) and is in terms of p0/p_2 and the traction coefficient, so it holds for a table recalibrated
    on the same material; without it a regenerated table would silently fall back to the relaxed passes."""
    if table.rolling_law is not None or previous is None or previous.rolling_law is None:
        return table
    return replace(table, rolling_law=previous.rolling_law)


def same_inputs(json_path: Path, inputs: str) -> bool:
    """True when ``json_path`` is a valid table made from the inputs hashed ``inputs`` AND the CSV beside it is
    exactly the one written from that table (a CSV of another run, e.g. of a second run into the same folder, is
    rewritten)."""
    csv_path = json_path.with_suffix(".csv")
    if not json_path.is_file() or not csv_path.is_file():
        return False
    try:
        table = LayerTable.read(json_path)
        return table.header.get("inputs_hash") == inputs and csv_path.read_text(encoding="utf-8") == table.to_csv()
    except (WrLayerError, OSError, UnicodeDecodeError):
        return False


def _note(n: PositionNote, kind: str) -> dict[str, Any]:
    return {"body": n.body, "y_mm": n.y_mm, kind: n.message}


def position_report(fit: PositionFit, method: str, note: str = "") -> PositionReport:
    """The summary line of one calibrated position."""
    g = fit.geometry
    return PositionReport(float(fit.y_mm), g.y_mate_mm, float(g.a_mm), float(g.b_mm), method, note)


def write_body_table(cfg: CalibrationConfig, b: BodySettings, fits: list[tuple[str, PositionFit]],
                     failed: list[PositionNote], warnings: list[PositionNote], fit_code: str, plots: bool,
                     out_dir: Path, routes: dict[str, tuple[str, str]] | None = None
                     ) -> tuple[BodySummary, LayerTable | None, list[Path]]:
    """Write body ``b``'s table from its fits [(FEM cache key, fit)] in position order, listing its failed
    positions; unchanged inputs leave the files as they are, no fit removes a stale table. ``routes``: {key:
    (method, note)} of the positions (default: all "direct"), recorded as each entry's ``method``. Returns the
    body's summary, the table (None: none) and the files written."""
    routes = routes or {}
    body_failed = sorted((f for f in failed if f.body == b.body), key=lambda f: f.y_mm)
    json_path = out_dir / f"{b.body}_layer_table.json"
    csv_path = out_dir / f"{b.body}_layer_table.csv"
    n = dict(positions=len(b.positions_mm), calibrated=len(fits), failed=len(body_failed))
    if not fits:  # nothing calibrated: no table, and none left from an earlier run
        for stale in (json_path, csv_path):
            stale.unlink(missing_ok=True)
        return BodySummary(**n), None, []
    body_warnings = [w for w in warnings if w.body == b.body]
    entries = []
    reports = []
    for key, fit in fits:
        notes = [w.message for w in body_warnings if w.y_mm == fit.y_mm]
        reports.append(position_report(fit, *routes.get(key, ("direct", ""))))
        entry = dict(fit.to_dict(), method=reports[-1].method)
        entries.append(dict(entry, warnings=notes) if notes else entry)
    header = table_header(cfg, b)
    header["conforming_limit_b_over_R"] = HERTZ_B_OVER_R_LIMIT
    header["inputs_hash"] = inputs_hash({"keys": [k for k, _ in fits], "fit": asdict(cfg.fit), "fit_code": fit_code,
                                         "plots": plots, "warnings": [_note(w, "warning") for w in body_warnings]})
    unchanged = same_inputs(json_path, header["inputs_hash"])
    written: list[Path] = []
    if unchanged:
        table = LayerTable.read(json_path)
    else:
        table = with_rolling_law(LayerTable(header, entries, [{"y_mm": f.y_mm, "error": f.message}
                                                             for f in body_failed], f"{b.body} layer table"),
                                 previous_table(json_path))
        written += table.write(json_path, csv_path)
    rel = [f.max_error_mm / max(f.fem_points["u_mm"]) for _, f in fits]
    summary = BodySummary(**n, table=str(json_path), max_fit_error_mm=max(f.max_error_mm for _, f in fits),
                          max_relative_fit_error=max(rel),
                          max_residual_error_mm=max((abs(x) for _, f in fits for x in f.residual_error_mm),
                                                    default=0.0), position_details=tuple(reports))
    if plots and not unchanged:
        from calibration.plots import write_body_plots  # matplotlib only when pictures are drawn

        written += write_body_plots(table, b, out_dir / "plots")
    return summary, table, written


__all__ = ["BodySummary", "DEFINITION", "FIT_SOURCES", "PositionReport", "position_report", "previous_table", "same_inputs", "table_header",
           "with_rolling_law", "write_body_table"]
