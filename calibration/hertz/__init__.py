"""Hertzian contact geometry and loads for the indentation (units mm, N, MPa).

- :mod:`~calibration.hertz.geometry`: the contact ellipse from a profile position's curvatures and its mate.
- :mod:`~calibration.hertz.load`: Hertzian and uniform surface pressures on a named FE boundary.

Depends on: wrlayer, calibration.fem (material).
"""
