"""The FEM validation problem of ``bench_fem_validation``: materials, load path, the FEM solves and the Tamaas runs.

Units mm, N, MPa; lengths in the result rows are in units of the contact radius a where named ``/ a``. The problem
and its references are described in ``benchmarks/bench_fem_validation.py``.
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from benchmarks import tamaas_reference as tr
from calibration.fem.elastoplastic_solver import SolverOptions, solve_load_path
from calibration.fem.material import J2Material, von_mises_MPa
from calibration.hertz.load import HertzLoad

Y_MPA = 500.0
A_MM = 1.0
BLOCK_MM = 20.0
FINE_MM = 1.5
MATERIALS = {
    "elastic-perfectly plastic": J2Material(210000.0, 0.3, Y_MPA),
    "linear hardening (H_iso = H_kin = 10 GPa)": J2Material(210000.0, 0.3, Y_MPA, 10000.0, 10000.0),
    "isotropic hardening (H_iso = 10 GPa, H_kin = 0)": J2Material(210000.0, 0.3, Y_MPA, 10000.0, 0.0),
    "isotropic hardening (H_iso = 20 GPa, H_kin = 0)": J2Material(210000.0, 0.3, Y_MPA, 20000.0, 0.0),
}
#: short names of the materials in the tables
SHORT = {"elastic-perfectly plastic": "EPP", "linear hardening (H_iso = H_kin = 10 GPa)": "hardening",
         "isotropic hardening (H_iso = 10 GPa, H_kin = 0)": "iso. hardening",
         "isotropic hardening (H_iso = 20 GPa, H_kin = 0)": "iso. 20 GPa"}
#: Tamaas hardening modulus (MPa) of the materials it can model (isotropic hardening only)
TAMAAS_HARDENING = {"elastic-perfectly plastic": 0.0, "isotropic hardening (H_iso = 10 GPa, H_kin = 0)": 10000.0,
                    "isotropic hardening (H_iso = 20 GPa, H_kin = 0)": 20000.0}
#: materials Tamaas cannot model -> the isotropic material they equal under proportional loading (module docstring)
TAMAAS_EQUIVALENT = {"linear hardening (H_iso = H_kin = 10 GPa)": "isotropic hardening (H_iso = 20 GPa, H_kin = 0)"}
#: p0 / Y compared with Tamaas (quick; full adds 3.4)
TAMAAS_LEVELS = (2.0, 2.6, 3.0)
DIRICHLET = {"fixed": [0, 1, 2], "side": [0, 1, 2], "symmetry": [0], "sym_y": [1]}
LOAD = HertzLoad(0.0, A_MM, a_mm=A_MM)
#: largest load step (x Y) on the way up
STEP_Y = 0.1
#: p0 / Y at which the state is recorded (loading)
LEVELS_Y = (1.8, 2.0, 2.2, 2.4, 2.6, 2.8, 3.0)
#: p0 / Y from which the body is unloaded to zero (residual dent)
UNLOAD_Y = (2.0, 2.6, 3.0)
#: depth (x a) whose crossing by the top of the plastic zone is reported (the zone rises towards the surface)
TOP_DEPTH = 0.1
#: second plastic-zone threshold (equivalent plastic strain), reported beside "> 0" for both FEM and Tamaas
ZONE_THRESHOLD = 1e-5
#: report rows: key -> (label, scale, format)
ROW_KEYS = {"z_top": ("plastic zone top z / a", 1.0, "{:.3f}"),
            "z_bottom": ("plastic zone bottom z / a", 1.0, "{:.3f}"),
            "volume": ("plastic zone volume / a³", 1.0, "{:.3f}"),
            "dent_mm": ("residual dent [µm]", 1000.0, "{:.3f}")}
#: Tamaas grids (lengths / a): the first is the reference of the tables, the others give its grid difference
TAMAAS_GRIDS = {"quick": [{"period_a": 8.0, "dx_a": 1 / 8, "depth_a": 2.0}],
                "full": [{"period_a": 8.0, "dx_a": 1 / 16, "depth_a": 2.5},
                         {"period_a": 8.0, "dx_a": 1 / 8, "depth_a": 2.5},
                         {"period_a": 16.0, "dx_a": 1 / 8, "depth_a": 2.5}]}
#: compared quantities: key -> (label, FEM key, FEM scale to the Tamaas unit, format)
COMPARE = {"u_pl_um": ("inelastic centre displacement under load u_pl [µm]", "u_pl_mm", 1000.0, "{:.3f}"),
           "dent_um": ("residual dent after unloading [µm]", "dent_mm", 1000.0, "{:.3f}"),
           "z_top": ("plastic zone top z / a (eps_p > 0)", "z_top", 1.0, "{:.3f}"),
           "z_bottom": ("plastic zone bottom z / a (eps_p > 0)", "z_bottom", 1.0, "{:.3f}"),
           "z_top_thr": (f"plastic zone top z / a (eps_p > {ZONE_THRESHOLD:g})", "z_top_thr", 1.0, "{:.3f}"),
           "z_bottom_thr": (f"plastic zone bottom z / a (eps_p > {ZONE_THRESHOLD:g})", "z_bottom_thr", 1.0,
                            "{:.3f}")}


def plastic_zone(disc, state, threshold: float = 0.0) -> dict:
    """Extent of the yielded region (quadrature points with equivalent plastic strain > ``threshold``), lengths / a.

    z_top / z_bottom: smallest / largest depth of a yielded point; r_max: largest distance from the load axis;
    volume: yielded volume of the whole (4 x quarter) model / a^3. Resolution: the quadrature points, i.e. a
    fraction of the element size h (no point lies on the surface: the top cannot be closer than about 0.1 h).
    """
    x = disc.qp_coordinates()
    yielded = state.eq_plastic_strain > threshold
    if not yielded.any():
        return {"z_top": float("nan"), "z_bottom": float("nan"), "r_max": float("nan"), "volume": 0.0}
    depth = -x[2][yielded]
    r = np.hypot(x[0][yielded], x[1][yielded])
    return {"z_top": float(depth.min()) / A_MM, "z_bottom": float(depth.max()) / A_MM,
            "r_max": float(r.max()) / A_MM, "volume": 4.0 * float(disc.dx[yielded].sum()) / A_MM ** 3}


def elastic_reference(disc, mesh) -> dict:
    """Elastic solve at p0 = 1 MPa: first yield / Y (the solver's: largest quadrature-point von Mises stress),
    the depth / a of the von Mises maximum, centre compliance (mm/MPa) and the von Mises stress of the quadrature
    points near the axis (r < 0.15 a) for the figure.

    No quadrature point lies on the axis, so the depth of the maximum is located by a least-squares fit
    vm = c0 + c1 z + c2 z^2 + c3 z^3 + c4 r^2 to the points with r < 0.3 a and 0.2 a < z < 0.8 a (maximum of the
    cubic on that range). The maximum is flat: other fits (quadratic on 0.25-0.75 a, quartic on 0.2-0.9 a) move
    the depth by up to 5 %, the peak value by 0.3 %."""
    mat = MATERIALS["elastic-perfectly plastic"]
    res = solve_load_path(mesh, mat, LOAD, [1.0], options=SolverOptions(dirichlet=DIRICHLET), disc=disc)
    u = res.state.u_mm
    vm = von_mises_MPa(disc.strain(u) @ mat.elastic_matrix())
    x = disc.qp_coordinates()
    r, z = np.hypot(x[0], x[1]) / A_MM, -x[2] / A_MM
    sel = (r < 0.3) & (z > 0.2) & (z < 0.8)
    coef = np.linalg.lstsq(np.column_stack([z[sel] ** k for k in range(4)] + [r[sel] ** 2]), vm[sel], rcond=None)[0]
    zz = np.linspace(0.2, 0.8, 6001)
    depth = float(zz[np.argmax(sum(coef[k] * zz ** k for k in range(4)))])
    near_axis = r < 0.15
    return {"first_yield_over_Y": res.first_yield_p0_MPa / Y_MPA, "depth_over_a": depth,
            "compliance_mm_per_MPa": res.history[-1].u_centre_mm,
            "axis_depth": z[near_axis].tolist(), "axis_vm_per_p0": vm[near_axis].tolist()}


def load_path(disc, mesh, material: J2Material, levels_y, unload_y, step_y: float, c_el: float) -> list[dict]:
    """Load through ``levels_y`` x Y (steps <= step_y x Y), record the centre displacement, its inelastic part
    u_pl = u - c_el p0 and the plastic zone at each level; unload to zero from ``unload_y`` (residual dent)."""
    opts = SolverOptions(dirichlet=DIRICHLET, max_increment_MPa=step_y * Y_MPA)
    rows, state, branch = [], None, None
    for f in levels_y:
        p0 = f * Y_MPA
        t0 = time.perf_counter()
        res = solve_load_path(mesh, material, LOAD, [p0], options=opts, disc=disc, initial_state=state,
                              branch_points=branch)
        state, branch = res.state, res.branch_points
        u = res.history[-1].u_centre_mm
        zone_thr = plastic_zone(disc, state, ZONE_THRESHOLD)
        row = {"p0_over_Y": f, "u_mm": u, "u_pl_mm": u - c_el * p0, "newton": sum(i.newton_iters for i in res.history),
               **plastic_zone(disc, state), "z_top_thr": zone_thr["z_top"], "z_bottom_thr": zone_thr["z_bottom"]}
        if any(abs(f - g) < 1e-9 for g in unload_y):
            un = solve_load_path(mesh, material, LOAD, [0.0], options=opts, disc=disc, initial_state=state)
            row["dent_mm"] = un.history[-1].u_centre_mm
        row["time_s"] = time.perf_counter() - t0
        rows.append(row)
    return rows


def top_reaches(rows: list[dict], depth: float) -> float:
    """p0 / Y at which the top of the plastic zone rises to ``depth`` (x a), linear between the recorded levels
    (NaN when it is not crossed)."""
    p = [r["p0_over_Y"] for r in rows if np.isfinite(r["z_top"])]
    z = [r["z_top"] for r in rows if np.isfinite(r["z_top"])]
    for (p1, z1), (p2, z2) in zip(zip(p, z), zip(p[1:], z[1:])):
        if z1 > depth >= z2:
            return float(p1 + (p2 - p1) * (z1 - depth) / (z1 - z2))
    return float("nan")


def pct(a: float, b: float) -> float:
    """Deviation of ``a`` from ``b`` in per cent."""
    return (a / b - 1.0) * 100.0


def grid_label(g: dict) -> str:
    """Label of a Tamaas grid (lengths / a)."""
    return f"L = {g['period_a']:g} a, dx = a/{round(1 / g['dx_a'])}, Lz = {g['depth_a']:g} a"


def tamaas_reference(quick: bool) -> dict:
    """Solve the same load path with Tamaas (``benchmarks/tamaas_reference.py``) for the materials it can model
    (EPP, isotropic hardening) on the grids of ``TAMAAS_GRIDS``. Returns {"available": False, "reason": ...} when
    Tamaas cannot be imported; a run that raises is recorded with its error instead of stopping the benchmark."""
    version = tr.tamaas_version()
    if version is None:
        return {"available": False, "reason": "the Python package `tamaas` is not importable here "
                "(it is in the `bench` extra: `pip install -e '.[bench]'`)"}
    grids = TAMAAS_GRIDS["quick" if quick else "full"]
    levels = TAMAAS_LEVELS if quick else TAMAAS_LEVELS + (3.4,)
    runs = {}
    for name, hard in TAMAAS_HARDENING.items():
        for i, g in enumerate(grids):
            st = tr.TamaasSettings(**g, hardening_MPa=hard, levels_Y=levels, unload_Y=levels, step_Y=STEP_Y,
                                   threshold=ZONE_THRESHOLD)
            try:
                runs[(name, i)] = tr.solve(st)
            except Exception as exc:  # reported in the table, the FEM part still stands
                runs[(name, i)] = {"error": f"{type(exc).__name__}: {exc}"}
    return {"available": True, "version": version, "grids": grids, "runs": runs, "citation": tr.CITATION}


def tamaas_row(tam: dict, name: str, grid: int, f: float) -> dict | None:
    """The Tamaas row of material ``name`` on grid ``grid`` at p0 = ``f`` Y, or None (not run, failed, missing)."""
    run = tam.get("runs", {}).get((name, grid)) if tam.get("available") else None
    if not run or "error" in run:
        return None
    return next((r for r in run["levels"] if abs(r["p0_over_Y"] - f) < 1e-9), None)


@dataclasses.dataclass(frozen=True)
class ValidationRun:
    """Everything the report of one benchmark run is made from (kept in memory, written as the report's JSON data).

    Attributes
    ----------
    hs : tuple of float
        Element sizes h of the meshes near the load, coarse to fine, mm.
    step_y : float
        Largest load step, in units of the yield stress Y.
    ref_fy : float
        First-yield pressure p0 / Y of the closed-form Hertz axis stresses (Johnson 1985, eq. 3.45), -.
    ref_depth : float
        Depth z / a of first yield from the same closed form, -.
    elastic : dict
        h -> :func:`elastic_reference` of that mesh.
    meshes : dict
        h -> dofs, elements and wall times (s) of that mesh.
    cases : dict
        (material name, h) -> rows of :func:`load_path`.
    step_check : dict
        Material name -> rows of :func:`load_path` with half the step on the second-finest mesh (full mode).
    tam : dict
        :func:`tamaas_reference` result.
    t_tam : float
        Wall time of the Tamaas runs, s.
    """

    hs: tuple
    step_y: float
    ref_fy: float
    ref_depth: float
    elastic: dict
    meshes: dict
    cases: dict
    step_check: dict
    tam: dict
    t_tam: float
