"""The contact reference point of a loaded patch: where it is reported and where creepages and spin are evaluated.

Units mm, rad. Two definitions (``method.contact_point`` of a wheel_rail scene):

- ``"first_contact"``: the rigid first-contact point of the candidate (eta = 0 of its separation function, the
  point where the undeformed profiles touch before loading; with yaw it keeps the contact locus' longitudinal lead).
- ``"weighted_centre"``: the centre of the interpenetration region of the undeformed profiles at the loaded
  approach, weighted by the interpenetration depth (as CONTACT reports its contact reference point). In the
  strip coordinate eta of the contact plane, with the normal approach delta of the patch and the separation
  f(eta) (minimum 0 at the candidate's gap), the rigid interpenetration at (x, eta) is
  h = delta - f(eta) - x^2 / (2 R); integrated over x (|x| < sqrt(2 R g), g = delta - f) it gives
  (4/3) sqrt(2 R) g^(3/2), so

      eta_ref = sum eta g^(3/2) / sum g^(3/2)     over the separation table (0.02 mm samples), g = max(delta - f, 0)

  Its longitudinal lead is the contact locus' at the wheel profile coordinate of eta_ref (0 without yaw).

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
from contact.wheel_rail.track_geometry import TrackLayout, WheelsetPose, wheel_locus
from meshes.profiles.base import Profile
from wrlayer.errors import InputError

CONTACT_POINTS = ("first_contact", "weighted_centre")


def check_contact_point(name: str) -> str:
    if name not in CONTACT_POINTS:
        raise InputError("method.contact_point", f"must be one of {', '.join(CONTACT_POINTS)}, got {name!r}")
    return name


def weighted_centre_eta(cand: ContactCandidate, delta_mm: float) -> float:
    """eta (mm, side-frame orientation) of the depth-weighted centre of the interpenetration region (module doc)."""
    f = cand.f_mm - float(np.min(cand.f_mm))
    g = np.maximum(delta_mm - f, 0.0)
    w = g * np.sqrt(g)
    total = float(w.sum())
    if not total > 0:          # no interpenetration (delta <= 0): the first contact point
        return float(cand.eta_mm[int(np.argmin(cand.f_mm))])
    return float(np.sum(cand.eta_mm * w) / total)


@dataclass(frozen=True)
class ReferencePoint:
    """The chosen point of one patch (side frame): eta_mm along the contact plane; profile coordinates on rail and
    wheel; point_mm (3,) = (X lead, Y, Z) of P_ref (mm, rigid-contact geometry)."""

    kind: str
    eta_mm: float
    y_rail_mm: float
    y_wheel_mm: float
    point_mm: np.ndarray


def reference_point(kind: str, cand: ContactCandidate, delta_mm: float, wheel: Profile, layout: TrackLayout,
                    pose_side: WheelsetPose) -> ReferencePoint:
    """The ``kind`` reference point of ``cand`` loaded to the normal approach ``delta_mm`` (see the module doc)."""
    check_contact_point(kind)
    if kind == "first_contact":
        eta = 0.0
        lead = float(cand.X_mm)
    else:
        eta = weighted_centre_eta(cand, delta_mm)
        lead = float(wheel_locus(wheel, layout, pose_side, np.array([cand.wheel_coordinate(eta)])).X_mm[0])
    t = cand.lateral
    yz = np.array([cand.Y_mm, cand.Z_mm]) + eta * t[1:]
    return ReferencePoint(kind, eta, float(cand.rail_coordinate(eta)), float(cand.wheel_coordinate(eta)),
                          np.array([lead, yz[0], yz[1]]))


__all__ = ["CONTACT_POINTS", "ReferencePoint", "check_contact_point", "reference_point", "weighted_centre_eta"]
