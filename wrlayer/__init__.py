"""Shared basics of the wrlayer packages (meshes, calibration, contact): nothing here knows about contact or FEM.

- :mod:`wrlayer.errors`: the error types (InputError, ConvergenceError, ...), ``require`` and the command-line guard
  that turns them into one-line messages and documented exit codes.
- :mod:`wrlayer.atomic_write`: output files and folders written so that a failure never leaves a partial one.
- :mod:`wrlayer.offscreen`: headless pyvista/VTK rendering set-up.
- :mod:`wrlayer.version`: the package version and the code revision recorded in every result.
- :mod:`wrlayer.cli`: the ``wrlayer`` console command (``wrlayer simulate|calibrate|mesh|...``).

Depends on: numpy and the standard library only (pyvista imported lazily). Imported by every package.
"""
