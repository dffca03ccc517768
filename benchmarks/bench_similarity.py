"""Similarity benchmark: the master-curve route against the direct 3D FEM at the default run's positions.

For every position of ``calibration/configs/default.toml`` that the similarity route serves (non-conforming, a/b
in the master's range), its characteristic from the master is compared with the direct FEM of the same position:
the first-yield pressure p_y, u_pl at every load level of the direct path (absolute p0, relative to the direct
u_pl at the largest level) and the residual dents after unloading from each peak (relative, at the same peak
factors f p_y). Also: the time per position once the master exists (the route and the interpolation; and a whole
``calibrate`` call per position including the geometry and the fit), and the master's own FEM cost.

Inputs: the direct FEM results of the default run's positions (``out/calibration_direct/cache``, the default
configuration with ``run.method = "direct"``) and the master's FEM results (``MASTER`` below, where ``make
calibrate`` keeps them); in "full" mode missing ones are
computed (a cold default run: minutes on 2 workers), in "quick" mode the benchmark reports what is missing.
``python -m benchmarks.bench_similarity DIRECT_OUT MASTER_DIR`` compares two given folders.

The wear example with its tables recalibrated by similarity after every step
(``scenes/wear/s1002_60e1_recalibrated.toml``) is timed against the example without recalibration
(``scenes/wear/s1002_60e1.toml``), both in this process, the master cached (full mode; ``--wear`` alone). Units: mm,
MPa, s.
"""

from __future__ import annotations

import dataclasses
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
DIRECT_OUT = ROOT / "out" / "calibration_direct"
MASTER = ROOT / "out" / "calibration" / "cache"  # where `make calibrate` (similarity) keeps the master
CONFIG = ROOT / "calibration" / "configs" / "default.toml"
WEAR = ROOT / "scenes" / "wear" / "s1002_60e1.toml"
WEAR_RECALIBRATED = ROOT / "scenes" / "wear" / "s1002_60e1_recalibrated.toml"
#: The wear run with recalibration at every step may take at most this many times the run without (-).
WEAR_TARGET = 2.0
#: The agreement asked of the similarity route before it becomes the default of ``make calibrate`` (-).
TARGET = 0.02


def _config(master_dir: Path, method: str = "similarity"):
    from calibration.config import load_config

    cfg = load_config(CONFIG)
    return dataclasses.replace(cfg, run=dataclasses.replace(cfg.run, method=method, master_dir=str(master_dir),
                                                            plots=False))


def compare(direct, sim, load) -> dict:
    """Relative differences of the similarity indentation ``sim`` against the direct FEM ``direct``."""
    from calibration.indentation import load_levels

    levels = np.array(load_levels(direct.first_yield_MPa, load))
    u_d = np.interp(levels, direct.p_MPa, direct.u_pl_mm)
    u_s = np.interp(levels, sim.p_MPa, sim.u_pl_mm)
    res_d, res_s = np.asarray(direct.residual_fem_mm), np.asarray(sim.residual_fem_mm)
    return {"p_y": sim.first_yield_MPa / direct.first_yield_MPa - 1.0,
            "u_pl": float(np.max(np.abs(u_s - u_d)) / u_d[-1]),
            "residual": float(np.max(np.abs(res_s / res_d - 1.0))) if res_d.size else 0.0}


def _master(cfg, quick: bool):
    """(MasterCurves or None, what is missing) from the master's cache; computed in full mode."""
    from calibration.cache import fem_entry, load_indentation
    from calibration.pipeline import calibrate
    from calibration.similarity.master import MasterCurves, master_tasks

    mat = cfg.bodies[0].material
    tasks = master_tasks(cfg, mat)
    cache = Path(cfg.run.master_dir)
    missing = [t for t in tasks if not fem_entry(cache, t.key).is_file()]
    if len(missing) == len(tasks) and quick:
        return None, f"no master positions in {cache}"
    if missing and not quick:
        with tempfile.TemporaryDirectory() as tmp:
            calibrate(dataclasses.replace(cfg, bodies=cfg.bodies[:1]), tmp, show_progress=False)
    results = {t.key: load_indentation(fem_entry(cache, t.key))[0] for t in tasks
               if fem_entry(cache, t.key).is_file()}  # a failed master position has no entry
    return MasterCurves.build(cfg, mat, tasks, results), ""


def _direct(cfg, direct_out: Path, quick: bool):
    """({key: IndentationResult} of the default positions, tasks, what is missing)."""
    from calibration.cache import fem_entry, load_indentation
    from calibration.pipeline import calibrate
    from calibration.tasks import make_tasks

    dcfg = dataclasses.replace(cfg, run=dataclasses.replace(cfg.run, method="direct"))
    tasks, _, _ = make_tasks(dcfg, direct_out, False)
    cache = direct_out / "cache"
    missing = [t for t in tasks if not fem_entry(cache, t.key).is_file()]
    if missing and quick:
        return {}, tasks, f"{len(missing)} of {len(tasks)} direct FEM positions not in {cache}"
    if missing:
        calibrate(dcfg, direct_out, show_progress=False)
    return {t.key: load_indentation(fem_entry(cache, t.key))[0] for t in tasks}, tasks, ""


def _timing(cfg, master, tasks) -> dict:
    """Per-position times once the master exists: route + interpolation, and a whole calibrate call."""
    from calibration.pipeline import calibrate
    from calibration.position_fit import fit_position
    from calibration.similarity.route import route, similar_indentation

    served = [t for t in tasks if route(t, cfg.reference_load_N, master.aspect_range).method == "similarity"]
    t0 = time.perf_counter()
    for _ in range(20):
        for t in served:
            similar_indentation(master, t.geometry.a_mm, t.geometry.b_mm)
    interp_s = (time.perf_counter() - t0) / (20 * max(1, len(served)))
    t0 = time.perf_counter()
    for _ in range(5):  # what one more position costs: its route, the interpolation and the Prandtl fit
        for t in served:
            route(t, cfg.reference_load_N, master.aspect_range)
            fit_position(similar_indentation(master, t.geometry.a_mm, t.geometry.b_mm), t.geometry, cfg.fit, t.label)
    position_s = (time.perf_counter() - t0) / (5 * max(1, len(served)))
    served_cfg = dataclasses.replace(cfg, bodies=tuple(dataclasses.replace(b, positions_mm=tuple(
        t.y_mm for t in served if t.body == b.body)) for b in cfg.bodies))
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        result = calibrate(served_cfg, tmp, show_progress=False, log=lambda *a: None)
        whole_s = time.perf_counter() - t0
    return {"served": len(served), "interpolation_s": interp_s, "position_s": position_s, "load": os.getloadavg()[0],
            "route_s": result.similarity.seconds_per_position if result.similarity else float("nan"),
            "calibrate_s_per_position": whole_s / max(1, len(served)), "calibrate_s": whole_s}


def compare_runs(direct_out: Path, master_dir: Path, quick: bool = True) -> dict:
    """The comparison and timings (``data`` of the report), or what is missing."""
    from calibration.similarity.route import route, similar_indentation

    cfg = _config(master_dir)
    master, why = _master(cfg, quick)
    direct, tasks, why_d = _direct(cfg, direct_out, quick)
    if master is None or not direct:
        return {"missing": "; ".join(w for w in (why, why_d) if w)}
    rows = []
    for t in tasks:
        r = route(t, cfg.reference_load_N, master.aspect_range)
        row = {"body": t.body, "y_mm": t.y_mm, "a_over_b": t.geometry.a_mm / t.geometry.b_mm,
               "method": r.method, "note": r.note}
        if r.method == "similarity":
            row.update(compare(direct[t.key], similar_indentation(master, t.geometry.a_mm, t.geometry.b_mm),
                               cfg.load))
        rows.append(row)
    served = [r for r in rows if r["method"] == "similarity"]
    worst = {k: max((abs(r[k]) for r in served), default=float("nan")) for k in ("p_y", "u_pl", "residual")}
    return {"rows": rows, "worst": worst, "master_fem_s": master.fem_seconds,
            "master_positions": len(master.aspects) * len(master.lengths_mm) - len(master.substituted),
            "substituted": master.substituted,
            "timing": _timing(cfg, master, tasks), "target": TARGET}


def wear_timing() -> dict:
    """Wall times (s) of the wear example with and without recalibration by similarity after every step (the
    master in ``MASTER``, computed first when missing: its cost is not in the times), the machine's load."""
    import os
    import tomllib

    from contact.wear.loop import run_wear
    from contact.wear.scene import parse_wear_scene

    _master(_config(MASTER), quick=False)  # the master exists before the timed runs
    times, steps = {}, {}
    for name, path in (("plain", WEAR), ("recalibrated", WEAR_RECALIBRATED)):
        load = os.getloadavg()[0]
        t0 = time.perf_counter()
        with tempfile.TemporaryDirectory() as tmp:
            scene = parse_wear_scene(tomllib.loads(path.read_text()), path)
            run = run_wear(scene, show_progress=False, work_dir=Path(tmp))
        times[name] = time.perf_counter() - t0
        steps[name] = {"steps": len(run.steps), "load": load,
                       "recalibration_s": sum(r.timings.get("recalibration_s", 0.0) for r in run.steps)}
    return {"plain_s": times["plain"], "recalibrated_s": times["recalibrated"],
            "ratio": times["recalibrated"] / times["plain"], "target": WEAR_TARGET, "runs": steps}


def _markdown(data: dict) -> str:
    if "missing" in data:
        return f"Not measured: {data['missing']} (run the full mode, or `make calibrate` with method direct)."
    md = ["| body | y [mm] | a/b | route | p_y | u_pl (rel. to max) | residual dents |", "|---|---|---|---|---|---|---|"]
    for r in data["rows"]:
        if r["method"] == "similarity":
            md.append(f"| {r['body']} | {r['y_mm']:g} | {r['a_over_b']:.2f} | similarity | {100 * r['p_y']:+.2f} % | "
                      f"{100 * r['u_pl']:.2f} % | {100 * r['residual']:.2f} % |")
        else:
            md.append(f"| {r['body']} | {r['y_mm']:g} | {r['a_over_b']:.2f} | direct: {r['note']} | | | |")
    w, tm = data["worst"], data["timing"]
    md += ["", f"Worst over the {tm['served']} served positions: p_y {100 * w['p_y']:.2f} %, u_pl "
               f"{100 * w['u_pl']:.2f} %, residual dents {100 * w['residual']:.2f} % (target {100 * TARGET:g} %).",
           f"Master: {data['master_positions']} FEM positions, {data['master_fem_s']:.0f} s of FEM"
           f"{' (substituted: ' + '; '.join(data['substituted']) + ')' if data['substituted'] else ''}. Per position "
           f"once the master exists (load {tm['load']:.1f} on 2 cores): interpolation {1e3 * tm['interpolation_s']:.3f} "
           f"ms, route, interpolation and Prandtl fit {1e3 * tm['position_s']:.1f} ms; a whole calibrate call (profiles, "
           f"geometry, fit, tables) {1e3 * tm['calibrate_s_per_position']:.0f} ms per position."]
    return "\n".join(md)


def run(mode: str, out: Path) -> dict:
    data = compare_runs(DIRECT_OUT, MASTER, quick=mode != "full")
    if mode == "full" and "missing" not in data:
        data["wear"] = wear_timing()
        w = data["wear"]
        data_md = (f"\n\nWear example, 3000 km, tables recalibrated by similarity after every step: "
                   f"{w['recalibrated_s']:.0f} s ({w['runs']['recalibrated']['steps']} steps, recalibration "
                   f"{w['runs']['recalibrated']['recalibration_s']:.0f} s) against {w['plain_s']:.0f} s without "
                   f"recalibration: x{w['ratio']:.2f} (target < x{WEAR_TARGET:g}; load "
                   f"{w['runs']['plain']['load']:.1f} / {w['runs']['recalibrated']['load']:.1f}).")
        return {"title": "Calibration by similarity against the direct 3D FEM", "markdown": _markdown(data) + data_md,
                "figures": [], "data": data}
    return {"title": "Calibration by similarity against the direct 3D FEM", "markdown": _markdown(data),
            "figures": [], "data": data}


if __name__ == "__main__":
    if sys.argv[1:] == ["--wear"]:
        print(wear_timing())
    else:
        print(_markdown(compare_runs(Path(sys.argv[1]), Path(sys.argv[2]), quick=True)))
