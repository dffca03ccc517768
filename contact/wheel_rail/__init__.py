"""Wheel on rail: track and wheelset geometry, contact search, kinematics, the loaded wheel solve and its scenes.

One module per step of a wheel–rail case:

- :mod:`~contact.wheel_rail.track_geometry`: rail placement (gauge, inclination), wheelset pose, wheel locus.
- :mod:`~contact.wheel_rail.contact_search`: locate: contact candidates (tread, flange) from the profiles.
- :mod:`~contact.wheel_rail.kinematics`: contact frames and creepages of a wheelset.
- :mod:`~contact.wheel_rail.reference_point`: the contact reference point (first contact or weighted centre).
- :mod:`~contact.wheel_rail.inputs`: the solver inputs of one wheel (``WheelRailInputs``; the layers are ``contact.scenes.layers.LayerSources``).
- :mod:`~contact.wheel_rail.balance`: total force: the vertical load balance over the candidates of one wheel
  (normal + tangential per patch, layers looked up per strip).
- :mod:`~contact.wheel_rail.root_finder`: the secant iteration of the balance.
- :mod:`~contact.wheel_rail.solve`: solve one wheel: search, balance, passes, coverage; merge and layer retries.
- :mod:`~contact.wheel_rail.solution`: the solution of one wheel (patches, forces).
- :mod:`~contact.wheel_rail.deformed`: residual displacements on the profiles; the rigid wheelset's roll.
- :mod:`~contact.wheel_rail.scene`: the typed wheel–rail scene (the shared sections of
  :mod:`~contact.scenes.sections` and :mod:`~contact.scenes.layers`, extended in :mod:`~contact.wheel_rail.sections`).
- :mod:`~contact.wheel_rail.parse`: scene TOML -> the typed scene; :mod:`~contact.wheel_rail.sweep`: its cases
  (:mod:`~contact.wheel_rail.sweep_spec`: the case records); :mod:`~contact.wheel_rail.scene_files`: the profile
  and CSV files a scene names.
- :mod:`~contact.wheel_rail.run`: output: a scene run (every case, every wheel); :mod:`~contact.wheel_rail.results`
  and :mod:`~contact.wheel_rail.patch_result`: the result records; :mod:`~contact.wheel_rail.result_files`: the
  conventions and cases.csv.
- :mod:`~contact.wheel_rail.plots`: pictures of wheel-rail results.

Depends on: contact.normal, contact.tangential, contact.layer, contact.passes, contact.scenes (result writing) and
meshes.profiles (the public profile API). Nothing else in contact imports it (but ``contact.__main__`` and
contact.wear).
"""
