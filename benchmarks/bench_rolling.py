"""Rolling (moving-load) FEM: time per pass and convergence of the first-pass groove (step length, track length,
mesh), and the groove / static-dent ratios and pass increments compared with the rolling reference.

Reference behaviour (volume-integral method, circular Hertz pressure moved across a periodic EPP half-space,
E 210 GPa, nu 0.3, Y 500 MPa, frictionless): first-pass groove 0.8-0.9 of the static dent at p0 = 1.3, 1.7,
2.1 p_y; the second pass adds 0-3 % of the first at 1.3 and 1.7 p_y (shakedown), about 12 % at 2.1 p_y
(ratcheting). Quick mode: the coarse mesh, two passes and the study at one level (a few minutes on 2 busy cores);
full mode: the shipped ``calibration/configs/rolling_halfspace.toml`` and the study around it. One BLAS thread.
``python benchmarks/bench_rolling.py [--quick|--full] --out DIR`` runs it alone.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import pathlib
import sys
import time

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
          "later passes add | reference groove / static, pass 2 | s per pass | layer relaxed / state kept "
          "after the last pass (mm) |", "|---|---|---|---|---|---|---|---|---|"]
    for lv in res.levels:
        g = lv.groove_mm
        add2 = f"{_pct(g[1], g[0]):+.1f} %" if len(g) > 1 else "-"
        later = ", ".join(f"{_pct(g[k], g[k - 1]):+.2f} %" for k in range(2, len(g))) or "-"
        ref = REFERENCE.get(round(lv.p0_over_py, 2))
        ref_txt = f"{ref[0][0]}-{ref[0][1]}, {ref[1]}" if ref else "-"
        lg = lv.layer_groove_mm
        layer = f"{lg.relaxed[-1]:.4g} / {lg.state_kept[-1]:.4g}" if lg.relaxed else "-"
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


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python benchmarks/bench_rolling.py", description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_const", dest="mode", const="quick", default="full")
    ap.add_argument("--full", action="store_const", dest="mode", const="full")
    ap.add_argument("--out", type=pathlib.Path, default=pathlib.Path("out/bench"))
    args = ap.parse_args(argv)
    res = run(args.mode, args.out)
    (args.out / "rolling").mkdir(parents=True, exist_ok=True)
    (args.out / "rolling" / "report.md").write_text(f"# {res['title']}\n\n{res['markdown']}\n")
    (args.out / "rolling" / "report.json").write_text(json.dumps(res["data"], indent=1, default=float))
    print(res["markdown"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
