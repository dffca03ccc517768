"""Wheel/rail contact geometry of a wheelset on its track (rigid contact; units mm, rad).

- :func:`contact_geometry` -> :class:`GeometryResult` (:mod:`~contact.geometry.analysis`): the whole analysis;
- :mod:`~contact.geometry.sweep`: contact points, rolling radii, contact angles and roll over a lateral sweep;
- :mod:`~contact.geometry.conicity`: equivalent conicity after EN 15302 (kinematic wavelength, harmonic
  linearisation);
- :mod:`~contact.geometry.jumps`: jumps of the contact points;
- :mod:`~contact.geometry.outputs`: CSV tables and pictures; :mod:`~contact.geometry.command`: ``wrlayer geometry``.

Depends on: contact.wheel_rail (track placement, contact search, rigid roll), meshes (profiles), wrlayer (errors,
command line, files). The wear loop (contact.wear) uses its conicity formulas.
"""

from contact.geometry.analysis import GeometryResult, contact_geometry
from contact.geometry.conicity import ConicityCurve, KinematicOscillation, conicity_curve, kinematic_oscillation
from contact.geometry.jumps import ContactJump
from contact.geometry.sweep import LateralSweep, WheelsetProfiles

__all__ = ["ConicityCurve", "ContactJump", "GeometryResult", "KinematicOscillation", "LateralSweep",
           "WheelsetProfiles", "conicity_curve", "contact_geometry", "kinematic_oscillation"]
