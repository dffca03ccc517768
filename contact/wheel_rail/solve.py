"""One wheel on its rail: contact search, vertical load balance, normal and tangential solution per patch, layers
looked up at the contact location, residual displacements mapped back onto both profiles (units mm, N, MPa, s).

Vertical load balance (``method.balance``)
------------------------------------------
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
from its force-approach relation. Converged to |sum F_Z - Q| <= 1e-10 Q (``vertical_balance_rel`` of the final
patches is reported; ConvergenceError above 1e-6). ``balance = "normal"``: sum N_i cos(gamma_i) = Q (the earlier
model, kept for comparison; on the flange it overestimates N by 25-60 %).

Each patch is a separate normal problem in its own contact plane (no elastic interaction between patches), solved
with ``method.normal`` (:func:`contact.normal.method.solve_normal_with`). Each wheel's vertical position is solved
on its own: for a whole wheelset with a given (or rigid-contact, "auto") roll angle the two wheels' approaches
differ slightly, which amounts to an extra roll of (Delta_right - Delta_left) / (wheel distance), ~1e-5 rad at
10 kN, not fed back (the A-2.2 benchmark prescribes the roll per case).

Reference point (``method.contact_point``)
------------------------------------------
"first_contact" or "weighted_centre" (:mod:`contact.wheel_rail.reference_point`): the reported location of a patch,
the point where the creepages and the spin are evaluated, and the origin of FASTSIM's strip coordinate and Mz.

Layers
------
Per body (rail, wheel) a calibration table (anything with ``characteristic_at(y_mm)`` and ``y_range_mm``, e.g.
:class:`contact.layer.layer_table.LayerTable`) is looked up strip by strip at the strip's profile coordinate on that body
(the point of the body's profile on the strip's normal line in the contact plane; only strips with a separation
below ``LAYER_F_CAPS_MM[0]`` get an element, more if the patch reaches further); strips outside a table's range
take its end value, and a strip IN CONTACT outside the range is an InputError. One ``combined`` characteristic
(the paper's eq. 13 layer of both bodies) may be given instead. Passes (paper section 5) run per patch at the
patch's normal force of the first pass (:func:`contact.passes.passes.run_passes`). Each body's accumulated residual
displacement u_p(eta) (along the patch normal, into the body) is mapped back onto the body's profile at the strip
positions and the profile points are moved by -u_p along the profile's outward normal (:func:`deformed_profile`).
With ``WheelRailLayers.scale_to_patch`` every patch's table characteristics are scaled to that patch's own solved
semi-axes (a, b) = (length/2, width/2) (``LayerTable.characteristic_at(y, patch_mm)``: displacements x sqrt(ab) /
sqrt(a_c b_c), issue 12 item 7): the balance is solved, the layers rebuilt at the patches' sizes, and this is
repeated until no loaded patch's a or b changes by more than ``PATCH_SCALING_TOLERANCE`` (ConvergenceError after
``PATCH_SCALING_ITERATIONS`` balances; :func:`contact.layer.patch_scaling.settle_patch_sizes`, shared with the
scenes).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.optimize import brentq

from contact.layer.characteristic import Characteristic
from contact.layer.patch_scaling import settle_patch_sizes
from contact.layer.prandtl_layer import LayerPair, PrandtlLayer
from contact.normal.kik_piotrowski import NormalForceEvaluator, NormalProblem, NormalSolution, solve_normal
from contact.normal.method import NormalMethod, solve_normal_with
from contact.normal.patch import Patch
from contact.passes.passes import PassesOptions, PassRecord, run_passes
from contact.tangential.fastsim import Creepage, TangentialResult, solve_tangential
from contact.wheel_rail.inputs import WheelRailInputs, WheelRailLayers
from contact.wheel_rail.contact_search import ContactCandidate, SearchResult, SearchSettings, search_contacts
from contact.wheel_rail.kinematics import PatchKinematics, contact_frame, creepages
from contact.wheel_rail.reference_point import ReferencePoint, check_contact_point, reference_point
from contact.wheel_rail.track_geometry import (
    PlacedRail,
    TrackLayout,
    WheelsetPose,
    axle_direction,
    place_rail,
    side_sign,
)
from meshes.profiles import Profile
from wrlayer.errors import ConvergenceError, InputError, require

BALANCE_RTOL = 1e-6
#: The balance iteration stops at |sum F_Z - Q| <= BALANCE_ITER_RTOL Q.
BALANCE_ITER_RTOL = 1e-10
#: Barrier heights (mm) up to which neighbouring candidates are merged when their patches grow into each other.
MERGE_RETRY_MM = (0.02, 0.05, 0.1, 0.2, 0.5)
#: Layers are built only on strips whose separation is below the first of these caps (mm) (the virtual penetration
#: alpha delta stays far below 0.3 mm at wheel loads); if a strip in contact has no element, the case is solved again
#: with the next cap.
LAYER_F_CAPS_MM = (0.3, 1.0, np.inf)


@dataclass(eq=False)
class PatchSolution:
    """One loaded contact candidate: geometry (side frame), track-frame vectors, normal and tangential solutions.

    ``strip_sign`` is +1 (right) or -1 (left): the problem's strip coordinate (track orientation) is
    strip_sign * eta of the candidate.
    """

    candidate: ContactCandidate
    side: str
    strip_sign: int
    problem: NormalProblem
    normal: NormalSolution
    normal_force_N: float
    point_track: np.ndarray
    normal_track: np.ndarray
    lateral_track: np.ndarray
    kinematics: PatchKinematics
    tangential: list[TangentialResult]
    passes: list[PassRecord] = field(default_factory=list)
    rail_y_of_strip: np.ndarray | None = None
    wheel_y_of_strip: np.ndarray | None = None
    residual_mm: dict = field(default_factory=dict)
    clamped_strips: dict = field(default_factory=dict)
    reference: ReferencePoint | None = None
    pass_normals: list = field(default_factory=list, repr=False)  # normal solution of every pass (wear outputs)
    layer_patch_mm: tuple[float, float] | None = None  # (a, b) the table layers were scaled to (scale_to_patch)
    layer_scaling_solves: int = 0  # balances solved with scaled layers (scale_to_patch; 0: not scaled)

    @property
    def vertical_N(self) -> float:
        """Z component of the contact force on the wheel (track frame): N cos(gamma) + F_s sin(gamma) (N)."""
        return float(self.force_track_N()[2])

    @property
    def Fx_N(self) -> float:
        return float(sum(t.Fx_N for t in self.tangential))

    @property
    def Fy_N(self) -> float:
        return float(sum(t.Fy_N for t in self.tangential))

    @property
    def Mz_Nmm(self) -> float:
        return float(sum(t.Mz_Nmm for t in self.tangential))

    def force_track_N(self) -> np.ndarray:
        """Force of the rail on the wheel in the track frame (N): N n + Fx e_X + Fy t."""
        return (self.normal_force_N * self.normal_track + self.Fx_N * np.array([1.0, 0.0, 0.0])
                + self.Fy_N * self.lateral_track)


@dataclass(eq=False)
class WheelRailSolution:
    """All loaded patches of one wheel; ``approach_mm`` = Delta (mm, vertical, beyond rigid contact; every wheel, one
    patch or several); ``vertical_balance_rel``: |sum F_Z - Q| / Q of the balanced quantity (balance "total": the
    vertical component of normal + tangential forces; "normal": of the normal forces); ``balance_iterations``:
    patch solves of the balance; ``merge_mm``: the candidate merge level that was used (module docstring)."""

    inputs: WheelRailInputs
    search: SearchResult
    rail: PlacedRail
    patches: list[PatchSolution]
    approach_mm: float
    vertical_balance_rel: float
    unloaded: list[ContactCandidate]
    wheel: Profile
    balance_iterations: int = 0
    merge_mm: float | None = None

    @property
    def vertical_force_N(self) -> float:
        """Z component of the total contact force on the wheel (N)."""
        return float(sum(p.vertical_N for p in self.patches))


def _track_vector(v: np.ndarray, sign: int) -> np.ndarray:
    return np.array([v[0], sign * v[1], v[2]])


def _problem(cand: ContactCandidate, sign: int, inputs: WheelRailInputs, force: float) -> NormalProblem:
    eta, f = (cand.eta_mm, cand.f_mm) if sign > 0 else (-cand.eta_mm[::-1], cand.f_mm[::-1])
    return NormalProblem(eta, f, force, cand.rolling_radius_kp_mm, inputs.E_MPa, inputs.poisson, alpha=inputs.alpha,
                         grid_mm=inputs.grid_mm, interpolation="pchip")


def _clamped_lookup(table: Any, coords: np.ndarray, body: str, name: str,
                    patch_mm: tuple[float, float] | None = None) -> tuple[list[Characteristic], np.ndarray]:
    lo, hi = (float(v) for v in table.y_range_mm)
    clamped = (coords < lo) | (coords > hi)
    cache: dict[float, Characteristic] = {}
    chars = []
    for y in np.clip(coords, lo, hi):
        key = round(float(y), 9)
        if key not in cache:
            try:
                cache[key] = (table.characteristic_at(float(y)) if patch_mm is None
                              else table.characteristic_at(float(y), patch_mm=patch_mm))
            except InputError as err:
                raise InputError(f"layers.{body} ({name})", str(err)) from None
        chars.append(cache[key])
    return chars, clamped


def _layer_pair(cand: ContactCandidate, sign: int, prob: NormalProblem, layers: WheelRailLayers,
                f_cap_mm: float = LAYER_F_CAPS_MM[0], patch_mm: tuple[float, float] | None = None
                ) -> tuple[LayerPair | None, dict, dict]:
    """Per-strip layers of a patch; returns (pair, profile coordinate per body on the strips, clamped masks).
    ``patch_mm`` = (a, b): table characteristics scaled to that patch (``layers.scale_to_patch``)."""
    if layers is None or layers.empty:
        return None, {}, {}
    strips = prob.strip_y_mm
    eta = sign * strips
    coords = {"rail": cand.rail_coordinate(eta), "wheel": cand.wheel_coordinate(eta)}
    near = prob.separation_on_grid_mm <= f_cap_mm
    if layers.combined is not None:
        return LayerPair(combined=PrandtlLayer.uniform(layers.combined, strips[near], name="combined layer")), coords, {}
    built, clamped = {}, {}
    for body in ("rail", "wheel"):
        table = getattr(layers, body)
        if table is None:
            continue
        name = layers.names.get(body, body)
        lo, hi = (float(v) for v in table.y_range_mm)
        clamped[body] = (coords[body] < lo) | (coords[body] > hi)
        chars, _ = _clamped_lookup(table, coords[body][near], body, name, patch_mm)
        built[body] = PrandtlLayer.from_characteristics(chars, strips[near], name=f"{body} layer ({name})")
    return LayerPair(**built), coords, clamped


def _check_coverage(patch: PatchSolution, layers: WheelRailLayers) -> None:
    on = patch.normal.p_peak_MPa > 0
    for body, mask in patch.clamped_strips.items():
        if np.any(mask & on):
            lo, hi = (float(v) for v in getattr(layers, body).y_range_mm)
            ys = (patch.rail_y_of_strip if body == "rail" else patch.wheel_y_of_strip)[mask & on]
            raise InputError(f"layers.{body} ({layers.names.get(body, body)})",
                             f"does not cover the contact location: strips in contact at y = {ys.min():.4g}.."
                             f"{ys.max():.4g} mm on the {body}, the table covers {lo:.4g}..{hi:.4g} mm")


# ------------------------------------------------------------------------------------------------ load balance
@dataclass(eq=False)
class _Candidate:
    """A contact candidate prepared for the balance: layers, angle, the KP approach -> force evaluator."""

    cand: ContactCandidate
    pair: Any
    coords: dict
    clamped: dict
    cos_g: float
    sin_g: float
    evaluator: NormalForceEvaluator
    sign: int = 1
    delta_guess: float | None = None
    layer_patch_mm: tuple[float, float] | None = None


@dataclass(eq=False)
class _Loaded:
    """One candidate solved at a normal force: normal and tangential solution at its reference point."""

    ctx: _Candidate
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
        n_track = _track_vector(self.ref.normal, self.ctx.sign)
        return n_track, contact_frame(n_track)[1]


class _Balance:
    """Vertical load balance of one wheel (module docstring): the candidates' normal forces such that the vertical
    component of the total contact force (or, with ``balance = "normal"``, of the normal forces only) equals Q."""

    def __init__(self, found: SearchResult, rail: PlacedRail, wheel: Profile, inputs: WheelRailInputs,
                 layers: WheelRailLayers, sign: int, case: str, f_cap_mm: float,
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
            prob = _problem(c, sign, inputs, Q / cg)
            pair, coords, clamped = _layer_pair(c, sign, prob, layers, f_cap_mm, patch_mm.get(k))
            self.ctx.append(_Candidate(c, pair, coords, clamped, cg, sg, NormalForceEvaluator(prob, pair), sign,
                                       layer_patch_mm=patch_mm.get(k)))

    # -- one candidate at a force
    def load(self, ctx: _Candidate, force: float) -> _Loaded:
        """Solve ``ctx`` at the normal force ``force`` (N): normal solution, reference point, creepages there,
        FASTSIM about it."""
        self.evaluations += 1
        inp = self.inputs
        prob = _problem(ctx.cand, self.sign, inp, force)
        sol = solve_normal_with(inp.normal_method, prob, ctx.pair, delta_guess_mm=ctx.delta_guess)
        ctx.delta_guess = sol.delta_mm
        ref = reference_point(inp.contact_point, ctx.cand, sol.delta_mm, self.wheel, inp.layout, self.pose_side,
                              self.rail)
        point = _track_vector(ref.point_mm, self.sign)
        n_track = _track_vector(ref.normal, self.sign)
        centre = np.array([0.0, inp.pose.lateral_mm, self.found.wheel_height_mm])   # rigid-contact geometry
        kin = creepages(point, n_track, centre, self.axle, inp.speed_mm_s, inp.omega_rad_s)
        tang = _tangential(sol, kin, inp, self.sign * ref.eta_mm)
        return _Loaded(ctx, float(force), prob, sol, ref, kin, tang)

    def force_at_approach(self, ctx: _Candidate, delta: float) -> float:
        """Normal force (N) of a candidate at the normal approach ``delta`` (mm); 0 when it does not touch."""
        if delta <= 0:
            return 0.0
        n_kp = ctx.evaluator.force_at(delta)
        if self.inputs.normal_method.name == "kik_piotrowski" or n_kp <= 0:
            return n_kp
        # another normal method: invert its force -> approach relation, starting at the KP force
        def miss(log_n: float) -> float:
            return self._solve_only(ctx, math.exp(log_n)).delta_mm - delta
        x = _secant(miss, math.log(n_kp), math.log(n_kp) + 0.05, 1e-12, 40, f"{self.case}: approach of a patch")
        return math.exp(x)

    def _solve_only(self, ctx: _Candidate, force: float) -> NormalSolution:
        return solve_normal_with(self.inputs.normal_method, _problem(ctx.cand, self.sign, self.inputs, force),
                                 ctx.pair)

    # -- the balance
    def solve(self) -> tuple[list[_Loaded], float, int]:
        """(loaded candidates, vertical approach Delta (mm), number of balance iterations)."""
        Q = self.inputs.vertical_load_N
        with_tangential = self.inputs.balance == "total" and self.inputs.friction > 0
        if len(self.ctx) == 1:
            ctx = self.ctx[0]
            n0 = Q / ctx.cos_g
            if not with_tangential:
                lp = self.load(ctx, n0)
                return [lp], self._Delta(lp), 1
            mu = self.inputs.friction
            limit = ctx.cos_g - mu * abs(ctx.sin_g)
            if not limit > 0:
                raise ConvergenceError(f"{self.case}: vertical load balance: at the contact angle "
                                       f"{math.degrees(ctx.cand.contact_angle_rad):.1f} deg with friction {mu:g} the "
                                       "contact force cannot carry the vertical load (flange climbing limit)")
            cache: dict[float, _Loaded] = {}

            def excess(n: float) -> float:
                cache[n] = self.load(ctx, n)
                return cache[n].vertical_N - Q

            first = self.load(ctx, n0)
            cache[n0] = first
            n_z = float(first.frame[0][2])
            n1 = (Q - (first.vertical_N - n0 * n_z)) / n_z                    # one fixed-point step
            # steps kept within the friction bounds (widened: the reference point's angle may differ slightly)
            n = _secant(excess, n0, n1, 1e-13 * n0, 50, f"{self.case}: vertical load balance", f0=first.vertical_N - Q,
                        bounds=(0.5 * Q / (ctx.cos_g + mu * abs(ctx.sin_g)), 2.0 * Q / limit),
                        ftol=BALANCE_ITER_RTOL * Q)
            lp = cache.get(n) or self.load(ctx, n)
            return [lp], self._Delta(lp), self.evaluations
        # several candidates: one vertical approach Delta shared by all (Brent on the normal balance first)
        Delta0 = self._normal_only_Delta()
        if not with_tangential:
            return self._at_Delta(Delta0), Delta0, self.evaluations
        cache_d: dict[float, list[_Loaded]] = {}

        def excess_d(Delta: float) -> float:
            cache_d[Delta] = self._at_Delta(Delta)
            return sum(lp.vertical_N for lp in cache_d[Delta]) - Q

        e0 = excess_d(Delta0)
        Delta1 = Delta0 * (1.0 - 0.5 * e0 / Q)
        Delta = _secant(excess_d, Delta0, Delta1, 1e-14 * max(Delta0, 1e-3), 50, f"{self.case}: vertical load "
                        "balance (several patches)", f0=e0, bounds=(0.0, None),
                        ftol=BALANCE_ITER_RTOL * Q)
        return cache_d.get(Delta) or self._at_Delta(Delta), Delta, self.evaluations

    def _Delta(self, lp: _Loaded) -> float:
        return (lp.normal.delta_mm + lp.ctx.cand.normal_gap_mm) / lp.ctx.cos_g

    def _at_Delta(self, Delta: float) -> list[_Loaded]:
        Q = self.inputs.vertical_load_N
        out = []
        for ctx in self.ctx:
            n = self.force_at_approach(ctx, Delta * ctx.cos_g - ctx.cand.normal_gap_mm)
            if n > 1e-9 * Q:
                out.append(self.load(ctx, n))
        if not out:
            raise ConvergenceError(f"{self.case}: vertical load balance: no patch is loaded at the approach "
                                   f"{Delta:g} mm")
        return out

    def _normal_only_Delta(self) -> float:
        """Delta with sum N_i cos(gamma_i) = Q (KP force-approach relations; Brent)."""
        Q = self.inputs.vertical_load_N
        ctx = self.ctx

        def forces(Delta: float) -> np.ndarray:
            return np.array([c.evaluator.force_at(Delta * c.cos_g - c.cand.normal_gap_mm)
                             if Delta * c.cos_g > c.cand.normal_gap_mm else 0.0 for c in ctx])

        def excess(Delta: float) -> float:
            return float(forces(Delta) @ np.array([c.cos_g for c in ctx])) - Q

        primary = min(ctx, key=lambda c: c.cand.normal_gap_mm)
        try:
            sol1 = solve_normal(primary.evaluator.prob, primary.pair)
            delta_hi = (sol1.delta_mm + primary.cand.normal_gap_mm) / primary.cos_g
        except InputError as err:
            if err.what != "separation.y_mm":
                raise
            delta_hi = max(c.cand.normal_gap_mm / c.cos_g for c in ctx) + 1e-3
            for _ in range(60):
                if excess(delta_hi) > 0:
                    break
                delta_hi *= 2.0
            else:
                raise ConvergenceError(f"{self.case}: vertical load balance: no approach carries {Q:g} N") from None
        if excess(delta_hi) <= 0:  # only the primary is loaded (the others cannot close their gap)
            return delta_hi
        try:
            return float(brentq(excess, 0.0, delta_hi, xtol=1e-15, rtol=1e-14, maxiter=200))
        except (ValueError, RuntimeError) as err:
            raise ConvergenceError(f"{self.case}: vertical load balance: Brent failed ({err})") from None


def _secant(fun, x0: float, x1: float, xtol: float, maxiter: int, what: str, f0: float | None = None,
            bounds: tuple[float | None, float | None] = (None, None), ftol: float = 0.0) -> float:
    """Root of a smooth monotone scalar function by the secant method, steps kept inside ``bounds`` (halfway to a
    bound when a step would leave them); stops when a step is below ``xtol`` or |f| <= ``ftol``.
    ConvergenceError after ``maxiter`` steps."""
    lo, hi = bounds
    f0 = fun(x0) if f0 is None else f0
    if abs(f0) <= ftol:
        return x0
    f1 = fun(x1)
    for _ in range(maxiter):
        if abs(f1) <= ftol or abs(x1 - x0) <= xtol:
            return x1
        if f1 == f0:
            break
        x2 = x1 - f1 * (x1 - x0) / (f1 - f0)
        if lo is not None and x2 <= lo:
            x2 = 0.5 * (x1 + lo)
        if hi is not None and x2 >= hi:
            x2 = 0.5 * (x1 + hi)
        if not math.isfinite(x2):
            break
        x0, f0, x1 = x1, f1, x2
        f1 = fun(x1)
    raise ConvergenceError(f"{what}: the secant iteration did not converge (last step {x1 - x0:.3g}, residual "
                           f"{f1:.3g})")


def solve_wheel(rail_profile: Profile, wheel_profile: Profile, inputs: WheelRailInputs,
                layers: WheelRailLayers | None = None, placed_rail: PlacedRail | None = None,
                case: str = "wheel-rail case") -> WheelRailSolution:
    """Solve one wheel on its rail (see the module docstring). ``placed_rail`` may be passed to reuse a placement
    (it depends only on the rail profile and the layout).

    Patches that grow into each other (a patch reaching the barrier to its neighbouring candidate) are merged: the
    contact search is repeated with a larger ``merge_mm`` (:data:`MERGE_RETRY_MM`) so that the neighbours become one
    candidate with one separation function (in the contact plane of the lower minimum), on which the normal solver
    finds the interacting regions itself. ``WheelRailSolution.merge_mm`` records the value used."""
    rail = placed_rail if placed_rail is not None else place_rail(rail_profile, inputs.layout)
    first_error = None
    merges = [inputs.search.merge_mm] + [m for m in MERGE_RETRY_MM if m > inputs.search.merge_mm]
    for merge in merges:
        try:
            sol = _solve_with_search(rail, wheel_profile, inputs, layers, case,
                                     dataclasses.replace(inputs.search, merge_mm=merge))
            sol.merge_mm = merge
            return sol
        except InputError as err:
            if err.what != "separation.y_mm":
                raise
            first_error = first_error or err
        except ConvergenceError as err:
            if str(err).startswith(case):
                raise
            raise ConvergenceError(f"{case}: {err}") from None
    raise InputError(case, "a contact patch reaches the end of its separation function (the barrier to the "
                     "neighbouring contact candidate, or the search cap of "
                     f"{inputs.search.f_cap_mm:g} mm) even with candidates merged up to merge_mm = "
                     f"{merges[-1]:g} mm ({first_error.problem})") from None


def _solve_with_search(rail: PlacedRail, wheel_profile: Profile, inputs: WheelRailInputs,
                       layers: WheelRailLayers | None, case: str, search: SearchSettings) -> WheelRailSolution:
    sign = side_sign(inputs.side)
    pose_side = inputs.pose.for_side(inputs.side)
    found = search_contacts(rail, wheel_profile, inputs.layout, pose_side, search, case=case)
    layers = layers if layers is not None else WheelRailLayers()
    for k, cap in enumerate(LAYER_F_CAPS_MM):
        try:
            return _solve_found(found, rail, wheel_profile, inputs, layers, sign, case, cap)
        except InputError as err:  # a strip in contact without a layer element: widen the layer
            if err.what == "separation.y_mm" or k == len(LAYER_F_CAPS_MM) - 1 or not _is_layer_name(err.what):
                raise
    raise AssertionError("unreachable")


def _is_layer_name(what: str) -> bool:
    return what == "combined layer" or (" layer (" in what and not what.startswith("layers."))


def _solve_found(found: SearchResult, rail: PlacedRail, wheel_profile: Profile, inputs: WheelRailInputs,
                 layers: WheelRailLayers, sign: int, case: str, f_cap_mm: float) -> WheelRailSolution:
    balance = _Balance(found, rail, wheel_profile, inputs, layers, sign, case, f_cap_mm)
    loaded, Delta, iterations = balance.solve()
    scaling_solves = 0
    if layers.scale_to_patch:  # the fixed point over each loaded candidate's patch size (module docstring)
        counts = [iterations]

        def solve_at(sizes: dict):
            scaled = _Balance(found, rail, wheel_profile, inputs, layers, sign, case, f_cap_mm, sizes)
            solved = scaled.solve()
            counts.append(solved[2])
            return (scaled, *solved), _patch_sizes(scaled, solved[0])

        (balance, loaded, Delta, _), _, scaling_solves = settle_patch_sizes(
            solve_at, _patch_sizes(balance, loaded), f"{case}: layers.scale_to_patch")
        iterations = sum(counts)
    patches = []
    for lp in loaded:
        ctx = lp.ctx
        c, pair, coords, clamped = ctx.cand, ctx.pair, ctx.coords, ctx.clamped
        records: list[PassRecord] = []
        holder: list[NormalSolution] = []
        sol, tang = lp.normal, lp.tangential
        if pair is not None:  # passes (paper section 5) at the balanced force; pass 1 is the balanced solution
            records, _ = run_passes(lp.prob, pair, inputs.passes, on_pass=lambda rec, s, h=holder: h.append(s),
                                    method=inputs.normal_method)
        if not coords:
            eta = sign * lp.prob.strip_y_mm
            coords = {"rail": c.rail_coordinate(eta), "wheel": c.wheel_coordinate(eta)}
        n_track, t_track = lp.frame
        patch = PatchSolution(c, inputs.side, sign, lp.prob, sol, float(sol.normal_force_N),
                              _track_vector(lp.ref.point_mm, sign), n_track, t_track, lp.kin, tang, records,
                              coords.get("rail"), coords.get("wheel"),
                              {} if not records else {k: np.asarray(v) for k, v in
                                                      records[-1].cumulative_residual_mm.items()}, clamped,
                              reference=lp.ref, layer_patch_mm=ctx.layer_patch_mm,
                              layer_scaling_solves=scaling_solves)
        patch.pass_normals = list(holder) if pair is not None else [sol]
        if pair is not None:
            _check_coverage(patch, layers)
        patches.append(patch)
    Q = inputs.vertical_load_N
    if inputs.balance == "total":
        vertical = sum(float(p.force_track_N()[2]) for p in patches)
    else:
        vertical = sum(p.normal_force_N * math.cos(p.candidate.contact_angle_rad) for p in patches)
    rel = abs(vertical - Q) / Q
    if not rel <= BALANCE_RTOL:
        raise ConvergenceError(f"{case}: vertical load balance off by {rel:.3g} (relative) > {BALANCE_RTOL:g}")
    unloaded = [c for c in found.candidates if all(c is not p.candidate for p in patches)]
    return WheelRailSolution(inputs, found, rail, patches, float(Delta), rel, unloaded, wheel_profile,
                             balance_iterations=iterations)


def _patch_sizes(balance: _Balance, loaded: list[_Loaded]) -> dict[int, tuple[float, float]]:
    """Candidate index -> solved semi-axes (a, b) = (length/2, width/2) (mm) of every loaded candidate."""
    index = {id(ctx): k for k, ctx in enumerate(balance.ctx)}
    return {index[id(lp.ctx)]: (0.5 * lp.normal.length_mm, 0.5 * lp.normal.width_mm) for lp in loaded}


def _tangential(sol: NormalSolution, kin: PatchKinematics, inputs: WheelRailInputs,
                eta_ref_mm: float = 0.0) -> list[TangentialResult]:
    """FASTSIM on every region of the patch; strip coordinate (problem orientation) and spin about ``eta_ref_mm``
    (the reference point, problem orientation) where the creepages ``kin`` were evaluated. With the exact normal
    solver each strip carries the exact pressure along its line (semi-ellipses with Kik–Piotrowski)."""
    if inputs.friction == 0:
        return []
    cr = Creepage(kin.vx, kin.vy, kin.phi_per_mm)
    out = []
    for k, p in enumerate(sol.patches):
        shifted = p if eta_ref_mm == 0.0 else Patch(p.grid_mm, p.y_mm - eta_ref_mm, p.x_lead_mm, p.p_peak_MPa)
        kw = {}
        if getattr(sol, "field", None) is not None:   # the exact solver: FASTSIM on its pressure, line by line
            from contact.normal.exact import fastsim_pressure, strip_centres

            kw["pressure_cells_MPa"] = fastsim_pressure(sol, k, inputs.fastsim_cells)
            kw["strip_centre_mm"] = strip_centres(sol, k)
        out.append(solve_tangential(shifted, cr, inputs.G_MPa, inputs.poisson, inputs.friction, inputs.speed_mm_s,
                                    nx=inputs.fastsim_cells, **kw))
    return out


# ------------------------------------------------------------------------------------------------ deformed profiles
def deformed_profile(profile: Profile, y_strip_mm: np.ndarray, residual_mm: np.ndarray, spacing_mm: float = 0.1
                     ) -> np.ndarray:
    """Points (n, 2) of ``profile`` with the residual displacement u_p(y) (mm, into the body, given at the profile
    coordinates ``y_strip_mm`` of the strips; zero elsewhere) applied along the inward normal.

    The points are at ``spacing_mm`` in y over the profile's range plus the strip positions (so a dent narrower than
    the spacing is still resolved); u_p is interpolated linearly between strips.
    """
    ys = np.asarray(y_strip_mm, dtype=float)
    up = np.asarray(residual_mm, dtype=float)
    order = np.argsort(ys)
    ys, up = ys[order], up[order]
    y = np.linspace(profile.y_min, profile.y_max, int(np.ceil((profile.y_max - profile.y_min) / spacing_mm)) + 1)
    inside = ys[(ys > profile.y_min) & (ys < profile.y_max)]
    y = np.unique(np.concatenate([y, inside]))
    u = np.interp(y, ys, up, left=0.0, right=0.0) if ys.size else np.zeros_like(y)
    n = profile.normal(y)
    pts = np.column_stack([y, profile.z(y)]) - u[:, None] * n
    keep = np.concatenate([[True], np.diff(pts[:, 0]) > 1e-9])
    return pts[keep]


def residual_on_profiles(patches: list[PatchSolution]) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Per body ("rail", "wheel"): (profile coordinates, residual displacement) of all loaded strips of all patches.

    A ``combined`` layer's residual is split equally between the two bodies (it stands for both together).
    """
    out: dict[str, list] = {"rail": [[], []], "wheel": [[], []]}
    for p in patches:
        if not p.residual_mm:
            continue
        coords = {"rail": p.rail_y_of_strip, "wheel": p.wheel_y_of_strip}
        for body in ("rail", "wheel"):
            if body in p.residual_mm:
                u = p.residual_mm[body]
            elif "combined" in p.residual_mm:
                u = 0.5 * p.residual_mm["combined"]
            else:
                continue
            out[body][0].append(coords[body])
            out[body][1].append(u)
    return {b: (np.concatenate(v[0]), np.concatenate(v[1])) for b, v in out.items() if v[0]}


__all__ = [
    "BALANCE_RTOL",
    "PatchSolution",
    "WheelRailInputs",
    "WheelRailLayers",
    "WheelRailSolution",
    "deformed_profile",
    "residual_on_profiles",
    "rigid_roll",
    "solve_wheel",
]


def rigid_roll(rail: PlacedRail, wheel: Profile, layout: TrackLayout, pose: WheelsetPose,
               settings: SearchSettings | None = None, bracket_rad: float = 0.05) -> float:
    """Roll angle (rad) of a rigid wheelset (identical wheels and rails left and right) at which both wheels touch
    their rails when it is lowered: the minimum vertical gaps of the two sides are equal (Brent, 1e-12 rad).
    ``pose.roll_rad`` is ignored."""
    from contact.wheel_rail.contact_search import raw_min_gap

    settings = settings or SearchSettings()

    def difference(roll: float) -> float:
        p = WheelsetPose(pose.lateral_mm, pose.yaw_rad, roll)
        return (raw_min_gap(rail, wheel, layout, p.for_side("right"), settings)
                - raw_min_gap(rail, wheel, layout, p.for_side("left"), settings))

    lo, hi = -bracket_rad, bracket_rad
    d_lo, d_hi = difference(lo), difference(hi)
    if d_lo * d_hi > 0:
        raise ConvergenceError(f"rigid wheelset roll: no root in [{lo:g}, {hi:g}] rad (both wheels cannot touch)")
    return float(brentq(difference, lo, hi, xtol=1e-12, rtol=1e-12, maxiter=100))
