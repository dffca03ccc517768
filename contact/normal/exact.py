"""Exact normal contact on the elastic half-space with the Prandtl layer in series (FFT boundary elements).

Units: mm, N, MPa. The accuracy reference for the Kik–Piotrowski (KP) method and a fast accurate alternative,
selected by ``method.normal = "exact"``. Same input (:class:`NormalProblem`, :class:`LayerPair`) and output
(:class:`NormalSolution`) as the KP solver.

Problem. Separation of the undeformed surfaces at the cell centres of a uniform grid (lines y_j = the problem's
strips, spacing h = ``grid_mm``; cells x_i, spacing dx):

    f(x, y) = f(y) + x^2 / (2 R)             (f(y): the problem's separation on the strip grid, R: rolling radius)

Contact with approach delta: g = f + u_E(p) + u_L(p) - delta >= 0, p >= 0, g p = 0, sum p dx h = N, where
u_E = C * p is the half-space displacement of both bodies (:mod:`contact.normal.halfspace`, Love's influence
coefficients, FFT convolution) and u_L the layer displacement of each cell (:mod:`contact.normal.exact_layer`,
modes ``indentation`` / ``rolling``). Without a layer this is the exact (discretised) Boussinesq problem that KP's
eq. (13) approximates at one point; with a layer, eq. (13)'s 1/(2k) term holds at every cell instead of only at
the reference point.

Solution. Outer iteration on the layer: linearise u_L at the current pressure, u_L ~ b + c p (each cell's
current segment, eq. 7), solve the linear complementarity problem by Polonsky–Keer CG
(:mod:`contact.normal.constrained_cg`, force prescribed, or the approach with ``approach_mm``), re-evaluate the
exact u_L at the new pressure; stop when max |u_L(p) - (b + c p)| <= ``layer_rtol`` delta. ConvergenceError when
the CG or the outer iteration does not converge.

Grid (chosen automatically). A KP solution of the same problem gives the patch: the grid covers its lines and
x extent plus ``margin`` (relative, at least 2 cells each side); dx = KP patch length / ``cells``. After a solve,
a grid border that carries pressure is moved out (x: by 30 %; y: by the margin), and strips outside the grid
where the separation plus the elastic displacement of the solved pressure lies below delta (a further valley
touching) are added; the solve is repeated until neither happens. All contact regions share one grid (their
elastic interaction is exact). InputError when the patch reaches the end of the separation table. A warm start
(``start``: a nearby solution's field) grows KP's grid by the same border rule until its pressure fits, then
starts the CG from that pressure (:func:`solve_exact`).

Outputs per line y_j: p_peak = max_x p (the loading the passes apply to the strip's element), the contact
extent along x with each end refined by linear extrapolation to zero of p^2 without a layer (the half-space's
edge, p ~ sqrt of the distance) or of p with a layer (near the edge the layer dominates: p ~ distance), and the
strip force. Each connected run of lines is a :class:`Patch` with x_lead = half the refined
extent and the semi-elliptic peak that carries the strip's exact force (for FASTSIM); the exact field is kept in
``NormalSolution.field``. Patch length, width (refined the same way along y from p_peak) and area (sum of refined
extents times h) are reported as for KP.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from contact.layer.prandtl_layer import LayerPair
from contact.normal.boussinesq import rectangle_kernel_integral
from contact.normal.constrained_cg import constrained_cg
from contact.normal.exact_field import ExactField, fastsim_pressure, strip_centres
from contact.normal.exact_layer import LAYER_MODES, CellLayer
from contact.normal.halfspace import HalfSpace, compliance_factor
from contact.normal.kik_piotrowski import solve_normal
from contact.normal.layer_at_strip import layer_points
from contact.normal.patch import Patch
from contact.normal.problem import NormalProblem
from contact.normal.solution import NormalSolution, RegionSolution
from wrlayer.errors import ConvergenceError, InputError, require

# ExactField, fastsim_pressure and strip_centres are re-exported: callers take the solver's outputs from here
__all__ = ["DEFAULT_CELLS", "CELLS_RANGE", "ExactOptions", "ExactField", "solve_exact", "fastsim_pressure",
           "strip_centres", "line_extent", "line_area", "layer_is_elastic"]

#: Default cells along x over the KP patch length (``method.exact_cells``), from the time-error study
#: (docs/exact-solver.md): about 0.5 % in p_max on the paper scene.
DEFAULT_CELLS = 48
CELLS_RANGE = (8, 1024)


@dataclass(frozen=True)
class ExactOptions:
    """Options of the exact solver (keys: ``method.exact_cells``, ``method.layer_mode``).

    cells: cells along x over the KP patch length; layer_mode: "indentation" or "rolling"; margin: relative grid
    margin around the KP patch; cg_tol / cg_max_iter: CG stop (relative pressure change) and limit; layer_rtol /
    layer_max_iter: outer layer iteration stop (mismatch / delta) and limit; approach_mm: prescribe the approach
    (mm) instead of the force (the force is then an output); max_grid_changes: grid enlargements allowed.
    """

    cells: int = DEFAULT_CELLS
    layer_mode: str = "indentation"
    margin: float = 0.15
    cg_tol: float = 1e-5
    cg_max_iter: int = 3000
    layer_rtol: float = 1e-5
    layer_max_iter: int = 60
    approach_mm: float | None = None
    max_grid_changes: int = 8

    def __post_init__(self):
        lo, hi = CELLS_RANGE
        require(isinstance(self.cells, (int, np.integer)) and lo <= self.cells <= hi, "method.exact_cells",
                f"must be an integer in [{lo}, {hi}], got {self.cells!r}")
        require(self.layer_mode in LAYER_MODES, "method.layer_mode",
                f"must be one of {', '.join(LAYER_MODES)}, got {self.layer_mode!r}")
        require(bool(np.isfinite(self.margin) and 0.0 <= self.margin <= 2.0), "margin", "must lie in [0, 2]")
        for name in ("cg_max_iter", "layer_max_iter"):
            require(int(getattr(self, name)) >= 1, name, f"must be >= 1, got {getattr(self, name)!r}")
        for name in ("cg_tol", "layer_rtol"):
            v = getattr(self, name)
            require(bool(np.isfinite(v) and 0.0 < v < 1.0), name, f"must lie in (0, 1), got {v!r}")
        if self.approach_mm is not None:
            require(bool(np.isfinite(self.approach_mm) and self.approach_mm > 0), "approach_mm",
                    f"must be a positive number, got {self.approach_mm!r}")


@dataclass
class _Grid:
    j0: int
    ny: int
    nx: int
    dx: float

    def x(self) -> np.ndarray:
        return (np.arange(self.nx) - 0.5 * (self.nx - 1)) * self.dx

    def lines(self) -> np.ndarray:
        return np.arange(self.j0, self.j0 + self.ny)


def _edge_extension(outer: float, inner: float, step: float, power: int) -> float:
    """Distance beyond the outer contact cell centre where p^power, extrapolated linearly from the outer and the
    inner cell, reaches 0 (clipped to [0, step]; half a step without a usable inner value). power 2: the
    half-space's square-root edge; power 1: the linear edge of a contact with a layer (Winkler-like near the edge)."""
    if inner > outer > 0:
        qo, qi = outer ** power, inner ** power
        return float(min(step, step * qo / (qi - qo)))
    return 0.5 * step


def line_extent(values: np.ndarray, coords: np.ndarray, step: float, power: int) -> tuple[float, float]:
    """(low end, high end) of the positive run of ``values`` along ``coords`` with refined ends."""
    on = np.flatnonzero(values > 0)
    a, b = int(on[0]), int(on[-1])
    lo_in = values[a + 1] if a + 1 <= b else 0.0
    hi_in = values[b - 1] if b - 1 >= a else 0.0
    return (coords[a] - _edge_extension(values[a], lo_in, step, power),
            coords[b] + _edge_extension(values[b], hi_in, step, power))


def layer_is_elastic(layer: LayerPair | None, strip_y_mm: np.ndarray, h: float, p_peak: np.ndarray) -> bool:
    """True when no layer element yields under the strips' peak pressures p_peak (MPa) (no layer: True)."""
    if layer is None:
        return True
    for lay in layer.bodies().values():
        ix = layer_points(lay, strip_y_mm, h)
        loaded = (p_peak > 0) & (ix >= 0)
        if np.any(p_peak[loaded] > lay.yield_pressure_MPa(ix[loaded]) * (1.0 + 1e-12)):
            return False
    return True


def line_area(length: np.ndarray, y_lines: np.ndarray, y_lo: float, y_hi: float, h: float) -> float:
    """Patch area (mm^2) from the refined line extents: the inner lines count length x h; an end line counts its
    length times the width from its inner cell edge to the refined patch end (d + h/2, d in [0, h]: the distance
    of the line centre from the refined end)."""
    if length.size == 1:
        return float(length[0] * (y_hi - y_lo))
    total = float(np.sum(length[1:-1]) * h)
    total += length[0] * (y_lines[0] - y_lo + 0.5 * h) + length[-1] * (y_hi - y_lines[-1] + 0.5 * h)
    return float(total)


def _initial_grid(prob: NormalProblem, kp: NormalSolution, opts: ExactOptions) -> _Grid:
    n_strips = prob.strip_y_mm.size
    lo = min(int(r.strips[0]) for r in kp.regions)
    hi = max(int(r.strips[-1]) for r in kp.regions)
    my = max(2, int(math.ceil(opts.margin * (hi - lo + 1))))
    lo, hi = max(0, lo - my), min(n_strips - 1, hi + my)
    dx = kp.length_mm / opts.cells
    half = int(math.ceil(0.5 * kp.length_mm * (1.0 + opts.margin) / dx)) + 2
    return _Grid(lo, hi - lo + 1, 2 * half + 1, dx)


def _start_pressure(prob: NormalProblem, kp: NormalSolution, grid: _Grid) -> np.ndarray:
    """KP's semi-elliptic pressure (eq. 11) sampled at the cell centres (the CG's starting point)."""
    p = np.zeros((grid.ny, grid.nx))
    x = grid.x()
    lines = grid.lines()
    for region, patch in zip(kp.regions, kp.patches):
        rows = np.searchsorted(lines, region.strips)
        ok = (rows < grid.ny) & (lines[np.minimum(rows, grid.ny - 1)] == region.strips)
        p[rows[ok]] = np.maximum(p[rows[ok]], patch.pressure_MPa(x[:, None]).T[ok])
    return p


def _field_pressure(start: ExactField, grid: _Grid) -> np.ndarray:
    """An earlier solution's pressure (``start``: e.g. the previous step of an iteration over the load) on the
    grid: each line the grid shares with it interpolated linearly in x (0 beyond its cells); the CG's warm start
    (the CG scales it to the force)."""
    p = np.zeros((grid.ny, grid.nx))
    rows = np.searchsorted(start.lines, grid.lines())
    ok = (rows < start.lines.size) & (start.lines[np.minimum(rows, start.lines.size - 1)] == grid.lines())
    x = grid.x()
    for j in np.flatnonzero(ok):
        p[j] = np.interp(x, start.x_mm, start.p_MPa[rows[j]], left=0.0, right=0.0)
    return p


def _regrid_pressure(p: np.ndarray, old: _Grid, new: _Grid) -> np.ndarray:
    """The pressure of the old grid on the new one (same dx, same centre in x; lines shifted)."""
    out = np.zeros((new.ny, new.nx))
    r0 = old.j0 - new.j0
    c0 = (new.nx - old.nx) // 2
    out[r0:r0 + old.ny, c0:c0 + old.nx] = p
    return out


def _border_growth(grid: _Grid, p: np.ndarray, margin: float) -> tuple[_Grid, int]:
    """The grid grown where the pressure ``p`` on it reaches a border (x: both ends, by 30 % of nx; y: the
    touched end, by the margin), and that y margin (lines)."""
    new = _Grid(grid.j0, grid.ny, grid.nx, grid.dx)
    if np.any(p[:, 0] > 0) or np.any(p[:, -1] > 0):
        new.nx = 2 * int(math.ceil(0.65 * grid.nx)) + 1
    rows = np.flatnonzero(np.any(p > 0, axis=1))
    my = max(2, int(math.ceil(margin * grid.ny)))
    if rows.size and rows[0] == 0:
        new.j0, new.ny = grid.j0 - my, new.ny + my
    if rows.size and rows[-1] == grid.ny - 1:
        new.ny += my
    return new, my


def _warm_grid(start: ExactField, grid: _Grid, margin: float, n_strips: int, changes: int) -> tuple[_Grid, int]:
    """KP's grid grown by the solver's own border rule (:func:`_border_growth`) until ``start``'s pressure fits
    (within the separation table), as the cold solve would grow it after its first CG: (grid, growth steps)."""
    for k in range(changes):
        new, _ = _border_growth(grid, _field_pressure(start, grid), margin)
        lo, hi = max(new.j0, 0), min(new.j0 + new.ny - 1, n_strips - 1)
        new.j0, new.ny = lo, hi - lo + 1
        if (new.j0, new.ny, new.nx) == (grid.j0, grid.ny, grid.nx):
            return grid, k
        grid = new
    return grid, changes


def _offgrid_contact(prob: NormalProblem, f_strips: np.ndarray, grid: _Grid, p: np.ndarray, delta: float,
                     factor: float) -> np.ndarray:
    """Strips outside the grid where f(y) + u_E(0, y) < delta (contact the grid misses), sorted."""
    lines = grid.lines()
    outside = np.ones(f_strips.size, dtype=bool)
    outside[lines] = False
    cand = np.flatnonzero(outside & (f_strips < delta))
    if cand.size == 0:
        return cand
    y = prob.strip_y_mm
    h = prob.grid_mm
    x = grid.x()
    on = p > 0
    rows, cols = np.nonzero(on)
    pv = p[on]
    # screen: 1/r >= 1/(farthest distance) over every loaded cell, so u_E(0, y) >= C sum(p dA) / r_far
    y_on = y[lines][rows]
    r_far = np.hypot(np.abs(x[cols]).max() + grid.dx, np.maximum(np.abs(y_on.max() - y[cand]),
                                                               np.abs(y_on.min() - y[cand])) + h)
    cand = cand[f_strips[cand] + factor * pv.sum() * grid.dx * h / r_far < delta]
    if cand.size == 0:
        return cand
    hits = []
    for start in range(0, cand.size, 64):
        chunk = cand[start:start + 64]
        yc = y[lines][rows][None, :] - y[chunk][:, None]
        xc = x[cols][None, :]
        k = rectangle_kernel_integral(xc - 0.5 * grid.dx, xc + 0.5 * grid.dx, yc - 0.5 * h, yc + 0.5 * h)
        u = factor * (k @ pv)
        hits.append(chunk[f_strips[chunk] + u < delta])
    return np.concatenate(hits)


def _solve_on_grid(prob: NormalProblem, f_strips: np.ndarray, layer: LayerPair | None, grid: _Grid,
                   p_start: np.ndarray, opts: ExactOptions, factor: float, stats: dict):
    h = prob.grid_mm
    x = grid.x()
    lines = grid.lines()
    f = f_strips[lines][:, None] + (x * x)[None, :] / (2.0 * prob.rolling_radius_mm)
    hs = HalfSpace(grid.ny, grid.nx, h, grid.dx, factor)
    cell_area = grid.dx * h
    kw = dict(force_N=None if opts.approach_mm is not None else prob.normal_force_N, approach_mm=opts.approach_mm,
              tol=opts.cg_tol, max_iter=opts.cg_max_iter, cells_displacement=hs.cells_displacement)
    cl = CellLayer(layer, prob.strip_y_mm, h, lines, opts.layer_mode)
    if not cl.present:
        res = constrained_cg(hs.displacement, f, 0.0, 0.0, cell_area, p_start, **kw)
        stats["cg_iterations"] += res.iterations
        return res, f, np.zeros_like(f), cl
    p = p_start
    u_l, c = cl.linearise(p)
    cg_tol = 1e-3                              # loose while the layer linearisation is far off, then tightened
    for k in range(1, opts.layer_max_iter + 1):
        b = u_l - c * p
        kw["tol"] = cg_tol
        res = constrained_cg(hs.displacement, f, c, b, cell_area, p, **kw)
        stats["cg_iterations"] += res.iterations
        p = res.p_MPa
        u_new, c_new = cl.linearise(p)
        mismatch = float(np.abs(u_new - (b + c * p)).max())
        stats["layer_iterations"] += 1
        cg_tol = max(opts.cg_tol, min(cg_tol, 0.1 * mismatch / max(res.delta_mm, 1e-12)))
        u_l, c = u_new, c_new
        if mismatch <= opts.layer_rtol * max(res.delta_mm, 1e-12) and cg_tol <= opts.cg_tol:
            stats["layer_mismatch_mm"] = mismatch
            return res, f, u_l, cl
    raise ConvergenceError(f"exact normal solver: the layer iteration ({opts.layer_mode}) did not converge in "
                           f"{opts.layer_max_iter} iterations (layer mismatch {mismatch:.3g} mm)")


def solve_exact(prob: NormalProblem, layer: LayerPair | None = None, options: ExactOptions = ExactOptions(),
                start: ExactField | None = None, cg_tol: float | None = None, **kp_kwargs) -> NormalSolution:
    """Solve the normal contact exactly on the half-space with the layer (module docstring); layers unchanged.

    ``start``: the field of an earlier solve of a nearby problem (e.g. the previous step of the wheel-rail load
    balance): the CG starts from its pressure on this grid instead of KP's (the grid is placed by KP either way),
    the same solution to the CG tolerance in fewer iterations. ``cg_tol``: replaces ``options.cg_tol`` (a loose
    first estimate, e.g. the first point of an iteration over the load).
    ``kp_kwargs`` (delta_guess_mm, loglog_slope_guess, rtol_N) go to the KP solve that places the grid.
    Raises InputError (patch reaching the end of the separation table, layer not covering the patch) and
    ConvergenceError (CG, layer iteration or grid placement not converged).
    """
    if start is not None and start.kp_delta_mm is not None:   # KP from the start's own KP solve
        kp_kwargs = {**kp_kwargs, "delta_guess_mm": start.kp_delta_mm, "loglog_slope_guess": start.kp_slope}
    kp = solve_normal(prob, layer, **kp_kwargs)
    if cg_tol is not None:
        options = replace(options, cg_tol=cg_tol)
    factor = compliance_factor(prob.E_MPa, prob.poisson)
    f_strips = prob.separation_on_grid_mm
    n_strips = f_strips.size
    grid = _initial_grid(prob, kp, options)
    stats = {"cg_iterations": 0, "layer_iterations": 0, "grid_changes": 0, "layer_mismatch_mm": 0.0}
    p_start = None
    if start is not None:
        warm, stats["grid_changes"] = _warm_grid(start, grid, options.margin, n_strips, options.max_grid_changes)
        p_start = _field_pressure(start, warm)
        grid = warm if np.any(p_start > 0) else grid
    if p_start is None or not np.any(p_start > 0):           # no start, or an unrelated one: KP's pressure
        p_start = _start_pressure(prob, kp, grid)
    for _ in range(options.max_grid_changes + 1):
        res, f, u_l, cl = _solve_on_grid(prob, f_strips, layer, grid, p_start, options, factor, stats)
        p = res.p_MPa
        new, my = _border_growth(grid, p, options.margin)
        lo, hi = new.j0, new.j0 + new.ny - 1
        extra = _offgrid_contact(prob, f_strips, grid, p, res.delta_mm, factor)
        if extra.size:
            lo, hi = min(lo, int(extra[0]) - my), max(hi, int(extra[-1]) + my)
        if lo < 0 or hi > n_strips - 1:
            end = prob.strip_y_mm[0] if lo < 0 else prob.strip_y_mm[-1]
            raise InputError("separation.y_mm", f"the contact patch reaches the end of the separation table at "
                             f"y = {end:.4g} mm (N = {prob.normal_force_N:g} N, exact solver): extend the table "
                             f"(it covers {prob.y_mm[0]:.4g}..{prob.y_mm[-1]:.4g} mm)")
        new.j0, new.ny = lo, hi - lo + 1
        if (new.j0, new.ny, new.nx) == (grid.j0, grid.ny, grid.nx):
            break
        stats["grid_changes"] += 1
        p_start = _regrid_pressure(p, grid, new)
        grid = new
    else:
        raise ConvergenceError(f"exact normal solver: the grid still had to grow after {options.max_grid_changes} "
                               "enlargements (contact at the grid border)")
    if not np.any(p > 0):
        raise ConvergenceError("exact normal solver: no contact (zero pressure everywhere)")
    cl.check_coverage(p, prob.strip_y_mm[grid.lines()])
    return _solution(prob, layer, kp, grid, res, f, u_l, stats, options.approach_mm is None)


def _solution(prob, layer, kp, grid, res, f, u_l, stats, opts_force) -> NormalSolution:
    h, dx = prob.grid_mm, grid.dx
    p = res.p_MPa
    x = grid.x()
    lines = grid.lines()
    y = prob.strip_y_mm
    line_max = p.max(axis=1)
    p_peak = np.zeros(y.size)
    p_peak[lines] = line_max
    on = np.flatnonzero(line_max > 0)
    runs = np.split(on, np.flatnonzero(np.diff(on) > 1) + 1)
    power = 1 if layer is not None and layer.bodies() else 2      # edge law for the refined extents
    patches, regions, lengths, widths, areas = [], [], [], [], []
    extents = np.full((lines.size, 2), np.nan)
    for run in runs:
        ext = np.array([line_extent(p[j], x, dx, power) for j in run])
        extents[run] = ext
        x_lead = 0.5 * (ext[:, 1] - ext[:, 0])
        force = p[run].sum(axis=1) * dx * h
        patches.append(Patch(h, y[lines[run]], x_lead, force / (0.5 * np.pi * x_lead * h)))
        y_lo, y_hi = line_extent(np.concatenate([[0.0], line_max[run], [0.0]]),
                             np.concatenate([[y[lines[run[0]]] - h], y[lines[run]], [y[lines[run[-1]]] + h]]), h,
                             power)
        lengths.append(float(2.0 * x_lead.max()))
        widths.append(float(y_hi - y_lo))
        areas.append(line_area(2.0 * x_lead, y[lines[run]], y_lo, y_hi, h))
        jr = int(run[np.argmax(line_max[run])])
        ir = int(np.argmax(p[jr]))
        regions.append(RegionSolution(
            strips=lines[run], reference=int(lines[jr]), x_lead_mm=x_lead, p0_MPa=float(line_max[jr]),
            I1_mm3=float("nan"), I2_mm2=float("nan"), u_layer_mm=float(u_l[jr, ir]), normal_force_N=float(force.sum()),
            layer_segments=0, approach_mm=float(res.delta_mm - f[jr, ir]), interaction_mm=0.0))
    main = max(regions, key=lambda r: r.p0_MPa)
    elastic = layer_is_elastic(layer, y, h, p_peak)
    n_total = float(p.sum() * dx * h)
    iterations = {"delta_evaluations": kp.iterations["delta_evaluations"],
                  "loglog_slope": kp.iterations["loglog_slope"], "cg_iterations": stats["cg_iterations"],
                  "layer_iterations": stats["layer_iterations"], "grid_changes": stats["grid_changes"],
                  "grid_cells": [grid.ny, grid.nx], "cell_mm": [float(dx), float(h)],
                  "cg_change": float(res.change), "gap_error_mm": float(res.gap_error_mm),
                  "layer_mismatch_mm": float(stats["layer_mismatch_mm"])}
    target = prob.normal_force_N
    fieldv = ExactField(x, y[lines], lines, p, u_l, f, float(dx), float(h), extents, float(kp.delta_mm),
                        float(kp.iterations["loglog_slope"]))
    return NormalSolution(
        patches=patches, regions=regions, delta_mm=float(res.delta_mm), delta0_mm=float(prob.alpha * res.delta_mm),
        p_max_MPa=float(p.max()), length_mm=max(lengths), width_mm=float(sum(widths)), area_mm2=float(sum(areas)),
        u0_mm=float(main.u_layer_mm), strip_y_mm=y, p_peak_MPa=p_peak, iterations=iterations,
        residual_N=float(n_total - target) if opts_force else 0.0, elastic=elastic, normal_force_N=n_total,
        method="exact", field=fieldv)
