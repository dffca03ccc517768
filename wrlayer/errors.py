"""The project's error types and the command-line guard that turns them into one-line messages.

Every package (meshes, calibration, contact) raises these, so that a command-line user sees
``error: <input>: <what is wrong>`` and a non-zero exit code instead of a traceback.

Exit codes of every entry point (``python -m contact``, ``python -m calibration``, ``python -m meshes``; see
docs/inputs-and-errors.md):

- 0: success.
- 1: a batch finished with some items failed (``simulate-all``: failing scenes), or a stress run found failures.
- 2: bad input — :class:`InputError`: a file, key, value or command-line argument (also an unusable ``--out``,
  a run refused by its cost estimate, an output folder in use by another run, an unreadable/unwritable path).
- 3: numerical failure — :class:`ConvergenceError` (Newton, bracketing, a degenerate mesh, out of memory).
- 4: calibration finished but some positions failed (the tables hold the others).
- 130: interrupted (Ctrl-C); 143: terminated (SIGTERM). Both remove the run's staging folders and end its
  worker processes before exiting.
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import signal
import sys
import threading
from typing import Callable, Iterator


class WrLayerError(Exception):
    """Base of the project's clear errors. ``str(err)`` is a complete one-line message."""

    exit_code = 1


class InputError(WrLayerError, ValueError):
    """Bad input: names the input (file, key or argument) and says what is wrong with it."""

    exit_code = 2

    def __init__(self, what: str, problem: str):
        self.what = what
        self.problem = problem
        super().__init__(f"{what}: {problem}")

    def __reduce__(self):
        # rebuilt from (what, problem), so that it crosses from a worker process (the default pickles the message
        # alone, and the unpickling would fail and break the process pool)
        return type(self), (self.what, self.problem), self.__dict__


class ConvergenceError(WrLayerError, ArithmeticError):
    """A numerical method did not converge or left its bracket; never returned as a result."""

    exit_code = 3


class PatchTruncated(InputError):
    """A contact patch reaches the end of its separation table or function (``what``: ``separation.y_mm``): the
    table is too narrow, or (wheel on rail) the patch grows into the neighbouring contact candidate, which the
    wheel–rail solver answers by merging the candidates. Exit code 2 like every InputError."""


class LayerNotCovered(InputError):
    """A strip in contact has no layer element, or lies outside the range of a calibration table: the layer does not
    cover the contact location. ``what`` names the layer. Exit code 2 like every InputError."""


class LayerElementMissing(LayerNotCovered):
    """A loaded strip has no element of a layer that was built on fewer strips than the patch reached (``what``
    names the layer); the wheel–rail solver answers it by building the layer on more strips."""


class LayerRangeExceeded(InputError):
    """A strip's peak pressure lies above the largest pressure its calibration table was calibrated to (``what``
    names the table and the position): the layer would be extrapolated. Exit code 2 like every InputError."""


def typed_input_error(err: InputError) -> InputError:
    """``err`` as :class:`PatchTruncated` or :class:`LayerElementMissing` when it is one of those raised as a plain
    InputError by the normal solvers of contact.normal (a separation problem found while solving is named
    ``separation.y_mm``; a layer without an element on a loaded strip "... does not cover the contact patch");
    any other error unchanged. Callers that react to these two (the wheel–rail merge and layer retries, the scene
    messages) pass the solvers' errors through it; once contact.normal raises the subclasses it is the identity."""
    if type(err) is not InputError:
        return err
    if err.what == "separation.y_mm":
        return PatchTruncated(err.what, err.problem)
    if "does not cover the contact patch" in err.problem:
        return LayerElementMissing(err.what, err.problem)
    return err


def cli_guard(main: Callable[..., int | None]) -> Callable[..., int]:
    """Wrap a command-line ``main``: project errors become ``error: ...`` on stderr and an exit code.

    Unexpected exceptions (programming errors) still propagate with their traceback.
    """

    @functools.wraps(main)
    def wrapped(*args, **kwargs) -> int:
        global _terminated, _pending, _kept
        previous = _catch_sigterm()
        outermost = previous is not _raise_terminated
        if outermost:  # fresh flags, a quiet unraisable hook
            _terminated, _pending, _kept = False, False, ""
        hook = sys.unraisablehook
        sys.unraisablehook = _unraisable
        try:
            try:
                rc = main(*args, **kwargs)
                check_terminated()
            except BaseException as err:
                if _terminated and not isinstance(err, Terminated):  # whatever a library made of the interrupted
                    raise Terminated() from None  # call (e.g. numba wraps it), SIGTERM came first: terminated
                raise
        except Terminated as err:
            print(f"error: terminated (SIGTERM); {err.kept or _kept or 'nothing written'}", file=sys.stderr)
            return 143
        except WrLayerError as err:
            print(f"error: {_one_line(str(err))}", file=sys.stderr)
            return err.exit_code
        except KeyboardInterrupt:
            print("error: interrupted", file=sys.stderr)
            return 130
        except OSError as err:  # a path the user gave cannot be read or written (permissions, disk full, ...)
            where = err.filename if err.filename is not None else "file system"
            print(f"error: {where}: {err.strerror or err}", file=sys.stderr)
            return InputError.exit_code
        except MemoryError:
            print("error: out of memory (the run is too large for this machine; reduce the grid, cells, passes "
                  "or cases)", file=sys.stderr)
            return ConvergenceError.exit_code
        finally:
            sys.unraisablehook = hook
            if previous is not None:
                signal.signal(signal.SIGTERM, previous)
            if outermost:  # the command has answered its SIGTERM: later library calls in this process (tests,
                _terminated, _pending, _kept = False, False, ""  # a notebook) must not raise it again
        return 0 if rc is None else int(rc)

    return wrapped


class Terminated(BaseException):
    """Raised in the main thread on SIGTERM while a command runs, so that staging folders are removed and worker
    processes ended (``finally``/``except BaseException`` blocks run) before the process exits with 143.
    ``kept``: what a run that publishes as it goes kept (e.g. a wear run's completed steps); "" for nothing."""

    def __init__(self, kept: str = ""):
        super().__init__(kept)
        self.kept = kept


#: Set by the SIGTERM handler and kept: an exception raised inside a C callback (e.g. numba's compiler calling back
#: through ctypes) is printed and dropped by Python, so the signal would be lost; :func:`check_terminated` at the
#: points where output is committed, and the command wrapper at its end, raise it again.
_terminated = False


#: What the running command has kept on disk so far (:func:`record_kept`), for the SIGTERM line; "" for nothing.
_kept = ""


def record_kept(text: str) -> None:
    """Say what the running command has put in place so far (e.g. ``2 completed step(s) kept in out/wear.partial``);
    a SIGTERM then prints it instead of "nothing written". Called by the writer right after the output is in place,
    inside the same :func:`termination_deferred` block, so the line is never ahead of or behind the folder."""
    global _kept
    _kept = text


#: Depth of :func:`termination_deferred` blocks and whether a SIGTERM arrived inside one (raised at its end).
_deferring = 0
_pending = False


def _raise_terminated(signum, frame):
    global _terminated, _pending
    _terminated = True
    if _deferring:
        _pending = True
        return
    raise Terminated()


@contextlib.contextmanager
def termination_deferred() -> Iterator[None]:
    """Hold back a SIGTERM that arrives during the block and raise it as :class:`Terminated` when the block ends.

    For the few steps that must not be cut in two: creating a staging folder and handing it to the ``try`` that
    removes it, and removing it (an interrupted removal would leave half a folder behind)."""
    global _deferring, _pending
    _deferring += 1
    try:
        yield
    finally:
        _deferring -= 1
        held, _pending = _pending, _pending and bool(_deferring)  # an error leaving the block: the flag keeps it
    if held and not _deferring:
        raise Terminated()


def _unraisable(info) -> None:
    """sys.unraisablehook while a command runs: a Terminated dropped inside a C callback is not printed (the flag
    keeps it, :func:`check_terminated` raises it again); anything else goes to the default hook."""
    if info.exc_type is not None and issubclass(info.exc_type, Terminated):
        return
    sys.__unraisablehook__(info)


def check_terminated() -> None:
    """Raise :class:`Terminated` if SIGTERM arrived during this command (even if its first raise was swallowed)."""
    if _terminated:
        raise Terminated()


def _catch_sigterm():
    """Install the SIGTERM handler (main thread only); returns the previous handler to restore, or None."""
    if threading.current_thread() is not threading.main_thread():
        return None
    try:
        return signal.signal(signal.SIGTERM, _raise_terminated)
    except (ValueError, OSError):
        return None


def _one_line(text: str, limit: int = 600) -> str:
    """The message on one line, cut to ``limit`` characters."""
    text = " ".join(text.split())
    return text if len(text) <= limit else text[: limit - 4] + " ..."


class ArgumentParser(argparse.ArgumentParser):
    """argparse with the project's error format: a bad command-line argument is ONE line
    ``error: <prog>: <problem>`` (no usage block) and exit code 2."""

    def error(self, message: str):
        self.exit(InputError.exit_code, f"error: {self.prog}: {message} (see {self.prog} --help)\n")


def require(condition: bool, what: str, problem: str) -> None:
    """Raise :class:`InputError` (what, problem) unless ``condition`` holds."""
    if not condition:
        raise InputError(what, problem)
