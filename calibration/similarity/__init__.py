"""Calibration by similarity: the 3D FEM characteristic of a non-conforming position from master curves.

A half-space of J2 material with linear hardening under the Hertz pressure ``p0 sqrt(1 - (x/a)^2 - (y/b)^2)`` has
no length of its own: at fixed p0 / p_y its displacements are proportional to the patch size sqrt(a b), and the
rest depends only on the aspect ratio a/b and the material (the 3D local model's result is independent of the
support and the section depth; docs/calibration.md, "Calibration by similarity"). The FEM therefore runs once per
material on a grid of aspect ratios (the master curves); any non-conforming position of any profile is then
interpolated in log(a/b) and scaled by its own sqrt(a b), in milliseconds. Conforming positions (b/R above
:data:`calibration.hertz.geometry.HERTZ_B_OVER_R_LIMIT`), patches outside the master's range and surfaces less or
more convex over the patch than the master's crown (:data:`calibration.similarity.route.CONVEXITY_LIMIT`) are
calibrated by the direct FEM, reported per position.

- :mod:`calibration.similarity.master`: the master grid's FEM tasks and the master curves (JSON).
- :mod:`calibration.similarity.route`: which positions the master serves, and their characteristic from it.

Depends on: calibration.config, calibration.settings, calibration.hertz, calibration.indentation,
calibration.results, calibration.tasks, meshes.
"""
