"""FaStrip's model coefficients at its interpolation nodes, shipped as a table for the default cells per strip.

Units: the coefficients are dimensionless (k_x, k_phi of
:func:`contact.tangential.fastrip.solve_model_coefficients`: the strip model's full-adhesion forces on the ellipse
a = 1 mm per unit creepage and spin). Each node a/b = 10^(k / NODES_PER_DECADE) costs a linear solve of every strip
(about 5 ms); a wheel–rail sweep meets some fifty of them, a fifth of FaStrip's time on the A-2.2 sweep when every
process solved its own. The table holds the nodes
k = -:data:`TABLE_HALF_RANGE` .. +:data:`TABLE_HALF_RANGE` (a/b from 0.01 to 100) for :data:`TABLE_CELLS` cells
per strip, as this module computes them (``python -m contact.tangential.fastrip_nodes`` writes it again); other
nodes and other cell counts are solved when first met.
"""

from __future__ import annotations

import functools
import json
from pathlib import Path

__all__ = ["TABLE_CELLS", "TABLE_HALF_RANGE", "TABLE_PATH", "table_node", "write_table"]

#: Cells per strip of the shipped table (``method.fastsim_cells``'s default).
TABLE_CELLS = 60
#: The table's nodes k = -TABLE_HALF_RANGE .. TABLE_HALF_RANGE (two decades of a/b either side of 1 at 32 per
#: decade).
TABLE_HALF_RANGE = 64
TABLE_PATH = Path(__file__).with_name("fastrip_nodes.json")


@functools.cache
def _table() -> tuple[int, int, dict[int, tuple[float, float]]]:
    """(cells per strip, nodes per decade, {k: (k_x, k_phi)}) of the shipped table."""
    data = json.loads(TABLE_PATH.read_text(encoding="utf-8"))
    nodes = {int(k): (float(kx), float(kp)) for k, kx, kp in zip(data["k"], data["k_x"], data["k_phi"])}
    return int(data["cells"]), int(data["nodes_per_decade"]), nodes


def table_node(k: int, nx: int, nodes_per_decade: int) -> tuple[float, float] | None:
    """(k_x, k_phi) of node ``k`` from the shipped table, or None when the table does not hold it (another cell
    count or node spacing, or a node beyond its range)."""
    cells, spacing, nodes = _table()
    if nx != cells or nodes_per_decade != spacing:
        return None
    return nodes.get(int(k))


def write_table(path: Path = TABLE_PATH) -> None:
    """Solve every node of the table and write it to ``path`` (JSON; numbers with their full precision)."""
    from contact.tangential.fastrip import NODES_PER_DECADE, solve_model_coefficients
    from wrlayer.atomic_write import atomic_write_text

    ks = list(range(-TABLE_HALF_RANGE, TABLE_HALF_RANGE + 1))
    values = [solve_model_coefficients(10.0 ** (k / NODES_PER_DECADE), TABLE_CELLS) for k in ks]
    data = {"units": "-", "written_by": "python -m contact.tangential.fastrip_nodes", "cells": TABLE_CELLS,
            "nodes_per_decade": NODES_PER_DECADE, "k": ks, "k_x": [v[0] for v in values],
            "k_phi": [v[1] for v in values]}
    atomic_write_text(path, json.dumps(data, indent=1) + "\n")


if __name__ == "__main__":
    write_table()
    print(f"wrote {TABLE_PATH}")
