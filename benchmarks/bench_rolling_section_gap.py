"""The rolling layer against the rolling FEM on the profile SECTION (units mm, MPa, s).

The gap cases of :mod:`benchmarks.rolling_gap_cases` roll on the half-space block with each position's patch;
the block's static dent is 13-16 % below the shipped tables' residuals at h = a/2, while the section's is within
about 3 % (docs/rolling.md, "Accuracy"). Here five positions of the default tables (60E1 rail crown y = 0, gauge
corner y = -35 mm and field side y = 25 mm, S1002 wheel tread y = 0 and flange root y = -37.5 mm) are rolled on
their own sections at the gap's coarse discretisation (h = a/2 quadratic tetrahedra, step a/4, track 1.5 contact
lengths, run-out 4 a), levels 1.15, 1.3, 1.5, 1.7, 2.1 p_y (p_y: the section's FEM first yield), traction
coefficients 0 and 0.2, five passes at constant p0, and the FEM groove after passes 1, 2 and 5 is compared with what
the contact code applies AT THE SAME PEAK PRESSURE p0 (MPa): the table's residual r(p0) (the element's exact
unloading, ``Characteristic.unloading_residual``) times the table's rolling law G_n at p0 / p_2
(:class:`wrlayer.rolling_law.RollingLaw`), and the two static memory rules. (At equal normalised level instead, a
1 % difference between the section's p_y and the table's p_2 moves the layer's residual near first yield by some
10 %.)

``python -m benchmarks.bench_rolling_section_gap --runs DIR [--run]``: ``--run`` runs the configurations (:func:`section_config`) that have
no ``DIR/<case>/rolling.json`` yet (one per position and traction; about 15 minutes each on the project's busy
2-core machine), then the table is printed and written to ``DIR/section_gap.md``.
"""

from __future__ import annotations

import argparse
import json
import pathlib
import sys
from dataclasses import dataclass

from benchmarks.harness import command_line, stamped_report
from benchmarks.rolling_section_cases import COMPARED, POSITIONS, ROOT, TARGET, TRACTIONS, case_name, section_config
from benchmarks.rolling_section_law import law_markdown, section_runs, spread_markdown
from benchmarks.rolling_section_refined import (LONG_PASSES, REFINED_ELEMENTS, check_markdown, long_markdown,
                                                refined_markdown)
from benchmarks.rolling_section_static import mesh_factor, read_study, study_markdown
from calibration.rolling.run import run_rolling
from calibration.rolling.section_position import table_position
from wrlayer.layer_table import LayerTable


@dataclass(frozen=True)
class SectionGapRow:
    """One case: position label, traction c (-), level p0 / p_y (-), section p_y and table p_2 (MPa), the FEM's
    static dent and the table's residual r (mm), the FEM groove after the compared passes (mm) and the layer's
    groove with the rolling law, "relaxed" and "state kept" after the same passes (mm)."""

    position: str
    c: float
    level: float
    p_y_MPa: float
    p_2_MPa: float
    static_dent_mm: float
    table_residual_mm: float
    fem_mm: tuple[float, ...]
    law_mm: tuple[float, ...]
    relaxed_mm: tuple[float, ...]
    state_kept_mm: tuple[float, ...]

    def law_over_fem(self, mesh_factor: float = 1.0) -> tuple[float, ...]:
        """The layer's groove over the FEM groove times ``mesh_factor`` (the static dent's finest-mesh / a/2
        factor, :func:`benchmarks.rolling_section_static.mesh_factor`: the mesh-corrected groove), per pass."""
        return tuple(lw / (f * mesh_factor) for lw, f in zip(self.law_mm, self.fem_mm))

    def ratio_over_fem_ratio(self) -> tuple[float, ...]:
        """The rolling law's own share of the gap: G_n (the layer's groove over its static residual r) over the
        FEM's groove over the FEM's static dent at the same p0. law / FEM = this x (r / FEM static dent): what is
        left is the static dent's mismatch between the section mesh and the table's FEM, not the law."""
        return tuple((lw / self.table_residual_mm) / (f / self.static_dent_mm)
                     for lw, f in zip(self.law_mm, self.fem_mm))


def rows_of(run: dict, table_rel: str, y_mm: float, label: str, c: float) -> list[SectionGapRow]:
    """The rows of one rolling.json (its levels with all compared passes done)."""
    ch = LayerTable.read(ROOT / table_rel).characteristic_at(y_mm)
    law, shape = table_law(table_rel, y_mm)
    p_2 = ch.elastic_limit_MPa
    rows = []
    for lv in run["levels"]:
        grooves = lv["groove_mm"]
        if len(grooves) < max(COMPARED):
            continue
        x = lv["p0_over_py"]
        p0 = x * run["p_y_MPa"]  # the FEM's peak pressure (MPa): the layer is compared at the same p0
        r = float(ch.unloading_residual(p0))
        law_g = [float(r * law.factor(n, p0 / p_2, c, *shape)) for n in COMPARED]
        rows.append(SectionGapRow(label, c, x, run["p_y_MPa"], p_2, lv["static_dent_mm"], r,
                                  tuple(grooves[n - 1] for n in COMPARED), tuple(law_g),
                                  tuple(n * r for n in COMPARED), tuple(r for _ in COMPARED)))
    return rows


def table_law(table_rel: str, y_mm: float):
    """The table's rolling law and the patch shape at which it is read at ``y_mm``: (a/b, b/(2R)) (-) of the
    position's Hertz patch, which rolls the section (R: the table's lateral radius there)."""
    pos = table_position(table_rel, y_mm)
    table = LayerTable.read(ROOT / table_rel)
    return table.rolling_law, (pos.a_mm / pos.b_mm, 0.5 * pos.b_mm * table.lateral_curvature_at(y_mm))


def law_factors(row: SectionGapRow, passes) -> list[float]:
    """The table's rolling law G_n at the row's position, p0 / p_2, traction and patch shape, for ``passes`` (as
    :func:`rows_of` applies it)."""
    _, table_rel, y_mm, _ = next(p for p in POSITIONS if p[3] == row.position)
    law, shape = table_law(table_rel, y_mm)
    x = row.level * row.p_y_MPa / row.p_2_MPa
    return [float(g) for g in law.factor(list(passes), x, row.c, *shape)]


def collect(runs: pathlib.Path, run_missing: bool) -> list[SectionGapRow]:
    """Every case's rows; with ``run_missing`` the configurations without a result are run first."""
    rows = []
    for name, table_rel, y_mm, label in POSITIONS:
        for c in TRACTIONS:
            case = runs / case_name(name, c)
            result = case / "rolling.json"
            if not result.is_file() and run_missing:
                run_rolling(section_config(table_rel, y_mm, c), case)
            if result.is_file():
                rows += rows_of(json.loads(result.read_text()), table_rel, y_mm, label, c)
    return rows


def table_markdown(rows: list[SectionGapRow]) -> str:
    """The gap table: FEM groove / table residual, and layer / FEM with the rolling law and the static rules."""
    passes = ", ".join(str(n) for n in COMPARED)
    lines = [f"| position | c | p0 / p_y | section p_y / table p_2 | FEM static dent / table r | FEM groove, passes "
             f"{passes} (mm) | rolling law / FEM, passes {passes} | G_n / (FEM groove / FEM static dent) | relaxed / FEM, pass {COMPARED[-1]} | "
             f"state kept / FEM, passes 1, {COMPARED[-1]} |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        fem = ", ".join(f"{g:.5f}" for g in r.fem_mm)
        law = ", ".join(f"{v:.3f}" for v in r.law_over_fem())
        own = ", ".join(f"{v:.3f}" for v in r.ratio_over_fem_ratio())
        lines.append(f"| {r.position} | {r.c:g} | {r.level:g} | {r.p_y_MPa / r.p_2_MPa:.3f} | "
                     f"{r.static_dent_mm / r.table_residual_mm:.3f} | {fem} | {law} | {own} | "
                     f"{r.relaxed_mm[-1] / r.fem_mm[-1]:.2f} | {r.state_kept_mm[0] / r.fem_mm[0]:.3f}, "
                     f"{r.state_kept_mm[-1] / r.fem_mm[-1]:.3f} |")
    within = sum(all(abs(v - 1.0) <= TARGET for v in r.law_over_fem()) for r in rows)
    worst = max(rows, key=lambda r: max(abs(v - 1.0) for v in r.law_over_fem()), default=None)
    own_within = sum(all(abs(v - 1.0) <= TARGET for v in r.ratio_over_fem_ratio()) for r in rows)
    lines.append("")
    lines.append(f"The law's own ratio G_n within {TARGET:.0%} of the FEM's groove over its static dent: {own_within} "
                 f"of {len(rows)} cases (the rest of the gap is the static dent: section mesh against the table's FEM).")
    lines.append("")
    lines.append(f"Rolling law within {TARGET:.0%} of the section FEM after passes {passes}: {within} of {len(rows)} "
                 "cases" + (f"; worst {max(worst.law_over_fem(), key=lambda v: abs(v - 1)) - 1:+.1%} ({worst.position}, "
                            f"c = {worst.c:g}, {worst.level:g} p_y)." if worst else "."))
    return "\n".join(lines)


def corrected_markdown(rows: list[SectionGapRow], study: dict) -> str:
    """The sections' static dents under mesh refinement (:mod:`benchmarks.rolling_section_static`) and the rolling
    law against the gap's FEM groove corrected for its mesh (times the static dent's finest-mesh / a/2 factor)."""
    names = {label: name for name, _, _, label in POSITIONS}
    lines = ["The sections' static dents at the gap's peak pressures on finer meshes (`python -m "
             "benchmarks.rolling_section_static`), over the table's r at the same p0:", "", study_markdown(study), ""]
    corrected = []
    for r in rows:
        factor = mesh_factor(study, names[r.position], r.level)
        if factor is not None:
            corrected.append((r, r.law_over_fem(factor)))
    if corrected:
        lines += ["| position | c | p0 / p_y | static dent finest mesh / a/2 | rolling law / corrected FEM groove, "
                  f"passes {', '.join(str(n) for n in COMPARED)} |", "|---|---|---|---|---|"]
        lines += [f"| {r.position} | {r.c:g} | {r.level:g} | {mesh_factor(study, names[r.position], r.level):.3f} | "
                  + ", ".join(f"{v:.3f}" for v in ratios) + " |" for r, ratios in corrected]
        lines.append("")
        def count(limit, ratios_of):
            return sum(all(abs(v - 1.0) <= limit for v in ratios_of(r, ratios)) for r, ratios in corrected)

        worst_row, worst = max(corrected, key=lambda item: max(abs(v - 1.0) for v in item[1]))
        lines.append(f"Against the FEM groove corrected to the finest mesh's static dent (the groove over the static "
                     f"dent taken as mesh-converged), the rolling law is within {TARGET:.0%} after passes "
                     f"{', '.join(str(n) for n in COMPARED)} in {count(TARGET, lambda r, v: v)} of {len(corrected)} "
                     f"cases at these levels (within {2 * TARGET:.0%}: {count(2 * TARGET, lambda r, v: v)}; against "
                     f"the a/2 groove {count(TARGET, lambda r, v: r.law_over_fem())} and "
                     f"{count(2 * TARGET, lambda r, v: r.law_over_fem())}); worst "
                     f"{max(worst, key=lambda v: abs(v - 1)) - 1:+.1%} ({worst_row.position}, c = {worst_row.c:g}, "
                     f"{worst_row.level:g} p_y).")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=pathlib.Path, default=pathlib.Path("out/bench/rolling_section_gap"))
    ap.add_argument("--run", action="store_true", help="run the configurations without a result first")
    ap.add_argument("--static", type=pathlib.Path, default=None,
                    help="the sections' static dents on finer meshes (python -m benchmarks.rolling_section_static)")
    ap.add_argument("--refined", type=pathlib.Path, default=None,
                    help="each position's worst case rolled at h = a/4 (python -m benchmarks.rolling_section_refined;"
                         " needs --static)")
    ap.add_argument("--report", type=pathlib.Path, default=None,
                    help="also write the stamped report here (docs/validation/rolling-section-gap.md)")
    args = ap.parse_args(argv)
    args.runs.mkdir(parents=True, exist_ok=True)
    rows = collect(args.runs, args.run)
    text = table_markdown(rows)
    if args.static:
        study = read_study(args.static)
        text += "\n\n" + corrected_markdown(rows, study)
        refined = refined_markdown(rows, study, args.refined) if args.refined else ""
        if refined:
            text += (f"\n\nCases rolled again at h = a/{REFINED_ELEMENTS:g} at the same p0 (`python -m "
                     "benchmarks.rolling_section_refined`: each position's worst case against the corrected groove, "
                     "and the positions run whole):\n\n" + refined)
        long = long_markdown(rows, args.refined, law_factors) if args.refined else ""
        if long:
            text += (f"\n\nThe law (fitted on 5 passes) against runs of {LONG_PASSES} passes at h = a/"
                     f"{REFINED_ELEMENTS:g} (`rolling_section_refined --long`):\n\n" + long)
        checked = check_markdown(rows, args.refined) if args.refined else ""
        if checked:
            text += ("\n\nThe a/4 runs against h = a/6 (`rolling_section_refined --check`):\n\n" + checked)
        section = section_runs(rows, args.refined) if args.refined else []
        fitted = law_markdown(section) if section else ""
        if fitted:
            text += ("\n\nThe tables' rolling laws fitted to the a/4 runs (round: one node per position at its "
                     "convexity b/(2R); long patch: the field side; held out: positions not fitted; `python -m "
                     "benchmarks.rolling_section_law`; the column \"rolling law / a/4 groove\" above is the table's "
                     "law):\n\n" + fitted)
        spread = spread_markdown(section) if section else ""
        if spread:
            text += ("\n\nWhat each table's two round positions need (the G_n that puts the table's layer on each "
                     "a/4 groove, FEM groove over the table's r):\n\n" + spread)
    report = stamped_report("The rolling layer against the rolling FEM on the profile sections", text,
                            command_line("python -m benchmarks.bench_rolling_section_gap", argv))
    (args.runs / "section_gap.md").write_text(report)
    if args.report:
        args.report.write_text(report)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
