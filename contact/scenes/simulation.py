"""Run a contact scene: normal contact (Kik–Piotrowski with the layer), passes, FASTSIM -> the result dict.

Steps (units mm, N, MPa, s):
0. The normal solver is ``method.normal``: Kik–Piotrowski (default) or the exact half-space solver
   (:func:`contact.normal.method.solve_normal_with`); everything below works with either.
1. The separation table goes onto the solver's fixed strip grid (:class:`contact.normal.kik_piotrowski.NormalProblem`).
2. Layers (if any) are built on that grid: one combined characteristic (the paper's eq. 13 layer) or one per body;
   a per-body calibration table is read at ``position_mm + y`` for every strip y (outside the table's range the
   nearest tabulated end is used for building, and a contact on such a strip is an InputError: the table does not
   cover the contact location).
3. Without a layer: one normal solve. With a layer: :func:`contact.passes.passes.run_passes` (the paper's passes: the
   residual displacements of each pass raise the separation of the next; stop at shakedown or ``passes.max``).
4. With creepages: FASTSIM (:func:`contact.tangential.fastsim.solve_tangential`) on every patch of every pass, each patch in
   its own frame (origin y at the patch's reference strip, the maximum of the virtual penetration), the same
   creepages for all patches; Fx, Fy and Mz are summed over the patches (each Mz about its own patch origin),
   W_T max and P_T max are the maxima over the patches. With the exact normal solver each strip's cell pressures
   are the exact pressure along that line (:func:`contact.normal.exact.fastsim_pressure`), not a semi-ellipse.

``shakedown_pass`` is the number of the first pass that added no residual displacement beyond
``passes.tolerance_mm`` (a purely elastic pass: the paper's shakedown), null when none did or without a layer.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from contact.layer.patch_scaling import settle_patch_sizes
from contact.layer.prandtl_layer import LayerPair, PrandtlLayer
from contact.layer.strip_lookup import check_coverage, clamped_characteristics
from contact.normal.kik_piotrowski import NormalProblem, NormalSolution
from contact.normal.method import solve_normal_with
from contact.normal.patch import Patch
from contact.scenes.result_io import UNITS, code_version
from contact.scenes.scene import BODIES, Scene, scene_inputs
from contact.tangential.fastsim import Creepage, TangentialResult
from contact.tangential.on_patch import FastsimSettings, local_patch, solve_region
from wrlayer.errors import InputError, PatchTruncated, typed_input_error


@dataclass
class PassSnapshot:
    """The solutions of one pass (kept for the pictures): normal solution, FASTSIM per patch (None without
    creepage) and the patches in their own frames (y relative to the reference strip ``y_ref_mm``)."""

    number: int
    solution: NormalSolution
    tangential: list[TangentialResult | None]
    local_patches: list[Patch]
    y_ref_mm: list[float]


@dataclass
class SimulationRun:
    """Everything a scene run produced: the result dict (written as result.json) and arrays for pictures.

    strip_y_mm: the fixed strip grid; separation_before_mm / separation_after_mm: f on it before the first and
    after the last pass (shifted so min = 0 before); residual_mm: cumulative residual displacement per layer
    ("wheel", "rail", "combined") after the last pass; history: the per-pass dicts.
    """

    scene: Scene
    result: dict[str, Any]
    first: PassSnapshot
    last: PassSnapshot
    strip_y_mm: np.ndarray
    separation_before_mm: np.ndarray
    separation_after_mm: np.ndarray
    residual_mm: dict[str, np.ndarray] = field(default_factory=dict)
    every_pass: list[PassSnapshot] = field(default_factory=list)

    @property
    def history(self) -> list[dict[str, Any]]:
        return self.result["passes"]


# ---------------------------------------------------------------------------------------------------- layers
def build_layers(scene: Scene, strip_y_mm: np.ndarray, patch_mm: tuple[float, float] | None = None
                 ) -> LayerPair | None:
    """The scene's layers on the strip grid (PrandtlLayer per body, or one combined layer). A table layer is read
    at ``position_mm + y`` for every strip y, clamped to the table's range (coverage is checked after each pass, on
    the strips in contact: :func:`check_table_coverage`); with ``scale_to_patch`` scaled to ``patch_mm`` = (a, b)
    (mm)."""
    spec = scene.layer
    if spec is None:
        return None
    if spec.combined is not None:
        return LayerPair(combined=PrandtlLayer.uniform(spec.combined, strip_y_mm, name="layer"))
    layers = {}
    for body in BODIES:
        b = getattr(spec, body)
        if b is None:
            continue
        what = f"{scene.path.name}: layer.{body}"
        if b.characteristic is not None:
            layers[body] = PrandtlLayer.uniform(b.characteristic, strip_y_mm, name=what)
        else:
            chars, _ = clamped_characteristics(b.table, b.position_mm + strip_y_mm, f"{what}.table",
                                               patch_mm if b.scale_to_patch else None)
            layers[body] = PrandtlLayer.from_characteristics(chars, strip_y_mm, name=what)
    return LayerPair(**layers)


def check_table_coverage(scene: Scene, solution: NormalSolution) -> None:
    """LayerNotCovered when a strip in contact lies outside a body's calibration table."""
    if scene.layer is None:
        return
    in_contact = solution.strip_y_mm[solution.p_peak_MPa > 0]
    for body in BODIES:
        b = getattr(scene.layer, body)
        if b is not None and b.table is not None:
            check_coverage(b.table, b.position_mm + in_contact, f"{scene.path.name}: layer.{body}.table", body,
                           b.table_path.name, tolerance_mm=1e-9)


# ---------------------------------------------------------------------------------------------------- tangential
def solve_patches(scene: Scene, solution: NormalSolution, number: int) -> tuple[PassSnapshot, float]:
    """FASTSIM on every patch of the solution (if the scene has creepages), each in its own frame (origin at the
    patch's reference strip); returns the snapshot and its time (s)."""
    t0 = time.perf_counter()
    ts = scene.tangential
    solve = ts is not None and ts.has_creepage
    settings = None if not solve else FastsimSettings(scene.material.E_MPa, scene.material.poisson, ts.friction,
                                                      ts.speed_mm_s, scene.method.fastsim_cells, ts.flexibility)
    y_ref = [float(solution.strip_y_mm[region.reference]) for region in solution.regions]
    local = [local_patch(patch, yr) for patch, yr in zip(solution.patches, y_ref)]
    tang = [solve_region(solution, k, lp, Creepage(ts.creepage_x, ts.creepage_y, ts.spin_per_mm), settings)
            if solve else None for k, lp in enumerate(local)]
    return PassSnapshot(number, solution, tang, local, y_ref), time.perf_counter() - t0


def _patch_dict(snapshot: PassSnapshot, i: int) -> dict[str, Any]:
    region, patch, tr = snapshot.solution.regions[i], snapshot.local_patches[i], snapshot.tangential[i]
    out = {"y_ref_mm": snapshot.y_ref_mm[i], "y_min_mm": snapshot.y_ref_mm[i] + float(patch.y_mm[0]),
           "y_max_mm": snapshot.y_ref_mm[i] + float(patch.y_mm[-1]), "length_mm": patch.length_mm(),
           "width_mm": patch.width_mm(), "area_mm2": patch.area_mm2(), "p0_MPa": region.p0_MPa,
           "p_max_MPa": float(patch.p_peak_MPa.max()), "normal_force_N": region.normal_force_N,
           "u_layer_mm": region.u_layer_mm}
    if tr is None:
        out.update(Fx_N=0.0, Fy_N=0.0, Mz_Nmm=0.0, WT_max=None, PT_max_W_per_mm2=None, slip_area_mm2=None,
                   adhesion_area_mm2=None)
    else:
        out.update(Fx_N=tr.Fx_N, Fy_N=tr.Fy_N, Mz_Nmm=tr.Mz_Nmm, WT_max=tr.WT_max_N_per_mm,
                   PT_max_W_per_mm2=tr.PT_max_W_per_mm2, slip_area_mm2=tr.slip_area_mm2,
                   adhesion_area_mm2=tr.adhesion_area_mm2, equivalent_ellipse_a_mm=tr.ellipse.a_mm,
                   equivalent_ellipse_b_mm=tr.ellipse.b_mm)
    return out


def pass_dict(snapshot: PassSnapshot, record: Any = None, timings: dict[str, float] | None = None) -> dict[str, Any]:
    """The per-pass result entry (Table 1 quantities + layer numbers + solver statistics)."""
    sol = snapshot.solution
    patches = [_patch_dict(snapshot, i) for i in range(len(sol.patches))]
    has_t = any(t is not None for t in snapshot.tangential)
    up0 = 0.0 if record is None else float(record.up0_mm)
    up_max = 0.0 if record is None else float(record.max_residual_mm)
    return {
        "pass": snapshot.number,
        "length_mm": sol.length_mm, "width_mm": sol.width_mm, "area_mm2": sol.area_mm2,
        "delta_mm": sol.delta_mm, "delta0_mm": sol.delta0_mm, "p_max_MPa": sol.p_max_MPa,
        "Fx_N": float(sum(p["Fx_N"] for p in patches)), "Fy_N": float(sum(p["Fy_N"] for p in patches)),
        "Mz_Nmm": float(sum(p["Mz_Nmm"] for p in patches)),
        "WT_max": max(p["WT_max"] for p in patches) if has_t else None,
        "PT_max_W_per_mm2": max(p["PT_max_W_per_mm2"] for p in patches) if has_t else None,
        "u0_mm": sol.u0_mm, "up0_mm": up0, "up_max_mm": up_max, "elastic": bool(sol.elastic),
        "shakedown": bool(record is not None and record.shakedown),
        "dissipated_energy_max_N_per_mm": {} if record is None else dict(record.dissipated_energy_N_per_mm),
        "n_patches": len(patches), "normal_force_N": sol.normal_force_N, "residual_N": sol.residual_N,
        "iterations": dict(sol.iterations), "timings_s": timings or {}, "patches": patches,
    }


def reference_deviation(reference: dict[str, Any], last: dict[str, Any]) -> dict[str, float]:
    """Relative deviation (value - reference) / |reference| of the last pass from the scene's [reference] numbers
    (and ``passes``: the pass count); empty without a reference."""
    out = {}
    for key, ref in reference.items():
        value = last["pass"] if key == "passes" else last.get(key)
        if isinstance(ref, float) and ref != 0.0 and value is not None:
            out[key] = (float(value) - ref) / abs(ref)
    return out


# ---------------------------------------------------------------------------------------------------- the run
_NORMAL_METHOD_TEXT = {
    "kik_piotrowski": "Kik-Piotrowski virtual penetration with the Prandtl-body layer (paper eqs. 9-15)",
    "exact": "exact half-space (FFT boundary elements, Polonsky-Keer CG) with the Prandtl-body layer cell by cell "
             "(layer_mode {m.layer_mode}, exact_cells {cells})",
}



def scale_layers_to_patch(scene: Scene, prob: NormalProblem, layers: LayerPair):
    """Issue 12: a table characteristic holds for the patch size it was calibrated on (its displacements scale
    with sqrt(a b)). Solve the first pass's normal problem, rebuild the layers scaled to the solved semi-axes
    (a, b) = (length/2, width/2) and solve again until the patch settles
    (:func:`contact.layer.patch_scaling.settle_patch_sizes`). Returns (the layers at the settled (a, b), (a, b),
    normal solves including the first, unscaled one); ConvergenceError when the patch does not settle."""
    method = scene.method.normal_method()

    def sizes_of(sol) -> dict:
        return {0: (0.5 * sol.length_mm, 0.5 * sol.width_mm)}

    def solve_at(sizes: dict):
        scaled = build_layers(scene, prob.strip_y_mm, sizes[0])
        return scaled, sizes_of(solve_normal_with(method, prob, scaled))

    first = sizes_of(solve_normal_with(method, prob, layers))
    layers, sizes, solves = settle_patch_sizes(solve_at, first, f"{scene.path.name}: scale_to_patch")
    return layers, sizes[0], solves + 1


def normal_problem(scene: Scene) -> NormalProblem:
    sep, load, mat, met = scene.separation, scene.load, scene.material, scene.method
    return NormalProblem(sep.y_mm, sep.f_mm, load.normal_force_N, load.rolling_radius_mm, mat.E_MPa, mat.poisson,
                         alpha=met.alpha, grid_mm=met.grid_mm)


def simulate(scene: Scene) -> SimulationRun:
    """Run the scene; returns the result dict and the arrays for the pictures. Raises InputError for bad input
    found while solving (a layer table not covering the contact, a patch reaching the end of the separation table)
    and ConvergenceError for solver failures."""
    try:
        return _simulate(scene)
    except InputError as err:
        if isinstance(typed_input_error(err), PatchTruncated):  # name the scene file
            raise PatchTruncated(f"{scene.path.name}: {err.what}", err.problem) from None
        raise


def _simulate(scene: Scene) -> SimulationRun:
    t_start = time.perf_counter()
    prob = normal_problem(scene)
    y = prob.strip_y_mm
    f_before = prob.separation_on_grid_mm.copy()
    layers = build_layers(scene, y)
    scaled = None
    if layers is not None and scene.layer is not None and any(
            getattr(getattr(scene.layer, b), "scale_to_patch", False) for b in BODIES):
        layers, patch, solves = scale_layers_to_patch(scene, prob, layers)
        scaled = {"a_mm": patch[0], "b_mm": patch[1], "solves": solves}
    snapshots: list[PassSnapshot] = []
    history: list[dict[str, Any]] = []
    residual: dict[str, np.ndarray] = {}
    every: list[PassSnapshot] = []  # every pass, for the wear-ready frictional outputs

    if layers is None:
        t0 = time.perf_counter()
        sol = solve_normal_with(scene.method.normal_method(), prob)
        t_normal = time.perf_counter() - t0
        snap, t_tang = solve_patches(scene, sol, 1)
        snapshots.append(snap)
        every.append(snap)
        history.append(pass_dict(snap, None, {"normal_s": t_normal, "tangential_s": t_tang}))
        f_after = f_before
    else:
        from contact.passes.passes import PassesOptions, run_passes

        clock = [time.perf_counter()]
        from wrlayer.progress import progress

        # a bar over passes.max on a terminal (the run may stop earlier at shakedown); a plain counter otherwise
        ticks = progress(range(scene.passes.max), desc=scene.name, unit="pass", leave=False)
        tick = iter(ticks)

        def on_pass(record, solution):
            next(tick, None)
            t_pass = time.perf_counter() - clock[0]
            check_table_coverage(scene, solution)
            snap, t_tang = solve_patches(scene, solution, len(history) + 1)
            every.append(snap)
            if not snapshots:
                snapshots.append(snap)
            else:
                snapshots[1:] = [snap]
            history.append(pass_dict(snap, record, {"normal_and_layer_s": t_pass, "tangential_s": t_tang}))
            clock[0] = time.perf_counter()

        opts = PassesOptions(max_passes=scene.passes.max, tolerance_mm=scene.passes.tolerance_mm,
                             hardening=scene.passes.hardening)
        try:
            records, f_after = run_passes(prob, layers, opts, on_pass=on_pass, method=scene.method.normal_method())
        finally:
            getattr(ticks, "close", lambda: None)()
        f_after = np.asarray(f_after, dtype=float)
        if records:
            residual = {k: np.asarray(v, dtype=float) for k, v in records[-1].cumulative_residual_mm.items()}

    shakedown = next((h["pass"] for h in history if h["shakedown"]), None)
    result = {
        "inputs": scene_inputs(scene),
        "code_version": code_version(),
        "units": UNITS,
        "method": {"normal": _NORMAL_METHOD_TEXT[scene.method.normal].format(
            m=scene.method, cells=scene.method.normal_method().exact_options().cells),
                   "tangential": None if scene.tangential is None or not scene.tangential.has_creepage
                   else "FASTSIM on the strips of each patch (Kalker; equivalent-ellipse flexibilities)",
                   "layer": None if layers is None else sorted(layers.bodies())},
        "layer_scaled_to_patch": scaled,
        "n_passes": len(history),
        "shakedown_pass": shakedown,
        "passes": history,
        "reference_deviation": reference_deviation(scene.reference, history[-1]),
        "strip_grid": {"y_mm": y, "separation_before_mm": f_before, "separation_after_mm": f_after,
                       "residual_mm": residual},
        "solver": {"total_s": time.perf_counter() - t_start,
                   "delta_evaluations": int(sum(h["iterations"].get("delta_evaluations", 0) for h in history))},
    }
    return SimulationRun(scene, result, snapshots[0], snapshots[-1], y, f_before, f_after, residual, every)
