"""The profile sections' static dents under mesh refinement, at the rolling section gap's peak pressures (units mm,
MPa, s).

The section gap (:mod:`benchmarks.bench_rolling_section_gap`) rolls on the sections at h = a/2, where near first
yield the static dent is 0.82-0.91 of the table's residual r at the same p0. Whether that is the section mesh or
the table is decided here: the static dent of each gap position (same section, track and load path as the gap's
runs, :func:`calibration.rolling.run.static_dents`) at h = a/2, a/3, a/4 and the levels :data:`LEVELS`, each at
the peak pressure p0 = level x the section's p_y on the gap's own a/2 mesh (read from its ``rolling.json``), so
that every mesh is compared with the table at the same p0 in MPa.

``python -m benchmarks.rolling_section_static RUNS OUT [--meshes 2 3 4] [--positions crown tread]``: one JSON
file per (position, mesh) in OUT, written as soon as it is done (a present file is read, not recomputed); RUNS
is the gap's folder (``benchmarks/data/rolling_section_gap``). The gap's report reads OUT with ``--static OUT``
(:func:`study_markdown`, and the gap's FEM groove corrected by :func:`mesh_factor`).
"""

from __future__ import annotations

import argparse
import functools
import json
import time
from dataclasses import asdict, dataclass, replace
from pathlib import Path

import numpy as np

from benchmarks.rolling_section_cases import POSITIONS, ROOT, case_name, section_config
from calibration.fem.assembly import frees_its_meshes
from calibration.rolling.run import build_model, static_dents
from calibration.rolling.section_track import section_track_mesh
from wrlayer.atomic_write import atomic_write_text
from wrlayer.layer_table import LayerTable

#: Levels p0 / p_y(a/2) of the study: the gap's (a point stored with fewer has the first ones).
LEVELS = (1.15, 1.3, 1.5, 1.7, 2.1)
#: Meshes: elements per contact semi-axis (h = a / n).
MESHES = (2.0, 3.0, 4.0)


@dataclass(frozen=True)
class SectionStatic:
    """The static dents of one position on one mesh: ``p0_MPa`` (the gap's peak pressures), ``dent_mm`` (the
    section's static dent), ``table_residual_mm`` (the table's r at the same p0), ``p_y_MPa`` (this mesh's first
    yield), ``n_dofs`` and ``seconds`` (wall time)."""

    position: str
    elements_per_semi_axis: float
    p0_MPa: tuple[float, ...]
    dent_mm: tuple[float, ...]
    table_residual_mm: tuple[float, ...]
    p_y_MPa: float
    n_dofs: int
    seconds: float


def result_file(out: Path, position: str, n: float) -> Path:
    return out / f"{position}_h{n:g}.json"


@frees_its_meshes
def section_static(runs: Path, position: str, n: float) -> SectionStatic:
    """The static dents of ``position`` (a name of :data:`POSITIONS`) on the mesh with ``n`` elements per
    semi-axis, at the gap's peak pressures (its c = 0 run's p_y times :data:`LEVELS`)."""
    name, table_rel, y_mm, _ = next(p for p in POSITIONS if p[0] == position)
    gap = json.loads((runs / case_name(name, 0.0) / "rolling.json").read_text())
    p0s = [level * gap["p_y_MPa"] for level in LEVELS]
    cfg = section_config(table_rel, y_mm, 0.0)
    cfg = replace(cfg, mesh=replace(cfg.mesh, elements_per_semi_axis=n))
    t0 = time.perf_counter()
    model = build_model(cfg, section_track_mesh(cfg))
    curves = static_dents(model, cfg, p0s)
    return SectionStatic(position, n, tuple(p0s), tuple(float(c.dent_mm) for c in curves),
                         table_residuals(position, p0s), float(model.p_y_MPa),
                         int(model.disc.n_dofs), time.perf_counter() - t0)


@functools.lru_cache(maxsize=4)
def _shipped_table(table_rel: str) -> LayerTable:
    """The shipped table ``table_rel`` (relative to the repository), read once per process (a report reads it for
    every study point and row)."""
    return LayerTable.read(ROOT / table_rel)


def table_residuals(position: str, p0s) -> tuple[float, ...]:
    """The shipped table's r (its element's exact residual, mm) of ``position`` at the peaks ``p0s`` (MPa)."""
    _, table_rel, y_mm, _ = next(p for p in POSITIONS if p[0] == position)
    ch = _shipped_table(table_rel).characteristic_at(y_mm)
    return tuple(float(ch.unloading_residual(p)) for p in p0s)


def _stored(path: Path) -> SectionStatic:
    """A study point read from ``path``, its table r taken from the shipped table as it is now (the stored r is
    the table's at the time of the run; the FEM's dents do not depend on it)."""
    data = json.loads(path.read_text())
    point = SectionStatic(**{k: tuple(v) if isinstance(v, list) else v for k, v in data.items()})
    return replace(point, table_residual_mm=table_residuals(point.position, point.p0_MPa))


def read_or_run(runs: Path, out: Path, position: str, n: float) -> SectionStatic:
    """The study's point from OUT, computed and written first when missing."""
    path = result_file(out, position, n)
    if path.is_file():
        return _stored(path)
    res = section_static(runs, position, n)
    out.mkdir(parents=True, exist_ok=True)
    atomic_write_text(path, json.dumps(asdict(res), indent=1))
    return res


def read_study(out: Path) -> dict[tuple[str, float], SectionStatic]:
    """{(position, elements per semi-axis): point} of every study file present in ``out``."""
    study = {}
    for path in sorted(Path(out).glob("*_h*.json")):
        point = _stored(path)
        study[point.position, point.elements_per_semi_axis] = point
    return study


def mesh_factor(study: dict[tuple[str, float], SectionStatic], position: str, level: float) -> float | None:
    """The static dent of ``position`` at ``level`` (one of :data:`LEVELS`) on the finest mesh of the study over
    the one on the gap's a/2 mesh (the factor that corrects the gap's a/2 FEM groove for its mesh, when the groove
    over the static dent is mesh-converged); None without both."""
    meshes = sorted(n for (pos, n) in study if pos == position)
    k = next((i for i, x in enumerate(LEVELS) if abs(x - level) <= 1e-9 * x), None)  # levels read from JSON
    if k is None or 2.0 not in meshes or meshes[-1] == 2.0:
        return None
    if k >= min(len(study[position, m].dent_mm) for m in (2.0, meshes[-1])):
        return None
    return study[position, meshes[-1]].dent_mm[k] / study[position, 2.0].dent_mm[k]


def table_fem_residual(position: str, p0_MPa: float) -> float:
    """The residual dent of the table's own FEM at the peak pressure p0 (mm): its entry's residual_fem_mm
    interpolated over its unloading peaks (the table's r is the fitted element's, within the fit's error)."""
    _, table_rel, y_mm, _ = next(p for p in POSITIONS if p[0] == position)
    entry = next(e for e in _shipped_table(table_rel).positions if float(e["y_mm"]) == y_mm)
    return float(np.interp(p0_MPa, entry["residual_peaks_MPa"], entry["residual_fem_mm"]))


def study_markdown(study: dict[tuple[str, float], SectionStatic]) -> str:
    """One row per position and level: the table's fitted r over its own FEM residual, and the section's static
    dent over the table's r at each mesh."""
    meshes = sorted({n for _, n in study})
    lines = ["| position | p0 / p_y(a/2) | p0 (MPa) | table r / table FEM residual | "
             + " | ".join(f"dent / r at a/{n:g}" for n in meshes) + " | dofs | wall time (s) |",
             "|---|---|---|---|" + "---|" * len(meshes) + "---|---|"]
    for name, *_ in POSITIONS:
        points = [study.get((name, n)) for n in meshes]
        if not any(points):
            continue
        for k, level in enumerate(LEVELS):
            if k >= max(len(p.dent_mm) for p in points if p):
                break
            points_k = [p if p and k < len(p.dent_mm) else None for p in points]
            first = next(p for p in points_k if p)
            p0 = first.p0_MPa[k]
            fit_over_fem = first.table_residual_mm[k] / table_fem_residual(name, p0)
            cells = [f"{p.dent_mm[k] / p.table_residual_mm[k]:.3f}" if p else "—" for p in points_k]
            lines.append(f"| {name} | {level:g} | {p0:.0f} | {fit_over_fem:.3f} | " + " | ".join(cells) + " | "
                         + ", ".join(str(p.n_dofs) for p in points if p) + " | "
                         + ", ".join(f"{p.seconds:.0f}" for p in points if p) + " |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.rolling_section_static", description=__doc__.splitlines()[0])
    ap.add_argument("runs", type=Path, help="the section gap's runs (benchmarks/data/rolling_section_gap)")
    ap.add_argument("out", type=Path, help="where the study's JSON files go")
    ap.add_argument("--meshes", type=float, nargs="+", default=list(MESHES))
    ap.add_argument("--positions", nargs="+", default=[p[0] for p in POSITIONS])
    args = ap.parse_args(argv)
    for position in args.positions:
        for n in args.meshes:
            res = read_or_run(args.runs, args.out, position, n)
            print(f"{position} h = a/{n:g}: dent / table r = "
                  + ", ".join(f"{d / r:.3f}" for d, r in zip(res.dent_mm, res.table_residual_mm))
                  + f" ({res.n_dofs} dofs, {res.seconds:.0f} s)", flush=True)


if __name__ == "__main__":
    main()
