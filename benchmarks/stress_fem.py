"""Stress cases for the elastoplastic FEM engine (plane-strain Hertz load on a graded half block).

Each case loads a half block (``calibration.fem.verification_meshes.hertz_block``, P2 triangles, symmetry at y = 0,
far sides and bottom clamped) with a Hertz pressure of semi-width b = 1 mm to a multiple of the first-yield level
p_fy and is either

- a converged, VERIFIED result: (1) equilibrium recomputed from the returned stresses, |f_ext - f_int| on the free
  dofs <= 1e-6 |f_ext|; (2) the applied vertical force equals the analytic pi/2 b p0 / 2 (half model) within 1 %;
  (3) the load-centre displacement agrees with the same problem solved in small increments (p_fy / 8, full
  Newton) within ``CENTRE_RTOL``; or
- the project's clear error (:class:`wrlayer.errors.WrLayerError`, e.g. ConvergenceError from the step cutting) in
  the cases where one is acceptable: beyond the limit load (after the cutting has carried the load at least to
  ``min_progress`` p_fy) and for the modified-Newton strategy (linear convergence). Below the limit load the small
  increment reference converges, so the step cutting must recover there.

Anything else (an unverified result, another exception) fails the stress run.

Cases: far too large load increments (one step to 1.8 p_fy, i.e. peak 3.1 Y, mean pressure 2.5 Y, close to the
plane-strain limit load of about 3 Y mean; each strategy; and with at most 4 Newton iterations so that the step
cutting must act), nearly perfectly plastic material (H = 1e-6 E), perfectly plastic material beyond the limit load
(must end in a clear error, after the step cutting has carried the load well past first yield), very coarse (h = b) and very fine (h = b/40, full mode only) meshes, Poisson's ratio 0.499. Units mm, N, MPa (forces per mm thickness in plane strain).
"""

from __future__ import annotations

import re
import time
from dataclasses import dataclass, field, replace

import numpy as np

from calibration.fem.boundary import dirichlet_dofs
from calibration.fem.elastoplastic_solver import SolverOptions, solve_load_path
from calibration.fem.assembly import discretise
from calibration.hertz.load import HertzLoad
from calibration.fem.material import J2Material
from calibration.fem.verification_meshes import hertz_block
from wrlayer.errors import WrLayerError

__all__ = ["CENTRE_RTOL", "FEM_CASES", "FemCase", "run_fem_case"]

STEEL = J2Material(210000.0, 0.3, 500.0)
#: far boundaries clamped, y = 0 symmetry as rollers (u_y = 0)
DIRICHLET = {"fixed": [0, 1], "side": [0, 1], "sym_y": [0]}
B_MM = 1.0
#: load-centre displacement: big-step result vs small increments (radial return is path dependent in finite steps)
CENTRE_RTOL = 5e-2
EQUILIBRIUM_RTOL = 1e-6
FORCE_RTOL = 1e-2


@dataclass(frozen=True)
class FemCase:
    """One FEM stress case: mesh (h fine size, fine-zone size, block size, mm), material, load factor on p_fy,
    solver options for the tested run (the reference run uses p_fy/8 increments with full Newton)."""

    name: str
    what: str
    h_mm: float = 0.25
    fine_mm: float = 1.5
    length_mm: float = 20.0
    material: J2Material = STEEL
    load_factor: float = 1.8
    options: SolverOptions = field(default_factory=lambda: SolverOptions(dirichlet=DIRICHLET))
    must_converge: bool = True  # below the limit load: a ConvergenceError is a failure (the reference converges)
    min_progress: float | None = None  # beyond the limit: the error must come after p0 >= min_progress * p_fy
    quick: bool = True          # part of the quick mode
    subset: bool = False        # part of the pytest subset (tiny)


def _opts(**kw) -> SolverOptions:
    return SolverOptions(dirichlet=DIRICHLET, **kw)


NEARLY_PERFECT = J2Material(210000.0, 0.3, 500.0, H_iso_MPa=0.21)         # H = 1e-6 E
NEAR_INCOMPRESSIBLE = J2Material(210000.0, 0.499, 500.0)

COARSE = {"h_mm": 1.0, "fine_mm": 1.0, "length_mm": 10.0}

FEM_CASES: tuple[FemCase, ...] = (
    FemCase("big-step-pcg", "one increment 0 -> 1.8 p_fy (default pcg strategy)"),
    FemCase("big-step-newton", "one increment 0 -> 1.8 p_fy, full Newton", options=_opts(strategy="newton")),
    FemCase("big-step-modified", "one increment 0 -> 1.8 p_fy, modified Newton (elastic stiffness only; linear "
            "convergence, a clear error is acceptable; full mode only: about 3 min)", options=_opts(strategy="modified"),
            must_converge=False, quick=False),
    FemCase("cut-newton", "one increment 0 -> 1.8 p_fy with at most 6 Newton iterations (the step cutting must "
            "act and recover), full Newton", options=_opts(strategy="newton", max_newton=6), h_mm=0.5, subset=True),
    FemCase("cut-pcg", "one increment 0 -> 1.8 p_fy with at most 6 Newton iterations, pcg",
            options=_opts(strategy="pcg", max_newton=6), h_mm=0.5),
    FemCase("nearly-perfect-plastic", "H = 1e-6 E, one increment to 1.8 p_fy", material=NEARLY_PERFECT),
    FemCase("beyond-limit-newton", "perfectly plastic (H = 0), one increment to 4 p_fy (mean pressure 5.6 Y, "
            "beyond the plane-strain limit load): a clear error after the cutting has passed 1.5 p_fy",
            load_factor=4.0, options=_opts(strategy="newton"), must_converge=False,
            min_progress=1.5, **COARSE),
    FemCase("beyond-limit-pcg", "as beyond-limit-newton with the pcg strategy", load_factor=4.0,
            options=_opts(strategy="pcg"), must_converge=False, min_progress=1.5, subset=True, **COARSE),
    FemCase("coarse-mesh", "h = b = 1 mm, block 10 mm, one increment to 1.8 p_fy", subset=True, **COARSE),
    FemCase("fine-mesh", "h = b/40 = 0.025 mm (52k dofs), one increment to 1.8 p_fy", h_mm=0.025, fine_mm=1.5,
            length_mm=20.0, quick=False),
    FemCase("poisson-0.499", "nu = 0.499, one increment to 1.5 p_fy (1.8 p_fy is beyond the limit load here)",
            material=NEAR_INCOMPRESSIBLE, load_factor=1.5),
)


def _first_yield(mesh, disc, material) -> float:
    return solve_load_path(mesh, material, HertzLoad(0.0, B_MM), [1e-6], options=_opts(), disc=disc
                           ).first_yield_p0_MPa


def run_fem_case(case: FemCase) -> dict:
    """Run one case; returns a JSON-serialisable dict with ``outcome`` and the measured numbers.

    Outcomes: "ok" (converged and verified), "clear-error" (WrLayerError where one is acceptable), and the failures
    "unverified" (a returned result fails a check), "reference-failed" (the small-step reference run on the same
    discretisation raised) and "failed-to-recover" (ConvergenceError although the problem
    is below the limit load, or beyond it before the cutting passed ``min_progress`` p_fy). Exceptions other than
    WrLayerError propagate (also a failure of the stress run)."""
    t0 = time.perf_counter()
    mesh = hertz_block(case.h_mm, case.fine_mm, case.length_mm, order=2, dim=2)
    disc = discretise(mesh)
    load = HertzLoad(0.0, B_MM)
    out = {"case": case.name, "what": case.what, "n_dofs": int(disc.n_dofs)}
    p_fy = _first_yield(mesh, disc, case.material)
    out["p_fy_MPa"] = p_fy
    try:
        p_target = case.load_factor * p_fy
        opts = case.options
        t1 = time.perf_counter()
        res = solve_load_path(mesh, case.material, load, [p_target], options=opts, disc=disc)
        out["solve_s"] = time.perf_counter() - t1
    except WrLayerError as err:
        out.update(outcome="clear-error", error=f"{type(err).__name__}: {err}", wall_s=time.perf_counter() - t0)
        reached = re.search(r"at p0 = ([-+0-9.eE]+) MPa", str(err))
        out["failed_at_p0_MPa"] = float(reached.group(1)) if reached else None
        if case.must_converge or (case.min_progress is not None
                                  and not (reached and float(reached.group(1)) >= case.min_progress * p_fy)):
            out["outcome"] = "failed-to-recover"
        return out
    inc = res.history[-1]
    if case.min_progress is not None:
        out.update(outcome="unverified", problem="converged beyond the limit load", wall_s=time.perf_counter() - t0)
        return out
    out.update(p0_MPa=inc.p0_MPa, increments=len(res.history),
               automatic_substeps=sum(not h.requested for h in res.history),
               newton_iterations=int(sum(h.newton_iters for h in res.history)),
               u_centre_mm=inc.u_centre_mm, n_yielded=inc.n_yielded)
    # (1) equilibrium recomputed from the returned stresses
    free = np.ones(disc.n_dofs, dtype=bool)
    free[dirichlet_dofs(disc, opts.dirichlet)] = False
    force = load.prepare(disc.basis).force_per_MPa
    f_ext = inc.p0_MPa * force
    f_int = disc.internal_force(res.state.stress_MPa)
    out["equilibrium_rel"] = float(np.linalg.norm((f_ext - f_int)[free]) / np.linalg.norm(f_ext[free]))
    # (2) the applied vertical force (half model)
    fz = -float(f_ext[disc.basis.get_dofs().all("u^2")].sum())
    out["force_rel_error"] = abs(fz / (0.5 * load.total_force_per_MPa() * inc.p0_MPa) - 1.0)
    # (3) the same problem in small increments
    try:
        ref = solve_load_path(mesh, case.material, load, [p_target],
                              options=replace(opts, strategy="newton", max_increment_MPa=p_fy / 8,
                                              max_newton=25), disc=disc)
    except WrLayerError as err:   # the reference (same discretisation, small steps) must converge
        out.update(outcome="reference-failed", error=f"{type(err).__name__}: {err}", wall_s=time.perf_counter() - t0)
        return out
    u_ref = ref.history[-1].u_centre_mm
    out["u_centre_ref_mm"] = u_ref
    out["centre_rel_diff"] = abs(inc.u_centre_mm / u_ref - 1.0)
    ok = (out["equilibrium_rel"] <= EQUILIBRIUM_RTOL and out["force_rel_error"] <= FORCE_RTOL
          and out["centre_rel_diff"] <= CENTRE_RTOL and bool(np.isfinite(inc.u_centre_mm)) and inc.u_centre_mm > 0
          and abs(inc.p0_MPa - p_target) <= 1e-9 * p_target)
    out.update(outcome="ok" if ok else "unverified", wall_s=time.perf_counter() - t0)
    return out
