"""FEM calibration of the Prandtl surface layer (units mm, N, MPa, s).

- :mod:`calibration.fem`: the elastoplastic FEM engine on scikit-fem.
- :mod:`calibration.hertz`: Hertzian contact geometry and pressure loads.
- :mod:`calibration.indentation`: one position's indentation -> characteristic points.
- :mod:`calibration.fit`: the Prandtl element fit (paper eqs. 4-8).
- :mod:`calibration.config`, :mod:`calibration.pipeline`, :mod:`calibration.plots`: config files, the cached run over
  many positions (local pool or Dask) and the layer tables and pictures it writes.

Public API (imported on first use: ``import calibration`` loads neither scikit-fem nor gmsh; docs/api.md):

- ``load_config(path) -> CalibrationConfig``: read and validate a TOML configuration (bodies, positions in mm,
  material ``E_MPa``/``poisson``/``yield_MPa``, loads in N, mesh sizes in mm); ``parse_config(data, source)``
  for a dictionary.
- ``run_calibration(cfg, out_dir, plots=None)``: calibrate every body and position of ``cfg`` into ``out_dir``
  (``<body>_layer_table.json``/``.csv``, ``summary.json``; cached by input hash); returns the summary dictionary.
- ``CalibrationConfig``, ``BodySettings``, ``MaterialSettings``: the configuration's dataclasses (change a copy
  with :func:`dataclasses.replace`, e.g. fewer positions).

Depends on: wrlayer, meshes.
"""

from wrlayer import lazy_exports

#: Public name -> the module that defines it.
API = {
    "load_config": "calibration.config",
    "parse_config": "calibration.config",
    "CalibrationConfig": "calibration.config",
    "BodySettings": "calibration.config",
    "MaterialSettings": "calibration.config",
    "run_calibration": "calibration.pipeline",
}
__all__ = sorted(API)
__getattr__, __dir__ = lazy_exports(__name__, API)
