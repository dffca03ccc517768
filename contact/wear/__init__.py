"""Wear simulation: wheel and rail profiles that evolve by abrasive wear and by the inelastic displacement of the
Prandtl surface layer (units mm, N, MPa, s; distances in km where named so). Reference: docs/wear.md.

Modules (one concept each): :mod:`laws` (Archard with the Jendel map, USFD T-gamma), :mod:`collective` (load
collective, steady curves' per-wheel loads), :mod:`collective_scene` (the ``[collective]`` tables, sweep or
multibody export), :mod:`mbs_collective` (a multibody code's per-time-step export merged into a collective),
:mod:`curving` (cant, unbalanced acceleration and load transfer in a steady curve), :mod:`quasi_static` (the
wheelset's position, yaw and pitch rate in a steady curve from the quasi-static balance), :mod:`scene` (the TOML "wear" scene), :mod:`condition` (one running condition solved and turned into
depths), :mod:`runner` (in-process, local processes or Dask), :mod:`layer_state` (the layer's state per profile
position between steps), :mod:`profile_grid` (deposit, smoothing, profile update), :mod:`planning` (step length
and the tasks of a step), :mod:`step` (one wear step), :mod:`state` (what a step hands to the next),
:mod:`statistics` (numbers of a body's depths), :mod:`records` (step records and the run), :mod:`recalibrate`
(layer tables on the worn profiles, through the calibration's Python API), :mod:`conicity` (rolling-radius
difference and equivalent conicity after EN 15302), :mod:`loop` (the step loop as a generator of step records), :mod:`outputs` (files), :mod:`plots`
(pictures); a wear scene is run into a folder by :func:`contact.run_files.run_wear_file` (``wrlayer wear``).

Depends on: contact.wheel_rail, contact.geometry (the conicity formulas), contact.scenes, contact.passes,
contact.normal, contact.tangential, contact.layer, contact.result_warnings (the method's line in result.json),
meshes, calibration (the recalibration only, through its Python API).
"""
