"""The tangential rolling-contact problem (units mm, N, MPa).

- :mod:`~contact.tangential.fastsim`: Kalker's FASTSIM strip by strip: creep forces, slip, frictional power and work.
- :mod:`~contact.tangential.kalker_coefficients`: Kalker's creep coefficients C_ij(a/b, nu).

Depends on: contact.normal (the Patch). Never imports contact.wheel_rail or contact.scenes.
"""
