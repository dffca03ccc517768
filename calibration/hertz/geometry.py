"""Hertzian contact ellipse from the local curvatures of a profile position and its mating profile (units mm, N, MPa).

Hertz (Johnson, Contact Mechanics, section 4.2): the gap near the contact point is ``A x^2 + B y^2`` with
``A = (k_x1 + k_x2) / 2`` (rolling direction x) and ``B = (k_y1 + k_y2) / 2`` (lateral y), k the principal
curvatures counted positive where a surface is convex (bulges towards the other body). For the elliptic pressure
``p = p0 sqrt(1 - (x/a)^2 - (y/b)^2)`` on an elastic half-space with ``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2``,
the normal displacement inside the ellipse is ``delta - A x^2 - B y^2`` where, for the longer axis c_l along the
smaller curvature sum and the shorter c_s (e^2 = 1 - (c_s/c_l)^2, K and E complete elliptic integrals of
parameter e^2)::

    delta = p0 c_s K / E*,  A_l = p0 c_s (K - E) / (E* e^2 c_l^2),  A_s = p0 c_s ((c_l/c_s)^2 E - K) / (E* e^2 c_l^2)
    N = 2/3 pi a b p0

Curvatures of the profiles (frames in :mod:`meshes.profiles.base`): rail ``k_x = 0`` (straight rail),
``k_y = -curvature(y)``; wheel ``k_x = 1 / r(y)`` (rolling radius), ``k_y = +curvature(y)``.
The mating point on the other profile is where the two surfaces are tangent: the same surface slope angle in
the track frame, the rail being canted by ``rail_cant_rad`` (1:40 -> 0.025 rad, head tilted towards the gauge
side); among several such points the one laterally nearest to the given position is taken, if it lies within
``max_offset_mm`` (default 10 mm) of it; otherwise (no tangent point nearby, e.g. the rail's field-side
shoulder against the S1002 tread) the mate is taken at the same lateral coordinate (centred wheelset: taping
line over the rail centre line), clipped to the mate's range, and the geometry records which rule was used.
Wheel/rail contact is often nearly conforming laterally (B <= 0 at the mating point, no Hertz ellipse); then
B is raised to ``1 / (2 R_max)`` with the stated largest relative lateral radius R_max (default 300 mm) and the
position's geometry records it (``source``). Users who know the contact patch give ``semi_axes_mm`` instead.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields
from typing import Any

import numpy as np
from scipy.optimize import brentq
from scipy.special import ellipe, ellipk

from wrlayer import validate
from wrlayer.errors import InputError, require

#: Rail inclination 1:40 (rad), the standard for new UIC60 track.
DEFAULT_RAIL_CANT_RAD = math.atan(1.0 / 40.0)

#: Largest relative lateral radius of curvature (mm) used when the lateral contact is (nearly) conforming.
DEFAULT_MAX_LATERAL_RADIUS_MM = 300.0


@dataclass(frozen=True)
class HertzEllipse:
    """Semi-axes a_mm (rolling direction x) and b_mm (lateral), peak pressure p0_MPa and approach_mm (both
    bodies together) for the normal force normal_force_N."""

    a_mm: float
    b_mm: float
    p0_MPa: float
    approach_mm: float
    normal_force_N: float


def combined_modulus_MPa(E1_MPa: float, nu1: float, E2_MPa: float | None = None, nu2: float | None = None) -> float:
    """E* with 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 (MPa); body 2 defaults to body 1's material."""
    E2_MPa = E1_MPa if E2_MPa is None else E2_MPa
    nu2 = nu1 if nu2 is None else nu2
    return 1.0 / ((1.0 - nu1 ** 2) / E1_MPa + (1.0 - nu2 ** 2) / E2_MPa)


def _axis_ratio(ratio: float) -> float:
    """k = c_s / c_l in (0, 1] such that A_s / A_l = ratio >= 1 (Hertz's transcendental equation)."""
    if ratio - 1.0 <= 1e-12:
        return 1.0

    def f(k):
        m = 1.0 - k * k
        K, E = ellipk(m), ellipe(m)
        return (E / (k * k) - K) / (K - E) - ratio

    lo = 1e-4
    require(f(lo) > 0, "curvature sums", f"ratio {ratio:.4g} is beyond the supported axis ratio 1e-4")
    return brentq(f, lo, 1.0 - 1e-9, xtol=1e-15, rtol=1e-14, maxiter=500)


def hertz_ellipse(A_per_mm: float, B_per_mm: float, normal_force_N: float, E_star_MPa: float) -> HertzEllipse:
    """Hertz contact for the gap A x^2 + B y^2 (A, B in 1/mm, both > 0) under the normal force (N)."""
    require(math.isfinite(A_per_mm) and A_per_mm > 0 and math.isfinite(B_per_mm) and B_per_mm > 0,
            "curvature sums", f"A = {A_per_mm!r}, B = {B_per_mm!r} 1/mm must be positive (non-conforming contact)")
    require(math.isfinite(normal_force_N) and normal_force_N > 0, "reference_load_N",
            f"must be positive, got {normal_force_N!r}")
    require(math.isfinite(E_star_MPa) and E_star_MPa > 0, "E*", f"must be positive, got {E_star_MPa!r}")
    A_l, A_s = min(A_per_mm, B_per_mm), max(A_per_mm, B_per_mm)
    k = _axis_ratio(A_s / A_l)
    m = 1.0 - k * k
    K, E = ellipk(m), ellipe(m)
    # (K - E)/e^2 -> pi/4 for a circle; evaluate it stably near m = 0
    k_minus_e_over_m = (K - E) / m if m > 1e-6 else math.pi / 4 * (1.0 + 0.75 * m)
    # A_l = p0 c_s (K-E)/(E* e^2 c_l^2), p0 = 3N/(2 pi c_l c_s)  ->  c_l^3 = 3 N (K-E)/(2 pi E* e^2 A_l)
    c_l = (3.0 * normal_force_N * k_minus_e_over_m / (2.0 * math.pi * E_star_MPa * A_l)) ** (1.0 / 3.0)
    c_s = k * c_l
    p0 = 3.0 * normal_force_N / (2.0 * math.pi * c_l * c_s)
    approach = p0 * c_s * K / E_star_MPa
    a, b = (c_l, c_s) if A_per_mm <= B_per_mm else (c_s, c_l)
    return HertzEllipse(float(a), float(b), float(p0), float(approach), float(normal_force_N))


def surface_curvatures(profile, y_mm: float, r0_mm: float | None = None) -> tuple[float, float]:
    """(k_x, k_y) in 1/mm, positive where the surface is convex towards the mating body (see module docstring).

    Wheel: k_x = 1/r(y) with r from ``profile.radius(y)`` or, for profiles without it, r0_mm - z(y).
    """
    y = float(profile.check_y(y_mm, "position"))
    kappa = float(profile.curvature(y))
    if profile.body == "rail":
        return 0.0, -kappa
    if hasattr(profile, "radius"):
        r = float(profile.radius(y))
    else:
        require(r0_mm is not None, "wheel_radius_mm", f"needed for the wheel profile {profile.name!r}")
        r = float(r0_mm) - float(profile.z(y))
    return 1.0 / r, kappa


def _track_angle(profile, y, cant_rad: float):
    """Surface slope angle in the track frame (rad): the rail's own slope plus the cant."""
    ang = np.arctan(np.asarray(profile.dz(y), dtype=float))
    return ang + cant_rad if profile.body == "rail" else ang


def mating_position(profile, y_mm: float, mate, rail_cant_rad: float = DEFAULT_RAIL_CANT_RAD,
                    what: str = "position", max_offset_mm: float = 10.0) -> tuple[float, str]:
    """(lateral position in mm in the mate's frame, rule) for the mate's point in contact with y_mm: the nearest
    tangent point (same slope angle) within max_offset_mm ("tangent"), else the same y clipped ("same y")."""
    y = float(profile.check_y(y_mm, what))
    target = float(_track_angle(profile, y, rail_cant_rad))
    ys = np.linspace(mate.y_min, mate.y_max, 4001)
    g = _track_angle(mate, ys, rail_cant_rad) - target
    roots = []
    for i in np.nonzero(np.sign(g[:-1]) * np.sign(g[1:]) <= 0)[0]:
        lo, hi = ys[i], ys[i + 1]
        if g[i] == 0.0:
            roots.append(lo)
            continue
        roots.append(brentq(lambda t: float(_track_angle(mate, t, rail_cant_rad)) - target, lo, hi, xtol=1e-10))
    near = [r for r in roots if abs(r - y) <= max_offset_mm]
    if near:
        return float(min(near, key=lambda r: abs(r - y))), "tangent"
    return float(np.clip(y, mate.y_min, mate.y_max)), "same y"


@dataclass(frozen=True)
class LocalGeometry:
    """Local contact geometry used at one position (mm, 1/mm, N, MPa): the body's and the mate's convex
    curvatures, the mating position, the Hertz ellipse at the reference load and the source of the semi-axes."""

    y_mm: float
    z_mm: float
    mate: str | None
    y_mate_mm: float | None
    k_x_per_mm: float | None
    k_y_per_mm: float | None
    k_x_mate_per_mm: float | None
    k_y_mate_per_mm: float | None
    a_mm: float
    b_mm: float
    p0_ref_MPa: float | None
    approach_ref_mm: float | None
    reference_load_N: float | None
    source: str

    def to_dict(self) -> dict:
        return asdict(self)

    @classmethod
    def from_dict(cls, data: Any, what: str = "geometry") -> LocalGeometry:
        """Validate and build (InputError naming the field): numbers finite, optional ones may be None."""
        validate.table(data, what)
        names = [f.name for f in fields(cls)]
        validate.check_known(data, names, what)
        for name in names:
            key = validate.join(what, name)
            if name not in data:
                raise InputError(key, "missing")
            value = data[name]
            if name in ("mate", "source"):
                if value is not None or name == "source":
                    validate.text(value, key)
            elif value is not None or name in ("y_mm", "z_mm", "a_mm", "b_mm"):
                validate.number(value, key)
        return cls(**data)


def local_geometry(profile, y_mm: float, mate, reference_load_N: float, E_MPa: float, poisson: float,
                   rail_cant_rad: float = DEFAULT_RAIL_CANT_RAD, wheel_radius_mm: float | None = None,
                   max_lateral_radius_mm: float = DEFAULT_MAX_LATERAL_RADIUS_MM) -> LocalGeometry:
    """The Hertz ellipse at ``y_mm`` of ``profile`` against ``mate`` under ``reference_load_N`` (same material).

    A lateral curvature sum below
    1/(2 max_lateral_radius_mm) is raised to it (recorded in ``source``).
    """
    what = f"position y = {float(y_mm):g} mm ({profile.name})"
    y = float(profile.check_y(y_mm, what))
    ym, rule = mating_position(profile, y, mate, rail_cant_rad, what)
    kx, ky = surface_curvatures(profile, y, wheel_radius_mm)
    kxm, kym = surface_curvatures(mate, ym, wheel_radius_mm)
    A, B = 0.5 * (kx + kxm), 0.5 * (ky + kym)
    require(A > 0, what, f"rolling-direction curvature sum A = {A:.3g} 1/mm must be positive")
    source = f"Hertz against {mate.name} ({'tangent point' if rule == 'tangent' else 'same lateral coordinate'})"
    B_min = 0.5 / float(max_lateral_radius_mm)
    if B < B_min:
        source += f" (lateral curvature sum {B:.3g} 1/mm raised to 1/(2*{max_lateral_radius_mm:g} mm))"
        B = B_min
    h = hertz_ellipse(A, B, reference_load_N, combined_modulus_MPa(E_MPa, poisson))
    return LocalGeometry(y, float(profile.z(y)), mate.name, ym, kx, ky, kxm, kym, h.a_mm, h.b_mm, h.p0_MPa,
                         h.approach_mm, float(reference_load_N), source)


#: Largest lateral semi-axis relative to the smallest lateral radius of curvature of the two surfaces for which
#: the Hertz (half-space, quadratic gap) load is used as it is. Hertz assumes the patch small against the radii;
#: at b/R = 0.2 the quadratic gap y^2/(2R) is 1 % off the circle's at y = b (sagitta R - sqrt(R^2 - b^2)), at the
#: gauge corner / flange root (b/R = 0.4 at 100 kN) 4 %, and the measured FEM p_2 there was 25 % below the
#: half-space value.
HERTZ_B_OVER_R_LIMIT = 0.2


def conformity(geo: "LocalGeometry") -> float:
    """b / R_min: the lateral semi-axis over the smallest lateral radius of curvature of the body and its mate
    (0 when the curvatures are unknown, e.g. given semi-axes)."""
    ks = [abs(k) for k in (geo.k_y_per_mm, geo.k_y_mate_per_mm) if k is not None]
    return float(geo.b_mm * max(ks)) if ks else 0.0


def fitted_load_N(geo: "LocalGeometry", limit: float = HERTZ_B_OVER_R_LIMIT) -> float:
    """The normal load (N) at which the position's Hertz patch has b / R_min = ``limit`` (b grows as N^(1/3))."""
    return float(geo.reference_load_N * (limit / conformity(geo)) ** 3)


def given_geometry(profile, y_mm: float, a_mm: float, b_mm: float) -> LocalGeometry:
    """Semi-axes given by the user (no curvature analysis)."""
    what = f"position y = {float(y_mm):g} mm ({profile.name})"
    y = float(profile.check_y(y_mm, what))
    require(a_mm > 0 and b_mm > 0, what, f"semi_axes_mm must be positive, got ({a_mm!r}, {b_mm!r})")
    return LocalGeometry(y, float(profile.z(y)), None, None, None, None, None, None, float(a_mm), float(b_mm),
                         None, None, None, "given semi-axes")


def halfspace_centre_compliance_mm_per_MPa(a_mm: float, b_mm: float, E_MPa: float, poisson: float) -> float:
    """Centre displacement of ONE elastic half-space per MPa of p0 under the Hertz pressure on the a x b ellipse:
    c_s K(e) (1 - nu^2) / E (mm/MPa), c_s the shorter semi-axis (Johnson 3.2; circle: pi a (1 - nu^2) / (2 E))."""
    c_s, c_l = min(a_mm, b_mm), max(a_mm, b_mm)
    return float(c_s * ellipk(1.0 - (c_s / c_l) ** 2) * (1.0 - poisson ** 2) / E_MPa)
