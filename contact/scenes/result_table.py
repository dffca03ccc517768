"""A table like the paper's Table 1 from several scene results (markdown and CSV).

Rows: patch length, width, area, approach delta, F_x, F_y, p_max, W_T max, P_T max (Table 1), then the layer
displacement u(0) at the reference point under load and the residual u_p(0) the pass left there (reported in the
paper's text for the first pass). Columns: one per scene (its
last pass); scenes with several passes also get their first pass; scenes with a ``[reference]`` (published values)
get a column with those beside.
"""

from __future__ import annotations

import csv
import io
from typing import Any

#: (label, unit, result key, scale, decimals)
ROWS = (
    ("patch length", "mm", "length_mm", 1.0, 2),
    ("patch width", "mm", "width_mm", 1.0, 2),
    ("area", "mm^2", "area_mm2", 1.0, 1),
    ("approach delta", "mm", "delta_mm", 1.0, 6),
    ("F_x", "kN", "Fx_N", 1e-3, 2),
    ("F_y", "kN", "Fy_N", 1e-3, 2),
    ("p_max", "MPa", "p_max_MPa", 1.0, 0),
    ("W_T max", "N/mm", "WT_max", 1.0, 2),
    ("P_T max", "W/mm^2", "PT_max_W_per_mm2", 1.0, 2),
    ("layer u(0) under load", "mm", "u0_mm", 1.0, 4),
    ("residual u_p(0) of the pass", "mm", "up0_mm", 1.0, 4),
)


def table_columns(results: dict[str, dict[str, Any]]) -> list[tuple[str, dict[str, Any]]]:
    """(column title, values by result key) for every scene result that has passes."""
    columns = []
    for name, result in results.items():
        passes = result.get("passes")
        if not passes:
            continue
        if len(passes) > 1:
            columns.append((f"{name} (pass 1)", passes[0]))
            columns.append((f"{name} (pass {len(passes)})", passes[-1]))
        else:
            columns.append((name, passes[-1]))
        reference = (result.get("inputs") or {}).get("reference") or {}
        if any(key in reference for _, _, key, _, _ in ROWS):
            columns.append((f"{name}: {reference.get('source', 'reference')}", reference))
    return columns


def _cell(values: dict[str, Any], key: str, scale: float, decimals: int) -> str:
    value = values.get(key)
    if value is None:
        return "-"
    return f"{value * scale:.{decimals}f}"


def results_table(results: dict[str, dict[str, Any]]) -> tuple[str, str]:
    """The markdown and CSV texts of the table (quantities in rows, scenes in columns)."""
    columns = table_columns(results)
    header = ["quantity", "unit"] + [title for title, _ in columns]
    rows = [[label, unit] + [_cell(values, key, scale, dec) for _, values in columns]
            for label, unit, key, scale, dec in ROWS]
    md = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    md += ["| " + " | ".join(row) + " |" for row in rows]
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(header)
    writer.writerows(rows)
    return "\n".join(md) + "\n", buf.getvalue()
