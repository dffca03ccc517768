"""Vertical load balance of one wheel (``method.balance``; units mm, N, MPa, s, rad).

The wheel is first lowered until it touches the rail (rigid contact, :mod:`contact.wheel_rail.contact_search`).
Lowering it further by Delta (mm, along -Z; reported as ``approach_mm``) gives each contact candidate i (contact
angle gamma_i, normal gap g_i at rigid contact, 0 for the first contact) the normal approach
delta_i = Delta cos(gamma_i) - g_i. Patch i carries the normal force N_i along its normal n_i and the creep forces
F_x,i (rolling direction) and F_s,i (contact-plane lateral axis t_i, whose track-Z component is +-sin(gamma_i)).
With ``balance = "total"`` (default; the Manchester benchmark's definition) the vertical component of the whole
contact force on the wheel equals the vertical load Q:

    sum_i (N_i cos(gamma_i) + F_s,i t_Z,i) = Q          (t_Z,i = sin(gamma_i) on the right wheel, -sin on the left)

The tangential forces depend on the normal solution (patch size, mu N), so normal and tangential problems are
solved together inside the iteration: one loaded candidate: secant iteration on N (each step a normal solve,
the reference point, the creepages there and FASTSIM), kept inside [Q / (cos + mu |sin|), Q / (cos - mu |sin|)];
cos(gamma) <= mu |sin(gamma)| (flange climbing limit) is a ConvergenceError. Several candidates: secant iteration
on the common Delta (started at the normal-only balance found by Brent's method), every candidate's N_i(delta_i)
from its force-approach relation. Converged to |sum F_Z - Q| <= 1e-8 Q (the exact solvers' results are determined
to about 1e-7 of the approach by their own tolerances; the balance stops below that), 1e-7 Q with the coarse-grid
solver (:data:`COARSE_BALANCE_RTOL`). With the exact solvers each
solve starts from the candidate's previous one (pressure field, tractions; the coarse-grid solver without a layer
on its last grid, FaStrip from its strips' tractions), and the exact normal solve at the first point of the iteration is solved to a
loose tolerance only (:data:`ROUGH_CG_TOL`). ``balance = "normal"``:
sum N_i cos(gamma_i) = Q (the earlier model, kept for comparison; on the flange it overestimates N by 25-60 %).

Each patch is a separate normal problem in its own contact plane (no elastic interaction between patches), solved
with ``method.normal`` (:func:`contact.normal.method.solve_normal_with`), with the candidate's layers looked up
strip by strip (:func:`candidate_layers`). The reference point (``method.contact_point``,
:mod:`contact.wheel_rail.reference_point`) is where the creepages are evaluated and the origin of the tangential
results' strip coordinate and Mz (FASTSIM solves about each region's force centroid, the creepages moved there).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from contact.layer.prandtl_layer import LayerPair
from contact.scenes.layers import LayerSources, build_layer_pair
from contact.normal.kik_piotrowski import NormalForceEvaluator, NormalProblem, NormalSolution, solve_normal
from contact.normal.exact_field import ExactField
from contact.normal.method import NormalMethod, solve_normal_with
from contact.tangential.fastsim import Creepage, TangentialResult
from contact.tangential.on_patch import TangentialSettings, solve_regions
from contact.wheel_rail.contact_search import ContactCandidate, SearchResult
from contact.wheel_rail.inputs import WheelRailInputs
from contact.wheel_rail.kinematics import PatchKinematics, contact_frame, creepages, given_creepages
from contact.wheel_rail.reference_point import ReferencePoint, reference_point
from contact.wheel_rail.root_finder import secant
from contact.wheel_rail.track_geometry import PlacedRail, axle_direction
from meshes.profiles import Profile
from wrlayer.errors import ConvergenceError, InputError, PatchTruncated, require, typed_input_error

#: The balance iteration stops at |sum F_Z - Q| <= BALANCE_ITER_RTOL Q (:func:`balance_rtol`).
BALANCE_ITER_RTOL = 1e-8
#: The same with the coarse-grid normal solver. Its vertical force is not smooth in N at the 1e-6 Q level: a solve
#: that just refits the kept grid moves F_y by up to 0.15 % (the same jump at tangential tolerances 1e-4 to 1e-6), so
#: below 1e-6 Q the secant wanders between the two grids' values (at 1e-7: 165 loads for the A-2.2 sweep's 42
#: wheels, 3 wheels 8 to 11 loads; at 5e-7: 143, none above 5) while the solver's own error is about 1e-2; the
#: accepted balance (contact.wheel_rail.solve.BALANCE_RTOL) is :data:`JUMP_BALANCE_RTOL`.
COARSE_BALANCE_RTOL = 5e-7
#: Where F_Z(N) jumps across the balance (the secant cycles; :func:`contact.wheel_rail.root_finder.secant` then
#: bisects down to the jump) the balance is the jump's side nearer Q if within JUMP_BALANCE_RTOL Q. Measured: the
#: shipped MBS wear example (Kik-Piotrowski, tangential balance), step 3, condition 2: F_Z - Q from -0.19 to
#: +0.14 N within 0.03 N of N = 60573 N (a jump of 5.5e-6 Q).
JUMP_BALANCE_RTOL = 1e-5


def balance_rtol(normal_method: str) -> float:
    """The balance iteration's stop |sum F_Z - Q| / Q for the normal method named ``normal_method``."""
    return COARSE_BALANCE_RTOL if normal_method == "coarse_exact" else BALANCE_ITER_RTOL

#: The exact normal CG's tolerance at the balance's first point: its force only starts the secant (its error moves
#: the secant's second step by far less than the tolerance) and its pressure the next solve.
ROUGH_CG_TOL = 1e-3
#: Inversion of a normal method's force-approach relation (:meth:`VerticalBalance.force_at_approach`): secant on
#: log N stopped at a step below INVERSION_XTOL or |delta(N) - delta| <= INVERSION_RTOL delta; its second point
#: INVERSION_STEP above the first once an earlier inversion gave the start.
INVERSION_XTOL = 1e-12
INVERSION_RTOL = 1e-9
INVERSION_STEP = 1e-4
#: Layers are built only on strips whose separation is below the first of these caps (mm) (the virtual penetration
#: alpha delta stays far below 0.3 mm at wheel loads); if a strip in contact has no element, the case is solved again
#: with the next cap (:mod:`contact.wheel_rail.solve`).
LAYER_F_CAPS_MM = (0.3, 1.0, np.inf)
BODIES = ("rail", "wheel")


def track_vector(v: np.ndarray, sign: int) -> np.ndarray:
    """A side-frame vector in the track frame (the left side's frame is mirrored in Y)."""
    return np.array([v[0], sign * v[1], v[2]])


def candidate_problem(cand: ContactCandidate, sign: int, inputs: WheelRailInputs, force: float) -> NormalProblem:
    """The candidate's normal problem at the normal force ``force`` (N), strips in track orientation."""
    eta, f = (cand.eta_mm, cand.f_mm) if sign > 0 else (-cand.eta_mm[::-1], cand.f_mm[::-1])
    return inputs.method.normal_problem(eta, f, force, cand.rolling_radius_kp_mm, inputs.material,
                                        interpolation="pchip")


def patch_tangential(normal: NormalSolution, kin: PatchKinematics, inputs: WheelRailInputs,
                     eta_ref_mm: float, start: list[TangentialResult] | None = None) -> list[TangentialResult]:
    """The tangential solution (``method.tangential``) of every region of a patch's normal solution with the
    creepages ``kin`` evaluated at the reference point ``eta_ref_mm`` (mm, problem orientation; the origin of the
    results' strip coordinate and Mz); FASTSIM takes the spin about each region's force centroid with the
    creepages moved there from the reference point (:mod:`contact.tangential.spin_centre`). [] without friction.
    ``start``: the previous solve of the balance iteration (the exact theory and FaStrip start from its
    tractions)."""
    if inputs.friction == 0:
        return []
    settings = TangentialSettings(inputs.E_MPa, inputs.poisson, inputs.friction, inputs.speed_mm_s,
                                  inputs.fastsim_cells, method=inputs.tangential_method)
    return solve_regions(normal, Creepage(kin.vx, kin.vy, kin.phi_per_mm), settings, eta_ref_mm, start)


def candidate_layers(cand: ContactCandidate, sign: int, prob: NormalProblem, layers: LayerSources | None,
                     f_cap_mm: float = LAYER_F_CAPS_MM[0], patch_mm: tuple[float, float] | None = None
                     ) -> tuple[LayerPair | None, dict[str, np.ndarray]]:
    """Per-strip layers of a candidate's patch: (pair, profile coordinate per body on the strips). Each table is read
    at the strip's profile coordinate on that body (the point of the body's profile on the strip's normal line in
    the contact plane; :func:`contact.scenes.layers.build_layer_pair`); only strips with a separation below
    ``f_cap_mm`` get an element. ``patch_mm`` = (a, b): table characteristics scaled to that patch."""
    if layers is None or layers.empty:
        return None, {}
    eta = sign * prob.strip_y_mm
    coords = {"rail": cand.rail_coordinate(eta), "wheel": cand.wheel_coordinate(eta)}
    near = prob.separation_on_grid_mm <= f_cap_mm
    return build_layer_pair(layers, prob.strip_y_mm[near], lambda body: coords[body][near], patch_mm, "layers"), coords


@dataclass(eq=False)
class BalanceCandidate:
    """A contact candidate prepared for the balance: layers, angle, the Kik–Piotrowski approach -> force evaluator;
    ``delta_guess`` the last approach (mm) solved, ``field_guess`` its exact pressure field (None with
    Kik–Piotrowski) and ``tangential_guess`` its tangential solution (the next solve's start);
    ``log_force_ratio``: log(N / N_KP) at the approach of the last inversion of another normal method's force
    (:meth:`VerticalBalance.force_at_approach`; 0 before the first); ``coarse_warm``: the coarse-grid solver's
    last grid (:class:`contact.normal.coarse_exact.CoarseWarmStart`; None before its first solve)."""

    cand: ContactCandidate
    pair: LayerPair | None
    coords: dict
    cos_g: float
    sin_g: float
    evaluator: NormalForceEvaluator
    sign: int = 1
    delta_guess: float | None = None
    layer_patch_mm: tuple[float, float] | None = None
    tangential_guess: list[TangentialResult] | None = None
    field_guess: ExactField | None = None
    log_force_ratio: float = 0.0
    coarse_warm: object = None

    def normal_start(self, method: NormalMethod, rough: bool = False) -> dict:
        """The keywords that start a normal solve of this candidate from its last one (KP: the approach; the
        exact solver: with ``rough`` the CG tolerance :data:`ROUGH_CG_TOL`, and without a layer the pressure field:
        with a layer the warm-started solve's noise, set by the layer tolerance, would stall the balance; the
        coarse-grid solver without a layer: its last grid and pressure,
        :class:`contact.normal.coarse_exact.CoarseWarmStart`, and with ``rough`` a cold solve's fitted grid at its
        placing tolerance only (the next solve, warm, solves there to the full tolerance); with a layer the jumps between a kept and a refitted
        grid stalled the balance on a flange case of scenes/wheel_rail_sweep_layers.toml)."""
        if method.name == "exact":
            return {"delta_guess_mm": self.delta_guess, "start": self.field_guess if self.pair is None else None,
                    "cg_tol": ROUGH_CG_TOL if rough else None}
        if method.name == "coarse_exact" and self.pair is None:
            if self.coarse_warm is None:
                from contact.normal.coarse_exact import CoarseWarmStart   # only this method needs it

                self.coarse_warm = CoarseWarmStart()
            return {"delta_guess_mm": self.delta_guess, "warm": self.coarse_warm, "rough": rough}
        return {"delta_guess_mm": self.delta_guess}

    def problem_at(self, force: float) -> NormalProblem:
        """The candidate's normal problem at the normal force ``force`` (N) (:func:`candidate_problem`'s, its
        separation interpolated once)."""
        return self.evaluator.prob.with_force(float(force))

    def remember(self, sol: NormalSolution) -> None:
        """Keep ``sol`` as the start of the next normal solve."""
        self.delta_guess = sol.delta_mm
        self.field_guess = sol.field


@dataclass(eq=False)
class LoadedPatch:
    """One candidate solved at a normal force (N): normal and tangential solution at its reference point."""

    ctx: BalanceCandidate
    force: float
    prob: NormalProblem
    normal: NormalSolution
    ref: ReferencePoint
    kin: PatchKinematics
    tangential: list[TangentialResult]

    @property
    def vertical_N(self) -> float:
        """Z component (track) of the contact force on the wheel: N cos(gamma) + F_s sin(gamma) (N)."""
        fy = sum(t.Fy_N for t in self.tangential)
        n_track, t_track = self.frame
        return self.force * float(n_track[2]) + fy * float(t_track[2])

    @property
    def frame(self) -> tuple[np.ndarray, np.ndarray]:
        """(normal, lateral axis) of the contact plane at the reference point, track frame."""
        n_track = track_vector(self.ref.normal, self.ctx.sign)
        return n_track, contact_frame(n_track)[1]

    @property
    def semi_axes_mm(self) -> tuple[float, float]:
        """Solved semi-axes (a, b) = (length/2, width/2) (mm)."""
        return 0.5 * self.normal.length_mm, 0.5 * self.normal.width_mm

    @property
    def approach_mm(self) -> float:
        """The vertical approach Delta (mm) at which this candidate carries its force."""
        return (self.normal.delta_mm + self.ctx.cand.normal_gap_mm) / self.ctx.cos_g


class VerticalBalance:
    """Vertical load balance of one wheel (module docstring): the candidates' normal forces such that the vertical
    component of the total contact force (or, with ``balance = "normal"``, of the normal forces only) equals Q.
    ``case`` names the case in an InputError; a ConvergenceError's message leaves it to the caller."""

    def __init__(self, found: SearchResult, rail: PlacedRail, wheel: Profile, inputs: WheelRailInputs,
                 layers: LayerSources | None, sign: int, case: str, f_cap_mm: float,
                 patch_mm: dict[int, tuple[float, float]] | None = None):
        """``patch_mm``: candidate index -> (a, b) (mm) the candidate's table layers are scaled to."""
        self.found, self.wheel, self.inputs, self.sign, self.case = found, wheel, inputs, sign, case
        self.rail = rail
        self.pose_side = inputs.pose.for_side(inputs.side)
        self.axle = axle_direction(inputs.pose)
        self.evaluations = 0
        Q = inputs.vertical_load_N
        self.ctx = []
        patch_mm = patch_mm or {}
        for k, c in enumerate(found.candidates):
            cg, sg = math.cos(c.contact_angle_rad), math.sin(c.contact_angle_rad)
            require(cg > 0.05, case, "a contact normal is (nearly) horizontal: the wheel cannot carry a vertical "
                    "load there")
            prob = candidate_problem(c, sign, inputs, Q / cg)
            pair, coords = candidate_layers(c, sign, prob, layers, f_cap_mm, patch_mm.get(k))
            self.ctx.append(BalanceCandidate(c, pair, coords, cg, sg, NormalForceEvaluator(prob, pair), sign,
                                             layer_patch_mm=patch_mm.get(k)))

    def load(self, ctx: BalanceCandidate, force: float, rough: bool = False) -> LoadedPatch:
        """Solve ``ctx`` at the normal force ``force`` (N): normal solution, reference point, creepages there,
        the tangential solution about it. ``rough``: the exact normal solve only to :data:`ROUGH_CG_TOL` (the
        first point of the balance iteration, never its result)."""
        self.evaluations += 1
        inp = self.inputs
        prob = ctx.problem_at(force)
        sol = solve_normal_with(prob, ctx.pair, method=inp.normal_method,
                                **ctx.normal_start(inp.normal_method, rough))
        ctx.remember(sol)
        ref = reference_point(inp.contact_point, ctx.cand, sol.delta_mm, self.wheel, inp.layout, self.pose_side,
                              self.rail)
        point = track_vector(ref.point_mm, self.sign)
        n_track = track_vector(ref.normal, self.sign)
        centre = np.array([0.0, inp.pose.lateral_mm, self.found.wheel_height_mm])   # rigid-contact geometry
        kin = creepages(point, n_track, centre, self.axle, inp.speed_mm_s, inp.omega_rad_s, inp.yaw_rate_rad_s) \
            if inp.creepages is None else given_creepages(inp.creepages, n_track, inp.speed_mm_s)
        tangential = patch_tangential(sol, kin, inp, self.sign * ref.eta_mm, ctx.tangential_guess)
        ctx.tangential_guess = tangential
        return LoadedPatch(ctx, float(force), prob, sol, ref, kin, tangential)

    def force_at_approach(self, ctx: BalanceCandidate, delta: float) -> float:
        """Normal force (N) of a candidate at the normal approach ``delta`` (mm); 0 when it does not touch. Another
        normal method than KP: KP's force-approach relation inverted for that method by a secant on log N,
        started at KP's force times the ratio the last inversion found (it varies slowly with the approach). Its
        solves start cold (from KP): a warm-started CG stops within its tolerance wherever it started, and that
        noise (about 1e-7 of the approach) would stall the secant; the last one starts the next load. The
        coarse-grid solver's start on its kept grid is fixed while the grid stays (no such noise): its solves are
        warm-started (:class:`contact.normal.coarse_exact.CoarseWarmStart`)."""
        if delta <= 0:
            return 0.0
        n_kp = ctx.evaluator.force_at(delta)
        method = self.inputs.normal_method
        if method.name == "kik_piotrowski" or n_kp <= 0:
            return n_kp

        def miss(log_n: float) -> float:
            sol = solve_normal_with(ctx.problem_at(math.exp(log_n)), ctx.pair, method=method, **warm)
            ctx.remember(sol)
            return sol.delta_mm - delta

        # the coarse-grid solver keeps its grid and start (the solves on it are one function of N)
        warm = {k: v for k, v in ctx.normal_start(method).items() if k == "warm"}
        x0 = math.log(n_kp) + ctx.log_force_ratio
        step = 0.05 if ctx.log_force_ratio == 0.0 else INVERSION_STEP
        x = secant(miss, x0, x0 + step, INVERSION_XTOL, 40, "approach of a patch", ftol=INVERSION_RTOL * delta)
        ctx.log_force_ratio = x - math.log(n_kp)
        return math.exp(x)

    def solve(self) -> tuple[list[LoadedPatch], float, int]:
        """(loaded candidates, vertical approach Delta (mm), number of balance iterations)."""
        with_tangential = self.inputs.balance == "total" and self.inputs.friction > 0
        if len(self.ctx) == 1:
            return self._solve_one(self.ctx[0], with_tangential)
        # several candidates: one vertical approach Delta shared by all (Brent on the normal balance first)
        Q = self.inputs.vertical_load_N
        Delta0 = self._normal_only_Delta()
        if not with_tangential:
            return self._at_Delta(Delta0), Delta0, self.evaluations
        cache: dict[float, list[LoadedPatch]] = {}

        def excess(Delta: float) -> float:
            cache[Delta] = self._at_Delta(Delta)
            return sum(lp.vertical_N for lp in cache[Delta]) - Q

        e0 = excess(Delta0)
        Delta1 = Delta0 * (1.0 - 0.5 * e0 / Q)
        Delta = secant(excess, Delta0, Delta1, 1e-14 * max(Delta0, 1e-3), 50, "vertical load balance (several patches)",
                       f0=e0, bounds=(0.0, None), ftol=balance_rtol(self.inputs.normal_method.name) * Q,
                       jump_ftol=JUMP_BALANCE_RTOL * Q)
        return cache.get(Delta) or self._at_Delta(Delta), Delta, self.evaluations

    def _solve_one(self, ctx: BalanceCandidate, with_tangential: bool) -> tuple[list[LoadedPatch], float, int]:
        """One candidate: secant iteration on its normal force within the friction bounds."""
        Q = self.inputs.vertical_load_N
        n0 = Q / ctx.cos_g
        if not with_tangential:
            lp = self.load(ctx, n0)
            return [lp], lp.approach_mm, 1
        mu = self.inputs.friction
        limit = ctx.cos_g - mu * abs(ctx.sin_g)
        if not limit > 0:
            raise ConvergenceError("vertical load balance: at the contact angle "
                                   f"{math.degrees(ctx.cand.contact_angle_rad):.1f} deg with friction {mu:g} the "
                                   "contact force cannot carry the vertical load (flange climbing limit)")
        cache: dict[float, LoadedPatch] = {}

        def excess(n: float) -> float:
            cache[n] = self.load(ctx, n)
            return cache[n].vertical_N - Q

        first = self.load(ctx, n0, rough=True)             # not cached: only a full solve can be the result
        n_z = float(first.frame[0][2])
        n1 = (Q - (first.vertical_N - n0 * n_z)) / n_z                    # one fixed-point step
        # steps kept within the friction bounds (widened: the reference point's angle may differ slightly)
        n = secant(excess, n0, n1, 1e-13 * n0, 50, "vertical load balance", f0=first.vertical_N - Q,
                   bounds=(0.5 * Q / (ctx.cos_g + mu * abs(ctx.sin_g)), 2.0 * Q / limit),
                   ftol=balance_rtol(self.inputs.normal_method.name) * Q, jump_ftol=JUMP_BALANCE_RTOL * Q)
        lp = cache.get(n) or self.load(ctx, n)
        return [lp], lp.approach_mm, self.evaluations

    def _at_Delta(self, Delta: float) -> list[LoadedPatch]:
        Q = self.inputs.vertical_load_N
        out = []
        for ctx in self.ctx:
            n = self.force_at_approach(ctx, Delta * ctx.cos_g - ctx.cand.normal_gap_mm)
            if n > 1e-9 * Q:
                out.append(self.load(ctx, n))
        if not out:
            raise ConvergenceError(f"vertical load balance: no patch is loaded at the approach "
                                   f"{Delta:g} mm")
        return out

    def _first_contact_Delta(self) -> float:
        """An approach (mm) at which the candidates together carry more than Q: the primary candidate alone at Q,
        or (its patch truncated) doubled from the largest gap until the normal forces exceed Q."""
        primary = min(self.ctx, key=lambda c: c.cand.normal_gap_mm)
        try:
            sol1 = solve_normal(primary.evaluator.prob, primary.pair)
            return (sol1.delta_mm + primary.cand.normal_gap_mm) / primary.cos_g
        except InputError as err:
            if not isinstance(typed_input_error(err), PatchTruncated):
                raise
        delta_hi = max(c.cand.normal_gap_mm / c.cos_g for c in self.ctx) + 1e-3
        for _ in range(60):
            if self._normal_excess(delta_hi) > 0:
                return delta_hi
            delta_hi *= 2.0
        raise ConvergenceError("vertical load balance: no approach carries "
                               f"{self.inputs.vertical_load_N:g} N")

    def _normal_excess(self, Delta: float) -> float:
        """sum N_i cos(gamma_i) - Q at the approach Delta (KP force-approach relations) (N)."""
        forces = np.array([c.evaluator.force_at(Delta * c.cos_g - c.cand.normal_gap_mm)
                           if Delta * c.cos_g > c.cand.normal_gap_mm else 0.0 for c in self.ctx])
        return float(forces @ np.array([c.cos_g for c in self.ctx])) - self.inputs.vertical_load_N

    def _normal_only_Delta(self) -> float:
        """Delta with sum N_i cos(gamma_i) = Q (KP force-approach relations; Brent)."""
        delta_hi = self._first_contact_Delta()
        if self._normal_excess(delta_hi) <= 0:  # only the primary is loaded (the others cannot close their gap)
            return delta_hi
        try:
            return float(brentq(self._normal_excess, 0.0, delta_hi, xtol=1e-15, rtol=1e-14, maxiter=200))
        except (ValueError, RuntimeError) as err:
            raise ConvergenceError(f"vertical load balance: Brent failed ({err})") from None


__all__ = ["BALANCE_ITER_RTOL", "COARSE_BALANCE_RTOL", "LAYER_F_CAPS_MM", "BalanceCandidate", "LoadedPatch",
           "VerticalBalance", "balance_rtol", "candidate_layers", "candidate_problem", "patch_tangential", "track_vector"]
