"""Similarity benchmark: the master-curve route against the direct 3D FEM at the default run's 29 positions.

For every position of the configuration (default ``calibration/configs/default.toml``) its characteristic from the
master (at its own semi-axes and surface convexity b/(2R) over the patch) is compared with the direct FEM of the
same position at equal physical load (p0 in MPa): the first-yield pressure p_y, u_pl at every load level of the
direct path above p_y and the residual dent after unloading from every peak (the master's residual interpolated at
the direct run's peaks in MPa). Each error is relative to the direct value, or to half the direct value at 1.5 p_y
where that is larger (both vanish at first yield, as the calibration's own targets count them). Positions the
route sends to the direct FEM are listed with the reason and what the master's nearest point would give. Also: the
master's FEM count and time, the time per position once the master exists, and the wear example with its tables
recalibrated by similarity after every step (``scenes/wear/s1002_60e1_recalibrated.toml``) against the example
without recalibration (``scenes/wear/s1002_60e1.toml``), both in this process, the master cached (with
``--wear-elastic``: also under the ``similarity_elastic`` rules named).

Inputs: a direct run's FEM cache (``DIRECT_OUT/cache``: ``wrlayer calibrate`` of the configuration with
``run.method = "direct"``; keyed as this code keys the positions, or by ``--direct-keys``) and the master's FEM
cache (``MASTER``, where ``make calibrate`` keeps it); in "full" mode missing ones are computed, in "quick" mode the
benchmark reports what is missing. Regenerate::

    python -m benchmarks.bench_similarity --config CONFIG --direct DIRECT_OUT [--direct-keys KEYS.json]
        --master MASTER_DIR [--wear [--wear-elastic unanchored all]] [--sections] [--report FILE]

Units: mm, MPa, s.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import tempfile
import time
from pathlib import Path

import numpy as np

from benchmarks.harness import publish

ROOT = Path(__file__).resolve().parent.parent
DIRECT_OUT = ROOT / "out" / "calibration_direct"
MASTER = ROOT / "out" / "calibration" / "cache"  # where `make calibrate` (similarity) keeps the master
CONFIG = ROOT / "calibration" / "configs" / "default.toml"
WEAR = ROOT / "scenes" / "wear" / "s1002_60e1.toml"
WEAR_RECALIBRATED = ROOT / "scenes" / "wear" / "s1002_60e1_recalibrated.toml"
#: The wear run with recalibration at every step may take at most this many times the run without (-).
WEAR_TARGET = 1.5
#: The agreement asked of the similarity route at every served position (-).
TARGET = 0.02
#: Errors are relative to the direct value, or to this fraction of the direct value at 1.5 p_y where larger (-).
FLOOR_AT_1_5 = 0.5


def _config(config: Path, master_dir: Path, method: str = "similarity"):
    from calibration.config import load_config

    cfg = load_config(config)
    return dataclasses.replace(cfg, run=dataclasses.replace(cfg.run, method=method, master_dir=str(master_dir),
                                                            plots=False, workers=1))


@dataclasses.dataclass(frozen=True)
class DirectFem:
    """The direct FEM of one position (MPa, mm)."""

    p_y: float
    p_MPa: np.ndarray
    u_pl_mm: np.ndarray
    peaks_MPa: np.ndarray
    residual_mm: np.ndarray

    @classmethod
    def of(cls, ind) -> DirectFem:
        """From an :class:`calibration.results.IndentationResult`."""
        return cls(float(ind.first_yield_MPa), np.asarray(ind.p_MPa, dtype=float),
                   np.asarray(ind.u_pl_mm, dtype=float), np.asarray(ind.unload_peaks_MPa, dtype=float),
                   np.asarray(ind.residual_fem_mm, dtype=float))


def direct_keys(cfg, direct_out: Path, keys_file: Path | None) -> dict[tuple[str, float], str]:
    """{(body, y): cache key} of the direct FEM positions: those of ``cfg`` with ``run.method = "direct"`` (this
    code), or those listed in ``keys_file`` ({"body:y": key}, for a direct run made by another revision)."""
    from calibration.tasks import make_tasks

    if keys_file is not None:
        listed = json.loads(Path(keys_file).read_text())
        return {(k.split(":")[0], float(k.split(":")[1])): v for k, v in listed.items()}
    tasks, _, _ = make_tasks(cfg, direct_out, False)
    return {(t.body, t.y_mm): t.key for t in tasks}


def _relative(diff: np.ndarray, ref: np.ndarray, ref_1_5: float) -> np.ndarray:
    return diff / np.maximum(np.abs(ref), FLOOR_AT_1_5 * abs(ref_1_5))


def compare(direct: DirectFem, sim, load) -> dict:
    """Errors of the similarity indentation ``sim`` against ``direct`` at equal p0 (MPa): p_y (signed), u_pl per
    level above p_y and residual per peak (signed, relative as the module says), and their worst magnitudes."""
    from calibration.indentation import load_levels

    p_y = direct.p_y
    levels = np.array([p for p in load_levels(p_y, load) if p > p_y * (1 + 1e-9)])
    u_d = np.interp(levels, direct.p_MPa, direct.u_pl_mm)
    u_s = np.interp(levels, sim.p_MPa, sim.u_pl_mm)
    u_err = _relative(u_s - u_d, u_d, float(np.interp(1.5 * p_y, direct.p_MPa, direct.u_pl_mm)))
    r_s = np.interp(direct.peaks_MPa, sim.unload_peaks_MPa, sim.residual_fem_mm)
    r_1_5 = float(np.interp(1.5 * p_y, direct.peaks_MPa, direct.residual_mm)) if direct.peaks_MPa.size else 0.0
    r_err = _relative(r_s - direct.residual_mm, direct.residual_mm, r_1_5) if direct.peaks_MPa.size else np.zeros(0)
    # diagnostic: the same at equal p0/p_y (each at its own p_y): what is left when p_y is taken as exact
    u_q = np.interp(levels / p_y * sim.first_yield_MPa, sim.p_MPa, sim.u_pl_mm)
    u_q_err = _relative(u_q - u_d, u_d, float(np.interp(1.5 * p_y, direct.p_MPa, direct.u_pl_mm)))
    return {"p_y": sim.first_yield_MPa / p_y - 1.0, "levels_over_p_y": (levels / p_y).tolist(),
            "u_pl_at_equal_p0_over_p_y": float(np.max(np.abs(u_q_err))),
            "u_pl_per_level": u_err.tolist(), "peaks_over_p_y": (direct.peaks_MPa / p_y).tolist(),
            "residual_per_peak": r_err.tolist(), "u_pl": float(np.max(np.abs(u_err))),
            "residual": float(np.max(np.abs(r_err))) if r_err.size else 0.0}


def _master(cfg, quick: bool):
    """(MasterCurves or None, what is missing) from the master's cache; computed in full mode."""
    from calibration.cache import fem_entry, load_indentation
    from calibration.pipeline import calibrate
    from calibration.similarity.master import MasterCurves, master_tasks

    mat = cfg.bodies[0].material
    tasks = master_tasks(cfg, mat)
    cache = Path(cfg.run.master_dir)
    missing = [t for t in tasks if not fem_entry(cache, t.key).is_file()]
    if missing and quick:
        return None, f"{len(missing)} of {len(tasks)} master positions not in {cache}"
    if missing:
        with tempfile.TemporaryDirectory() as tmp:
            calibrate(dataclasses.replace(cfg, bodies=cfg.bodies[:1]), tmp, show_progress=False)
    results = {t.key: load_indentation(fem_entry(cache, t.key))[0] for t in tasks
               if fem_entry(cache, t.key).is_file()}  # a failed master position has no entry
    return MasterCurves.build(cfg, mat, tasks, results), ""


def _direct(cfg, direct_out: Path, quick: bool, keys_file: Path | None = None):
    """({(body, y): DirectFem} from the direct run's cache ``direct_out/cache``, what is missing)."""
    from calibration.cache import fem_entry, load_indentation
    from calibration.pipeline import calibrate

    dcfg = dataclasses.replace(cfg, run=dataclasses.replace(cfg.run, method="direct"))
    keys = direct_keys(dcfg, direct_out, keys_file)
    cache = Path(direct_out) / "cache"
    missing = [k for k, key in keys.items() if not fem_entry(cache, key).is_file()]
    if missing and quick:
        return {}, f"{len(missing)} of {len(keys)} direct FEM positions not in {cache}"
    if missing:
        calibrate(dcfg, direct_out, show_progress=False)
    return {k: DirectFem.of(load_indentation(fem_entry(cache, key))[0]) for k, key in keys.items()}, ""


def _timing(cfg, master, tasks) -> dict:
    """Per-position times once the master exists: route + interpolation, and route + interpolation + fit."""
    from calibration.position_fit import fit_position
    from calibration.similarity.route import route, task_indentation

    ranges = (master.aspect_range, master.convexity_range)
    t0 = time.perf_counter()
    for _ in range(5):
        for t in tasks:
            r = route(t, ranges, "nearest")
            task_indentation(master, t, r.convexity, r.plastic_convexity)
    route_s = (time.perf_counter() - t0) / (5 * len(tasks))
    t0 = time.perf_counter()
    for t in tasks:
        r = route(t, ranges, "nearest")
        fit_position(task_indentation(master, t, r.convexity, r.plastic_convexity), t.geometry, cfg.fit, t.label)
    fit_s = (time.perf_counter() - t0) / len(tasks)
    return {"route_and_interpolation_s": route_s, "with_fit_s": fit_s, "load": os.getloadavg()[0]}


def section_rows(cfg, master, tasks, direct: dict, direct_out: Path, workers: int = 2) -> list[dict]:
    """The served positions with p_y and c_el from their section's elastic solve
    (:mod:`calibration.similarity.elastic`; solved on ``workers`` processes, cached in ``direct_out/cache``):
    :func:`compare` against the direct FEM, and each solve's time (s)."""
    from calibration.similarity.anchor import anchored
    from calibration.similarity.elastic import section_elastics, with_section
    from calibration.similarity.route import route, task_indentation

    ranges = (master.aspect_range, master.convexity_range)
    served = [(t, r) for t in tasks if (r := route(t, ranges)).method == "similarity"]
    elastics, failed = section_elastics([t for t, _ in served], Path(direct_out) / "cache", workers, "",
                                        lambda *a: None)
    rows = []
    for t, r in served:
        if t.key in failed:
            rows.append({"body": t.body, "y_mm": t.y_mm, "failed": failed[t.key]})
            continue
        el = elastics[t.key]
        sim = anchored(task_indentation(master, t, r.convexity, r.plastic_convexity),
                       with_section(None, master, t, r.convexity, el),
                       float(np.sqrt(t.geometry.a_mm * t.geometry.b_mm)))
        row = {"body": t.body, "y_mm": t.y_mm, "seconds": el.seconds, "n_dofs": el.n_dofs}
        row.update(compare(direct[t.body, t.y_mm], sim, cfg.load))
        rows.append(row)
    return rows


def compare_runs(config: Path, direct_out: Path, master_dir: Path, quick: bool = True,
                 keys_file: Path | None = None, sections: bool = False) -> dict:
    """The comparison and timings (``data`` of the report), or what is missing; with ``sections`` also the
    served positions with their section's elastic solve (:func:`section_rows`)."""
    from calibration.similarity.route import route, task_indentation
    from calibration.tasks import make_tasks

    cfg = _config(config, master_dir)
    master, why = _master(cfg, quick)
    direct, why_d = _direct(cfg, direct_out, quick, keys_file)
    if master is None or why_d:
        return {"missing": "; ".join(w for w in (why, why_d) if w)}
    tasks, _, _ = make_tasks(cfg, Path(tempfile.gettempdir()), False)
    ranges = (master.aspect_range, master.convexity_range)
    rows = []
    for t in tasks:
        r = route(t, ranges)
        served = r if r.method == "similarity" else route(t, ranges, "nearest")
        row = {"body": t.body, "y_mm": t.y_mm, "a_over_b": t.geometry.a_mm / t.geometry.b_mm,
               "length_mm": float(np.sqrt(t.geometry.a_mm * t.geometry.b_mm)), "convexity": r.convexity,
               "method": r.method, "note": r.note}
        row.update(compare(direct[t.body, t.y_mm], task_indentation(master, t, served.convexity, served.plastic_convexity),
                                   cfg.load))
        rows.append(row)
    served = [r for r in rows if r["method"] == "similarity"]
    within = [r for r in served if max(abs(r["p_y"]), r["u_pl"], r["residual"]) <= TARGET]
    worst = {k: max((abs(r[k]) for r in served), default=float("nan")) for k in ("p_y", "u_pl", "residual")}
    n_fem = len(master.convexities) * len(master.lengths_mm) * len(master.aspects)
    return {"config": str(config), "rows": rows, "worst": worst, "served": len(served), "within": len(within),
            "master_fem_s": master.fem_seconds, "master_grid_points": n_fem,
            "master_positions": _master_count(cfg), "substituted": master.substituted,
            "timing": _timing(cfg, master, tasks), "target": TARGET,
            **({"sections": section_rows(cfg, master, tasks, direct, direct_out)} if sections else {})}


def _master_count(cfg) -> int:
    from calibration.similarity.master import master_tasks

    return len(master_tasks(cfg, cfg.bodies[0].material))


def wear_template(master_dir: Path, rule: str) -> str:
    """The wear example's recalibration template with the master in ``master_dir`` and ``[run] similarity_elastic
    = rule``."""
    text = (WEAR_RECALIBRATED.parent / "recalibrate_similarity.toml").read_text()
    text = text.replace('master_dir = "out/calibration/cache"', f'master_dir = "{master_dir}"')
    return text.replace('method = "similarity"', f'method = "similarity"\nsimilarity_elastic = "{rule}"', 1)


def wear_timing(config: Path = CONFIG, master_dir: Path = MASTER, elastic: tuple[str, ...] = ()) -> dict:
    """Wall times (s) of the wear example with and without recalibration by similarity after every step (the
    master in ``master_dir``, computed first when missing: its cost is not in the times), the machine's load; with
    ``elastic`` also the recalibrated run under each of these ``[run] similarity_elastic`` rules."""
    import tomllib

    from contact.wear.loop import run_wear
    from contact.wear.scene import parse_wear_scene

    _master(_config(config, master_dir), quick=False)  # the master exists before the timed runs
    times, runs = {}, {}
    with tempfile.TemporaryDirectory() as tmp:
        for rule in ("none", *elastic):
            (Path(tmp) / f"recalibrate_{rule}.toml").write_text(wear_template(master_dir, rule))
        cases = [("plain", WEAR, "none"), ("recalibrated", WEAR_RECALIBRATED, "none"),
                 *((f"elastic {rule}", WEAR_RECALIBRATED, rule) for rule in elastic)]
        for name, path, rule in cases:
            data = tomllib.loads(path.read_text())
            if "recalibrate" in data.get("wear", {}):
                data["wear"]["recalibrate"]["config"] = str(Path(tmp) / f"recalibrate_{rule}.toml")
            for key, value in data.get("layers", {}).items():
                if isinstance(value, str) and value.endswith(".json"):
                    data["layers"][key] = str((path.parent / value).resolve())
            load = os.getloadavg()[0]
            t0 = time.perf_counter()
            run = run_wear(parse_wear_scene(data, path), show_progress=False, work_dir=Path(tmp) / name)
            times[name] = time.perf_counter() - t0
            runs[name] = {"steps": len(run.steps), "load_before": load, "load_after": os.getloadavg()[0],
                          "recalibration_s": sum(r.timings.get("recalibration_s", 0.0) for r in run.steps),
                          "elastic_solves": len(list((Path(tmp) / name / "calibration" / "cache").glob("elastic-*")))}
    return {"plain_s": times["plain"], "recalibrated_s": times["recalibrated"],
            "ratio": times["recalibrated"] / times["plain"], "target": WEAR_TARGET, "runs": runs,
            "elastic": {rule: {"s": times[f"elastic {rule}"], "ratio": times[f"elastic {rule}"] / times["plain"],
                               **runs[f"elastic {rule}"]} for rule in elastic}}


def _pct(x: float) -> str:
    return f"{100 * x:+.2f}"


def _markdown(data: dict) -> str:
    if "missing" in data:
        return f"Not measured: {data['missing']} (run the full mode, or give --direct and --master)."
    md = ["| body | y [mm] | a/b | L [mm] | b/(2R) | route | p_y [%] | u_pl worst [%] | u_pl per level [%] | "
          "residual worst [%] | residual per peak [%] | u_pl worst at equal p0/p_y [%] |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in data["rows"]:
        route = "similarity" if r["method"] == "similarity" else f"direct ({r['note']}); master's nearest point:"
        md.append(f"| {r['body']} | {r['y_mm']:g} | {r['a_over_b']:.2f} | {r['length_mm']:.2f} | "
                  f"{r['convexity']:+.3f} | {route} | {_pct(r['p_y'])} | {100 * r['u_pl']:.2f} | "
                  f"{' '.join(_pct(e) for e in r['u_pl_per_level'])} | {100 * r['residual']:.2f} | "
                  f"{' '.join(_pct(e) for e in r['residual_per_peak'])} | {100 * r['u_pl_at_equal_p0_over_p_y']:.2f} |")
    first = data["rows"][0]
    w, tm = data["worst"], data["timing"]
    md += ["", f"Levels p0/p_y: {', '.join(f'{q:.3g}' for q in first['levels_over_p_y'])}; unloading peaks: "
               f"{', '.join(f'{q:.3g}' for q in first['peaks_over_p_y'])} (configuration {data['config']}). Errors "
               f"relative to the direct value, or to {FLOOR_AT_1_5:g} x its value at 1.5 p_y where larger; all at "
               "equal p0 (MPa) except the last column, a diagnostic at equal p0/p_y (each curve at its own p_y).",
           f"Served: {data['served']} of {len(data['rows'])} positions; within {100 * TARGET:g} % on p_y, u_pl at "
           f"every level and every residual: {data['within']} of them. Worst over the served positions: p_y "
           f"{100 * w['p_y']:.2f} %, u_pl {100 * w['u_pl']:.2f} %, residual {100 * w['residual']:.2f} %.",
           f"Master: {data['master_positions']} FEM positions ({data['master_grid_points']} grid points), "
           f"{data['master_fem_s']:.0f} s of FEM (one worker, machine shared){'; ' + '; '.join(data['substituted']) if data['substituted'] else ''}. "
           f"Per position once the master exists (load {tm['load']:.1f} on 2 cores): route and interpolation "
           f"{1e3 * tm['route_and_interpolation_s']:.1f} ms, with the Prandtl fit {1e3 * tm['with_fit_s']:.0f} ms."]
    if "sections" in data:
        md += ["", *_sections_markdown(data["sections"])]
    if "wear" in data:
        w = data["wear"]
        md.append(f"Wear example, tables recalibrated by similarity after every step: {w['recalibrated_s']:.0f} s "
                  f"({w['runs']['recalibrated']['steps']} steps, recalibration "
                  f"{w['runs']['recalibrated']['recalibration_s']:.0f} s) against {w['plain_s']:.0f} s without: "
                  f"x{w['ratio']:.2f} (target < x{WEAR_TARGET:g}; load {w['runs']['plain']['load_before']:.1f} / "
                  f"{w['runs']['recalibrated']['load_before']:.1f})."
                  + "".join(f" With `similarity_elastic = \"{rule}\"`: {e['s']:.0f} s (recalibration "
                            f"{e['recalibration_s']:.0f} s, {e.get('elastic_solves', '?')} elastic solves), "
                            f"x{e['ratio']:.2f}."
                            for rule, e in w.get("elastic", {}).items()))
    return "\n".join(md)


def _sections_markdown(rows: list[dict]) -> list[str]:
    ok = [r for r in rows if "failed" not in r]
    within = [r for r in ok if max(abs(r["p_y"]), r["u_pl"], r["residual"]) <= TARGET]
    md = ["With p_y and c_el from each served position's own section (`[run] similarity_elastic = \"all\"`: an "
          "elastic solve of the direct FEM's mesh; the plastic curves from the master at equal p0/p_y), at equal "
          "p0 as above:", "",
          "| body | y [mm] | p_y [%] | u_pl worst [%] | u_pl per level [%] | residual worst [%] | "
          "residual per peak [%] | elastic solve [s] |", "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if "failed" in r:
            md.append(f"| {r['body']} | {r['y_mm']:g} | failed: {r['failed']} | | | | | |")
            continue
        md.append(f"| {r['body']} | {r['y_mm']:g} | {_pct(r['p_y'])} | {100 * r['u_pl']:.2f} | "
                  f"{' '.join(_pct(e) for e in r['u_pl_per_level'])} | {100 * r['residual']:.2f} | "
                  f"{' '.join(_pct(e) for e in r['residual_per_peak'])} | {r['seconds']:.1f} |")
    secs = sorted(r["seconds"] for r in ok)
    worst = {k: max((abs(r[k]) for r in ok), default=float("nan")) for k in ("p_y", "u_pl", "residual")}
    md += ["", f"With the sections' elastic solves: within {100 * TARGET:g} % on p_y, u_pl at every level and "
               f"every residual: {len(within)} of {len(rows)} served positions; worst p_y {100 * worst['p_y']:.2f} %, "
               f"u_pl {100 * worst['u_pl']:.2f} %, residual {100 * worst['residual']:.2f} %. Elastic solve per "
               f"position (meshing included, wall time beside the other worker): median {secs[len(secs) // 2] if secs else float('nan'):.1f} s, "
               f"largest {secs[-1] if secs else float('nan'):.1f} s."]
    return md


def run(mode: str, out: Path) -> dict:
    data = compare_runs(CONFIG, DIRECT_OUT, MASTER, quick=mode != "full")
    if mode == "full" and "missing" not in data:
        data["wear"] = wear_timing()
    return {"title": "Calibration by similarity against the direct 3D FEM", "markdown": _markdown(data),
            "figures": [], "data": data}


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.bench_similarity", description=__doc__.splitlines()[0])
    ap.add_argument("--config", type=Path, default=CONFIG)
    ap.add_argument("--direct", type=Path, default=DIRECT_OUT, help="a direct run's output folder (its cache)")
    ap.add_argument("--direct-keys", type=Path, default=None,
                    help='JSON {"body:y": cache key} of the direct run (when another revision computed it)')
    ap.add_argument("--master", type=Path, default=MASTER, help="the master's FEM cache folder")
    ap.add_argument("--wear", action="store_true", help="also time the wear example with and without recalibration")
    ap.add_argument("--wear-elastic", nargs="*", default=[], choices=["unanchored", "all"],
                    help="with --wear: also time the recalibrated example under these similarity_elastic rules")
    ap.add_argument("--sections", action="store_true",
                    help="also serve the positions with p_y and c_el from their sections' elastic solves")
    ap.add_argument("--json", type=Path, default=None, help="also write the numbers here")
    ap.add_argument("--report", type=Path, default=None, help="write the report (markdown, stamped) here")
    args = ap.parse_args(argv)
    data = compare_runs(args.config, args.direct, args.master, quick=True, keys_file=args.direct_keys,
                        sections=args.sections)
    if args.wear and "missing" not in data:
        data["wear"] = wear_timing(args.config, args.master, tuple(args.wear_elastic))
    if args.json:
        args.json.write_text(json.dumps(data, indent=1) + "\n")
    publish(args.report, "Calibration by similarity against the direct 3D FEM", _markdown(data),
            "python -m benchmarks.bench_similarity", argv)


if __name__ == "__main__":
    main()
