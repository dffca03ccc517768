"""The shipped tables' rolling law fitted where it is compared: on the profile sections at h = a/4 (units mm, MPa).

The tables' patch-shape nodes were fitted to half-space blocks at h = a/2; rolled again at h = a/4 on the
sections, the groove over the static dent moved by up to 8 % and the law overstated the a/4 groove by 6-12 % at
1.15-1.3 p_y (docs/validation/rolling-section-gap.md). Here the nodes the sections reach (:data:`NODES`) are fitted
(:func:`calibration.rolling.law_fit.fit_passes`) to the refined section runs of
:mod:`benchmarks.rolling_section_refined`: per node, level and traction, the a/4 groove over the same run's a/4
static dent, passes 1-5, without a constant increment per pass (:data:`RATCHETING`). One node per position: the
round ones (a/b about 1.34) at their position's surface convexity b / (2 R) (:func:`position_convexity`; rail:
crown +0.009 and gauge corner +0.100; wheel: tread -0.008 and flange root -0.100), which the law interpolates
linearly; two positions of one table needed G_n up to 12 % apart at the same x (:func:`spread_markdown`), more than
any node of x and c alone can serve within 5 %. The long-patch node (a/b 3.83) is the rail field side, whose Hertz
patch has that shape, in both tables. A node's level x = p0 / p_2 is the run's peak pressure over the table's p_2
at the position, and the law is resampled to the levels of the tables' other nodes by its own bilinear rule. The
very long node (a/b 10.2, no section reaches it) stays as the table holds it (blocks,
:data:`benchmarks.rolling_gap.LONG_PATCHES`).

Checked beyond the fit: the positions of :data:`CHECKS`, rolled but not fitted (the wheel at y = -22.5 mm, b/(2R)
-0.036, between the tread and the flange root; the rail at y = -25 mm, +0.034, between the crown and the gauge
corner; the rail at y = -30 mm, a clamped patch on the corner's R13 like the corner's own; the rail at y = -20 mm,
whose table patch is the y = -25 mm one's, a, b and b/(2R) alike, wholly on R80; the wheel at y = -7.5 mm, an oval
patch, a/b 2.36, between the round and the long-patch nodes, at the tread's convexity), against their table's law
(:func:`law_markdown`).

``python -m benchmarks.rolling_section_law RUNS REFINED [--write-tables]``: RUNS the gap's a/2 runs
(``benchmarks/data/rolling_section_gap``, for the cases' peak pressures), REFINED the a/4 runs
(``benchmarks/data/rolling_section_refined``); prints the fit and with ``--write-tables`` writes the laws into the
shipped default tables (``rolling_law`` with convexity nodes, format version 5; the characteristics are
unchanged). A table with a node whose runs are incomplete is not written.
"""

from __future__ import annotations

import argparse
import functools
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from benchmarks.rolling_gap import long_patch_index, write_law
from benchmarks.rolling_section_cases import COMPARED, LEVELS, POSITIONS, ROOT, TARGET, TRACTIONS
from benchmarks.rolling_section_refined import REFINED_ELEMENTS, cases_of, complete_run
from calibration.rolling.law_fit import PassFit, fit_passes, rolling_law
from wrlayer.layer_table import LayerTable
from wrlayer.rolling_law import RollingLaw

RAIL_TABLE = "scenes/tables/rail_60E1_default.json"
WHEEL_TABLE = "scenes/tables/wheel_S1002_default.json"


@dataclass(frozen=True)
class SectionNode:
    """One patch-shape node fitted here: the tables it is written into, the law group whose a/b it takes
    (:data:`benchmarks.rolling_gap.GROUPS`: the table's own round group, or "long patch") and the position (a name of
    POSITIONS) whose runs it is fitted to, at that position's convexity (:func:`position_convexity`)."""

    tables: tuple[str, ...]
    group: str
    name: str


#: The nodes fitted to the sections: each table's two round positions, and the long-patch node from the field side.
NODES = (SectionNode((RAIL_TABLE,), "rail", "crown"), SectionNode((RAIL_TABLE,), "rail", "corner"),
         SectionNode((WHEEL_TABLE,), "wheel", "tread"), SectionNode((WHEEL_TABLE,), "wheel", "flange"),
         SectionNode((RAIL_TABLE, WHEEL_TABLE), "long patch", "field"))
#: Positions rolled but not fitted, each a check of its table's law between the nodes: {name: table}.
CHECKS = {"inner": WHEEL_TABLE, "gauge": RAIL_TABLE, "corner_upper": RAIL_TABLE, "gauge_upper": RAIL_TABLE,
          "tread_oval": WHEEL_TABLE}
#: Each table's two round positions, whose needs :func:`spread_markdown` compares.
ROUND_PAIRS = (("crown", "corner"), ("tread", "flange"))

#: The nodes have no constant increment per pass (B = 0, :func:`calibration.rolling.law_fit.fit_passes`): at
#: every a/4 section run the increments fall pass after pass (successive ratios over passes 2-5 <= 0.4, at the
#: field side <= 0.49) and the 10-pass runs (``rolling_section_refined --long``) shake down; a B fitted to 5
#: passes reads the slowly falling tail as ratcheting (at the crown, c = 0.2, 1.5 p_y: G_60 10 % above the
#: 10-pass run's groove).
RATCHETING = False


@dataclass(frozen=True)
class SectionRun:
    """One refined run: position name, traction c (-), the gap's level p0 / p_y (-), x = p0 / p_2 of the table at
    the position (-), the groove over the run's static dent after passes 1..n (-) and that static dent over the
    table's residual r at the same p0 (-)."""

    name: str
    c: float
    level: float
    x: float
    ratios: tuple[float, ...]
    dent_over_r: float = 1.0

    def required(self) -> np.ndarray:
        """The G_n (-) that puts the table's layer on this run's groove at passes 1..n: FEM groove over r."""
        return np.asarray(self.ratios) * self.dent_over_r


def section_runs(rows, refined: Path) -> list[SectionRun]:
    """The complete refined runs of the :data:`NODES` and :data:`CHECKS` positions (``rows``: the gap's a/2 rows,
    :class:`benchmarks.bench_rolling_section_gap.SectionGapRow`, for each case's p0 and the table's p_2)."""
    by_case = {(r.position, r.c, r.level): r for r in rows}
    out = []
    for name in [node.name for node in NODES] + list(CHECKS):
        for case in cases_of(rows, name):
            run = complete_run(refined / case.key)
            if run is None:
                continue
            lv = run["levels"][0]
            ratios = tuple(g / lv["static_dent_mm"] for g in lv["groove_mm"])
            level = round(case.level, 6)  # the gap's level as read back from JSON (1.4999999999999998)
            row = by_case[case.label, case.c, case.level]
            out.append(SectionRun(name, case.c, level, case.p0_MPa / row.p_2_MPa, ratios,
                                  lv["static_dent_mm"] / row.table_residual_mm))
    return out


def fit_node(runs: list[SectionRun], names) -> tuple[RollingLaw, dict[tuple[float, float], PassFit]]:
    """The node fitted to the mean ratio of the positions ``names``, on the levels :data:`LEVELS` (KeyError
    when a level or traction of these positions has no run), and the fits {(c, x): PassFit}."""
    mine = [r for r in runs if r.name in names]
    fits: dict[tuple[float, float], PassFit] = {}
    xs = []
    for lv in LEVELS:
        at = [r for r in mine if r.level == lv]
        if {(r.name, r.c) for r in at} != {(n, c) for n in names for c in TRACTIONS}:
            raise KeyError(f"{', '.join(names)}: the refined runs at {lv:g} p_y are incomplete")
        xs.append(float(np.mean([r.x for r in at])))
        for c in TRACTIONS:
            series = [r.ratios for r in at if r.c == c]
            n = min(len(s) for s in series)
            fits[(c, xs[-1])] = fit_passes(np.mean([s[:n] for s in series], axis=0), 1.0, ratcheting=RATCHETING)
    source = (f"rolling FEM on the profile sections of {' and '.join(names)} (benchmarks.rolling_section_refined: "
              f"h = a/{REFINED_ELEMENTS:g} quadratic tetrahedra, step a/4, track 1.5 contact lengths, "
              f"{min(len(r.ratios) for r in mine)} passes at constant p0; shakedown only, B = 0)")
    law = rolling_law(xs, list(TRACTIONS), fits, source)
    return on_levels(law, LEVELS), fits


def on_levels(law: RollingLaw, levels) -> RollingLaw:
    """``law`` resampled to the levels ``levels`` by its own rule (bilinear, clamped)."""
    x, c = np.meshgrid(np.asarray(levels, dtype=float), np.asarray(law.traction_coefficient))
    params = [p.tolist() for p in law.parameters(x, c)]
    return RollingLaw(list(levels), list(law.traction_coefficient), *params, source=law.source)


def complete_nodes(runs: list[SectionRun]) -> dict[SectionNode, RollingLaw]:
    """The :data:`NODES` whose runs are complete, each fitted (:func:`fit_node`)."""
    out = {}
    for node in NODES:
        try:
            out[node] = fit_node(runs, (node.name,))[0]
        except KeyError:
            continue
    return out


def position_convexity(name: str) -> float:
    """The surface convexity b / (2 R) (-) of the position ``name`` of POSITIONS at its table's reference patch
    (the patch that rolls its section): b from the table's geometry, 1/R its ``lateral_curvature_at``."""
    return _position_shape(name)[1]


def position_aspect(name: str) -> float:
    """The a/b (-) of the position's reference patch (a along the rolling direction)."""
    return _position_shape(name)[0]


@functools.lru_cache(maxsize=None)
def _position_shape(name: str) -> tuple[float, float]:
    _, table_rel, y_mm, _ = next(p for p in POSITIONS if p[0] == name)
    table = LayerTable.read(ROOT / table_rel)
    geo = next(p for p in table.positions if float(p["y_mm"]) == float(y_mm))["geometry"]
    b = float(geo["b_mm"])
    return float(geo["a_mm"]) / b, 0.5 * b * table.lateral_curvature_at(float(y_mm))


def table_laws(nodes: dict[SectionNode, RollingLaw]) -> dict[str, RollingLaw]:
    """Per table, the law its nodes give (``nodes``: :func:`complete_nodes`): each fitted node at its group's a/b
    (the table's stored round and long-patch a/b) and its position's convexity, and the stored very long node
    (blocks, flat: convexity 0). A table one of whose nodes is missing is left out."""
    out = {}
    for table_rel in (RAIL_TABLE, WHEEL_TABLE):
        mine = [n for n in NODES if table_rel in n.tables]
        if any(n not in nodes for n in mine):
            continue
        stored = LayerTable.read(ROOT / table_rel).rolling_law
        aspects = sorted(set(stored.aspect_ratio))  # the round, long and very long groups
        shapes = [(aspects[1] if n.group == "long patch" else aspects[0], position_convexity(n.name), nodes[n])
                  for n in mine]
        shapes.append((aspects[-1], 0.0, stored.node(long_patch_index("very long patch", stored))))
        out[table_rel] = RollingLaw.by_shape(sorted(shapes, key=lambda t: (t[0], t[1])))
    return out


def law_markdown(runs: list[SectionRun]) -> str:
    """Per refined run: the FEM's groove over its static dent (passes :data:`COMPARED`) and the table's law
    (:func:`table_laws`, at the position's a/b and convexity) over it; the nodes' own positions and the
    :data:`CHECKS` (held out) counted apart."""
    passes = ", ".join(str(n) for n in COMPARED)
    lines = [f"| position | role | c | p0 / p_y | x = p0 / p_2 | b/(2R) | FEM groove / static dent at "
             f"a/{REFINED_ELEMENTS:g}, passes {passes} | table's law / FEM |", "|---|---|---|---|---|---|---|---|"]
    laws = table_laws(complete_nodes(runs))
    tables = {**{n.name: n.tables[0] for n in NODES}, **CHECKS}
    counts = {"node": [0, 0], "held out": [0, 0]}
    n = np.array(COMPARED)
    for r in runs:
        law = laws.get(tables[r.name])
        if law is None:
            continue
        role = "held out" if r.name in CHECKS else "node"
        s = position_convexity(r.name)
        fem = np.asarray(r.ratios)[n - 1]
        ratio = law.factor(n, r.x, r.c, position_aspect(r.name), s) / fem
        counts[role][0] += bool(np.all(np.abs(ratio - 1.0) <= TARGET))
        counts[role][1] += 1
        lines.append(f"| {r.name} | {role} | {r.c:g} | {r.level:g} | {r.x:.3f} | {s:+.3f} | {_joined(fem)} | "
                     f"{_joined(ratio)} |")
    return _with_summary(lines, f"The tables' laws reproduce the groove over the static dent within {TARGET:.0%} "
                                f"after passes {passes} in {counts['node'][0]} of {counts['node'][1]} cases at "
                                f"their nodes' positions and in {counts['held out'][0]} of "
                                f"{counts['held out'][1]} at the positions held out.")


def spread_markdown(runs: list[SectionRun]) -> str:
    """Per pair of :data:`ROUND_PAIRS`, level and traction: the G_n each position needs (FEM groove over the table's
    r, :meth:`SectionRun.required`) at passes :data:`COMPARED`, both at the mean of the two positions' x = p0 / p_2
    (each position's need linear in x between its levels), larger over
    smaller, and how many cases no single node can serve within :data:`TARGET` at both positions (needed spread
    above (1 + T) / (1 - T))."""
    limit = (1.0 + TARGET) / (1.0 - TARGET)
    n = np.array(COMPARED)
    lines = [f"| positions | c | p0 / p_y | x | G needed, larger / smaller, passes {', '.join(map(str, COMPARED))} |",
             "|---|---|---|---|---|"]
    beyond = 0
    for names in ROUND_PAIRS:
        for c in TRACTIONS:
            own = {m: sorted((r for r in runs if r.name == m and r.c == c), key=lambda r: r.x) for m in names}
            if any(len(v) < 2 for v in own.values()):
                continue
            for lv in LEVELS:
                pair = [r for v in own.values() for r in v if r.level == lv]
                if len(pair) != 2:
                    continue
                x = float(np.mean([r.x for r in pair]))
                a, b = (_need_at(own[m], x)[n - 1] for m in names)
                spread = np.maximum(a, b) / np.minimum(a, b)
                beyond += bool(np.any(spread > limit))
                lines.append(f"| {' and '.join(names)} | {c:g} | {lv:g} | {x:.3f} | {_joined(spread)} |")
    return _with_summary(lines, f"In {beyond} of {len(lines) - 2} cases the two positions need G_n further apart "
                                f"than {limit:.3f} at the same x: there no node of x and c alone puts the layer "
                                f"within {TARGET:.0%} of both grooves (the tables' round nodes are therefore one "
                                f"per position, at its convexity).")


def _need_at(series: list[SectionRun], x: float) -> np.ndarray:
    """The G_n one position needs at x (-), linear between (and beyond, from the end pairs) its runs sorted by x."""
    k = int(np.clip(np.searchsorted([r.x for r in series], x) - 1, 0, len(series) - 2))
    lo, hi = series[k], series[k + 1]
    m = min(len(lo.ratios), len(hi.ratios))
    w = (x - lo.x) / (hi.x - lo.x)
    return (1.0 - w) * lo.required()[:m] + w * hi.required()[:m]


def _with_summary(lines: list[str], summary: str) -> str:
    """A markdown table (``lines``: header, rule and rows) followed by its summary sentence; "" without rows."""
    return "" if len(lines) == 2 else "\n".join(lines + ["", summary])


def _joined(values) -> str:
    return ", ".join(f"{v:.3f}" for v in values)


def main(argv: list[str] | None = None) -> None:
    from benchmarks.bench_rolling_section_gap import collect  # the gap's rows (that module reads this one)

    ap = argparse.ArgumentParser(prog="python -m benchmarks.rolling_section_law", description=__doc__.splitlines()[0])
    ap.add_argument("runs", type=Path, help="the section gap's a/2 runs (benchmarks/data/rolling_section_gap)")
    ap.add_argument("refined", type=Path, help="the a/4 runs (benchmarks/data/rolling_section_refined)")
    ap.add_argument("--write-tables", action="store_true", help="write the fitted nodes into the shipped tables")
    args = ap.parse_args(argv)
    runs = section_runs(collect(args.runs, False), args.refined)
    print(law_markdown(runs))
    print(spread_markdown(runs))
    if args.write_tables:
        for table_rel, law in table_laws(complete_nodes(runs)).items():
            print(f"wrote {write_law(table_rel, law)}")


if __name__ == "__main__":
    main()
