"""Shared basics of the wrlayer packages (meshes, calibration, contact): nothing here knows about contact or FEM.

- :mod:`wrlayer.characteristic`, :mod:`wrlayer.layer_table`: the layer's data shared by the calibration that
  produces them and the contact solvers that read them: the piecewise-linear characteristic p(u) with its Prandtl
  element parameters (paper eqs. 4-6), and the parameter table format.

- :mod:`wrlayer.errors`: the error types (InputError, ConvergenceError, ...), ``require`` and the command-line guard
  that turns them into one-line messages and documented exit codes.
- :mod:`wrlayer.validate`: validation helpers for values read from files.
- :mod:`wrlayer.atomic_write`: output files and folders written so that a failure never leaves a partial one.
- :mod:`wrlayer.cost`: run-time estimates and the guard that refuses long runs.
- :mod:`wrlayer.offscreen`, :mod:`wrlayer.plotting`, :mod:`wrlayer.progress`: headless rendering, figures, progress.
- :mod:`wrlayer.version`: the package version and the code revision recorded in every result.
- :mod:`wrlayer.cli`: the ``wrlayer`` console command (``wrlayer simulate|calibrate|mesh|...``).

Public API (imported on first use, so ``import wrlayer`` stays cheap; docs/api.md):

- ``WrLayerError``: base of the project's errors; ``exit_code`` is the command-line exit code.
- ``InputError``: bad input (a file, key, value or argument); ``what`` names it, ``problem`` says why; exit 2.
- ``ConvergenceError``: a numerical method did not converge; exit 3.
- ``package_version()``, ``code_version()``: the package version and the code revision recorded in every result.
- ``lazy_exports(package, api)``: the lazy ``__getattr__``/``__dir__`` of the packages' public names.

Depends on: none (numpy and the standard library; pyvista imported lazily).
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable

#: Public name -> the module that defines it.
API = {
    "WrLayerError": "wrlayer.errors",
    "InputError": "wrlayer.errors",
    "ConvergenceError": "wrlayer.errors",
    "package_version": "wrlayer.version",
    "code_version": "wrlayer.version",
}
__all__ = sorted(API) + ["lazy_exports"]


def lazy_exports(package: str, api: dict[str, str]) -> tuple[Callable[[str], object], Callable[[], list[str]]]:
    """The module-level ``__getattr__`` and ``__dir__`` of a package whose public names live in its modules.

    A name of ``api`` (name -> defining module) is imported from its module on first access and then cached in
    the package, so that importing the package (which every ``python -m`` entry point and every submodule import
    does) loads none of the heavy modules (scipy, numba, gmsh) until a public name is used.
    """

    def __getattr__(name: str) -> object:
        module = api.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(module), name)
        setattr(sys.modules[package], name, value)
        return value

    def __dir__() -> list[str]:
        return sorted(set(vars(sys.modules[package])) | set(api))

    return __getattr__, __dir__


__getattr__, __dir__ = lazy_exports(__name__, API)
