"""The calibration run: positions -> (cached) FEM indentations -> fits -> layer tables, plots and a summary.

The FEM result of each position is cached in ``OUT/cache/<key>.json`` under the hash of its inputs
(:mod:`calibration.tasks`), so a rerun with nothing changed does no FEM, and changing one position (or the fit
settings only) recomputes only what depends on it. Positions run with :class:`wrlayer.runner.Runner`: in-process,
in local worker processes (``run.workers``) or, given a scheduler address, on a Dask cluster. The fits are cached
too, keyed by the FEM result, the fit settings and the fitter's sources. A failed position is reported with its
cause (stderr, ``summary.json``) and listed under ``failed`` in its body's table, which holds the other positions
(the reader refuses to interpolate across a failed position); the computed positions stay cached, so a rerun
computes only what failed. Every file is written atomically.
"""

from __future__ import annotations

import json
import math
import sys
import time
from collections.abc import Callable, Mapping
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any

from calibration.cache import entry_exists, fem_entry, fit_entry, load_fit, load_indentation, save_entry
from calibration.cost import calibration_cost
from calibration.position_fit import fit_position
from calibration.results import IndentationResult, PositionFit
from calibration.run_summary import CalibrationResult, FemSeconds, SimilaritySummary
from calibration.settings import CalibrationConfig
from calibration.similarity.anchor import DirectReference, anchor, anchored, applies, configured_references
from calibration.similarity.elastic import (SectionElastic, needs_solve, section_elastics, section_reference,
                                            with_section)
from calibration.similarity.master import MasterCurves, master_key, master_tasks, stored_master
from calibration.similarity.route import (METHOD_DIRECT, METHOD_SIMILARITY, SIMILARITY_SOURCES, Route, route,
                                          similarity_task, task_indentation)
from calibration.tables import FIT_SOURCES, BodySummary, write_body_table
# make_tasks, position_geometry and limited_threads are also re-exported (__all__) for the benchmarks and input
# tests that import them from this module
from calibration.tasks import (PositionNote, PositionTask, code_hash, inputs_hash, make_tasks, position_geometry,
                               run_position)
from wrlayer.atomic_write import atomic_write_text, output_lock
from wrlayer.cost import guard
from wrlayer.errors import InputError, WrLayerError, record_kept, termination_deferred
from wrlayer.progress import ProgressBar
from wrlayer.runner import Runner, limited_threads

#: The run's record; :data:`SUMMARY_CACHED` is written instead by a run that computed nothing (all cached).
SUMMARY = "summary.json"
SUMMARY_CACHED = "summary_cached.json"


@dataclass(frozen=True)
class ComputedPositions:
    """What the FEM step returns: ``results`` {cache key: FEM result} of the positions computed (and cached),
    ``failed`` the positions whose FEM failed, with the cause."""

    results: dict[str, IndentationResult]
    failed: tuple[PositionNote, ...]


@dataclass(frozen=True)
class FittedPosition:
    """What the fit step returns for one position: its fit, or None and the ``failure`` that stopped it."""

    fit: PositionFit | None
    failure: PositionNote | None = None


@dataclass(frozen=True)
class WrittenTables:
    """What the table step returns: ``bodies`` {body: summary}, the ``files`` written and the positions whose fit
    ``failed`` (listed in their tables)."""

    bodies: dict[str, BodySummary]
    files: tuple[str, ...]
    failed: tuple[PositionNote, ...]


@dataclass(frozen=True)
class Anchoring:
    """The direct FEM ``references`` {(body, y): DirectReference} of a similarity run and whether a position whose
    patch left its reference's is computed by the direct FEM (``reanchor``) or served by the master alone."""

    references: Mapping[tuple[str, float], DirectReference]
    reanchor: bool = False


@dataclass(frozen=True)
class SimilarityRouting:
    """What the similarity step returns: the ``tasks`` (the served ones re-keyed by their similarity key), the
    ``results`` {key: characteristic from the master} of the served positions, every position's ``routes``
    {key: Route}, the ``warnings`` it raised (failed master points, positions served from outside the master's
    domain), the route's ``summary`` and the ``section_references`` {(body, y): reference} of the positions
    served with their section's elastic solve (:func:`calibration.similarity.elastic.section_reference`)."""

    tasks: tuple[PositionTask, ...]
    results: dict[str, IndentationResult]
    routes: dict[str, Route]
    warnings: tuple[PositionNote, ...]
    summary: SimilaritySummary
    section_references: dict[tuple[str, float], DirectReference]


def calibrate(config: CalibrationConfig, out_dir: str | Path, *, scheduler: str | None = None,
              plots: bool | None = None, show_progress: bool = True, log: Callable[[str], Any] = print,
              force: bool = False, anchors: Mapping[tuple[str, float], DirectReference] | None = None,
              reanchor: bool = False) -> CalibrationResult:
    """Calibrate all bodies and positions of ``config`` into ``out_dir``: tables ``OUT/<body>_layer_table.json``
    and ``.csv``, ``summary.json``, the cache, and with ``plots`` (default: ``config.run.plots``) pictures and
    fields. ``scheduler``: a Dask scheduler address (default: ``config.run.scheduler``; "" or None there: local).

    Holds a lock on ``out_dir`` (a second run into it is refused); unusable cache entries are recomputed; the
    positions to compute are costed first and refused above the limit unless ``force`` (InputError). A failed
    position does not raise: it is in ``result.failed`` and in its body's table. ``anchors`` {(body, y): direct
    FEM of a reference profile}, added to those of the bodies' ``anchor_table``: under ``run.method =
    "similarity"`` a served position with an anchor takes the master's value corrected by the master's error at
    the reference (:mod:`calibration.similarity.anchor`) while its patch is like the reference's; with
    ``reanchor`` a position whose patch is not is computed by the direct FEM instead (its entry then anchors the
    next recalibration), else served by the master alone."""
    out_dir = Path(out_dir)
    if out_dir.exists() and not out_dir.is_dir():
        raise InputError(f"--out {out_dir}", "exists and is not a folder")
    with output_lock(out_dir):
        references = {**configured_references(config.bodies), **(anchors or {})}  # those given here win
        return _run(config, out_dir, scheduler, plots, show_progress, log, force, Anchoring(references, reanchor))


def run_calibration(cfg: CalibrationConfig, out_dir: str | Path, scheduler: str | None = None,
                    plots: bool | None = None, show_progress: bool = True, log=print, force: bool = False) -> dict:
    """:func:`calibrate`, returning the summary as written to ``summary.json``."""
    return calibrate(cfg, out_dir, scheduler=scheduler, plots=plots, show_progress=show_progress, log=log,
                     force=force).to_dict()


def _split_cached(tasks: list[PositionTask], cache: Path, log) -> tuple[dict[str, IndentationResult],
                                                                         list[PositionTask]]:
    """({key: cached FEM result}, tasks to compute); a task whose fields are wanted but missing is computed."""
    results, todo = {}, []
    for t in tasks:
        f = fem_entry(cache, t.key)
        fields_missing = t.fields_dir is not None and not any(Path(t.fields_dir).rglob("*.vtu"))
        if entry_exists(f) and not fields_missing:  # a FIFO or a link loop too: reported, recomputed
            entry, why = load_indentation(f)
            if entry is not None:
                results[t.key] = entry
                continue
            log(f"calibration: cache entry {f.name} of {t.label} is invalid ({why}); recomputing it")
        todo.append(t)
    return results, todo


def _compute(todo: list[PositionTask], cfg: CalibrationConfig, scheduler: str, cache: Path,
             show_progress: bool) -> ComputedPositions:
    """Run the FEM of ``todo``; each result is cached as it arrives."""
    results: dict[str, IndentationResult] = {}
    failed: list[PositionNote] = []
    if not todo:
        return ComputedPositions(results, ())
    quiet = not show_progress
    saved = 0
    with ProgressBar(len(todo), "positions", "pos", quiet, 0) as bar_pos, \
            ProgressBar(sum(t.stages for t in todo), "load stages", "stage", quiet, 1, lines=False) as bar_steps, \
            Runner(cfg.run.workers, scheduler) as runner:
        for k, outcome in runner.imap(run_position, todo, on_progress=bar_steps.update):
            t = todo[k]
            if not runner.streams_progress:
                bar_steps.update(t.stages)
            bar_pos.update(1)
            if outcome.indentation is not None:
                with termination_deferred():  # cached and said so (the SIGTERM line), or neither
                    save_entry(fem_entry(cache, t.key), outcome.indentation)
                    saved += 1
                    record_kept(f"{saved} computed position(s) cached in {cache} (a rerun reuses them)")
                results[t.key] = outcome.indentation
            else:
                failed.append(PositionNote(t.body, t.y_mm, outcome.error))
    return ComputedPositions(results, tuple(failed))


def _fit(t: PositionTask, ind: IndentationResult, cfg: CalibrationConfig, cache: Path, fit_code: str,
         log) -> FittedPosition:
    """The (cached) fit of one position, or the error that stopped it."""
    f = fit_entry(cache, inputs_hash({"fem": t.key, "fit": asdict(cfg.fit), "code": fit_code}))
    fit, why = load_fit(f, t.y_mm) if entry_exists(f) else (None, None)
    if why:
        log(f"calibration: cache entry {f.name} of {t.label} is invalid ({why}); recomputing it")
    if fit is None:
        try:
            fit = fit_position(ind, t.geometry, cfg.fit, t.label)
        except WrLayerError as err:
            return FittedPosition(None, PositionNote(t.body, t.y_mm, str(err)))
        save_entry(f, fit)
    return FittedPosition(fit)


def _run(cfg: CalibrationConfig, out_dir: Path, scheduler, plots, show_progress, log, force,
         anchoring: Anchoring) -> CalibrationResult:
    t_start = time.perf_counter()
    plots = cfg.run.plots if plots is None else plots
    scheduler = scheduler if scheduler is not None else (cfg.run.scheduler or "")
    tasks, failed, warnings = make_tasks(cfg, out_dir, plots)
    failed, warnings = tuple(failed), tuple(warnings)
    cache = out_dir / "cache"
    routing = _similarity(cfg, tasks, out_dir, scheduler, show_progress, log, force, anchoring) \
        if cfg.run.method == "similarity" else None
    if routing is not None:
        tasks, warnings = list(routing.tasks), warnings + routing.warnings
    served = routing.results if routing is not None else {}
    cached, todo = _split_cached([t for t in tasks if t.key not in served], cache, log)
    # longest first: the most elongated patches take the most Newton iterations and solves (with the stretched mesh
    # of the default run 8-9.6 s at a/b = 5.8-13.6 against 6.4-7.6 s for round patches, docs/calibration.md), so
    # that no worker is left alone with a long position at the end
    todo.sort(key=lambda t: -t.aspect)
    n_cached = len(cached)
    estimate = guard(calibration_cost(cfg, todo, scheduler), force)
    if todo:
        log(f"calibration ({cfg.run.model.upper()} model): {len(todo)} position(s) to compute, {n_cached} cached "
            f"({'Dask ' + scheduler if scheduler else f'{min(cfg.run.workers, len(todo))} local worker(s)'}; "
            f"estimated {estimate.describe()})")
    fem = _compute(todo, cfg, scheduler, cache, show_progress)
    results = {**served, **cached, **fem.results}
    failed += fem.failed
    computed = [results[t.key] for t in todo if t.key in results]
    fem_s = [r.seconds for r in computed]
    fem_seconds = None if not fem_s else FemSeconds(min(fem_s), max(fem_s), sum(fem_s),
                                                    sum(r.output_seconds for r in computed))
    tables = _tables(cfg, tasks, results, routing.routes if routing is not None else {}, failed, warnings, plots,
                     out_dir, log)
    bodies = tables.bodies
    worst = max([s.max_relative_fit_error for s in bodies.values() if s.table is not None], default=0.0)
    result = CalibrationResult(bodies, len(todo), n_cached, fem_seconds, failed + tables.failed, warnings, worst,
                               time.perf_counter() - t_start, tables.files,
                               routing.summary if routing is not None else None,
                               routing.section_references if routing is not None else {})
    # a run that computed nothing (all cached) writes its own record beside the one of the run that computed:
    # the cold run's times and counts stay where the benchmark reads them
    name = SUMMARY_CACHED if not todo and (out_dir / SUMMARY).is_file() else SUMMARY
    with termination_deferred():
        atomic_write_text(out_dir / name, json.dumps(result.to_dict(), indent=1) + "\n")
        record_kept(f"the tables and {name} are in {out_dir}")
    _report(result, cfg.run.model, out_dir, log)
    return result


def _tables(cfg: CalibrationConfig, tasks: list[PositionTask], results: dict[str, IndentationResult],
            routes: dict[str, Route], failed: tuple[PositionNote, ...], warnings: tuple[PositionNote, ...],
            plots: bool, out_dir: Path, log) -> WrittenTables:
    """Fit every position with a result and write each body's table (listing ``failed`` and the positions whose
    fit fails)."""
    fit_code = code_hash(FIT_SOURCES)
    cache = out_dir / "cache"
    bodies, written, fit_failed = {}, [], []
    body_routes = {k: (r.method, r.note) for k, r in routes.items()}
    for b in cfg.bodies:
        fits = []
        for t in (t for t in tasks if t.body == b.body and t.key in results):
            fitted = _fit(t, results[t.key], cfg, cache, fit_code, log)
            if fitted.fit is not None:
                fits.append((t.key, fitted.fit))
            else:
                fit_failed.append(fitted.failure)
        bodies[b.body], _, files = write_body_table(cfg, b, fits, list(failed) + fit_failed, list(warnings),
                                                    fit_code, plots, out_dir, body_routes)
        written += [str(p) for p in files]
    return WrittenTables(bodies, tuple(written), tuple(fit_failed))


def _similarity(cfg: CalibrationConfig, tasks: list[PositionTask], out_dir: Path, scheduler: str, show_progress,
                log, force: bool, anchoring: Anchoring) -> SimilarityRouting:
    """The similarity route: compute (or read) each material's master, then give every position it serves its
    characteristic from the master (keyed by its similarity key) and every position its route."""
    if cfg.run.model != "3d":
        raise InputError(f"{cfg.source}: run.method", "'similarity' needs run.model = '3d'")
    mcache = Path(cfg.run.master_dir) if cfg.run.master_dir else out_dir / "cache"
    materials = list(dict.fromkeys(b.material for b in cfg.bodies))
    mtasks = {m: master_tasks(cfg, m) for m in materials}
    # a master written before (same FEM task keys, this format version) is read whole; any other is rebuilt
    stored = {m: stored_master(mcache, master_key(mtasks[m])) for m in materials}
    mresults, mtodo = _split_cached([t for m in materials if stored[m] is None for t in mtasks[m]], mcache, log)
    n_mcached = len(mresults) + sum(len(mtasks[m]) for m in materials if stored[m] is not None)
    outside = cfg.run.similarity_outside
    direct = [t for t in tasks if route(t, outside=outside).method == METHOD_DIRECT]
    estimate = guard(calibration_cost(cfg, mtodo + _split_cached(direct, out_dir / "cache", lambda *a: None)[1],
                                      scheduler), force)
    if mtodo:
        log(f"calibration (3D model, similarity): {len(mtodo)} master position(s) to compute "
            f"({len(mresults)} cached) in {mcache}; with the direct positions estimated {estimate.describe()}")
    computed = _compute(mtodo, cfg, scheduler, mcache, show_progress)
    mresults.update(computed.results)
    mfailed = computed.failed
    warnings = [PositionNote("master", n.y_mm, f"similarity master: {n.message}") for n in mfailed]
    results: dict[str, IndentationResult] = {}
    routes: dict[str, Route] = {}
    sections: dict[tuple[str, float], DirectReference] = {}
    masters = {m: stored[m] or MasterCurves.build(cfg, m, mtasks[m], mresults) for m in materials}
    for m, mc in masters.items():
        if mc is not None and stored[m] is None and not mfailed:  # a master with failed points is not kept
            mc.write(mcache)
    files = tuple(str(mc.write(out_dir)) for mc in masters.values() if mc is not None)
    out, code = [], code_hash(SIMILARITY_SOURCES)
    t0 = time.perf_counter()
    first = {t.key: route(t, (m.aspect_range, m.convexity_range), outside) if (m := masters[t.material]) else
             Route(METHOD_DIRECT, "the similarity master of its material failed") for t in tasks}
    routing_s = time.perf_counter() - t0
    elastics = _section_elastics(cfg, tasks, first, anchoring, out_dir, scheduler, log, warnings)
    t0 = time.perf_counter()  # the elastic solves are not the route's cost per position
    for t in tasks:
        master, r = masters[t.material], first[t.key]
        if r.method == METHOD_SIMILARITY:
            elastic = elastics.get(t.key)
            t, r, served, warning = _served(t, master, r, anchoring, code, elastic)
            if served is not None:
                results[t.key] = served
                if elastic is not None:
                    sections[t.body, t.y_mm] = section_reference(t, served, r.convexity, r.plastic_convexity,
                                                                 str(out_dir))
            if warning:
                warnings.append(PositionNote(t.body, t.y_mm, warning))
        routes[t.key] = r
        out.append(t)
    per_position = (routing_s + time.perf_counter() - t0) / max(len(tasks), 1)
    for t in out:
        if routes[t.key].method == METHOD_DIRECT:
            log(f"calibration: {t.body} y = {t.y_mm:g} mm by the direct FEM: {routes[t.key].note}")
    served = sum(r.method == METHOD_SIMILARITY for r in routes.values())
    summary = SimilaritySummary(served, len(tasks) - served, files, len(mtodo) - len(mfailed), n_mcached,
                                sum(mc.fem_seconds for mc in masters.values() if mc), per_position)
    return SimilarityRouting(tuple(out), results, routes, tuple(warnings), summary, sections)


def _section_elastics(cfg: CalibrationConfig, tasks: list[PositionTask], routes: dict[str, Route],
                      anchoring: Anchoring, out_dir: Path, scheduler: str, log,
                      warnings: list[PositionNote]) -> dict[str, SectionElastic]:
    """{task key: its section's elastic solution} of the positions the masters serve (``routes``: {task key:
    Route}), as ``run.similarity_elastic`` says ({} with "none"; with "all" those without a reference within
    :data:`calibration.similarity.elastic.REUSE_LIMITS`; with "unanchored" only those without an anchor that
    applies); a failed solve leaves its position to the master alone, in ``warnings``."""
    rule = cfg.run.similarity_elastic
    if rule == "none":
        return {}
    served = [t for t in tasks if routes[t.key].method == METHOD_SIMILARITY
              and (needs_solve(anchoring.references.get((t.body, t.y_mm)), t, routes[t.key].convexity)
                   if rule == "all" else _anchor_misses(t, routes[t.key], anchoring))]
    done, failed = section_elastics(served, out_dir / "cache", cfg.run.workers, scheduler, log)
    warnings.extend(PositionNote(t.body, t.y_mm, f"similarity: the section's elastic solve failed ({failed[t.key]}); "
                                                 "p_y and c_el from the master") for t in served if t.key in failed)
    return done


def _anchor_misses(t: PositionTask, r: Route, anchoring: Anchoring) -> str:
    """Why the position's reference (a direct FEM, or an earlier section solve) does not anchor it ("no direct
    reference", or the patch that left the reference's, :func:`calibration.similarity.anchor.applies`); "" when it
    does."""
    ref = anchoring.references.get((t.body, t.y_mm))
    return "no direct reference" if ref is None else applies(ref, t.geometry.a_mm, t.geometry.b_mm, r.convexity)


def _served(t: PositionTask, master: MasterCurves, r: Route, anchoring: Anchoring, code: str,
            elastic: SectionElastic | None = None) -> tuple[PositionTask, Route, IndentationResult | None, str]:
    """A position the master serves: (its task keyed by the similarity, its route with the anchoring noted, its
    characteristic, a warning or ""); with ``anchoring.reanchor`` a position whose patch left its reference's is
    routed to the direct FEM instead (task unchanged, no characteristic). ``elastic``: its section's elastic
    solution, which gives p_y and c_el (:mod:`calibration.similarity.elastic`)."""
    ref = anchoring.references.get((t.body, t.y_mm))
    why_not = _anchor_misses(t, r, anchoring) if ref is not None else ""
    if why_not and anchoring.reanchor:  # the patch left its anchor's: its own FEM, the next anchor
        return t, Route(METHOD_DIRECT, f"{why_not}; computed by the direct FEM (the position's new anchor)",
                        r.convexity), None, ""
    ref = None if why_not else ref
    correction = anchor(master, ref) if ref is not None else None
    if elastic is not None:
        correction = with_section(correction, master, t, r.convexity, elastic)
    t = similarity_task(t, master, r.convexity, code, ref, elastic, r.plastic_convexity)
    served = task_indentation(master, t, r.convexity, r.plastic_convexity)
    # outside the master's domain, served from its nearest point: said in the entry's warnings
    warning = f"similarity: {r.note}" if r.note else ""
    if correction is not None:
        served = anchored(served, correction, math.sqrt(t.geometry.a_mm * t.geometry.b_mm))
    note = f"anchored to the {ref.kind} of {ref.source}" if ref is not None else why_not
    section = "p_y and c_el from the section's elastic solve" if elastic is not None else ""
    return t, replace(r, note="; ".join(n for n in (r.note, note, section) if n)), served, warning


def _report(result: CalibrationResult, model: str, out_dir: Path, log) -> None:
    """Warnings and errors on stderr, one summary line to ``log``."""
    for w in result.warnings:
        print(f"warning: {w.message}", file=sys.stderr)
    for f in result.failed:
        print(f"error: {f.message}", file=sys.stderr)
    n_ok = sum(v.calibrated for v in result.bodies.values())
    fem = result.fem_seconds
    log(f"calibration ({model.upper()} model): {n_ok} position(s) calibrated ({result.positions_computed} computed, "
        f"{result.positions_cached} cached), {len(result.failed)} failed, {result.seconds:.1f} s"
        + ("" if fem is None else f" (FEM {fem.per_position_min:.1f}-{fem.per_position_max:.1f} s per position, "
                                  f"field output {fem.output_total:.0f} s in all)")
        + f", worst fit error {100 * result.worst_relative_fit_error:.2f} % of max u; "
        + f"tables in {out_dir}" + ("" if result.ok else " (failed positions are listed in them and are not "
                                    "interpolated across; a rerun computes only the failed ones)"))


__all__ = ["calibrate", "limited_threads", "make_tasks", "position_geometry",
           "run_calibration"]
