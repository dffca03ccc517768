"""The calibration run: positions -> (cached) FEM indentations -> fits -> layer tables, plots and a summary.

Each position's FEM inputs (profile and its file content, position, mating geometry, material, model, mesh and
load settings, the source code of ``calibration``/``meshes``) are hashed (SHA-256); the raw FEM result is cached
in ``OUT/cache/<hash>.json``, so a rerun with nothing changed does no FEM, and changing one position (or the fit
settings only) recomputes only what depends on it. Positions run in parallel in local processes
(``concurrent.futures.ProcessPoolExecutor``, ``run.workers``) or, given a scheduler address, on a Dask cluster.
The fits are cached too, keyed by the FEM result, the fit settings and the fitter's sources. A failed position
is reported with its cause (stderr, ``summary.json``) and listed under ``failed`` in its body's table, which
holds the other positions (the reader refuses to interpolate across a failed position); the computed positions
stay cached, so a rerun computes only what failed. Every file is written atomically.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import dataclasses
import hashlib
import json
import os
import platform
import queue as queue_mod
import sys
import time
from dataclasses import asdict, dataclass
from importlib import metadata
from pathlib import Path
from typing import Any

import numpy as np

from calibration.fit.characteristic_fit import fit_characteristic
from calibration.config import BodySettings, CalibrationConfig
from calibration.hertz.geometry import (HERTZ_B_OVER_R_LIMIT, conformity, fitted_load_N, given_geometry,
                                        local_geometry)
from contact.layer.layer_table import LayerTable
from calibration.cache import load_fit, load_indentation
from calibration.cost import calibration_cost
from wrlayer.atomic_write import atomic_write_text, output_lock
from wrlayer.cost import guard
from wrlayer.errors import InputError, WrLayerError

_ROOT = Path(__file__).resolve().parent.parent
#: Sources that determine a position's FEM result (the cache key includes their content).
_FEM_SOURCES = ("calibration/indentation.py", "calibration/hertz/geometry.py", "calibration/fem/elastoplastic_solver.py",
                "calibration/fem/assembly.py", "calibration/hertz/load.py", "calibration/fem/material.py",
                "calibration/fem/return_mapping.py", "calibration/fem/linear_solvers.py", "meshes/**/*.py")

#: Sources that determine a fit and the table written from it.
_FIT_SOURCES = ("calibration/fit/characteristic_fit.py", "calibration/pipeline.py", "contact/layer/characteristic.py",
                "contact/layer/layer_table.py")


def code_hash(patterns: tuple[str, ...] = _FEM_SOURCES) -> str:
    """SHA-256 of the Python sources matching ``patterns`` (default: those that determine the FEM results)."""
    h = hashlib.sha256()
    for pattern in patterns:
        for f in sorted(_ROOT.glob(pattern)):
            h.update(str(f.relative_to(_ROOT)).encode())
            h.update(f.read_bytes())
    return h.hexdigest()


def code_version() -> str:
    """``git describe`` of the checkout (with -dirty), or "unknown"."""
    import subprocess

    try:
        out = subprocess.run(["git", "describe", "--always", "--dirty"], cwd=_ROOT, capture_output=True,
                             text=True, timeout=10)
        return out.stdout.strip() or "unknown"
    except (OSError, subprocess.SubprocessError):
        return "unknown"


def software_versions() -> dict[str, str]:
    out = {"python": platform.python_version()}
    for pkg in ("numpy", "scipy", "scikit-fem", "gmsh", "wrlayer"):
        try:
            out[pkg] = metadata.version(pkg)
        except metadata.PackageNotFoundError:
            out[pkg] = "not installed"
    return out


def _profile_identity(spec: str) -> str:
    p = Path(spec)
    if p.is_file():
        return f"file:{hashlib.sha256(p.read_bytes()).hexdigest()}"
    return f"builtin:{spec.upper()}"


def _hash(obj: Any) -> str:
    return hashlib.sha256(json.dumps(obj, sort_keys=True, default=str).encode()).hexdigest()


@dataclass(frozen=True)
class PositionTask:
    """Everything a worker needs for one position (plain data, picklable)."""

    body: str
    profile: str
    y_mm: float
    geometry: dict
    material: dict
    model: str
    mesh: dict
    load: dict
    key: str
    fields_dir: str | None
    linear_solver: str = "scipy"
    blas_threads: int = 1


    @property
    def label(self) -> str:
        return f"{self.body} {Path(self.profile).name} y = {self.y_mm:g} mm"


def run_position(task: PositionTask, progress_queue=None) -> dict:
    """Worker: the FEM indentation of one position -> {"ok": True, "indentation": {...}} or {"ok": False,
    "error": message}, with the BLAS/MKL thread pools limited to ``task.blas_threads``. Never raises for a failed
    position."""

    def progress(n):
        if progress_queue is not None:
            progress_queue.put(n)

    try:
        with limited_threads(task.blas_threads):
            return _run_position(task, progress)
    except Exception as err:  # a failed position must not stop the others; report the cause
        return {"ok": False, "error": f"{task.label}: {type(err).__name__}: {err}"}


#: Environment variables of the BLAS/LAPACK/OpenMP thread pools (read when a library is loaded).
THREAD_VARIABLES = ("OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS", "NUMBA_NUM_THREADS")


def blas_threads_per_worker(workers: int) -> int:
    """Threads per calibration worker: the machine's cores shared evenly (at least 1). Measured on 2 cores: one
    3D position takes about 3-6x longer when MKL/OpenBLAS threads oversubscribe the cores (README issue 12;
    benchmarks/bench_calibration.py)."""
    return max(1, (os.cpu_count() or 1) // max(1, int(workers)))


@contextlib.contextmanager
def _thread_environment(n: int):
    """Set THREAD_VARIABLES to ``n`` while worker processes are spawned (they read them before numpy/MKL load;
    threadpoolctl in run_position limits them again), then restore this process's environment."""
    old = {var: os.environ.get(var) for var in THREAD_VARIABLES}
    os.environ.update({var: str(max(1, int(n))) for var in THREAD_VARIABLES})
    try:
        yield
    finally:
        for var, value in old.items():
            if value is None:
                os.environ.pop(var, None)
            else:
                os.environ[var] = value


def limited_threads(n: int):
    """Context limiting the BLAS/MKL/OpenMP pools of this process to ``n`` threads (threadpoolctl; the MKL
    of pypardiso is loaded first so that it is limited too)."""
    from threadpoolctl import threadpool_limits

    import calibration.fem.linear_solvers  # noqa: F401 - loads MKL (pypardiso) before the limit is applied
    return threadpool_limits(limits=max(1, int(n)))


def _run_position(task: PositionTask, progress) -> dict:
    from calibration.hertz.geometry import LocalGeometry
    from calibration.indentation import LoadSettings, MeshSettings, indent
    from calibration.fem.material import J2Material
    from meshes.profiles import get_profile

    try:
        profile = get_profile(task.profile)
        load = dict(task.load)
        load["unload_factors"] = tuple(load["unload_factors"])
        fields_dir = Path(task.fields_dir) if task.fields_dir else None
        res = indent(profile, LocalGeometry(**task.geometry), J2Material(**task.material), task.model,
                     MeshSettings(**task.mesh), LoadSettings(**load), fields_dir, progress,
                     task.linear_solver)
        return {"ok": True, "indentation": res.to_dict()}
    except WrLayerError as err:
        return {"ok": False, "error": f"{task.label}: {err}"}
    except Exception as err:  # a failed position must not stop the others; report the cause
        return {"ok": False, "error": f"{task.label}: {type(err).__name__}: {err}"}


def n_stages(load: dict) -> int:
    """Progress steps of one position: the elastic solve plus one per loading stage."""
    return 1 + len(set(load["unload_factors"]) | {load["max_factor"]})


def position_geometry(b: BodySettings, profile, mate, y: float, reference_load_N: float):
    """(LocalGeometry, warning or None) of one position: the Hertz patch at the reference load, or, at a
    conforming position (b/R_min > HERTZ_B_OVER_R_LIMIT), at the load whose patch has b/R_min at the limit."""
    if b.semi_axes_mm is not None:
        return given_geometry(profile, y, *b.semi_axes_mm), None
    args = (b.material.E_MPa, b.material.poisson, b.rail_cant_rad, b.wheel_radius_mm, b.max_lateral_radius_mm)
    geo = local_geometry(profile, y, mate, reference_load_N, *args)
    ratio = conformity(geo)
    if ratio <= HERTZ_B_OVER_R_LIMIT:
        return geo, None
    load_n = fitted_load_N(geo)
    geo = local_geometry(profile, y, mate, load_n, *args)
    return geo, (f"{b.body} y = {y:g} mm: conforming contact (b/R = {ratio:.2f} > {HERTZ_B_OVER_R_LIMIT:g} at "
                 f"{reference_load_N:g} N: the Hertz half-space load does not fit); calibrated at {load_n:.4g} N "
                 f"(b = {geo.b_mm:.3g} mm, b/R = {conformity(geo):.2f})")


def make_tasks(cfg: CalibrationConfig, out_dir: Path, plots: bool | None = None
               ) -> tuple[list[PositionTask], list[dict], list[dict]]:
    """Tasks for all positions, failures found already while computing the local geometry, and warnings
    (conforming positions, b/R above HERTZ_B_OVER_R_LIMIT, calibrated at a lower load). With ``plots``
    (default: the configuration's) each task writes VTK/PNG fields into OUT/fields/<body>_y<y>mm."""
    plots = cfg.run.plots if plots is None else plots
    from meshes.profiles import get_profile

    code = code_hash()
    tasks, failed, warnings = [], [], []
    for b in cfg.bodies:
        profile = get_profile(b.profile)
        mate = get_profile(b.mate) if b.mate else None
        for y in b.positions_mm:
            try:
                geo, warning = position_geometry(b, profile, mate, y, cfg.reference_load_N)
                if warning:
                    warnings.append({"body": b.body, "y_mm": y, "warning": warning})
            except WrLayerError as err:
                failed.append({"body": b.body, "y_mm": y, "error": str(err)})
                continue
            check_mesh_settings(cfg, b, profile, geo.to_dict())
            fem_inputs = {"profile": _profile_identity(b.profile), "body": b.body, "y_mm": y,
                          "geometry": geo.to_dict(), "material": asdict(b.material), "model": cfg.run.model,
                          "mesh": asdict(cfg.mesh), "load": asdict(cfg.load), "code": code}
            key = _hash(fem_inputs)
            fields = out_dir / "fields" / f"{b.body}_y{y:+08.3f}mm" if plots else None
            tasks.append(PositionTask(b.body, b.profile, float(y), geo.to_dict(), asdict(b.material),
                                      cfg.run.model, asdict(cfg.mesh), asdict(cfg.load), key,
                                      str(fields) if fields else None, cfg.run.linear_solver,
                                      blas_threads_per_worker(cfg.run.workers)))
    return tasks, failed, warnings


def first_slope_N_per_mm3(ind: dict, fit) -> float:
    """The layer's elastic slope S_1 (N/mm^3). The FEM body is homogeneous steel whose elasticity the contact
    solver's half-space already carries, so the layer has no elastic displacement of its own (S_1 -> inf); the
    Prandtl element needs a finite S_1 (eqs. 4-6), taken so that its elastic displacement at the largest
    calibrated pressure is ``fit.elastic_tolerance`` times the FEM inelastic one there (below the FEM's accuracy):
    S_1 = p_max / (t u_pl(p_max)). With ``fit.elastic_fraction`` given, the former S_1 = 1 / (f c_hs)."""
    if fit.elastic_fraction is not None:
        return 1.0 / (fit.elastic_fraction * ind["halfspace_compliance_mm_per_MPa"])
    p = np.asarray(ind["p_MPa"])
    u_pl = np.asarray(ind["u_pl_mm"])
    k = int(np.argmax(p))
    if not u_pl[k] > 0:
        raise InputError("fit.elastic_tolerance", f"no inelastic displacement at the largest pressure "
                                                  f"{p[k]:.6g} MPa: S_1 undefined (raise load.max_factor)")
    return float(p[k] / (fit.elastic_tolerance * u_pl[k]))


#: Mesh arguments checked by meshes.meshing.section_mesh.check_mesh_inputs -> the configuration key they come from.
_MESH_KEYS = {"h_min": "mesh.h_max_mm", "h_max": "mesh.h_max_mm", "depth_mm": "mesh.depth_mm",
              "grading": "mesh.grading", "order": "mesh.order"}


def check_mesh_settings(cfg: CalibrationConfig, b: BodySettings, profile, geometry: dict) -> None:
    """The mesh of one position is possible: h_max_mm >= h_min (= semi-axis / elements_per_semi_axis) and the
    section depth leaves material at the load point. InputError naming the configuration key and the position
    (checked before any FEM runs or any file is written)."""
    from meshes.meshing.section_mesh import DEFAULT_DEPTH_MM, check_mesh_inputs

    m = cfg.mesh
    a, bb = geometry["a_mm"], geometry["b_mm"]
    h_min = min(bb, a if cfg.run.model == "3d" else bb) / m.elements_per_semi_axis
    where = f"{b.body} y = {geometry['y_mm']:g} mm"
    if m.h_max_mm < h_min:
        raise InputError(f"{cfg.source}: mesh.h_max_mm", f"{m.h_max_mm:g} mm is below h_min = {h_min:.3g} mm "
                         f"(semi-axis / mesh.elements_per_semi_axis) at {where}")
    depth = DEFAULT_DEPTH_MM[profile.body] if m.depth_mm is None else m.depth_mm
    try:
        check_mesh_inputs(profile, geometry["y_mm"], h_min, m.h_max_mm, depth, m.order, m.grading)
    except InputError as err:
        key = _MESH_KEYS.get(err.what, f"mesh.{err.what}")
        raise InputError(f"{cfg.source}: {key}", f"{err.problem} ({where})") from None


def fit_position(ind: dict, geometry: dict, cfg: CalibrationConfig, what: str) -> dict:
    """The table entry of one position: fitted characteristic, parameters, errors, geometry and raw FEM data."""
    p = np.asarray(ind["p_MPa"])
    u_pl = np.asarray(ind["u_pl_mm"])
    s1 = first_slope_N_per_mm3(ind, cfg.fit)
    u = p / s1 + u_pl
    fit = fit_characteristic(p, u, cfg.fit.n_segments, s1_N_per_mm3=s1, p2_MPa=ind["first_yield_MPa"], what=what,
                             max_relative_error=cfg.fit.max_relative_error)
    ch = fit.characteristic
    peaks = np.asarray(ind["unload_peaks_MPa"])
    res_fit = ch.residual_displacement(peaks) if peaks.size else np.zeros(0)
    res_err = (res_fit - np.asarray(ind["residual_fem_mm"])).tolist()
    return {"y_mm": geometry["y_mm"], "characteristic": ch.to_dict(), "n_segments": fit.n_segments,
            "k_N_per_mm3": fit.parameters.k_N_per_mm3.tolist(), "T0_MPa": fit.parameters.T0_MPa.tolist(),
            "slopes_N_per_mm3": ch.slopes.tolist(), "p2_MPa": ch.elastic_limit_MPa,
            "first_yield_fem_MPa": ind["first_yield_MPa"],
            "max_error_mm": fit.max_error_mm, "rms_error_mm": fit.rms_error_mm,
            "residual_peaks_MPa": peaks.tolist(), "residual_fit_mm": np.asarray(res_fit).tolist(),
            "residual_fem_mm": ind["residual_fem_mm"], "residual_error_mm": res_err,
            "geometry": geometry,
            "fem": {k: ind[k] for k in ("model", "p_MPa", "u_fem_mm", "u_pl_mm", "fem_elastic_compliance_mm_per_MPa",
                                        "halfspace_compliance_mm_per_MPa", "reverse_plasticity_mm", "n_dofs",
                                        "n_elements", "newton_iterations", "seconds", "output_seconds",
                                        "first_yield_anywhere_MPa")},
            "fem_points": {"p_MPa": p.tolist(), "u_mm": u.tolist()}}


def _header(cfg: CalibrationConfig, b: BodySettings, keys: list[str]) -> dict:
    return {"body": b.body, "profile": Path(b.profile).name if Path(b.profile).is_file() else b.profile,
            "profile_source": b.profile, "mate": b.mate, "model": cfg.run.model,
            "units": {"length": "mm", "pressure": "MPa", "stiffness": "N/mm^3", "force": "N"},
            "material": asdict(b.material), "mesh": asdict(cfg.mesh), "load": asdict(cfg.load),
            "reference_load_N": cfg.reference_load_N, "fit": asdict(cfg.fit),
            "definition": "u(p) = p/S_1 + u_pl(p); u_pl = FEM approach of the load centre towards the material "
                          "point reference_depth_factor * max(a, b) below it, minus the same mesh's elastic part; "
                          "S_1 = p_max / (elastic_tolerance * u_pl(p_max)) (or 1/(elastic_fraction * half-space "
                          "centre compliance) when elastic_fraction is given); p_2 = FEM first yield "
                          "(docs/calibration.md)",
            "software": software_versions(), "code_version": code_version(), "code_hash": code_hash(),
            "config": cfg.source,
            "created_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}


def _same_inputs(json_path: Path, inputs_hash: str) -> bool:
    """True when ``json_path`` is a valid table made from the same inputs AND the CSV beside it is exactly the one
    written from that table (a CSV of another run, e.g. of a second run into the same folder, is rewritten)."""
    csv_path = json_path.with_suffix(".csv")
    if not json_path.is_file() or not csv_path.is_file():
        return False
    try:
        table = LayerTable.read(json_path)
        return table.header.get("inputs_hash") == inputs_hash and csv_path.read_text(encoding="utf-8") == \
            table.to_csv()
    except (WrLayerError, OSError, UnicodeDecodeError):
        return False


def _execute(tasks: list[PositionTask], cfg: CalibrationConfig, scheduler: str | None, show_progress: bool):
    """Run the tasks (local processes, in-process for workers = 1, or Dask); yields (task, result)."""
    from tqdm import tqdm

    from wrlayer.progress import progress_enabled

    if not tasks:
        return
    steps_total = sum(n_stages(t.load) for t in tasks)
    show = progress_enabled(quiet=not show_progress)  # bars on a terminal only: no escape codes in a log
    bar_pos = tqdm(total=len(tasks), desc="positions", unit="pos", disable=not show, position=0)
    bar_steps = tqdm(total=steps_total, desc="load stages", unit="stage", disable=not show, position=1)
    try:
        if scheduler:
            from distributed import Client, as_completed

            try:
                client = Client(scheduler, timeout="20s")
            except (OSError, TimeoutError, ValueError) as err:
                raise InputError("scheduler", f"cannot connect to the Dask scheduler {scheduler!r}: {err}") from None
            with client:
                # a Dask worker runs as many tasks as it has threads: one BLAS thread per task
                futures = {client.submit(run_position, dataclasses.replace(t, blas_threads=1), pure=False): t
                           for t in tasks}
                for fut in as_completed(futures):
                    t = futures[fut]
                    bar_steps.update(n_stages(t.load))
                    bar_pos.update(1)
                    yield t, fut.result()
            return
        if cfg.run.workers == 1 or len(tasks) == 1:
            for t in tasks:
                res = run_position(t, _DirectQueue(bar_steps))
                bar_pos.update(1)
                yield t, res
            return
        import multiprocessing as mp

        ctx = mp.get_context("spawn")
        q = ctx.Queue()  # handed to the workers at start (no Manager process that could outlive a killed run)
        pool = cf.ProcessPoolExecutor(max_workers=min(cfg.run.workers, len(tasks)), mp_context=ctx,
                                      initializer=worker_lifeline, initargs=(os.getpid(), q))
        try:
            with _thread_environment(min(t.blas_threads for t in tasks)):  # the workers start at the submits
                futures = {pool.submit(_run_in_worker, t): t for t in tasks}
            pending = set(futures)
            while pending:
                done, pending = cf.wait(pending, timeout=0.5, return_when=cf.FIRST_COMPLETED)
                _drain(q, bar_steps)
                for fut in done:
                    bar_pos.update(1)
                    yield futures[fut], fut.result()
            _drain(q, bar_steps)
            pool.shutdown(wait=True)
        except BaseException:  # an interrupt or an error: end the workers now, do not wait for their FEM runs
            for proc in list(getattr(pool, "_processes", {}).values()):
                proc.terminate()
            pool.shutdown(wait=False, cancel_futures=True)
            raise
        finally:
            q.close()
            q.join_thread()
    finally:
        bar_steps.close()
        bar_pos.close()


_WORKER_QUEUE = None


def worker_lifeline(parent_pid: int, progress_queue=None) -> None:
    """Initializer of a calibration worker process: the worker ends with its parent.

    On Linux the kernel sends SIGKILL to the worker when the parent dies (``prctl(PR_SET_PDEATHSIG)``); on every
    platform a daemon thread checks once a second that the parent is still there and exits the worker otherwise.
    So a killed run (``kill -9``) leaves no worker computing and holding the caller's pipes open."""
    global _WORKER_QUEUE
    _WORKER_QUEUE = progress_queue
    try:
        import ctypes
        import signal

        libc = ctypes.CDLL("libc.so.6", use_errno=True)
        libc.prctl(1, int(signal.SIGKILL), 0, 0, 0)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass
    if os.getppid() != parent_pid:  # the parent died before the line above took effect
        os._exit(1)

    def watch():
        while True:
            time.sleep(1.0)
            if os.getppid() != parent_pid:
                os._exit(1)

    import threading

    threading.Thread(target=watch, name="parent-watchdog", daemon=True).start()


def _run_in_worker(task: PositionTask) -> dict:
    return run_position(task, _WORKER_QUEUE)


class _DirectQueue:
    def __init__(self, bar):
        self.bar = bar

    def put(self, n):
        self.bar.update(n)


def _drain(q, bar):
    while True:
        try:
            bar.update(q.get_nowait())
        except (queue_mod.Empty, EOFError, OSError):
            return


def run_calibration(cfg: CalibrationConfig, out_dir: str | Path, scheduler: str | None = None,
                    plots: bool | None = None, show_progress: bool = True, log=print, force: bool = False) -> dict:
    """Calibrate all bodies and positions of ``cfg`` into ``out_dir``; returns the summary (also written as
    ``summary.json``). Tables: ``OUT/<body>_layer_table.json`` and ``.csv``.

    Holds a lock on ``out_dir`` (a second run into it is refused); cache entries are validated and invalid ones
    recomputed; the positions to compute are costed first and refused above the limit unless ``force``."""
    out_dir = Path(out_dir)
    if out_dir.exists() and not out_dir.is_dir():
        raise InputError(f"--out {out_dir}", "exists and is not a folder")
    with output_lock(out_dir):
        return _run_calibration(cfg, out_dir, scheduler, plots, show_progress, log, force)


def _run_calibration(cfg, out_dir: Path, scheduler, plots, show_progress, log, force) -> dict:
    t_start = time.perf_counter()
    plots = cfg.run.plots if plots is None else plots
    scheduler = scheduler if scheduler is not None else (cfg.run.scheduler or None)
    tasks, failed, warnings = make_tasks(cfg, out_dir, plots)
    cache = out_dir / "cache"
    results: dict[str, dict] = {}
    todo = []
    for t in tasks:
        f = cache / f"{t.key}.json"
        fields_missing = t.fields_dir is not None and not any(Path(t.fields_dir).rglob("*.vtu"))
        if f.is_file() and not fields_missing:
            entry, why = load_indentation(f)
            if entry is not None:
                results[t.key] = entry
                continue
            log(f"calibration: cache entry {f.name} of {t.label} is invalid ({why}); recomputing it")
        todo.append(t)
    # longest first: the most elongated patches take the most Newton iterations and solves (with the stretched mesh
    # of the default run 8-9.6 s at a/b = 5.8-13.6 against 6.4-7.6 s for round patches, docs/calibration.md), so
    # that no worker is left alone with a long position at the end
    todo.sort(key=lambda t: -max(t.geometry["a_mm"], t.geometry["b_mm"]) / min(t.geometry["a_mm"], t.geometry["b_mm"]))
    n_cached = len(tasks) - len(todo)
    guard(calibration_cost(cfg, todo, scheduler), force)
    if todo:
        log(f"calibration: {len(todo)} position(s) to compute, {n_cached} cached "
            f"({'Dask ' + scheduler if scheduler else f'{min(cfg.run.workers, len(todo))} local worker(s)'})")
    for t, res in _execute(todo, cfg, scheduler, show_progress):
        if res["ok"]:
            atomic_write_text(cache / f"{t.key}.json", json.dumps(res["indentation"]))
            results[t.key] = res["indentation"]
        else:
            failed.append({"body": t.body, "y_mm": t.y_mm, "error": res["error"]})
    summary = {"bodies": {}, "positions_computed": len(todo), "positions_cached": n_cached}
    computed = [results[t.key] for t in todo if t.key in results]
    fem_s = [r["seconds"] for r in computed]
    if fem_s:  # wall time inside the workers, FEM apart from the field output (VTU, PNG)
        summary["fem_seconds"] = {"per_position_min": min(fem_s), "per_position_max": max(fem_s), "total": sum(fem_s),
                                  "output_total": sum(r.get("output_seconds", 0.0) for r in computed)}
    worst = 0.0
    written = []
    fit_code = code_hash(_FIT_SOURCES)
    for b in cfg.bodies:
        entries, keys = [], []
        for t in (t for t in tasks if t.body == b.body):
            if t.key not in results:
                continue
            fit_file = cache / f"fit-{_hash({'fem': t.key, 'fit': asdict(cfg.fit), 'code': fit_code})}.json"
            entry = load_fit(fit_file, t.y_mm)[0] if fit_file.is_file() else None
            if entry is None:
                try:
                    entry = fit_position(results[t.key], t.geometry, cfg, t.label)
                except WrLayerError as err:
                    failed.append({"body": b.body, "y_mm": t.y_mm, "error": str(err)})
                    continue
                atomic_write_text(fit_file, json.dumps(entry))
            notes = [w["warning"] for w in warnings if w["body"] == b.body and w["y_mm"] == t.y_mm]
            entries.append(dict(entry, warnings=notes) if notes else entry)
            keys.append(t.key)
        body_failed = sorted((f for f in failed if f["body"] == b.body), key=lambda f: f["y_mm"])
        info = {"positions": len(b.positions_mm), "calibrated": len(entries), "failed": len(body_failed)}
        if not entries:  # nothing calibrated: no table, and none left from an earlier run
            for stale in (out_dir / f"{b.body}_layer_table.json", out_dir / f"{b.body}_layer_table.csv"):
                stale.unlink(missing_ok=True)
            info["table"] = None
        else:
            header = _header(cfg, b, keys)
            failed_rows = [{"y_mm": f["y_mm"], "error": f["error"]} for f in body_failed]
            header["conforming_limit_b_over_R"] = HERTZ_B_OVER_R_LIMIT
            header["inputs_hash"] = _hash({"keys": keys, "fit": asdict(cfg.fit), "fit_code": fit_code,
                                           "plots": plots, "warnings": [w for w in warnings if w["body"] == b.body]})
            json_path = out_dir / f"{b.body}_layer_table.json"
            unchanged = _same_inputs(json_path, header["inputs_hash"])
            table = LayerTable.read(json_path) if unchanged else LayerTable(header, entries, failed_rows,
                                                                            f"{b.body} layer table")
            if not unchanged:
                paths = table.write(json_path, out_dir / f"{b.body}_layer_table.csv")
                written += [str(p) for p in paths]
            rel = [e["max_error_mm"] / max(e["fem_points"]["u_mm"]) for e in entries]
            info.update(max_fit_error_mm=max(e["max_error_mm"] for e in entries),
                        max_relative_fit_error=max(rel),
                        max_residual_error_mm=max((abs(x) for e in entries for x in e["residual_error_mm"]),
                                                  default=0.0),
                        table=str(out_dir / f"{b.body}_layer_table.json"))
            worst = max(worst, max(rel))
            if plots and not unchanged:
                from calibration.plots import write_body_plots

                written += [str(p) for p in write_body_plots(table, b, out_dir / "plots")]
        summary["bodies"][b.body] = info
    summary.update(failed=failed, warnings=warnings, worst_relative_fit_error=worst,
                   seconds=time.perf_counter() - t_start, files=written)
    atomic_write_text(out_dir / "summary.json", json.dumps(summary, indent=1) + "\n")
    for w in warnings:
        print(f"warning: {w['warning']}", file=sys.stderr)
    for f in failed:
        print(f"error: {f['error']}", file=sys.stderr)
    n_ok = sum(v["calibrated"] for v in summary["bodies"].values())
    log(f"calibration: {n_ok} position(s) calibrated ({len(todo)} computed, {n_cached} cached), "
        f"{len(failed)} failed, {summary['seconds']:.1f} s"
        + ("" if not fem_s else f" (FEM {min(fem_s):.1f}-{max(fem_s):.1f} s per position, field output "
                                f"{summary['fem_seconds']['output_total']:.0f} s in all)")
        + f", worst fit error {100 * worst:.2f} % of max u; "
        + f"tables in {out_dir}" + ("" if not failed else " (failed positions are listed in them and are not "
                                     "interpolated across; a rerun computes only the failed ones)"))
    return summary


__all__ = ["run_calibration", "run_position", "make_tasks", "fit_position", "PositionTask", "code_hash"]
