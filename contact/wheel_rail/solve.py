"""One wheel on its rail: contact search, vertical load balance, normal and tangential solution per patch, layers
looked up at the contact location, residual displacements mapped back onto both profiles (units mm, N, MPa, s).

Vertical load balance
---------------------
The wheel is first lowered until it touches the rail (rigid contact, :mod:`contact.wheel_rail.contact_search`). Lowering it
further by Delta (mm, along -Z) gives each contact candidate i (contact angle gamma_i, normal gap g_i at rigid
contact, 0 for the first contact) the normal approach delta_i = Delta cos(gamma_i) - g_i. Its Kik–Piotrowski
normal force N_i(delta_i) (with the layers, if any) acts along its normal, so the vertical balance is

    sum_i N_i(delta_i) cos(gamma_i) = Q      (Q: vertical wheel load; tangential forces are not included)

One candidate: N = Q / cos(gamma) directly. Several: Delta is found by Brent's method in [0, Delta_1] (Delta_1:
the primary patch alone carrying Q), then every loaded patch is solved for its N_i; the balance holds to
< 1e-9 relative (checked; ConvergenceError above 1e-6). Each patch is a separate Kik–Piotrowski problem in its own
contact plane (no elastic interaction between patches). Each wheel's vertical position is solved on its own: for
a whole wheelset with a given (or rigid-contact, "auto") roll angle the two wheels' approaches differ slightly, which
amounts to an extra roll of (Delta_right - Delta_left) / (wheel distance), ~1e-5 rad at 10 kN, not fed back.

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
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np
from scipy.optimize import brentq

from contact.layer.characteristic import Characteristic
from contact.wheel_rail.contact_search import ContactCandidate, SearchResult, SearchSettings, search_contacts
from contact.tangential.fastsim import Creepage, TangentialResult, solve_tangential
from contact.normal.kik_piotrowski import NormalProblem, NormalSolution, NormalForceEvaluator, solve_normal
from contact.normal.method import NormalMethod, solve_normal_with
from contact.passes.passes import PassesOptions, PassRecord, run_passes
from contact.layer.prandtl_layer import LayerPair, PrandtlLayer
from contact.wheel_rail.track_geometry import PlacedRail, TrackLayout, WheelsetPose, axle_direction, place_rail, side_sign
from contact.wheel_rail.kinematics import PatchKinematics, contact_frame, creepages
from wrlayer.errors import ConvergenceError, InputError, require
from meshes.profiles.base import Profile

BALANCE_RTOL = 1e-6
#: Layers are built only on strips whose separation is below the first of these caps (mm) (the virtual penetration
#: alpha delta stays far below 0.3 mm at wheel loads); if a strip in contact has no element, the case is solved again
#: with the next cap.
LAYER_F_CAPS_MM = (0.3, 1.0, np.inf)


class LayerLookup(Protocol):
    """A per-position layer table (e.g. :class:`contact.layer.layer_table.LayerTable`)."""

    def characteristic_at(self, y_mm: float) -> Characteristic: ...

    @property
    def y_range_mm(self) -> tuple[float, float]: ...


@dataclass(frozen=True)
class WheelRailLayers:
    """Layer tables per body (``rail``, ``wheel``; either may be None) or one ``combined`` characteristic."""

    rail: Any = None
    wheel: Any = None
    combined: Characteristic | None = None
    names: dict = field(default_factory=dict)

    def __post_init__(self):
        require(self.combined is None or (self.rail is None and self.wheel is None), "layers",
                "give either per-body tables (rail, wheel) or one combined characteristic, not both")

    @property
    def empty(self) -> bool:
        return self.rail is None and self.wheel is None and self.combined is None


@dataclass(frozen=True)
class WheelRailInputs:
    """Everything but the profiles for one wheel on its rail (units mm, N, MPa, s, rad).

    pitch_rate_rad_s None means pure rolling at the nominal radius: V / r0.
    """

    layout: TrackLayout = field(default_factory=TrackLayout)
    pose: WheelsetPose = field(default_factory=WheelsetPose)
    side: str = "right"
    vertical_load_N: float = 10000.0
    speed_mm_s: float = 2000.0
    pitch_rate_rad_s: float | None = None
    friction: float = 0.3
    E_MPa: float = 210000.0
    poisson: float = 0.28
    alpha: float = 0.55
    grid_mm: float = 0.1
    fastsim_cells: int = 60
    passes: PassesOptions = field(default_factory=lambda: PassesOptions(max_passes=1))
    search: SearchSettings = field(default_factory=SearchSettings)
    normal: NormalMethod = field(default_factory=NormalMethod)  # the patches' normal solver (load split: KP)

    def __post_init__(self):
        side_sign(self.side)
        for key in ("vertical_load_N", "speed_mm_s", "E_MPa", "grid_mm"):
            v = getattr(self, key)
            require(bool(np.isfinite(v)) and v > 0, key, f"must be a positive number, got {v!r}")
        require(bool(np.isfinite(self.friction)) and self.friction >= 0, "friction", f"must be >= 0, got {self.friction!r}")
        require(0.0 <= self.poisson < 0.5, "poisson", f"must lie in [0, 0.5), got {self.poisson!r}")

    @property
    def G_MPa(self) -> float:
        return self.E_MPa / (2.0 * (1.0 + self.poisson))

    @property
    def omega_rad_s(self) -> float:
        return self.speed_mm_s / self.layout.nominal_radius_mm if self.pitch_rate_rad_s is None \
            else float(self.pitch_rate_rad_s)


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
    pass_normals: list = field(default_factory=list, repr=False)  # normal solution of every pass (wear outputs)

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
    """All loaded patches of one wheel; ``approach_mm`` = Delta (vertical, beyond rigid contact);
    ``wheel_height_mm``: wheelset-centre height at rigid contact; ``vertical_balance_rel``: |sum N cos(gamma) - Q|/Q."""

    inputs: WheelRailInputs
    search: SearchResult
    rail: PlacedRail
    patches: list[PatchSolution]
    approach_mm: float
    vertical_balance_rel: float
    unloaded: list[ContactCandidate]
    wheel: Profile


def _track_vector(v: np.ndarray, sign: int) -> np.ndarray:
    return np.array([v[0], sign * v[1], v[2]])


def _problem(cand: ContactCandidate, sign: int, inputs: WheelRailInputs, force: float) -> NormalProblem:
    eta, f = (cand.eta_mm, cand.f_mm) if sign > 0 else (-cand.eta_mm[::-1], cand.f_mm[::-1])
    return NormalProblem(eta, f, force, cand.rolling_radius_kp_mm, inputs.E_MPa, inputs.poisson, alpha=inputs.alpha,
                         grid_mm=inputs.grid_mm, interpolation="pchip")


def _clamped_lookup(table: Any, coords: np.ndarray, body: str, name: str) -> tuple[list[Characteristic], np.ndarray]:
    lo, hi = (float(v) for v in table.y_range_mm)
    clamped = (coords < lo) | (coords > hi)
    cache: dict[float, Characteristic] = {}
    chars = []
    for y in np.clip(coords, lo, hi):
        key = round(float(y), 9)
        if key not in cache:
            try:
                cache[key] = table.characteristic_at(float(y))
            except InputError as err:
                raise InputError(f"layers.{body} ({name})", str(err)) from None
        chars.append(cache[key])
    return chars, clamped


def _layer_pair(cand: ContactCandidate, sign: int, prob: NormalProblem, layers: WheelRailLayers,
                f_cap_mm: float = LAYER_F_CAPS_MM[0]) -> tuple[LayerPair | None, dict, dict]:
    """Per-strip layers of a patch; returns (pair, profile coordinate per body on the strips, clamped masks)."""
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
        chars, _ = _clamped_lookup(table, coords[body][near], body, name)
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


def _balance(cands: list[ContactCandidate], sign: int, inputs: WheelRailInputs, layers: WheelRailLayers,
             case: str = "wheel-rail case", f_cap_mm: float = LAYER_F_CAPS_MM[0]) -> tuple[list[tuple[ContactCandidate, float, NormalProblem, Any, dict, dict]], float]:
    """Normal forces of the candidates that carry the vertical load (see the module docstring)."""
    Q = inputs.vertical_load_N
    cos_g = np.array([math.cos(c.contact_angle_rad) for c in cands])
    require(bool(np.all(cos_g > 0.05)), case,
            "a contact normal is (nearly) horizontal: the wheel cannot carry a vertical load there")
    primary = int(np.argmin([c.normal_gap_mm for c in cands]))
    built = []
    for c, cg in zip(cands, cos_g):
        prob = _problem(c, sign, inputs, Q / cg)
        pair, coords, clamped = _layer_pair(c, sign, prob, layers, f_cap_mm)
        built.append((c, prob, pair, coords, clamped))
    if len(cands) == 1:
        c, prob, pair, coords, clamped = built[0]
        return [(c, Q / cos_g[0], prob, pair, coords, clamped)], float("nan")
    evaluators = [NormalForceEvaluator(prob, pair) for _, prob, pair, _, _ in built]

    def forces(Delta: float) -> np.ndarray:
        out = np.zeros(len(cands))
        for i, (c, cg) in enumerate(zip(cands, cos_g)):
            d = Delta * cg - c.normal_gap_mm
            out[i] = evaluators[i].force_at(d) if d > 0 else 0.0
        return out

    def excess(Delta: float) -> float:
        return float(forces(Delta) @ cos_g) - Q

    # primary alone carrying Q -> upper bracket
    c1, prob1, pair1 = built[primary][:3]
    try:
        sol1 = solve_normal(prob1, pair1)
        delta_hi = (sol1.delta_mm + c1.normal_gap_mm) / cos_g[primary]
    except InputError as err:
        if err.what != "separation.y_mm":
            raise
        # the primary alone would need more than its separation table: grow the bracket instead (the final
        # solves of the loaded candidates still check their tables)
        delta_hi = max(c.normal_gap_mm / cg for c, cg in zip(cands, cos_g)) + 1e-3
        for _ in range(60):
            if excess(delta_hi) > 0:
                break
            delta_hi *= 2.0
        else:
            raise ConvergenceError(f"{case}: vertical load balance: no approach carries {Q:g} N") from None
    if excess(delta_hi) <= 0:  # only the primary is loaded (others cannot close their gap)
        Delta = delta_hi
    else:
        try:
            Delta = brentq(excess, 0.0, delta_hi, xtol=1e-15, rtol=1e-14, maxiter=200)
        except (ValueError, RuntimeError) as err:
            raise ConvergenceError(f"vertical load balance: Brent failed ({err})") from None
    n = forces(Delta)
    loaded = []
    for i, (c, prob, pair, coords, clamped) in enumerate(built):
        if n[i] > 1e-9 * Q:
            loaded.append((c, float(n[i]), prob, pair, coords, clamped))
    # tiny forces dropped: rescale onto the exact balance through the solver's own N target
    total = sum(f * math.cos(c.contact_angle_rad) for c, f, *_ in loaded)
    loaded = [(c, f * Q / total, *rest) for c, f, *rest in loaded]
    return loaded, float(Delta)


def solve_wheel(rail_profile: Profile, wheel_profile: Profile, inputs: WheelRailInputs,
                layers: WheelRailLayers | None = None, placed_rail: PlacedRail | None = None,
                case: str = "wheel-rail case") -> WheelRailSolution:
    """Solve one wheel on its rail (see the module docstring). ``placed_rail`` may be passed to reuse a placement
    (it depends only on the rail profile and the layout)."""
    sign = side_sign(inputs.side)
    rail = placed_rail if placed_rail is not None else place_rail(rail_profile, inputs.layout)
    pose_side = inputs.pose.for_side(inputs.side)
    found = search_contacts(rail, wheel_profile, inputs.layout, pose_side, inputs.search, case=case)
    layers = layers if layers is not None else WheelRailLayers()
    for k, cap in enumerate(LAYER_F_CAPS_MM):
        try:
            return _solve_found(found, rail, wheel_profile, inputs, layers, sign, case, cap)
        except InputError as err:  # a strip in contact without a layer element: widen the layer
            if err.what == "separation.y_mm":
                raise InputError(case, "a contact patch reaches the end of its separation function (the barrier "
                                 "to the neighbouring contact candidate, or the search cap of "
                                 f"{inputs.search.f_cap_mm:g} mm): the patches would merge, which this planar "
                                 f"two-candidate model does not represent ({err.problem})") from None
            if k == len(LAYER_F_CAPS_MM) - 1 or not _is_layer_name(err.what):
                raise
    raise AssertionError("unreachable")


def _is_layer_name(what: str) -> bool:
    return what == "combined layer" or (" layer (" in what and not what.startswith("layers."))


def _solve_found(found: SearchResult, rail: PlacedRail, wheel_profile: Profile, inputs: WheelRailInputs,
                 layers: WheelRailLayers, sign: int, case: str, f_cap_mm: float) -> WheelRailSolution:
    loaded, Delta = _balance(found.candidates, sign, inputs, layers, case, f_cap_mm)
    centre = np.array([0.0, inputs.pose.lateral_mm, found.wheel_height_mm])
    axle = axle_direction(inputs.pose)
    patches = []
    for c, force, prob, pair, coords, clamped in loaded:
        prob = _problem(c, sign, inputs, force)
        n_track = _track_vector(c.normal, sign)
        _, t_track, _ = contact_frame(n_track)
        point = _track_vector(c.wheel_point, sign)
        kin = creepages(point, n_track, centre, axle, inputs.speed_mm_s, inputs.omega_rad_s)
        records: list[PassRecord] = []
        if pair is None:
            sol = solve_normal_with(inputs.normal, prob)
        else:
            holder: list[NormalSolution] = []
            records, _ = run_passes(prob, pair, inputs.passes, on_pass=lambda rec, s, h=holder: h.append(s),
                                    method=inputs.normal)
            sol = holder[0]
        tang = _tangential(sol, kin, inputs)
        if not coords:
            eta = sign * prob.strip_y_mm
            coords = {"rail": c.rail_coordinate(eta), "wheel": c.wheel_coordinate(eta)}
        patch = PatchSolution(c, inputs.side, sign, prob, sol, float(sol.normal_force_N), point, n_track, t_track,
                              kin, tang, records, coords.get("rail"), coords.get("wheel"),
                              {} if not records else {k: np.asarray(v) for k, v in
                                                      records[-1].cumulative_residual_mm.items()}, clamped)
        patch.pass_normals = holder if pair is not None else [sol]
        if pair is not None:
            _check_coverage(patch, layers)
        patches.append(patch)
    Q = inputs.vertical_load_N
    vertical = sum(p.normal_force_N * math.cos(p.candidate.contact_angle_rad) for p in patches)
    rel = abs(vertical - Q) / Q
    if not rel <= BALANCE_RTOL:
        raise ConvergenceError(f"{case}: vertical load balance off by {rel:.3g} (relative) > {BALANCE_RTOL:g}")
    unloaded = [c for c in found.candidates if all(c is not p.candidate for p in patches)]
    return WheelRailSolution(inputs, found, rail, patches, 0.0 if math.isnan(Delta) else Delta, rel, unloaded,
                             wheel_profile)


def _tangential(sol: NormalSolution, kin: PatchKinematics, inputs: WheelRailInputs) -> list[TangentialResult]:
    """FASTSIM on every region of the patch (strip coordinate relative to the contact point, spin about it)."""
    if inputs.friction == 0:
        return []
    cr = Creepage(kin.vx, kin.vy, kin.phi_per_mm)
    return [solve_tangential(p, cr, inputs.G_MPa, inputs.poisson, inputs.friction, inputs.speed_mm_s,
                             nx=inputs.fastsim_cells) for p in sol.patches]


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
