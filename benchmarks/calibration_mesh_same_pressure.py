"""The calibration FEM's mesh convergence at equal peak pressure p0 (MPa), every position of the default run.

``bench_calibration``'s every-position study compares the default mesh with a finer reference at multiples of
each mesh's own first-yield pressure p_y. A table is read at a pressure in MPa, and near first yield a residual
dent moves fast with p0 (d ln r / d ln p0 is about 14-20 at 1.15 p_y), so a p_y shift of 0.3 % hides a 5 % dent
difference there. Here each position's reference
(:data:`benchmarks.calibration_mesh_convergence.EVERY_POSITION_REFERENCES`: isotropic 8 elements per semi-axis,
extruded 6 on elongated patches) unloads from the default mesh's absolute peaks
(:func:`benchmarks.calibration_mesh_convergence.convergence_at_same_pressure`): residual dents at the same peaks
(1.05-3 p_y of the default), u_pl at the default's levels above 1.2 p_y, first yield.

``python -m benchmarks.calibration_mesh_same_pressure OUT [--workers 2] [--report FILE]``: one JSON per position
in OUT (``<body>_y<y>.json``; a complete one is read, not run again), the table on stdout and with ``--report``
the stamped validation report (docs/validation/calibration-mesh.md). About 1-3 min of one core a position
(29 positions: about 20 min on 2 cores). Units: mm, MPa, s.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from benchmarks.calibration_mesh_convergence import convergence_at_same_pressure, every_position_references
from benchmarks.harness import publish
from wrlayer.atomic_write import atomic_write_text
from wrlayer.runner import Runner

#: The deviations counted in the summary (relative).
LIMITS = (0.01, 0.02)
#: The residual dents from this peak (multiple of the default's p_y) up count in the summary's "from 1.1 p_y".
FROM_PEAK = 1.1


def position_file(out: Path, body: str, y_mm: float) -> Path:
    """The result file of one position in ``out``."""
    return out / f"{body}_y{y_mm:g}.json"


def run_position(task: tuple[Path, str, float, dict]) -> Path:
    """One position (``task``: output folder, body, y (mm), reference mesh settings) at equal peaks, written
    atomically; returns its file."""
    out, body, y_mm, ref_kw = task
    result = convergence_at_same_pressure(body, y_mm, {}, ref_kw)
    return atomic_write_text(position_file(out, body, y_mm), json.dumps(result, indent=1))


def markdown(results: list[dict]) -> str:
    """The table (one row per position: dofs, first yield, u_pl, residual dents at every peak) and the summary."""
    if not results:
        return ""
    peaks = results[0]["case"]["peak_factor"]
    lines = ["| position | a/b | dofs (default / reference) | reference | first yield | u_pl at the levels, largest | "
             f"residual dents at {', '.join(f'{f:g}' for f in peaks)} p_y [%] |", "|---|---|---|---|---|---|---|"]
    worst = []
    for r in results:
        case, e = r["case"], r["errors"]
        res = np.asarray(e["residual_levels"])
        above = np.asarray(case["peak_factor"]) >= FROM_PEAK - 1e-9
        worst.append((float(np.max(np.abs(res[above]))), float(abs(res[0])), abs(e["u_pl_levels_max"])))
        ref = r["ref"]["mesh"]
        lines.append(f"| {case['body']} y = {case['y_mm']:g} | {case['a_mm'] / case['b_mm']:.2f} | "
                     f"{case['n_dofs']} / {r['ref']['n_dofs']} | {ref['style']} {ref['elements_per_semi_axis']:g} | "
                     f"{100 * e['first_yield']:+.2f} % | {100 * e['u_pl_levels_max']:.2f} % | "
                     f"{', '.join(f'{100 * x:+.2f}' for x in res)} |")
    w = np.asarray(worst)
    counted = np.maximum(w[:, 0], w[:, 2])  # from 1.1 p_y up and u_pl (1.05 p_y: the dent is nearly nil)
    counts = "; ".join(f"within {lim:.0%}: {int(np.sum(counted <= lim))}" for lim in LIMITS)
    largest = (f"residual from {FROM_PEAK:g} p_y {100 * w[:, 0].max():.2f} %, at 1.05 p_y {100 * w[:, 1].max():.2f} %, "
               f"u_pl {100 * w[:, 2].max():.2f} %")
    lines += ["", f"{len(results)} positions at equal peak pressure (MPa). Residual dents from {FROM_PEAK:g} p_y up "
                  f"and u_pl at the levels, worst of each position: {counts}. Largest: {largest}."]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.calibration_mesh_same_pressure",
                                 description=__doc__.splitlines()[0])
    ap.add_argument("out", type=Path, help="one JSON per position (complete ones are read)")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--report", type=Path, default=None, help="also write the stamped report here")
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    positions = [(body, y, ref) for body, y, _, ref in every_position_references()]
    todo = [(args.out, body, y, ref) for body, y, ref in positions if not position_file(args.out, body, y).is_file()]
    with Runner(args.workers) as runner:
        for _, path in runner.imap(run_position, todo):
            print(f"done: {path.name}", flush=True)
    results = [json.loads(position_file(args.out, body, y).read_text()) for body, y, _ in positions]
    publish(args.report, "The calibration FEM's mesh convergence at equal peak pressure", markdown(results),
            "python -m benchmarks.calibration_mesh_same_pressure", argv)


if __name__ == "__main__":
    main()
