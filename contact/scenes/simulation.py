"""Run a contact scene: normal contact with the layer, passes, FASTSIM -> the result records.

Steps (units mm, N, MPa, s):
0. The normal solver is ``method.normal`` (:mod:`contact.normal.method`): "auto" (default: the exact half-space
   solver), Kik–Piotrowski, the exact solver or the half-space on a coarse grid
   (:func:`contact.normal.method.solve_normal_with`); everything below works with each.
1. The separation table goes onto the solver's fixed strip grid (:class:`contact.normal.kik_piotrowski.NormalProblem`).
2. Layers (if any) are built on that grid (:mod:`contact.scenes.scene_layers`): one combined characteristic (the
   paper's eq. 13 layer) or one per body; a per-body calibration table is read at ``position_mm + y``.
3. Without a layer: one normal solve. With a layer: :func:`contact.passes.passes.run_passes` (the paper's passes: the
   residual displacements of each pass raise the separation of the next; stop at shakedown or ``passes.max``);
   each pass's contact is checked against the tables' ranges as it is solved.
4. With creepages: the tangential solution of ``method.tangential`` ("fastsim", "fastrip" or "exact";
   :func:`contact.tangential.on_patch.solve_regions`) on every patch of every pass. The creepages hold at the
   scene's origin (x = 0, y = 0): a patch centred at y_c sees the longitudinal creepage creepage_x - spin y_c
   (FASTSIM takes the spin about each patch's force centroid, docs/conventions.md); Fx, Fy and Mz are summed over
   the patches, every Mz about the scene's origin; W_T max and P_T max are the maxima over the patches. Each
   patch's geometry is reported in its own frame (origin y at the patch's reference strip, the maximum of the
   virtual penetration).

``shakedown_pass`` is the number of the first pass that added no residual displacement beyond
``passes.tolerance_mm`` (a purely elastic pass: the paper's shakedown), null when none did or without a layer.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Iterator
from dataclasses import dataclass, field

import numpy as np

from contact.normal.kik_piotrowski import NormalProblem, NormalSolution
from contact.normal.method import solve_normal_with
from contact.normal.patch import Patch
from contact.passes.passes import run_passes
from contact.passes.record import SCENE_PASS_LAYOUT, PassRecord, RegionRecord
from contact.scenes.result_io import UNITS, code_version
from contact.scenes.run_result import (
    MethodDescription,
    PatchScaling,
    SceneResult,
    SolverStats,
    StripGrid,
    reference_deviation,
)
from contact.scenes.scene_spec import Scene
from contact.scenes.scene_layers import (
    build_layers,
    check_table_coverage,
    scale_layers_to_patch,
    scales_to_patch,
)
from contact.tangential.fastsim import Creepage, TangentialResult
from contact.tangential.on_patch import TangentialSettings, solve_regions
from wrlayer.errors import InputError, PatchTruncated, typed_input_error
from wrlayer.progress import progress
from wrlayer.short_repr import short_repr


_NORMAL_METHOD_TEXT = {
    "kik_piotrowski": "Kik-Piotrowski virtual penetration with the Prandtl-body layer (paper eqs. 9-15); p_max "
                      "approximate (up to 20 % below the exact half-space on Hertzian patches, 27 % on wheel-rail "
                      "ones, 50 % on flat-topped ones: docs/validation/fast-normal.md)",
    "exact": "exact half-space (FFT boundary elements, Polonsky-Keer CG) with the Prandtl-body layer cell by cell "
             "(layer_mode {m.layer_mode}, exact_cells {cells})",
    "coarse_exact": "exact half-space on a coarse grid fitted to the patch (Polonsky-Keer CG) with the Prandtl-body "
                    "layer cell by cell (indentation)",
}

#: The result's ``method.tangential`` text per ``method.tangential`` key.
TANGENTIAL_METHOD_TEXT = {
    "fastsim": "FASTSIM on the strips of each patch (Kalker; equivalent-ellipse flexibilities)",
    "fastrip": "FaStrip on the strips of each patch (Sichani, Enblom, Berg)",
    "exact": "Kalker's exact steady rolling theory on the patch grid (CONTACT's full theory)",
}


@dataclass(frozen=True, eq=False)
class PassSnapshot:
    """The solutions of one pass (kept for the pictures and the frictional outputs): normal solution, FASTSIM per
    patch (None without creepage) and the patches in their own frames (y relative to the reference strip
    ``y_ref_mm``)."""

    number: int
    solution: NormalSolution
    tangential: list[TangentialResult | None]
    local_patches: list[Patch]
    y_ref_mm: list[float]
    residual_mm: dict[str, np.ndarray] = field(default_factory=dict)

    __repr__ = short_repr  # the arrays by their shapes


@dataclass(frozen=True, eq=False)
class SimulationRun:
    """Everything a scene run produced: the result records (written as result.json) and arrays for pictures.

    strip_y_mm: the fixed strip grid; separation_before_mm / separation_after_mm: f on it before the first and
    after the last pass (shifted so min = 0 before); residual_mm: cumulative residual displacement per layer
    ("wheel", "rail", "combined") after the last pass; every_pass: the snapshot of every pass.
    """

    scene: Scene
    result: SceneResult
    first: PassSnapshot
    last: PassSnapshot
    strip_y_mm: np.ndarray
    separation_before_mm: np.ndarray
    separation_after_mm: np.ndarray
    residual_mm: dict[str, np.ndarray] = field(default_factory=dict)
    every_pass: list[PassSnapshot] = field(default_factory=list)

    def __repr__(self) -> str:
        return f"SimulationRun({self.scene.name}: {self.result!r})"

    @property
    def history(self) -> tuple[PassRecord, ...]:
        return self.result.passes


def solve_patches(scene: Scene, solution: NormalSolution, number: int,
                  residual_mm: dict[str, np.ndarray] | None = None) -> tuple[PassSnapshot, float]:
    """The tangential solution (``method.tangential``) of every patch of the solution, if the scene has creepages:
    creepages about the scene's origin, each result's strip y and Mz in the scene frame; returns the snapshot and
    its time (s)."""
    t0 = time.perf_counter()
    ts = scene.tangential
    y_ref = [float(solution.strip_y_mm[region.reference]) for region in solution.regions]
    local = [local_patch(patch, yr) for patch, yr in zip(solution.patches, y_ref)]
    tang: list[TangentialResult | None] = [None] * len(local)
    if ts is not None and ts.has_creepage:
        settings = TangentialSettings(scene.material.E_MPa, scene.material.poisson, ts.friction, ts.speed_mm_s,
                                      scene.method.fastsim_cells, ts.flexibility, scene.method.tangential)
        tang = solve_regions(solution, Creepage(ts.creepage_x, ts.creepage_y, ts.spin_per_mm), settings)
    snapshot = PassSnapshot(number=number, solution=solution, tangential=tang, local_patches=local, y_ref_mm=y_ref,
                            residual_mm=dict(residual_mm or {}))
    return snapshot, time.perf_counter() - t0


def local_patch(patch: Patch, y_ref_mm: float) -> Patch:
    """``patch`` with its strip coordinate measured from ``y_ref_mm`` (mm)."""
    return Patch(patch.grid_mm, patch.y_mm - y_ref_mm, patch.x_lead_mm, patch.p_peak_MPa)


def region_result(snapshot: PassSnapshot, i: int) -> RegionRecord:
    """Region ``i`` of a pass (its own frame; creep forces when solved)."""
    region, patch, tr = snapshot.solution.regions[i], snapshot.local_patches[i], snapshot.tangential[i]
    yr = snapshot.y_ref_mm[i]
    geometry = dict(y_ref_mm=yr, y_min_mm=yr + float(patch.y_mm[0]), y_max_mm=yr + float(patch.y_mm[-1]),
                    length_mm=patch.length_mm(), width_mm=patch.width_mm(), area_mm2=patch.area_mm2(),
                    p0_MPa=region.p0_MPa, p_max_MPa=float(patch.p_peak_MPa.max()),
                    normal_force_N=region.normal_force_N, u_layer_mm=region.u_layer_mm)
    if tr is None:
        return RegionRecord(**geometry)
    return RegionRecord(**geometry, Fx_N=tr.Fx_N, Fy_N=tr.Fy_N, Mz_Nmm=tr.Mz_Nmm,
                        WT_max_N_per_mm=tr.WT_max_N_per_mm,
                        PT_max_W_per_mm2=tr.PT_max_W_per_mm2, slip_area_mm2=tr.slip_area_mm2,
                        adhesion_area_mm2=tr.adhesion_area_mm2, equivalent_ellipse_a_mm=tr.ellipse.a_mm,
                        equivalent_ellipse_b_mm=tr.ellipse.b_mm)


def pass_result(snapshot: PassSnapshot, record: PassRecord, timings: dict[str, float] | None = None) -> PassRecord:
    """The pass as result.json keeps it (:data:`contact.passes.record.SCENE_PASS_LAYOUT`): the record of the normal
    solve and the layer with the tangential solution of its regions and the timings."""
    sol = snapshot.solution
    regions = tuple(region_result(snapshot, i) for i in range(len(sol.patches)))
    has_t = any(t is not None for t in snapshot.tangential)
    return dataclasses.replace(
        record, regions=regions, timings_s=timings or {},
        Fx_N=float(sum(r.Fx_N for r in regions)), Fy_N=float(sum(r.Fy_N for r in regions)),
        Mz_Nmm=float(sum(r.Mz_Nmm for r in regions)),
        WT_max_N_per_mm=max(r.WT_max_N_per_mm for r in regions) if has_t else None,
        PT_max_W_per_mm2=max(r.PT_max_W_per_mm2 for r in regions) if has_t else None,
    ).projected(SCENE_PASS_LAYOUT)


def simulate(scene: Scene) -> SimulationRun:
    """Run the scene; returns the result records and the arrays for the pictures. Raises InputError for bad input
    found while solving (a layer table not covering the contact, a patch reaching the end of the separation table)
    and ConvergenceError for solver failures."""
    try:
        return _simulate(scene)
    except InputError as err:
        if isinstance(typed_input_error(err), PatchTruncated):  # name the scene file
            raise PatchTruncated(f"{scene.path.name}: {err.what}", err.problem) from None
        raise


def _layered_passes(scene: Scene, prob: NormalProblem, layers) -> tuple[list[tuple], list[PassRecord], np.ndarray]:
    """The passes of a layered scene: ([(record, solution, normal and layer time (s))], records, separation after
    the last pass); every pass's contact checked against the tables as it is solved."""
    stamps = [time.perf_counter()]
    solved: list[tuple] = []
    # a bar over passes.max on a terminal (the run may stop earlier at shakedown); a plain counter otherwise
    ticks = progress(range(scene.passes.max), desc=scene.name, unit="pass", lines=False, leave=False)
    tick = iter(ticks)

    def on_pass(record: PassRecord, solution: NormalSolution) -> None:
        next(tick, None)
        stamps.append(time.perf_counter())
        check_table_coverage(scene, solution)
        solved.append((record, solution, stamps[-1] - stamps[-2]))

    opts = scene.passes.options
    try:
        records, f_after = run_passes(prob, layers, opts, on_pass=on_pass, method=scene.method.normal_method())
    finally:
        getattr(ticks, "close", lambda: None)()
    return solved, records, np.asarray(f_after, dtype=float)


def _elastic_pass(scene: Scene, prob: NormalProblem) -> tuple[PassSnapshot, PassRecord]:
    """The one pass of a scene without a layer."""
    t0 = time.perf_counter()
    sol = solve_normal_with(prob, method=scene.method.normal_method())
    t_normal = time.perf_counter() - t0
    snap, t_tang = solve_patches(scene, sol, 1)
    return snap, pass_result(snap, PassRecord.of(sol, 1), {"normal_s": t_normal, "tangential_s": t_tang})


def _with_tangential(scene: Scene, solved: list[tuple]) -> Iterator[tuple[PassSnapshot, PassRecord]]:
    """Every pass of ``solved`` ((record, solution, time) of :func:`_layered_passes`) with FASTSIM on its patches:
    (snapshot, result record)."""
    for number, (record, solution, t_pass) in enumerate(solved, start=1):
        snap, t_tang = solve_patches(scene, solution, number, record.cumulative_residual_mm)
        yield snap, pass_result(snap, record, {"normal_and_layer_s": t_pass, "tangential_s": t_tang})


def _simulate(scene: Scene) -> SimulationRun:
    t_start = time.perf_counter()
    prob = scene.normal_problem()
    y = prob.strip_y_mm
    f_before = prob.separation_on_grid_mm.copy()
    layers = build_layers(scene, y)
    scaled = None
    if layers is not None and scales_to_patch(scene):
        layers, patch, solves = scale_layers_to_patch(scene, prob, layers)
        scaled = PatchScaling(a_mm=patch[0], b_mm=patch[1], solves=solves)
    residual: dict[str, np.ndarray] = {}
    if layers is None:
        passes, f_after = [_elastic_pass(scene, prob)], f_before
    else:
        solved, records, f_after = _layered_passes(scene, prob, layers)
        passes = list(_with_tangential(scene, solved))
        if records:
            residual = {k: np.asarray(v, dtype=float) for k, v in records[-1].cumulative_residual_mm.items()}
    snapshots = [snap for snap, _ in passes]
    history = tuple(rec for _, rec in passes)
    method = MethodDescription(
        normal=_NORMAL_METHOD_TEXT[scene.method.normal].format(
            m=scene.method, cells=scene.method.normal_method().exact_options().cells),
        tangential=None if scene.tangential is None or not scene.tangential.has_creepage
        else TANGENTIAL_METHOD_TEXT[scene.method.tangential],
        layer=None if layers is None else tuple(sorted(layers.bodies())))
    result = SceneResult(
        inputs=scene.to_dict(), code_version=code_version(), units=UNITS, method=method,
        layer_scaled_to_patch=scaled, n_passes=len(history),
        shakedown_pass=next((h.index for h in history if h.shakedown), None), passes=history,
        reference_deviation=reference_deviation(scene.reference, history[-1]),
        strip_grid=StripGrid(y_mm=tuple(y.tolist()), separation_before_mm=tuple(f_before.tolist()),
                             separation_after_mm=tuple(f_after.tolist()),
                             residual_mm={k: tuple(v.tolist()) for k, v in residual.items()}),
        solver=SolverStats(total_s=time.perf_counter() - t_start,
                           delta_evaluations=int(sum(h.iterations.get("delta_evaluations", 0) for h in history))))
    return SimulationRun(scene=scene, result=result, first=snapshots[0], last=snapshots[-1], strip_y_mm=y,
                         separation_before_mm=f_before, separation_after_mm=f_after, residual_mm=residual,
                         every_pass=snapshots)


__all__ = ["PassSnapshot", "SimulationRun", "build_layers", "pass_result", "region_result",
           "local_patch", "simulate", "solve_patches"]
