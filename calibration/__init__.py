"""FEM calibration of the Prandtl surface layer (units mm, N, MPa, s).

- :mod:`calibration.fem`: the elastoplastic FEM engine on scikit-fem.
- :mod:`calibration.hertz`: Hertzian contact geometry and pressure loads.
- :mod:`calibration.indentation`: one position's indentation -> characteristic points.
- :mod:`calibration.fit`: the Prandtl element fit (paper eqs. 4-8).
- :mod:`calibration.config`, :mod:`calibration.pipeline`, :mod:`calibration.plots`: config files, the cached run over
  many positions (local pool or Dask) and the layer tables and pictures it writes.

Depends on: meshes, contact.layer (the table format), wrlayer.
"""
