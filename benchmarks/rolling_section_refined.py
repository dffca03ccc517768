"""The rolling section gap's worst case of each position rolled again on a finer mesh (units mm, MPa, s).

The section gap (:mod:`benchmarks.bench_rolling_section_gap`) rolls at h = a/2 and corrects its FEM groove for the
mesh by the static dent's finest-mesh / a/2 factor (:func:`benchmarks.rolling_section_static.mesh_factor`): that
assumes the groove over the static dent to be converged at a/2. Here that assumption is tested where it decides
most: for each position, the case (traction, level) in which the rolling law is farthest from the corrected FEM
groove is rolled again at h = a/4 (:data:`REFINED_ELEMENTS`), same track, steps and passes, at the a/2 run's
peak pressure p0 in MPa (so both meshes and the layer meet at the same p0). The report gives, per case, the
groove over the static dent at both meshes (which side moved) and the law against the a/4 groove.

``python -m benchmarks.rolling_section_refined RUNS STATIC OUT [--workers 2] [--whole crown] [--check CASE ...]
[--long CASE ...]`` (``--whole``: also every level and traction of these positions; ``--check``: these cases also
at h = a/6, whether the a/4 ratio is converged; ``--long``: these cases at a/4 with 10 passes): RUNS and STATIC
are the gap's folders (``benchmarks/data/rolling_section_gap``, ``benchmarks/data/rolling_section_static``); one
run folder per case in OUT (``<position>_c<c>_p<level>_h4``, ``..._h6``, ``..._h4_n10``), a complete one is read,
not run again. The gap's report reads OUT with ``--refined OUT`` (:func:`refined_markdown`). About 6-8 minutes
of one core per case on an idle machine.
"""

from __future__ import annotations

import argparse
import json
from dataclasses import dataclass, replace
from pathlib import Path

from benchmarks.rolling_section_cases import COMPARED, N_PASSES, POSITIONS, TARGET, case_name, section_config
from benchmarks.rolling_section_static import mesh_factor
from calibration.rolling.config import RollingConfig
from calibration.rolling.run import run_rolling
from wrlayer.runner import Runner

#: Elements per contact semi-axis of the refined runs (h = a / 4; the gap's runs: a / 2).
REFINED_ELEMENTS = 4.0
#: Elements per semi-axis of the convergence check of the refined runs (``--check``: h = a / 6).
CHECK_ELEMENTS = 6.0
#: Passes of the long refined runs (``--long``): the rolling law fitted on 5 passes, checked at pass 10.
LONG_PASSES = 10


@dataclass(frozen=True)
class RefinedCase:
    """One gap case to roll on the finer mesh: the position's name, table, y (mm) and label, the traction c (-),
    the level p0 / p_y of the gap's a/2 run (-), that run's peak pressure p0 (MPa) and the elements per semi-axis
    of the refined mesh (-) and the passes rolled."""

    name: str
    table: str
    y_mm: float
    label: str
    c: float
    level: float
    p0_MPa: float
    elements: float = REFINED_ELEMENTS
    passes: int = N_PASSES

    @property
    def key(self) -> str:
        more = f"_n{self.passes}" if self.passes != N_PASSES else ""
        return f"{case_name(self.name, self.c)}_p{self.level:g}_h{self.elements:g}{more}"

    def config(self) -> RollingConfig:
        """The gap's configuration of the case at h = a / ``elements``, one level given in MPa."""
        cfg = section_config(self.table, self.y_mm, self.c)
        return replace(cfg, contact=replace(cfg.contact, levels=(self.p0_MPa,), level_unit="MPa"),
                       mesh=replace(cfg.mesh, elements_per_semi_axis=self.elements),
                       track=replace(cfg.track, n_passes=self.passes),
                       source=f"{cfg.source}, {self.level:g} p_y at h = a/{self.elements:g}")


def worst_cases(rows, study) -> list[RefinedCase]:
    """Per position, the gap row (:class:`benchmarks.bench_rolling_section_gap.SectionGapRow`) whose rolling law is
    farthest from the mesh-corrected FEM groove over the compared passes."""
    cases = []
    for name, table, y_mm, label in POSITIONS:
        scored = []
        for r in rows:
            factor = mesh_factor(study, name, r.level) if r.position == label else None
            if factor is not None:
                scored.append((max(abs(v - 1.0) for v in r.law_over_fem(factor)), r))
        if scored:
            cases.append(_case(name, max(scored, key=lambda item: item[0])[1]))
    return cases


def cases_of(rows, name: str) -> list[RefinedCase]:
    """Every gap row of the position ``name`` (all levels and tractions), as refined cases."""
    label = next(p[3] for p in POSITIONS if p[0] == name)
    return [_case(name, r) for r in rows if r.position == label]


def every_case(rows) -> list[tuple[RefinedCase, object]]:
    """Every gap row of every position as (its refined case, the row), in the order of :data:`POSITIONS`."""
    return [(_case(name, r), r) for name, *_, label in POSITIONS for r in rows if r.position == label]


def _case(name: str, row) -> RefinedCase:
    """The gap row ``row`` of the position ``name`` at its a/2 run's peak pressure."""
    _, table, y_mm, label = next(p for p in POSITIONS if p[0] == name)
    return RefinedCase(name, table, y_mm, label, row.c, row.level, row.level * row.p_y_MPa)


def run_refined(task: tuple[RefinedCase, Path]) -> str:
    """Worker: roll one case into its folder under the output (kept when complete); returns its key."""
    case, out = task
    folder = out / case.key
    if complete_run(folder, case.passes) is None:
        run_rolling(case.config(), folder, force=True)
    return case.key


def complete_run(folder: Path, passes: int = N_PASSES) -> dict | None:
    """The rolling.json of a run folder with ``passes`` passes done, or None."""
    path = folder / "rolling.json"
    if not path.is_file():
        return None
    run = json.loads(path.read_text())
    levels = run["levels"]
    return run if levels and len(levels[0]["groove_mm"]) >= passes else None


def refined_markdown(rows, study, out: Path) -> str:
    """Per gap case with a complete refined run in ``out`` (each position's worst case, and every case of the
    positions run whole): the groove over the static dent at a/2 and a/4 (passes :data:`COMPARED`), the a/4 static
    dent over the a/2 one, and the rolling law over the a/4 groove."""
    passes = ", ".join(str(n) for n in COMPARED)
    lines = [f"| position | c | p0 / p_y | p0 (MPa) | groove / static dent at a/2, passes {passes} | the same at "
             f"a/{REFINED_ELEMENTS:g} | static dent a/{REFINED_ELEMENTS:g} / a/2 | rolling law / a/"
             f"{REFINED_ELEMENTS:g} groove, passes {passes} | law / corrected a/2 groove | dofs | wall time (s) |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    within = n = 0
    moves: list[float] = []
    for case, r in every_case(rows):
        run = complete_run(out / case.key)
        if run is None:
            continue
        lv = run["levels"][0]
        fine = [lv["groove_mm"][k - 1] for k in COMPARED]
        law = [lw / g for lw, g in zip(r.law_mm, fine)]
        factor = mesh_factor(study, case.name, case.level)
        moves += [(g / lv["static_dent_mm"]) / (f / r.static_dent_mm) - 1.0 for g, f in zip(fine, r.fem_mm)]
        n += 1
        within += all(abs(v - 1.0) <= TARGET for v in law)
        lines.append(f"| {case.label} | {case.c:g} | {case.level:g} | {lv['p0_MPa']:.0f} | "
                     + ", ".join(f"{f / r.static_dent_mm:.3f}" for f in r.fem_mm) + " | "
                     + ", ".join(f"{g / lv['static_dent_mm']:.3f}" for g in fine) + " | "
                     f"{lv['static_dent_mm'] / r.static_dent_mm:.3f} | " + ", ".join(f"{v:.3f}" for v in law) + " | "
                     + (", ".join(f"{v:.3f}" for v in r.law_over_fem(factor)) if factor is not None else "—")
                     + " | "
                     f"{run['n_dofs']} | {run['seconds']:.0f} |")
    if n == 0:
        return ""
    lines += ["", f"Against the a/{REFINED_ELEMENTS:g} rolling FEM at the same p0 the rolling law is within "
              f"{TARGET:.0%} after passes {passes} in {within} of these {n} cases. The groove over the static dent "
              f"moved by {min(moves):+.1%} to {max(moves):+.1%} from a/2 to a/{REFINED_ELEMENTS:g} (the a/2 "
              "correction takes it as unchanged)."]
    return "\n".join(lines)


def check_markdown(rows, out: Path) -> str:
    """Per case with a complete run at h = a / :data:`CHECK_ELEMENTS` in ``out`` (``--check``): the groove over the
    static dent at a/2, a/4 and a/6 (passes :data:`COMPARED`), the a/6 static dent over the a/4 one and the rolling
    law over the a/6 groove: is the a/4 ratio converged?"""
    passes = ", ".join(str(n) for n in COMPARED)
    h4, h6 = f"a/{REFINED_ELEMENTS:g}", f"a/{CHECK_ELEMENTS:g}"
    lines = [f"| position | c | p0 / p_y | groove / static dent at a/2, {h4}, {h6} (passes {passes}) | static dent "
             f"{h6} / {h4} | rolling law / {h6} groove | dofs | wall time (s) |", "|---|---|---|---|---|---|---|---|"]
    for case, r in every_case(rows):
        fine, finest = complete_run(out / case.key), complete_run(out / replace(case, elements=CHECK_ELEMENTS).key)
        if fine is None or finest is None:
            continue
        ratios = [[f / r.static_dent_mm for f in r.fem_mm]]
        ratios += [[lv["groove_mm"][k - 1] / lv["static_dent_mm"] for k in COMPARED]
                   for lv in (fine["levels"][0], finest["levels"][0])]
        law = [lw / finest["levels"][0]["groove_mm"][k - 1] for lw, k in zip(r.law_mm, COMPARED)]
        lines.append(f"| {case.label} | {case.c:g} | {case.level:g} | "
                     + "; ".join(", ".join(f"{v:.3f}" for v in series) for series in ratios) + " | "
                     f"{finest['levels'][0]['static_dent_mm'] / fine['levels'][0]['static_dent_mm']:.3f} | "
                     + ", ".join(f"{v:.3f}" for v in law) + f" | {finest['n_dofs']} | {finest['seconds']:.0f} |")
    return "\n".join(lines) if len(lines) > 2 else ""


def long_markdown(rows, out: Path, law_of) -> str:
    """Per case with a complete :data:`LONG_PASSES`-pass run at h = a/4 in ``out`` (``--long``): its groove over
    its static dent after passes 1, 2, 5 and 10 and the table's law G_n there over it (``law_of(row, passes)``:
    the law's G_n at the row's p0 / p_2, traction and patch shape)."""
    n = (1, 2, 5, LONG_PASSES)
    lines = [f"| position | c | p0 / p_y | groove / static dent at a/{REFINED_ELEMENTS:g}, passes "
             f"{', '.join(map(str, n))} | the table's G_n / FEM | wall time (s) |", "|---|---|---|---|---|---|"]
    for case, r in every_case(rows):
        run = complete_run(out / replace(case, passes=LONG_PASSES).key, LONG_PASSES)
        if run is None:
            continue
        lv = run["levels"][0]
        fem = [lv["groove_mm"][k - 1] / lv["static_dent_mm"] for k in n]
        law = law_of(r, n)
        lines.append(f"| {case.label} | {case.c:g} | {case.level:g} | " + ", ".join(f"{v:.3f}" for v in fem) + " | "
                     + ", ".join(f"{g / f:.3f}" for g, f in zip(law, fem)) + f" | {run['seconds']:.0f} |")
    return "\n".join(lines) if len(lines) > 2 else ""


def main(argv: list[str] | None = None) -> None:
    from benchmarks.bench_rolling_section_gap import collect  # the gap's rows (that module reads this one)
    from benchmarks.rolling_section_static import read_study

    ap = argparse.ArgumentParser(prog="python -m benchmarks.rolling_section_refined",
                                 description=__doc__.splitlines()[0])
    ap.add_argument("runs", type=Path, help="the section gap's runs (benchmarks/data/rolling_section_gap)")
    ap.add_argument("static", type=Path, help="the static study (benchmarks/data/rolling_section_static)")
    ap.add_argument("out", type=Path, help="where the refined runs go")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--whole", nargs="*", default=[], choices=[p[0] for p in POSITIONS],
                    help="also every level and traction of these positions")
    ap.add_argument("--check", nargs="*", default=[], metavar="CASE",
                    help=f"also these cases (e.g. crown_c0.2_p1.15) at h = a/{CHECK_ELEMENTS:g}")
    ap.add_argument("--long", nargs="*", default=[], metavar="CASE",
                    help=f"also these cases at h = a/{REFINED_ELEMENTS:g} with {LONG_PASSES} passes")
    args = ap.parse_args(argv)
    rows, study = collect(args.runs, False), read_study(args.static)
    cases = worst_cases(rows, study)
    cases += [c for name in args.whole for c in cases_of(rows, name) if c.key not in {k.key for k in cases}]
    every = {f"{case_name(c.name, c.c)}_p{c.level:g}": c for c, _ in every_case(rows)}
    unknown = [k for k in args.check + args.long if k not in every]
    if unknown:
        ap.error(f"--check, --long: no gap case {', '.join(unknown)} (cases look like crown_c0.2_p1.15)")
    cases += [replace(every[k], elements=CHECK_ELEMENTS) for k in args.check]
    cases += [replace(every[k], passes=LONG_PASSES) for k in args.long]
    args.out.mkdir(parents=True, exist_ok=True)
    for case in cases:
        print(f"{case.key}: {case.label}, c = {case.c:g}, {case.level:g} p_y, p0 = {case.p0_MPa:.1f} MPa", flush=True)
    with Runner(args.workers) as runner:
        for _, key in runner.imap(run_refined, [(c, args.out) for c in cases]):
            print(f"done: {key}", flush=True)
    print(refined_markdown(rows, study, args.out))
    print(check_markdown(rows, args.out))


if __name__ == "__main__":
    main()
