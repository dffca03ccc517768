"""A safe, headless, deterministic Gmsh session (context manager).

Gmsh keeps one global state per process, so sessions are serialised with a lock. The session initialises Gmsh
without its SIGINT handler, silences the terminal, fixes the random seed and uses one thread (same inputs ->
identical mesh), and always finalises -- also when the block raises -- so that the next call starts clean.
If Gmsh was already initialised by the caller, the session only adds (and afterwards removes) its own model and
makes the caller's model current again; Gmsh options set by the session (``General.*``, ``Mesh.*``) stay set.
"""

from __future__ import annotations

import contextlib
import itertools
import threading
from collections.abc import Iterator

import gmsh

from wrlayer.errors import ConvergenceError

_LOCK = threading.RLock()
_COUNTER = itertools.count()

#: Options set in every session (deterministic, quiet, single-threaded).
SESSION_OPTIONS: dict[str, float] = {
    "General.Terminal": 0,
    "General.Verbosity": 1,
    "General.NumThreads": 1,
    "Mesh.MaxNumThreads1D": 1,
    "Mesh.MaxNumThreads2D": 1,
    "Mesh.MaxNumThreads3D": 1,
    "Mesh.RandomSeed": 1,
}


@contextlib.contextmanager
def gmsh_session(name: str = "wrlayer") -> Iterator[object]:
    """Yield the ``gmsh`` module with a fresh current model called ``name``; clean up on exit."""
    with _LOCK:
        owner = not gmsh.isInitialized()
        if owner:
            gmsh.initialize(readConfigFiles=False, interruptible=False)
        model = f"{name}-{next(_COUNTER)}"
        previous = None if owner else gmsh.model.getCurrent()
        try:
            for key, value in SESSION_OPTIONS.items():
                gmsh.option.setNumber(key, value)
            gmsh.model.add(model)
            yield gmsh
        finally:
            if owner:
                gmsh.finalize()
            else:
                with contextlib.suppress(Exception):
                    gmsh.model.setCurrent(model)
                    gmsh.model.remove()
                    gmsh.model.setCurrent(previous)


def generate(dim: int, order: int = 1) -> None:
    """Mesh the current model up to ``dim`` with elements of ``order`` (1 or 2; order 2 puts the mid-edge
    nodes on the exact geometry). A Gmsh failure becomes ConvergenceError."""
    try:
        gmsh.model.mesh.generate(dim)
        if order == 2:
            gmsh.model.mesh.setOrder(2)
    except Exception as err:  # Gmsh raises plain Exception with its error message
        raise ConvergenceError(f"Gmsh could not mesh the {dim}D model: {err}") from err
