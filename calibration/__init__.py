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
- :mod:`calibration.results`: a position's results (FEM indentation, table entry) as typed records.
- :mod:`calibration.tasks`, :mod:`calibration.cache`, :mod:`calibration.tables`, :mod:`calibration.pipeline`,
  :mod:`calibration.plots`: the cached run over many positions (:mod:`wrlayer.runner`) and the layer tables,
  summary and pictures it writes.

Depends on: meshes, contact.layer (the table format), wrlayer.
"""

from __future__ import annotations

from importlib import import_module

#: The API names and their modules, imported on first use: ``import calibration.hertz`` stays free of the FEM
#: engine and the run machinery.
_API = {"calibrate": "calibration.pipeline", "run_calibration": "calibration.pipeline",
        "CalibrationResult": "calibration.pipeline", "load_config": "calibration.config",
        "parse_config": "calibration.config", "CalibrationConfig": "calibration.settings"}


def __getattr__(name: str):
    if name in _API:
        return getattr(import_module(_API[name]), name)
    raise AttributeError(f"module 'calibration' has no attribute {name!r}")


__all__ = sorted(_API)
