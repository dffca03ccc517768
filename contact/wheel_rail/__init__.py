"""Wheel on rail: track and wheelset geometry, contact search, kinematics, the loaded wheel solve and its scenes.

- :mod:`~contact.wheel_rail.track_geometry`: rail placement (gauge, inclination), wheelset pose, wheel locus.
- :mod:`~contact.wheel_rail.contact_search`: contact candidates (tread, flange) from the profiles.
- :mod:`~contact.wheel_rail.kinematics`: contact frames and creepages of a wheelset.
- :mod:`~contact.wheel_rail.reference_point`: the contact reference point (first contact or weighted centre).
- :mod:`~contact.wheel_rail.solve`: the vertical load balance over the patches of one wheel, normal + tangential.
- :mod:`~contact.wheel_rail.scene`: wheel-rail scene files, sweeps and their results.
- :mod:`~contact.wheel_rail.plots`: pictures of wheel-rail results.

Depends on: contact.normal, contact.tangential, contact.layer, contact.passes, contact.scenes (scene keys, result
writing) and meshes.profiles (the public profile API). Nothing else in contact imports it (but ``contact.__main__``).
"""
