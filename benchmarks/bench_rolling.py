"""Rolling (moving-load) FEM: time per pass and convergence of the first-pass groove (step length, track length,
mesh), and the groove / static-dent ratios and pass increments compared with the rolling reference.

Reference behaviour (volume-integral method, circular Hertz pressure moved across a periodic EPP half-space,
E 210 GPa, nu 0.3, Y 500 MPa, frictionless): first-pass groove 0.8-0.9 of the static dent at p0 = 1.3, 1.7,
2.1 p_y; the second pass adds 0-3 % of the first at 1.3 and 1.7 p_y (shakedown), about 12 % at 2.1 p_y
(ratcheting). Quick mode: the coarse mesh, two passes and the study at one level (a few minutes on 2 busy cores);
full mode: the shipped ``calibration/configs/rolling_halfspace.toml`` and the study around it. One BLAS thread.
``python -m benchmarks.bench_rolling [--quick|--full] --out DIR`` runs it alone; ``--gap`` (with ``--cases DIR``,
default ``DIR/rolling/gap``: one JSON per case, completed cases are read, not recomputed) the gap between the
layer's memory rules and the rolling FEM at the half-space and the calibration positions, the rolling laws, and
with ``--write-tables`` the very long patch's law into the shipped default tables (their round and long-patch
nodes: :mod:`benchmarks.rolling_section_law`).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import os
import pathlib
import sys
import time

from benchmarks import rolling_gap as gap, rolling_gap_cases as gap_cases, rolling_gap_static as gap_static
from benchmarks.harness import command_line, stamped_report
from calibration.rolling.config import RollingConfig, load_rolling_config
from calibration.rolling.run import RollingResult, run_rolling

ROOT = pathlib.Path(__file__).resolve().parents[1]
SHIPPED = ROOT / "calibration" / "configs" / "rolling_halfspace.toml"
#: Reference (first-pass groove / static dent range, second-pass increment in % of the first) per p0 / p_y.
REFERENCE = {1.3: ((0.8, 0.9), "0-3 %"), 1.7: ((0.8, 0.9), "0-3 %"), 2.1: ((0.8, 0.9), "about 12 %")}
#: The study's level (p0 / p_y).
STUDY_LEVEL = 1.7


def _replace(cfg: RollingConfig, **tables) -> RollingConfig:
    """``cfg`` with fields of its tables replaced: _replace(cfg, track=dict(n_passes=1))."""
    kw = {name: dataclasses.replace(getattr(cfg, name), **vals) for name, vals in tables.items()}
    return dataclasses.replace(cfg, **kw)


def base_config(quick: bool) -> RollingConfig:
    """The shipped configuration (full) or its coarse version (quick: 2 elements per a, short track, 2 passes)."""
    cfg = _replace(load_rolling_config(SHIPPED), run=dict(plots=False))
    if quick:
        cfg = _replace(cfg, mesh=dict(elements_per_semi_axis=2.0, size_factor=4.0),
                       track=dict(length_factor=1.5, step_factor=0.5, n_passes=2))
    return cfg


def study(cfg: RollingConfig, out: pathlib.Path) -> list[dict]:
    """First-pass groove at STUDY_LEVEL: the base, half the step, a longer track, a finer mesh."""
    one = _replace(cfg, contact=dict(levels=(STUDY_LEVEL,)), track=dict(n_passes=1))
    t, m = one.track, one.mesh
    variants = {"base": one, "step / 2": _replace(one, track=dict(step_factor=t.step_factor / 2)),
                "track + 1 contact length": _replace(one, track=dict(length_factor=t.length_factor + 1.0)),
                "mesh h x 2/3": _replace(one, mesh=dict(elements_per_semi_axis=1.5 * m.elements_per_semi_axis))}
    rows = []
    for name, c in variants.items():
        t0 = time.perf_counter()
        res = run_rolling(c, out / "study" / name.replace(" ", "_").replace("/", "_"), force=True)
        lv = res.levels[0]
        rows.append({"variant": name, "n_dofs": res.n_dofs, "groove_mm": lv.groove_mm[0],
                     "static_dent_mm": lv.static_dent_mm, "ratio": lv.groove_mm[0] / lv.static_dent_mm,
                     "pass_s": lv.pass_seconds[0], "wall_s": time.perf_counter() - t0})
    return rows


def _pct(a: float, b: float) -> float:
    return 100.0 * (a / b - 1.0)


def _markdown(res: RollingResult, rows: list[dict], load: tuple, cfg: RollingConfig, wall: float) -> list[str]:
    t, m = cfg.track, cfg.mesh
    md = [__doc__.split("\n\n", 1)[1].split("Quick mode")[0].strip(), "",
          f"Run: {res.n_dofs} dofs ({res.n_elements} quadratic tetrahedra), h = a / {m.elements_per_semi_axis:g}, "
          f"track {t.length_factor:g} contact lengths, step {t.step_factor:g} a, {t.n_passes} passes; "
          f"p_y = {res.p_y_MPa:.1f} MPa (FEM, analytic 1.61 Y = 805 MPa); machine load average "
          f"{load[0]:.2f} / {load[1]:.2f} / {load[2]:.2f} (1 / 5 / 15 min) at the start; wall {wall:.0f} s.", "",
          "| p0 / p_y | static dent (mm) | groove pass 1..n (mm) | groove / static | pass 2 adds | "
          "later passes add | reference groove / static, pass 2 | s per pass | layer relaxed / state kept / rolling "
          "after the last pass (mm) |", "|---|---|---|---|---|---|---|---|---|"]
    for lv in res.levels:
        g = lv.groove_mm
        add2 = f"{_pct(g[1], g[0]):+.1f} %" if len(g) > 1 else "-"
        later = ", ".join(f"{_pct(g[k], g[k - 1]):+.2f} %" for k in range(2, len(g))) or "-"
        ref = REFERENCE.get(round(lv.p0_over_py, 2))
        ref_txt = f"{ref[0][0]}-{ref[0][1]}, {ref[1]}" if ref else "-"
        lg = lv.layer_groove_mm
        layer = (f"{lg.relaxed[-1]:.4g} / {lg.state_kept[-1]:.4g} / "
                 f"{lg.rolling[-1] if lg.rolling else float('nan'):.4g}") if lg.relaxed else "-"
        md.append(f"| {lv.p0_over_py:.2f} | {lv.static_dent_mm:.4g} | {', '.join(f'{x:.4g}' for x in g)} | "
                  f"{g[0] / lv.static_dent_mm:.3f} | {add2} | {later} | {ref_txt} | "
                  f"{sum(lv.pass_seconds) / len(lv.pass_seconds):.0f} | {layer} |")
    base = rows[0]
    md += ["", f"First-pass groove at p0 = {STUDY_LEVEL} p_y, one change at a time (deviation from the base):", "",
           "| variant | dofs | groove (mm) | deviation | static dent (mm) | groove / static | s per pass |",
           "|---|---|---|---|---|---|---|"]
    for r in rows:
        md.append(f"| {r['variant']} | {r['n_dofs']} | {r['groove_mm']:.4g} | {_pct(r['groove_mm'], base['groove_mm']):+.2f} % "
                  f"| {r['static_dent_mm']:.4g} | {r['ratio']:.3f} | {r['pass_s']:.0f} |")
    return md


def run(mode: str, out: pathlib.Path) -> dict:
    """Benchmark entry point (``python -m benchmarks --only rolling``), one BLAS/MKL thread."""
    from threadpoolctl import threadpool_limits

    out = pathlib.Path(out) / "rolling"
    load = os.getloadavg()
    with threadpool_limits(limits=1):
        cfg = base_config(mode == "quick")
        t0 = time.perf_counter()
        res = run_rolling(cfg, out / "run", force=True)
        wall = time.perf_counter() - t0
        rows = study(cfg, out)
    md = _markdown(res, rows, load, cfg, wall)
    data = {"result": res.to_dict(), "study": rows, "load_average": list(load), "wall_s": wall}
    return {"title": "Rolling: moving-load FEM, passes and convergence", "markdown": "\n".join(md),
            "figures": [], "data": data}


def _f(values, fmt=".4g") -> str:
    return ", ".join(f"{v:{fmt}}" for v in values)


def gap_markdown(rows: list[gap.GapRow], laws: dict, fits: dict) -> list[str]:
    """The gap table, the 10 % check and the laws (markdown lines)."""
    md = ["| position | c | p0 / p_y | static dent: block / layer (mm) | FEM groove after 1, 2, 5, 10 (mm) | "
          "relaxed / FEM after 1, 2, 5, 10 | state kept / FEM after 1, 2, 5, 10 | rolling law / FEM after 1, 2, 5, 10 "
          "| law on the block: worst |", "|---|---|---|---|---|---|---|---|---|"]
    for r in sorted(rows, key=lambda r: (r.group, r.position, r.traction, r.p0_over_py)):
        fem = _f(r.fem_mm) + ("" if r.fem_passes >= 10 else f" (FEM {r.fem_passes} passes, then its fit)")
        rel = {k: [x / y for x, y in zip(getattr(r, k), r.fem_mm)]
               for k in ("relaxed_mm", "state_kept_mm", "rolling_mm")}
        md.append(f"| {r.position}{' (stand-in)' if 'stand-in' in r.key else ''} | "
                  f"{r.traction:g} | {r.p0_over_py:g} | {r.static_dent_mm:.4g} / {r.layer_static_mm:.4g} | {fem} | "
                  f"{_f(rel['relaxed_mm'], '.2f')} | {_f(rel['state_kept_mm'], '.3f')} | "
                  f"{_f(rel['rolling_mm'], '.3f')} "
                  f"| {100 * r.error('law_on_block_mm'):.2f} % |")
    md += ["", "Worst |layer / FEM - 1| over passes 1, 2, 5, 10 and all cases (target 10 %):", "",
           "| rule | worst | case |", "|---|---|---|"]
    for name, label in (("relaxed_mm", "relaxed (paper)"), ("state_kept_mm", "state kept"),
                        ("rolling_mm", "rolling law on the layer's static residual"),
                        ("law_on_block_mm", "rolling law on the block's static dent")):
        worst = max(rows, key=lambda r: r.error(name), default=None)
        if worst is None:
            continue
        md.append(f"| {label} | {100 * worst.error(name):.1f} % | {worst.key} |")
    md += ["", "Rolling laws (G_n = rho (1 + A (1 - q^(n-1)) / (1 - q) + B (n - 1)); fit error: largest over the "
           "group's mean groove series):", "", "| group | c | p0 / p_2 | rho | A | q | B | fit error |",
           "|---|---|---|---|---|---|---|---|"]
    for g, per in fits.items():
        for (c, lv), f in sorted(per.items()):
            md.append(f"| {g} | {c:g} | {lv:g} | {f.first_pass_ratio:.4f} | {f.shakedown_increment:.4f} | "
                      f"{f.shakedown_decay:.2f} | {f.ratchet_increment:.5f} | {100 * f.max_relative_error:.2f} % |")
    return md


def gap_summary(rows: list[gap.GapRow]) -> list[str]:
    """The condensed gap table of docs/validation/rolling-gap.md (stand-ins left out: they repeat their position's
    ratios)."""
    md = ["| position | c | p0 / p_y | FEM groove / static dent, passes 1, 2, 5, 10 | relaxed / FEM, pass 10 | "
          "state kept / FEM, passes 1, 10 | rolling law / FEM, passes 1, 10 | law on the block: worst |",
          "|---|---|---|---|---|---|---|---|"]
    for r in sorted((r for r in rows if "stand-in" not in r.key),
                    key=lambda r: (r.group != "half-space", r.position, r.traction, r.p0_over_py)):
        g = [x / r.static_dent_mm for x in r.fem_mm]
        extra = "" if r.fem_passes >= 10 else f" (FEM {r.fem_passes}, then fit)"
        md.append(f"| {r.position} | {r.traction:g} | {r.p0_over_py:g} | {_f(g, '.3f')}{extra} | "
                  f"{r.relaxed_mm[-1] / r.fem_mm[-1]:.2f} | {r.state_kept_mm[0] / r.fem_mm[0]:.3f}, "
                  f"{r.state_kept_mm[-1] / r.fem_mm[-1]:.3f} | {r.rolling_mm[0] / r.fem_mm[0]:.3f}, "
                  f"{r.rolling_mm[-1] / r.fem_mm[-1]:.3f} | {100 * r.error('law_on_block_mm'):.2f} % |")
    return md


def gap_plot(rows: list[gap.GapRow], results: list, laws: dict, path: pathlib.Path) -> pathlib.Path | None:
    """FEM groove / static dent against the pass (markers) and the rolling law (lines), per position and c."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:  # pictures are optional in the report
        return None
    positions = sorted({r.position for r in rows})
    fig, axes = plt.subplots(len(gap_cases.TRACTIONS), len(positions), figsize=(3.0 * len(positions), 5.2),
                             sharey=True, squeeze=False)
    n = list(range(1, 11))
    for i, c in enumerate(gap_cases.TRACTIONS):
        for j, pos in enumerate(positions):
            ax = axes[i][j]
            for k, lv in enumerate(gap_cases.LEVELS):
                case = next((r for r in results if r.position == pos and r.traction == c and r.p0_over_py == lv), None)
                if case is None or not case.groove_mm:
                    continue
                col = f"C{k}"
                g = [x / case.static_dent_mm for x in case.groove_mm]
                ax.plot(range(1, len(g) + 1), g, "o", color=col, ms=3, label=f"FEM {lv:g} p_y")
                ax.plot(n, laws[gap.group_of(pos)].factor(n, lv, c), "-", color=col, lw=1)
            ax.axhline(1.0, color="k", ls=":", lw=0.8)
            ax.set_title(f"{pos}, c = {c:g}", fontsize=8)
            ax.set_xlabel("pass")
            if j == 0:
                ax.set_ylabel("groove / static dent")
    axes[0][0].legend(fontsize=6)
    fig.suptitle("rolling FEM (markers), rolling law (lines); state kept = 1 (dotted), relaxed = n", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path


def _ext(ext, scale: float = 1.0) -> str:
    order = f", p = {ext.order:.2f}" if math.isfinite(ext.order) else ""
    return f"{ext.value / scale:.3f} ({ext.method}{order})"


def static_study_markdown(points: list, conv: dict, statics: dict) -> list[str]:
    """The static dents of the gap positions under mesh refinement over the layer's static residual r, and at a
    common peak pressure the mesh limit over the finest mesh."""
    meshes = sorted({p.elements_per_semi_axis for p in points})
    common = gap_static.common_pressure_dents(points)
    md = ["| position | p0 / p_y | p_y (MPa) on " + ", ".join(f"a/{n:g}" for n in meshes) + " | static dent / r on "
          + ", ".join(f"a/{n:g}" for n in meshes) + " | mesh limit / r | r (mm) | common p0: limit / finest |",
          "|---|---|---|---|---|---|---|"]
    for (pos, lv), ext in sorted(conv.items()):
        r = statics.get((pos, lv))
        if r is None:
            continue
        mine = sorted((p for p in points if p.position == pos), key=lambda p: p.elements_per_semi_axis)
        md.append(f"| {pos} | {lv:g} | {_f([p.p_y_MPa for p in mine], '.1f')} | "
                  f"{_f([p.dent_at(lv) / r for p in mine], '.3f')} | {_ext(ext, r)} | {r:.4g} | "
                  f"{_ext(common[(pos, lv)])} |")
    return md


def ratio_check_markdown(checks: list, rows: list[gap.GapRow]) -> list[str]:
    """The groove / static dent ratio on the gap's mesh and on the finer one, and the law on the layer against
    the finer mesh's groove at the reported passes."""
    md = ["| case | dofs (gap, fine) | pass | groove / static dent, gap mesh | fine mesh | change | "
          "law on the layer / fine FEM |", "|---|---|---|---|---|---|---|"]
    by_key = {r.key: r for r in rows}
    for ch in checks:
        row = by_key.get(ch.key)
        law = dict(zip(row.passes, row.rolling_mm)) if row is not None else {}
        for k, c, f, d, g in zip(ch.passes, ch.coarse_ratio, ch.fine_ratio, ch.change(), ch.fine_groove_mm):
            vs = f"{law[k] / g:.3f}" if k in law else "-"
            md.append(f"| {ch.key} | {ch.coarse_dofs}, {ch.fine_dofs} | {k} | {c:.4f} | {f:.4f} | {100 * d:+.2f} % | "
                      f"{vs} |")
    return md


def corrected_markdown(rows: list[gap.GapRow], corrected: list[gap.GapRow]) -> list[str]:
    """The rolling law on the layer against the coarse and the mesh-corrected FEM, and the count within target."""
    md = ["| position | c | p0 / p_y | static dent / r: a/2, mesh limit | law / FEM (a/2), passes 1, 2, 5, 10 | "
          "law / FEM (mesh-corrected), passes 1, 2, 5, 10 |", "|---|---|---|---|---|---|"]
    fine = {r.key: r for r in corrected}
    for r in sorted(rows, key=lambda r: (r.group != "half-space", r.position, r.traction, r.p0_over_py)):
        c = fine.get(r.key)
        if c is None:
            continue
        md.append(f"| {r.position} | {r.traction:g} | {r.p0_over_py:g} | {r.static_dent_mm / r.layer_static_mm:.3f}, "
                  f"{c.static_dent_mm / c.layer_static_mm:.3f} | "
                  f"{_f([x / y for x, y in zip(r.rolling_mm, r.fem_mm)], '.3f')} | "
                  f"{_f([x / y for x, y in zip(c.rolling_mm, c.fem_mm)], '.3f')} |")
    n_a = len(gap_static.within_target([r for r in rows if r.key in fine]))
    md += ["", f"Within {100 * gap.TARGET:g} % at passes 1, 2, 5, 10: {n_a} of {len(fine)} against the a/2 FEM, "
               f"{len(gap_static.within_target(corrected))} of {len(corrected)} against the mesh-corrected FEM."]
    return md


def run_gap(out: pathlib.Path, cases_dir: pathlib.Path, write_tables: bool = False, compute: bool = True) -> dict:
    """The gap: every default case (computed where its file is missing or incomplete, unless ``compute`` is
    False), the report and (optionally) the laws written into the shipped default tables."""
    from threadpoolctl import threadpool_limits

    load = os.getloadavg()
    with threadpool_limits(limits=1):
        for case in gap_cases.default_cases() if compute else []:
            if case.position.name not in gap.STAND_INS:  # the wheel's positions: their stand-ins unless computed
                gap_cases.run_case(case, cases_dir)
    results = gap.with_stand_ins(gap.load_results(cases_dir))
    static_dir = cases_dir.parent / (cases_dir.name + "_static")
    points = gap_static.load_points(static_dir) if static_dir.exists() else []
    hs = max((p for p in points if p.position == gap_cases.HALF_SPACE.name), default=None,
             key=lambda p: p.elements_per_semi_axis)
    halfspace = hs.reference() if hs is not None else None
    rows, laws = gap.gap_rows(results, halfspace)
    fits = {g: gap.fit_group(results, g)[1] for g in laws}
    statics = gap.layer_static_residuals(results, halfspace)
    conv = gap_static.converged_dents(points)
    mesh_dir = cases_dir.parent / (cases_dir.name + "_mesh")
    checks = gap_static.ratio_checks(results, gap.load_results(mesh_dir) if mesh_dir.exists() else [])
    md = gap_markdown(rows, laws, fits)
    md += ["", "Condensed (docs/validation/rolling-gap.md):", ""] + gap_summary(rows)
    if halfspace is not None:
        own = [r for r in results if gap.group_of(r.position) == "half-space"]  # the other groups' fits unchanged
        md += ["", gap.own_block_line(gap.gap_rows(own, None)[0])]
    if points:  # the mesh studies only where their runs are present (a report of the law's cases alone omits them)
        md += ["", f"Static dents under mesh refinement ({static_dir.name}; the half-space's r: the default fit to "
                   "the finest mesh):", ""] + static_study_markdown(points, conv, statics)
        md += ["", "Mesh-corrected FEM groove = (a/2 groove / a/2 static dent) x mesh-limit static dent:", ""]
        md += corrected_markdown(rows, gap_static.corrected_rows(rows, conv))
    if checks:
        md += ["", f"Groove / static dent on a finer mesh ({mesh_dir.name}):", ""] + ratio_check_markdown(checks, rows)
    shape_dir = cases_dir.parent / (cases_dir.name + "_shape")
    if shape_dir.exists() and all(g in laws for g in gap.LONG_PATCHES):
        md += ["", f"The laws' patch-shape nodes against blocks at other shapes ({shape_dir.name}):", ""]
        md += gap.shape_check_markdown(gap.load_results(shape_dir), laws)
    fig = gap_plot(rows, results, laws, out / "rolling_gap.png")
    if write_tables:
        gap.write_block_nodes(laws)
    data = {"rows": [r.to_dict() for r in rows], "laws": {g: lw.to_dict() for g, lw in laws.items()},
            "corrected_rows": [r.to_dict() for r in gap_static.corrected_rows(rows, conv)],
            "static_study": [p.to_dict() for p in points],
            "ratio_checks": [dataclasses.asdict(c) for c in checks], "load_average": list(load)}
    return {"title": "Rolling: the gap between the layer's passes and the rolling FEM", "markdown": "\n".join(md),
            "figures": [str(fig)] if fig else [], "data": data}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.bench_rolling", description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_const", dest="mode", const="quick", default="full")
    ap.add_argument("--full", action="store_const", dest="mode", const="full")
    ap.add_argument("--out", type=pathlib.Path, default=pathlib.Path("out/bench"))
    ap.add_argument("--gap", action="store_true", help="the gap report (cases cached per file)")
    ap.add_argument("--cases", type=pathlib.Path, default=None,
                    help="folder of the gap cases (default OUT/rolling/gap)")
    ap.add_argument("--write-tables", action="store_true", help="write the rolling laws into the shipped tables")
    ap.add_argument("--report-only", action="store_true", help="report the cases present, compute none")
    ap.add_argument("--report", type=pathlib.Path, default=None,
                    help="also write the stamped report here (docs/validation/rolling.md; with --gap rolling-gap.md)")
    args = ap.parse_args(argv)
    command = command_line("python -m benchmarks.bench_rolling", argv)
    if args.gap:
        (args.out / "rolling").mkdir(parents=True, exist_ok=True)
        res = run_gap(args.out / "rolling", args.cases or args.out / "rolling" / "gap", args.write_tables,
                      not args.report_only)
        report = stamped_report(res["title"], res["markdown"], command)
        (args.out / "rolling" / "gap_report.md").write_text(report)
        if args.report:
            args.report.write_text(report)
        (args.out / "rolling" / "gap_report.json").write_text(json.dumps(res["data"], indent=1, default=float))
        print(res["markdown"])
        return 0
    res = run(args.mode, args.out)
    (args.out / "rolling").mkdir(parents=True, exist_ok=True)
    report = stamped_report(res["title"], res["markdown"], command)
    (args.out / "rolling" / "report.md").write_text(report)
    if args.report:
        args.report.write_text(report)
    (args.out / "rolling" / "report.json").write_text(json.dumps(res["data"], indent=1, default=float))
    print(res["markdown"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
