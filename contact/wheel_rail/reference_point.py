"""The contact reference point of a loaded patch: where it is reported and where creepages and spin are evaluated.

Units mm, rad. Two definitions (``method.contact_point`` of a wheel_rail scene):

- ``"first_contact"``: the rigid first-contact point of the candidate (eta = 0 of its separation function, the
  point where the undeformed profiles touch before loading; with yaw it keeps the contact locus' longitudinal lead).
- ``"weighted_centre"``: the centre of the interpenetration region of the undeformed profiles at the loaded
  approach, weighted by the SQUARE of the interpenetration depth (the default of CONTACT's contact reference point,
  whose weighted centre uses depth^2 per cell of the interpenetration area). In the strip coordinate eta of the
  contact plane, with the normal approach delta of the patch and the separation f(eta) (minimum 0 at the
  candidate's gap), the rigid interpenetration at (x, eta) is h = delta - f(eta) - x^2 / (2 R); integrated over x
  (|x| < sqrt(2 R g), g = delta - f) h^2 gives (16/15) sqrt(2 R) g^(5/2), so

      eta_ref = sum eta g^(5/2) / sum g^(5/2)     over the separation table (0.02 mm samples), g = max(delta - f, 0)

  Its longitudinal lead is the contact locus' at the wheel profile coordinate of eta_ref (0 without yaw).

Orientation: with the first contact the contact plane is the candidate's (its common normal). With the weighted
centre its angle is the mean of the rail's local contact angles over the interpenetration with the same weights
(as CONTACT's weighted contact angle): on a wide conformal tread patch this differs from the first-contact angle by
up to 0.01 rad, which changes the spin by up to 20 %. The normal force, the creep forces, the spin and the vertical
balance use this orientation; the normal problem itself (the separation function and its approach) stays in the
candidate's plane.

In both cases the creepages are evaluated at the wheel surface point of the reference point, relative to the
wheelset centre, in the rigid-contact geometry: P_ref = P_0 + eta_ref t (P_0: the rigid contact point, t: the
contact plane's lateral axis); lowering the wheelset by its approach moves the centre and its surface together, so
the rolling radius at the point is the undeformed one (this reproduces CONTACT's creepages of the A-2.2 cases; a
point halfway into the interpenetration would change the longitudinal creepage by about approach / (2 r0) ~ 3e-5).
FASTSIM's strip coordinate and the spin moment Mz are taken about eta_ref as well.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from contact.wheel_rail.contact_search import ContactCandidate
from contact.wheel_rail.track_geometry import PlacedRail, TrackLayout, WheelsetPose, wheel_locus
from meshes.profiles import Profile
from wrlayer.errors import InputError

CONTACT_POINTS = ("first_contact", "weighted_centre")


def check_contact_point(name: str) -> str:
    if name not in CONTACT_POINTS:
        raise InputError("method.contact_point", f"must be one of {', '.join(CONTACT_POINTS)}, got {name!r}")
    return name


def _weights(cand: ContactCandidate, delta_mm: float) -> np.ndarray | None:
    f = cand.f_mm - float(np.min(cand.f_mm))
    g = np.maximum(delta_mm - f, 0.0)
    w = g * g * np.sqrt(g)
    return w if float(w.sum()) > 0 else None


def weighted_centre_eta(cand: ContactCandidate, delta_mm: float) -> float:
    """eta (mm, side-frame orientation) of the depth^2-weighted centre of the interpenetration region (module doc)."""
    w = _weights(cand, delta_mm)
    if w is None:              # no interpenetration (delta <= 0): the first contact point
        return float(cand.eta_mm[int(np.argmin(cand.f_mm))])
    return float(np.sum(cand.eta_mm * w) / w.sum())


def weighted_angle(cand: ContactCandidate, delta_mm: float, rail: PlacedRail) -> float:
    """Contact angle (rad, side frame) of the weighted-centre contact plane: the mean of the rail's local contact
    angles over the interpenetration, with the same depth^2 weights (as CONTACT's weighted contact angle)."""
    w = _weights(cand, delta_mm)
    if w is None:
        return float(cand.contact_angle_rad)
    return float(np.sum(rail_angles(cand, rail) * w) / w.sum())


#: How many (candidate, rail) pairs :func:`rail_angles` keeps (a wheel's balance alternates between its candidates).
RAIL_ANGLES_KEPT = 4
_RAIL_ANGLES: list = []


def rail_angles(cand: ContactCandidate, rail: PlacedRail) -> np.ndarray:
    """The rail's local contact angle (rad, side frame) at each sample of ``cand``'s separation table (read-only).
    The same for every approach: kept for the last :data:`RAIL_ANGLES_KEPT` (candidate, rail) pairs (by identity),
    so that a balance iteration evaluates the rail's normals once per candidate, not once per load."""
    for c, r, gamma in _RAIL_ANGLES:
        if c is cand and r is rail:
            return gamma
    n2 = rail.normal(cand.rail_coordinate(cand.eta_mm))
    gamma = np.arctan2(-n2[:, 0], n2[:, 1])
    gamma.setflags(write=False)
    _RAIL_ANGLES.insert(0, (cand, rail, gamma))
    del _RAIL_ANGLES[RAIL_ANGLES_KEPT:]
    return gamma


@dataclass(frozen=True)
class ReferencePoint:
    """The chosen point of one patch (side frame): eta_mm along the contact plane; profile coordinates on rail and
    wheel; point_mm (3,) = (X lead, Y, Z) of P_ref (mm, rigid-contact geometry); angle_rad, normal (3,), lateral
    (3,): orientation of the contact plane at the point (first contact: the candidate's common normal; weighted
    centre: the weighted mean angle)."""

    kind: str
    eta_mm: float
    y_rail_mm: float
    y_wheel_mm: float
    point_mm: np.ndarray
    angle_rad: float
    normal: np.ndarray
    lateral: np.ndarray


def reference_point(kind: str, cand: ContactCandidate, delta_mm: float, wheel: Profile, layout: TrackLayout,
                    pose_side: WheelsetPose, rail: PlacedRail | None = None) -> ReferencePoint:
    """The ``kind`` reference point of ``cand`` loaded to the normal approach ``delta_mm`` (see the module doc;
    ``rail`` is needed for the weighted centre's orientation)."""
    check_contact_point(kind)
    if kind == "first_contact":
        eta = 0.0
        lead = float(cand.X_mm)
        gamma = float(cand.contact_angle_rad)
        n, t = cand.normal, cand.lateral
    else:
        eta = weighted_centre_eta(cand, delta_mm)
        lead = float(wheel_locus(wheel, layout, pose_side, np.array([cand.wheel_coordinate(eta)])).X_mm[0])
        gamma = weighted_angle(cand, delta_mm, rail) if rail is not None else float(cand.contact_angle_rad)
        n = np.array([0.0, -np.sin(gamma), np.cos(gamma)])
        t = np.array([0.0, np.cos(gamma), np.sin(gamma)])
    yz = np.array([cand.Y_mm, cand.Z_mm]) + eta * cand.lateral[1:]
    return ReferencePoint(kind, eta, float(cand.rail_coordinate(eta)), float(cand.wheel_coordinate(eta)),
                          np.array([lead, yz[0], yz[1]]), gamma, n, t)


__all__ = ["CONTACT_POINTS", "RAIL_ANGLES_KEPT", "ReferencePoint", "check_contact_point", "rail_angles",
           "reference_point", "weighted_angle", "weighted_centre_eta"]
