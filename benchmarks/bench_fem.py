"""FEM engine benchmark: 3D elastoplastic Hertz indentation, run time vs error, solver variants, felupe.

Problem (units mm, N, MPa): quarter block 20 mm (unstructured gmsh tets, graded from element size h within
1.2 mm of the load), circular Hertz pressure a = b = 1 mm, steel E = 210 GPa, nu = 0.3, Y = 500 MPa, perfectly
plastic; far faces clamped, symmetry planes x = 0, y = 0. Load path: p0 = 0 -> 2 x 1.61 Y (twice the analytic
first-yield pressure) in 8 equal increments, then unloaded to 0 in one increment. Quantities: centre
displacement at peak load and the residual dent after unloading. Errors are measured against the Richardson
extrapolation of the three finest levels (observed order) of the same problem.
"""

from __future__ import annotations

import json
import pathlib
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from benchmarks.harness import interleaved_medians, machine_info, max_rss_mb, peak_memory_mb
from calibration.fem.boundary import dirichlet_dofs
from calibration.fem.elastoplastic_solver import SolverOptions, solve_load_path
from calibration.fem.assembly import discretise
from calibration.hertz.load import HertzLoad
from calibration.fem.linear_solvers import HAVE_PARDISO
from calibration.fem.material import J2Material
from calibration.fem.verification_meshes import hertz_block_gmsh
from wrlayer.plotting import save_figure

#: the fast direct solver where pypardiso is installed (x86_64), SuperLU otherwise (labels follow)
DIRECT, DIRECT_NAME = ("pardiso", "PARDISO") if HAVE_PARDISO else ("scipy", "SuperLU")
OURS, FELUPE = f"ours (pcg + {DIRECT_NAME})", f"felupe (Newton, {DIRECT_NAME})"
MAT = J2Material(210000.0, 0.3, 500.0)
#: the felupe cross-check uses a small linear isotropic hardening (H = 1000 MPa, 0.5 % of E): felupe 11.3's Newton
#: stagnates (no quadratic convergence, 60 iterations) on the perfectly plastic case at 2 p_FY, ours converges
MAT_FELUPE = J2Material(210000.0, 0.3, 500.0, H_iso_MPa=1000.0)
LOAD = HertzLoad(0.0, 1.0, a_mm=1.0)
DIRICHLET = {"fixed": [0, 1, 2], "side": [0, 1, 2], "symmetry": [0], "sym_y": [1]}
P_FY = 1.61 * MAT.yield_MPa
P_PEAK = 2.0 * P_FY
LEVELS = [P_PEAK, 0.0]
BLOCK_MM = 20.0


def _mesh(h: float, order: int = 2):
    return hertz_block_gmsh(h, 1.2, BLOCK_MM, order=order, dim=3)


def indentation(h: float, strategy: str = "pcg", backend: str = "auto", order: int = 2, mesh=None,
                increments: int = 8, material: J2Material = MAT, **options) -> dict:
    """One load/unload run (``increments`` equal load steps up to the peak); returns times, dofs and the two
    displacements (mm). ``options``: further SolverOptions fields (e.g. factor_precision="double")."""
    t0 = time.perf_counter()
    mesh = _mesh(h, order) if mesh is None else mesh
    t_mesh = time.perf_counter() - t0
    opts = SolverOptions(dirichlet=DIRICHLET, strategy=strategy, linear_solver=backend,
                         max_increment_MPa=P_PEAK / increments, **options)
    t1 = time.perf_counter()
    disc = discretise(mesh)
    res = solve_load_path(mesh, material, LOAD, LEVELS, options=opts, disc=disc)
    t_solve = time.perf_counter() - t1
    peak = max(res.history, key=lambda i: i.p0_MPa)
    fac = [v.factor for v in disc.problem_cache.values() if hasattr(v, "factor")]
    return {"h_mm": h, "order": order, "strategy": strategy, "backend": backend, "n_dofs": int(res.n_dofs),
            "options": options, "linear_solves": sum(f.n_solves for f in fac),
            "factorisations": sum(f.n_factorisations for f in fac),
            "n_elements": int(mesh.t.shape[1]), "mesh_s": t_mesh, "solve_s": t_solve,
            "u_peak_mm": peak.u_centre_mm, "dent_mm": res.history[-1].u_centre_mm,
            "first_yield_over_Y": res.first_yield_p0_MPa / material.yield_MPa,
            "newton_iters": sum(i.newton_iters for i in res.history),
            "cg_iters": sum(i.cg_iters for i in res.history), "n_yielded": res.history[-1].n_yielded}


def factor_precision(h: float, repeat: int = 10) -> list[dict]:
    """PARDISO factorisation and triangular-solve times of the elastic stiffness of the level-h block, double
    against single precision (medians of ``repeat`` solves, one BLAS thread as in the calibration workers), and
    the relative residual of one solve and of the refined solve."""
    from calibration.fem.problem import TangentProblem
    from calibration.fem.linear_solvers import Factoriser

    mesh = _mesh(h)
    disc = discretise(mesh)
    prob = TangentProblem(disc, MAT, dirichlet_dofs(disc, DIRICHLET), SolverOptions(dirichlet=DIRICHLET))
    b = np.random.default_rng(0).standard_normal(disc.n_dofs)
    b[prob.fixed] = 0.0
    rows = []
    for precision in ("double", "single"):
        f = Factoriser(disc.csr_indptr, disc.csr_indices, disc.n_dofs, DIRECT, precision)
        t0 = time.perf_counter()
        f.factorise(prob.Ke_bc_data)  # analysis + numerical factorisation
        t_first = time.perf_counter() - t0
        t0 = time.perf_counter()
        f.factorise(prob.Ke_bc_data)  # numerical factorisation only (as a tangent refresh)
        t_num = time.perf_counter() - t0
        times = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            x = f.solve(b)
            times.append(time.perf_counter() - t0)
        res1 = float(np.linalg.norm(prob.Ke.dot(x) - b) / np.linalg.norm(b))
        xr = f.solve_refined(b, prob.Ke.dot, rtol=1e-12)
        rows.append({"precision": precision, "n_dofs": int(disc.n_dofs), "first_factorisation_s": t_first,
                     "refactorisation_s": t_num, "solve_ms": 1e3 * float(np.median(times)), "relres_one_solve": res1,
                     "relres_refined": float(np.linalg.norm(prob.Ke.dot(xr) - b) / np.linalg.norm(b)),
                     "solves_refined": f.n_solves - repeat})
        f.release()
    return rows


def elastic_half_space(h: float, block_mm: float) -> dict:
    """Elastic Hertz load (p0 = 100 MPa) on a block of size ``block_mm``: centre displacement against the
    half-space value w0 = pi p0 a (1 - nu^2) / (2 E) (Johnson 1985, eq. 3.41)."""
    t0 = time.perf_counter()
    mesh = hertz_block_gmsh(h, 1.2, block_mm, order=2, dim=3)
    res = solve_load_path(mesh, MAT, LOAD, [100.0], options=SolverOptions(dirichlet=DIRICHLET))
    w0 = np.pi * 100.0 * 1.0 * (1 - MAT.poisson ** 2) / (2 * MAT.E_MPa)
    return {"h_mm": h, "block_mm": block_mm, "n_dofs": int(res.n_dofs), "time_s": time.perf_counter() - t0,
            "w0_mm": res.history[-1].u_centre_mm, "w0_exact_mm": w0,
            "err_pct": (res.history[-1].u_centre_mm / w0 - 1) * 100,
            "first_yield_over_Y": res.first_yield_p0_MPa / MAT.yield_MPa}


def richardson(h: list[float], q: list[float]) -> tuple[float, float]:
    """Extrapolated value and observed order from the three finest levels (h decreasing), for q = q* + C h^p."""
    (h1, h2, h3), (q1, q2, q3) = h[-3:], q[-3:]
    r = h1 / h2  # assumes a roughly constant refinement ratio
    ratio = (q1 - q2) / (q2 - q3) if q2 != q3 else np.inf
    p = np.log(abs(ratio)) / np.log(r) if np.isfinite(ratio) and ratio > 0 else 2.0
    p = float(np.clip(p, 0.5, 4.0))
    r23 = h2 / h3
    return float(q3 + (q3 - q2) / (r23 ** p - 1.0)), p


def felupe_indentation(mesh_p1, force_per_MPa: np.ndarray, fixed_masks: dict, tol: float = 1e-8,
                       increments: int = 8, material: J2Material = MAT_FELUPE) -> dict:
    """The same P1 problem solved with felupe's small-strain J2 model (isotropic hardening K = 0)."""
    import felupe as fem

    mesh = fem.Mesh(mesh_p1.p.T.copy(), mesh_p1.t.T.copy(), "tetra")
    region = fem.RegionTetra(mesh)
    field = fem.FieldContainer([fem.Field(region, dim=3)])
    bounds = {}
    for name, (mask, comps) in fixed_masks.items():
        skip = tuple(0 if c in comps else 1 for c in range(3))
        bounds[name] = fem.Boundary(field[0], mask=mask, skip=skip)
    umat = fem.LinearElasticPlasticIsotropicHardening(E=material.E_MPa, nu=material.poisson, sy=material.yield_MPa,
                                                      K=material.H_iso_MPa)
    solid = fem.SolidBody(umat, field)
    F = force_per_MPa.reshape(-1, 3)
    pts = np.nonzero(np.abs(F).sum(axis=1) > 0)[0]
    load = fem.PointLoad(field, pts, values=np.zeros((len(pts), 3)))
    ramp_levels = list(np.linspace(P_PEAK / increments, P_PEAK, increments)) + [0.0]
    step = fem.Step(items=[solid, load], ramp={load: [s * F[pts] for s in ramp_levels]}, boundaries=bounds)
    centre = int(np.argmin(np.linalg.norm(mesh_p1.p.T, axis=1)))
    disp = []
    job = fem.Job([step], callback=lambda i, j, res: disp.append(-field[0].values[centre, 2]))
    t0 = time.perf_counter()
    if HAVE_PARDISO:
        import pypardiso

        spsolve = pypardiso.spsolve
    else:
        from scipy.sparse.linalg import spsolve
    job.evaluate(tol=tol, verbose=0, solver=spsolve, maxiter=60)
    return {"solve_s": time.perf_counter() - t0, "u_peak_mm": disp[increments - 1], "dent_mm": disp[-1]}


def _felupe_case(h: float):
    """P1 mesh, the skfem-based solve and the felupe inputs for the comparison."""
    mesh = _mesh(h, order=1)
    disc = discretise(mesh)
    force = LOAD.prepare(disc.basis).force_per_MPa
    x = mesh.p
    tol = 1e-9 * BLOCK_MM
    masks = {"fixed": ((x[2] < -BLOCK_MM + tol) | (x[0] > BLOCK_MM - tol) | (x[1] > BLOCK_MM - tol), (0, 1, 2)),
             "symmetry": (x[0] < tol, (0,)), "sym_y": (x[1] < tol, (1,))}
    # the same constrained dofs in both codes (vertex dofs are interleaved per node for P1)
    ours = dirichlet_dofs(disc, DIRICHLET)
    theirs = np.unique(np.concatenate([(np.nonzero(m)[0][:, None] * 3 + np.array(c)[None, :]).ravel()
                                       for m, c in masks.values()]))
    assert np.array_equal(np.sort(ours), theirs), "constraint sets differ"
    return mesh, force, masks


def _interleaved_runs(fns: dict, repeat: int) -> tuple[dict, dict]:
    """benchmarks.harness.interleaved_medians (no warm-up) that also keeps each callable's last result."""
    results = {}

    def keep(k, fn):
        return lambda: results.__setitem__(k, fn())

    times = interleaved_medians({k: keep(k, fn) for k, fn in fns.items()}, repeat=repeat, warmup=0)
    return times, results


def _plot(rows, ref_u, ref_dent, out: pathlib.Path) -> pathlib.Path:
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    t = [r["solve_s"] + r["mesh_s"] for r in rows]
    eu = [abs(r["u_peak_mm"] / ref_u - 1) * 100 for r in rows]
    ed = [abs(r["dent_mm"] / ref_dent - 1) * 100 for r in rows]
    ax.loglog(t, eu, "o-", label="centre displacement at peak")
    ax.loglog(t, ed, "s-", label="residual dent")
    for r, x, y in zip(rows, t, eu):
        ax.annotate(f"h={r['h_mm']:g}", (x, y), textcoords="offset points", xytext=(4, 4), fontsize=8)
    ax.axhline(2.0, color="grey", lw=0.8, ls="--")
    ax.set_xlabel("run time (mesh + solve) [s]")
    ax.set_ylabel("error vs Richardson extrapolation [%]")
    ax.set_title("3D Hertz indentation to 2 x first yield and unloading (P2 tets)")
    ax.legend()
    ax.grid(True, which="both", alpha=0.3)
    path = out / "fem_time_vs_error.png"
    save_figure(fig, path)
    return path


def _mesh_levels(hs: list[float]) -> tuple[list[dict], dict]:
    """One indentation per level h (heap and RSS recorded) and its error against the Richardson extrapolation."""
    rows = []
    for h in hs:
        result, heap = peak_memory_mb(lambda h=h: indentation(h))
        result["heap_peak_MiB"] = heap
        result["max_rss_MiB"] = max_rss_mb()
        rows.append(result)
    ref_u, p_u = richardson([r["h_mm"] for r in rows], [r["u_peak_mm"] for r in rows])
    ref_d, p_d = richardson([r["h_mm"] for r in rows], [r["dent_mm"] for r in rows])
    for r in rows:
        r["err_u_peak_pct"] = (r["u_peak_mm"] / ref_u - 1) * 100
        r["err_dent_pct"] = (r["dent_mm"] / ref_d - 1) * 100
    return rows, {"u_peak_mm": ref_u, "order_u": p_u, "dent_mm": ref_d, "order_dent": p_d}


def _solver_variants(h_cmp: float, quick: bool) -> tuple[dict, dict]:
    """Solver variants on one level (interleaved medians): times (s) and each variant's last result."""
    mesh_cmp = _mesh(h_cmp)
    variants = {f"pcg + {DIRECT_NAME}": ("pcg", DIRECT, {}), f"newton + {DIRECT_NAME}": ("newton", DIRECT, {}),
                f"modified + {DIRECT_NAME}": ("modified", DIRECT, {}), "pcg + SuperLU": ("pcg", "scipy", {})}
    if HAVE_PARDISO:  # the fast paths switched off one at a time (`make bench`, bench_fem)
        variants["pcg + PARDISO, double-precision factor"] = ("pcg", DIRECT, {"factor_precision": "double"})
        variants["pcg + PARDISO, fixed CG tolerance"] = ("pcg", DIRECT, {"cg_forcing": "fixed"})
        variants["pcg + PARDISO, no elastic predictor"] = ("pcg", DIRECT, {"elastic_predictor": False})
    if quick:  # modified Newton: ~2000 iterations, 25x the time of the others (measured); full mode only
        variants.pop("pcg + SuperLU", None)
        variants.pop(f"modified + {DIRECT_NAME}")
    return _interleaved_runs({k: (lambda s=s, b=b, o=o: indentation(h_cmp, s, b, mesh=mesh_cmp, **o))
                              for k, (s, b, o) in variants.items()}, repeat=1 if quick else 3)


def _increment_error(h: float, n_incr: tuple[int, ...]) -> dict:
    """Load-increment (time-discretisation) error on one level: backward-Euler return mapping, Newton."""
    mesh_inc = _mesh(h)
    incr = [indentation(h, "newton", mesh=mesh_inc, increments=n) for n in n_incr]
    ref_inc_u, p_inc_u = richardson([1 / n for n in n_incr[-3:]], [r["u_peak_mm"] for r in incr[-3:]])
    ref_inc_d, _ = richardson([1 / n for n in n_incr[-3:]], [r["dent_mm"] for r in incr[-3:]])
    return {"n": list(n_incr), "runs": incr, "reference_u_peak_mm": ref_inc_u, "reference_dent_mm": ref_inc_d,
            "order": p_inc_u}


def _felupe_comparison(h_fe: float, quick: bool) -> dict:
    """Ours and felupe on the same P1 mesh, interleaved median solve times (s)."""
    mesh1, force1, masks = _felupe_case(h_fe)
    fe_times, fe_res = _interleaved_runs({
        OURS: lambda: indentation(h_fe, order=1, mesh=mesh1, material=MAT_FELUPE),
        FELUPE: lambda: felupe_indentation(mesh1, force1, masks)}, repeat=2 if quick else 3)
    return {"h_mm": h_fe, "ours": fe_res[OURS], "felupe": fe_res[FELUPE], "median_s": fe_times,
            "ratio": fe_times[FELUPE] / fe_times[OURS]}


def _levels_markdown(hs: list[float], rows: list[dict], rich: dict, elastic: list[dict]) -> list[str]:
    md = [__doc__.split("\n\n", 1)[1].strip(), "",
          f"Richardson reference (levels h = {hs[-3:]} mm): centre displacement at peak "
          f"{rich['u_peak_mm'] * 1000:.4f} µm (observed order {rich['order_u']:.2f}), "
          f"dent {rich['dent_mm'] * 1000:.4f} µm (order {rich['order_dent']:.2f}).", "",
          "| h mm | dofs | elements | mesh s | solve s | heap MiB | max RSS MiB | Newton its | CG its | "
          "u_peak µm | err % | dent µm | err % | first yield / Y |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        md.append(f"| {r['h_mm']:g} | {r['n_dofs']} | {r['n_elements']} | {r['mesh_s']:.2f} | {r['solve_s']:.2f} | "
                  f"{r['heap_peak_MiB']:.0f} | {r['max_rss_MiB']:.0f} | {r['newton_iters']} | {r['cg_iters']} | "
                  f"{r['u_peak_mm'] * 1000:.4f} | {r['err_u_peak_pct']:+.2f} | {r['dent_mm'] * 1000:.4f} | "
                  f"{r['err_dent_pct']:+.2f} | {r['first_yield_over_Y']:.4f} |")
    md += ["", "Elastic check against the half-space (Boussinesq/Hertz, p0 = 100 MPa, "
           f"h = {elastic[0]['h_mm']} mm, far faces clamped; the truncation error decays like a / block size):", "",
           "| block mm | dofs | time s | w0 FE µm | w0 half-space µm | error % | first yield / Y (Johnson: 1.61) |",
           "|---|---|---|---|---|---|---|"]
    for e in elastic:
        md.append(f"| {e['block_mm']:g} | {e['n_dofs']} | {e['time_s']:.1f} | {e['w0_mm'] * 1000:.4f} | "
                  f"{e['w0_exact_mm'] * 1000:.4f} | {e['err_pct']:+.2f} | {e['first_yield_over_Y']:.4f} |")
    return md


def _solvers_markdown(h_cmp: float, var_times: dict, var_res: dict, h_prec: float, precision: list[dict],
                      h_inc: float, inc: dict) -> list[str]:
    md = ["", f"Linear-solver strategies on h = {h_cmp} mm ({var_res[next(iter(var_res))]['n_dofs']} dofs), "
          "interleaved medians (s):", "",
          "| variant | solve s | Newton its | CG its | triangular solves | factorisations | u_peak µm | dent µm |",
          "|---|---|---|---|---|---|---|---|"]
    for k, r in var_res.items():
        md.append(f"| {k} | {var_times[k]:.2f} | {r['newton_iters']} | {r['cg_iters']} | {r['linear_solves']} | "
                  f"{r['factorisations']} | {r['u_peak_mm'] * 1000:.5f} | {r['dent_mm'] * 1000:.5f} |")
    if precision:
        md += ["", f"PARDISO factorisation precision on h = {h_prec} mm ({precision[0]['n_dofs']} dofs, elastic "
               "stiffness, one thread): the single-precision factorisation preconditions CG (and is refined in "
               "double precision where a direct solve is needed).", "",
               "| precision | first factorisation s | refactorisation s | solve ms | rel. residual, one solve | "
               "refined | solves to refine |", "|---|---|---|---|---|---|---|"]
        for r in precision:
            md.append(f"| {r['precision']} | {r['first_factorisation_s']:.2f} | {r['refactorisation_s']:.2f} | "
                      f"{r['solve_ms']:.1f} | {r['relres_one_solve']:.1e} | {r['relres_refined']:.1e} | "
                      f"{r['solves_refined']} |")
    n_incr, ref_inc_u, ref_inc_d = inc["n"], inc["reference_u_peak_mm"], inc["reference_dent_mm"]
    md += ["", f"Load-increment error (h = {h_inc} mm, newton; the table above uses 8 increments to the peak). "
           f"Reference: Richardson extrapolation of {'/'.join(map(str, n_incr[-3:]))} increments "
           f"(observed order {inc['order']:.2f}): u_peak "
           f"{ref_inc_u * 1000:.4f} µm, dent {ref_inc_d * 1000:.4f} µm. The increment error of 8 increments is larger "
           "than the mesh error of the finest level above: the calibration therefore limits the step to "
           "`max_increment_factor` x first yield (0.15 by default, i.e. about 14 steps to this peak).", "",
           "| increments to the peak | solve s | u_peak µm | err % | dent µm | err % |", "|---|---|---|---|---|---|"]
    for n, r in zip(n_incr, inc["runs"]):
        md.append(f"| {n} | {r['solve_s']:.1f} | {r['u_peak_mm'] * 1000:.4f} | "
                  f"{(r['u_peak_mm'] / ref_inc_u - 1) * 100:+.2f} | {r['dent_mm'] * 1000:.4f} | "
                  f"{(r['dent_mm'] / ref_inc_d - 1) * 100:+.2f} |")
    return md


def _felupe_markdown(fe: dict) -> list[str]:
    fe_times, ours1, theirs, ratio = fe["median_s"], fe["ours"], fe["felupe"], fe["ratio"]
    return ["", f"felupe {__import__('felupe').__version__} on the same P1 tetrahedral mesh (h = {fe['h_mm']} mm, "
            f"{ours1['n_dofs']} dofs, same constrained dofs, same consistent nodal forces, same 9 increments, "
            f"both with {DIRECT_NAME}; material with linear isotropic hardening H = {MAT_FELUPE.H_iso_MPa:g} MPa, "
            "because felupe's Newton stagnates on the perfectly plastic case): interleaved median solve times "
            f"ours {fe_times[OURS]:.2f} s, felupe {fe_times[FELUPE]:.2f} s "
            f"(felupe / ours = {ratio:.2f}). Same discretisation, so equal error: u_peak ours "
            f"{ours1['u_peak_mm'] * 1000:.5f} µm vs felupe {theirs['u_peak_mm'] * 1000:.5f} µm, dent "
            f"{ours1['dent_mm'] * 1000:.5f} vs {theirs['dent_mm'] * 1000:.5f} µm. (P1 tets are much less accurate "
            "than P2 for this problem; the comparison is of the solvers, not of the elements.)"]


def run(mode: str, out: pathlib.Path) -> dict:
    out = pathlib.Path(out)
    quick = mode == "quick"
    hs = [0.5, 0.35, 0.25] if quick else [0.4, 0.28, 0.2, 0.14]
    rows, rich = _mesh_levels(hs)
    fig = _plot(rows, rich["u_peak_mm"], rich["dent_mm"], out)
    elastic = [elastic_half_space(0.25 if quick else 0.15, L) for L in ((60.0,) if quick else (20.0, 60.0, 200.0))]
    var_times, var_res = _solver_variants(hs[1], quick)
    precision = factor_precision(hs[-1]) if HAVE_PARDISO else []
    inc = _increment_error(hs[0], (8, 16, 32) if quick else (8, 16, 32, 64))
    fe = _felupe_comparison(0.4 if quick else 0.2, quick)
    md = (_levels_markdown(hs, rows, rich, elastic)
          + _solvers_markdown(hs[1], var_times, var_res, hs[-1], precision, hs[0], inc) + _felupe_markdown(fe))
    data = {"levels": rows, "richardson": rich,
            "elastic_half_space": elastic, "variants": {k: dict(var_res[k], median_s=var_times[k]) for k in var_res},
            "factor_precision": precision, "increments": inc, "felupe": fe, "machine": machine_info()}
    json.dumps(data)  # must be serialisable
    return {"title": "FEM engine: 3D elastoplastic Hertz indentation", "markdown": "\n".join(md),
            "figures": [fig], "data": data}
