"""The elastic solve of a served position's own section, which puts the body around the patch into a similarity
result (units mm, MPa, s).

The master's first-yield pressure p_y is 0.2-1.6 % off the direct FEM where the section is not the master's arc
block (the rail's gauge side, the wheel's rim; ``docs/validation/similarity.md``), and u_pl at equal p0 moves
about ten times as much, because the load levels are multiples of p_y. p_y and the elastic centre compliance c_el
are properties of the elastic solution alone: one elastic solve of the position's own mesh (the direct FEM's mesh,
load and first-yield search, :func:`calibration.indentation.local_first_yield_MPa`) gives them exactly as the
direct FEM does, for the cost of meshing, one factorisation and one solve (about a quarter of a direct position).
The master then gives the plastic part at equal p0 / p_y:

    p_y = p_y,section,   c_el = c_el,section,   u_pl(q p_y) = L U_m(q),   residual(f p_y) = L R_m(f)

(m: the master at the position's semi-axes and convexity, :mod:`calibration.similarity.route`). A position with
a direct reference (:mod:`calibration.similarity.anchor`) keeps the reference's correction of U and R and takes
p_y and c_el from its own section.

Under ``similarity_elastic = "all"`` a solve is repeated only where the patch moved: a position whose patch is within
:data:`REUSE_LIMITS` of its reference's (a direct FEM, or the section solve of an earlier recalibration,
:func:`section_reference`) keeps the reference's p_y / master and c_el / master ratios. Measured on the wear
example's profiles (initial, after each step, after 3000 km and that wear x5; every pair, 27 positions;
``docs/validation/similarity-reuse.md``): within these limits the p_y ratio moves by 0.06 % (median; 90 % of the
pairs within 0.13 %, largest 0.28 %), less than a new solve of the same patch on another profile scatters (0.07 %,
0.33 %, 0.58 %: the mesh follows the profile's points); beyond the anchor's limits by 0.58 % (1.23 %, 1.73 %), up
to ten times that in u_pl at equal p0. Wider limits (b/(2R) 0.015, a/b x1.4, sqrt(ab) x1.15) saved 5 of the wear
example's 12 solves but lost 3 positions within 2 % after that wear x5 (``docs/validation/similarity-worn.md``);
with these, both worn cases count as many as a solve at every position.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterable
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from calibration.cache import entry_exists, read_json_entry, save_entry
from calibration.config import profile_of
from calibration.fem.material import J2Material
from calibration.indentation import elastic_response, position_model
from calibration.results import IndentationResult
from calibration.similarity.anchor import Anchor, DirectReference, PatchLimits, patch_moved
from calibration.similarity.master import MasterCurves
from calibration.similarity.route import similar_indentation
from calibration.tasks import PositionTask, inputs_hash, task_failure
from wrlayer import validate
from wrlayer.errors import InputError
from wrlayer.runner import Runner


#: The patch whose reference's p_y and c_el ratios stand for a solve of its own (see the module).
REUSE_LIMITS = PatchLimits(convexity=0.01, aspect_factor=1.2, size_factor=1.1)


def needs_solve(ref: DirectReference | None, task: PositionTask, convexity: float) -> str:
    """Why ``task`` (on a surface of convexity ``convexity``, -) needs its own section's elastic solve under
    ``similarity_elastic = "all"``: no reference, or a patch beyond :data:`REUSE_LIMITS` of the reference's; ""
    when the reference's ratios stand for it."""
    if ref is None:
        return "no reference"
    moved = patch_moved(ref, task.geometry.a_mm, task.geometry.b_mm, convexity, REUSE_LIMITS)
    return f"beyond the reuse limits: {moved}" if moved else ""


@dataclass(frozen=True)
class SectionElastic:
    """The elastic solution of one position's own section at p0 = 1 MPa.

    Attributes
    ----------
    p_y_MPa : float
        First-yield pressure near the load centre (MPa), as the direct FEM finds it.
    compliance_mm_per_MPa : float
        Elastic centre compliance against the layer displacement's reference (mm/MPa), as the direct FEM's c_el.
    n_dofs : int
        Degrees of freedom of the section's mesh (-).
    seconds : float
        Wall time of the solve, meshing included (s).
    """

    p_y_MPa: float
    compliance_mm_per_MPa: float
    n_dofs: int
    seconds: float

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    @classmethod
    def from_dict(cls, data: Any, what: str = "section elastic") -> SectionElastic:
        """Validate and build (InputError naming the field)."""
        validate.table(data, what)
        validate.check_known(data, list(cls.__dataclass_fields__), what)
        values = {}
        for name in ("p_y_MPa", "compliance_mm_per_MPa", "seconds"):
            value = data.get(name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) \
                    or value < 0 or (value == 0 and name != "seconds"):
                raise InputError(validate.join(what, name), f"must be a positive finite number, got {value!r}")
            values[name] = float(value)
        n = data.get("n_dofs")
        if isinstance(n, bool) or not isinstance(n, int) or n < 0:
            raise InputError(validate.join(what, "n_dofs"), f"must be a non-negative integer, got {n!r}")
        return cls(n_dofs=n, **values)


def section_elastic(task: PositionTask) -> SectionElastic:
    """The elastic solve of ``task``'s own 3D model (:func:`calibration.indentation.elastic_response` on the mesh,
    Dirichlet map and probes the direct FEM builds). Raises InputError (mesh, degenerate solution) or
    ConvergenceError."""
    t0 = time.perf_counter()
    pm = position_model(profile_of(task.profile), task.geometry, task.model, task.mesh)
    el = elastic_response(pm, J2Material(**asdict(task.material)), task.geometry, task.mesh, task.linear_solver)
    return SectionElastic(float(el.p_y_MPa), float(el.compliance_mm_per_MPa["ref"]), int(pm.disc.n_dofs),
                          time.perf_counter() - t0)


@dataclass(frozen=True)
class ElasticOutcome:
    """What the worker returns for one position: its section's elastic solution, or the error that stopped it."""

    key: str
    elastic: SectionElastic | None
    error: str | None = None


def run_section_elastic(task: PositionTask) -> ElasticOutcome:
    """Worker: :func:`section_elastic` of one position; never raises (the error names the position)."""
    try:
        return ElasticOutcome(task.key, section_elastic(task))
    except Exception as err:  # one failed section must not stop the others
        return ElasticOutcome(task.key, None, task_failure(task, err))


def elastic_entry(cache: Path, task: PositionTask) -> Path:
    """The cache file of ``task``'s section elastic solution (keyed by the task's FEM inputs)."""
    return cache / f"elastic-{inputs_hash({'section_elastic': task.key})}.json"


def section_elastics(tasks: Iterable[PositionTask], cache: Path, workers: int, scheduler: str,
                     log: Callable[[str], Any]) -> tuple[dict[str, SectionElastic], dict[str, str]]:
    """({task key: elastic solution}, {task key: why it failed}) of ``tasks``: read from ``cache`` or solved on
    ``workers`` local processes (or the Dask ``scheduler``), each cached as it arrives; an unusable entry is
    reported and solved again."""
    done: dict[str, SectionElastic] = {}
    todo = []
    for t in tasks:
        f = elastic_entry(cache, t)
        if entry_exists(f):
            data, why = read_json_entry(f)
            try:
                done[t.key] = SectionElastic.from_dict(data, f.name) if why is None else None
            except InputError as err:
                why = str(err)
            if why is None:
                continue
            log(f"calibration: cache entry {f.name} of {t.label} is invalid ({why}); recomputing it")
        todo.append(t)
    failed: dict[str, str] = {}
    if todo:
        log(f"calibration: elastic solves of {len(todo)} served position(s)' own sections")
        cache.mkdir(parents=True, exist_ok=True)
        with Runner(min(workers, len(todo)), scheduler) as runner:
            for k, outcome in runner.imap(run_section_elastic, todo):
                if outcome.elastic is None:
                    failed[todo[k].key] = outcome.error or "failed"
                    continue
                save_entry(elastic_entry(cache, todo[k]), outcome.elastic)
                done[todo[k].key] = outcome.elastic
    return done, failed


def with_section(anc: Anchor | None, master: MasterCurves, task: PositionTask, convexity: float,
                 elastic: SectionElastic) -> Anchor:
    """``anc`` (a direct reference's correction, None: none) with p_y and c_el taken from the position's own
    section: the ratios to the master's values at the position's semi-axes and convexity."""
    base = similar_indentation(master, task.geometry.a_mm, task.geometry.b_mm, convexity)
    n_q, n_f = len(master.q), len(master.unload_factors)
    return Anchor(elastic.p_y_MPa / base.first_yield_MPa,
                  elastic.compliance_mm_per_MPa / base.fem_elastic_compliance_mm_per_MPa,
                  anc.u_pl if anc is not None else (0.0,) * n_q,
                  anc.residual if anc is not None else (0.0,) * n_f,
                  "; ".join(s for s in ((anc.source if anc is not None else ""), "the section's elastic solve") if s))


def section_reference(task: PositionTask, served: IndentationResult, convexity: float,
                      plastic_convexity: float | None, source: str) -> DirectReference:
    """The reference a served position with its section's elastic solve leaves for a later recalibration of the
    same position (the wear loop's next step): ``served`` (its characteristic: the master's curves at the section's
    p_y and c_el) at its patch and convexities. Anchored to it, a nearby patch takes the master's value with the
    section's p_y / master ratio (and c_el's) and the master's curves unchanged (their difference at the reference
    is zero), without a solve of its own (:func:`calibration.similarity.anchor.applies` decides "nearby")."""
    g = task.geometry
    return DirectReference(task.body, float(task.y_mm), float(g.a_mm), float(g.b_mm), float(convexity),
                           float(served.first_yield_MPa), tuple(map(float, served.p_MPa)),
                           tuple(map(float, served.u_pl_mm)), tuple(map(float, served.unload_peaks_MPa)),
                           tuple(map(float, served.residual_fem_mm)),
                           float(served.fem_elastic_compliance_mm_per_MPa), source, plastic_convexity,
                           kind="section's elastic solve")


__all__ = ["REUSE_LIMITS", "ElasticOutcome", "SectionElastic", "elastic_entry", "needs_solve", "run_section_elastic",
           "section_elastic", "section_elastics", "section_reference", "with_section"]
