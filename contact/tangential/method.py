"""One call for the tangential problem on a pressure grid: FASTSIM, FaStrip or Kalker's exact theory.

Units: mm, N, MPa, s. The input is a :class:`PressureGrid` (the exact normal solver's cells, or a Kik–Piotrowski
patch rasterised onto such cells); :func:`solve_on_grid` returns one
:class:`contact.tangential.fastsim.TangentialResult` per contact region for every method, so the frictional
outputs, pictures and result keys work unchanged:

- "fastsim": Kalker's simplified theory (:mod:`contact.tangential.fastsim`) on one strip per loaded line, each
  strip from its line's first to its last loaded cell, carrying that line's cell pressures;
- "fastrip": the FaStrip strip theory (:mod:`contact.tangential.fastrip`) on the same strips;
- "exact": Kalker's full theory on the grid itself (:mod:`contact.tangential.exact_rolling`).

Rows of a region's result are its lines; columns run from the leading edge (+x) to the trailing edge, as
FASTSIM's. Creepages act about the grid frame's origin (x = 0, y = 0); creepages
given about another point are moved there with :meth:`contact.tangential.fastsim.Creepage.about`.
"""

from __future__ import annotations

from contextlib import contextmanager
from dataclasses import dataclass, replace

import numpy as np

from contact.normal.coarse_tangential import tangential_grid
from contact.normal.exact import fastsim_pressure, strip_centres
from contact.normal.kik_piotrowski import NormalSolution
from contact.normal.patch import Patch
from contact.tangential.exact_rolling import RollingOptions, solve_rolling
from contact.tangential.fastrip import solve_fastrip
from contact.tangential.fastsim import Creepage, StripCells, TangentialResult, equivalent_ellipse
from contact.tangential.spin_centre import solve_about_centroid
from wrlayer.errors import ConvergenceError, require

__all__ = ["ROW_FIELDS", "TANGENTIAL_METHODS", "PressureGrid", "on_strips", "solve_on_grid", "solve_for_normal_solution",
           "strip_rows"]

#: Values of ``method.tangential``.
TANGENTIAL_METHODS = ("fastsim", "fastrip", "exact")
#: The per-row fields of a TangentialResult (one row per strip or grid line).
ROW_FIELDS = ("dx_mm", "x_mm", "pn_MPa", "tx_MPa", "ty_MPa", "slip", "slip_velocity_mm_s", "PT_W_per_mm2",
              "WT_field_N_per_mm", "WT_N_per_mm")


@dataclass(frozen=True)
class PressureGrid:
    """Normal pressure on a uniform grid of rectangular cells (the exact normal solver's).

    Attributes
    ----------
    x_mm : numpy.ndarray
        (nx,) cell centres along the rolling direction, uniform and increasing; +x is the leading side (mm).
    y_mm : numpy.ndarray
        (ny,) line (cell row) centres, uniform and increasing (mm).
    p_MPa : numpy.ndarray
        (ny, nx) cell pressures >= 0 (MPa).
    """

    x_mm: np.ndarray
    y_mm: np.ndarray
    p_MPa: np.ndarray

    def __post_init__(self):
        x = np.asarray(self.x_mm, dtype=float)
        y = np.asarray(self.y_mm, dtype=float)
        p = np.asarray(self.p_MPa, dtype=float)
        require(x.ndim == 1 and x.size >= 2 and y.ndim == 1 and y.size >= 1, "pressure grid",
                "needs at least 2 cells along x and 1 line")
        require(p.shape == (y.size, x.size), "pressure grid", f"p_MPa must have shape ({y.size}, {x.size})")
        require(bool(np.all(np.isfinite(p)) and np.all(p >= 0) and np.any(p > 0)), "pressure grid",
                "p_MPa must be finite, >= 0 and somewhere > 0")
        for name, v in (("x_mm", x), ("y_mm", y)):
            if v.size > 1:
                d = np.diff(v)
                require(bool(np.all(d > 0) and np.ptp(d) <= 1e-9 * d[0] * v.size), f"pressure grid.{name}",
                        "must be uniform and increasing")
        object.__setattr__(self, "x_mm", x)
        object.__setattr__(self, "y_mm", y)
        object.__setattr__(self, "p_MPa", p)

    @property
    def dx_mm(self) -> float:
        return float(self.x_mm[1] - self.x_mm[0])

    @property
    def dy_mm(self) -> float:
        return float(self.y_mm[1] - self.y_mm[0]) if self.y_mm.size > 1 else self.dx_mm

    @classmethod
    def from_exact(cls, solution, region: int | None = None, y_ref_mm: float = 0.0) -> "PressureGrid":
        """The exact normal solution's pressure (``solution.field``, :class:`contact.normal.exact.ExactField`);
        only the lines of patch ``region`` when given (else every region); y measured from ``y_ref_mm`` (mm)."""
        fld = solution.field
        p = fld.p_MPa
        if region is not None:
            rows = np.searchsorted(fld.lines, solution.regions[region].strips)
            keep = np.zeros(p.shape[0], dtype=bool)
            keep[rows] = True
            p = np.where(keep[:, None], p, 0.0)
        return cls(fld.x_mm, fld.y_mm - y_ref_mm, p)

    @classmethod
    def from_patch(cls, patch: Patch, nx: int = 60) -> "PressureGrid":
        """A strip patch (Kik–Piotrowski's semi-elliptic strips, eq. 11) on cells of the patch's strip width and
        nx cells over its length; each cell carries the mean of its strip's pressure over the cell (exact)."""
        L = patch.x_lead_mm.max()
        dx = 2.0 * L / nx
        x = (np.arange(nx) - 0.5 * (nx - 1)) * dx
        lo, hi = x - 0.5 * dx, x + 0.5 * dx
        a = patch.x_lead_mm[:, None]
        u_lo, u_hi = np.clip(lo[None, :] / a, -1, 1), np.clip(hi[None, :] / a, -1, 1)
        prim = lambda u: 0.5 * (u * np.sqrt(1.0 - u * u) + np.arcsin(u))  # noqa: E731 - Int sqrt(1 - u^2)
        p = patch.p_peak_MPa[:, None] * a * (prim(u_hi) - prim(u_lo)) / dx
        return cls(x, patch.y_mm, p)

    def regions(self) -> list[np.ndarray]:
        """Line indices of each contact region: the runs of consecutive loaded lines, in increasing y."""
        on = np.flatnonzero(self.p_MPa.max(axis=1) > 0)
        return np.split(on, np.flatnonzero(np.diff(on) > 1) + 1)

    def _line_ends(self, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(first loaded cell's trailing edge, last loaded cell's leading edge (mm), force per unit width (N/mm))
        of each line in ``rows``."""
        on = self.p_MPa[rows] > 0
        dx, nx = self.dx_mm, self.x_mm.size
        lo = self.x_mm[np.argmax(on, axis=1)] - 0.5 * dx
        hi = self.x_mm[nx - 1 - np.argmax(on[:, ::-1], axis=1)] + 0.5 * dx
        return lo, hi, self.p_MPa[rows].sum(axis=1) * dx

    def line_patch(self, rows: np.ndarray) -> tuple[Patch, np.ndarray]:
        """(Patch, strip centres (ny,)) of the loaded lines ``rows``: each line a strip from its first to its last
        loaded cell (whole cells), with the semi-ellipse of the line's force as p_peak (eq. 12)."""
        lo, hi, force = self._line_ends(rows)
        half = 0.5 * (hi - lo)
        return Patch(self.dy_mm, self.y_mm[rows], half, force / (0.5 * np.pi * half)), 0.5 * (hi + lo)

    def strips(self, rows: np.ndarray, nx: int) -> tuple[Patch, np.ndarray, np.ndarray]:
        """(Patch, cell pressures (ny, nx) from the leading edge, strip centres (ny,)) of the loaded lines ``rows``
        for the strip methods: the strips of :meth:`line_patch`, each with nx cell pressures interpolated linearly
        in the line's pressure (0 at the strip's ends) and scaled to the line's force."""
        pn = []
        frac = (np.arange(nx) + 0.5) / nx
        for r, lo, hi, force in zip(rows, *self._line_ends(rows)):
            line = self.p_MPa[r]
            on = np.flatnonzero(line > 0)
            xs = np.concatenate([[lo], self.x_mm[on[0]:on[-1] + 1], [hi]])
            ps = np.concatenate([[0.0], line[on[0]:on[-1] + 1], [0.0]])
            cells = np.interp(hi - frac * (hi - lo), xs, ps)
            pn.append(cells * force / (cells.sum() * (hi - lo) / nx))
        patch, centre = self.line_patch(rows)
        return patch, np.array(pn), centre


def _exact(grid: PressureGrid, creepage: Creepage, G_MPa, poisson, friction, speed_mm_s, options,
           start: list[TangentialResult] | None = None) -> list[TangentialResult]:
    """Kalker's full theory on all regions of the grid at once (their elastic interaction included), one
    TangentialResult per region (rows: its lines; columns from the leading edge); started from the tractions of
    ``start`` (an earlier solve of one region on a grid of the same shape), if given."""
    regions = grid.regions()
    lines = np.arange(regions[0][0], regions[-1][-1] + 1)
    y, x, p = grid.y_mm[lines], grid.x_mm, grid.p_MPa[lines]
    X, Y = np.meshgrid(x, y)
    initial = None
    if start is not None and len(start) == 1 and len(regions) == 1:
        initial = (start[0].tx_MPa[:, ::-1], start[0].ty_MPa[:, ::-1])
    sol = solve_rolling(x, y, p, creepage.vx - creepage.phi_per_mm * Y, creepage.vy + creepage.phi_per_mm * X,
                        friction, G_MPa, poisson, options, initial)
    dx, dy = grid.dx_mm, grid.dy_mm
    out = []
    for rows in regions:
        k = np.s_[rows - lines[0], ::-1]             # the region's lines, columns from the leading edge
        slip_speed = np.hypot(sol.sx, sol.sy)[k]
        t_x, t_y, pr = sol.tx_MPa[k], sol.ty_MPa[k], p[k]
        work = np.hypot(t_x, t_y) * slip_speed * dx       # N/mm per cell and pass
        patch, _ = grid.line_patch(rows)
        cells = StripCells(np.ascontiguousarray(X[k]), np.full(rows.size, dx), np.zeros(rows.size), pr, creepage,
                           float(friction), float(speed_mm_s))
        res = cells.result(patch, t_x, t_y, sol.slip[k], slip_speed * speed_mm_s, work,
                           equivalent_ellipse(patch, G_MPa, poisson), "exact", (np.nan, np.nan, np.nan),
                           sol.iterations, sol.residual)
        # the grid's cells, not the strips' extents, carry the pressure: force and areas from the cells
        loaded = float(np.count_nonzero(pr > 0) * dx * dy)
        out.append(replace(res, normal_force_N=float(pr.sum() * dx * dy),
                           adhesion_area_mm2=loaded - res.slip_area_mm2))
    return out


def solve_on_grid(grid: PressureGrid, creepage: Creepage, friction: float, G_MPa: float, poisson: float,
                  method: str = "exact", speed_mm_s: float = 1000.0, nx: int = 60,
                  options: RollingOptions = RollingOptions(), start: list[TangentialResult] | None = None
                  ) -> list[TangentialResult]:
    """The tangential solution of ``method`` ("fastsim", "fastrip" or "exact") on the grid's pressure: one
    TangentialResult per contact region (:meth:`PressureGrid.regions`), Mz of each about the grid's origin (so
    they add up).

    creepage: about the grid frame's origin; friction: Coulomb mu; G_MPa, poisson: the common material (shear
    modulus E / (2 (1 + nu)) in MPa); speed_mm_s: rolling speed V; nx: cells per strip of the strip methods;
    options: the exact solver's. FASTSIM takes the spin about each region's force centroid
    (:func:`contact.tangential.spin_centre.solve_about_centroid`). ConvergenceError when the exact solver or a
    FaStrip strip does not converge. ``start``: the exact solver's starting tractions (see :func:`_exact`).
    """
    require(method in TANGENTIAL_METHODS, "method.tangential", f"must be one of {TANGENTIAL_METHODS}, got {method!r}")
    if method == "exact":
        return _exact(grid, creepage, G_MPa, poisson, friction, speed_mm_s, options, start)
    solver = solve_about_centroid if method == "fastsim" else solve_fastrip
    out = []
    for rows in grid.regions():
        patch, pn, xc = grid.strips(rows, nx)
        out.append(solver(patch, creepage, G_MPa, poisson, friction, speed_mm_s, nx=nx, pressure_cells_MPa=pn,
                          strip_centre_mm=xc))
    return out


def solve_for_normal_solution(solution: NormalSolution, creepage: Creepage, friction: float, G_MPa: float,
                              poisson: float, method: str = "fastsim", speed_mm_s: float = 1000.0, nx: int = 60,
                              flexibility: str = "three", options: RollingOptions = RollingOptions(),
                              origin_y_mm: float = 0.0, start: list[TangentialResult] | None = None
                              ) -> list[TangentialResult]:
    """The tangential solution of every patch of a normal solution (Kik–Piotrowski or exact), in its order.

    Frame: the solution's strips measured from ``origin_y_mm`` (mm, the solution's strip coordinate; x = 0 at the
    separation's reference point); creepage about that origin; each result's Mz about it (so the patches' moments
    add up) and its strip y in it.
    "fastsim": FASTSIM with the spin about each patch's force centroid
    (:func:`contact.tangential.spin_centre.solve_about_centroid`) on the patch's strips, with the exact pressure
    along each line for an exact solution (:func:`contact.normal.exact.fastsim_pressure`, ``strip_centres``);
    "fastrip": FaStrip on the same strips; "exact": Kalker's full theory on the exact solver's grid (all patches
    at once), or, for a Kik–Piotrowski solution, on each patch rasterised with ``nx`` cells along x
    (:meth:`PressureGrid.from_patch`; the patches then do not interact tangentially).
    InputError when a patch carries no pressure; ConvergenceError naming the patch when a solve does not converge.
    ``start``: an earlier result of the same solution's kind (e.g. the previous load of a balance iteration), the
    exact theory's starting tractions on the exact grid, or per patch FaStrip's (the same solution to the
    tolerance, in fewer sweeps).
    """
    require(method in TANGENTIAL_METHODS, "method.tangential", f"must be one of {TANGENTIAL_METHODS}, got {method!r}")
    patches = [p if origin_y_mm == 0.0 else Patch(p.grid_mm, p.y_mm - origin_y_mm, p.x_lead_mm, p.p_peak_MPa)
               for p in solution.patches]
    for k, p in enumerate(patches):
        require(bool(np.any(p.p_peak_MPa > 0) and np.any(p.x_lead_mm > 0)), f"patch {k + 1}",
                f"carries no pressure: no tangential solution ({method})")
    exact_field = getattr(solution, "field", None) is not None
    on_grid = getattr(solution, "grid_pressure", None)
    if method == "exact" and (exact_field or on_grid is not None):
        if exact_field:
            grid = PressureGrid.from_exact(solution, y_ref_mm=origin_y_mm)
        else:
            fine = tangential_grid(on_grid)
            grid = PressureGrid(fine.x_mm, fine.y_mm - origin_y_mm, fine.p_MPa)
        with _naming("patches 1.." + str(len(patches)), method):
            return solve_on_grid(grid, creepage, friction, G_MPa, poisson, "exact", speed_mm_s, nx, options, start)
    out = []
    same = start is not None and len(start) == len(patches)
    for k, patch in enumerate(patches):
        with _naming(f"patch {k + 1}", method):
            out.append(_one_patch(solution, k, patch, creepage, friction, G_MPa, poisson, method, speed_mm_s, nx,
                                  flexibility, options, start[k] if same else None))
    return out


def _one_patch(solution, k: int, patch: Patch, creepage: Creepage, friction, G_MPa, poisson, method, speed_mm_s,
               nx, flexibility, options, start: TangentialResult | None = None) -> TangentialResult:
    """Patch ``k`` of ``solution`` (``patch``: in the frame to solve in) by a strip method or, for a
    Kik–Piotrowski solution, by the exact theory on the patch rasterised with ``nx`` cells. ``start``: the same
    patch's earlier solution by the same method: FaStrip's start (:func:`contact.tangential.fastrip.start_tractions`),
    the exact theory's starting tractions when the raster has the same shape."""
    if method == "exact":
        grid = PressureGrid.from_patch(patch, nx)
        same = start is not None and start.method == "exact" and start.tx_MPa.shape == grid.p_MPa.shape
        return solve_on_grid(grid, creepage, friction, G_MPa, poisson, "exact", speed_mm_s, nx, options,
                             [start] if same else None)[0]
    kw = {}
    if getattr(solution, "field", None) is not None:
        kw = {"pressure_cells_MPa": fastsim_pressure(solution, k, nx), "strip_centre_mm": strip_centres(solution, k)}
    if method == "fastsim":
        return solve_about_centroid(patch, creepage, G_MPa, poisson, friction, speed_mm_s, nx,
                                    flexibility=flexibility, **kw)
    return solve_fastrip(patch, creepage, G_MPa, poisson, friction, speed_mm_s, nx, start=start, **kw)


def on_strips(result: TangentialResult, y_mm: np.ndarray) -> TangentialResult:
    """``result`` with one row per strip at ``y_mm`` (mm, the frame of ``result.y_mm``): each strip takes the row of
    the result's line nearest to it; the totals (forces, moment, areas, maxima) stay the solve's."""
    y = np.asarray(y_mm, dtype=float)
    k = np.abs(np.asarray(result.y_mm)[None, :] - y[:, None]).argmin(axis=1)
    return replace(result, y_mm=y, **{name: np.asarray(getattr(result, name))[k] for name in ROW_FIELDS})


def strip_rows(results: list, solution: NormalSolution, origin_y_mm: float = 0.0) -> list:
    """The tangential results of ``solution``'s patches (its order; None entries kept) with one row per strip, for
    the writers that pair them with the strips: the exact theory on a coarse-grid solution solved on the grid's
    lines (:func:`solve_for_normal_solution`), so each strip takes its nearest line (:func:`on_strips`); other
    results are returned as they are. ``origin_y_mm``: the results' strip origin in the solution's strip
    coordinate (mm)."""
    if getattr(solution, "grid_pressure", None) is None:
        return list(results)
    return [on_strips(t, q.y_mm - origin_y_mm) if t is not None and t.method == "exact" else t
            for q, t in zip(solution.patches, results)]


@contextmanager
def _naming(where: str, method: str):
    """A ConvergenceError of the solver, re-raised naming the patch (or patches) and the method."""
    try:
        yield
    except ConvergenceError as err:
        raise ConvergenceError(f"tangential solution ({method}) of {where}: {err}") from None
