"""FEM calibration of the Prandtl surface layer (units mm, N, MPa, s).

Python API (a calibration of given positions)::

    import calibration
    cfg = calibration.load_config("calibration/configs/default.toml")   # or parse_config(data, source, base)
    cfg = dataclasses.replace(cfg, bodies=(dataclasses.replace(cfg.bodies[0], profile=worn_profile),))
    result = calibration.calibrate(cfg, "out/cal", scheduler=None, plots=False)
    result.tables, result.failed, result.to_dict()                       # CalibrationResult

- :mod:`calibration.settings`, :mod:`calibration.config`: the configuration model and its TOML reader.
- :mod:`calibration.fem`: the elastoplastic FEM engine on scikit-fem.
- :mod:`calibration.hertz`: Hertzian contact geometry and pressure loads.
- :mod:`calibration.position_mesh`, :mod:`calibration.indentation`: one position's mesh and FEM indentation.
- :mod:`calibration.fit`, :mod:`calibration.position_fit`: the Prandtl element fit (paper eqs. 4-8).
- :mod:`calibration.placement`: the rail inclination of a body (profiles in their own frame).
- :mod:`calibration.similarity`: master curves over the patch aspect ratio and the similarity route.
- :mod:`calibration.batch`: a folder of profile files with one template configuration.
- :mod:`calibration.results`: a position's results (FEM indentation, table entry) as typed records.
- :mod:`calibration.tasks`, :mod:`calibration.cache`, :mod:`calibration.tables`, :mod:`calibration.pipeline`,
  :mod:`calibration.run_summary`, :mod:`calibration.plots`: the cached run over many positions
  (:mod:`wrlayer.runner`) and the layer tables, summary and pictures it writes.

Public API (imported on first use: ``import calibration`` loads neither scikit-fem nor gmsh; docs/api.md):

- ``load_config(path) -> CalibrationConfig``: read and validate a TOML configuration (bodies, positions in mm,
  material ``E_MPa``/``poisson``/``yield_MPa``, loads in N, mesh sizes in mm); ``parse_config(data, source)``
  for a dictionary.
- ``calibrate(cfg, out_dir, *, scheduler=None, plots=None) -> CalibrationResult``: calibrate every body and
  position of ``cfg`` into ``out_dir`` (``<body>_layer_table.json``/``.csv``, ``summary.json``; cached by input
  hash); ``run_calibration`` is the same returning the summary dictionary.
- ``calibration.batch.calibrate_profiles(paths, template, out_dir) -> {file: CalibrationResult}``: every profile
  file of ``paths`` (files, folders, globs) calibrated with a template configuration, the batch's cost printed
  first.
- ``CalibrationConfig``, ``BodySettings``, ``MaterialSettings``: the configuration's dataclasses (change a copy
  with :func:`dataclasses.replace`, e.g. fewer positions).

Depends on: wrlayer, meshes.
"""

from wrlayer import lazy_exports

#: Public name -> the module that defines it (imported on first use).
API = {
    "calibrate": "calibration.pipeline",
    "run_calibration": "calibration.pipeline",
    "CalibrationResult": "calibration.run_summary",
    "load_config": "calibration.config",
    "parse_config": "calibration.config",
    "CalibrationConfig": "calibration.settings",
    "BodySettings": "calibration.settings",
    "MaterialSettings": "calibration.settings",
}
__all__ = sorted(API)
__getattr__, __dir__ = lazy_exports(__name__, API)
