"""Tables of several scene results: the full table like the paper's Table 1 (``table.md``, ``table.csv``) and a
short console summary (:func:`summary_text`, at most :data:`SUMMARY_WIDTH` columns).

Full table, rows: patch length, width, area, approach delta, F_x, F_y, p_max, W_T max, P_T max (Table 1), then the
layer displacement u(0) at the reference point under load and the residual u_p(0) the pass left there (reported in
the paper's text for the first pass). Columns: one per scene (its last pass); scenes with several passes also get
their first pass; scenes with a ``[reference]`` (published values) get a column with those beside. The markdown
file adds a section with the key numbers of every wheel–rail scene (:func:`wheel_rail_rows`); the CSV holds the
Table 1 rows only.

Console summary: one short table per scene kind, one row per scene: contact scenes (last pass; a scene's
``[reference]`` values on an indented row below it) and wheel–rail scenes (cases, failures, largest values over
the cases); the last line names the files holding the full table. One scene's key numbers on the terminal
(``wrlayer simulate``, each scene of ``simulate-all``): :func:`scene_summary`; a wear run's steps
(``wrlayer wear``): :func:`wear_summary`.
"""

from __future__ import annotations

import csv
import io
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from contact.passes.record import PassRecord
    from contact.scenes.run_result import SceneResult

#: A batch's results by scene name: :class:`contact.scenes.run_result.SceneResult` or a wheel–rail sweep's
#: :class:`contact.wheel_rail.results.SweepResult` (this package does not import the wheel–rail package).
Results = dict[str, Any]

#: (label, unit, result key, scale, decimals)
ROWS = (
    ("patch length", "mm", "length_mm", 1.0, 2),
    ("patch width", "mm", "width_mm", 1.0, 2),
    ("area", "mm^2", "area_mm2", 1.0, 1),
    ("approach delta", "mm", "delta_mm", 1.0, 6),
    ("F_x", "kN", "Fx_N", 1e-3, 2),
    ("F_y", "kN", "Fy_N", 1e-3, 2),
    ("p_max", "MPa", "p_max_MPa", 1.0, 0),
    ("W_T max", "N/mm", "WT_max_N_per_mm", 1.0, 2),
    ("P_T max", "W/mm^2", "PT_max_W_per_mm2", 1.0, 2),
    ("layer u(0) under load", "mm", "u0_mm", 1.0, 4),
    ("residual u_p(0) of the pass", "mm", "up0_mm", 1.0, 4),
)


def pass_values(record: PassRecord) -> dict[str, Any]:
    """The table's quantities of one pass, by result key (:data:`ROWS`)."""
    return {key: getattr(record, key) for _, _, key, _, _ in ROWS}


def scene_reference(result: SceneResult) -> dict[str, Any]:
    """The scene's ``[reference]`` values (published numbers, ``source``), from the result's inputs echo."""
    return result.inputs.get("reference") or {}


def contact_results(results: Results) -> dict[str, SceneResult]:
    """The contact scenes' results (those with passes) of a batch."""
    return {name: r for name, r in results.items() if getattr(r, "passes", None)}


def table_columns(results: Results) -> list[tuple[str, dict[str, Any]]]:
    """(column title, values by result key) for every scene result that has passes."""
    columns = []
    for name, result in contact_results(results).items():
        passes = result.passes
        if len(passes) > 1:
            columns.append((f"{name} (pass 1)", pass_values(passes[0])))
            columns.append((f"{name} (pass {len(passes)})", pass_values(passes[-1])))
        else:
            columns.append((name, pass_values(passes[-1])))
        reference = scene_reference(result)
        if any(key in reference for _, _, key, _, _ in ROWS):
            columns.append((f"{name}: {reference.get('source', 'reference')}", reference))
    return columns


def _cell(values: dict[str, Any], key: str, scale: float, decimals: int) -> str:
    value = values.get(key)
    if value is None:
        return "-"
    return f"{value * scale:.{decimals}f}"


def _markdown(header: list[str], rows: list[list[str]]) -> list[str]:
    return ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)] + ["| " + " | ".join(r) + " |" for r in rows]


def results_table(results: Results) -> tuple[str, str]:
    """The markdown and CSV texts of the full table (quantities in rows, scenes in columns); the markdown adds the
    wheel–rail scenes' key numbers (:func:`wheel_rail_rows`) when there are any."""
    columns = table_columns(results)
    header = ["quantity", "unit"] + [title for title, _ in columns]
    rows = [[label, unit] + [_cell(values, key, scale, dec) for _, values in columns]
            for label, unit, key, scale, dec in ROWS]
    md = _markdown(header, rows)
    wheel_rail = wheel_rail_rows(results)
    if wheel_rail:
        md += ["", "Wheel–rail scenes (largest absolute values over the cases and wheels):", ""]
        md += _markdown(WHEEL_RAIL_HEADER, wheel_rail)
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(header)
    writer.writerows(rows)
    return "\n".join(md) + "\n", buf.getvalue()


# ------------------------------------------------------------------------------------------- console summary
#: Widest line of :func:`summary_text` (terminal columns).
SUMMARY_WIDTH = 100
#: Widest scene name in the summary (longer names are cut, ending in "…").
NAME_WIDTH = 28
#: Columns of the contact-scene summary: (short label, result key; unit, scale and decimals from :data:`ROWS`).
SUMMARY_COLUMNS = (("area", "area_mm2"), ("delta", "delta_mm"), ("p_max", "p_max_MPa"), ("F_x", "Fx_N"),
                   ("F_y", "Fy_N"), ("u(0)", "u0_mm"))
#: Columns of the wheel–rail rows (console summary and table.md).
WHEEL_RAIL_HEADER = ["scene", "normal method", "cases", "failed", "patches", "N max kN", "p_max MPa", "Y/Q max"]


def _name(text: str) -> str:
    return text if len(text) <= NAME_WIDTH else text[:NAME_WIDTH - 1] + "…"


def contact_rows(results: Results) -> tuple[list[str], list[list[str]]]:
    """Header and rows of the contact scenes' summary: per scene its last pass, then its ``[reference]`` values
    (if any of the summary's) on an indented row."""
    spec = {key: (unit, scale, dec) for _, unit, key, scale, dec in ROWS}
    header = ["scene", "passes"] + [f"{label} {spec[key][0]}" for label, key in SUMMARY_COLUMNS]

    def cells(values: dict[str, Any]) -> list[str]:
        return [_cell(values, key, *spec[key][1:]) for _, key in SUMMARY_COLUMNS]

    rows = []
    for name, result in contact_results(results).items():
        rows.append([_name(name), str(len(result.passes))] + cells(pass_values(result.passes[-1])))
        reference = scene_reference(result)
        if any(key in reference for _, key in SUMMARY_COLUMNS):
            count = f"{reference['passes']:g}" if reference.get("passes") is not None else "-"
            rows.append([_name("  " + str(reference.get("source", "reference"))), count] + cells(reference))
    return header, rows


def _largest(values, fmt: str) -> str:
    """The largest absolute value formatted, "-" when there is none."""
    values = [abs(v) for v in values if v is not None]
    return format(max(values), fmt) if values else "-"


def wheel_rail_rows(results: Results) -> list[list[str]]:
    """One row per wheel–rail scene (:data:`WHEEL_RAIL_HEADER`): normal method, cases, failed cases, loaded
    patches, and the largest normal force (kN), p_max (MPa) and |Y/Q| over its cases and wheels."""
    rows = []
    for name, result in results.items():
        if getattr(result, "type", None) != "wheel_rail":
            continue
        wheels = [w for c in result.cases for w in (c.wheels or {}).values()]
        patches = [p for w in wheels for p in w.patches]
        method = result.inputs["method"]["normal"]  # the inputs echo
        rows.append([_name(name), method, str(len(result.cases)), str(result.n_failed), str(len(patches)),
                     _largest([p.normal_force_N / 1e3 for p in patches], ".1f"),
                     _largest([p.p_max_MPa for p in patches], ".0f"),
                     _largest([w.Y_over_Q for w in wheels], ".2f")])
    return rows


def _aligned(header: list[str], rows: list[list[str]]) -> list[str]:
    """Plain-text columns: the first left-aligned, the others right-aligned, two spaces between."""
    widths = [max(len(r[i]) for r in [header, *rows]) for i in range(len(header))]
    return ["  ".join(c.ljust(w) if i == 0 else c.rjust(w) for i, (c, w) in enumerate(zip(r, widths))).rstrip()
            for r in [header, *rows]]


#: Columns of a contact scene's pass rows in :func:`scene_summary` (label, result key; as :data:`SUMMARY_COLUMNS`).
PASS_COLUMNS = (("p_max", "p_max_MPa"), ("length", "length_mm"), ("width", "width_mm"), ("delta", "delta_mm"),
                ("F_x", "Fx_N"), ("F_y", "Fy_N"), ("u_p(0)", "up0_mm"))
#: Most pass rows of :func:`scene_summary`: more passes show the first and last ones around a "…" row.
SHOWN_PASSES = 6


def scene_summary(name: str, result: Any) -> list[str]:
    """The key numbers of one scene's result for the terminal (each line at most :data:`SUMMARY_WIDTH` columns):
    a contact scene's passes (p_max MPa, patch length and width mm, approach mm, F_x, F_y kN, the residual
    u_p(0) the pass left mm; the first and last passes when there are more than :data:`SHOWN_PASSES`), a
    wheel–rail sweep's row of :func:`wheel_rail_rows` (cases, failed, largest N, p_max, |Y/Q|)."""
    if getattr(result, "type", None) == "wheel_rail":
        title = f"{_name(name)}: {len(result.cases)} cases, {result.n_failed} failed; largest over the cases:"
        return [title, *_aligned(WHEEL_RAIL_HEADER, wheel_rail_rows({name: result}))]
    spec = {key: (unit, scale, dec) for _, unit, key, scale, dec in ROWS}
    header = ["pass"] + [f"{label} {spec[key][0]}" for label, key in PASS_COLUMNS]
    passes = list(result.passes)
    rows = [[str(p.index)] + [_cell(pass_values(p), key, *spec[key][1:]) for _, key in PASS_COLUMNS]
            for p in passes]
    if len(rows) > SHOWN_PASSES:
        head = SHOWN_PASSES // 2
        rows = rows[:head] + [["…"] + [""] * len(PASS_COLUMNS)] + rows[head + 1 - SHOWN_PASSES:]
    shakedown = getattr(result, "shakedown_pass", None)
    title = f"{_name(name)}: {len(passes)} pass{'es' if len(passes) > 1 else ''}" + (
        f", shakedown at pass {shakedown}" if shakedown is not None else "")
    return [title, *_aligned(header, rows)]


def wear_summary(name: str, steps, result_path: str | Path) -> list[str]:
    """The key numbers of a wear run's steps (:class:`contact.wear.records.StepRecord`) for the terminal: the
    distance run and where the result is, then per step its distance range (km), the largest wear depth (µm) with
    its body and position y (mm), and the rolling radius difference dr (mm)."""
    done_km = steps[-1].end_km if steps else 0.0
    lines = [f"{name}: {len(steps)} steps, {done_km:.6g} km -> {result_path}, steps.csv, profiles/"]
    for rec in steps:
        (side, body), worst = max(rec.bodies.items(), key=lambda item: item[1].stats.wear_max_mm)
        lines.append(f"  step {rec.index}: {rec.start_km:.6g}..{rec.end_km:.6g} km, max wear "
                     f"{worst.stats.wear_max_mm * 1e3:.2f} µm ({side} {body} at y = {worst.stats.wear_max_y_mm:.2f}"
                     f" mm), dr = {rec.conicity.delta_r_mm:.4f} mm")
    return lines


def summary_text(results: Results, out_dir: str | Path) -> str:
    """The console summary of a batch: one table per scene kind (at most :data:`SUMMARY_WIDTH` columns), then
    where the full table and the per-scene results are (one path a line, indented)."""
    out = Path(out_dir)
    parts = []
    header, rows = contact_rows(results)
    if rows:
        parts += ["contact scenes: last pass (indented: the scene's [reference])", *_aligned(header, rows), ""]
    wheel_rail = wheel_rail_rows(results)
    if wheel_rail:
        parts += ["wheel–rail scenes: largest absolute values over the cases and wheels",
                  *_aligned(WHEEL_RAIL_HEADER, wheel_rail), ""]
    parts += ["full table (every pass, all quantities, references) and each scene's result:",
              f"  {out / 'table.md'}", f"  {out / 'table.csv'}", f"  {out / '<scene>' / 'result.json'}"]
    return "\n".join(parts)
