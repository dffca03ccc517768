"""Independent reference for the elastic-plastic Hertz-pressure benchmark: the same problem solved with Tamaas.

Tamaas (PyPI ``tamaas``, tested with 2.9.0) implements the Fourier-accelerated volume-integral method of
L. Frérot, M. Bonnet, J.-F. Molinari & G. Anciaux, "A Fourier-accelerated volume integral method for
elastoplastic contact", Computer Methods in Applied Mechanics and Engineering 351, 951–976 (2019),
doi:10.1016/j.cma.2019.04.006 (library: L. Frérot, G. Anciaux, V. Rey, S. Pham-Ba & J.-F. Molinari, "Tamaas: a
library for elastic-plastic contact of periodic rough surfaces", Journal of Open Source Software 5, 2121 (2020),
doi:10.21105/joss.02121). The body is a half-space, periodic in x and y (period L), plastic strain allowed in the
layer 0 <= z <= Lz; von Mises plasticity with linear isotropic hardening (``IsotropicHardening``, hardening modulus
d sigma_y / d eps_p_cum). No finite elements: the unknown is the strain on a regular grid, the elastic fields come
from the Boussinesq (surface traction) and Mindlin (eigenstress) integral operators applied in Fourier space.

Problem solved (units mm, MPa): prescribed circular Hertz pressure p0 sqrt(1 - (r/a)^2) centred in the periodic
cell, raised in steps, unloaded to zero from some levels; no indenter, as in ``bench_fem_validation``.

How the library is driven (Tamaas 2.9, read from its Python sources and docstrings and checked numerically here):

* ``Model(volume_2d, [Lz, L, L], [Nz, N, N])``: index 0 of the first axis is the surface, layer k is at depth
  z = k Lz / (Nz - 1); surface grid points at x = i L / N. E and nu must be set before the ``Residual`` is made.
* ``model.traction[..., 2] > 0`` is a compressive pressure (checked: sigma_zz = -p at the surface), u_z > 0 is
  into the body.
* ``Residual`` solves eps - grad N[sigma_eig(eps)] - grad M[t] = 0 for the strain INCREMENT of the step, with the
  traction field holding the traction INCREMENT; ``EPSolver.updateState()`` commits the increment to the model
  fields 'strain', 'plastic_strain', 'cumulated_plastic_strain', 'stress'. (Checked on L = 4 a, dx = a/8: the
  steps 1.5, 1.6, ..., 2.0 Y with increments give a dent of 0.707 µm, one step 0 -> 2.0 Y 0.718 µm; writing the
  full pressure at every step applies it again and gives 2.9 mm.)
* The inelastic (residual) surface displacement is the Mindlin operator applied to the eigenstress C : eps_p of
  the committed total plastic strain; it equals the sum of the step increments the solver reports (checked).
  The elastic part is linear in p0 and is not needed: u_pl = u - c_el p0 is exactly this residual part.

Displacements of a periodic model are defined up to a constant, so the dent and u_pl are measured as
u_z(centre) - u_z(cell corner), the corner being the point farthest from the load (L / sqrt 2). The FEM of
``bench_fem_validation`` measures them against its clamped far faces 20 a away; the dependence on L is part of
the convergence study in docs/calibration.md.

Plastic zone: the grid points with cumulated plastic strain > 0 (z_top, z_bottom; the FEM's definition) and
> ``threshold`` (z_top_thr, z_bottom_thr); top / bottom are the smallest / largest depth of such points (anywhere in
the cell, not only on the axis), resolution dz = dx.
"""

from __future__ import annotations

import dataclasses
import time
from typing import Any

import numpy as np

#: Tamaas version this module was written and verified with
TESTED_VERSION = "2.9.0"
CITATION = ("L. Frérot, M. Bonnet, J.-F. Molinari & G. Anciaux, A Fourier-accelerated volume integral method for "
            "elastoplastic contact, Comput. Methods Appl. Mech. Eng. 351, 951-976 (2019), "
            "doi:10.1016/j.cma.2019.04.006; Tamaas: Frérot et al., JOSS 5, 2121 (2020), doi:10.21105/joss.02121")


def tamaas_version() -> str | None:
    """Installed Tamaas version, or None when it cannot be imported."""
    try:
        import tamaas
    except Exception:  # noqa: BLE001 - any import failure means "not available"
        return None
    return str(tamaas.__version__)


@dataclasses.dataclass(frozen=True)
class TamaasSettings:
    """Grid, material and load path of one Tamaas run (lengths in units of the contact radius a, stresses MPa).

    period_a: period L / a of the cell in x and y; dx_a: grid spacing / a in x, y and z (N = L/dx points per
    direction, must be an even integer so that a grid point sits at the load centre); depth_a: depth Lz / a of
    the plastic layer (Nz = Lz/dx + 1 layers). levels_Y: p0 / Y at which the state is recorded, reached in steps
    of at most step_Y from start_Y (one elastic step from zero), passing through the probe_Y levels (onset of
    plasticity); unload_Y: levels from which the body is unloaded to zero (state restored afterwards);
    threshold: second cumulated-plastic-strain threshold of the zone extent (the first is 0); tolerance: DF-SANE residual
    tolerance (Tamaas' default 1e-9).
    """

    period_a: float = 8.0
    dx_a: float = 1.0 / 8.0
    depth_a: float = 2.0
    E_MPa: float = 210000.0
    poisson: float = 0.3
    yield_MPa: float = 500.0
    hardening_MPa: float = 0.0
    a_mm: float = 1.0
    levels_Y: tuple[float, ...] = (2.0, 2.6, 3.0)
    unload_Y: tuple[float, ...] = (2.0, 2.6, 3.0)
    step_Y: float = 0.1
    start_Y: float = 1.5
    probe_Y: tuple[float, ...] = (1.55, 1.65)
    threshold: float = 1e-5
    tolerance: float = 1e-9

    @property
    def n_xy(self) -> int:
        n = self.period_a / self.dx_a
        if abs(n - round(n)) > 1e-9 or round(n) % 2:
            raise ValueError(f"period_a / dx_a must be an even integer, got {n}")
        return int(round(n))

    @property
    def n_z(self) -> int:
        n = self.depth_a / self.dx_a
        if abs(n - round(n)) > 1e-9:
            raise ValueError(f"depth_a / dx_a must be an integer, got {n}")
        return int(round(n)) + 1


def load_steps(levels: tuple[float, ...], step: float, start: float, extra: tuple[float, ...] = ()) -> list[float]:
    """p0 / Y of every load step: ``start`` (a level below first yield, reached in one elastic step from zero),
    then the multiples of ``step`` above it, the ``levels`` and the ``extra`` levels, ascending, up to the largest
    level (as the FEM benchmark: 0.1 Y steps)."""
    top = max(levels)
    grid = {round(k * step, 9) for k in range(int(np.ceil(start / step)), int(np.floor(top / step + 1e-9)) + 1)}
    targets = {round(v, 9) for v in (*levels, *extra) if start < v <= top} | {v for v in grid if v > start}
    return [start] + sorted(targets)


def zone_extent(cum_plastic: np.ndarray, z_a: np.ndarray, threshold: float) -> tuple[float, float, int]:
    """(top, bottom, count): smallest and largest depth (same units as ``z_a``) of the points whose cumulated
    plastic strain exceeds ``threshold``; NaN, NaN, 0 when there is none. ``cum_plastic`` has the depth on its
    first axis."""
    mask = cum_plastic > threshold
    layers = np.flatnonzero(mask.reshape(mask.shape[0], -1).any(axis=1))
    if layers.size == 0:
        return float("nan"), float("nan"), 0
    return float(z_a[layers[0]]), float(z_a[layers[-1]]), int(mask.sum())


def hertz_axis_von_mises(zeta: np.ndarray, nu: float) -> np.ndarray:
    """von Mises stress / p0 on the axis of a circular Hertz pressure at depth zeta = z/a (Johnson 1985,
    eq. 3.45)."""
    zeta = np.maximum(np.asarray(zeta, dtype=float), 1e-12)
    s_r = -(1 + nu) * (1 - zeta * np.arctan(1 / zeta)) + 0.5 / (1 + zeta ** 2)
    s_z = -1 / (1 + zeta ** 2)
    return np.abs(s_z - s_r)


def solve(settings: TamaasSettings, verbose: bool = False) -> dict:
    """Run the prescribed-pressure load path with Tamaas and return the reference quantities.

    Returns a JSON-serialisable dict: ``elastic`` (first yield p0/Y from the grid maximum of the elastic von Mises
    stress, its depth z/a refined by a parabola through the three axis points around the maximum, and the largest
    deviation of the axis von Mises stress from Johnson eq. 3.45 in units of p0), ``onset_Y`` (first load step
    with a plastic point, and the step before it), ``levels`` (one row per recorded level: p0_over_Y, u_pl_um =
    inelastic centre displacement under load, dent_um after unloading to zero, z_top / z_bottom of the plastic
    zone / a (cumulated plastic strain > 0, and z_top_thr / z_bottom_thr > threshold), n_plastic, reverse-yield check: max increase of cumulated plastic strain during the unloading,
    hardening check: largest |von Mises - (Y + H eps_p_cum)| / Y over the points yielding in the last step;
    equivalent-strain check: largest |eps_p_cum - |eps_p_zz|| on the axis / max eps_p_cum there),
    ``grid``, ``time_s`` and ``stopped`` (None, or why the path stopped early: the plastic zone reached the
    bottom of the layer, Lz too small; the levels above are then missing). Raises ImportError when Tamaas is not
    installed."""
    import tamaas as tm  # optional dependency: imported only when a reference run is asked for

    t_start = time.perf_counter()
    s = settings
    cell = _cell(tm, s)
    elastic = _elastic_check(cell, s)
    onset, last_elastic, prev = None, 0.0, 0.0
    rows, step_log, stopped = [], [], None
    dz_a = cell.z_a[1] - cell.z_a[0]
    for f in load_steps(s.levels_Y, s.step_Y, s.start_Y, s.probe_Y):
        t0 = time.perf_counter()
        cum_before = np.array(cell.model["cumulated_plastic_strain"])
        _apply_increment(cell, (f - prev) * s.yield_MPa)
        prev = f
        cum = np.array(cell.model["cumulated_plastic_strain"])
        top, bottom, count = zone_extent(cum, cell.z_a, 0.0)
        if onset is None:
            if (cum > 0).any():
                onset = (last_elastic, f)
            else:
                last_elastic = f
        if np.isfinite(bottom) and bottom >= cell.z_a[-1] - 1.5 * dz_a:
            stopped = (f"plastic zone reaches the bottom of the layer (z = {bottom:.3f} a) at p0 = {f:g} Y: "
                       "load path stopped there (increase depth_a)")
            break
        step_log.append({"p0_over_Y": f, "time_s": time.perf_counter() - t0})
        if verbose:
            print(f"  tamaas p0 = {f:.3f} Y: zone {top:.3f}-{bottom:.3f} a, {count} points, "
                  f"{time.perf_counter() - t0:.1f} s", flush=True)
        if not any(abs(f - lev) < 1e-9 for lev in s.levels_Y):
            continue
        row = _level_row(cell, s, f, cum, cum_before, top, bottom, count)
        if any(abs(f - lev) < 1e-9 for lev in s.unload_Y):
            row.update(_unload(cell, s, f))
        rows.append(row)
    return {"settings": dataclasses.asdict(s), "tamaas_version": tamaas_version(),
            "grid": {"n_xy": cell.n, "n_z": cell.nz, "dx_mm": s.dx_a * s.a_mm,
                     "unknowns": int(cell.nz * cell.n * cell.n * 6)},
            "elastic": elastic, "onset_Y": list(onset) if onset else None, "levels": rows,
            "steps": step_log, "stopped": stopped, "time_s": time.perf_counter() - t_start}


#: the model fields that make up the state of a load step (saved before an unloading, restored after it)
STATE_FIELDS = ("strain", "plastic_strain", "cumulated_plastic_strain", "stress")


@dataclasses.dataclass(frozen=True)
class _Cell:
    """One Tamaas model of the periodic cell and what the load path needs of it (lengths mm, depths z / a)."""

    tm: Any
    model: Any
    material: Any
    residual: Any
    solver: Any
    shape: np.ndarray
    z_a: np.ndarray
    n: int
    nz: int
    c: int


def _cell(tm: Any, s: TamaasSettings) -> _Cell:
    """The model, its J2 isotropic-hardening material and DF-SANE solver, and the unit Hertz pressure shape."""
    from tamaas.nonlinear_solvers import DFSANECXXSolver  # optional dependency, as in solve

    tm.set_log_level(tm.LogLevel.warning)
    a = s.a_mm
    n, nz = s.n_xy, s.n_z
    length, depth = s.period_a * a, s.depth_a * a
    model = tm.ModelFactory.createModel(tm.model_type.volume_2d, [depth, length, length], [nz, n, n])
    model.E, model.nu = s.E_MPa, s.poisson
    material = tm.materials.IsotropicHardening(model, sigma_y=s.yield_MPa, hardening=s.hardening_MPa)
    residual = tm.Residual(model, material)
    solver = DFSANECXXSolver(residual)
    solver.tolerance = s.tolerance
    x = np.arange(n) * length / n
    gx, gy = np.meshgrid(x, x, indexing="ij")
    c = n // 2
    shape = np.sqrt(np.clip(1.0 - ((gx - x[c]) ** 2 + (gy - x[c]) ** 2) / a ** 2, 0.0, None))
    z_a = np.arange(nz) * (depth / (nz - 1)) / a
    # the material and residual are kept with the solver: the C++ solver refers to them
    return _Cell(tm, model, material, residual, solver, shape, z_a, n, nz, c)


def _von_mises(cell: _Cell, stress: np.ndarray) -> np.ndarray:
    tm = cell.tm
    vm = np.zeros(stress.shape[:-1] + (1,))
    tm.compute.von_mises(tm.model_type.volume_2d, vm, np.ascontiguousarray(stress))
    return vm[..., 0]


def _elastic_check(cell: _Cell, s: TamaasSettings) -> dict:
    """The elastic field of p0 = 1 MPa (operators only, no plasticity) against Johnson eq. 3.45 on the axis."""
    n, nz, c, z_a, model = cell.n, cell.nz, cell.c, cell.z_a, cell.model
    trac = np.zeros((n, n, 3))
    trac[..., 2] = cell.shape
    strain = np.zeros((nz, n, n, 6))
    model.operators["boussinesq_gradient"](trac, strain)
    stress = np.zeros_like(strain)
    model.operators["hooke"](strain, stress)
    vm1 = _von_mises(cell, stress)
    k = int(np.argmax(vm1[:, c, c]))
    y0, y1, y2 = vm1[k - 1, c, c], vm1[k, c, c], vm1[k + 1, c, c]
    shift = 0.5 * (y0 - y2) / (y0 - 2 * y1 + y2)
    dz_a = z_a[1] - z_a[0]
    axis_dev = vm1[:, c, c] - hertz_axis_von_mises(z_a, s.poisson)
    return {"first_yield_over_Y": float(1.0 / vm1.max()),
            "first_yield_axis_parabola_over_Y": float(1.0 / (y1 - 0.25 * (y0 - y2) * shift)),
            "depth_over_a": float(z_a[k] + shift * dz_a),
            "axis_vm_max_dev_per_p0": float(np.abs(axis_dev).max()),
            "axis_vm_dev_at_max_per_p0": float(axis_dev[k]),
            "centre_szz_surface_per_p0": float(stress[0, c, c, 2])}


def _apply_increment(cell: _Cell, dp0_MPa: float) -> None:
    """Solve one step whose Hertz pressure changes by ``dp0_MPa`` and commit it (the traction holds the increment)."""
    cell.model.traction[...] = 0.0
    cell.model.traction[..., 2] = dp0_MPa * cell.shape
    cell.solver.solve()
    cell.solver.updateState()


def _plastic_displacement_um(cell: _Cell) -> float:
    """Inelastic surface displacement u_z(centre) - u_z(corner) (µm): Mindlin operator of C : eps_p."""
    model, n, nz, c = cell.model, cell.n, cell.nz, cell.c
    eps_p = np.ascontiguousarray(np.array(model["plastic_strain"]))
    eig = np.zeros_like(eps_p)
    model.operators["hooke"](eps_p, eig)
    u = np.zeros((nz, n, n, 3))
    model.operators["mindlin"](eig, u)
    return float((u[0, c, c, 2] - u[0, 0, 0, 2]) * 1000.0)


def _level_row(cell: _Cell, s: TamaasSettings, f: float, cum: np.ndarray, cum_before: np.ndarray, top: float,
               bottom: float, count: int) -> dict:
    """The recorded quantities at the level p0 = ``f`` Y, with the yield-surface and equivalent-strain checks."""
    c = cell.c
    grew = (cum - cum_before) > 0
    vm = _von_mises(cell, np.array(cell.model["stress"]))
    hard_err = (float(np.abs(vm[grew] - (s.yield_MPa + s.hardening_MPa * cum[grew])).max() / s.yield_MPa)
                if grew.any() else float("nan"))
    top_t, bottom_t, _ = zone_extent(cum, cell.z_a, s.threshold)
    # on the axis the plastic strain is axisymmetric with a fixed direction (-1/2, -1/2, 1) eps_zz, so the
    # accumulated equivalent plastic strain int sqrt(2/3 deps:deps) must equal |eps_p_zz| there
    eps_axis = np.array(cell.model["plastic_strain"])[:, c, c, 2]
    eq_check = float(np.abs(cum[:, c, c] - np.abs(eps_axis)).max() / max(cum[:, c, c].max(), 1e-300))
    return {"p0_over_Y": f, "u_pl_um": _plastic_displacement_um(cell), "z_top": top, "z_bottom": bottom,
            "z_top_thr": top_t, "z_bottom_thr": bottom_t, "n_plastic": count, "yield_surface_check": hard_err,
            "eq_strain_axis_check": eq_check}


def _unload(cell: _Cell, s: TamaasSettings, f: float) -> dict:
    """Unload from p0 = ``f`` Y to zero: the dent (µm) and the reverse-yield check; the loaded state is restored."""
    model = cell.model
    saved = {k: np.array(model[k]) for k in STATE_FIELDS}
    model.traction[..., 2] = -f * s.yield_MPa * cell.shape
    cell.solver.solve()
    cell.solver.updateState()
    out = {"dent_um": _plastic_displacement_um(cell),
           "unload_reverse_yield": float((np.array(model["cumulated_plastic_strain"]) - saved[
               "cumulated_plastic_strain"]).max())}
    for k in STATE_FIELDS:
        model[k][...] = saved[k]
    model.traction[...] = 0.0
    return out
