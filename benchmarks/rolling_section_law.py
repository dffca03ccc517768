"""The shipped tables' rolling law fitted where it is compared: on the profile sections at h = a/4 (units mm, MPa).

The tables' patch-shape nodes were fitted to half-space blocks at h = a/2; rolled again at h = a/4 on the
sections, the groove over the static dent moved by up to 8 % and the law overstated the a/4 groove by 6-12 % at
1.15-1.3 p_y (docs/validation/rolling-section-gap.md). Here the nodes the sections reach (:data:`NODES`) are fitted
(:func:`calibration.rolling.law_fit.fit_passes`) to the refined section runs of
:mod:`benchmarks.rolling_section_refined`: per node, level and traction, the mean over the node's positions of the
a/4 groove over the same run's a/4 static dent, passes 1-5, without a constant increment per pass
(:data:`RATCHETING`). The round node (a/b about 1.34) is each table's own two positions (rail: crown and gauge
corner; wheel: tread and flange root); the long-patch node (a/b 3.83) is the rail field side, whose Hertz patch
has that shape, in both tables. Its level x = p0 / p_2 is the run's peak pressure over the table's p_2 at the
position (mean over the positions), and the law is resampled to the levels of the tables' other nodes by its own
bilinear rule. The very long node (a/b 10.2, no section reaches it) stays as the table holds it (blocks,
:data:`benchmarks.rolling_gap.LONG_PATCHES`).

Checked beyond the fit: each position of a two-position node against the law fitted to the other position alone
(:func:`law_markdown`, column "other position's law"), and how far apart the two positions' needs are
(:func:`spread_markdown`).

``python -m benchmarks.rolling_section_law RUNS REFINED [--write-tables]``: RUNS the gap's a/2 runs
(``benchmarks/data/rolling_section_gap``, for the cases' peak pressures), REFINED the a/4 runs
(``benchmarks/data/rolling_section_refined``); prints the fit and with ``--write-tables`` writes the nodes into the
shipped default tables (``rolling_law``, format version 3; the characteristics are unchanged).
The fit of a node whose runs are incomplete is left out (the table keeps its stored node).
"""

from __future__ import annotations

import argparse
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from benchmarks.rolling_gap import long_patch_index, with_nodes, write_law
from benchmarks.rolling_section_cases import COMPARED, LEVELS, POSITIONS, ROOT, TARGET, TRACTIONS
from benchmarks.rolling_section_refined import REFINED_ELEMENTS, cases_of, complete_run
from calibration.rolling.law_fit import PassFit, fit_passes, rolling_law
from wrlayer.rolling_law import RollingLaw

RAIL_TABLE = "scenes/tables/rail_60E1_default.json"
WHEEL_TABLE = "scenes/tables/wheel_S1002_default.json"


@dataclass(frozen=True)
class SectionNode:
    """One patch-shape node fitted here: the tables it is written into, its index among their nodes
    (``RollingLaw.aspect_ratio``, 0 = round) and the positions (names of POSITIONS) whose mean it is."""

    tables: tuple[str, ...]
    index: int
    names: tuple[str, ...]


#: The nodes fitted to the sections: each table's round node, and the long-patch node from the field side.
NODES = (SectionNode((RAIL_TABLE,), 0, ("crown", "corner")), SectionNode((WHEEL_TABLE,), 0, ("tread", "flange")),
         SectionNode((RAIL_TABLE, WHEEL_TABLE), long_patch_index("long patch"), ("field",)))

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
    """The complete refined runs of the :data:`NODES` positions (``rows``: the gap's a/2 rows,
    :class:`benchmarks.bench_rolling_section_gap.SectionGapRow`, for each case's p0 and the table's p_2)."""
    by_case = {(r.position, r.c, r.level): r for r in rows}
    out = []
    for name in (n for node in NODES for n in node.names):
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
            out[node] = fit_node(runs, node.names)[0]
        except KeyError:
            continue
    return out


def fitted_nodes(runs: list[SectionRun]) -> dict[str, dict[int, RollingLaw]]:
    """Per table, the :data:`NODES` whose runs are complete, fitted: {table: {index: law}}."""
    out: dict[str, dict[int, RollingLaw]] = {}
    for node, law in complete_nodes(runs).items():
        for table_rel in node.tables:
            out.setdefault(table_rel, {})[node.index] = law
    return out


def law_markdown(runs: list[SectionRun]) -> str:
    """Per refined run: the FEM's groove over its static dent (passes :data:`COMPARED`), the node fitted here
    over it, and (nodes of two positions) the node fitted to the other position alone over it."""
    passes = ", ".join(str(n) for n in COMPARED)
    lines = [f"| position | c | p0 / p_y | x = p0 / p_2 | FEM groove / static dent at a/{REFINED_ELEMENTS:g}, passes "
             f"{passes} | fitted node / FEM | other position's law / FEM |", "|---|---|---|---|---|---|---|"]
    counts = {"own": 0, "other": 0, "held out": 0}
    n = np.array(COMPARED)
    for node, own in complete_nodes(runs).items():
        other = {m: fit_node(runs, tuple(k for k in node.names if k != m))[0] for m in node.names
                 if len(node.names) > 1}
        for r in (r for r in runs if r.name in node.names):
            fem = np.asarray(r.ratios)[n - 1]
            mine = own.factor(n, r.x, r.c) / fem
            counts["own"] += bool(np.all(np.abs(mine - 1.0) <= TARGET))
            held_out = "—"
            if r.name in other:
                theirs = other[r.name].factor(n, r.x, r.c) / fem
                counts["held out"] += 1
                counts["other"] += bool(np.all(np.abs(theirs - 1.0) <= TARGET))
                held_out = _joined(theirs)
            lines.append(f"| {r.name} | {r.c:g} | {r.level:g} | {r.x:.3f} | {_joined(fem)} | {_joined(mine)} | "
                         f"{held_out} |")
    total = len(lines) - 2
    if total == 0:
        return ""
    lines += ["", f"The nodes fitted to these runs reproduce the groove over the static dent within {TARGET:.0%} after "
                  f"passes {passes} in {counts['own']} of {total} cases; fitted to the other position of a "
                  f"two-position node alone, in {counts['other']} of {counts['held out']}."]
    return "\n".join(lines)


def spread_markdown(runs: list[SectionRun]) -> str:
    """Per two-position node, level and traction: the G_n each position needs (FEM groove over the table's r,
    :meth:`SectionRun.required`) at passes :data:`COMPARED`, both at the node's x (the mean of the two positions'
    x = p0 / p_2, as :func:`fit_node` places it; each position's need linear in x between its levels), larger over
    smaller, and how many cases no single node can serve within :data:`TARGET` at both positions (needed spread
    above (1 + T) / (1 - T))."""
    limit = (1.0 + TARGET) / (1.0 - TARGET)
    n = np.array(COMPARED)
    lines = [f"| node | c | p0 / p_y | x | G needed, larger / smaller, passes {', '.join(map(str, COMPARED))} |",
             "|---|---|---|---|---|"]
    beyond = 0
    for node in (nd for nd in NODES if len(nd.names) == 2):
        for c in TRACTIONS:
            own = {m: sorted((r for r in runs if r.name == m and r.c == c), key=lambda r: r.x) for m in node.names}
            if any(len(v) < 2 for v in own.values()):
                continue
            for lv in LEVELS:
                pair = [r for v in own.values() for r in v if r.level == lv]
                if len(pair) != 2:
                    continue
                x = float(np.mean([r.x for r in pair]))
                a, b = (_need_at(own[m], x)[n - 1] for m in node.names)
                spread = np.maximum(a, b) / np.minimum(a, b)
                beyond += bool(np.any(spread > limit))
                lines.append(f"| {' and '.join(node.names)} | {c:g} | {lv:g} | {x:.3f} | {_joined(spread)} |")
    if len(lines) == 2:
        return ""
    return "\n".join(lines + ["", f"In {beyond} of {len(lines) - 2} cases the two positions need G_n further apart "
                                   f"than {limit:.3f} at the same x: there no node of this law (a function of x "
                                   f"and c) puts the layer within {TARGET:.0%} of both grooves."])


def _need_at(series: list[SectionRun], x: float) -> np.ndarray:
    """The G_n one position needs at x (-), linear between (and beyond, from the end pairs) its runs sorted by x."""
    k = int(np.clip(np.searchsorted([r.x for r in series], x) - 1, 0, len(series) - 2))
    lo, hi = series[k], series[k + 1]
    m = min(len(lo.ratios), len(hi.ratios))
    w = (x - lo.x) / (hi.x - lo.x)
    return (1.0 - w) * lo.required()[:m] + w * hi.required()[:m]


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
        for table_rel, fitted in fitted_nodes(runs).items():
            print(f"wrote {write_law(table_rel, with_nodes(table_rel, fitted))}")


if __name__ == "__main__":
    main()
