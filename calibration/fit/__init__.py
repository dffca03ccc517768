"""Fitting the Prandtl element to an FEM characteristic (paper eqs. 4-8, units mm, MPa).

- :mod:`~calibration.fit.characteristic_fit`: piecewise-linear concave fit -> springs k_i and slider thresholds T_0i.
- :mod:`~calibration.fit.breakpoints`: its break points, the exact least-squares optimum over their placements.

Depends on: wrlayer (the characteristic it produces, wrlayer.characteristic).
"""
