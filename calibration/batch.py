"""Calibrate a folder of profile files with one template configuration (units mm, N, MPa, s).

``calibrate_profiles(paths, template, out_dir)`` calibrates every profile file of ``paths`` (files, folders or
glob patterns) as the template's body of the same kind (rail or wheel: its mate, positions, inclination, material
and the shared settings), each into ``out_dir/<file stem>/``, locally or on the Dask cluster of
``run.scheduler``. With ``run.method = "similarity"`` all of them share one master (``run.master_dir``, default
``out_dir/master``), computed once. The cost of the whole batch is estimated and printed before any FEM runs, and
refused above the limit of :mod:`wrlayer.cost` unless forced. docs/calibration.md, "Many positions and profiles on a cluster".
"""

from __future__ import annotations

import dataclasses
import glob
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

from calibration.cache import fem_entry
from calibration.config import profile_of, resolve_profile
from calibration.cost import calibration_cost
from calibration.pipeline import calibrate
from calibration.run_summary import CalibrationResult
from calibration.settings import CalibrationConfig
from calibration.similarity.master import master_tasks
from calibration.similarity.route import METHOD_DIRECT, route
from calibration.tasks import make_tasks
from meshes.profiles import PROFILE_FILE_SUFFIXES
from wrlayer.cost import CostEstimate, guard
from wrlayer.errors import InputError


def profile_files(paths: Iterable[str | Path]) -> list[Path]:
    """The profile files of ``paths``: files as given, folders' files with a profile suffix, glob patterns
    expanded; sorted, each once. InputError for a path that matches nothing."""
    found: list[Path] = []
    for spec in paths:
        p = Path(spec)
        if p.is_dir():
            hits = [f for f in sorted(p.iterdir()) if f.suffix.lower() in PROFILE_FILE_SUFFIXES]
        elif p.is_file():
            hits = [p]
        else:
            hits = [Path(f) for f in sorted(glob.glob(str(spec))) if Path(f).suffix.lower() in PROFILE_FILE_SUFFIXES]
        if not hits:
            raise InputError(str(spec), f"no profile file (suffixes {', '.join(PROFILE_FILE_SUFFIXES)}) found")
        found += hits
    return sorted(set(found), key=str)


def profile_config(template: CalibrationConfig, path: Path, master_dir: str) -> CalibrationConfig:
    """The template with ``path`` as its body of the file's kind (the other body dropped)."""
    spec, profile = resolve_profile(str(path), str(path), Path("."))
    bodies = [b for b in template.bodies if b.body == profile.body]
    if not bodies:
        raise InputError(str(path), f"is a {profile.body} profile; the template {template.source} has no "
                                    f"[[bodies]] body = '{profile.body}'")
    run = dataclasses.replace(template.run, master_dir=master_dir)
    return dataclasses.replace(template, source=f"{template.source} ({path.name})", run=run,
                               bodies=(dataclasses.replace(bodies[0], profile=spec),))


def batch_cost(configs: dict[Path, CalibrationConfig], out_dir: Path, scheduler: str) -> CostEstimate:
    """Estimate of the FEM positions still to compute over the batch (cached ones cost nothing); a position
    outside a profile's range is InputError naming the file (before any FEM)."""
    todo, master = [], {}
    for path, cfg in configs.items():
        tasks, _, _ = make_tasks(cfg, out_dir / path.stem, False)
        if cfg.run.method == "similarity":
            tasks = [t for t in tasks if route(t, outside=cfg.run.similarity_outside).method == METHOD_DIRECT]
            for b in cfg.bodies:
                for t in master_tasks(cfg, b.material):
                    if not fem_entry(Path(cfg.run.master_dir), t.key).is_file():
                        master[t.key] = t
        todo += [t for t in tasks if not fem_entry(out_dir / path.stem / "cache", t.key).is_file()]
    first = next(iter(configs.values()))
    est = calibration_cost(first, todo + list(master.values()), scheduler)
    return dataclasses.replace(est, what=first.source.split(" (")[0],
                               factors={"profile file(s)": len(configs), **est.factors})


def calibrate_profiles(paths: Iterable[str | Path], template: CalibrationConfig, out_dir: str | Path, *,
                       scheduler: str | None = None, force: bool = False, log: Callable[[str], Any] = print,
                       **kw) -> dict[Path, CalibrationResult]:
    """Calibrate every profile file of ``paths`` (files, folders, globs) with ``template`` into
    ``out_dir/<stem>/``; {file: result}. The batch's cost is printed (``log``) before any FEM runs and refused
    above the limit unless ``force``. ``kw``: passed to :func:`calibration.pipeline.calibrate` (plots,
    show_progress)."""
    out_dir = Path(out_dir)
    files = profile_files(paths)
    stems = [f.stem for f in files]
    if len(set(stems)) != len(stems):
        raise InputError("paths", "two profile files share a file name; their outputs would collide")
    master_dir = template.run.master_dir or str(out_dir / "master")
    configs = {f: profile_config(template, f, master_dir) for f in files}
    for f, cfg in configs.items():
        profile_of(cfg.bodies[0].profile)  # every file readable before any work
    scheduler = scheduler if scheduler is not None else (template.run.scheduler or "")
    est = guard(batch_cost(configs, out_dir, scheduler), force)
    log(f"calibration batch: {est.describe()}")
    return {f: calibrate(cfg, out_dir / f.stem, scheduler=scheduler, force=True, log=log, **kw)
            for f, cfg in configs.items()}


__all__ = ["batch_cost", "calibrate_profiles", "profile_config", "profile_files"]
