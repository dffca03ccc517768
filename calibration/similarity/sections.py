"""Synthetic sections of the similarity master and the surface-shape measure that places a position among them
(units mm).

A master position stands at y = 0 of a synthetic rail block whose running surface is a circular arc of signed
lateral radius R = b / (2 c) around the load point, continued by its tangents to the block's sides: c > 0 convex
(a rail crown or gauge corner), c < 0 concave (a wheel's flange root or hollow tread), c = 0 flat. The shape
dimension of the master is this convexity c = b / (2 R): the sag of the surface over the half-width b of the patch,
over b (-). A profile position's own convexity is the same number measured on its surface over the patch
(:func:`patch_convexity`): the curvature of the circle that fits the surface's distance from its tangent plane
over y - b .. y + b by least squares weighted by the Hertz pressure, times b / 2. A position's mate enters the FEM
only through the semi-axes a and b (the load is the Hertz pressure on the body's own surface), so the mate's
conformity b / R_mate needs no master dimension of its own.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from meshes.profiles.base import ArcPiece, Profile, line_piece

#: The plastic curves are taken from the master at the convexity measured over this many b either side of the
#: load point (:func:`plastic_convexity`), p_y and the elastic compliance at the one over the patch: the plastic zone
#: at 1.5-3 p_y reaches past the patch, and where the surface's curvature changes across the patch (the 60E1 head
#: at y = -25 and +25 mm, between its radii) the patch's own convexity left the plastic curves of the section's
#: elastic solve 4.5 % and 4.8 % from the direct FEM; over 3 b, 1.8 % and 2.4 % (``benchmarks/bench_similarity.py
#: --sections``: 23 of 27 served positions within 2 %; over 1, 2 and 4 b: 21, 22 and 22).
PLASTIC_WINDOW_B = 3.0
#: Half-width of a synthetic block (mm): the 60E1 head's (the master's earlier section).
BLOCK_HALF_WIDTH_MM = 36.0
#: The arc spans at most this many b either side of the load point (beyond, the tangents continue): the plastic
#: zone of the Hertz load lies within about 1.5 b of the load point; the arc also ends at 0.8 R, where the
#: tangents are at 53 degrees.
ARC_SPAN_B = 4.0
ARC_SPAN_R = 0.8


@lru_cache(maxsize=64)
def arc_section(convexity: float, b_mm: float) -> Profile:
    """The synthetic rail block whose surface is the arc of convexity ``convexity`` = b / (2 R) (-) for the patch
    half-width ``b_mm`` (mm) at y = 0, z = 0, continued by its tangents to +-:data:`BLOCK_HALF_WIDTH_MM`."""
    w = BLOCK_HALF_WIDTH_MM
    name = f"arc c={convexity:+.4f} b={b_mm:.4g}mm"
    if convexity == 0.0:
        return Profile(name, "rail", [line_piece(-w, w, 0.0, 0.0)])
    radius = b_mm / (2.0 * abs(convexity))
    span = min(ARC_SPAN_B * b_mm, ARC_SPAN_R * radius, w)
    convex = convexity > 0.0  # rail: material below, a convex surface bends down
    arc = ArcPiece(-span, span, (0.0, -radius if convex else radius), radius, convex)
    pieces = [arc]
    if span < w:
        z_end, slope = float(arc.z(span)), float(arc.dz(span))
        pieces = [line_piece(-w, -span, z_end, slope), arc, line_piece(span, w, z_end, slope)]
    return Profile(name, "rail", pieces)


def patch_convexity(profile, y_mm: float, b_mm: float) -> float:
    """The signed convexity c = b / (2 R) of the profile over the patch y - b .. y + b (-): R the radius of the
    circle that fits the surface's distance d(s) from its tangent at y (measured along the normal, s along the
    tangent) as d = s^2 / (2 R) by least squares with the Hertz weight sqrt(1 - (s/b)^2); positive where the surface
    bends away from the body's material. Points beyond the profile's ends are left out."""
    y0, z0 = float(y_mm), float(profile.z(y_mm))
    n = np.asarray(profile.normal(y0), dtype=float)        # out of the material
    t = np.array([n[1], -n[0]])
    s = np.linspace(-b_mm, b_mm, 81)[1:-1]
    # points at tangent distance s: solve along the profile by the arc length (the surface may be steep)
    s0 = float(profile.arc_length(y0))
    ss = np.clip(s0 + s, 0.0, profile.length)
    keep = (s0 + s >= 0.0) & (s0 + s <= profile.length)
    ys = np.asarray(profile.y_at_arc_length(ss[keep]), dtype=float)
    pts = np.stack([ys - y0, np.asarray(profile.z(ys), dtype=float) - z0], axis=-1)
    along, dist = pts @ t, pts @ n                            # dist < 0: the surface falls away (convex)
    w = np.sqrt(np.clip(1.0 - (along / b_mm) ** 2, 0.0, None))
    kappa = -2.0 * np.sum(w * dist * along ** 2) / max(np.sum(w * along ** 4), 1e-300)
    return float(kappa * b_mm / 2.0)


def plastic_convexity(profile, y_mm: float, b_mm: float) -> float:
    """The convexity b / (2 R) (-) with R fitted over y -+ :data:`PLASTIC_WINDOW_B` b (:func:`patch_convexity` over
    that half-width, in units of the patch's b): the surface shape the plastic zone sees."""
    return patch_convexity(profile, y_mm, PLASTIC_WINDOW_B * b_mm) / PLASTIC_WINDOW_B


__all__ = ["ARC_SPAN_B", "ARC_SPAN_R", "BLOCK_HALF_WIDTH_MM", "PLASTIC_WINDOW_B", "arc_section", "patch_convexity",
           "plastic_convexity"]
