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

from wrlayer import lazy_exports

#: Public name -> the module that defines it (imported on first use: the command line's parser loads no solver).
API = {
    "ConicityCurve": "contact.geometry.conicity",
    "ContactJump": "contact.geometry.jumps",
    "GeometryResult": "contact.geometry.analysis",
    "KinematicOscillation": "contact.geometry.conicity",
    "LateralSweep": "contact.geometry.sweep",
    "WheelsetProfiles": "contact.geometry.sweep",
    "conicity_curve": "contact.geometry.conicity",
    "contact_geometry": "contact.geometry.analysis",
    "kinematic_oscillation": "contact.geometry.conicity",
}
__all__ = sorted(API)
__getattr__, __dir__ = lazy_exports(__name__, API)
