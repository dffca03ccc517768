"""The exact half-space normal contact on a coarse grid fitted to the patch (``method.normal = "coarse_exact"``).

Units: mm, N, MPa. The same problem as :mod:`contact.normal.exact` (Boussinesq half-space of both bodies, Love's
influence coefficients, the Prandtl layer in series cell by cell in ``indentation`` mode, force prescribed), solved
on about ``cells`` lines (y) by ``x_cells`` cells (x) placed over the contact regions instead of the strip grid.
Along x every line's separation is f(y) + x^2 / (2 R), so the pressure is nearly semi-elliptic there and needs
fewer cells than the profile-shaped y direction (defaults 32 x 12, chosen on ``benchmarks/bench_fast_normal.py``).

Placing the grid. Contact can only occur where f(x, y) = f(y) + x^2 / (2 R) lies below the approach delta (the
elastic and layer displacements are >= 0). A first solve on half the lines and cells covers that region's bounding
box for a Hertz-like delta, rebuilt until the solved delta lies within it; with ``delta_guess_mm`` (a nearby
solve's approach) the region {f < delta_guess / 2} (:data:`GUESS_REGION`) stands for that solve's loaded cells.
The grid is then fitted to the loaded cells plus :data:`MARGIN` of their extent: one line interval per run of
loaded lines (one lattice of spacing dy, no lines in the gaps between separated regions, whose elastic interaction
stays exact; :mod:`contact.normal.coarse_grid`), moved out where the pressure reaches an end and refitted until
no end moves by more than a cell. These solves stop at :data:`ROUGH_TOL`; the last one is solved again to ``tol``.
Lines need not be strips: f is interpolated from the separation table as the problem does (no kinks between
strips). A grid's separation and influence tables are built once (:func:`contact.normal.coarse_grid.grid_tables`).
With ``warm`` (:class:`CoarseWarmStart`, the wheel–rail balance's successive forces of one patch) the solve starts
on the last solve's grid, to the full tolerance, and ends there when the loaded cells still fit it (within
:data:`WARM_KEEP_CELLS`).

Solve. Polonsky–Keer CG with the influence matrix applied from its table of cell offsets, in one compiled kernel
(:mod:`contact.normal.coarse_cg`); with a layer, the exact solver's outer iteration (each cell's loading curve
linearised on its current segment, paper eq. 7, until the mismatch is below ``layer_rtol`` delta). The layer of a
line is the element of the nearest strip.

Outputs. Each loaded line's contact ends along x, and each run's ends along y (from the lines' peak pressure),
where the parabola through the outer three cells' p^2 (p with a layer: linear near the edge) meets zero; the area
from these extents as the exact solver's (:func:`contact.normal.exact.line_area`). The lines' peak pressure,
half-length and force per width are interpolated linearly onto the problem's strips inside each run's y extent
(each strip a semi-ellipse carrying its share of the run's force, for the passes and FASTSIM; ``field`` is None).
``grid_pressure``: the grid's pressure; the exact tangential theory solves on it refined
(:func:`contact.normal.coarse_tangential.tangential_grid`).
With ``extrapolate`` the scalar outputs (p_max, delta, area, length, width) are Richardson-extrapolated from the
final grid solved with half the lines and cells (Q = Q_n + (Q_n - Q_{n/2}) / 3; measured worse on the benchmark
set, not the default). ConvergenceError when the CG, the layer iteration or the grid placement does not converge;
InputError when the patch reaches the end of the separation table or a layer does not cover it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from contact.layer.prandtl_layer import LayerPair
from contact.normal.coarse_cg import dense_cg
from contact.normal.coarse_ends import line_ends
from contact.normal.coarse_grid import MARGIN, CoarseGrid, grid_tables, loaded_spans, merged, resample, separation_at
from contact.normal.coarse_layer import LineLayers
from contact.normal.coarse_warm import CoarseWarmStart
from contact.normal.exact import layer_is_elastic, line_area
from contact.normal.halfspace import compliance_factor
from contact.normal.kik_piotrowski import hertz_like_guess
from contact.normal.patch import Patch
from contact.normal.problem import NormalProblem
from contact.normal.solution import GridPressure, NormalSolution, RegionSolution
from wrlayer.errors import ConvergenceError, InputError, require

__all__ = ["DEFAULT_CELLS", "MARGIN", "CoarseOptions", "CoarseWarmStart", "solve_coarse_exact"]

#: Default lines and cells of the coarse grid (``method.coarse_cells``), from the time-error study of
#: ``benchmarks/bench_fast_normal.py``.
DEFAULT_CELLS = 32
#: Default cells along x (rolling direction): the separation is x^2 / (2 R) along x on every line, so the pressure
#: is nearly semi-elliptic along x and needs fewer cells than the profile-shaped y direction.
DEFAULT_X_CELLS = 12
CELLS_RANGE = (6, 128)
#: CG and layer tolerance of the solves that only place the grid (the last solve uses ``tol``, ``layer_rtol``).
ROUGH_TOL = 1e-3
#: With an approach guess delta, the first loaded region is {f < GUESS_REGION delta}.
GUESS_REGION = 0.5
#: A warm start keeps its grid while every end of the new solution's fit lies within this many cells of the grid's
#: (a cold fit stops at 1 cell). A fit end moves by a whole cell when one more line or cell is loaded, so at 1 cell
#: a force 2 % higher refitted the kept grid of 2 of the 60 patches of ``benchmarks/bench_fast_normal.py`` (1.7-1.8
#: ms warm instead of 0.4-0.7 ms) and 15 of the 155 warm solves of the A-2.2 sweep; at 1.5 cells none of the 60 and
#: 7 of the 155, with the set's errors unchanged.
WARM_KEEP_CELLS = 1.5


@dataclass(frozen=True)
class CoarseOptions:
    """Options of the coarse-grid solver (key ``method.coarse_cells``).

    cells: lines and cells of the grid over the box (even); extrapolate: Richardson extrapolation from cells/2 and
    cells; tol / max_iter: CG stop (relative pressure change) and limit; layer_rtol / layer_max_iter: outer layer
    iteration; max_boxes: box rebuilds allowed.
    """

    cells: int = DEFAULT_CELLS
    x_cells: int = DEFAULT_X_CELLS
    extrapolate: bool = False
    tol: float = 1e-5
    max_iter: int = 2000
    layer_rtol: float = 1e-5
    layer_max_iter: int = 60
    max_boxes: int = 10

    def __post_init__(self):
        lo, hi = CELLS_RANGE
        for name in ("cells", "x_cells"):
            v = getattr(self, name)
            require(isinstance(v, (int, np.integer)) and lo <= v <= hi and v % 2 == 0,
                    f"method.coarse_{name}", f"must be an even integer in [{lo}, {hi}], got {v!r}")


def _solve_on(prob: NormalProblem, grid: CoarseGrid, layer: LineLayers, p_start: np.ndarray, opts: CoarseOptions,
              factor: float, stats: dict, rough: bool = False):
    """(p (ny, nx), delta (mm), u_L (ny, nx), f (ny, nx)) on the grid."""
    tables = grid_tables(prob, grid, factor)
    f, k, cols = tables.f, tables.k, tables.cols
    area = grid.dx * grid.dy
    p = np.array(p_start, dtype=float)
    if not np.any(p > 0):
        p = np.where(f <= f.min() + 1e-12, 1.0, 0.0)
    N = prob.normal_force_N
    tol = ROUGH_TOL if rough else opts.tol
    layer_rtol = ROUGH_TOL if rough else opts.layer_rtol
    if not layer.present:
        zero = np.zeros(f.size)
        p, delta, its, change = dense_cg(cols, k, grid.rows, f.ravel(), zero, zero, area, p.ravel(), N, tol,
                                         opts.max_iter)
        stats["cg_iterations"] += its
        if change >= tol:
            raise ConvergenceError(f"coarse exact normal solver: CG did not converge in {opts.max_iter} iterations")
        return p.reshape(f.shape), delta, np.zeros_like(f), f
    curves = layer.on_lines(grid.y)
    for _ in range(opts.layer_max_iter):
        u_l, c = layer.linearise(p, curves)
        b = u_l - c * p
        p, delta, its, change = dense_cg(cols, k, grid.rows, f.ravel(), c.ravel(), b.ravel(), area, p.ravel(), N, tol,
                                         opts.max_iter)
        stats["cg_iterations"] += its
        stats["layer_iterations"] += 1
        if change >= tol:
            raise ConvergenceError(f"coarse exact normal solver: CG did not converge in {opts.max_iter} iterations")
        p = p.reshape(f.shape)
        u_new, _ = layer.linearise(p, curves)
        if float(np.abs(u_new - (b + c * p)).max()) <= layer_rtol * max(delta, 1e-12):
            return p, delta, u_new, f
    raise ConvergenceError(f"coarse exact normal solver: the layer iteration did not converge in "
                           f"{opts.layer_max_iter} iterations")


def _located(prob, layer, opts, factor, stats, shape, delta_box):
    """Solve on the box of ``delta_box`` with shape = (lines, cells), rebuilt until the solved delta lies within it:
    (grid, p, delta)."""
    p, old = None, None
    for _ in range(opts.max_boxes):
        grid = CoarseGrid.over_box(prob, delta_box, shape)
        start = resample(p, old, grid) if old is not None else np.zeros((grid.y.size, grid.x.size))
        p, delta, _, _ = _solve_on(prob, grid, layer, start, opts, factor, stats, rough=True)
        stats["boxes"] += 1
        if delta <= delta_box:
            return grid, p, delta
        # a box that cuts the patch squeezes the pressure (delta overshoots, more with a yielding layer)
        delta_box, old = min(1.02 * max(delta, 1.2 * delta_box), 2.0 * delta_box), grid
    raise ConvergenceError(f"coarse exact normal solver: the box still had to grow after {opts.max_boxes} "
                           "rebuilds")


def _fitted(prob, layer, opts, factor, stats, shape, grid, p, fitted: tuple | None = None, rough: bool = False):
    """Solve with about shape[0] lines over the runs of loaded lines of ``p`` on ``grid`` and shape[1] cells over
    its loaded cells, plus :data:`MARGIN` (:func:`loaded_spans`), refitted to the new solution until no end moves
    by more than a cell; an interval end (or x end) the pressure reaches is moved out by half the interval: (grid,
    p, delta, u_L, f, (spans, x span) the grid was fitted to). ``fitted``: the (spans, x span) ``grid`` itself was
    fitted to (a warm start): the first solve is on ``grid``, to the full tolerance, and the last when the grid
    need not move. ``rough``: the fitted grid's solution at :data:`ROUGH_TOL` is the last (not solved to ``tol``)."""
    spans, x_span = loaded_spans(grid, p) if fitted is None else fitted
    for it in range(opts.max_boxes):
        final = fitted is not None and it == 0
        new = grid if final else CoarseGrid.over(prob, spans, x_span, shape, grid.box_delta)
        p, delta, u_l, f = _solve_on(prob, new, layer, p if final else resample(p, grid, new), opts, factor, stats,
                                     rough=not final)
        stats["boxes"] += 1
        grid = new
        loaded = p.max(axis=1) > 0
        for side, k in ((0, 0), (1, -1)):
            if grid.clipped[side] and loaded[k]:
                end = prob.strip_y_mm[-side]
                raise InputError("separation.y_mm", f"the contact patch reaches the end of the separation table at "
                                 f"y = {end:.4g} mm (N = {prob.normal_force_N:g} N, coarse exact solver): extend "
                                 f"the table (it covers {prob.y_mm[0]:.4g}..{prob.y_mm[-1]:.4g} mm)")
        grown, moved = [], False
        for lines, lo, hi in grid.spans():
            size = hi - lo
            a, b = lo - 0.5 * size if loaded[lines[0]] else lo, hi + 0.5 * size if loaded[lines[-1]] else hi
            moved |= (a, b) != (lo, hi)
            grown.append((a, b))
        cols = p.max(axis=0) > 0
        width = x_span[1] - x_span[0]
        x_grown = (x_span[0] - 0.5 * width if cols[0] else x_span[0],
                   x_span[1] + 0.5 * width if cols[-1] else x_span[1])
        if moved or x_grown != x_span:
            spans, x_span = merged(grown), x_grown
            continue
        want, want_x = loaded_spans(grid, p)
        cells = WARM_KEEP_CELLS if final else 1.0
        dy, dx = cells * grid.dy, cells * grid.dx
        if len(want) == len(spans) and all(abs(a - c) <= dy and abs(b - d) <= dy
                                           for (a, b), (c, d) in zip(want, spans)) \
                and abs(want_x[0] - x_span[0]) <= dx and abs(want_x[1] - x_span[1]) <= dx:
            if not final and not rough:
                p, delta, u_l, f = _solve_on(prob, grid, layer, p, opts, factor, stats)      # to the full tolerance
            return grid, p, delta, u_l, f, (spans, x_span)
        spans, x_span = want, want_x
    raise ConvergenceError(f"coarse exact normal solver: the grid still moved after {opts.max_boxes} "
                           "refits (contact at the grid border)")


def solve_coarse_exact(prob: NormalProblem, layer: LayerPair | None = None, options: CoarseOptions = CoarseOptions(),
                       delta_guess_mm: float | None = None, warm: CoarseWarmStart | None = None,
                       rough: bool = False) -> NormalSolution:
    """Solve the normal contact on the coarse grid (module docstring); the layers are not modified.
    ``delta_guess_mm``: the approach of a nearby solve (mm; e.g. the previous step of the wheel-rail balance): the
    first grid covers {f < delta_guess / 2} instead of a locating solve from the Hertz-like estimate. ``warm``: the
    last solve of the same problem at another force (:class:`CoarseWarmStart`; read and updated): when it matches,
    the solve starts on its grid (``delta_guess_mm`` is then not needed). ``rough``: a start only (the wheel–rail
    balance's first point, never its result): a cold solve ends on its fitted grid at :data:`ROUGH_TOL` (not
    solved again to ``tol``; a warm solve started from it is)."""
    factor = compliance_factor(prob.E_MPa, prob.poisson)
    lay = LineLayers(layer, prob)
    stats = {"cg_iterations": 0, "layer_iterations": 0, "boxes": 0}
    shape = (options.cells, options.x_cells)
    half = (options.cells // 2, max(options.x_cells // 2, 4))
    start = warm.start_for(prob, layer, options) if warm is not None else None
    if start is not None:
        warm.solves += 1
        grid, p, delta, u_l, f, fitted = _fitted(prob, lay, options, factor, stats, shape, start[0], start[2],
                                                 start[1])
        warm.kept += int(grid is start[0])
    else:
        grid, p, delta, u_l, f, fitted = _fitted(prob, lay, options, factor, stats, shape,
                                                 *_first_grid(prob, lay, options, factor, stats, half, delta_guess_mm),
                                                 rough=rough)
    if warm is not None:
        warm.keep(prob, layer, options, grid, fitted, p)
    sol = _outputs(prob, lay, grid, p, delta, u_l, f)
    if options.extrapolate:
        coarse = CoarseGrid.over(prob, [(lo, hi) for _, lo, hi in grid.spans()],
                            (grid.x[0] - 0.5 * grid.dx, grid.x[-1] + 0.5 * grid.dx), half, grid.box_delta)
        ph, dh, uh, fh = _solve_on(prob, coarse, lay, resample(p, grid, coarse), options, factor, stats)
        sol = sol[:1] + tuple(_richardson(a, b) for a, b in zip(_outputs(prob, lay, coarse, ph, dh, uh, fh)[1:],
                                                                 sol[1:]))
    return _solution(prob, layer, sol, stats, options)


def _first_grid(prob, lay, options, factor, stats, half, delta_guess_mm):
    """(grid, pressure) of a cold solve's first fit: over {f < delta_guess / 2} with a semi-ellipsoidal pressure
    when an approach guess is given, else the locating solve's (:func:`_located`)."""
    if delta_guess_mm is not None and delta_guess_mm > 0:
        # a nearby solve's approach: the region {f < delta/2} (Hertz's contact for a circle) as the first loaded
        # region, with a semi-ellipsoidal start, instead of a locating solve
        grid = CoarseGrid.over_box(prob, GUESS_REGION * delta_guess_mm, half)
        f0 = separation_at(prob, grid.y)[:, None] + (grid.x * grid.x)[None, :] / (2.0 * prob.rolling_radius_mm)
        p = np.sqrt(np.clip(1.0 - f0 / (GUESS_REGION * delta_guess_mm), 0.0, None))
        if np.any(p > 0):
            return grid, p
    grid, p, _ = _located(prob, lay, options, factor, stats, half, 1.2 * hertz_like_guess(prob))
    return grid, p


def _richardson(q_half, q_full):
    if isinstance(q_full, float):
        return q_full + (q_full - q_half) / 3.0
    return q_full


def _outputs(prob, lay: LineLayers, grid: CoarseGrid, p, delta, u_l, f):
    """(grid, p_max, delta, area, length, width, strip data) of a grid solution."""
    if not np.any(p > 0):
        raise ConvergenceError("coarse exact normal solver: no contact (zero pressure everywhere)")
    lay.check_coverage(p, grid.y)
    power = 1 if lay.present else 2
    line_max = p.max(axis=1)
    on = np.flatnonzero(line_max > 0)
    runs = np.split(on, np.flatnonzero(np.diff(grid.rows[on]) > 1) + 1)
    area = length = width = 0.0
    strips = []
    for run in runs:
        x_lo, x_hi = line_ends(p[run], grid.x, grid.dx, power)
        half = 0.5 * (x_hi - x_lo)
        y_ends = line_ends(np.concatenate([[0.0], line_max[run], [0.0]])[None, :],
                       np.concatenate([[grid.y[run[0]] - grid.dy], grid.y[run], [grid.y[run[-1]] + grid.dy]]),
                       grid.dy, power)
        y_lo, y_hi = float(y_ends[0][0]), float(y_ends[1][0])
        area += line_area(2.0 * half, grid.y[run], y_lo, y_hi, grid.dy)
        length = max(length, float(2.0 * half.max()))
        width += float(y_hi - y_lo)
        kr = int(run[np.argmax(line_max[run])])
        ir = int(np.argmax(p[kr]))
        strips.append((grid.y[run], line_max[run], half, p[run].sum(axis=1) * grid.dx, y_lo, y_hi,
                       float(u_l[kr, ir]), float(delta - f[kr, ir])))
    return grid, float(p.max()), float(delta), float(area), length, width, strips, _grid_pressure(grid, p, power)


def _grid_pressure(grid: CoarseGrid, p: np.ndarray, power: int) -> GridPressure:
    """The grid's pressure on every lattice line from its first to its last (zeros in the gaps between runs)."""
    full = np.zeros((int(grid.rows[-1] - grid.rows[0]) + 1, grid.x.size))
    full[grid.rows - grid.rows[0]] = p
    y = grid.y[0] + np.arange(full.shape[0]) * grid.dy
    return GridPressure(grid.x.copy(), y, full, power)


def _solution(prob: NormalProblem, layer, out, stats, options) -> NormalSolution:
    grid, p_max, delta, area, length, width, runs, on_grid = out
    ys, h = prob.strip_y_mm, prob.grid_mm
    p_peak = np.zeros(ys.size)
    patches, regions = [], []
    for y_lines, line_max, half, force, y_lo, y_hi, u_ref, approach in runs:
        idx = np.flatnonzero((ys > y_lo) & (ys < y_hi))
        if idx.size == 0:                                  # narrower than a strip: the strip nearest its peak
            idx = np.array([int(np.argmin(np.abs(ys - y_lines[np.argmax(line_max)])))])
        yy = np.concatenate([[y_lo], y_lines, [y_hi]])
        at = (lambda v: np.interp(ys[idx], yy, np.concatenate([[0.0], v, [0.0]])))  # noqa: E731
        peak, x_lead, w = at(line_max), np.maximum(at(half), 1e-9 * length), at(force)
        if not np.any(w > 0):
            peak, x_lead, w = line_max.max() + 0 * idx, half.max() + 0 * idx, force.max() + 0 * idx
        run_force = float(force.sum() * grid.dy)
        strip_force = w * h * run_force / float(w.sum() * h)     # the run's force shared in proportion to w
        p_peak[idx] = peak
        patches.append(Patch(h, ys[idx], x_lead, strip_force / (0.5 * np.pi * x_lead * h)))
        ref = int(idx[np.argmax(peak)])
        regions.append(RegionSolution(
            strips=idx, reference=ref, x_lead_mm=x_lead, p0_MPa=float(line_max.max()), I1_mm3=float("nan"),
            I2_mm2=float("nan"), u_layer_mm=u_ref, normal_force_N=run_force, layer_segments=0,
            approach_mm=approach, interaction_mm=0.0))
    main = max(regions, key=lambda r: r.p0_MPa)
    iterations = {"cg_iterations": stats["cg_iterations"], "layer_iterations": stats["layer_iterations"],
                  "boxes": stats["boxes"], "grid_cells": [int(grid.y.size), int(grid.x.size)],
                  "cell_mm": [float(grid.dx), float(grid.dy)], "extrapolated": bool(options.extrapolate)}
    n_total = float(sum(r.normal_force_N for r in regions))
    return NormalSolution(
        patches=patches, regions=regions, delta_mm=delta, delta0_mm=float(prob.alpha * delta), p_max_MPa=p_max,
        length_mm=length, width_mm=width, area_mm2=area, u0_mm=float(main.u_layer_mm), strip_y_mm=ys,
        p_peak_MPa=p_peak, iterations=iterations, residual_N=n_total - prob.normal_force_N,
        elastic=layer_is_elastic(layer, ys, h, p_peak), normal_force_N=n_total, method="coarse_exact", field=None,
        grid_pressure=on_grid)
