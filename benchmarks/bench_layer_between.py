"""The shipped tables' elements between their FEM levels: a check on levels the fit never saw (units mm, MPa).

The operating-range fit (:mod:`calibration.fit.operating_range`) is checked by ``bench_layer_range`` at the FEM
levels it was fitted to (1.05, 1.1, 1.2, 1.25, 1.3, 1.5, 1.7, ... p_2). Between them the element is piecewise
linear with break points where the fit put them, and near first yield, where u_pl is most curved, a segment can
pass through its two neighbouring FEM points and still miss the curve between them. This benchmark reruns the FEM
of a position with the default configuration, but unloading from peaks between the table's levels
(``BETWEEN``), and compares the shipped table's element with it at the same peak pressure p0 (MPa):

- the loaded inelastic displacement u_pl(p0) (element: u(p0) - p0 / S_1, S_1 its first slope);
- the residual dent after load to p0 and unload (the element's exact unloading with its reverse factor).

Errors are (element - FEM) / max(FEM, FEM(1.5 p_2) / 3) (the calibration's target measure; target 3 %), and the
largest |element - FEM| / FEM at the peaks from 1.1 p_2 up (relative to the value itself: what the fit's own measure
aims at). The rerun's first yield must equal the table's p_2 (same mesh and material; it is reported).

``python -m benchmarks.bench_layer_between [--positions rail:0 wheel:-37.5 ...] [--report FILE]``
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
CONFIG = ROOT / "calibration" / "configs" / "default.toml"
TABLES = {"rail": ROOT / "scenes" / "tables" / "rail_60E1_default.json",
          "wheel": ROOT / "scenes" / "tables" / "wheel_S1002_default.json"}
#: Peaks p0 / p_2 between the table's FEM levels (-).
BETWEEN = (1.075, 1.15, 1.175, 1.275, 1.4, 1.6, 1.8, 2.2)
#: The positions of the rolling section cases (body, y in mm): crown, gauge corner, field side, tread, flange root.
POSITIONS = (("rail", 0.0), ("rail", -35.0), ("rail", 25.0), ("wheel", 0.0), ("wheel", -37.5))
#: The target on the scaled error (-).
TARGET = 0.03
#: The lowest peak of the error relative to the value itself (p0 / p_2, -).
RELATIVE_FROM = 1.1


@dataclass(frozen=True)
class BetweenRow:
    """One position: the element against the FEM at the BETWEEN peaks.

    Attributes
    ----------
    body : str
        "rail" or "wheel".
    y_mm : float
        Lateral position (mm).
    p2_table_MPa, p_y_fem_MPa : float
        The table's p_2 and the rerun's first yield (MPa).
    levels : list of float
        Peaks p0 / p_2 (-).
    u_pl_fem_mm, u_pl_element_mm : list of float
        Loaded inelastic displacement at the peaks (mm).
    residual_fem_mm, residual_element_mm : list of float
        Residual dent after unloading from the peaks (mm).
    u_pl_error, residual_error : list of float
        Scaled errors (element - FEM) / max(FEM, FEM(1.5 p_2) / 3) (-).
    fem_seconds : float
        Wall time of the rerun (s).
    """

    body: str
    y_mm: float
    p2_table_MPa: float
    p_y_fem_MPa: float
    levels: list[float]
    u_pl_fem_mm: list[float]
    u_pl_element_mm: list[float]
    residual_fem_mm: list[float]
    residual_element_mm: list[float]
    u_pl_error: list[float]
    residual_error: list[float]
    fem_seconds: float

    def worst(self) -> float:
        return float(max(np.max(np.abs(self.u_pl_error)), np.max(np.abs(self.residual_error))))

    def worst_relative(self, from_level: float = RELATIVE_FROM) -> float:
        """The largest |element - FEM| / FEM of u_pl and the residual at the peaks from ``from_level`` p_2 (-)."""
        keep = np.asarray(self.levels) >= from_level - 1e-9
        pairs = ((self.u_pl_element_mm, self.u_pl_fem_mm), (self.residual_element_mm, self.residual_fem_mm))
        e = [np.abs(np.asarray(el)[keep] / np.asarray(fem)[keep] - 1.0) for el, fem in pairs]
        return float(np.max(np.concatenate(e), initial=0.0))


def rerun(body: str, y_mm: float, levels: tuple[float, ...]):
    """The FEM of the default configuration's position with unloading peaks ``levels`` x p_y."""
    from calibration.config import load_config
    from calibration.tasks import make_tasks, run_position
    from wrlayer.runner import limited_threads

    cfg = load_config(CONFIG)
    cfg = dataclasses.replace(cfg, load=dataclasses.replace(cfg.load, unload_factors=tuple(levels)))
    with tempfile.TemporaryDirectory() as tmp, limited_threads(1):
        tasks, _, _ = make_tasks(cfg, Path(tmp), plots=False)
        task = next(t for t in tasks if t.body == body and abs(t.y_mm - y_mm) < 1e-9)
        out = run_position(task)
    if out.error:
        raise RuntimeError(f"{body} y = {y_mm:g} mm: {out.error}")
    return out.indentation


def compare(body: str, y_mm: float, ind, levels: tuple[float, ...] = BETWEEN) -> BetweenRow:
    """The shipped table's element at (body, y_mm) against the rerun ``ind`` at its peaks."""
    from calibration.fit.operating_range import error_scale_mm
    from wrlayer.layer_table import LayerTable

    table = LayerTable.read(TABLES[body])
    ch = table.characteristic_at(y_mm)
    p2 = ch.elastic_limit_MPa
    s1 = ch.p_MPa[1] / ch.u_mm[1]  # the first segment: the elastic slope S_1 (N/mm^3)
    p, u_pl = np.asarray(ind.p_MPa), np.asarray(ind.u_pl_mm)
    peaks = np.asarray(ind.unload_peaks_MPa)
    upl_fem = np.interp(peaks, p, u_pl)
    upl_el = ch.displacement(peaks) - peaks / s1
    res_fem = np.asarray(ind.residual_fem_mm)
    res_el = np.asarray(ch.unloading_residual(peaks))
    upl_err = (upl_el - upl_fem) / error_scale_mm(p, u_pl, p2, peaks)
    res_err = (res_el - res_fem) / error_scale_mm(peaks, res_fem, p2, peaks)
    return BetweenRow(body, y_mm, p2, float(ind.first_yield_MPa), (peaks / float(ind.first_yield_MPa)).tolist(),
                      upl_fem.tolist(), np.asarray(upl_el).tolist(), res_fem.tolist(), res_el.tolist(),
                      upl_err.tolist(), res_err.tolist(), float(ind.seconds))


def markdown(rows: list[BetweenRow]) -> str:
    levels = rows[0].levels
    head = ("| body | y (mm) | p_y rerun / table p_2 | " + " | ".join(f"u_pl {x:.3g}" for x in levels) + " | "
            + " | ".join(f"res {x:.3g}" for x in levels)
            + f" | worst | worst of the value from {RELATIVE_FROM:g} p_2 |")
    lines = [head, "|" + "---|" * (5 + 2 * len(levels))]
    for r in rows:
        lines.append(f"| {r.body} | {r.y_mm:g} | {r.p_y_fem_MPa / r.p2_table_MPa:.6f} | "
                     + " | ".join(f"{100 * e:+.1f}" for e in r.u_pl_error) + " | "
                     + " | ".join(f"{100 * e:+.1f}" for e in r.residual_error) + f" | {100 * r.worst():.1f} | "
                     f"{100 * r.worst_relative():.1f} |")
    met = sum(r.worst() <= TARGET for r in rows)
    return (f"The shipped tables' elements at peaks between their FEM levels, against a FEM rerun of the same "
            f"position unloading from those peaks; errors in % of max(FEM, FEM(1.5 p_2) / 3), element minus FEM, at "
            f"equal p0 (MPa). **{met} of {len(rows)} positions within {100 * TARGET:g} % at every peak.**\n\n"
            + "\n".join(lines) + "\n")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.bench_layer_between", description=__doc__.splitlines()[0])
    ap.add_argument("--positions", nargs="*", default=None, help="body:y_mm (default: the rolling section positions)")
    ap.add_argument("--report", type=Path, default=None)
    args = ap.parse_args(argv)
    try:
        positions = ([(s.split(":")[0], float(s.split(":")[1])) for s in args.positions] if args.positions
                     else list(POSITIONS))
    except (IndexError, ValueError):
        print(f"error: --positions: expected body:y_mm, got {args.positions}", file=sys.stderr)
        return 2
    rows = []
    for body, y in positions:
        rows.append(compare(body, y, rerun(body, y, BETWEEN)))
        print(f"{body} y = {y:g}: worst {100 * rows[-1].worst():.2f} % ({rows[-1].fem_seconds:.1f} s)", flush=True)
    md = markdown(rows)
    print(md)
    if args.report:
        from benchmarks.harness import command_line, stamped_report
        from wrlayer.atomic_write import atomic_write_text

        cmd = command_line("python -m benchmarks.bench_layer_between", argv)
        atomic_write_text(args.report, stamped_report("Validation: the layer between its calibrated levels", md, cmd))
    return 0


if __name__ == "__main__":
    sys.exit(main())
