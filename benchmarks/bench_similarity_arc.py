"""Where the similarity route's error comes from: the master's interpolation, or its arc-block model of a surface.

For every position the route serves from the master (default ``calibration/configs/default.toml``), the 3D FEM of
one synthetic arc block (:func:`calibration.similarity.sections.arc_section`) at the position's own semi-axes a, b
and the convexity its plastic curves are taken at (``Route.plastic_convexity``) is run: the master point the route
would need, without interpolation. Then, at equal p0/p_y (each curve at its own first-yield pressure, as the route
combines the master's plastic curves with the section's own p_y), three comparisons of u_pl at the levels 1.05-3
p_y of the direct path and of the residual dents at its unloading peaks:

- the arc block's FEM against the position's direct FEM: the error of the arc-block model itself;
- the master (interpolated at the same point) against the direct FEM: what the route gives;
- the master against the arc block's FEM: the interpolation error of the master grid.

Errors relative to the direct (or arc) value, or to half its value at 1.5 p_y where larger (as
:mod:`benchmarks.bench_similarity`). Inputs as that benchmark: the direct run's FEM cache and the master's cache
("quick" mode reports what is missing). With ``--fine DIR`` (the mesh study's folder,
``benchmarks/data/calibration_mesh_same_pressure``: each position's direct FEM on the default and on a finer mesh)
every position where the arc FEM misses the target is run again on the arc block with the finer mesh, and both
sides are compared converged: the arc block's fine FEM against the direct fine FEM, and how far each side moved from
its default mesh. Regenerate::

    python -m benchmarks.bench_similarity_arc --fine benchmarks/data/calibration_mesh_same_pressure
        --report docs/validation/similarity-arc.md

Units: mm, MPa, s.
"""

from __future__ import annotations

import argparse
import dataclasses
import tempfile
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from benchmarks.bench_similarity import (CONFIG, DIRECT_OUT, MASTER, TARGET, _config, _direct, _master, _relative,
                                         direct_keys)
from benchmarks.harness import publish

TITLE = "Similarity: the arc-block model against the master's interpolation"
#: The levels compared: the direct path's multiples of p_y within this range (-).
Q_RANGE = (1.05, 3.0)


def equal_q_errors(ref, other) -> tuple[np.ndarray, np.ndarray]:
    """(u_pl errors per level, residual errors per peak) of ``other`` against ``ref`` (IndentationResult-like:
    first_yield_MPa, p_MPa, u_pl_mm, unload_peaks_MPa, residual_fem_mm) at equal p0/p_y, relative to ``ref`` or to
    :data:`benchmarks.bench_similarity.FLOOR_AT_1_5` of its value at 1.5 p_y where larger (its ``_relative``)."""
    py_r, py_o = ref.first_yield_MPa, other.first_yield_MPa
    q = np.asarray(ref.p_MPa) / py_r
    q = q[(q >= Q_RANGE[0] - 1e-9) & (q <= Q_RANGE[1] + 1e-9)]
    u_r = np.interp(q * py_r, ref.p_MPa, ref.u_pl_mm)
    u_o = np.interp(q * py_o, other.p_MPa, other.u_pl_mm)
    f = np.asarray(ref.unload_peaks_MPa) / py_r
    r_r = np.asarray(ref.residual_fem_mm, dtype=float)
    r_o = np.interp(f * py_o, other.unload_peaks_MPa, other.residual_fem_mm)
    return (_relative(u_o - u_r, u_r, float(np.interp(1.5 * py_r, ref.p_MPa, ref.u_pl_mm))),
            _relative(r_o - r_r, r_r, float(np.interp(1.5, f, r_r))))


def arc_tasks(cfg, master, tasks):
    """[(position task, route, the arc block's FEM task)] of every position the route serves."""
    from calibration.similarity.master import arc_task
    from calibration.similarity.route import route
    from calibration.tasks import code_hash

    code = code_hash()
    ranges = (master.aspect_range, master.convexity_range)
    out = []
    for t in tasks:
        r = route(t, ranges)
        if r.method != "similarity":
            continue
        mat = next(body.material for body in cfg.bodies if body.body == t.body)
        out.append((t, r, arc_task(cfg, mat, round(r.plastic_convexity, 6), t.geometry.a_mm, t.geometry.b_mm, code)))
    return out


def _run(task):
    from calibration.tasks import run_position

    return run_position(task)


def mesh_study_result(run: dict) -> SimpleNamespace:
    """One run of the mesh study's JSON (:mod:`benchmarks.calibration_mesh_same_pressure`: levels and peaks as
    multiples of its own p_y) in the attribute names :func:`equal_q_errors` reads (MPa, mm)."""
    p_y = run["first_yield_MPa"]
    return SimpleNamespace(first_yield_MPa=p_y, p_MPa=np.asarray(run["p_factor"]) * p_y,
                           u_pl_mm=np.asarray(run["u_pl_mm"]), unload_peaks_MPa=np.asarray(run["peak_factor"]) * p_y,
                           residual_fem_mm=np.asarray(run["residual_fem_mm"]))


def _worst(ref, other) -> float:
    u, res = equal_q_errors(ref, other)
    return float(max(np.abs(u).max(), np.abs(res).max()))


def fine_rows(cfg, jobs, rows: list[dict], arcs: list, fine_dir: Path, workers: int) -> list[dict]:
    """Both sides on finer meshes where the arc FEM misses the target: for every such row with a mesh-study file in
    ``fine_dir``, the arc block on that study's reference mesh against the direct FEM on it, and how far the arc
    and the direct FEM moved from their default meshes (worst |error| at equal p0/p_y, as the rows)."""
    import json

    from calibration.similarity.master import arc_task
    from calibration.tasks import code_hash
    from wrlayer.runner import Runner

    todo = []
    for (t, r, _), row, arc in zip(jobs, rows, arcs):
        study = Path(fine_dir) / f"{t.body}_y{t.y_mm:g}.json"
        if "failed" in row or row["arc_vs_direct"]["worst"] <= TARGET or not study.is_file():
            continue
        data = json.loads(study.read_text())
        fine_cfg = dataclasses.replace(cfg, mesh=dataclasses.replace(cfg.mesh, **data["ref"]["mesh"]))
        mat = next(body.material for body in cfg.bodies if body.body == t.body)
        task = arc_task(fine_cfg, mat, round(r.plastic_convexity, 6), t.geometry.a_mm, t.geometry.b_mm, code_hash())
        todo.append((row, arc, data, task))
    with Runner(workers) as runner:
        outs = list(runner.map(_run, [task for *_, task in todo]))
    out = []
    for (row, arc, data, _), res in zip(todo, outs):
        if res.error:
            out.append({"body": row["body"], "y_mm": row["y_mm"], "failed": res.error})
            continue
        fine, direct, direct_fine = res.indentation, mesh_study_result(data["case"]), mesh_study_result(data["ref"])
        out.append({"body": row["body"], "y_mm": row["y_mm"], "mesh": data["ref"]["mesh"],
                    "dofs": [arc.n_dofs, fine.n_dofs], "arc_vs_direct": _worst(direct, arc),
                    "fine_arc_vs_fine_direct": _worst(direct_fine, fine), "arc_moved": _worst(arc, fine),
                    "direct_moved": _worst(direct, direct_fine)})
    return out


def run(mode: str = "quick", workers: int = 2, fine_dir: Path | None = None) -> dict:
    """The three comparisons of every served position (module docstring)."""
    from calibration.cache import fem_entry, load_indentation
    from calibration.similarity.route import similar_indentation
    from calibration.tasks import make_tasks
    from wrlayer.runner import Runner

    cfg = _config(CONFIG, MASTER)
    master, why = _master(cfg, mode == "quick")
    direct, why_direct = _direct(cfg, DIRECT_OUT, mode == "quick")   # present (or computed in full mode)
    if master is None or not direct:
        return {"missing": why or why_direct, "rows": []}
    dcfg = dataclasses.replace(cfg, run=dataclasses.replace(cfg.run, method="direct"))
    keys = direct_keys(dcfg, DIRECT_OUT, None)
    tasks, _, _ = make_tasks(cfg, Path(tempfile.mkdtemp()), False)
    jobs = arc_tasks(cfg, master, tasks)
    with Runner(workers) as runner:
        outs = list(runner.map(_run, [arc for _, _, arc in jobs]))
    rows = []
    for (t, r, _), out in zip(jobs, outs):
        row = {"body": t.body, "y_mm": t.y_mm, "a_over_b": t.geometry.a_mm / t.geometry.b_mm,
               "length_mm": float(np.sqrt(t.geometry.a_mm * t.geometry.b_mm)), "convexity": r.convexity,
               "plastic_convexity": r.plastic_convexity}
        if out.error:
            rows.append({**row, "failed": out.error})
            continue
        ind = load_indentation(fem_entry(DIRECT_OUT / "cache", keys[t.body, t.y_mm]))[0]
        arc = out.indentation
        sim = similar_indentation(master, t.geometry.a_mm, t.geometry.b_mm, r.convexity, r.plastic_convexity)
        for name, (ref, other) in {"arc_vs_direct": (ind, arc), "master_vs_direct": (ind, sim),
                                   "master_vs_arc": (arc, sim)}.items():
            u, res = equal_q_errors(ref, other)
            row[name] = {"u_pl": u.tolist(), "residual": res.tolist(),
                         "worst": float(max(np.abs(u).max(), np.abs(res).max()))}
        row["p_y_arc_over_direct"] = arc.first_yield_MPa / ind.first_yield_MPa - 1.0
        rows.append(row)
    fine = fine_rows(cfg, jobs, rows, [o.indentation for o in outs], fine_dir, workers) if fine_dir else []
    return {"missing": "", "rows": rows, "fine": fine}


def markdown(data: dict) -> str:
    if data["missing"]:
        return f"Not run: {data['missing']}.\n"
    rows = [r for r in data["rows"] if "failed" not in r]
    lines = ["Worst |error| over u_pl at the direct path's levels 1.05-3 p_y and the residual dents at its peaks, "
             "at equal p0/p_y (%):\n",
             "| body | y [mm] | a/b | L [mm] | b/(2R) plastic | arc FEM vs direct | master vs direct | "
             "master vs arc FEM |", "|---|---|---|---|---|---|---|---|"]
    for r in data["rows"]:
        if "failed" in r:
            lines.append(f"| {r['body']} | {r['y_mm']:g} | {r['a_over_b']:.2f} | {r['length_mm']:.2f} | "
                         f"{r['plastic_convexity']:+.4f} | failed: {r['failed'][:60]} | | |")
            continue
        lines.append(f"| {r['body']} | {r['y_mm']:g} | {r['a_over_b']:.2f} | {r['length_mm']:.2f} | "
                     f"{r['plastic_convexity']:+.4f} | {100 * r['arc_vs_direct']['worst']:.2f} | "
                     f"{100 * r['master_vs_direct']['worst']:.2f} | {100 * r['master_vs_arc']['worst']:.2f} |")
    count = {k: sum(r[k]["worst"] <= TARGET for r in rows) for k in ("arc_vs_direct", "master_vs_direct",
                                                                      "master_vs_arc")}
    lines.append(f"\nWithin {TARGET:.0%} of the direct FEM: the arc block's own FEM at {count['arc_vs_direct']} of "
                 f"{len(rows)} served positions, the master at {count['master_vs_direct']}; the master within "
                 f"{TARGET:.0%} of the arc block's FEM (its interpolation) at {count['master_vs_arc']}. "
                 "Where the arc FEM misses, a finer master grid cannot help: the circle fitted over the plastic "
                 "window is not the section the direct FEM loads.")
    if data.get("fine"):
        lines += ["\nBoth sides on finer meshes where the arc FEM misses (the mesh study's reference mesh; worst "
                  "|error| as above, %):\n", "| body | y [mm] | finer mesh | dofs arc: default / finer | arc vs "
                  "direct, default meshes | arc vs direct, finer meshes | arc moved | direct moved |",
                  "|---|---|---|---|---|---|---|---|"]
        for f in data["fine"]:
            if "failed" in f:
                lines.append(f"| {f['body']} | {f['y_mm']:g} | failed: {f['failed'][:60]} | | | | | |")
                continue
            mesh = ", ".join(f"{k} {v}" for k, v in f["mesh"].items())
            lines.append(f"| {f['body']} | {f['y_mm']:g} | {mesh} | {f['dofs'][0]} / {f['dofs'][1]} | "
                         f"{100 * f['arc_vs_direct']:.2f} | {100 * f['fine_arc_vs_fine_direct']:.2f} | "
                         f"{100 * f['arc_moved']:.2f} | {100 * f['direct_moved']:.2f} |")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.bench_similarity_arc", description=__doc__.splitlines()[0])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--fine", type=Path, default=None,
                    help="the mesh study's folder: rerun the misses with both sides on finer meshes")
    ap.add_argument("--report", type=Path, default=None, help="write the stamped report here")
    args = ap.parse_args(argv)
    publish(args.report, TITLE, markdown(run("quick", args.workers, args.fine)),
            "python -m benchmarks.bench_similarity_arc", argv)


if __name__ == "__main__":
    main()
