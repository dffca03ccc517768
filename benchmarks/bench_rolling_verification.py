"""Rolling FEM verification: step-length convergence of the first-pass groove with plain steps and with material
sub-steps along the load's path (:mod:`calibration.rolling.substeps`), the 2D frictionless EPP line contact at
p0/k = 3.5, 4.35 and 5.0 against Bhargava, Hahn & Wert (1985) (shakedown below Johnson's limit 4 k, continued
plastic strain above), and the 3D half-space levels of the shipped configuration with sub-steps.

Quick mode: 2D only (a small block, a few minutes on 2 busy cores). Full mode: the 3D study on the shipped mesh
(h = a/3, track 2 contact lengths, 45,951 dofs) at p0 = 1.7 p_y, the 2D study at 4.35 k, the 2D line contact on a
40 a block, the shipped levels with sub-steps (a/4; a/8 at 1.7 and 2.1 p_y): about two hours of CPU. Every case
is cached in ``OUT/rolling_verification/cases/<case>.json`` (delete to rerun). One BLAS thread. Full mode also
runs the Tamaas rolling reference (``benchmarks/tamaas_rolling.py``: coarse grid, the three EPP levels and 2.1 p_y
with isotropic hardening, about 15 minutes) when Tamaas is importable, cached in
``OUT/rolling_verification/tamaas/``; ``--tamaas`` runs only that part.
``python benchmarks/bench_rolling_verification.py [--quick|--full|--tamaas] --out DIR`` runs it alone.
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import sys

from benchmarks import tamaas_rolling
from benchmarks.harness import command_line, stamped_report
from benchmarks.rolling_verification_cases import Case, VerificationResult, CaseRunner
from benchmarks.tamaas_reference import tamaas_version

#: The step study's level (p0 / p_y, 3D) and the 2D one (p0 / k).
STUDY_LEVEL_3D, STUDY_LEVEL_2D = 1.7, 4.35
#: (step / a, material sub-steps) of the step studies: plain steps and sub-stepped ones.
STEPS = {"quick": [(0.5, 1), (0.25, 1), (0.125, 1), (0.0625, 1), (0.5, 4), (0.25, 4), (0.125, 4)],
         "full_2d": [(0.5, 1), (0.25, 1), (0.125, 1), (0.0625, 1), (0.03125, 1), (0.015625, 1),
                     (0.5, 4), (0.25, 4), (0.125, 4), (0.0625, 4)],
         "full_3d": [(0.25, 1), (0.125, 1), (0.0625, 1), (0.03125, 1), (0.5, 4), (0.25, 4), (0.125, 4), (0.0625, 4),
                     (0.25, 2)]}
#: The recommended step of the shipped configuration (step / a, sub-steps).
RECOMMENDED = (0.125, 4)
#: 2D line contact levels (p0 / k) and passes.
BHW_LEVELS = {3.5: 6, 4.35: 20, 5.0: 12}


def study_cases(mode: str) -> list[Case]:
    if mode == "quick":
        return [Case(f"q2d_s{round(1 / s)}_m{m}", "2d", STUDY_LEVEL_2D, unit="k", n=3.0, size=8.0, length=1.5,
                     step=s, substeps=m) for s, m in STEPS["quick"]]
    out = [Case(f"3d_L{STUDY_LEVEL_3D}_s{round(1 / s)}_m{m}", "3d", STUDY_LEVEL_3D, step=s, substeps=m,
                static=(s, m) == (0.25, 1)) for s, m in STEPS["full_3d"]]
    out.append(Case(f"3d_L{STUDY_LEVEL_3D}_s4_m1_r16", "3d", STUDY_LEVEL_3D, substeps=1, ramp=16))
    out += [Case(f"2d_L{STUDY_LEVEL_2D}_s{round(1 / s)}_m{m}", "2d", STUDY_LEVEL_2D, unit="k", n=4.0, size=15.0,
                 step=s, substeps=m) for s, m in STEPS["full_2d"]]
    return out + [Case(f"2d_L{STUDY_LEVEL_2D}_s{round(1 / s)}_m1_r16", "2d", STUDY_LEVEL_2D, unit="k", n=4.0,
                       size=15.0, step=s, ramp=16) for s in (0.125, 0.0625)]


def line_contact_cases(mode: str) -> list[Case]:
    step, m = 0.25, 4
    if mode == "quick":
        return [Case(f"q2d_bhw_{lv}k", "2d", lv, unit="k", n=3.0, size=15.0, length=2.0, step=0.5, substeps=4,
                     passes=4) for lv in BHW_LEVELS]
    out = [Case(f"2d_bhw_{lv}k_{p}p", "2d", lv, unit="k", n=4.0, size=40.0, length=2.5, step=step, substeps=m,
                passes=p) for lv, p in BHW_LEVELS.items()]
    return out + [Case("2d_bhw_4.35k_s8", "2d", 4.35, unit="k", n=4.0, size=40.0, length=2.5, step=step / 2,
                       substeps=m, passes=6)]


def shipped_cases(mode: str) -> list[Case]:
    """The shipped levels with 4 sub-steps at a/4 and at the recommended a/8 (3 passes), the first pass at 2.1 p_y
    with a/16 (the step error grows with p0), at 1.7 p_y on a track one contact length longer and on the finer
    mesh h = a/4.5."""
    if mode == "quick":
        return []
    step, m = RECOMMENDED
    out = [Case(f"3d_ship_L{lv}_s{round(1 / s)}_m{m}", "3d", lv, step=s, substeps=m, passes=3, static=True)
           for s in (0.25, step) for lv in (1.3, 1.7, 2.1)]
    return out + [Case(f"3d_L2.1_s{round(2 / step)}_m{m}", "3d", 2.1, step=step / 2, substeps=m),
                  Case(f"3d_L1.7_s{round(1 / step)}_m{m}_track3", "3d", 1.7, length=3.0, step=step, substeps=m,
                       static=True),
                  Case(f"3d_L1.7_s{round(1 / step)}_m{m}_h4.5", "3d", 1.7, n=4.5, step=step, substeps=m, static=True)]


def _pct(a: float, b: float) -> float:
    return 100.0 * (a / b - 1.0)


def limits(rows: list[VerificationResult]) -> dict[str, float]:
    """ds -> 0 limits of the first-pass groove, first order from the two finest steps of each method (mm)."""
    out = {}
    for label, m in (("plain", 1), ("sub-steps", 4)):
        pick = lambda r, m=m: r.case.substeps == m and r.case.ramp == 4  # noqa: E731 - the ramp study apart
        seq = sorted((r for r in rows if pick(r)), key=lambda r: r.case.step)
        if len(seq) >= 2 and abs(seq[1].case.step - 2 * seq[0].case.step) < 1e-12:
            out[label] = 2.0 * seq[0].groove_mm[0] - seq[1].groove_mm[0]
    return out


def study_markdown(rows: list[VerificationResult], title: str) -> list[str]:
    lim = limits(rows)
    ref = lim.get("plain", rows[0].groove_mm[0])
    dent = next((r.static_dent_mm for r in rows if r.static_dent_mm > 0), 0.0)
    lims = "; ".join(f"{k}: {v:.5g} mm" for k, v in lim.items())
    md = [f"{title} ({rows[0].n_dofs} dofs). Limits ds -> 0 (first order from the two finest steps): {lims}.", "",
          "| sub-steps | step | ramp steps | groove pass 1 (mm) | vs plain limit | vs sub-step limit | "
          "groove / static | wall s per pass | Newton iterations | load average |",
          "|---|---|---|---|---|---|---|---|---|---|"]
    for r in sorted(rows, key=lambda r: (r.case.substeps, r.case.ramp, -r.case.step)):
        g = r.groove_mm[0]
        sub = f"{_pct(g, lim['sub-steps']):+.1f} %" if "sub-steps" in lim else "-"
        ratio = f"{g / dent:.3f}" if dent > 0 else "-"
        md.append(f"| {r.case.substeps} | a/{1 / r.case.step:g} | {r.case.ramp} | {g:.5g} | {_pct(g, ref):+.1f} % "
                  f"| {sub} | {ratio} | {r.pass_seconds[0]:.0f} | {r.newton_iterations[0]} | "
                  f"{r.load_average[0]:.1f} |")
    return md


def line_contact_markdown(rows: list[VerificationResult]) -> list[str]:
    md = ["2D plane strain, frictionless, elastic-perfectly plastic; per pass: groove (mm), net plastic strain "
          "change (largest below |x| <= a, -), growth of the largest equivalent plastic strain (-), surface shift "
          "increment (mm).", "",
          "| p0 / k | p0 / p_y | step | pass | groove (mm) | net plastic change | eq. plastic strain growth | "
          "shift increment (mm) |", "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        eq, sh = r.max_eq_plastic_strain, r.shift_mm
        for k in range(len(r.groove_mm)):
            if k > 5 and k != len(r.groove_mm) - 1 and k % 4 != 3:
                continue
            md.append(f"| {r.case.level:g} | {r.p0_MPa / r.p_y_MPa:.2f} | a/{1 / r.case.step:g} | {k + 1} | "
                      f"{r.groove_mm[k]:.4g} | "
                      f"{r.net_plastic_increment[k]:.3g} | {eq[k] - (eq[k - 1] if k else 0.0):.3g} | "
                      f"{sh[k] - (sh[k - 1] if k else 0.0):+.3g} |")
    return md


def shipped_markdown(rows: list[VerificationResult]) -> list[str]:
    if not rows:
        return []
    md = [f"Shipped mesh ({rows[0].n_dofs} dofs), 4 material sub-steps; CPU: process time per pass (the first "
          "pass with the unit responses), wall: under the machine's load:", "",
          "| p0 / p_y | step | track | h | static dent (mm) | groove after each pass (mm) | groove / static | "
          "pass 2 adds | pass 3 adds | CPU s per pass | wall s per pass |", "|" + "---|" * 11]
    for r in rows:
        g = r.groove_mm
        dent = f"{r.static_dent_mm:.4g}" if r.static_dent_mm > 0 else "-"
        ratio = f"{g[0] / r.static_dent_mm:.3f}" if r.static_dent_mm > 0 else "-"
        adds = [f"{_pct(g[k], g[k - 1]):+.1f} %" if len(g) > k else "-" for k in (1, 2)]
        cpu = f"{sum(r.pass_cpu_seconds) / len(g):.0f}" if r.pass_cpu_seconds else "-"
        md.append(f"| {r.case.level:g} | a/{1 / r.case.step:g} | {r.case.length:g} | a/{r.case.n:g} | {dent} | "
                  f"{', '.join(f'{x:.4g}' for x in g)} | {ratio} | {adds[0]} | {adds[1]} | {cpu} | "
                  f"{sum(r.pass_seconds) / len(g):.0f} |")
    return md


def tamaas_markdown(mode: str, out: pathlib.Path) -> tuple[list[str], list[dict]]:
    """The Tamaas rolling reference's table (full and tamaas modes, when Tamaas is importable) and its cases."""
    version = tamaas_version()
    if version is None or mode == "quick":
        return [f"Tamaas rolling reference: {'not run in quick mode' if version else 'not importable here'}."], []
    res = [tamaas_rolling.run_case(c, out / "tamaas", progress=lambda s: print(s, flush=True))
           for c in tamaas_rolling.cases("coarse")]
    return [f"Tamaas {version} rolling reference (periodic cell 8 a, plastic layer 2 a, p_y = "
            f"{tamaas_rolling.PY_OVER_Y} Y):", ""] + tamaas_rolling.markdown(res), res


def run(mode: str, out: pathlib.Path) -> dict:
    """Benchmark entry point (``python -m benchmarks --only rolling_verification``), one BLAS/MKL thread; mode
    "tamaas" runs only the Tamaas rolling reference."""
    from threadpoolctl import threadpool_limits

    out = pathlib.Path(out) / "rolling_verification"
    runner = CaseRunner(out / "cases", progress=lambda s: print(s, flush=True))
    load = os.getloadavg()
    fem = mode != "tamaas"
    with threadpool_limits(limits=1):
        study = [runner(c) for c in study_cases(mode)] if fem else []
        line = [runner(c) for c in line_contact_cases(mode)] if fem else []
        shipped = [runner(c) for c in shipped_cases(mode)] if fem else []
        tam_md, tam = tamaas_markdown(mode, out)
    md = [f"Machine load average {load[0]:.1f} / {load[1]:.1f} / {load[2]:.1f} (1 / 5 / 15 min) at the start; "
          "each case's own in its row or JSON.", ""]
    for dim, title in (("3d", f"3D half-space, circular contact, p0 = {STUDY_LEVEL_3D} p_y"),
                       ("2d", f"2D line contact, p0 = {STUDY_LEVEL_2D} k")):
        rows = [r for r in study if r.case.model == dim]
        if rows:
            md += study_markdown(rows, title) + [""]
    if fem:
        md += line_contact_markdown(line) + [""] + shipped_markdown(shipped) + [""]
    md += tam_md
    data = {"cases": [r.to_dict() for r in study + line + shipped], "load_average": list(load),
            "tamaas": tamaas_version(), "tamaas_cases": tam}
    return {"title": "Rolling FEM verification: step length, line contact, shipped levels",
            "markdown": "\n".join(md), "figures": [], "data": data}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python benchmarks/bench_rolling_verification.py",
                                 description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_const", dest="mode", const="quick", default="full")
    ap.add_argument("--full", action="store_const", dest="mode", const="full")
    ap.add_argument("--tamaas", action="store_const", dest="mode", const="tamaas",
                    help="only the Tamaas rolling reference")
    ap.add_argument("--out", type=pathlib.Path, default=pathlib.Path("out/bench"))
    ap.add_argument("--report", type=pathlib.Path, default=None,
                    help="also write the stamped report here (docs/validation/rolling-verification.md)")
    args = ap.parse_args(argv)
    res = run(args.mode, args.out)
    folder = args.out / "rolling_verification"
    report = stamped_report(res["title"], res["markdown"],
                            command_line("python benchmarks/bench_rolling_verification.py", argv))
    (folder / "report.md").write_text(report)
    if args.report:
        args.report.write_text(report)
    (folder / "report.json").write_text(json.dumps(res["data"], indent=1, default=float))
    print(res["markdown"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
