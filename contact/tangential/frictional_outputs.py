"""Wear-ready frictional outputs of a contact result, per strip and per FASTSIM cell, as CSV beside result.json
(units mm, N, MPa, s, W).

For a user with their own wear law: every FASTSIM result (one per patch region and pass) gives

    per strip (frictional_strips.csv):
      WT_N_per_mm            frictional work per unit area over one pass (N mm/mm^2 = N/mm): what a material point of
                             the strip dissipates crossing the patch
      Tgamma_A_mean_N_per_mm2  WT / (2 x_l): the strip's mean T gamma / A (frictional work per unit area per
                             rolled length; N/mm^2, the USFD wear-index unit)
      Tgamma_A_max_N_per_mm2, PT_max_W_per_mm2, PT_mean_W_per_mm2: largest / mean over the strip's cells
    per cell (frictional_cells.csv, the FASTSIM cells: strip j, cell k, centre x):
      pn_MPa, tx_MPa, ty_MPa, slip (0/1), slip_velocity_mm_s, slip_mm (slip distance in the cell),
      work_N_per_mm (frictional work per unit area accumulated in the cell, one pass),
      PT_W_per_mm2 (frictional power density at the rolling speed), Tgamma_A_N_per_mm2 (work / cell length)

P_T = 1e-3 V T gamma/A with V in mm/s (N/mm^2 * mm/s = 1e-3 W/mm^2). Keys identify the case: ``labels`` (e.g.
case, side, patch, region, pass) are written as the first columns.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

import numpy as np

from contact.tangential.fastsim import TangentialResult
from contact.tangential.method import strip_rows
from wrlayer.atomic_write import atomic_write_text

STRIP_FILE = "frictional_strips.csv"
CELL_FILE = "frictional_cells.csv"
PATTERNS = ("frictional_strips.csv", "frictional_cells.csv")
STRIP_COLUMNS = ("y_mm", "x_lead_mm", "p_peak_MPa", "WT_N_per_mm", "Tgamma_A_mean_N_per_mm2",
                 "Tgamma_A_max_N_per_mm2", "PT_max_W_per_mm2", "PT_mean_W_per_mm2")
CELL_COLUMNS = ("y_mm", "x_mm", "dx_mm", "pn_MPa", "tx_MPa", "ty_MPa", "slip", "slip_velocity_mm_s", "slip_mm",
                "work_N_per_mm", "PT_W_per_mm2", "Tgamma_A_N_per_mm2")


def cell_fields(t: TangentialResult) -> dict[str, np.ndarray]:
    """Per-cell (ny, nx) frictional fields of one FASTSIM result (see the module docstring)."""
    wf = np.asarray(t.WT_field_N_per_mm, float)
    work = np.diff(np.concatenate([np.zeros((wf.shape[0], 1)), wf], axis=1), axis=1)
    dx = np.broadcast_to(np.asarray(t.dx_mm, float)[:, None], work.shape)
    return {"x_mm": t.x_mm, "dx_mm": dx, "pn_MPa": t.pn_MPa, "tx_MPa": t.tx_MPa, "ty_MPa": t.ty_MPa,
            "slip": t.slip.astype(int), "slip_velocity_mm_s": t.slip_velocity_mm_s,
            "slip_mm": t.slip_velocity_mm_s * dx / t.speed_mm_s, "work_N_per_mm": work,
            "PT_W_per_mm2": t.PT_W_per_mm2, "Tgamma_A_N_per_mm2": work / dx}


def strip_fields(t: TangentialResult, x_lead_mm: np.ndarray, p_peak_MPa: np.ndarray) -> dict[str, np.ndarray]:
    """Per-strip (ny,) frictional quantities."""
    c = cell_fields(t)
    xl = np.asarray(x_lead_mm, float)
    return {"x_lead_mm": xl, "p_peak_MPa": np.asarray(p_peak_MPa, float), "WT_N_per_mm": t.WT_N_per_mm,
            "Tgamma_A_mean_N_per_mm2": t.WT_N_per_mm / (2.0 * xl),
            "Tgamma_A_max_N_per_mm2": c["Tgamma_A_N_per_mm2"].max(axis=1),
            "PT_max_W_per_mm2": t.PT_W_per_mm2.max(axis=1), "PT_mean_W_per_mm2": t.PT_W_per_mm2.mean(axis=1)}


def _fmt(v) -> str:
    return str(v) if isinstance(v, (str, int, np.integer)) else f"{float(v):.7g}"


def _block(prefix: str, columns: list[np.ndarray]) -> str:
    """Rows ``prefix`` + the columns (numbers, 7 significant digits), comma-separated: the text of np.savetxt with
    fmt="%.7g", formatted in one operation (one % over the whole block instead of one per row)."""
    table = np.column_stack([np.ravel(c).astype(float) for c in columns])
    if table.size == 0:
        return ""
    row = prefix.replace("%", "%%") + ",".join(["%.7g"] * table.shape[1]) + "\n"
    return (row * table.shape[0]) % tuple(table.ravel().tolist())


def frictional_tables(items: Iterable[tuple[dict, TangentialResult, np.ndarray, np.ndarray, np.ndarray, dict]]
                      ) -> tuple[str, str] | None:
    """CSV texts (strips, cells) of ``items``: (labels, result, strip y (mm, the frame to report), x_lead, p_peak,
    extra per-strip columns {name: (ny,) array}, e.g. profile coordinates). None when there is no result."""
    strips, cells = [], []
    strip_head = cell_head = None
    for labels, t, y, xl, pk, extra in items:
        if t is None:
            continue
        lab_names, extra_names = list(labels), list(extra)
        if strip_head is None:
            strip_head = lab_names + list(STRIP_COLUMNS[:1]) + extra_names + list(STRIP_COLUMNS[1:])
            cell_head = lab_names + list(CELL_COLUMNS[:1]) + extra_names + list(CELL_COLUMNS[1:])
        prefix = "".join(_fmt(labels[k]) + "," for k in lab_names)
        sf, cf = strip_fields(t, xl, pk), cell_fields(t)
        y = np.asarray(y, float)
        nx = cf["x_mm"].shape[1]
        ex = [np.asarray(extra[k], float) for k in extra_names]
        strips.append(_block(prefix, [y, *ex] + [sf[k] for k in STRIP_COLUMNS[1:]]))
        cells.append(_block(prefix, [np.repeat(y, nx), *[np.repeat(e, nx) for e in ex]]
                            + [np.broadcast_to(cf[n], cf["x_mm"].shape) for n in CELL_COLUMNS[1:]]))
    if strip_head is None:
        return None
    # plain CSV (header line, no comment line: numpy.genfromtxt(names=True), pandas and spreadsheets read it);
    # the units are in the column names
    return ",".join(strip_head) + "\n" + "".join(strips), ",".join(cell_head) + "\n" + "".join(cells)


def write_tables(out_dir: Path, tables: tuple[str, str] | None) -> list[str]:
    """Write the two CSV files into ``out_dir`` (atomically); returns their names."""
    if tables is None:
        return []
    atomic_write_text(Path(out_dir) / STRIP_FILE, tables[0])
    atomic_write_text(Path(out_dir) / CELL_FILE, tables[1])
    return [STRIP_FILE, CELL_FILE]


def write_scene_run(run, out_dir: Path) -> list[str]:
    """Kik–Piotrowski scene (:class:`contact.scenes.simulation.SimulationRun`): every pass, every patch region;
    strip y in the scene's separation frame."""
    snaps = getattr(run, "every_pass", None) or [run.first] + ([run.last] if run.last is not run.first else [])
    items = []
    for snap in snaps:
        for i, (lp, t) in enumerate(zip(snap.local_patches, strip_rows(snap.tangential, snap.solution))):
            items.append(({"pass": snap.number, "region": i}, t, lp.y_mm + snap.y_ref_mm[i], lp.x_lead_mm,
                          lp.p_peak_MPa, {}))
    return write_tables(out_dir, frictional_tables(items))


def write_wheel_rail(sols: list, out_dir: Path) -> list[str]:
    """Wheel–rail scene: ``sols[case] = {side: WheelRailSolution}`` (None for a failed case); the FASTSIM solution of
    each patch region in every pass (pass 1: the solver's own; later passes: FASTSIM on that pass's normal
    solution with the same creepages, :meth:`contact.wheel_rail.solution.WheelRailSolution.pass_tangential`), strips
    in the patch's strip coordinate with their rail and wheel profile coordinates."""
    items = []
    for k, case in enumerate(sols):
        if not case:
            continue
        for side, sol in case.items():
            for ip, p in enumerate(sol.patches):
                grid = p.problem.strip_y_mm
                normals = getattr(p, "pass_normals", None) or [p.normal]
                for npass, normal in enumerate(normals, start=1):
                    tang = p.tangential if npass == 1 else sol.pass_tangential(p, normal)
                    tang = strip_rows(tang, normal, p.eta_ref_mm)
                    if [t.WT_N_per_mm.size for t in tang] != [q.n_strips for q in normal.patches]:
                        # pass 1 re-solved on other strips than the balance's last solve (the coarse-grid
                        # solver's grid depends on its start): FASTSIM on that pass's solution, as for later passes
                        tang = sol.pass_tangential(p, normal)
                    for ir, (patch, t) in enumerate(zip(normal.patches, tang)):
                        extra = {"y_rail_mm": np.interp(patch.y_mm, grid, p.rail_y_of_strip),
                                 "y_wheel_mm": np.interp(patch.y_mm, grid, p.wheel_y_of_strip)}
                        items.append(({"case": k, "side": side, "patch": ip, "region": ir, "pass": npass}, t,
                                      patch.y_mm, patch.x_lead_mm, patch.p_peak_MPa, extra))
    return write_tables(out_dir, frictional_tables(items))


__all__ = ["CELL_COLUMNS", "PATTERNS", "STRIP_COLUMNS", "cell_fields", "frictional_tables", "strip_fields",
           "write_scene_run", "write_tables", "write_wheel_rail"]
