"""Quasi-static curving: the lateral position y and the yaw (attack angle) psi of a wheelset in a steady curve,
found from the balance of the lateral forces and of the yaw moments (units mm, N, N mm, s, rad).

Model (the quasi-static curving of one wheelset, as multibody codes solve it: Iwnicki (ed.), Handbook of Railway
Vehicle Dynamics, 2006, ch. 9; Wickens, Fundamentals of Rail Vehicle Dynamics, 2003, ch. 7). The wheelset runs at
the speed V with the yaw rate psi' = -V kappa of the curve and the pitch rate omega: a condition's given pitch rate
(traction, braking), or free (no torque about the axle, T = 0 below; solved by a secant for every (y, psi) from
the last omega, starting at V / r0); both wheels are solved by the wheel-rail solver
(:func:`contact.wheel_rail.solve.solve_wheel`: contact search, each wheel's vertical load balanced, the tread and
the flange as separate patches, creepages from :func:`contact.wheel_rail.kinematics.creepages`, the tangential
forces of ``method.tangential``), elastic (no layer, no passes). With F_i the force of the rail on the wheel at
patch i (normal force along the contact normal plus the creep forces, track frame) at the point P_i:

    R_y(y, psi)   = sum_i F_Y,i + s m a_u - k_y y                                  = 0     (lateral)
    R_psi(y, psi) = sum_i [(P_i - C) x F_i]_Z + M_z,i n_Z,i - k_psi (psi - psi_f)  = 0     (yaw)
    T(omega)      = sum_i [(P_i - C) x (F_i - N_i n_i)] . a                         = 0     (free pitch)

m = (Q_right + Q_left) / g the mass the wheelset carries, a_u the unbalanced lateral acceleration
(:class:`contact.wear.curving.CurveSpec`), s = sign(kappa) (the force points to the outer rail), C the wheelset
centre, a the axle direction, N_i n_i the normal force (it meets the axle of the wheel, a surface of revolution,
so only the creep forces have a torque about it), M_z,i the patch's spin moment about its normal n_i; k_y,
k_psi: lateral and yaw stiffness of the primary suspension to a bogie frame held on the track centre line at the
yaw psi_f relative to the track tangent (0: a radial frame); k_y = k_psi = 0: a free wheelset.

Solution (nested, both by Brent's method, :func:`scipy.optimize.brentq`): for a given y, psi(y) solves R_y = 0
(the creep forces rise steeply with the attack angle; bracket grown from the last psi); the outer function
g(y) = R_psi(y, psi(y)) decreases with y (the longitudinal creep moment 2 e0 f11 (e0/R - lambda y/r0) of the
linear theory, and the flange's lateral force turning psi), so its root is bracketed by stepping from y = 0 in
:data:`SCAN_STEP_MM` towards the outer rail until g changes sign. Where no attack angle balances the lateral force
(the creep forces saturate at mu N), g is taken as +-:data:`UNBALANCED` on the side of the missing force, so that
the scan moves on towards the flange; a solve that fails (flange climbing, no contact) ends the scan. The result
is accepted when |R_y| <= :data:`LATERAL_RTOL` (Q_right + Q_left) and |R_psi| <= :data:`YAW_RTOL` (Q_right +
Q_left) e0 (and |T| <= LATERAL_RTOL (Q_right + Q_left) r0 by the secant); otherwise a ConvergenceError (never a
silent result).

For a conical wheelset (conicity lambda, half distance e0 of the contact points, rolling radius r0) without
suspension and cant deficiency this is the pure rolling line y0 = e0 r0 / (lambda R) with psi = 0 (Boocock,
"Steady-state motion of railway vehicles on curved track", J. Mech. Eng. Sci. 11 (1969) 556-566).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from contact.wear.curving import G_MM_S2, CurvingBalance
from contact.wheel_rail.inputs import WheelRailInputs
from contact.wheel_rail.solution import WheelRailSolution
from contact.wheel_rail.solve import solve_wheel
from contact.wheel_rail.track_geometry import SIDES, PlacedRail, WheelsetPose, axle_direction
from meshes.profiles import Profile
from wrlayer.errors import ConvergenceError, InputError
from wrlayer.json_io import Record

#: Accepted lateral residual |R_y| relative to the axle load Q_right + Q_left (-).
LATERAL_RTOL = 1e-4
#: Accepted yaw-moment residual |R_psi| relative to (Q_right + Q_left) e0 (-).
YAW_RTOL = 1e-4
#: Step (mm) of the scan for the bracket of the lateral position, and its largest |y| (mm; beyond any flangeway).
SCAN_STEP_MM = 1.0
SCAN_MAX_MM = 20.0
#: First step (rad) of the attack-angle bracket; it doubles up to |psi| <= PSI_MAX_RAD.
PSI_STEP_RAD = 1e-3
PSI_MAX_RAD = 0.05
#: A free wheelset's pitch rate: first step, largest change and tolerance of its root, relative to omega (-).
OMEGA_STEP = 1e-5
OMEGA_RANGE = 0.2
OMEGA_XTOL = 1e-8
#: Brent's tolerances on y (mm) and psi (rad).
Y_XTOL_MM = 1e-5
PSI_XTOL_RAD = 1e-9
#: The inner Newton: units of psi (rad) and of omega (relative to V / r0), steps, residual at convergence (in
#: tolerances), largest step and finite-difference step (in units).
PSI_SCALE_RAD = 1e-3
OMEGA_SCALE = 1e-3
NEWTON_STEPS = 12
NEWTON_FTOL = 0.1
NEWTON_MAX_STEP = 20.0
NEWTON_FD_STEP = 1e-2
#: The outer function's value (N mm) where no attack angle balances the lateral force.
UNBALANCED = 1e12


@dataclass(frozen=True, kw_only=True)
class WheelsetBalance(Record):
    """The balanced wheelset of a condition as result.json records it (``steps[].balance[]``).

    Attributes
    ----------
    condition : int
        Index of the condition in the collective (0-based).
    lateral_mm : float
        Lateral position y found (mm, towards the right rail).
    yaw_rad : float
        Yaw psi found (rad, relative to the track tangent).
    lateral_residual_N : float
        R_y at (y, psi) (N).
    yaw_residual_Nmm : float
        R_psi at (y, psi) (N mm).
    external_lateral_N : float
        s m a_u (N): the unbalanced lateral force the contacts carry (without the suspension's).
    creep_lateral_N : float
        Sum of the creep forces' track-Y components over both wheels (N).
    longitudinal_N : float
        Sum of the contact forces' X components over both wheels (N; ~0 with a free pitch rate).
    pitch_rate_rad_s : float
        The pitch rate omega (rad/s): found (free wheelset, no torque about the axle) or the condition's.
    wheel_solves : int
        Wheel solves of the balance.
    """

    condition: int
    lateral_mm: float
    yaw_rad: float
    lateral_residual_N: float
    yaw_residual_Nmm: float
    external_lateral_N: float
    creep_lateral_N: float
    longitudinal_N: float
    pitch_rate_rad_s: float
    wheel_solves: int


@dataclass(frozen=True)
class Wheelset:
    """Both wheels on their rails: ``profiles[side] = (rail, wheel)``, ``placed[side]``: the rails placed,
    ``inputs[side]``: each wheel's solver inputs (load, speed, yaw rate; the pose and the pitch rate are
    replaced); the roll is ``roll_rad`` or, with ``roll_of``, the rigid wheelset's at each pose."""

    profiles: dict[str, tuple[Profile, Profile]]
    placed: dict[str, PlacedRail]
    inputs: dict[str, WheelRailInputs]
    roll_rad: float = 0.0
    roll_of: Callable[[WheelsetPose], float] | None = None

    def solve(self, lateral_mm: float, yaw_rad: float, pitch_rate_rad_s: float, case: str
              ) -> dict[str, WheelRailSolution]:
        """Both wheels solved at (y, psi, omega), with the roll ``roll_rad`` or ``roll_of(pose)``."""
        pose = WheelsetPose(lateral_mm, yaw_rad, self.roll_rad)
        if self.roll_of is not None:
            pose = WheelsetPose(lateral_mm, yaw_rad, self.roll_of(pose))
        out = {}
        for side in SIDES:
            rail, wheel = self.profiles[side]
            inputs = dataclasses.replace(self.inputs[side], pose=pose, pitch_rate_rad_s=pitch_rate_rad_s)
            out[side] = solve_wheel(rail, wheel, inputs, None, self.placed[side], case=f"{case}, {side} wheel")
        return out


@dataclass(frozen=True)
class WheelsetForces:
    """Sums over both wheels' patches (track frame): lateral force (N), yaw moment about the centre (N mm), torque
    about the axle (N mm), the creep forces' lateral part (N) and the longitudinal force (N)."""

    lateral_N: float
    yaw_Nmm: float
    axle_torque_Nmm: float
    creep_lateral_N: float
    longitudinal_N: float


def wheelset_forces(solutions: dict[str, WheelRailSolution]) -> WheelsetForces:
    """The contact forces of the rails on both wheels summed (module docstring), moments about the wheelset
    centre (0, y, Z_c) of each wheel's solution."""
    total, moment, creep_y = np.zeros(3), np.zeros(3), 0.0
    torque = 0.0
    for sol in solutions.values():
        centre = np.array([0.0, sol.inputs.pose.lateral_mm, sol.search.wheel_height_mm])
        axle = axle_direction(sol.inputs.pose)
        for p in sol.patches:
            force = p.force_track_N()
            arm = p.point_track - centre
            total += force
            moment += np.cross(arm, force) + p.Mz_Nmm * p.normal_track
            # the normal of a wheel (a surface of revolution) meets its axle: only the creep forces turn it
            creep = force - p.normal_force_N * p.normal_track
            torque += float(np.cross(arm, creep) @ axle)
            creep_y += p.Fy_N * p.lateral_track[1]
    return WheelsetForces(float(total[1]), float(moment[2]), torque, float(creep_y), float(total[0]))


def grown_root(fun: Callable[[float], float], x0: float, step: float, limit: float, xtol: float) -> float | None:
    """Root of an increasing function ``fun`` near ``x0``: a bracket grown from x0 by doubling steps (starting at
    ``step``) towards the root, then Brent to ``xtol``; None when |x - x0| would exceed ``limit``."""
    a, fa = x0, fun(x0)
    if fa == 0.0:
        return a
    step = -math.copysign(step, fa)
    while True:
        b = a + step
        if abs(b - x0) > limit:
            return None
        fb = fun(b)
        if fb * fa <= 0.0:
            break
        a, fa, step = b, fb, 2.0 * step
    return float(brentq(fun, min(a, b), max(a, b), xtol=xtol, rtol=4 * np.finfo(float).eps, maxiter=100))


@dataclass(frozen=True)
class Evaluation:
    """The wheelset at (y, psi, omega): R_y (N), R_psi (N mm) and the contact forces."""

    psi: float
    omega: float
    lateral_residual_N: float
    yaw_residual_Nmm: float
    forces: WheelsetForces


class QuasiStaticCurving:
    """The balance of one wheelset in a steady curve of curvature ``kappa_1_per_mm`` (module docstring);
    ``pitch_rate_rad_s`` None: free (solved with the torque about the axle), else given; ``case`` names it in
    errors."""

    def __init__(self, wheelset: Wheelset, balance: CurvingBalance, kappa_1_per_mm: float, e0_mm: float,
                 case: str, pitch_rate_rad_s: float | None = None):
        if kappa_1_per_mm == 0.0:
            raise InputError(case, "the quasi-static curving balance needs a curve (curvature_1_per_m != 0)")
        self.wheelset, self.balance, self.case = wheelset, balance, case
        inputs = wheelset.inputs["right"]
        axle_load = sum(i.vertical_load_N for i in wheelset.inputs.values())
        self.external_N = math.copysign(1.0, kappa_1_per_mm) * axle_load / G_MM_S2 * \
            balance.unbalanced_acceleration_mm_s2
        self.lateral_tol_N = LATERAL_RTOL * axle_load
        self.yaw_tol_Nmm = YAW_RTOL * axle_load * e0_mm
        self.torque_tol_Nmm = LATERAL_RTOL * axle_load * inputs.layout.nominal_radius_mm
        self.free_pitch = pitch_rate_rad_s is None
        self.omega = inputs.speed_mm_s / inputs.layout.nominal_radius_mm if self.free_pitch else pitch_rate_rad_s
        self.omega0 = self.omega
        self.solves = 0
        self.psi = 0.0
        self.jacobian: np.ndarray | None = None
        self.last: Evaluation | None = None
        self.seen: dict[float, tuple[float, Evaluation | None]] = {}

    def evaluate(self, y: float, psi: float, omega: float) -> Evaluation:
        """Both wheels solved at (y, psi, omega) and the residuals there."""
        b = self.balance
        self.solves += 2
        forces = wheelset_forces(self.wheelset.solve(y, psi, omega, self.case))
        r_y = forces.lateral_N + self.external_N - b.lateral_stiffness_N_per_mm * y
        r_psi = forces.yaw_Nmm - b.yaw_stiffness_Nmm_per_rad * (psi - b.frame_yaw_rad)
        return Evaluation(psi, omega, r_y, r_psi, forces)

    def _scaled(self, e: Evaluation) -> np.ndarray:
        """The inner residuals in units of their tolerances: R_y and, with a free pitch rate, T."""
        r = [e.lateral_residual_N / self.lateral_tol_N]
        return np.array(r + [e.forces.axle_torque_Nmm / self.torque_tol_Nmm] if self.free_pitch else r)

    def _at(self, y: float, u: np.ndarray) -> Evaluation:
        """The evaluation at the scaled unknowns u = (psi / PSI_SCALE_RAD[, omega / (OMEGA_SCALE omega0)])."""
        omega = u[1] * OMEGA_SCALE * self.omega0 if self.free_pitch else self.omega
        return self.evaluate(y, float(u[0] * PSI_SCALE_RAD), float(omega))

    def newton(self, y: float) -> Evaluation | None:
        """psi (and a free omega) balancing R_y (and T) at y: Newton with Broyden's update of the Jacobian kept
        from the last y, in units of the tolerances; None when it does not converge in NEWTON_STEPS."""
        u = np.array([self.psi / PSI_SCALE_RAD, self.omega / (OMEGA_SCALE * self.omega0)][:1 + self.free_pitch])
        e = self._at(y, u)
        f = self._scaled(e)
        if self.jacobian is None:
            self.jacobian = np.empty((f.size, f.size))
            for k in range(f.size):
                du = np.zeros(f.size)
                du[k] = NEWTON_FD_STEP
                self.jacobian[:, k] = (self._scaled(self._at(y, u + du)) - f) / NEWTON_FD_STEP
        for _ in range(NEWTON_STEPS):
            if np.all(np.abs(f) <= NEWTON_FTOL):
                self.psi, self.omega = e.psi, e.omega
                return e
            try:
                du = np.linalg.solve(self.jacobian, -f)
            except np.linalg.LinAlgError:
                return None
            du *= min(1.0, NEWTON_MAX_STEP / max(np.max(np.abs(du)), 1e-300))
            if abs(u[0] + du[0]) * PSI_SCALE_RAD > PSI_MAX_RAD:
                return None
            try:
                e = self._at(y, u + du)
            except (ConvergenceError, InputError):
                return None              # the bracketed path reports it if it is real
            f_new = self._scaled(e)
            self.jacobian += np.outer(f_new - f - self.jacobian @ du, du) / (du @ du)
            u, f = u + du, f_new
        return None

    def bracketed(self, y: float) -> Evaluation | None:
        """The robust path: psi by a grown bracket and Brent (R_y rises with psi), a free omega by the same for
        each psi (T falls with omega); None when no |psi - last| <= PSI_MAX_RAD balances R_y."""
        seen: dict[float, Evaluation] = {}

        def lateral(psi: float) -> float:
            if not self.free_pitch:
                seen[psi] = self.evaluate(y, psi, self.omega)
                return seen[psi].lateral_residual_N
            at_omega: dict[float, Evaluation] = {}

            def torque(omega: float) -> float:
                at_omega[omega] = self.evaluate(y, psi, omega)
                return -at_omega[omega].forces.axle_torque_Nmm

            omega = grown_root(torque, self.omega, OMEGA_STEP * self.omega, OMEGA_RANGE * self.omega,
                               OMEGA_XTOL * self.omega)
            if omega is None:
                raise ConvergenceError(f"{self.case}: the free wheelset's pitch rate: no torque balance within "
                                       f"{OMEGA_RANGE:.0%} of {self.omega:.6g} rad/s at y = {y:.6g} mm, yaw "
                                       f"{psi:.4g} rad")
            seen[psi] = at_omega[omega] if omega in at_omega else self.evaluate(y, psi, omega)
            return seen[psi].lateral_residual_N

        psi = grown_root(lateral, self.psi, PSI_STEP_RAD, PSI_MAX_RAD, PSI_XTOL_RAD)
        if psi is None:
            return None
        e = seen[psi] if psi in seen else (lateral(psi), seen[psi])[1]
        self.psi, self.omega, self.jacobian = e.psi, e.omega, None
        return e

    def yaw_residual(self, y: float) -> float:
        """g(y) = R_psi(y, psi(y)) (N mm); +-UNBALANCED where no attack angle balances the lateral force. Kept
        per y (Brent evaluates the bracket's ends again); ``self.last``: the inner balance at y (None: none)."""
        if y not in self.seen:
            e = self.newton(y)
            if e is None:
                self.jacobian = None     # Broyden's last update may be poor: a fresh one after the robust path
                e = self.bracketed(y)
            if e is None:
                r_y = self.evaluate(y, self.psi, self.omega).lateral_residual_N
                # a force towards +Y still missing: the root lies at larger y
                self.seen[y] = (math.copysign(UNBALANCED, r_y), None)
            else:
                self.seen[y] = (e.yaw_residual_Nmm, e)
        g, self.last = self.seen[y]
        return g

    def bracket(self) -> tuple[float, float]:
        """Two lateral positions (mm) about the root of g, stepping from 0 towards the side g points to."""
        a, ga = 0.0, self.yaw_residual(0.0)
        step = math.copysign(SCAN_STEP_MM, ga)
        while abs(a + step) <= SCAN_MAX_MM:
            b = a + step
            try:
                gb = self.yaw_residual(b)
            except (ConvergenceError, InputError) as err:
                raise ConvergenceError(f"{self.case}: quasi-static curving: no balance found for y between 0 and "
                                       f"{a:g} mm; at y = {b:g} mm: {err}") from None
            if gb * ga <= 0.0:
                return min(a, b), max(a, b)
            a, ga = b, gb
        raise ConvergenceError(f"{self.case}: quasi-static curving: the yaw moment does not change sign for "
                               f"|y| <= {SCAN_MAX_MM:g} mm")

    def solve(self, condition: int = 0) -> WheelsetBalance:
        """The balanced (y, psi) and the residuals there; ConvergenceError when they exceed the tolerances."""
        lo, hi = self.bracket()
        y = float(brentq(self.yaw_residual, lo, hi, xtol=Y_XTOL_MM, rtol=4 * np.finfo(float).eps, maxiter=100))
        self.yaw_residual(y)           # the inner balance at the root itself (Brent's last point may be another)
        e = self.last
        torque = 0.0 if e is None or not self.free_pitch else e.forces.axle_torque_Nmm
        if e is None or not (abs(e.lateral_residual_N) <= self.lateral_tol_N
                             and abs(e.yaw_residual_Nmm) <= self.yaw_tol_Nmm and abs(torque) <= self.torque_tol_Nmm):
            got = "no attack angle balances the lateral force" if e is None else \
                (f"the lateral residual is {e.lateral_residual_N:.4g} N (tolerance {self.lateral_tol_N:.3g}), the "
                 f"yaw residual {e.yaw_residual_Nmm:.4g} N mm (tolerance {self.yaw_tol_Nmm:.3g}), the axle torque "
                 f"{torque:.4g} N mm (tolerance {self.torque_tol_Nmm:.3g})")
            raise ConvergenceError(f"{self.case}: quasi-static curving did not balance: at y = {y:.6g} mm {got}")
        return WheelsetBalance(condition=condition, lateral_mm=y, yaw_rad=e.psi,
                               lateral_residual_N=e.lateral_residual_N, yaw_residual_Nmm=e.yaw_residual_Nmm,
                               external_lateral_N=self.external_N, creep_lateral_N=e.forces.creep_lateral_N,
                               longitudinal_N=e.forces.longitudinal_N, pitch_rate_rad_s=e.omega,
                               wheel_solves=self.solves)


__all__ = ["Evaluation", "QuasiStaticCurving", "Wheelset", "WheelsetBalance", "WheelsetForces",
           "wheelset_forces"]
