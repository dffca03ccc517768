"""Calibration by similarity: the 3D FEM characteristic of any position from master curves.

A half-space of J2 material with linear hardening under the Hertz pressure ``p0 sqrt(1 - (x/a)^2 - (y/b)^2)`` has
no length of its own: at fixed p0 / p_y its displacements are proportional to the patch size sqrt(a b), and the
rest depends on the aspect ratio a/b, the material and the shape of the body's surface over the patch, measured by
its convexity b / (2 R) (docs/calibration.md, "Calibration by similarity"). The FEM therefore runs once per
material on a grid of synthetic concave, flat and convex sections and aspect ratios (the master curves); any
position of any profile, conforming ones included, is then interpolated in the convexity and log(a/b) and scaled
by its own sqrt(a b), in milliseconds. Positions outside the master's domain (a patch reaching past the profile's
end, a/b or the convexity outside the grid) are calibrated by the direct FEM or served from the master's nearest
point (``[run] similarity_outside``), reported per position.

- :mod:`calibration.similarity.sections`: the synthetic sections and the convexity of a position's surface.
- :mod:`calibration.similarity.master`: the master grid's FEM tasks and the master curves (versioned JSON).
- :mod:`calibration.similarity.route`: which positions the master serves, and their characteristic from it.
- :mod:`calibration.similarity.anchor`: a worn position corrected by the master's error at a direct FEM reference.
- :mod:`calibration.similarity.elastic`: a served position's p_y and elastic compliance from its own section's
  elastic solve (``[run] similarity_elastic``).

Depends on: calibration.config, calibration.settings, calibration.hertz, calibration.results, calibration.tasks,
calibration.cache, calibration.fem, calibration.indentation, meshes.
"""
