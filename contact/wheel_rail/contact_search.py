"""Contact search between a wheel and a rail profile placed in the track (units mm, rad).

All geometry is computed in the side frame of :mod:`contact.wheel_rail.track_geometry` (the rail at +Y, field side +Y,
profiles unmirrored); :func:`search_contacts` returns the contact points of the wheel lowered vertically onto its
rail, each with its separation function in its own contact plane.

Contact points
--------------
The wheel's contact locus (for yaw: the points whose normal is perpendicular to X, exact for a straight rail) gives
the wheel surface as a curve Z_w(Y) in the (Y, Z) plane; the rail gives Z_r(Y). The vertical gap
g(Y) = Z_w(Y) - Z_r(Y) is sampled every 0.05 mm of the wheel profile. Its interior local minima are the contact
candidates: at a minimum the two tangents are parallel, so both profiles have a common normal there and, when
g = 0, the two points coincide (they are the points of minimum distance; for a gap g > 0 they are the points that
touch first when the wheel is lowered, which is the loading direction). Minima separated by a barrier lower than
``merge_mm`` are one candidate (their separation function then has two humps and the normal solver splits the
region itself). Each minimum is refined on the exact profile functions (vertex of the parabola through the exact
gaps at the three samples around it; the gap there is evaluated exactly). The
wheel's rigid height is the one at which the lowest minimum is zero; candidates with g < ``candidate_gap_mm``
above it are kept (two-point contact: tread and flange). The load balance decides which of them carry load.

Conventions of the reported location (documented for users)
-----------------------------------------------------------
- ``y_rail_mm``: rail profile coordinate (rail frame: from the head centre line, + towards the FIELD side, so the
  gauge side is negative), the same for the left and the right rail;
- ``y_wheel_mm``: wheel profile coordinate (S1002: S, 0 at the taping line, + towards the field side, flange
  negative), the same for both wheels;
- ``Y_mm``, ``Z_mm``: the rail contact point in the side frame (track frame mirrored for the left side);
  ``X_mm``: longitudinal lead of the wheel contact point (non-zero only with yaw);
- ``contact_angle_rad``: angle of the common normal from the track vertical, POSITIVE when the normal (from the
  rail into the wheel) tilts towards the track centre (tread of a conical wheel: small positive; flange: ~1.2 rad);
- ``wheel_contact_angle_rad``: the same angle measured in the wheelset (from the plane normal to the axle),
  i.e. atan of the profile slope dr/dy of the wheel; it equals contact_angle - roll on the side frame.

Rolling-direction radius for Kik–Piotrowski (``rolling_radius_kp_mm``)
-------------------------------------------------------------------
The KP strips use x_l(y) = sqrt(2 R g(y)) with R the radius of the relative curvature of the two surfaces in the
rolling direction X at the contact point. The rail is straight (no curvature in X). The wheel is a body of
revolution: its principal normal curvatures are k_c = cos(gamma_w) / r = 1 / (r sqrt(1 + r'^2)) (circumferential,
Meusnier) and k_m = the profile's curvature in its meridian plane (convex positive, i.e. z''/(1+z'^2)^1.5 of the
wheel profile, negative at the flange root). By Euler's formula the normal curvature along X is
k_X = k_c cos^2(beta) + k_m sin^2(beta), beta the angle between the circumferential direction and X in the
tangent plane (beta = 0 without yaw; |beta| ~ |yaw| otherwise). R = 1 / k_X; without yaw R = r / cos(gamma_w),
r = the local wheel radius at the contact point. (The twist term of a yawed contact is neglected: KP takes one
R per patch.)

Separation function in the contact plane
----------------------------------------
For each candidate: the contact plane passes through the rail contact point P, with unit lateral axis t (in the
(Y, Z) plane, positive towards +Y, tangent to both profiles) and normal n (from the rail into the wheel). Both
profile curves, restricted to the candidate's basin (between the barriers to the neighbouring candidates), are
expressed in (eta, zeta) = ((Q - P).t, (Q - P).n); along the part of each curve that is a graph over eta (the
branch through P) the separation is f(eta) = zeta_wheel(eta) - zeta_rail(eta), the distance between the profiles
measured along the patch normal (the rail point on each normal line found by Newton's method on the exact rail
profile), sampled every 0.02 mm of the wheel and cut where it exceeds ``f_cap_mm``. Its
minimum is the normal gap of the candidate (0 for the first contact). eta is the strip coordinate of the patch.
With yaw the wheel curve is the contact locus, i.e. at every lateral position the gap is the smallest over X; the
locus points' longitudinal leads are not carried into the Kik–Piotrowski strips, which are all centred at x = 0
(the lead of the contact point is reported as ``X_mm``). At 24 mrad yaw the leads vary across +-3 mm of eta by
~0.3 mm on the tread but by several mm on the flange (whose contact point leads by ~ r r' yaw ~ 30 mm): there
the patch is in reality skewed, which this planar treatment does not represent.
"""

from __future__ import annotations

import functools
import itertools
import math
from dataclasses import dataclass, field

import numpy as np

from contact.wheel_rail.track_geometry import (PlacedRail, TrackLayout, WheelLocus, WheelsetPose, wheel_locus,
                                               wheel_sample_y)
from meshes.profiles import Profile
from wrlayer.errors import InputError

#: Default search settings (mm).
MERGE_MM = 0.005
CANDIDATE_GAP_MM = 1.0
F_CAP_MM = 2.0
WHEEL_SAMPLE_MM = 0.05
SEPARATION_SAMPLE_MM = 0.02
#: :func:`first_contact_radius` builds the candidates only when the second-lowest gap minimum lies within this of
#: the lowest (mm): beyond it the other candidates' normal gaps (about their vertical gap times the cosine of a
#: contact angle below 75 degrees, > 2.5e-4 mm) exceed the first contact's own (its separation function sampled
#: every SEPARATION_SAMPLE_MM misses the touching point by under 1e-5 mm even at a 13 mm flange radius).
FIRST_CONTACT_TIE_MM = 1e-3


@dataclass(frozen=True)
class SearchSettings:
    """merge_mm: barrier below which neighbouring gap minima are one candidate; candidate_gap_mm: largest gap
    (above the first contact) of a kept candidate; f_cap_mm: the separation function is cut where it exceeds this;
    sample_mm: wheel sample spacing of the gap search; separation_sample_mm: wheel sample spacing of the
    separation functions (mm)."""

    merge_mm: float = MERGE_MM
    candidate_gap_mm: float = CANDIDATE_GAP_MM
    f_cap_mm: float = F_CAP_MM
    sample_mm: float = WHEEL_SAMPLE_MM
    separation_sample_mm: float = SEPARATION_SAMPLE_MM


@dataclass(frozen=True, eq=False)
class ContactCandidate:
    """One contact point in the side frame (see the module docstring for every convention; mm, rad).

    eta_mm / f_mm: separation function along the contact plane (f >= normal_gap_mm); q_of_eta / y_of_eta:
    rail and wheel profile coordinates at the strip positions eta (for layer look-ups and for mapping residual
    displacements back onto the profiles) as (eta, value) tables.
    """

    y_rail_mm: float
    y_wheel_mm: float
    X_mm: float
    Y_mm: float
    Z_mm: float
    vertical_gap_mm: float
    normal_gap_mm: float
    contact_angle_rad: float
    wheel_contact_angle_rad: float
    wheel_radius_mm: float
    rolling_radius_kp_mm: float
    normal: np.ndarray            # (3,) side frame, from the rail into the wheel
    lateral: np.ndarray           # (3,) side frame, contact-plane lateral axis (positive Y component)
    wheel_point: np.ndarray       # (3,) wheel contact point (side frame, wheel at its rigid-contact height)
    eta_mm: np.ndarray = field(repr=False)
    f_mm: np.ndarray = field(repr=False)
    eta_rail: tuple = field(repr=False, default=())
    eta_wheel: tuple = field(repr=False, default=())

    def rail_coordinate(self, eta) -> np.ndarray:
        """Rail profile coordinate (mm) of the strip at eta (side frame orientation)."""
        return np.interp(eta, *self.eta_rail)

    def wheel_coordinate(self, eta) -> np.ndarray:
        """Wheel profile coordinate (mm) of the strip at eta (side frame orientation)."""
        return np.interp(eta, *self.eta_wheel)


@dataclass(frozen=True, eq=False)
class SearchResult:
    """Contact candidates (by increasing Y) of one wheel; wheel_height_mm: wheelset-centre height Z_c at rigid
    contact (side frame); plus the sampled gap for pictures."""

    candidates: list[ContactCandidate]
    wheel_height_mm: float
    Y_mm: np.ndarray = field(repr=False)
    gap_mm: np.ndarray = field(repr=False)
    flange_tip: tuple = ()


# bounded, not keyed weakly by profile: a wear run keeps every step's profile in its records, and tables that live
# as long as their profile grew its memory by about 0.2 MiB a step; a search uses a few (profile, spacing) pairs
@functools.lru_cache(maxsize=16)
def _wheel_table(wheel: Profile, spacing_mm: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(y, z(y), z'(y)) of the wheel at ``spacing_mm`` (cached per profile object: the profile is immutable)."""
    y = wheel_sample_y(wheel, spacing_mm)
    return y, wheel.z(y), wheel.dz(y)


def _gap_samples(rail: PlacedRail, wheel: Profile, layout: TrackLayout, pose: WheelsetPose, settings: SearchSettings):
    y, z, dz = _wheel_table(wheel, settings.sample_mm)
    loc = wheel_locus(wheel, layout, pose, y, z, dz)
    Zr = np.interp(loc.Y_mm, rail.Y_mm, rail.Z_mm, left=np.nan, right=np.nan)
    return y, loc, Zr


def raw_min_gap(rail: PlacedRail, wheel: Profile, layout: TrackLayout, pose: WheelsetPose,
                settings: SearchSettings = SearchSettings()) -> float:
    """Minimum of Z_wheel - Z_rail (mm) with the wheelset centre at Z = 0 (sampled; for roll/height finding)."""
    _, loc, Zr = _gap_samples(rail, wheel, layout, pose, settings)
    g = loc.Z_mm - Zr
    if not np.any(np.isfinite(g)):
        raise InputError("contact search", "the wheel and the rail do not overlap laterally (no contact within the "
                         "search range)")
    return float(np.nanmin(g))


def _gap_exact(rail: PlacedRail, wheel: Profile, layout: TrackLayout, pose: WheelsetPose, y) -> np.ndarray:
    """Exact vertical gaps (wheel centre at Z = 0) at wheel profile coordinates y (mm)."""
    loc = wheel_locus(wheel, layout, pose, np.asarray(y, dtype=float))
    return loc.Z_mm - rail.Z_at(loc.Y_mm)


def _refine_minimum(rail, wheel, layout, pose, y_samples: np.ndarray) -> tuple[float, float]:
    """Vertex of the parabola through the exact gaps at three sampled y around a minimum, and its exact gap."""
    g = _gap_exact(rail, wheel, layout, pose, y_samples)
    k = int(np.clip(np.nanargmin(g), 1, y_samples.size - 2))
    y3, g3 = y_samples[k - 1:k + 2], g[k - 1:k + 2]
    h = y3[1] - y3[0]
    curv = g3[0] - 2.0 * g3[1] + g3[2]
    y_v = y3[1] + (0.5 * h * (g3[0] - g3[2]) / curv if curv > 0 else 0.0)
    y_v = float(np.clip(y_v, y3[0], y3[2]))
    g_v = float(_gap_exact(rail, wheel, layout, pose, np.array([y_v]))[0])
    if g_v > g3[1]:
        return float(y3[1]), float(g3[1])
    return y_v, g_v


def _local_minima(g: np.ndarray, merge_mm: float) -> list[int]:
    """Indices of interior local minima of g, merging those whose separating barrier is below merge_mm."""
    inner = np.flatnonzero((g[1:-1] <= g[:-2]) & (g[1:-1] < g[2:])) + 1
    mins: list[int] = []
    for i in inner:
        if mins:
            j = mins[-1]
            barrier = float(np.max(g[j:i + 1]))
            if barrier - max(g[i], g[j]) < merge_mm:
                if g[i] < g[j]:
                    mins[-1] = int(i)
                continue
        mins.append(int(i))
    return mins


def _run_around(ok: np.ndarray, i0: int) -> slice:
    """The maximal run of True in ``ok`` (per point) that contains index i0."""
    bad = np.flatnonzero(~ok)
    lo = int(bad[bad < i0].max()) + 1 if np.any(bad < i0) else 0
    hi = int(bad[bad > i0].min()) - 1 if np.any(bad > i0) else ok.size - 1
    return slice(lo, hi + 1)


def _branch(eta: np.ndarray, i0: int) -> slice:
    """The run of points around index i0 along which eta strictly increases."""
    bad = np.flatnonzero(np.diff(eta) <= 0)          # step k -> k+1 does not increase
    lo = int(bad[bad < i0].max()) + 1 if np.any(bad < i0) else 0
    hi = int(bad[bad >= i0].min()) if np.any(bad >= i0) else eta.size - 1
    return slice(lo, hi + 1)


@dataclass(frozen=True)
class _Minima:
    """The sampled vertical gaps of a wheel over its rail and their refined local minima (side frame, mm):
    wheel samples ``y`` and their locus ``loc``; ``lo``..``hi`` the samples over the rail; ``gg`` the gaps there;
    ``mins`` the kept minima (indices into ``gg``), ``refined`` their exact (y_wheel, vertical gap)."""

    y: np.ndarray
    loc: WheelLocus
    lo: int
    hi: int
    gg: np.ndarray
    mins: list[int]
    refined: list[tuple[float, float]]
    tip: tuple[float, float]


def _located_minima(rail: PlacedRail, wheel: Profile, layout: TrackLayout, pose: WheelsetPose,
                    settings: SearchSettings, case: str) -> _Minima:
    """The gap minima of :func:`search_contacts` (its errors included), before any candidate is built."""
    if wheel.body != "wheel":
        raise InputError("wheel profile", f"{wheel.name} is a {wheel.body} profile, not a wheel")
    y, loc, Zr = _gap_samples(rail, wheel, layout, pose, settings)
    ok = np.isfinite(Zr)
    if np.count_nonzero(ok) < 5:
        raise InputError(case, "the profiles do not meet: the wheel and the rail do not overlap laterally "
                         "(no contact within the search range; check gauge, back-to-back and lateral displacement)")
    idx = np.flatnonzero(ok)
    lo, hi = int(idx[0]), int(idx[-1])
    gg = loc.Z_mm[lo:hi + 1] - Zr[lo:hi + 1]
    # flange tip: lowest point of the wheel locus
    tip = int(np.argmin(loc.Z_mm))
    tip_Y = float(loc.Y_mm[tip])
    if tip_Y > rail.gauge_point[0]:
        raise InputError(case, f"flange through the rail: the flange tip (wheel y = {y[tip]:.2f} mm) lies at "
                         f"Y = {tip_Y:.2f} mm, on the field side of the rail's gauge point Y = "
                         f"{rail.gauge_point[0]:.2f} mm")
    k_min = int(np.nanargmin(gg))
    if k_min in (0, gg.size - 1):
        end = "wheel" if (k_min == 0 and lo == 0) or (k_min == gg.size - 1 and hi == y.size - 1) else "rail"
        raise InputError(case, f"the profiles do not meet within the search range: the smallest gap lies at the end "
                         f"of the {end} profile (Y = {loc.Y_mm[lo + k_min]:.2f} mm)")
    g0 = float(gg[k_min])
    mins = [m for m in _local_minima(gg, settings.merge_mm) if gg[m] - g0 < settings.candidate_gap_mm]
    # refine each minimum on the exact functions
    refined = [_refine_minimum(rail, wheel, layout, pose, y[lo + max(m - 2, 0):lo + min(m + 3, gg.size)])
               for m in mins]
    return _Minima(y, loc, lo, hi, gg, mins, refined, (float(y[tip]), tip_Y))


def search_contacts(rail: PlacedRail, wheel: Profile, layout: TrackLayout, pose: WheelsetPose,
                    settings: SearchSettings = SearchSettings(), case: str = "contact search") -> SearchResult:
    """Contact candidates of ``wheel`` (at ``pose``, side frame) lowered onto ``rail``; see the module docstring.

    InputError naming ``case`` when the profiles do not meet within the search range (the lowest gap lies at an
    end of the profiles) or when the flange would cut through the rail (its tip lies over the rail head).
    """
    m = _located_minima(rail, wheel, layout, pose, settings, case)
    y, gg, lo = m.y, m.gg, m.lo
    height = -min(v for _, v in m.refined)
    # basins: between the barriers to neighbouring candidates
    bounds = [lo]
    for m1, m2 in itertools.pairwise(m.mins):
        bounds.append(lo + m1 + int(np.argmax(gg[m1:m2 + 1])))
    bounds.append(m.hi)
    cands = []
    for k, (y_w, gap) in enumerate(m.refined):
        ys, zs, dzs = _wheel_table(wheel, settings.separation_sample_mm)
        win = slice(int(np.searchsorted(ys, y[bounds[k]])), int(np.searchsorted(ys, y[bounds[k + 1]], "right")))
        cands.append(_candidate(rail, wheel, layout, pose, y_w, gap + height, height, ys[win], zs[win], dzs[win],
                                settings))
    return SearchResult(cands, height, m.loc.Y_mm[lo:m.hi + 1], gg + height, m.tip)


def first_contact_radius(rail: PlacedRail, wheel: Profile, layout: TrackLayout, pose: WheelsetPose,
                         settings: SearchSettings = SearchSettings(), case: str = "contact search") -> float:
    """The wheel's radius (mm) at its first contact: the candidate of :func:`search_contacts` with the smallest
    normal gap, the same number. Where the lowest gap minimum lies more than :data:`FIRST_CONTACT_TIE_MM` below
    every other, it is that candidate (the others' normal gaps are then positive, its own zero) and no candidate's
    separation function is built (about two thirds of a search); otherwise the candidates decide."""
    m = _located_minima(rail, wheel, layout, pose, settings, case)
    gaps = sorted(v for _, v in m.refined)
    if len(gaps) > 1 and gaps[1] - gaps[0] <= FIRST_CONTACT_TIE_MM:
        found = search_contacts(rail, wheel, layout, pose, settings, case)
        return float(min(found.candidates, key=lambda c: c.normal_gap_mm).wheel_radius_mm)
    y_w = min(m.refined, key=lambda item: item[1])[0]
    return float(wheel_locus(wheel, layout, pose, np.array([y_w])).radius_mm[0])


def _candidate(rail: PlacedRail, wheel: Profile, layout: TrackLayout, pose: WheelsetPose, y_w: float,
               vertical_gap: float, height: float, y_window: np.ndarray, z_window: np.ndarray, dz_window: np.ndarray,
               settings: SearchSettings) -> ContactCandidate:
    loc = wheel_locus(wheel, layout, pose, np.array([y_w]))
    Y = float(loc.Y_mm[0])
    q = float(rail.q_at(np.array([Y]))[0])
    P = rail.point(q)
    n2 = rail.normal(q)
    n = np.array([0.0, n2[0], n2[1]])
    t = np.array([0.0, n2[1], -n2[0]])
    gamma = math.atan2(-n2[0], n2[1])
    r = float(loc.radius_mm[0])
    dr = float(loc.dr_dy[0])
    gamma_w = math.atan(dr)
    k_c = 1.0 / (r * math.sqrt(1.0 + dr * dr))
    k_m = float(wheel.curvature(y_w))
    cos_b = abs(float(loc.circumferential[0, 0]))
    k_x = k_c * cos_b ** 2 + k_m * (1.0 - cos_b ** 2)
    if not k_x > 0:
        raise InputError("contact search", f"the wheel surface at y = {y_w:.3f} mm is not convex in the rolling "
                         "direction (yaw too large for the Kik–Piotrowski radius)")
    wheel_point = np.array([loc.X_mm[0], Y, loc.Z_mm[0] + height])
    # separation in the contact plane
    wl = wheel_locus(wheel, layout, pose, y_window, z_window, dz_window)
    Yw, Zw = wl.Y_mm, wl.Z_mm + height
    Y_lo, Y_hi = float(Yw[0]), float(Yw[-1])
    rmask = (rail.Y_mm >= Y_lo) & (rail.Y_mm <= Y_hi)
    Yr, Zr, qr = rail.Y_mm[rmask], rail.Z_mm[rmask], rail.q_mm[rmask]
    eta_w = (Yw - P[0]) * t[1] + (Zw - P[1]) * t[2]
    zeta_w = (Yw - P[0]) * n[1] + (Zw - P[1]) * n[2]
    eta_r = (Yr - P[0]) * t[1] + (Zr - P[1]) * t[2]
    zeta_r = (Yr - P[0]) * n[1] + (Zr - P[1]) * n[2]
    bw = _branch(eta_w, int(np.argmin(np.abs(eta_w))))
    br = _branch(eta_r, int(np.argmin(np.abs(eta_r))))
    eta_w, zeta_w, yw_b = eta_w[bw], zeta_w[bw], y_window[bw]
    eta_r, zeta_r, qr_b = eta_r[br], zeta_r[br], qr[br]
    lo, hi = max(eta_w[0], eta_r[0]), min(eta_w[-1], eta_r[-1])
    keep = (eta_w >= lo) & (eta_w <= hi)
    eta = eta_w[keep]
    f = zeta_w[keep] - _rail_zeta(rail, P, t, n, eta, np.interp(eta, eta_r, qr_b))
    # cut where f exceeds the cap, keeping the run around the contact point
    i0 = int(np.argmin(np.abs(eta)))
    run = _run_around(f - float(f.min()) <= settings.f_cap_mm, i0)
    eta, f = eta[run], f[run]
    if eta.size < 3:
        raise InputError("contact search", f"no separation function around the contact point at Y = {Y:.2f} mm")
    return ContactCandidate(
        y_rail_mm=q, y_wheel_mm=float(y_w), X_mm=float(loc.X_mm[0]), Y_mm=float(P[0]), Z_mm=float(P[1]),
        vertical_gap_mm=float(vertical_gap), normal_gap_mm=max(float(f.min()), 0.0), contact_angle_rad=gamma,
        wheel_contact_angle_rad=gamma_w, wheel_radius_mm=r, rolling_radius_kp_mm=1.0 / k_x, normal=n, lateral=t,
        wheel_point=wheel_point, eta_mm=eta, f_mm=f, eta_rail=(eta_r, qr_b), eta_wheel=(eta_w, yw_b))


def _rail_zeta(rail: PlacedRail, P: np.ndarray, t: np.ndarray, n: np.ndarray, eta: np.ndarray,
               q: np.ndarray) -> np.ndarray:
    """zeta of the rail on the contact-plane normal lines through eta (exact; Newton on q from a close start)."""
    c, s = math.cos(rail.angle_rad), math.sin(rail.angle_rad)
    prof = rail.profile
    for _ in range(2):
        Q = rail.point(q)
        dz = prof.dz(q)
        d_eta = t[1] * (c - s * dz) + t[2] * (s + c * dz)
        q = np.clip(q - ((Q[:, 0] - P[0]) * t[1] + (Q[:, 1] - P[1]) * t[2] - eta) / d_eta, prof.y_min, prof.y_max)
    Q = rail.point(q)
    return (Q[:, 0] - P[0]) * n[1] + (Q[:, 1] - P[1]) * n[2]


__all__ = ["FIRST_CONTACT_TIE_MM", "ContactCandidate", "SearchResult", "SearchSettings", "first_contact_radius",
           "raw_min_gap", "search_contacts"]
