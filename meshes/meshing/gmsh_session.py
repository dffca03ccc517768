"""A safe, headless, deterministic Gmsh session (context manager).

Gmsh keeps one global state per process, so sessions are serialised with a lock. The session initialises Gmsh
without its SIGINT handler, silences the terminal, fixes the random seed and uses one thread (same inputs ->
identical mesh), and always finalises -- also when the block raises -- so that the next call starts clean.
If Gmsh was already initialised by the caller, the session only adds (and afterwards removes) its own model and
makes the caller's model current again; Gmsh options set by the session (``General.*``, ``Mesh.*``) stay set.
Gmsh's start changes the process's signal dispositions; :func:`initialize_gmsh` puts them back
(:func:`signal_dispositions_kept`).
"""

from __future__ import annotations

import contextlib
import ctypes
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


#: Standard signals whose dispositions a Gmsh start may change (1..31; SIGKILL and SIGSTOP cannot be set).
_SIGNALS = tuple(range(1, 32))
#: Bytes reserved for one ``struct sigaction`` (152 on Linux/glibc x86-64, 16 on macOS), read and written back as is.
_SIGACTION_BYTES = 512


def _libc_sigaction():
    """libc's ``sigaction`` through ctypes, or None where it is not available (Windows)."""
    try:
        fn = ctypes.CDLL(None, use_errno=True).sigaction
    except (OSError, AttributeError, TypeError):
        return None
    fn.argtypes = (ctypes.c_int, ctypes.c_void_p, ctypes.c_void_p)
    fn.restype = ctypes.c_int
    return fn


_SIGACTION = _libc_sigaction()


def _dispositions() -> dict[int, ctypes.Array] | None:
    """The process's disposition of every standard signal (opaque ``struct sigaction`` buffers)."""
    if _SIGACTION is None:
        return None
    saved = {}
    for sig in _SIGNALS:
        buf = ctypes.create_string_buffer(_SIGACTION_BYTES)
        if _SIGACTION(sig, None, buf) == 0:
            saved[sig] = buf
    return saved


def _restore(saved: dict[int, ctypes.Array] | None) -> None:
    for sig, buf in (saved or {}).items():
        _SIGACTION(sig, buf, None)      # SIGKILL/SIGSTOP fail with EINVAL: nothing to restore there


@contextlib.contextmanager
def signal_dispositions_kept() -> Iterator[None]:
    """Put every standard signal's disposition back as it was when the block started (at the C level, whoever set
    it). Gmsh's start resets SIGINT, SIGTERM, SIGILL, SIGFPE, SIGSEGV and SIGBUS to their defaults and un-ignores
    SIGPIPE (measured with Gmsh 4.x on Linux: /proc/self/status), behind Python's back: Python still reports its own
    handlers. After it, SIGTERM killed a run without its `error: terminated` line and its clean-up, a write to a
    pipe of a terminated worker killed the caller (SIGPIPE: a pytest-xdist worker crashed in a runner test after a
    meshing test) and faulthandler no longer reported crashes."""
    saved = _dispositions()
    try:
        yield
    finally:
        _restore(saved)


def initialize_gmsh() -> None:
    """``gmsh.initialize`` (no configuration files, no SIGINT handler of its own) with every signal's disposition
    kept (:func:`signal_dispositions_kept`)."""
    with signal_dispositions_kept():
        gmsh.initialize(readConfigFiles=False, interruptible=False)


@contextlib.contextmanager
def gmsh_session(name: str = "wrlayer") -> Iterator[object]:
    """Yield the ``gmsh`` module with a fresh current model called ``name``; clean up on exit."""
    with _LOCK:
        owner = not gmsh.isInitialized()
        if owner:
            initialize_gmsh()
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
