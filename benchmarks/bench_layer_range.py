"""The layer over the operating range: each table position's element against its own FEM, level by level.

For every position of the shipped default tables (``scenes/tables/*_default.json``, made by ``make calibrate``)
the table's element is compared with the FEM points stored in the table: the loaded inelastic displacement u_pl at
every FEM level and the residual dent after unloading from each peak (the element's exact unloading, with its
reverse factor), as (element - FEM) / max(FEM, FEM(1.5 p_2) / 3) (docs/calibration-method.md, "Fit over the
operating range"). The target: within 3 % at every level from 1.1 to 2.5 p_2. For comparison, the paper's fit (5
segments, absolute least squares, Masing unloading) of the same FEM points; and the element's largest error relative
to the FEM value itself from 1.1 p_2 up (what the fit's own measure, ``[fit] error_floor``, aims at). The full table
(every position and level) goes to ``OUT/layer_range.csv``.

Regenerate: ``python -m benchmarks --only layer_range`` (or ``python -m benchmarks.bench_layer_range [TABLE ...]``).
Units: mm, MPa.
"""

from __future__ import annotations

import csv
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
TABLES = (ROOT / "scenes" / "tables" / "rail_60E1_default.json", ROOT / "scenes" / "tables" / "wheel_S1002_default.json")
#: The levels of the target (p0 / p_2, -) and the target itself (scaled error, -).
TARGET_RANGE = (1.1, 2.5)
TARGET = 0.03
#: The levels of the report's columns (p0 / p_2, -).
COLUMNS = (1.1, 1.2, 1.3, 1.5, 1.7, 2.0, 2.5)


def _paper_fit_errors(pos: dict, levels: np.ndarray, p2: float) -> tuple[np.ndarray, np.ndarray]:
    """The paper's fit (5 segments, absolute least squares, Masing) of the position's FEM points: its scaled u_pl
    errors at ``levels`` (x p_2) and its scaled residual errors at the table's peaks."""
    from calibration.fit.characteristic_fit import fit_characteristic
    from calibration.fit.operating_range import error_scale_mm

    p = np.asarray(pos["fem_points"]["p_MPa"])
    u = np.asarray(pos["fem_points"]["u_mm"])
    u_pl = np.asarray(pos["fem"]["u_pl_mm"])
    s1 = float(p[-1] / (u[-1] - u_pl[-1]))  # u = p / S_1 + u_pl
    ch = fit_characteristic(p, u, 5, s1_N_per_mm3=s1, p2_MPa=p2, max_relative_error=0.5).characteristic
    at = levels * p2
    upl_err = (ch.displacement(at) - at / s1 - np.interp(at, p, u_pl)) / error_scale_mm(p, u_pl, p2, at)
    peaks = np.asarray(pos["residual_peaks_MPa"])
    res = np.asarray(pos["residual_fem_mm"])
    res_err = (ch.unloading_residual(peaks) - res) / error_scale_mm(peaks, res, p2, peaks)
    return upl_err, res_err


def _relative_errors(pos: dict, ch, p2: float) -> tuple[float, float]:
    """The element's largest |element - FEM| / FEM over the levels (u_pl) and peaks (residual) in
    [1.1 p_2, 2.5 p_2] (-)."""
    p = np.asarray(pos["fem"]["p_MPa"])
    u_pl = np.asarray(pos["fem"]["u_pl_mm"])
    at = p[(p >= TARGET_RANGE[0] * p2 * (1 - 1e-6)) & (p <= TARGET_RANGE[1] * p2 * (1 + 1e-6))]
    fem = np.interp(at, p, u_pl)
    upl = (ch.displacement(at) - at / ch.initial_stiffness - fem) / fem
    peaks = np.asarray(pos["residual_peaks_MPa"])
    keep = (peaks >= TARGET_RANGE[0] * p2 * (1 - 1e-6)) & (peaks <= TARGET_RANGE[1] * p2 * (1 + 1e-6))
    res_fem = np.asarray(pos["residual_fem_mm"])[keep]
    res = (ch.unloading_residual(peaks[keep]) - res_fem) / res_fem
    return float(np.max(np.abs(upl), initial=0.0)), float(np.max(np.abs(res), initial=0.0))


def position_rows(table_path: Path) -> list[dict]:
    """One row per position of a table: its fit and its scaled errors per level (table element and paper fit)."""
    from wrlayer.layer_table import LayerTable

    table = LayerTable.read(table_path)
    rows = []
    for pos, ch in zip(table.positions, table.characteristics):
        if "levels_over_p2" not in pos:
            raise ValueError(f"{table_path}: position y = {pos['y_mm']} has no level errors (format 4 needed)")
        p2 = float(pos["first_yield_fem_MPa"])
        x = np.asarray(pos["levels_over_p2"])
        upl = np.asarray(pos["u_pl_error"])
        peaks = np.asarray(pos["residual_peaks_MPa"]) / p2
        res = np.asarray(pos["residual_error"])
        paper_upl, paper_res = _paper_fit_errors(pos, x, p2)
        rel_upl, rel_res = _relative_errors(pos, ch, p2)
        inside = (x >= TARGET_RANGE[0] - 1e-6) & (x <= TARGET_RANGE[1] + 1e-6)
        inside_pk = (peaks >= TARGET_RANGE[0] - 1e-6) & (peaks <= TARGET_RANGE[1] + 1e-6)
        rows.append({"body": table.body, "y_mm": float(pos["y_mm"]), "method": pos.get("method", "direct"),
                     "n_segments": ch.n_segments, "reverse_factor": ch.reverse_factor,
                     "levels_over_p2": x.tolist(), "u_pl_error": upl.tolist(), "peaks_over_p2": peaks.tolist(),
                     "residual_error": res.tolist(),
                     "max_u_pl_error": float(np.max(np.abs(upl[inside]), initial=0.0)),
                     "max_residual_error": float(np.max(np.abs(res[inside_pk]), initial=0.0)),
                     "paper_max_u_pl_error": float(np.max(np.abs(paper_upl[inside]), initial=0.0)),
                     "paper_max_residual_error": float(np.max(np.abs(paper_res[inside_pk]), initial=0.0)),
                     "paper_u_pl_error_1.3": float(np.interp(1.3, x, paper_upl)),
                     "max_relative_u_pl_error": rel_upl, "max_relative_residual_error": rel_res})
    return rows


def _at(row: dict, level: float, key: str, levels_key: str) -> str:
    x = np.asarray(row[levels_key])
    j = int(np.argmin(np.abs(x - level)))
    return f"{100 * row[key][j]:+.1f}" if abs(x[j] - level) < 1e-6 else "–"


def _markdown(rows: list[dict]) -> str:
    head = ("| body | y (mm) | route | N | ρ | " + " | ".join(f"u_pl {c:g}" for c in COLUMNS) + " | "
            + " | ".join(f"res {c:g}" for c in COLUMNS) + " | max u_pl / res | paper fit max u_pl / res "
            "| max of the value u_pl / res |")
    lines = [head, "|" + "---|" * (8 + 2 * len(COLUMNS))]
    for r in rows:
        lines.append(f"| {r['body']} | {r['y_mm']:g} | {r['method']} | {r['n_segments']} | {r['reverse_factor']:.2f} | "
                     + " | ".join(_at(r, c, "u_pl_error", "levels_over_p2") for c in COLUMNS) + " | "
                     + " | ".join(_at(r, c, "residual_error", "peaks_over_p2") for c in COLUMNS)
                     + f" | {100 * r['max_u_pl_error']:.1f} / {100 * r['max_residual_error']:.1f}"
                     + f" | {100 * r['paper_max_u_pl_error']:.1f} / {100 * r['paper_max_residual_error']:.1f}"
                     + f" | {100 * r['max_relative_u_pl_error']:.1f} / {100 * r['max_relative_residual_error']:.1f} |")
    worst_u = max(r["max_u_pl_error"] for r in rows)
    worst_r = max(r["max_residual_error"] for r in rows)
    met = sum(r["max_u_pl_error"] <= TARGET and r["max_residual_error"] <= TARGET for r in rows)
    rel = max(max(r["max_relative_u_pl_error"], r["max_relative_residual_error"]) for r in rows)
    return (f"Errors in % of max(FEM, FEM(1.5 p_2)/3), element minus FEM, at the levels p0/p_2 of the columns; "
            f"target {100 * TARGET:g} % from {TARGET_RANGE[0]:g} to {TARGET_RANGE[1]:g} p_2. **{met} of {len(rows)} "
            f"positions within the target** (worst u_pl {100 * worst_u:.2f} %, residual {100 * worst_r:.2f} %). "
            "The paper's fit of the same FEM points (5 segments, Masing) for comparison. Relative to the FEM value "
            f"itself (last column) the element is within {100 * rel:.2f} % at every level and peak from "
            f"{TARGET_RANGE[0]:g} to {TARGET_RANGE[1]:g} p_2.\n\n" + "\n".join(lines) + "\n")


def _write_csv(rows: list[dict], path: Path) -> Path:
    with path.open("w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(["body", "y_mm", "quantity", "level_over_p2", "scaled_error"])
        for r in rows:
            for x, e in zip(r["levels_over_p2"], r["u_pl_error"]):
                w.writerow([r["body"], r["y_mm"], "u_pl", x, e])
            for x, e in zip(r["peaks_over_p2"], r["residual_error"]):
                w.writerow([r["body"], r["y_mm"], "residual", x, e])
    return path


def run(mode: str, out: Path, tables: tuple[Path, ...] = TABLES) -> dict:
    rows = [row for t in tables for row in position_rows(Path(t))]
    _write_csv(rows, Path(out) / "layer_range.csv")
    return {"title": "The layer over the operating range: each table position against its own FEM",
            "markdown": _markdown(rows), "figures": [], "data": {"positions": rows, "target": TARGET}}


if __name__ == "__main__":
    result = run("quick", Path("."), tuple(Path(a) for a in sys.argv[1:]) or TABLES)
    print(result["markdown"])
