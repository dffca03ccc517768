"""``run_rolling(config, out_dir) -> RollingResult``: static dents, passes of the moving load and the layer's
prediction for every level; ``rolling.json`` and ParaView series (units mm, N, MPa, s; docs/rolling.md).

Order of work: mesh and cost guard (before any FEM), discretisation and the kept elastic factorisation, the
elastic first-yield pressure p_y of the static load at mid-track, one static indentation per level (its dent;
the highest one's loading curve gives the layer's characteristic), then the passes level by level. Output:
``out_dir/rolling.json`` (:class:`RollingResult`) and, with ``run.plots``, ``out_dir/fields/level_<k>/passes.pvd``:
the unloaded body before the first pass and after each pass (plastic strain, residual stress, displacement).
The run is built beside ``out_dir`` (:func:`wrlayer.atomic_write.staged_output_dir`): after every pass what is
complete (``rolling.json`` with ``status`` "running: ...", the fields so far) is published into
``<out_dir>.partial``, and ``out_dir`` keeps an earlier output until the run ends, when the run replaces it and the
partial folder is removed. A SIGTERM or Ctrl-C leaves the published passes in the partial folder (``status``
"terminated (SIGTERM) after ..."). A step that fails (RollingConvergenceError, exit code 3) ends the run: its
record (``failed``, ``status`` "stopped: ...") with the passes completed before it replaces ``out_dir``.
"""

from __future__ import annotations

import json
import math
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from calibration.fem.assembly import discretise, frees_its_meshes
from calibration.fem.elastoplastic_solver import LoadPath
from calibration.fem.solver_state import SolverOptions, SolverState
from calibration.hertz.load import HertzLoad
from calibration.rolling.config import RollingConfig
from calibration.rolling.cost import rolling_cost
from calibration.rolling.groove import GrooveProfile, SurfaceProbe
from calibration.rolling.law_fit import fit_passes, rolling_law
from calibration.rolling.layer_prediction import LayerGroove, StaticCurve, layer_grooves, static_curve
from calibration.rolling.moving_load import MovingHertzLoad, SurfaceForces
from calibration.rolling.passes import MovingLoadPass, RollingConvergenceError, roll
from calibration.rolling.substeps import SubstepSolver, UnitResponses
from calibration.rolling.section_groove import SectionProbe
from calibration.rolling.section_track import SectionStaticLoad, section_static_load, section_track_mesh
from calibration.rolling.track_mesh import TrackMesh, track_axes, track_mesh
from wrlayer.atomic_write import StagedOutput, atomic_write_text, output_error, staged_output_dir
from wrlayer.cost import guard
from wrlayer.errors import InputError, Terminated, check_terminated

#: Version of the rolling.json layout (2: ``rolling_law`` and ``layer_groove_mm.rolling``; ``status`` is an added key).
FORMAT_VERSION = 2
#: Files of a rolling output folder that the tool writes (never carried over from an earlier run's folder).
ROLLING_OWNED = ("rolling.json", "fields/")


@dataclass(frozen=True)
class LevelResult:
    """One load level.

    Attributes
    ----------
    p0_over_py : float
        Peak pressure over the FEM first-yield pressure p_y of the static load (-).
    p0_MPa : float
        Peak Hertz pressure p0 (MPa).
    static_dent_mm : float
        Residual depth of the static indentation at mid-track (mm, relative to the far field; section: to the
        support).
    groove_mm : list of float
        Groove depth after each completed pass (mm, cumulative, :class:`~calibration.rolling.groove.GrooveProfile`).
    layer_groove_mm : LayerGroove
        The layer's groove after each pass, {"relaxed": [...], "state_kept": [...]} (mm; empty lists without a fit).
    shift_mm : list of float
        Mean residual surface displacement along x at mid-track after each pass (mm).
    max_eq_plastic_strain : list of float
        Largest equivalent plastic strain below mid-track after each pass (-).
    pass_seconds : list of float
        Wall time of each pass (s).
    newton_iterations : list of int
        Newton iterations of each pass.
    profiles : list of GrooveProfile
        The groove profile after each pass (:class:`~calibration.rolling.groove.GrooveProfile`, mm).
    """

    p0_over_py: float
    p0_MPa: float
    static_dent_mm: float
    groove_mm: list[float] = field(default_factory=list)
    layer_groove_mm: LayerGroove = LayerGroove([], [])
    shift_mm: list[float] = field(default_factory=list)
    max_eq_plastic_strain: list[float] = field(default_factory=list)
    pass_seconds: list[float] = field(default_factory=list)
    newton_iterations: list[int] = field(default_factory=list)
    profiles: list[GrooveProfile] = field(default_factory=list)

    def with_pass(self, rec: MovingLoadPass, prof: GrooveProfile) -> LevelResult:
        """This level with one more completed pass."""
        return replace(self, groove_mm=self.groove_mm + [prof.groove_mm], shift_mm=self.shift_mm + [prof.shift_mm],
                       max_eq_plastic_strain=self.max_eq_plastic_strain + [prof.max_eq_plastic_strain],
                       pass_seconds=self.pass_seconds + [rec.seconds],
                       newton_iterations=self.newton_iterations + [rec.newton_iters],
                       profiles=self.profiles + [prof])

    def to_dict(self) -> dict:
        out = {k: getattr(self, k) for k in self.__dataclass_fields__}
        out["layer_groove_mm"] = self.layer_groove_mm.to_dict()
        out["profiles"] = [p.to_dict() for p in self.profiles]
        out["groove_over_static"] = [g / self.static_dent_mm if self.static_dent_mm > 0 else math.nan
                                     for g in self.groove_mm]
        return out


@dataclass(frozen=True)
class RollingResult:
    """A rolling run (``rolling.json``).

    Attributes
    ----------
    format_version : int
        Version of the file's layout.
    config : dict
        The configuration's tables as read (units as their keys).
    p_y_MPa : float
        FEM first-yield pressure of the static (frictionless) load at mid-track (MPa).
    n_dofs : int
        Degrees of freedom of the mesh.
    n_elements : int
        Elements of the mesh.
    levels : list of LevelResult
        One entry per level (the completed passes).
    failed : str
        The error that stopped the run ("" : none).
    seconds : float
        Wall time of the run (s).
    files : list of str
        Files written (rolling.json, the .pvd series).
    rolling_law : dict
        The rolling law fitted to the passes (:class:`wrlayer.rolling_law.RollingLaw`, levels in p0 / p_y, the
        run's traction coefficient; {} when no level has passes above p_y): the ``rolling_law`` of a layer table.
    status : str
        "complete"; a failed run "stopped: <error>"; in the partial folder of a running run "running: <n>
        pass(es) completed", of a killed one "terminated (SIGTERM) after <n> pass(es)" or "interrupted after ...".
    """

    format_version: int
    config: dict
    p_y_MPa: float
    n_dofs: int
    n_elements: int
    levels: list[LevelResult]
    failed: str = ""
    seconds: float = 0.0
    files: list[str] = field(default_factory=list)
    rolling_law: dict = field(default_factory=dict)
    status: str = "complete"

    def to_dict(self) -> dict:
        out = {k: getattr(self, k) for k in self.__dataclass_fields__}
        out["levels"] = [lv.to_dict() for lv in self.levels]
        return out

    def with_rolling_law(self, traction: float) -> RollingResult:
        """This result with the rolling law fitted to its completed passes (levels above p_y with a positive
        groove and static dent, one per level) and each level's ``layer_groove_mm.rolling``: the layer's static
        residual times the law's G_n (docs/rolling.md)."""
        done = sorted((lv for lv in self.levels if lv.groove_mm and lv.groove_mm[0] > 0 and lv.static_dent_mm > 0
                       and lv.p0_over_py > 1.0), key=lambda lv: lv.p0_over_py)
        xs = [lv.p0_over_py for lv in done]
        if not done or np.any(np.diff(xs) <= 0):
            return self
        c = abs(traction)
        law = rolling_law(xs, [c], {(c, lv.p0_over_py): fit_passes(lv.groove_mm, lv.static_dent_mm) for lv in done},
                          f"this run: {len(done)} level(s), passes 1..{max(len(lv.groove_mm) for lv in done)}")
        levels = []
        for lv in self.levels:
            lg = lv.layer_groove_mm
            if lg.relaxed and lv.p0_over_py > 1.0:
                n = np.arange(1, len(lg.relaxed) + 1)
                lg = replace(lg, rolling=(lg.relaxed[0] * law.factor(n, lv.p0_over_py, c)).tolist())
            levels.append(replace(lv, layer_groove_mm=lg))
        return replace(self, levels=levels, rolling_law=law.to_dict())


@dataclass(frozen=True)
class RollingModel:
    """The discretised block with its kept problem: track mesh, discretisation, solver options, static load,
    moving load forces, surface probe (block or section), p_y (MPa), elastic centre compliance c_el (mm/MPa) and the tangent problem."""

    tm: TrackMesh
    disc: object
    opts: SolverOptions
    static_load: HertzLoad | SectionStaticLoad
    forces: SurfaceForces
    probe: SurfaceProbe | SectionProbe
    p_y_MPa: float
    compliance_mm_per_MPa: float
    prob: object


def body_mesh(config: RollingConfig) -> TrackMesh:
    """The track mesh of ``contact.body``: the block or the profile section."""
    if config.contact.body == "section":
        return section_track_mesh(config)
    return track_mesh(config.contact, config.track, config.mesh)


def build_model(config: RollingConfig, tm: TrackMesh) -> RollingModel:
    """Discretise, factorise once and solve the unit static load elastically (p_y and c_el). The block's static
    load is the engine's HertzLoad at mid-track, the section's the moving load held there
    (:class:`calibration.rolling.section_track.SectionStaticLoad`)."""
    c = config.contact
    disc = discretise(tm.mesh, config.mesh.order)
    b = None if c.model == "2d" else c.lateral_mm
    window = (-tm.track_half_mm, tm.track_half_mm)
    if c.body == "section":
        profile = c.section_profile()
        forces = SurfaceForces(disc.basis, MovingHertzLoad(c.a_mm, b, c.traction_coefficient, profile, c.y_mm),
                               window)
        static = section_static_load(disc, forces, profile, c.y_mm)
        probe = SectionProbe(disc, profile, c.y_mm, c.a_mm, b, track_axes(c, config.track, config.mesh)[0])
    else:
        static = HertzLoad(0.0, c.a_mm) if b is None else HertzLoad(0.0, b, c.a_mm, centre_x_mm=0.0)
        probe = SurfaceProbe(disc, c.a_mm)
    opts = SolverOptions(rtol=1e-6, etol=1e-8, dirichlet=tm.dirichlet, linear_solver=config.run.linear_solver)
    path = LoadPath(tm.mesh, config.material.j2(), static, [0.0], opts, disc=disc)
    u1 = path.u_unit
    c_el = path.prepared.centre_displacement_mm(u1) + probe.far_field(u1)
    if c.body != "section":
        forces = SurfaceForces(disc.basis, MovingHertzLoad(c.a_mm, b, c.traction_coefficient), window)
    return RollingModel(tm, disc, opts, static, forces, probe, float(path.first_yield_p0_MPa), float(c_el),
                        path.prob)


def level_pressures(config: RollingConfig, p_y_MPa: float) -> list[float]:
    """The levels in MPa (from p_y, k = Y / sqrt(3) or MPa)."""
    unit = {"p_y": p_y_MPa, "k": config.material.yield_MPa / math.sqrt(3.0), "MPa": 1.0}[config.contact.level_unit]
    return [float(x) * unit for x in config.contact.levels]


def static_dents(model: RollingModel, config: RollingConfig, levels_MPa: list[float]) -> list[StaticCurve]:
    """One virgin static indentation (load to p0 in steps of p_y / 10, unload) per level."""
    out = []
    mat = config.material.j2()
    for p0 in levels_MPa:
        opts = replace(model.opts, max_increment_MPa=0.1 * model.p_y_MPa, max_unload_increment_MPa=p0)
        path = LoadPath(model.tm.mesh, mat, model.static_load, [p0, 0.0], opts, disc=model.disc,
                        probes={"far": model.probe.far_field})
        out.append(static_curve(path, lambda u: model.probe.depth_at(u, 0.0), model.compliance_mm_per_MPa))
    model.prob.reset_to_elastic()
    return out


@frees_its_meshes
def run_rolling(config: RollingConfig, out_dir: str | Path, force: bool = False, progress=None) -> RollingResult:
    """Run every level of ``config`` into ``out_dir`` (see the module docstring). ``force``: run beyond the cost
    limit; ``progress(text)``: called after each pass (once it is published). InputError (bad input, cost, an
    ``out_dir`` that is not new, empty or an earlier output of the tool, a second run into it),
    RollingConvergenceError; OSError on writing as OutputError naming the folder."""
    t0 = time.perf_counter()
    out_dir = Path(out_dir)
    guard(rolling_cost(config), force)
    tm = body_mesh(config)
    with staged_output_dir(out_dir, owned=ROLLING_OWNED) as staged:   # refused before any FEM if not ours
        try:
            return _run_staged(config, tm, staged, t0, progress)
        except OSError as err:
            raise output_error(err, out_dir) from None


def _run_staged(config: RollingConfig, tm: TrackMesh, staged: StagedOutput, t0: float, progress) -> RollingResult:
    """The run built in ``staged.dir`` and published after every pass (the caller holds the output's lock)."""
    model = build_model(config, tm)
    levels_MPa = level_pressures(config, model.p_y_MPa)
    curves = static_dents(model, config, levels_MPa)
    n_passes = config.track.n_passes
    try:
        layer = layer_grooves(curves[int(np.argmax(levels_MPa))], model.p_y_MPa, levels_MPa, n_passes,
                              config.run.layer_segments, [c.dent_mm for c in curves])
    except InputError:  # no inelastic static curve to fit (all levels elastic): no layer prediction
        layer = [LayerGroove([], [])] * len(levels_MPa)
    results = [LevelResult(p0 / model.p_y_MPa, p0, c.dent_mm, layer_groove_mm=lg)
               for p0, c, lg in zip(levels_MPa, curves, layer)]
    files: list[str] = []
    base = RollingResult(FORMAT_VERSION, config.to_dict(), model.p_y_MPa, int(model.disc.n_dofs),
                         int(tm.mesh.t.shape[1]), results, files=files)
    traction = config.contact.traction_coefficient
    positions = [x * config.contact.a_mm for x in config.track.positions_over_a()]
    responses = UnitResponses(model.prob, model.forces)   # per mesh: shared by all levels and passes
    done = 0
    try:
        for k, p0 in enumerate(levels_MPa):
            series = _series(config, staged.dir, k, model)
            solver = SubstepSolver(model.prob, model.forces, p0, config.track.substeps, responses=responses)
            try:
                virgin = SolverState.virgin(model.disc)
                for rec in roll(solver, virgin, positions, n_passes, config.track.ramp_steps, k):
                    if isinstance(rec, MovingLoadPass):
                        results[k] = results[k].with_pass(rec, model.probe.profile(rec.state))
                        done += 1
                        if series is not None:
                            series(model.disc, rec.state)
                            series.write_pvd()
                        now = replace(base, levels=results, seconds=time.perf_counter() - t0,
                                      status=f"running: {done} pass(es) completed")
                        _write(staged.dir, now.with_rolling_law(traction))
                        staged.publish(staged.partial_kept(f"{done} completed pass(es)"))
                        if progress is not None:
                            progress(f"level {k}: pass {rec.pass_index} groove {results[k].groove_mm[-1]:.4g} mm "
                                     f"({rec.seconds:.1f} s)")
            except RollingConvergenceError as err:
                failed = replace(base, levels=results, failed=str(err), seconds=time.perf_counter() - t0,
                                 status=f"stopped: {err}")
                _write(staged.dir, failed.with_rolling_law(traction))
                staged.finish(f"the stopped run's {done} completed pass(es) are in {staged.path}")
                raise
            finally:
                if series is not None and series.steps:
                    files.append(str(staged.path / series.write_pvd().relative_to(staged.dir)))
            model.prob.reset_to_elastic()
        result = replace(base, levels=results, seconds=time.perf_counter() - t0).with_rolling_law(traction)
        _write(staged.dir, result)
        check_terminated()  # a SIGTERM swallowed by a C callback: the published passes stay
        staged.finish(f"the complete run ({done} passes) is in {staged.path}")
    except (Terminated, KeyboardInterrupt) as err:
        if staged.where == staged.partial:  # the published passes say how the run ended
            how = "terminated (SIGTERM)" if isinstance(err, Terminated) else "interrupted"
            _mark(staged.partial, f"{how} after {done} pass(es)")
        raise
    files.insert(0, str(staged.path / "rolling.json"))
    return result


def _write(out_dir: Path, result: RollingResult) -> Path:
    return atomic_write_text(out_dir / "rolling.json", json.dumps(result.to_dict(), indent=1, allow_nan=True))


def _mark(folder: Path, status: str) -> None:
    """Set the ``status`` of the rolling.json published in ``folder`` (a full disk may refuse: "running" stays)."""
    try:
        data = json.loads((folder / "rolling.json").read_text())
        data["status"] = status
        atomic_write_text(folder / "rolling.json", json.dumps(data, indent=1, allow_nan=True))
    except (OSError, ValueError, InputError):
        pass


def _series(config: RollingConfig, out_dir: Path, level: int, model: RollingModel):
    """The ParaView series of one level (None without plots), started with the virgin body."""
    if not config.run.plots:
        return None
    from calibration.fem.output import FieldSeries  # pyvista/meshio only where fields are written

    series = FieldSeries(out_dir / "fields" / f"level_{level}", config.material.j2(), stem="passes")
    series(model.disc, SolverState.virgin(model.disc))
    return series


__all__ = ["FORMAT_VERSION", "LevelResult", "RollingModel", "RollingResult", "body_mesh", "build_model", "level_pressures",
           "run_rolling", "static_dents"]
