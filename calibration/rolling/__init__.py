"""Rolling (moving-load) elastoplastic FEM of a half-space or a profile section, pass after pass (units mm, N, MPa, s).

A Hertz pressure (circular/elliptic in 3D, line load in 2D plane strain) with a surface traction q = c p in the
rolling direction is moved in quasi-static steps along x over a track, pass after pass, on a half-space block
refined along the loaded strip, or on a profile section extruded along the track; the residual groove after each pass is compared with the static dent at the same
p0 and with the calibrated layer's prediction under both memory rules (docs/rolling.md).

- :mod:`~calibration.rolling.config`: the configuration model (frozen dataclasses) and its TOML reader.
- :mod:`~calibration.rolling.track_mesh`: the block refined along the track (2D and 3D half model).
- :mod:`~calibration.rolling.section_position`: a layer table's position (profile, semi-axes a, b, material).
- :mod:`~calibration.rolling.section_track`: the profile section extruded along the track (supports, surface
  probes, the static load).
- :mod:`~calibration.rolling.section_groove`: the groove along the section's inward normal.
- :mod:`~calibration.rolling.moving_load`: the nodal forces of the Hertz pressure and traction at a load position.
- :mod:`~calibration.rolling.passes`: the passes as a generator of step and pass records (engine's Newton/PCG).
- :mod:`~calibration.rolling.groove`: the residual surface displacement (groove) along and across the track.
- :mod:`~calibration.rolling.layer_prediction`: the static dent, the fitted characteristic and the layer's groove.
- :mod:`~calibration.rolling.run`: ``run_rolling(config, out_dir)`` writing ``rolling.json`` and ParaView series.
- :mod:`~calibration.rolling.law_fit`: the rolling law (first-pass ratio, shakedown and ratcheting increments)
  fitted to the grooves of the passes (:class:`wrlayer.rolling_law.RollingLaw`).

Depends on: wrlayer, meshes (the profiles and the section extrusion), calibration.fem, calibration.hertz,
calibration.fit, calibration.position_fit (the layer's elastic slope S_1), calibration.position_mesh (the rail's
support), calibration.settings (the fit, mesh and material defaults), wrlayer.rolling_law and wrlayer.layer_table
(the rolling law and the tables).
"""
